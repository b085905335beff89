//! Timed deadlock (semantics.md §7.4, §8.4): a reachable state from which
//! the process can only let time pass, forever.
//!
//! RoboTool checks it as divergence freedom of the process with `tock`
//! prioritised below every other event and hidden; natively, a `tock` is
//! *forced* at a state where no τ and no event other than `tock` is enabled
//! (✓ counts as another event), and a timed deadlock is a reachable cycle of
//! forced `tock`s and τ steps (the hidden `tock`s and the process's own τs
//! together diverge: a machine that only ever lets time pass between
//! internal steps is stuck just as much). One exploration records those
//! edges; an iterative Tarjan on them finds the cycles. A state with no transition at all (a
//! timelock) is not a timed deadlock; [`find_deadlock`](super::find_deadlock)
//! reports those.

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Label, Lts, Rows, TAU, TOCK};

use super::{cyclic_components, explore, shortest_cycle, state_path, tarjan, visited_from_initial, Flow, Lasso, Path};

/// The verdict of [`find_timed_deadlock`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TimedDeadlockResult<S> {
    /// No reachable cycle of forced `tock`s and τs.
    Free,
    /// After `path` the process can only perform `tock`, forever: `cycle`
    /// is a cycle of forced `tock`s from the end of `path` back to it.
    /// `path` is a shortest path to a state on such a cycle (the first in
    /// BFS order), `cycle` a shortest forced-`tock` cycle through it.
    TimedDeadlock {
        /// The shortest path to the first state on a forced-`tock` cycle.
        path: Path<S>,
        /// The `tock` steps around the cycle, ending at the end of `path`.
        cycle: Vec<(Label, S)>,
    },
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Searches `lts` for a reachable cycle of forced `tock`s.
pub fn find_timed_deadlock<L: Lts>(
    lts: &L,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (TimedDeadlockResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match search(lts, &mut meter) {
        Ok(Some((path, cycle))) => TimedDeadlockResult::TimedDeadlock { path, cycle },
        Ok(None) => TimedDeadlockResult::Free,
        Err(stop) => TimedDeadlockResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

fn search<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Option<Lasso<L::State>>, Stop> {
    let mut visited = visited_from_initial(lts, meter)?;
    // Forced-tock edges (source, target, label), in source order because
    // sources are visited in index order.
    let mut forced: Vec<(u32, u32, Label)> = Vec::new();
    explore(
        &mut visited,
        meter,
        lts.state_width(),
        |s: &[u8], out: &mut Rows<L::State>| lts.successor_rows(s, out),
        |visited, meter, i, succ| {
            let only_tock = !succ.is_empty() && succ.labels().iter().all(|l| l.event == TOCK);
            for (label, t, h) in succ.iter() {
                let (j, _) = visited.insert(meter, h, t, i)?;
                if only_tock || label.event == TAU {
                    if forced.len() == forced.capacity() {
                        meter.add_extra_bytes((forced.capacity().max(4) * 12) as u64)?;
                    }
                    forced.push((i, j, label));
                }
            }
            Ok(Flow::<()>::Continue)
        },
    )?;

    let n = visited.len();
    // Tarjan's arrays and the compressed graph.
    meter.add_extra_bytes((n as u64 + 1) * 24 + forced.len() as u64 * 4)?;
    let mut start = vec![0usize; n + 1];
    for &(a, _, _) in &forced {
        start[a as usize + 1] += 1;
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let targets: Vec<u32> = forced.iter().map(|&(_, b, _)| b).collect();
    let comp = tarjan(&start, &targets).comp;
    let cyclic = cyclic_components(&start, &targets, &comp);
    // Indices are in BFS order: the first state on a cycle is the nearest.
    let Some(entry) = (0..n).find(|&v| cyclic[comp[v] as usize]) else {
        return Ok(None);
    };
    let path = state_path(lts, &visited, entry as u32);
    let cycle = shortest_cycle(&start, &targets, &comp, entry as u32)
        .unwrap_or_default()
        .into_iter()
        .map(|e| (forced[e].2, lts.decode(visited.row(forced[e].1))))
        .collect();
    Ok(Some((path, cycle)))
}
