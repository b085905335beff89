//! Refinement `Spec ⊑ Impl` in the traces, stable-failures,
//! failures-divergences and tick-tock models (semantics.md §8.3, §7.5),
//! and determinism.
//!
//! The specification is normalised lazily, as FDR's `normal`: a node is a
//! τ-closed set of specification states (interned by its sorted state ids),
//! with whether it can diverge, the minimal acceptances of its stable
//! members and, computed on demand and memoised, its successor on each
//! visible event. The check is a breadth-first search over (node,
//! implementation state) pairs, so a counterexample is a shortest
//! implementation path. Specification and implementation must number their
//! events alike (the same event table).
//!
//! Determinism normalises the process itself: it is deterministic iff it
//! cannot diverge and no node has a stable member refusing an event the
//! node can perform.

use hashbrown::HashTable;
use rustc_hash::FxHashMap;

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Event, Label, Lts, Rows, TAU, TOCK};

use super::divergence::TauDivergence;
use super::{
    explore, fx, pair_hash_from, pair_row, pair_row_hash, split_pair, trace_search, Flow, Path, RowHash, Visited,
    NO_PARENT,
};

/// The semantic model a refinement is checked in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SemanticModel {
    /// Traces only (`[T=`).
    Traces,
    /// Traces and stable failures (`[F=`): refusals count, divergence does not.
    Failures,
    /// Failures and divergences (`[FD=`): a divergent specification node
    /// allows anything, a divergent implementation must be allowed.
    FailuresDivergences,
    /// Tick-tock (Baxter, Ribeiro and Cavalcanti, Acta Informatica 2022):
    /// the stable failures, and also what is refused at each `tock`. An
    /// implementation that lets time pass at a stable state refusing `X`
    /// must be matched by specification states that refuse `X` and let
    /// time pass, and only those continue: an internal choice cannot be
    /// revised once time has passed.
    TickTock,
}

/// The verdict of [`refines`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RefinementResult<S> {
    /// Every behaviour of the implementation is allowed by the specification.
    Holds,
    /// A shortest behaviour of the implementation the specification does not allow.
    Fails(RefinementCex<S>),
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Why a refinement fails, with an implementation path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RefinementCex<S> {
    /// After `path` the implementation performs `event` (path's last step),
    /// which the spec cannot.
    Trace {
        /// The implementation's path, ending with the offending step.
        path: Path<S>,
        /// The offending step's label (also the last step of `path`).
        event: Label,
    },
    /// After `path` (ending in a stable implementation state) the
    /// implementation offers only `offered`, which includes none of the
    /// specification's acceptances: it refuses more than the spec may.
    Refusal {
        /// The implementation's path to the stable state.
        path: Path<S>,
        /// The events the stable state offers, sorted.
        offered: Vec<Event>,
        /// The specification's minimal acceptances after the same trace,
        /// each sorted, in sorted order (empty in the stable-failures model
        /// when the specification has no stable state after that trace).
        acceptances: Vec<Vec<Event>>,
    },
    /// Tick-tock: after `path` (ending in a stable implementation state)
    /// the implementation lets time pass (`tock`) offering only `offered`,
    /// and no stable state of the specification after the same trace lets
    /// time pass refusing as much: those that can let time pass offer
    /// `acceptances` (each sorted, tock included).
    TockRefusal {
        /// The implementation's path to the stable state, then its `tock`.
        path: Path<S>,
        /// The events the stable state offers, sorted (with `tock`).
        offered: Vec<Event>,
        /// What the specification's stable, time-passing states offer
        /// after the same trace (empty if none can let time pass).
        acceptances: Vec<Vec<Event>>,
    },
    /// After `path` the implementation can diverge; `cycle` is the τ-lasso
    /// from the last state of `path` (τ steps into a τ-loop and once
    /// around it, ending where the loop starts).
    Divergence {
        /// The implementation's path to a divergent state.
        path: Path<S>,
        /// The τ steps it can repeat forever.
        cycle: Vec<(Label, S)>,
    },
}

