//! The verification algorithms, generic over on-the-fly [`Lts`]s: deadlock
//! search, refinement in the traces, stable-failures and
//! failures-divergences models, divergence, determinism and timed deadlock
//! (semantics.md §7–§8).
//!
//! Every search is breadth-first, so counterexamples are shortest in steps,
//! τ included (as FDR's). Results and statistics are deterministic: the
//! same on every run and for any [`Budget::threads`]. The engine here is a
//! ply-by-ply BFS whose frontier is expanded in parallel chunks (successor
//! generation is where models spend their time) and merged into the visited
//! table sequentially in frontier order, so states get the indices and
//! parents a sequential BFS would give them.

use std::hash::{BuildHasher, Hash};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

use crate::budget::{Budget, Meter, Stop};
use crate::lts::{Event, Label, Lts, Rows, TAU};

pub mod deadlock;
pub mod divergence;
pub mod event;
pub mod explicit;
pub mod refine;
pub mod timed;
pub mod timelock;

pub use deadlock::{find_deadlock, DeadlockResult};
pub use divergence::{find_divergence, DivergenceResult};
pub use event::{find_event, EventResult};
pub use refine::{check_determinism, refines, DeterminismResult, RefinementCex, RefinementResult, SemanticModel};
pub use timed::{find_timed_deadlock, TimedDeadlockResult};
pub use timelock::{find_timelock, TimelockResult};

/// An execution of an LTS: the initial state and the steps taken from it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Path<S> {
    /// Where the execution starts (the LTS's initial state).
    pub initial: S,
    /// The steps: `steps[i].1` is the state reached by `steps[i].0`.
    pub steps: Vec<(Label, S)>,
}

impl<S> Path<S> {
    /// The state the path ends in.
    pub fn last(&self) -> &S {
        self.steps.last().map_or(&self.initial, |(_, s)| s)
    }

    /// The number of steps, τ included.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether the path has no step.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// The events of the steps, τ included.
    pub fn events(&self) -> Vec<Event> {
        self.steps.iter().map(|(l, _)| l.event).collect()
    }

    /// The trace: the events of the steps without τ.
    pub fn trace(&self) -> Vec<Event> {
        self.steps.iter().map(|(l, _)| l.event).filter(|&e| e != TAU).collect()
    }
}

/// The parent of the root in [`Visited`].
pub(crate) const NO_PARENT: u32 = u32::MAX;

/// A path to a state and a cycle back to it (a lasso).
pub(crate) type Lasso<S> = (Path<S>, Vec<(Label, S)>);

/// A visited table holding the initial state of `lts` (index 0).
pub(crate) fn visited_from_initial<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Visited, Stop> {
    let mut visited = Visited::new(lts.state_width(), RowHash::State);
    let mut row = vec![0u8; lts.state_width()];
    lts.encode(&lts.initial(), &mut row);
    visited.insert(meter, hash_row(&row), &row, NO_PARENT)?;
    Ok(visited)
}

/// The hash every table of the engine uses (fast; states are small).
#[inline]
pub(crate) fn fx<T: Hash + ?Sized>(t: &T) -> u64 {
    FxBuildHasher.hash_one(t)
}

/// The hash of a stored state's row: FxHash over its 8-byte words, then a
/// finaliser so that the low bits (the table's bucket) and the top bits
/// (its tag) both depend on every byte.
#[inline]
pub(crate) fn hash_row(row: &[u8]) -> u64 {
    const K: u64 = 0xf135_7aea_2e62_a9c5;
    let word = |at: usize| {
        let mut w = [0u8; 8];
        w.copy_from_slice(&row[at..at + 8]);
        u64::from_le_bytes(w)
    };
    let n = row.len();
    let mut h = n as u64;
    if (8..=16).contains(&n) {
        // The common widths: one word, or two (possibly overlapping), no loop.
        h = (h.rotate_left(26) ^ word(0)).wrapping_mul(K);
        if n > 8 {
            h = (h.rotate_left(26) ^ word(n - 8)).wrapping_mul(K);
        }
    } else {
        let mut chunks = row.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            h = (h.rotate_left(26) ^ u64::from_le_bytes(w)).wrapping_mul(K);
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            h = (h.rotate_left(26) ^ u64::from_le_bytes(w)).wrapping_mul(K);
        }
    }
    h ^= h >> 32;
    h = h.wrapping_mul(K);
    h ^ (h >> 29)
}

