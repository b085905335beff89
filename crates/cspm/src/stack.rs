//! A guard against stack overflow in the recursive passes: the distance
//! between the stack address where a pass started and the current one. It
//! bounds stack use whatever the frame sizes of the build (debug frames are
//! many times larger than release ones).

/// Stack the static passes (parse, lowering, names, types) may use: half
/// of the 2 MiB of a default spawned thread.
pub(crate) const STATIC_PASS_STACK: usize = 1 << 20;

#[derive(Clone, Copy, Debug)]
pub(crate) struct StackGuard {
    base: usize,
    limit: usize,
}

#[inline(never)]
fn here() -> usize {
    let marker = 0u8;
    std::hint::black_box(&marker) as *const u8 as usize
}

impl StackGuard {
    pub(crate) fn new(limit: usize) -> StackGuard {
        StackGuard { base: here(), limit }
    }

    /// Whether more than the limit is in use since the guard was made.
    pub(crate) fn exceeded(&self) -> bool {
        here().abs_diff(self.base) > self.limit
    }
}
