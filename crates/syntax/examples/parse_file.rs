//! Parses files repeatedly, for profiling (`perf`, `valgrind --tool=callgrind`):
//! `cargo run --release -p robosim-syntax --example parse_file -- FILE [N]`;
//! `--generate FILE` writes the generated 10,000-line benchmark model.

use robosim_syntax::{parse, FileKind};

// As in the `robosim` binary and the benchmark.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use robosim_test_support::generated;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: parse_file FILE [N]");
        std::process::exit(2);
    };
    if path == "--generate" {
        let out = args.next().unwrap_or_else(|| "generated.rct".into());
        std::fs::write(&out, generated::generated_model(10_000)).expect("cannot write the model");
        return;
    }
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("cannot read {path}: {e}");
        std::process::exit(2)
    });
    let kind = FileKind::from_path(std::path::Path::new(&path)).unwrap_or(FileKind::RoboChart);
    let mut errors = 0;
    for _ in 0..n {
        errors = parse(&text, kind).errors().len();
    }
    println!("{path}: {} bytes, {errors} errors", text.len());
}