/// Whether two rows are equal: rows of 8 to 16 bytes (the common case)
/// compare as two overlapping words, without a call to `memcmp`.
#[inline]
fn same_row(a: &[u8], b: &[u8]) -> bool {
    let n = a.len();
    if n != b.len() {
        return false;
    }
    if !(8..=16).contains(&n) {
        return a == b;
    }
    let word = |r: &[u8], at: usize| {
        let mut w = [0u8; 8];
        w.copy_from_slice(&r[at..at + 8]);
        u64::from_le_bytes(w)
    };
    word(a, 0) == word(b, 0) && word(a, n - 8) == word(b, n - 8)
}

/// The hash of a (normal-form node, state) pair from the state's hash, so
/// that the state part can be hashed by the worker threads.
#[inline]
pub(crate) fn pair_hash_from(node: u32, state_hash: u64) -> u64 {
    state_hash ^ (u64::from(node) + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// The row of a (normal-form node, state) pair: the node's 4 bytes, then
/// the state's row.
pub(crate) fn pair_row(node: u32, state: &[u8], out: &mut Vec<u8>) {
    out.clear();
    out.extend_from_slice(&node.to_le_bytes());
    out.extend_from_slice(state);
}

/// The node and state row of a pair's row (see [`pair_row`]).
#[inline]
pub(crate) fn split_pair(row: &[u8]) -> (u32, &[u8]) {
    let (node, state) = row.split_at(4);
    (u32::from_le_bytes([node[0], node[1], node[2], node[3]]), state)
}

/// [`pair_hash_from`] of a stored pair's row.
#[inline]
pub(crate) fn pair_row_hash(row: &[u8]) -> u64 {
    let (node, state) = split_pair(row);
    pair_hash_from(node, hash_row(state))
}

/// log2 of the entries per segment of [`Segments`]: small enough that the
/// last segment's unused reserve is a few percent of a large table.
const SEG_SHIFT: u32 = 14;
/// Entries per segment of [`Segments`].
const SEG: usize = 1 << SEG_SHIFT;

/// A growable array of entries of `stride` items each, stored in segments
/// of [`SEG`] entries: growing never moves or copies what is stored, and
/// the unused reserve is at most one segment (a `Vec` doubling wastes up
/// to half its memory). The first segment grows by doubling, so tiny
/// searches stay tiny.
struct Segments<T> {
    segs: Vec<Vec<T>>,
    stride: usize,
    len: usize,
    /// Entries in the last segment and the entries it has room for (kept,
    /// not divided out of the items, on the hot path).
    last_len: usize,
    last_cap: usize,
}

impl<T: Copy> Segments<T> {
    fn new(stride: usize) -> Self {
        Segments { segs: Vec::new(), stride, len: 0, last_len: 0, last_cap: 0 }
    }

    #[inline]
    fn get(&self, i: usize) -> &[T] {
        let at = (i & (SEG - 1)) * self.stride;
        &self.segs[i >> SEG_SHIFT][at..at + self.stride]
    }

    /// Entries `lo..hi`, which must lie in one segment, back to back.
    fn slice(&self, lo: usize, hi: usize) -> &[T] {
        let at = (lo & (SEG - 1)) * self.stride;
        &self.segs[lo >> SEG_SHIFT][at..at + (hi - lo) * self.stride]
    }

    /// Allocated entries.
    fn capacity(&self) -> usize {
        self.segs.len().saturating_sub(1) * SEG + self.last_cap
    }

    /// The entries the next push allocates room for (0 if there is room).
    #[inline]
    fn next_growth(&self) -> usize {
        if self.segs.is_empty() {
            4
        } else if self.last_len < self.last_cap {
            0
        } else if self.last_len == SEG {
            SEG
        } else {
            (self.last_cap * 2).min(SEG) - self.last_cap
        }
    }

    /// Makes room for one more entry; fails if the allocator refuses.
    fn reserve_one(&mut self) -> Result<(), std::collections::TryReserveError> {
        let grow = self.next_growth();
        if grow == 0 {
            return Ok(());
        }
        if !self.segs.is_empty() && self.last_len < SEG {
            let last = self.segs.last_mut().expect("a last segment");
            last.try_reserve_exact((self.last_cap + grow - self.last_len) * self.stride)?;
            self.last_cap += grow;
        } else {
            let first = self.segs.is_empty();
            let mut seg = Vec::new();
            seg.try_reserve_exact(grow * self.stride)?;
            self.segs.try_reserve(1)?;
            self.segs.push(seg);
            (self.last_len, self.last_cap) = (0, if first { 4 } else { SEG });
        }
        Ok(())
    }

    /// Appends an entry (`stride` items), after [`Segments::reserve_one`].
    #[inline]
    fn push(&mut self, value: &[T]) {
        if self.segs.is_empty() || self.last_len == SEG {
            self.segs.push(Vec::with_capacity(SEG * self.stride));
            (self.last_len, self.last_cap) = (0, SEG);
        }
        if let Some(last) = self.segs.last_mut() {
            last.extend_from_slice(value);
        }
        self.last_len += 1;
        self.len += 1;
    }
}

/// The visited table of a BFS: states as rows of a fixed width (see
/// [`Lts::state_width`]), in discovery order (so a ply is a contiguous
/// index range), each with the index of the node it was discovered from.
/// The label of that step is not stored: [`Visited::path_to`] recomputes
/// it from the parent.
pub(crate) struct Visited {
    rows: Segments<u8>,
    parents: Segments<u32>,
    /// Indices into `rows`, hashed by row (the rows are stored once).
    table: HashTable<u32>,
    hash: RowHash,
}

/// How a [`Visited`] table's rows are hashed: named rather than passed as a
/// function pointer, so that rehashing on growth inlines the hash.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RowHash {
    /// States' rows: [`hash_row`].
    State,
    /// (node, state) pairs' rows: [`pair_row_hash`].
    Pair,
}

impl RowHash {
    /// The hash of `row`.
    #[inline]
    pub(crate) fn of(self, row: &[u8]) -> u64 {
        match self {
            RowHash::State => hash_row(row),
            RowHash::Pair => pair_row_hash(row),
        }
    }
}

/// Bytes per table slot: the `u32` index and hashbrown's control byte.
const TABLE_SLOT_BYTES: u64 = 5;

impl Visited {
    /// An empty table of rows of `width` bytes, hashed with `hash` (which
    /// must agree with the hashes passed to [`Visited::insert`]).
    pub(crate) fn new(width: usize, hash: RowHash) -> Visited {
        assert!(width > 0, "states are stored in at least one byte");
        Visited { rows: Segments::new(width), parents: Segments::new(1), table: HashTable::new(), hash }
    }

    /// The number of nodes.
    pub(crate) fn len(&self) -> usize {
        self.rows.len
    }

    /// The bytes of a row.
    pub(crate) fn width(&self) -> usize {
        self.rows.stride
    }

    /// The row of node `i`.
    pub(crate) fn row(&self, i: u32) -> &[u8] {
        self.rows.get(i as usize)
    }

    /// The node `i` was discovered from, or [`NO_PARENT`] for the root.
    pub(crate) fn parent(&self, i: u32) -> u32 {
        self.parents.get(i as usize)[0]
    }

    fn bytes_for(&self, node_slots: usize, table_slots: usize) -> u64 {
        let per_node = (self.rows.stride + std::mem::size_of::<u32>()) as u64;
        // hashbrown keeps 1/8 of its buckets free.
        let buckets = table_slots as u64 * 8 / 7;
        node_slots as u64 * per_node + buckets * TABLE_SLOT_BYTES
    }

    /// The memory of the table.
    pub(crate) fn bytes(&self) -> u64 {
        self.bytes_for(self.rows.capacity(), self.table.capacity())
    }

    /// Finds the node stored as `row` (hashed `hash`), or inserts it,
    /// discovered from `parent`. Returns its index and whether it is new.
    /// Fails, without inserting, when the state or memory budget would be
    /// exceeded.
    #[inline]
    pub(crate) fn insert(
        &mut self,
        meter: &mut Meter<'_>,
        hash: u64,
        row: &[u8],
        parent: u32,
    ) -> Result<(u32, bool), Stop> {
        // Inlined: most calls find the row (every state is reached several
        // times) and take only this lookup.
        let rows = &self.rows;
        if let Some(&i) = self.table.find(hash, |&i| same_row(rows.get(i as usize), row)) {
            return Ok((i, false));
        }
        self.insert_new(meter, hash, row, parent).map(|i| (i, true))
    }

    /// [`Visited::insert`] of a row known not to be in the table.
    #[inline(never)]
    fn insert_new(&mut self, meter: &mut Meter<'_>, hash: u64, row: &[u8], parent: u32) -> Result<u32, Stop> {
        let len = self.rows.len;
        // Indices are u32 with one value reserved for NO_PARENT.
        let limit = meter.budget.max_states.min(u64::from(u32::MAX - 1));
        if len as u64 >= limit {
            return Err(Stop::States);
        }
        let grew = self.reserve_one(meter)?;
        self.rows.push(row);
        self.parents.push(&[parent]);
        let (rows, h) = (&self.rows, self.hash);
        self.table.insert_unique(hash, len as u32, |&i| h.of(rows.get(i as usize)));
        meter.stats.states = self.rows.len as u64;
        // The memory only changes when something grew.
        if grew {
            meter.set_table_bytes(self.bytes())?;
        }
        Ok(len as u32)
    }

    /// Makes room for one more node, refusing growth past the memory budget
    /// (checked before allocating, so a table doubling never overshoots it)
    /// and turning allocation failure into [`Stop::Memory`]. Returns
    /// whether anything grew.
    fn reserve_one(&mut self, meter: &mut Meter<'_>) -> Result<bool, Stop> {
        let grow_nodes = self.rows.next_growth();
        let grow_table = self.table.len() == self.table.capacity();
        if grow_nodes == 0 && !grow_table {
            return Ok(false);
        }
        let node_slots = self.rows.capacity() + grow_nodes;
        let table_slots = if grow_table { (self.table.capacity() * 2).max(4) } else { self.table.capacity() };
        let projected = self.bytes_for(node_slots, table_slots);
        meter.check_bytes(projected.saturating_sub(self.bytes()))?;
        self.rows.reserve_one().map_err(|_| Stop::Memory)?;
        self.parents.reserve_one().map_err(|_| Stop::Memory)?;
        if grow_table {
            self.table = self.grown_table()?;
        }
        Ok(true)
    }

    /// A table with the buckets the full table would grow to, holding the
    /// same indices: built from the rows segment by segment, which costs
    /// about half of letting the table rehash its entries one at a time
    /// (each a lookup of its row through the segments).
    #[cold]
    fn grown_table(&self) -> Result<HashTable<u32>, Stop> {
        let (rows, h) = (&self.rows, self.hash);
        let rehash = |&i: &u32| h.of(rows.get(i as usize));
        let mut table = HashTable::new();
        // hashbrown grows a full table to room for one more than it holds.
        table.try_reserve(self.table.capacity() + 1, rehash).map_err(|_| Stop::Memory)?;
        let mut i = 0u32;
        for seg in &rows.segs {
            for row in seg.chunks_exact(rows.stride) {
                table.insert_unique(h.of(row), i, rehash);
                i += 1;
            }
        }
        Ok(table)
    }

    /// The rows of nodes `lo..hi`, back to back; the range must not cross
    /// a multiple of [`SEG`].
    fn slice(&self, lo: usize, hi: usize) -> &[u8] {
        self.rows.slice(lo, hi)
    }

    /// The indices from the root to `i`, both included.
    pub(crate) fn ancestry(&self, i: u32) -> Vec<u32> {
        let mut chain = vec![i];
        let mut at = i;
        while self.parent(at) != NO_PARENT {
            at = self.parent(at);
            chain.push(at);
        }
        chain.reverse();
        chain
    }

    /// The path from the root to node `i`, each node's row seen through
    /// `view`; `label(parent, child)` gives the label of the step that
    /// discovered `child` from `parent`.
    pub(crate) fn path_to<S>(
        &self,
        i: u32,
        view: impl Fn(&[u8]) -> S,
        mut label: impl FnMut(u32, u32) -> Label,
    ) -> Path<S> {
        let chain = self.ancestry(i);
        Path {
            initial: view(self.row(chain[0])),
            steps: chain.windows(2).map(|w| (label(w[0], w[1]), view(self.row(w[1])))).collect(),
        }
    }
}

/// The label of the step of `lts` that discovered the state stored as
/// `child` from the one stored as `parent`: the first transition of the
/// parent into the child, as the search inserted them in order.
pub(crate) fn step_label<L: Lts>(lts: &L, parent: &[u8], child: &[u8]) -> Label {
    let mut rows = Rows::new(child.len());
    lts.successor_rows(parent, &mut rows);
    (0..rows.len()).find(|&k| rows.row(k) == child).map_or(Label::TAU, |k| rows.label(k))
}

/// The path of `lts` to node `i` of `visited`.
pub(crate) fn state_path<L: Lts>(lts: &L, visited: &Visited, i: u32) -> Path<L::State> {
    visited.path_to(i, |r| lts.decode(r), |p, c| step_label(lts, visited.row(p), visited.row(c)))
}

/// What a visitor tells the BFS after handling a node.
pub(crate) enum Flow<R> {
    /// Go on exploring.
    Continue,
    /// Stop: the check has its answer.
    Break(R),
}

/// The transitions of one expanded node, as the visitor sees them: labels,
/// target rows and their hashes.
pub(crate) struct Succ<'a> {
    labels: &'a [Label],
    rows: &'a [u8],
    width: usize,
    hashes: &'a [u64],
}

