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
use crate::lts::{Event, Label, Lts, TAU};

pub mod deadlock;
pub mod divergence;
pub mod explicit;
pub mod refine;
pub mod timed;

pub use deadlock::{find_deadlock, DeadlockResult};
pub use divergence::{find_divergence, DivergenceResult};
pub use refine::{check_determinism, refines, DeterminismResult, RefinementCex, RefinementResult, SemanticModel};
pub use timed::{find_timed_deadlock, TimedDeadlockResult};

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

/// The heap bytes of a state of `lts` beyond its inline size.
pub(crate) fn heap_bytes<L: Lts>(lts: &L, s: &L::State) -> usize {
    lts.state_bytes(s).saturating_sub(std::mem::size_of::<L::State>())
}

/// A visited table holding the initial state of `lts` (index 0).
pub(crate) fn visited_from_initial<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Visited<L::State>, Stop> {
    let mut visited: Visited<L::State> = Visited::new(fx::<L::State>);
    let init = lts.initial();
    let h = fx(&init);
    visited.insert(meter, h, |_| false, || init, |s| heap_bytes(lts, s), NO_PARENT, Label::TAU)?;
    Ok(visited)
}

/// The hash every table of the engine uses (fast; states are small).
#[inline]
pub(crate) fn fx<T: Hash + ?Sized>(t: &T) -> u64 {
    FxBuildHasher.hash_one(t)
}

