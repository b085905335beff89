//! The `robosim` binary. The end-to-end suites (`tests/Cargo.toml`) build
//! this same file into the program they run.

use std::process::ExitCode;

// The semantic model and the syntax trees allocate and free many small
// objects (a rowan cursor node per visited node); mimalloc makes a re-check
// after a keystroke about a third faster than the system allocator.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    robosim_cli::run()
}