impl<'a> Succ<'a> {
    /// Whether there is no transition.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// The labels.
    #[inline]
    pub(crate) fn labels(&self) -> &'a [Label] {
        self.labels
    }

    /// The transitions: label, target row, the row's hash.
    #[inline]
    pub(crate) fn iter(&self) -> impl Iterator<Item = (Label, &'a [u8], u64)> + 'a {
        let rows = self.rows.chunks_exact(self.width);
        self.labels.iter().zip(rows).zip(self.hashes).map(|((&l, r), &h)| (l, r, h))
    }
}

/// The successors of one batch of the frontier, computed by the workers:
/// chunk by chunk, for each source the end of its run in `succ`.
struct ChunkBuf<S> {
    ends: Vec<usize>,
    succ: Rows<S>,
    hashes: Vec<u64>,
}

impl<S> ChunkBuf<S> {
    fn new(width: usize) -> Self {
        ChunkBuf { ends: Vec::new(), succ: Rows::new(width), hashes: Vec::new() }
    }

    fn clear(&mut self) {
        self.ends.clear();
        self.succ.clear();
        self.hashes.clear();
    }
}

/// Sources per chunk handed to one worker at a time: large enough to
/// amortise the hand-out, small enough to balance the load.
const CHUNK: usize = 256;
/// Sources expanded per batch when several threads work: the buffers hold
/// one batch of successors, which bounds their memory.
const PAR_BATCH: usize = 1 << 14;
/// Sources per batch for a single thread: small, to stay in cache.
const SEQ_BATCH: usize = 64;