/// The verdict of [`check_determinism`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DeterminismResult<S> {
    /// The process is deterministic (and divergence-free).
    Deterministic,
    /// After `path`, which ends in a stable state that refuses `event`, the
    /// process refuses `event`, yet another execution with the same trace
    /// can perform it.
    Nondeterministic {
        /// A shortest path to the refusing stable state.
        path: Path<S>,
        /// The event both possible and refusable after the trace.
        event: Event,
    },
    /// The process can diverge after `path`, by following the τ-lasso
    /// `cycle` (as in [`DivergenceResult`](super::DivergenceResult)).
    Divergent {
        /// A shortest path to a divergent state.
        path: Path<S>,
        /// The τ steps it can repeat forever.
        cycle: Vec<(Label, S)>,
    },
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Checks `spec ⊑ imp` in `model`, breadth first over (spec normal-form
/// node, implementation state) pairs. Both LTSs must use the same event ids.
pub fn refines<Sp: Lts, Im: Lts>(
    spec: &Sp,
    imp: &Im,
    model: SemanticModel,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (RefinementResult<Im::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match refine_search(spec, imp, model, &mut meter) {
        Ok(Some(cex)) => RefinementResult::Fails(cex),
        Ok(None) => RefinementResult::Holds,
        Err(stop) => RefinementResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

/// A counterexample found at a pair, before its path is rebuilt.
enum Found<S> {
    Divergence(u32),
    Refusal(u32, Vec<Event>, Vec<Vec<Event>>),
    TockRefusal(u32, Vec<Event>, Vec<Vec<Event>>, S),
    Trace(u32, Label, S),
}

fn refine_search<Sp: Lts, Im: Lts>(
    spec: &Sp,
    imp: &Im,
    model: SemanticModel,
    meter: &mut Meter<'_>,
) -> Result<Option<RefinementCex<Im::State>>, Stop> {
    let fd = model == SemanticModel::FailuresDivergences;
    let failures = model != SemanticModel::Traces;
    let tick_tock = model == SemanticModel::TickTock;
    let mut norm = Normaliser::new(spec);
    let root = norm.root(meter)?;
    // Rows are (normal-form node, implementation state) pairs.
    let width = imp.state_width();
    let mut visited = Visited::new(4 + width, RowHash::Pair);
    let mut init = vec![0u8; width];
    imp.encode(&imp.initial(), &mut init);
    let mut row = Vec::new();
    pair_row(root, &init, &mut row);
    visited.insert(meter, pair_row_hash(&row), &row, NO_PARENT)?;
    let mut div = TauDivergence::new();
    let mut offered: Vec<Event> = Vec::new();

    let found = explore(
        &mut visited,
        meter,
        width,
        |p: &[u8], out: &mut Rows<Im::State>| imp.successor_rows(split_pair(p).1, out),
        |visited, meter, i, succ| {
            let n = split_pair(visited.row(i)).0;
            let has_tau = succ.labels().iter().any(|l| l.event == TAU);
            if fd {
                if norm.divergent(n) {
                    // The specification may do anything from here.
                    return Ok(Flow::Continue);
                }
                if has_tau && div.diverges(imp, &imp.decode(split_pair(visited.row(i)).1), meter)? {
                    return Ok(Flow::Break(Found::Divergence(i)));
                }
            }
            if failures && !has_tau {
                offered.clear();
                offered.extend(succ.labels().iter().map(|l| l.event));
                offered.sort_unstable();
                offered.dedup();
                if !norm.accepts(n, &offered) {
                    return Ok(Flow::Break(Found::Refusal(i, offered.clone(), norm.acceptances(n))));
                }
            }
            for (label, t, h) in succ.iter() {
                let next = if label.event == TAU {
                    n
                } else if tick_tock && label.event == TOCK && !has_tau {
                    // Time passes at a stable state, refusing everything not
                    // `offered` (computed above): the largest refusal is the
                    // strongest observation, as smaller ones leave more
                    // specification states to continue from.
                    match norm.after_tock(n, &offered, meter)? {
                        Some(m) => m,
                        None => {
                            let acc = norm.tock_acceptances(n);
                            return Ok(Flow::Break(Found::TockRefusal(i, offered.clone(), acc, imp.decode(t))));
                        }
                    }
                } else {
                    match norm.after(n, label.event, meter)? {
                        Some(m) => m,
                        None => return Ok(Flow::Break(Found::Trace(i, label, imp.decode(t)))),
                    }
                };
                pair_row(next, t, &mut row);
                visited.insert(meter, pair_hash_from(next, h), &row, i)?;
            }
            Ok(Flow::Continue)
        },
    )?;

    // The label of the step that discovered pair `c` from pair `p`: the
    // first transition of p's state into c's state that leads the
    // specification to c's node (every node it needs is memoised), found
    // as the search found it (a tick-tock `tock` by what p's state offers).
    let mut label = |p: u32, c: u32| -> Label {
        let (n, parent) = split_pair(visited.row(p));
        let (m, child) = split_pair(visited.row(c));
        let mut rows: Rows<Im::State> = Rows::new(width);
        imp.successor_rows(parent, &mut rows);
        let stable = !rows.labels(0, rows.len()).iter().any(|l| l.event == TAU);
        let mut offered: Vec<Event> = rows.labels(0, rows.len()).iter().map(|l| l.event).collect();
        offered.sort_unstable();
        offered.dedup();
        for k in 0..rows.len() {
            let l = rows.label(k);
            if rows.row(k) != child {
                continue;
            }
            let next = if l.event == TAU {
                Some(n)
            } else if tick_tock && l.event == TOCK && stable {
                norm.after_tock(n, &offered, meter).ok().flatten()
            } else {
                norm.after(n, l.event, meter).ok().flatten()
            };
            if next == Some(m) {
                return l;
            }
        }
        Label::TAU
    };
    let view = |r: &[u8]| imp.decode(split_pair(r).1);
    Ok(match found {
        None => None,
        Some(Found::Trace(i, event, t)) => {
            let mut path = visited.path_to(i, view, &mut label);
            path.steps.push((event, t));
            Some(RefinementCex::Trace { path, event })
        }
        Some(Found::Refusal(i, offered, acceptances)) => {
            Some(RefinementCex::Refusal { path: visited.path_to(i, view, &mut label), offered, acceptances })
        }
        Some(Found::TockRefusal(i, offered, acceptances, t)) => {
            let mut path = visited.path_to(i, view, &mut label);
            path.steps.push((Label::TOCK, t));
            Some(RefinementCex::TockRefusal { path, offered, acceptances })
        }
        Some(Found::Divergence(i)) => {
            let path = visited.path_to(i, view, &mut label);
            let cycle = div.lasso(imp, path.last(), meter)?;
            Some(RefinementCex::Divergence { path, cycle })
        }
    })
}

/// Checks whether `lts` is deterministic in the failures-divergences sense:
/// divergence-free, and never able to both perform and refuse an event
/// after the same trace. Breadth first over the normal form, so the
/// counterexample's trace is shortest; its path is a shortest execution
/// with that trace. The statistics count normal-form nodes as states.
pub fn check_determinism<L: Lts>(
    lts: &L,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (DeterminismResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match determinism_search(lts, &mut meter) {
        Ok(r) => r,
        Err(stop) => DeterminismResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

fn determinism_search<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<DeterminismResult<L::State>, Stop> {
    let mut norm = Normaliser::new(lts);
    let root = norm.root(meter)?;
    // Nodes are created only below, in BFS order, so node ids are BFS
    // indices; each records the node and event it was first reached by.
    let mut parent: Vec<(u32, Event)> = vec![(NO_PARENT, TAU)];
    let mut depth: Vec<u32> = vec![0];
    let mut k = root;
    let mut initials: Vec<Event> = Vec::new();
    while (k as usize) < norm.node_count() {
        meter.poll()?;
        meter.stats.states = norm.node_count() as u64;
        meter.stats.plies = meter.stats.plies.max(depth[k as usize] + 1);
        let trace_to = |k: u32| {
            let mut trace = Vec::new();
            let mut at = k;
            while parent[at as usize].0 != NO_PARENT {
                trace.push(parent[at as usize].1);
                at = parent[at as usize].0;
            }
            trace.reverse();
            trace
        };
        if norm.divergent(k) {
            let mut div = TauDivergence::new();
            let mut targets = rustc_hash::FxHashSet::default();
            for &m in norm.members(k) {
                let s = norm.state(m);
                if div.diverges(lts, s, meter)? {
                    targets.insert(s.clone());
                }
            }
            let trace = trace_to(k);
            // Some member is reachable by the node's trace, so the search
            // finds one; the bare initial state is only a safety net.
            let path = trace_search(lts, &trace, |s| targets.contains(s), meter)?.unwrap_or_else(|| bare(lts));
            let cycle = div.lasso(lts, path.last(), meter)?;
            return Ok(DeterminismResult::Divergent { path, cycle });
        }
        norm.initials(k, &mut initials);
        if let Some((m, event)) = norm.refusing_member(k, &initials) {
            let trace = trace_to(k);
            let target = norm.state(m).clone();
            let path = trace_search(lts, &trace, |s| *s == target, meter)?.unwrap_or_else(|| bare(lts));
            return Ok(DeterminismResult::Nondeterministic { path, event });
        }
        for &e in &initials {
            meter.stats.transitions += 1;
            if let Some(next) = norm.after(k, e, meter)? {
                if next as usize == parent.len() {
                    if parent.len() as u64 >= meter.budget.max_states {
                        return Err(Stop::States);
                    }
                    parent.push((k, e));
                    depth.push(depth[k as usize] + 1);
                }
            }
        }
        k += 1;
    }
    meter.stats.states = norm.node_count() as u64;
    Ok(DeterminismResult::Deterministic)
}

/// The empty path at the initial state.
fn bare<L: Lts>(lts: &L) -> Path<L::State> {
    Path { initial: lts.initial(), steps: Vec::new() }
}

/// `a ⊆ b` for sorted, deduplicated slices.
fn is_subset(a: &[Event], b: &[Event]) -> bool {
    let mut rest = b.iter();
    a.iter().all(|x| rest.by_ref().any(|y| y == x))
}

/// A `(start, len)` range into one of the normaliser's arenas.
type Range = (u32, u32);

/// A range's slice of an arena.
fn slice<T>(arena: &[T], (start, len): Range) -> &[T] {
    &arena[start as usize..(start + len) as usize]
}

/// Not computed yet (transitions) / no successor (after).
const NONE: u32 = u32::MAX;

/// The lazily built normal form of an LTS (pre-normal form: no
/// bisimulation reduction). Nodes and per-state transitions live in flat
/// arenas: specifications can have many nodes, and a node is built in a
/// handful of appends instead of a handful of allocations.
pub(crate) struct Normaliser<'l, L: Lts> {
    lts: &'l L,
    ids: FxHashMap<L::State, u32>,
    states: Vec<L::State>,
    /// Each state's transitions as (event, state id), computed on first
    /// need (`start == NONE` until then).
    trans_at: Vec<Range>,
    trans: Vec<(Event, u32)>,
    /// Node ids, hashed by their members.
    node_table: HashTable<u32>,
    /// Per node: its members (sorted state ids), whether it can diverge,
    /// its minimal acceptances (a range of `acc_sets`, each a range of
    /// `acc_events`).
    members_at: Vec<Range>,
    members: Vec<u32>,
    divergent: Vec<bool>,
    acc_at: Vec<Range>,
    acc_sets: Vec<Range>,
    acc_events: Vec<Event>,
    /// Memo of `after`: the successor node, or `NONE`.
    after: FxHashMap<(u32, Event), u32>,
    /// Memo of `after_tock`, by node and the implementation's offer.
    after_tock: FxHashMap<(u32, Vec<Event>), u32>,
    /// Closure marks: `mark[s] == epoch` once s is in the set being built.
    mark: Vec<u32>,
    epoch: u32,
    // Reused buffers.
    buf: Vec<(Label, L::State)>,
    stack: Vec<u32>,
    set: Vec<u32>,
    seeds: Vec<u32>,
}

impl<'l, L: Lts> Normaliser<'l, L> {
    pub(crate) fn new(lts: &'l L) -> Self {
        Normaliser {
            lts,
            ids: FxHashMap::default(),
            states: Vec::new(),
            trans_at: Vec::new(),
            trans: Vec::new(),
            node_table: HashTable::new(),
            members_at: Vec::new(),
            members: Vec::new(),
            divergent: Vec::new(),
            acc_at: Vec::new(),
            acc_sets: Vec::new(),
            acc_events: Vec::new(),
            after: FxHashMap::default(),
            after_tock: FxHashMap::default(),
            mark: Vec::new(),
            epoch: 0,
            buf: Vec::new(),
            stack: Vec::new(),
            set: Vec::new(),
            seeds: Vec::new(),
        }
    }

    /// The number of nodes built so far.
    pub(crate) fn node_count(&self) -> usize {
        self.members_at.len()
    }

    /// The members of node `n`: sorted state ids.
    pub(crate) fn members(&self, n: u32) -> &[u32] {
        slice(&self.members, self.members_at[n as usize])
    }

    /// The state with id `id`.
    pub(crate) fn state(&self, id: u32) -> &L::State {
        &self.states[id as usize]
    }

    /// Whether some member of node `n` can reach a τ-cycle (inside the
    /// node, which is τ-closed).
    pub(crate) fn divergent(&self, n: u32) -> bool {
        self.divergent[n as usize]
    }

    fn acceptance_sets(&self, n: u32) -> impl Iterator<Item = &[Event]> {
        slice(&self.acc_sets, self.acc_at[n as usize]).iter().map(|&r| slice(&self.acc_events, r))
    }

    /// The minimal initial-event sets of the stable members of node `n`,
    /// each sorted, in sorted order.
    pub(crate) fn acceptances(&self, n: u32) -> Vec<Vec<Event>> {
        self.acceptance_sets(n).map(<[Event]>::to_vec).collect()
    }

    /// Whether a stable state offering `offered` (sorted) is allowed at
    /// node `n`: it offers all of some acceptance.
    pub(crate) fn accepts(&self, n: u32, offered: &[Event]) -> bool {
        self.acceptance_sets(n).any(|a| is_subset(a, offered))
    }

    fn intern(&mut self, s: L::State, meter: &mut Meter<'_>) -> Result<u32, Stop> {
        if let Some(&id) = self.ids.get(&s) {
            return Ok(id);
        }
        if self.states.len() as u64 >= meter.budget.max_states.min(u64::from(NONE - 1)) {
            return Err(Stop::States);
        }
        // The state twice (map key and list) plus map and list overhead.
        meter.add_extra_bytes(2 * self.lts.state_bytes(&s) as u64 + 24)?;
        let id = self.states.len() as u32;
        self.ids.insert(s.clone(), id);
        self.states.push(s);
        self.trans_at.push((NONE, 0));
        self.mark.push(0);
        Ok(id)
    }

    fn ensure_trans(&mut self, id: u32, meter: &mut Meter<'_>) -> Result<(), Stop> {
        if self.trans_at[id as usize].0 != NONE {
            return Ok(());
        }
        let mut buf = std::mem::take(&mut self.buf);
        buf.clear();
        self.lts.successors(&self.states[id as usize], &mut buf);
        let start = self.trans.len() as u32;
        for (label, t) in buf.drain(..) {
            let tid = self.intern(t, meter)?;
            self.trans.push((label.event, tid));
        }
        self.buf = buf;
        let len = self.trans.len() as u32 - start;
        meter.add_extra_bytes(u64::from(len) * 8)?;
        self.trans_at[id as usize] = (start, len);
        Ok(())
    }

    /// The transitions of a state whose transitions were computed.
    fn trans(&self, id: u32) -> &[(Event, u32)] {
        match self.trans_at[id as usize] {
            (NONE, _) => &[],
            r => slice(&self.trans, r),
        }
    }

    fn has_tau(&self, id: u32) -> bool {
        self.trans(id).iter().any(|&(e, _)| e == TAU)
    }

    /// The node of the initial state's τ-closure.
    pub(crate) fn root(&mut self, meter: &mut Meter<'_>) -> Result<u32, Stop> {
        let init = self.lts.initial();
        let id = self.intern(init, meter)?;
        self.seeds.clear();
        self.seeds.push(id);
        self.close(meter)
    }

    /// The node after `event` from node `n`, or `None` if no member can
    /// perform it. Memoised.
    pub(crate) fn after(&mut self, n: u32, event: Event, meter: &mut Meter<'_>) -> Result<Option<u32>, Stop> {
        if let Some(&m) = self.after.get(&(n, event)) {
            return Ok((m != NONE).then_some(m));
        }
        // Members' transitions were computed when the node was built.
        let mut seeds = std::mem::take(&mut self.seeds);
        seeds.clear();
        for &s in self.members(n) {
            seeds.extend(self.trans(s).iter().filter(|(e, _)| *e == event).map(|&(_, t)| t));
        }
        self.seeds = seeds;
        let result = if self.seeds.is_empty() { NONE } else { self.close(meter)? };
        meter.add_extra_bytes(16)?;
        self.after.insert((n, event), result);
        Ok((result != NONE).then_some(result))
    }

    /// Whether member `s` is stable, can let time pass and offers nothing
    /// outside `offered` (sorted): it refuses all `offered` refuses.
    fn passes_time_within(&self, s: u32, offered: &[Event]) -> bool {
        let t = self.trans(s);
        t.iter().any(|&(e, _)| e == TOCK) && t.iter().all(|&(e, _)| e != TAU && offered.binary_search(&e).is_ok())
    }

    /// Tick-tock: the node after a `tock` taken at a stable state offering
    /// `offered` (sorted, with `tock`), or `None`. Only the stable members
    /// that refuse all the implementation refuses and can let time pass
    /// continue. Memoised.
    pub(crate) fn after_tock(&mut self, n: u32, offered: &[Event], meter: &mut Meter<'_>) -> Result<Option<u32>, Stop> {
        if let Some(&m) = self.after_tock.get(&(n, offered.to_vec())) {
            return Ok((m != NONE).then_some(m));
        }
        let mut seeds = std::mem::take(&mut self.seeds);
        seeds.clear();
        for &s in self.members(n) {
            if self.passes_time_within(s, offered) {
                seeds.extend(self.trans(s).iter().filter(|(e, _)| *e == TOCK).map(|&(_, t)| t));
            }
        }
        self.seeds = seeds;
        let result = if self.seeds.is_empty() { NONE } else { self.close(meter)? };
        meter.add_extra_bytes(32 + 4 * offered.len() as u64)?;
        self.after_tock.insert((n, offered.to_vec()), result);
        Ok((result != NONE).then_some(result))
    }

    /// What the stable members of node `n` that can let time pass offer:
    /// each sorted, deduplicated, in sorted order.
    pub(crate) fn tock_acceptances(&self, n: u32) -> Vec<Vec<Event>> {
        let mut out: Vec<Vec<Event>> = self
            .members(n)
            .iter()
            .map(|&s| self.trans(s))
            .filter(|t| t.iter().any(|&(e, _)| e == TOCK) && t.iter().all(|&(e, _)| e != TAU))
            .map(|t| {
                let mut v: Vec<Event> = t.iter().map(|&(e, _)| e).collect();
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();
        out.sort();
        out.dedup();
        out
    }

    /// The node of the τ-closure of `self.seeds`, built if new.
    fn close(&mut self, meter: &mut Meter<'_>) -> Result<u32, Stop> {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            // Marks wrapped: clear them so no stale mark matches.
            self.mark.iter_mut().for_each(|m| *m = 0);
            self.epoch = 1;
        }
        let epoch = self.epoch;
        let mut stack = std::mem::take(&mut self.stack);
        let mut set = std::mem::take(&mut self.set);
        stack.clear();
        set.clear();
        for &s in &self.seeds {
            if self.mark[s as usize] != epoch {
                self.mark[s as usize] = epoch;
                stack.push(s);
            }
        }
        while let Some(s) = stack.pop() {
            if let Err(stop) = meter.poll().and_then(|()| self.ensure_trans(s, meter)) {
                (self.stack, self.set) = (stack, set);
                return Err(stop);
            }
            set.push(s);
            for &(e, t) in slice(&self.trans, self.trans_at[s as usize]) {
                if e == TAU && self.mark[t as usize] != epoch {
                    self.mark[t as usize] = epoch;
                    stack.push(t);
                }
            }
        }
        set.sort_unstable();
        let result = self.node_of(&set, meter);
        (self.stack, self.set) = (stack, set);
        result
    }

    /// The node whose members are `set` (sorted, τ-closed), built if new.
    fn node_of(&mut self, set: &[u32], meter: &mut Meter<'_>) -> Result<u32, Stop> {
        let hash = fx(set);
        let (members, members_at) = (&self.members, &self.members_at);
        let same = |&n: &u32| slice(members, members_at[n as usize]) == set;
        if let Some(&n) = self.node_table.find(hash, same) {
            return Ok(n);
        }
        let n = self.node_count();
        if n as u64 >= meter.budget.max_states.min(u64::from(NONE - 1)) {
            return Err(Stop::States);
        }
        let divergent = self.has_tau_cycle(set);
        let acc_start = self.acc_sets.len();
        self.push_min_acceptances(set);
        self.members_at.push((self.members.len() as u32, set.len() as u32));
        self.members.extend_from_slice(set);
        self.divergent.push(divergent);
        self.acc_at.push((acc_start as u32, (self.acc_sets.len() - acc_start) as u32));
        let (members, members_at) = (&self.members, &self.members_at);
        self.node_table.insert_unique(hash, n as u32, |&m| fx(slice(members, members_at[m as usize])));
        meter.add_extra_bytes(set.len() as u64 * 4 + 48)?;
        Ok(n as u32)
    }

    /// Whether the τ-edges among `set` (τ-closed, sorted) contain a cycle:
    /// Kahn's algorithm fails to remove every member.
    fn has_tau_cycle(&self, set: &[u32]) -> bool {
        let taus = set.iter().map(|&s| self.trans(s).iter().filter(|&&(e, _)| e == TAU).count()).sum::<usize>();
        if taus == 0 {
            return false;
        }
        let pos = |t: u32| set.binary_search(&t).ok();
        let mut indegree = vec![0u32; set.len()];
        for &s in set {
            for &(e, t) in self.trans(s) {
                if let (TAU, Some(p)) = (e, pos(t)) {
                    indegree[p] += 1;
                }
            }
        }
        let mut ready: Vec<usize> = (0..set.len()).filter(|&p| indegree[p] == 0).collect();
        let mut removed = 0;
        while let Some(p) = ready.pop() {
            removed += 1;
            for &(e, t) in self.trans(set[p]) {
                if let (TAU, Some(q)) = (e, pos(t)) {
                    indegree[q] -= 1;
                    if indegree[q] == 0 {
                        ready.push(q);
                    }
                }
            }
        }
        removed < set.len()
    }

    /// Appends to the acceptance arenas the minimal initial-event sets of
    /// the stable members of `set`, sorted.
    fn push_min_acceptances(&mut self, set: &[u32]) {
        let first_event = self.acc_events.len();
        let first_set = self.acc_sets.len();
        for &s in set {
            if self.has_tau(s) {
                continue;
            }
            let start = self.acc_events.len();
            let (trans, trans_at) = (&self.trans, &self.trans_at);
            self.acc_events.extend(slice(trans, trans_at[s as usize]).iter().map(|&(e, _)| e));
            self.acc_events[start..].sort_unstable();
            let mut len = 0;
            for i in start..self.acc_events.len() {
                if len == 0 || self.acc_events[start + len - 1] != self.acc_events[i] {
                    self.acc_events[start + len] = self.acc_events[i];
                    len += 1;
                }
            }
            self.acc_events.truncate(start + len);
            self.acc_sets.push((start as u32, len as u32));
        }
        if self.acc_sets.len() - first_set <= 1 {
            return;
        }
        // Several stable members: sort, deduplicate, keep the minimal sets,
        // and rewrite them compactly.
        let events = &self.acc_events;
        let mut sets: Vec<&[Event]> = self.acc_sets[first_set..].iter().map(|&r| slice(events, r)).collect();
        sets.sort();
        sets.dedup();
        let minimal: Vec<Vec<Event>> =
            sets.iter().filter(|a| !sets.iter().any(|b| b != *a && is_subset(b, a))).map(|a| a.to_vec()).collect();
        self.acc_events.truncate(first_event);
        self.acc_sets.truncate(first_set);
        for a in minimal {
            self.acc_sets.push((self.acc_events.len() as u32, a.len() as u32));
            self.acc_events.extend(a);
        }
    }

    /// The visible events some member of node `n` can perform, sorted.
    fn initials(&self, n: u32, out: &mut Vec<Event>) {
        out.clear();
        for &s in self.members(n) {
            out.extend(self.trans(s).iter().map(|&(e, _)| e).filter(|&e| e != TAU));
        }
        out.sort_unstable();
        out.dedup();
    }

    /// The first stable member (by id) of node `n` that refuses one of the
    /// node's `initials`, with the smallest such event.
    fn refusing_member(&self, n: u32, initials: &[Event]) -> Option<(u32, Event)> {
        for &s in self.members(n) {
            let trans = self.trans(s);
            if trans.iter().any(|&(e, _)| e == TAU) {
                continue;
            }
            if let Some(&e) = initials.iter().find(|&&e| !trans.iter().any(|&(f, _)| f == e)) {
                return Some((s, e));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subsets() {
        assert!(is_subset(&[], &[1, 2]));
        assert!(is_subset(&[1, 3], &[1, 2, 3]));
        assert!(!is_subset(&[1, 4], &[1, 2, 3]));
        assert!(!is_subset(&[0], &[]));
    }
}
