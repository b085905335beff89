//! What the engine's API promises that a verification fixture
//! (`test_data/verify`, run by `fixtures.rs`) cannot state: how options
//! are read and described, budgets that depend on the clock, and the
//! numbering of the events a lowering produces.

use robosim_engine::verify::AsyncBuffer;

fn buffer(text: &str) -> AsyncBuffer {
    AsyncBuffer::parse(text).expect("a buffer")
}

/// `--async-buffer` (robotool-facts.md RT-12): a size from 1 to 8 and an
/// optional policy; nothing else.
#[test]
fn buffer_assumptions_are_read_strictly() {
    assert_eq!(AsyncBuffer::parse("3"), Ok(AsyncBuffer { size: 3, overwrite: true }));
    assert_eq!(AsyncBuffer::parse("2:block"), Ok(AsyncBuffer { size: 2, overwrite: false }));
    for bad in ["0", "9:overwrite", "x", "1:drop", ""] {
        assert!(AsyncBuffer::parse(bad).is_err(), "{bad}");
    }
}

/// The note every report under a buffer assumption carries says whether it
/// is RoboTool's own buffer or one the user assumed.
#[test]
fn buffer_assumptions_are_described() {
    assert!(buffer("1:overwrite")
        .describe()
        .contains("buffer 1 value; when full, a new value replaces the oldest (RoboTool's default buffer)"));
    assert!(buffer("2:block").describe().ends_with(
        "when full, the sender waits (assumed with `--async-buffer`; RoboTool's default buffer is `1:overwrite`)"
    ));
}