/// Breadth-first exploration from the nodes already in `visited` (the root).
///
/// `expand` computes the successors of a node's row as rows of
/// `succ_width` bytes (on worker threads), which are hashed with
/// [`hash_row`] there too, to take work off the sequential merge. `visit`
/// is then called on the calling thread for each expanded node, in
/// discovery order, with its index and successors; it inserts what it
/// wants into `visited` and may stop the search. Returns the visitor's
/// answer, or `None` when the whole space was explored.
pub(crate) fn explore<S, R, E, V>(
    visited: &mut Visited,
    meter: &mut Meter<'_>,
    succ_width: usize,
    expand: E,
    mut visit: V,
) -> Result<Option<R>, Stop>
where
    S: Send,
    E: Fn(&[u8], &mut Rows<S>) + Sync,
    V: FnMut(&mut Visited, &mut Meter<'_>, u32, Succ<'_>) -> Result<Flow<R>, Stop>,
{
    let threads = meter.budget.threads.max(1);
    let batch_size = if threads > 1 { PAR_BATCH } else { SEQ_BATCH };
    let mut bufs: Vec<ChunkBuf<S>> = Vec::new();
    let mut head = 0usize;
    let mut ply_end = 0usize;
    loop {
        if head == ply_end {
            if head == visited.len() {
                return Ok(None);
            }
            ply_end = visited.len();
            meter.stats.plies += 1;
        }
        // A batch stays within one storage segment, to be one slice.
        let end = ply_end.min(head + batch_size).min((head / SEG + 1) * SEG);
        let width = visited.width();
        let chunks = expand_batch(visited.slice(head, end), width, succ_width, threads, &mut bufs, meter, &expand)?;
        let mut source = head as u32;
        for buf in &bufs[..chunks] {
            // Each source's transitions are split off the front of what is
            // left of the chunk's: one bounds check each, no index sums.
            let (mut labels, mut rows, mut hashes) =
                (buf.succ.labels(0, buf.succ.len()), buf.succ.rows(0, buf.succ.len()), &buf.hashes[..]);
            let mut start = 0;
            for &stop in &buf.ends {
                let n = stop - start;
                meter.stats.transitions += n as u64;
                let (l, r, h);
                ((l, labels), (r, rows), (h, hashes)) =
                    (labels.split_at(n), rows.split_at(n * succ_width), hashes.split_at(n));
                let succ = Succ { labels: l, rows: r, width: succ_width, hashes: h };
                if let Flow::Break(r) = visit(visited, meter, source, succ)? {
                    return Ok(Some(r));
                }
                meter.poll()?;
                start = stop;
                source += 1;
            }
        }
        head = end;
    }
}

