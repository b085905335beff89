//! Helpers shared by the tests, benchmarks and profiling examples of the
//! workspace's crates and by the end-to-end suites in `tests/`: one crate
//! instead of borrowing each other's files by `#[path]`.
//!
//! It depends on none of the product's crates, so that any of them (the
//! syntax crate included) can use it as a dev-dependency.

pub mod generated;
pub mod inputs;
pub mod lsp_framing;
