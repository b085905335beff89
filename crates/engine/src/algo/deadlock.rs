//! Deadlock search (semantics.md §7.2, §8.2): a breadth-first search for a
//! reachable state with no transition at all, with the shortest path to it.
//!
//! Models have already applied hiding and priority, so "no transition"
//! after priority is exactly FDR's `deadlock free [F]` on the prioritised
//! process. The one exception is successful termination: the state a ✓
//! step leads to has no transitions but is not a deadlock. A state with no
//! transitions is a deadlock when some path reaches it by a step other than
//! ✓ (or it is the initial state).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Label, Lts, Rows, TICK};

use super::{explore, state_path, visited_from_initial, Flow, Path};

/// The verdict of [`find_deadlock`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DeadlockResult<S> {
    /// No reachable state deadlocks.
    Free,
    /// The shortest path (in steps, τ included) to a deadlocked state: the
    /// first one in breadth-first order.
    Deadlock(Path<S>),
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Searches `lts` for a reachable deadlock, breadth first.
pub fn find_deadlock<L: Lts>(
    lts: &L,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (DeadlockResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match search(lts, &mut meter) {
        Ok(Some(path)) => DeadlockResult::Deadlock(path),
        Ok(None) => DeadlockResult::Free,
        Err(stop) => DeadlockResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

/// Where a deadlock was found: the state, or (for a terminated state also
/// reached by a non-✓ step) the source and label of that step.
enum Found {
    State(u32),
    Via(u32, Label, u32),
}

fn search<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Option<Path<L::State>>, Stop> {
    let mut visited = visited_from_initial(lts, meter)?;

    // ✓ bookkeeping, only ever non-empty for models that terminate:
    // states first reached by ✓; those of them found to have no
    // transitions; and the first non-✓ step into a ✓-reached state that
    // was not expanded yet.
    let mut tick_reached: FxHashSet<u32> = FxHashSet::default();
    let mut terminated: FxHashSet<u32> = FxHashSet::default();
    let mut other_entry: FxHashMap<u32, (u32, Label)> = FxHashMap::default();

    let found = explore(
        &mut visited,
        meter,
        lts.state_width(),
        |s: &[u8], out: &mut Rows<L::State>| lts.successor_rows(s, out),
        |visited, meter, i, succ| {
            if succ.is_empty() {
                // Reached first by ✓ (the root is not).
                if !tick_reached.contains(&i) {
                    return Ok(Flow::Break(Found::State(i)));
                }
                if let Some(&(src, label)) = other_entry.get(&i) {
                    return Ok(Flow::Break(Found::Via(src, label, i)));
                }
                terminated.insert(i);
                return Ok(Flow::Continue);
            }
            for (label, t, h) in succ.iter() {
                let (j, new) = visited.insert(meter, h, t, i)?;
                if new {
                    if label.event == TICK {
                        tick_reached.insert(j);
                    }
                } else if label.event != TICK && tick_reached.contains(&j) {
                    if terminated.contains(&j) {
                        return Ok(Flow::Break(Found::Via(i, label, j)));
                    }
                    other_entry.entry(j).or_insert((i, label));
                }
            }
            Ok(Flow::Continue)
        },
    )?;
    Ok(found.map(|f| match f {
        Found::State(i) => state_path(lts, &visited, i),
        Found::Via(src, label, target) => {
            let mut path = state_path(lts, &visited, src);
            path.steps.push((label, lts.decode(visited.row(target))));
            path
        }
    }))
}