/// Expands the rows `sources` (of `width` bytes) into `bufs` (one buffer
/// per chunk of [`CHUNK`] sources), on `threads` threads when there is
/// more than one chunk. Returns the number of chunks.
#[allow(clippy::too_many_arguments)]
fn expand_batch<S, E>(
    sources: &[u8],
    width: usize,
    succ_width: usize,
    threads: usize,
    bufs: &mut Vec<ChunkBuf<S>>,
    meter: &mut Meter<'_>,
    expand: &E,
) -> Result<usize, Stop>
where
    S: Send,
    E: Fn(&[u8], &mut Rows<S>) + Sync,
{
    let count = sources.len() / width;
    let chunks = count.div_ceil(CHUNK);
    while bufs.len() < chunks {
        bufs.push(ChunkBuf::new(succ_width));
    }
    let fill = |buf: &mut ChunkBuf<S>, source: &[u8]| {
        expand(source, &mut buf.succ);
        buf.ends.push(buf.succ.len());
    };
    // Once per chunk rather than per source: one pass over all its rows.
    let hash = |buf: &mut ChunkBuf<S>| {
        buf.hashes.extend(buf.succ.rows(0, buf.succ.len()).chunks_exact(succ_width).map(hash_row));
    };
    let chunk_sources = |c: usize| {
        let (lo, hi) = (c * CHUNK, count.min((c + 1) * CHUNK));
        sources[lo * width..hi * width].chunks_exact(width)
    };
    if threads == 1 || chunks == 1 {
        for (c, buf) in bufs[..chunks].iter_mut().enumerate() {
            buf.clear();
            for source in chunk_sources(c) {
                fill(buf, source);
                meter.poll()?;
            }
            hash(buf);
        }
        return Ok(chunks);
    }

    // Chunks are handed out through a counter; each chunk's buffer sits
    // behind its own (uncontended) lock so any thread can fill it.
    let cells: Vec<Mutex<&mut ChunkBuf<S>>> = bufs[..chunks].iter_mut().map(Mutex::new).collect();
    let next = AtomicUsize::new(0);
    let halt = meter.halt();
    let work = |on_source: &mut dyn FnMut() -> bool| loop {
        let c = next.fetch_add(1, Ordering::Relaxed);
        if c >= chunks || halt.raised() {
            return;
        }
        let mut guard = cells[c].lock().unwrap_or_else(|e| e.into_inner());
        let buf: &mut ChunkBuf<S> = &mut guard;
        buf.clear();
        for source in chunk_sources(c) {
            fill(buf, source);
            if !on_source() {
                return;
            }
        }
        hash(buf);
    };
    let mut main_stop = None;
    std::thread::scope(|scope| {
        for _ in 1..threads.min(chunks) {
            scope.spawn(|| {
                let mut count = 0u32;
                work(&mut || {
                    count = count.wrapping_add(1);
                    !(count.is_multiple_of(64) && halt.should_stop())
                });
            });
        }
        // The calling thread works too, and keeps reporting progress.
        work(&mut || match meter.poll() {
            Ok(()) => !halt.raised(),
            Err(stop) => {
                main_stop = Some(stop);
                halt.raise();
                false
            }
        });
    });
    if let Some(stop) = main_stop {
        return Err(stop);
    }
    if halt.raised() {
        return Err(meter.halt_reason());
    }
    Ok(chunks)
}

