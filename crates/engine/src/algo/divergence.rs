//! Divergence: a reachable state from which the process can perform τ
//! forever (a reachable τ-cycle), found breadth first, with the shortest
//! path to the first such state and the τ-lasso it can follow.
//!
//! [`TauDivergence`] is the per-state test the refinement and determinism
//! checks share: whether a state can reach a τ-cycle by τ steps, computed by
//! an iterative Tarjan over the τ-subgraph below it and memoised, so every
//! state is classified once.

use rustc_hash::FxHashMap;

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Label, Lts, Rows, TAU};

use super::{cyclic_components, explore, shortest_cycle, state_path, tarjan, visited_from_initial, Flow, Lasso, Path};

/// The verdict of [`find_divergence`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DivergenceResult<S> {
    /// No reachable state can perform τ forever.
    Free,
    /// After `path` (the shortest path to a state that can diverge) the
    /// process can follow `cycle` forever: τ steps from the end of `path`
    /// into a τ-loop and once around it (the last state of `cycle` is the
    /// state where the loop starts, which appears earlier in `cycle` or is
    /// the end of `path`).
    Divergent {
        /// The shortest path to the first divergent state in BFS order.
        path: Path<S>,
        /// The τ-lasso from there.
        cycle: Vec<(Label, S)>,
    },
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Searches `lts` for a reachable divergence, breadth first.
pub fn find_divergence<L: Lts>(
    lts: &L,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (DivergenceResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match search(lts, &mut meter) {
        Ok(Some((path, cycle))) => DivergenceResult::Divergent { path, cycle },
        Ok(None) => DivergenceResult::Free,
        Err(stop) => DivergenceResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

fn search<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Option<Lasso<L::State>>, Stop> {
    let mut visited = visited_from_initial(lts, meter)?;
    let mut div = TauDivergence::new();
    let found = explore(
        &mut visited,
        meter,
        lts.state_width(),
        |s: &[u8], out: &mut Rows<L::State>| lts.successor_rows(s, out),
        |visited, meter, i, succ| {
            // A state without τ cannot start a τ-cycle: skip the test.
            if succ.labels().iter().any(|l| l.event == TAU) && div.diverges(lts, &lts.decode(visited.row(i)), meter)? {
                return Ok(Flow::Break(i));
            }
            for (_, t, h) in succ.iter() {
                visited.insert(meter, h, t, i)?;
            }
            Ok(Flow::Continue)
        },
    )?;
    match found {
        Some(i) => {
            let path = state_path(lts, &visited, i);
            let cycle = div.lasso(lts, path.last(), meter)?;
            Ok(Some((path, cycle)))
        }
        None => Ok(None),
    }
}

/// The memoised test "can this state reach a τ-cycle by τ steps?".
pub(crate) struct TauDivergence<S> {
    /// Per classified state: [`NO`] or [`YES`]; during a classification,
    /// `FIRST_LOCAL + i` for the `i`-th node of the τ-subgraph being built
    /// (so one table serves as memo and as the subgraph's index).
    memo: FxHashMap<S, u32>,
    // Buffers of the τ-subgraph under classification, kept between calls.
    nodes: Vec<S>,
    start: Vec<usize>,
    targets: Vec<u32>,
    known: Vec<bool>,
    buf: Vec<(Label, S)>,
}

const NO: u32 = 0;
const YES: u32 = 1;
const FIRST_LOCAL: u32 = 2;

/// The τ-subgraph below a state, for counterexamples: nodes in BFS order
/// from the start (index 0), edges in compressed form with their labels.
struct TauGraph<S> {
    nodes: Vec<S>,
    start: Vec<usize>,
    targets: Vec<u32>,
    labels: Vec<Label>,
    /// BFS parent of each node, as an edge position (`usize::MAX` for the start).
    parent_edge: Vec<usize>,
}

impl<S: Clone + Eq + std::hash::Hash> TauDivergence<S> {
    pub(crate) fn new() -> Self {
        TauDivergence {
            memo: FxHashMap::default(),
            nodes: Vec::new(),
            start: Vec::new(),
            targets: Vec::new(),
            known: Vec::new(),
            buf: Vec::new(),
        }
    }

    /// Whether `s` can reach a τ-cycle by τ steps. Classifies (and
    /// memoises) every unclassified state of the τ-subgraph below `s` in
    /// one Tarjan pass.
    pub(crate) fn diverges<L: Lts<State = S>>(&mut self, lts: &L, s: &S, meter: &mut Meter<'_>) -> Result<bool, Stop> {
        if let Some(&d) = self.memo.get(s) {
            return Ok(d == YES);
        }
        // The τ-subgraph of unclassified states below s; edges to
        // classified states only record whether they lead to divergence.
        self.nodes.clear();
        self.start.clear();
        self.targets.clear();
        self.known.clear();
        self.start.push(0);
        self.nodes.push(s.clone());
        self.memo.insert(s.clone(), FIRST_LOCAL);
        let mut buf = std::mem::take(&mut self.buf);
        let mut k = 0;
        while k < self.nodes.len() {
            meter.poll()?;
            if self.memo.len() as u64 > meter.budget.max_states {
                return Err(Stop::States);
            }
            buf.clear();
            lts.successors(&self.nodes[k], &mut buf);
            let mut known = false;
            for (label, t) in buf.drain(..) {
                if label.event != TAU {
                    continue;
                }
                let target = match self.memo.get(&t) {
                    Some(&NO) => continue,
                    Some(&YES) => {
                        known = true;
                        continue;
                    }
                    Some(&local) => local - FIRST_LOCAL,
                    None => {
                        let j = self.nodes.len() as u32;
                        meter.add_extra_bytes((2 * lts.state_bytes(&t) + std::mem::size_of::<S>() + 24) as u64)?;
                        self.memo.insert(t.clone(), FIRST_LOCAL + j);
                        self.nodes.push(t);
                        j
                    }
                };
                self.targets.push(target);
            }
            self.known.push(known);
            self.start.push(self.targets.len());
            k += 1;
        }
        self.buf = buf;

        let divergent: Vec<bool> = if self.nodes.len() == 1 {
            // The common case: s's τ steps all lead to classified states.
            vec![self.known[0] || !self.targets.is_empty()]
        } else {
            let sccs = tarjan(&self.start, &self.targets);
            let mut flag = cyclic_components(&self.start, &self.targets, &sccs.comp);
            // Components complete before those that reach them, so one pass
            // in completion order settles each from its successors.
            for &v in &sccs.order {
                let v = v as usize;
                let c = sccs.comp[v] as usize;
                let reaches = self.known[v]
                    || self.targets[self.start[v]..self.start[v + 1]]
                        .iter()
                        .any(|&w| flag[sccs.comp[w as usize] as usize]);
                flag[c] |= reaches;
            }
            (0..self.nodes.len()).map(|v| flag[sccs.comp[v] as usize]).collect()
        };
        for (state, &d) in self.nodes.drain(..).zip(&divergent) {
            self.memo.insert(state, if d { YES } else { NO });
        }
        Ok(divergent[0])
    }

    /// For a state that [`diverges`](Self::diverges): the shortest τ-path to
    /// a state on a τ-cycle, followed by the shortest τ-cycle through it.
    pub(crate) fn lasso<L: Lts<State = S>>(
        &mut self,
        lts: &L,
        s: &S,
        meter: &mut Meter<'_>,
    ) -> Result<Vec<(Label, S)>, Stop> {
        if !self.diverges(lts, s, meter)? {
            return Ok(Vec::new());
        }
        let g = self.divergent_graph(lts, s, meter)?;
        let comp = tarjan(&g.start, &g.targets).comp;
        let cyclic = cyclic_components(&g.start, &g.targets, &comp);
        // Nodes are in BFS order from s: the first on a cycle is the nearest.
        let Some(entry) = (0..g.nodes.len()).find(|&v| cyclic[comp[v] as usize]) else {
            return Ok(Vec::new());
        };
        let mut prefix = Vec::new();
        let mut at = entry;
        while g.parent_edge[at] != usize::MAX {
            let e = g.parent_edge[at];
            prefix.push(e);
            at = super::source_of(&g.start, e) as usize;
        }
        prefix.reverse();
        let around = shortest_cycle(&g.start, &g.targets, &comp, entry as u32).unwrap_or_default();
        Ok(prefix.into_iter().chain(around).map(|e| (g.labels[e], g.nodes[g.targets[e] as usize].clone())).collect())
    }

    /// The τ-subgraph of divergent states reachable from `from` (all
    /// classified by [`diverges`](Self::diverges) already), breadth first.
    fn divergent_graph<L: Lts<State = S>>(
        &mut self,
        lts: &L,
        from: &S,
        meter: &mut Meter<'_>,
    ) -> Result<TauGraph<S>, Stop> {
        let mut index: FxHashMap<S, u32> = FxHashMap::default();
        let mut g = TauGraph {
            nodes: vec![from.clone()],
            start: vec![0],
            targets: Vec::new(),
            labels: Vec::new(),
            parent_edge: vec![usize::MAX],
        };
        index.insert(from.clone(), 0);
        let mut buf = Vec::new();
        let mut k = 0;
        while k < g.nodes.len() {
            meter.poll()?;
            buf.clear();
            lts.successors(&g.nodes[k], &mut buf);
            for (label, t) in buf.drain(..) {
                if label.event != TAU || self.memo.get(&t) != Some(&YES) {
                    continue;
                }
                let target = match index.get(&t) {
                    Some(&j) => j,
                    None => {
                        let j = g.nodes.len() as u32;
                        index.insert(t.clone(), j);
                        g.nodes.push(t);
                        g.parent_edge.push(g.targets.len());
                        j
                    }
                };
                g.targets.push(target);
                g.labels.push(label);
            }
            g.start.push(g.targets.len());
            k += 1;
        }
        Ok(g)
    }
}