/// The hash of a (normal-form node, state) pair from the state's hash, so
/// that the state part can be hashed by the worker threads.
#[inline]
pub(crate) fn pair_hash_from(node: u32, state_hash: u64) -> u64 {
    state_hash ^ (u64::from(node) + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// [`pair_hash_from`] of a stored pair.
pub(crate) fn pair_hash<S: Hash>(pair: &(u32, S)) -> u64 {
    pair_hash_from(pair.0, fx(&pair.1))
}

/// log2 of the entries per segment of [`Segments`].
const SEG_SHIFT: u32 = 16;
/// Entries per segment of [`Segments`].
const SEG: usize = 1 << SEG_SHIFT;

/// A growable array stored in segments of [`SEG`] entries: growing never
/// moves or copies what is stored, and the unused reserve is at most one
/// segment (a `Vec` doubling wastes up to half its memory). The first
/// segment grows by doubling, so tiny searches stay tiny.
struct Segments<T> {
    segs: Vec<Vec<T>>,
    len: usize,
}

impl<T> Segments<T> {
    fn new() -> Self {
        Segments { segs: Vec::new(), len: 0 }
    }

    fn get(&self, i: usize) -> &T {
        &self.segs[i >> SEG_SHIFT][i & (SEG - 1)]
    }

    /// Entries `lo..hi`, which must lie in one segment.
    fn slice(&self, lo: usize, hi: usize) -> &[T] {
        &self.segs[lo >> SEG_SHIFT][lo & (SEG - 1)..hi - (lo & !(SEG - 1))]
    }

    /// Allocated entries.
    fn capacity(&self) -> usize {
        match self.segs.last() {
            None => 0,
            Some(last) => (self.segs.len() - 1) * SEG + last.capacity(),
        }
    }

    /// The entries the next push allocates room for (0 if there is room).
    fn next_growth(&self) -> usize {
        match self.segs.last() {
            None => 4,
            Some(last) if last.len() < last.capacity() => 0,
            Some(last) if last.len() == SEG => SEG,
            Some(last) => (last.capacity() * 2).min(SEG) - last.capacity(),
        }
    }

    /// Makes room for one more entry; fails if the allocator refuses.
    fn reserve_one(&mut self) -> Result<(), std::collections::TryReserveError> {
        let grow = self.next_growth();
        if grow == 0 {
            return Ok(());
        }
        match self.segs.last_mut() {
            Some(last) if last.len() < SEG => last.try_reserve_exact(grow),
            _ => {
                let mut seg = Vec::new();
                seg.try_reserve_exact(if self.segs.is_empty() { 4 } else { SEG })?;
                self.segs.try_reserve(1)?;
                self.segs.push(seg);
                Ok(())
            }
        }
    }

    /// Appends an entry, after [`Segments::reserve_one`].
    fn push(&mut self, value: T) {
        if self.segs.last().is_none_or(|last| last.len() == SEG) {
            self.segs.push(Vec::with_capacity(SEG));
        }
        if let Some(last) = self.segs.last_mut() {
            last.push(value);
        }
        self.len += 1;
    }
}

/// How a node was discovered: the node it came from and the step's label.
#[derive(Clone, Copy)]
struct Origin {
    parent: u32,
    label: Label,
}

/// The visited table of a BFS: nodes in discovery order (so a ply is a
/// contiguous index range), each with the index of the node it was
/// discovered from and the label of that step.
pub(crate) struct Visited<N> {
    nodes: Segments<N>,
    origins: Segments<Origin>,
    /// Indices into `nodes`, hashed by node (the nodes are stored once).
    table: HashTable<u32>,
    hash: fn(&N) -> u64,
    /// Heap bytes owned by the nodes (beyond their inline size).
    heap: u64,
}

/// Bytes per table slot: the `u32` index and hashbrown's control byte.
const TABLE_SLOT_BYTES: u64 = 5;

impl<N: Eq> Visited<N> {
    /// An empty table hashing nodes with `hash` (which must agree with the
    /// hashes passed to [`Visited::insert`]).
    pub(crate) fn new(hash: fn(&N) -> u64) -> Visited<N> {
        Visited { nodes: Segments::new(), origins: Segments::new(), table: HashTable::new(), hash, heap: 0 }
    }

    /// The number of nodes.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len
    }

    /// The node with index `i`.
    pub(crate) fn node(&self, i: u32) -> &N {
        self.nodes.get(i as usize)
    }

    /// The label of the step that discovered node `i` (meaningless for the root).
    pub(crate) fn label(&self, i: u32) -> Label {
        self.origins.get(i as usize).label
    }

    /// The node `i` was discovered from, or [`NO_PARENT`] for the root.
    pub(crate) fn parent(&self, i: u32) -> u32 {
        self.origins.get(i as usize).parent
    }

    fn bytes_for(&self, node_slots: usize, table_slots: usize) -> u64 {
        let per_node = (std::mem::size_of::<N>() + std::mem::size_of::<Origin>()) as u64;
        // hashbrown keeps 1/8 of its buckets free.
        let buckets = table_slots as u64 * 8 / 7;
        node_slots as u64 * per_node + buckets * TABLE_SLOT_BYTES + self.heap
    }

    /// The estimated memory of the table.
    pub(crate) fn bytes(&self) -> u64 {
        self.bytes_for(self.nodes.capacity(), self.table.capacity())
    }

    /// Finds the node `eq` recognises (hashed `hash`), or inserts `make()`,
    /// discovered from `parent` by `label`, whose heap bytes are `heap`.
    /// Returns its index and whether it is new. Fails, without inserting,
    /// when the state or memory budget would be exceeded.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn insert(
        &mut self,
        meter: &mut Meter<'_>,
        hash: u64,
        eq: impl Fn(&N) -> bool,
        make: impl FnOnce() -> N,
        heap: impl FnOnce(&N) -> usize,
        parent: u32,
        label: Label,
    ) -> Result<(u32, bool), Stop> {
        let nodes = &self.nodes;
        if let Some(&i) = self.table.find(hash, |&i| eq(nodes.get(i as usize))) {
            return Ok((i, false));
        }
        let len = self.nodes.len;
        // Indices are u32 with one value reserved for NO_PARENT.
        let limit = meter.budget.max_states.min(u64::from(u32::MAX - 1));
        if len as u64 >= limit {
            return Err(Stop::States);
        }
        self.reserve_one(meter)?;
        let node = make();
        self.heap += heap(&node) as u64;
        self.nodes.push(node);
        self.origins.push(Origin { parent, label });
        let (nodes, h) = (&self.nodes, self.hash);
        self.table.insert_unique(hash, len as u32, |&i| h(nodes.get(i as usize)));
        meter.stats.states = self.nodes.len as u64;
        meter.set_table_bytes(self.bytes())?;
        Ok((len as u32, true))
    }

    /// Makes room for one more node, refusing growth past the memory budget
    /// (checked before allocating, so a table doubling never overshoots it)
    /// and turning allocation failure into [`Stop::Memory`].
    fn reserve_one(&mut self, meter: &mut Meter<'_>) -> Result<(), Stop> {
        let grow_nodes = self.nodes.next_growth();
        let grow_table = self.table.len() == self.table.capacity();
        if grow_nodes == 0 && !grow_table {
            return Ok(());
        }
        let node_slots = self.nodes.capacity() + grow_nodes;
        let table_slots = if grow_table { (self.table.capacity() * 2).max(4) } else { self.table.capacity() };
        let projected = self.bytes_for(node_slots, table_slots);
        meter.check_bytes(projected.saturating_sub(self.bytes()))?;
        self.nodes.reserve_one().map_err(|_| Stop::Memory)?;
        self.origins.reserve_one().map_err(|_| Stop::Memory)?;
        if grow_table {
            let (nodes, h) = (&self.nodes, self.hash);
            self.table.try_reserve(1, |&i| h(nodes.get(i as usize))).map_err(|_| Stop::Memory)?;
        }
        Ok(())
    }

    /// Nodes `lo..hi`, which must not cross a multiple of [`SEG`].
    fn slice(&self, lo: usize, hi: usize) -> &[N] {
        self.nodes.slice(lo, hi)
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

    /// The path from the root to node `i`, each node seen through `view`.
    pub(crate) fn path_to<S>(&self, i: u32, view: impl Fn(&N) -> S) -> Path<S> {
        let chain = self.ancestry(i);
        Path {
            initial: view(self.node(chain[0])),
            steps: chain[1..].iter().map(|&k| (self.label(k), view(self.node(k)))).collect(),
        }
    }
}

/// What a visitor tells the BFS after handling a node.
pub(crate) enum Flow<R> {
    /// Go on exploring.
    Continue,
    /// Stop: the check has its answer.
    Break(R),
}

/// The successors of one batch of the frontier, computed by the workers:
/// chunk by chunk, for each source the end of its run in `succ`.
struct ChunkBuf<X> {
    ends: Vec<usize>,
    succ: Vec<(Label, X)>,
    hashes: Vec<u64>,
}

impl<X> ChunkBuf<X> {
    fn new() -> Self {
        ChunkBuf { ends: Vec::new(), succ: Vec::new(), hashes: Vec::new() }
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
/// `expand` computes a node's successors (on worker threads), `succ_hash`
/// hashes each successor (also on the workers, to take work off the
/// sequential merge). `visit` is then called on the calling thread for each
/// expanded node, in discovery order, with its index, successors and their
/// hashes; it inserts what it wants into `visited` and may stop the search.
/// Returns the visitor's answer, or `None` when the whole space was explored.
pub(crate) fn explore<N, X, R, E, H, V>(
    visited: &mut Visited<N>,
    meter: &mut Meter<'_>,
    expand: E,
    succ_hash: H,
    mut visit: V,
) -> Result<Option<R>, Stop>
where
    N: Eq + Sync,
    X: Send,
    E: Fn(&N, &mut Vec<(Label, X)>) + Sync,
    H: Fn(&X) -> u64 + Sync,
    V: FnMut(&mut Visited<N>, &mut Meter<'_>, u32, &[(Label, X)], &[u64]) -> Result<Flow<R>, Stop>,
{
    let threads = meter.budget.threads.max(1);
    let batch_size = if threads > 1 { PAR_BATCH } else { SEQ_BATCH };
    let mut bufs: Vec<ChunkBuf<X>> = Vec::new();
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
        let chunks = expand_batch(visited.slice(head, end), threads, &mut bufs, meter, &expand, &succ_hash)?;
        let mut source = head as u32;
        for buf in &bufs[..chunks] {
            let mut start = 0;
            for &stop in &buf.ends {
                let succ = &buf.succ[start..stop];
                meter.stats.transitions += succ.len() as u64;
                if let Flow::Break(r) = visit(visited, meter, source, succ, &buf.hashes[start..stop])? {
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

/// Expands `sources` into `bufs` (one buffer per chunk of [`CHUNK`]
/// sources), on `threads` threads when there is more than one chunk.
/// Returns the number of chunks.
fn expand_batch<N, X, E, H>(
    sources: &[N],
    threads: usize,
    bufs: &mut Vec<ChunkBuf<X>>,
    meter: &mut Meter<'_>,
    expand: &E,
    succ_hash: &H,
) -> Result<usize, Stop>
where
    N: Sync,
    X: Send,
    E: Fn(&N, &mut Vec<(Label, X)>) + Sync,
    H: Fn(&X) -> u64 + Sync,
{
    let chunks = sources.len().div_ceil(CHUNK);
    while bufs.len() < chunks {
        bufs.push(ChunkBuf::new());
    }
    let fill = |buf: &mut ChunkBuf<X>, source: &N| {
        let before = buf.succ.len();
        expand(source, &mut buf.succ);
        buf.hashes.extend(buf.succ[before..].iter().map(|(_, x)| succ_hash(x)));
        buf.ends.push(buf.succ.len());
    };
    if threads == 1 || chunks == 1 {
        for (c, buf) in bufs[..chunks].iter_mut().enumerate() {
            buf.clear();
            for source in &sources[c * CHUNK..sources.len().min((c + 1) * CHUNK)] {
                fill(buf, source);
                meter.poll()?;
            }
        }
        return Ok(chunks);
    }

    // Chunks are handed out through a counter; each chunk's buffer sits
    // behind its own (uncontended) lock so any thread can fill it.
    let cells: Vec<Mutex<&mut ChunkBuf<X>>> = bufs[..chunks].iter_mut().map(Mutex::new).collect();
    let next = AtomicUsize::new(0);
    let halt = meter.halt();
    let work = |on_source: &mut dyn FnMut() -> bool| loop {
        let c = next.fetch_add(1, Ordering::Relaxed);
        if c >= chunks || halt.raised() {
            return;
        }
        let mut guard = cells[c].lock().unwrap_or_else(|e| e.into_inner());
        let buf: &mut ChunkBuf<X> = &mut guard;
        buf.clear();
        for source in &sources[c * CHUNK..sources.len().min((c + 1) * CHUNK)] {
            fill(buf, source);
            if !on_source() {
                return;
            }
        }
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
    let mut seen: Visited<(u32, L::State)> = Visited::new(pair_hash::<L::State>);
    // A private meter: the search is small and must not disturb the
    // check's statistics, but it obeys the same budget.
    let budget: &Budget = meter.budget;
    let mut local = Meter::new(budget, None);
    let root = (0u32, lts.initial());
    let h = pair_hash(&root);
    seen.insert(&mut local, h, |_| false, || root, |_| 0, NO_PARENT, Label::TAU)?;
    let mut buf = Vec::new();
    let mut k = 0u32;
    while (k as usize) < seen.len() {
        meter.poll()?;
        let (pos, state) = seen.node(k).clone();
        if pos as usize == trace.len() && accept(&state) {
            return Ok(Some(seen.path_to(k, |(_, s)| s.clone())));
        }
        buf.clear();
        lts.successors(&state, &mut buf);
        for (label, t) in buf.drain(..) {
            let next = if label.event == TAU {
                pos
            } else if trace.get(pos as usize) == Some(&label.event) {
                pos + 1
            } else {
                continue;
            };
            let h = pair_hash_from(next, fx(&t));
            seen.insert(&mut local, h, |(p, s)| *p == next && *s == t, || (next, t.clone()), |_| 0, k, label)?;
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
        let mut seg: Segments<u32> = Segments::new();
        assert_eq!((seg.capacity(), seg.next_growth()), (0, 4));
        for i in 0..(2 * SEG + 10) as u32 {
            seg.reserve_one().expect("memory");
            seg.push(i);
        }
        assert_eq!(seg.len, 2 * SEG + 10);
        assert_eq!(seg.capacity(), 3 * SEG);
        assert_eq!(*seg.get(SEG + 5), SEG as u32 + 5);
        assert_eq!(seg.slice(SEG - 2, SEG), &[SEG as u32 - 2, SEG as u32 - 1]);
        assert_eq!(seg.slice(2 * SEG, 2 * SEG + 3), &[2 * SEG as u32, 2 * SEG as u32 + 1, 2 * SEG as u32 + 2]);
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