/// Strongly connected components of a graph given in compressed form (the
/// successors of node `v` are `targets[start[v]..start[v + 1]]`), by an
/// iterative Tarjan (graphs can be deep; no recursion).
pub(crate) struct Sccs {
    /// The component of each node. Components are numbered in completion
    /// order, a reverse topological order: an edge between two components
    /// goes to a smaller number.
    pub(crate) comp: Vec<u32>,
    /// The nodes grouped by component, components in completion order.
    pub(crate) order: Vec<u32>,
}

/// See [`Sccs`].
pub(crate) fn tarjan(start: &[usize], targets: &[u32]) -> Sccs {
    const NONE: u32 = u32::MAX;
    let n = start.len().saturating_sub(1);
    let mut index = vec![NONE; n];
    let mut low = vec![0u32; n];
    let mut comp = vec![NONE; n];
    let mut order = Vec::with_capacity(n);
    let mut stack: Vec<u32> = Vec::new();
    let mut calls: Vec<(u32, usize)> = Vec::new();
    let mut next_index = 0u32;
    let mut next_comp = 0u32;
    for root in 0..n {
        if index[root] != NONE {
            continue;
        }
        index[root] = next_index;
        low[root] = next_index;
        next_index += 1;
        stack.push(root as u32);
        calls.push((root as u32, start[root]));
        while let Some(&mut (v, ref mut pos)) = calls.last_mut() {
            let v = v as usize;
            if *pos < start[v + 1] {
                let w = targets[*pos] as usize;
                *pos += 1;
                if index[w] == NONE {
                    index[w] = next_index;
                    low[w] = next_index;
                    next_index += 1;
                    stack.push(w as u32);
                    calls.push((w as u32, start[w]));
                } else if comp[w] == NONE {
                    // w is on the stack: same component candidate.
                    low[v] = low[v].min(index[w]);
                }
            } else {
                calls.pop();
                if let Some(&(u, _)) = calls.last() {
                    low[u as usize] = low[u as usize].min(low[v]);
                }
                if low[v] == index[v] {
                    while let Some(w) = stack.pop() {
                        comp[w as usize] = next_comp;
                        order.push(w);
                        if w as usize == v {
                            break;
                        }
                    }
                    next_comp += 1;
                }
            }
        }
    }
    Sccs { comp, order }
}

/// Which components of [`tarjan`]'s result contain a cycle: more than one
/// node, or a self-loop.
pub(crate) fn cyclic_components(start: &[usize], targets: &[u32], comp: &[u32]) -> Vec<bool> {
    let count = comp.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    let mut size = vec![0u32; count];
    let mut cyclic = vec![false; count];
    for (v, &c) in comp.iter().enumerate() {
        size[c as usize] += 1;
        if targets[start[v]..start[v + 1]].contains(&(v as u32)) {
            cyclic[c as usize] = true;
        }
    }
    for (c, flag) in cyclic.iter_mut().enumerate() {
        *flag |= size[c] > 1;
    }
    cyclic
}

/// The shortest cycle from `from` back to itself through nodes of its own
/// component, as the positions in `targets` of the edges taken (so callers
/// can recover labels). `None` if there is none.
pub(crate) fn shortest_cycle(start: &[usize], targets: &[u32], comp: &[u32], from: u32) -> Option<Vec<usize>> {
    let c = comp[from as usize];
    // BFS parents, as the edge position that reached each node.
    let mut reached: rustc_hash::FxHashMap<u32, usize> = rustc_hash::FxHashMap::default();
    let mut queue = std::collections::VecDeque::from([from]);
    while let Some(v) = queue.pop_front() {
        let first = start[v as usize];
        for (pos, &w) in targets[first..start[v as usize + 1]].iter().enumerate().map(|(k, w)| (first + k, w)) {
            if comp[w as usize] != c {
                continue;
            }
            if w == from {
                // Walk back from v to `from`.
                let mut edges = vec![pos];
                let mut at = v;
                while at != from {
                    // Every node reached but `from` has a BFS parent edge.
                    let &p = reached.get(&at)?;
                    edges.push(p);
                    at = source_of(start, p);
                }
                edges.reverse();
                return Some(edges);
            }
            if let std::collections::hash_map::Entry::Vacant(e) = reached.entry(w) {
                e.insert(pos);
                queue.push_back(w);
            }
        }
    }
    None
}

/// The node whose successor list contains edge position `pos`.
pub(crate) fn source_of(start: &[usize], pos: usize) -> u32 {
    // The last node whose list starts at or before pos and is non-empty.
    (start.partition_point(|&s| s <= pos) - 1) as u32
}

/// The shortest execution of `lts` whose visible trace is `trace` and that
/// ends in a state `accept` holds of (τ steps count). Used to turn a
/// counterexample found on normal-form nodes into a concrete path.
pub(crate) fn trace_search<L: Lts>(
    lts: &L,
    trace: &[Event],
    mut accept: impl FnMut(&L::State) -> bool,
    meter: &mut Meter<'_>,
) -> Result<Option<Path<L::State>>, Stop> {
    let width = lts.state_width();
    // Rows are (position in the trace, state) pairs.
    let mut seen = Visited::new(4 + width, RowHash::Pair);
    // A private meter: the search is small and must not disturb the
    // check's statistics, but it obeys the same budget.
    let budget: &Budget = meter.budget;
    let mut local = Meter::new(budget, None);
    let mut init = vec![0u8; width];
    lts.encode(&lts.initial(), &mut init);
    let mut row = Vec::new();
    pair_row(0, &init, &mut row);
    seen.insert(&mut local, pair_row_hash(&row), &row, NO_PARENT)?;
    // The position reached by a step with `label` from position `pos`.
    let next_pos = |pos: u32, label: Label| {
        if label.event == TAU {
            Some(pos)
        } else if trace.get(pos as usize) == Some(&label.event) {
            Some(pos + 1)
        } else {
            None
        }
    };
    let mut buf: Rows<L::State> = Rows::new(width);
    let mut k = 0u32;
    while (k as usize) < seen.len() {
        meter.poll()?;
        let (pos, state) = split_pair(seen.row(k));
        let state = state.to_vec();
        if pos as usize == trace.len() && accept(&lts.decode(&state)) {
            let label = |p: u32, c: u32| {
                let (pos, parent) = split_pair(seen.row(p));
                let (cpos, child) = split_pair(seen.row(c));
                let mut rows = Rows::new(width);
                lts.successor_rows(parent, &mut rows);
                (0..rows.len())
                    .find(|&j| rows.row(j) == child && next_pos(pos, rows.label(j)) == Some(cpos))
                    .map_or(Label::TAU, |j| rows.label(j))
            };
            return Ok(Some(seen.path_to(k, |r| lts.decode(split_pair(r).1), label)));
        }
        buf.clear();
        lts.successor_rows(&state, &mut buf);
        for j in 0..buf.len() {
            let Some(next) = next_pos(pos, buf.label(j)) else { continue };
            let t = buf.row(j);
            pair_row(next, t, &mut row);
            seen.insert(&mut local, pair_hash_from(next, hash_row(t)), &row, k)?;
        }
        k += 1;
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csr(n: usize, edges: &[(u32, u32)]) -> (Vec<usize>, Vec<u32>) {
        let mut start = vec![0usize; n + 1];
        for &(a, _) in edges {
            start[a as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut sorted = edges.to_vec();
        sorted.sort();
        (start, sorted.iter().map(|&(_, b)| b).collect())
    }

    #[test]
    fn segments_grow_without_moving_and_slice_within_a_segment() {
        let mut seg: Segments<u32> = Segments::new(2);
        assert_eq!((seg.capacity(), seg.next_growth()), (0, 4));
        for i in 0..(2 * SEG + 10) as u32 {
            seg.reserve_one().expect("memory");
            seg.push(&[i, !i]);
            assert!(seg.capacity() >= seg.len);
        }
        assert_eq!(seg.len, 2 * SEG + 10);
        assert_eq!(seg.capacity(), 3 * SEG);
        let s = SEG as u32;
        assert_eq!(seg.get(SEG + 5), &[s + 5, !(s + 5)]);
        assert_eq!(seg.slice(SEG - 2, SEG), &[s - 2, !(s - 2), s - 1, !(s - 1)]);
        assert_eq!(seg.slice(2 * SEG, 2 * SEG + 2), &[2 * s, !(2 * s), 2 * s + 1, !(2 * s + 1)]);
    }

    #[test]
    fn visited_table_grows_like_hashbrown_and_finds_every_row() {
        let budget = Budget::default();
        let mut meter = Meter::new(&budget, None);
        for (width, hash) in [(8, RowHash::State), (10, RowHash::State), (12, RowHash::Pair), (3, RowHash::State)] {
            let mut visited = Visited::new(width, hash);
            // The same number of items inserted into a table left to grow itself.
            let mut plain: HashTable<u32> = HashTable::new();
            let row = |k: u32| -> Vec<u8> {
                (0..width).map(|b| (k.wrapping_mul(2654435761) >> (b % 4 * 8)) as u8 ^ b as u8).collect()
            };
            let n = (2 * SEG + 100) as u32;
            for k in 0..n {
                let r = row(k);
                assert_eq!(visited.insert(&mut meter, hash.of(&r), &r, k / 2).expect("budget"), (k, true));
                plain.insert_unique(u64::from(k), k, |&i| u64::from(i));
                assert_eq!(visited.table.capacity(), plain.capacity(), "{k}");
                // Every row inserted so far is still found, at its index.
                if k.is_power_of_two() || k == n - 1 {
                    for j in (0..=k).step_by(97) {
                        let r = row(j);
                        assert_eq!(visited.insert(&mut meter, hash.of(&r), &r, 0).expect("budget"), (j, false));
                        assert_eq!((visited.row(j), visited.parent(j)), (&r[..], j / 2));
                    }
                }
            }
        }
    }

    #[test]
    fn tarjan_finds_components_in_reverse_topological_order() {
        // 0 → 1 ⇄ 2 → 3, 3 ↺, 4 → 0
        let (start, targets) = csr(5, &[(0, 1), (1, 2), (2, 1), (2, 3), (3, 3), (4, 0)]);
        let Sccs { comp, order } = tarjan(&start, &targets);
        assert_eq!(order.len(), 5);
        assert_eq!(comp[1], comp[2]);
        assert!(comp[3] < comp[1] && comp[1] < comp[0] && comp[0] < comp[4]);
        let cyclic = cyclic_components(&start, &targets, &comp);
        assert!(cyclic[comp[1] as usize] && cyclic[comp[3] as usize]);
        assert!(!cyclic[comp[0] as usize] && !cyclic[comp[4] as usize]);
        let cycle = shortest_cycle(&start, &targets, &comp, 1).expect("1 is on a cycle");
        assert_eq!(cycle.iter().map(|&p| targets[p]).collect::<Vec<_>>(), vec![2, 1]);
        assert_eq!(source_of(&start, cycle[1]), 2);
        assert!(shortest_cycle(&start, &targets, &comp, 0).is_none());
    }

    #[test]
    fn tarjan_on_a_deep_chain_does_not_recurse() {
        let n = 1_000_000u32;
        let edges: Vec<(u32, u32)> = (0..n - 1).map(|i| (i, i + 1)).collect();
        let (start, targets) = csr(n as usize, &edges);
        let comp = tarjan(&start, &targets).comp;
        assert_eq!(comp[n as usize - 1], 0);
        assert_eq!(comp[0], n - 1);
    }
}
