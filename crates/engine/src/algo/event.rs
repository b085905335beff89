//! Reachability of an event (robotool-facts RT-10's `terminates` asks
//! whether ✓ is reachable): a breadth-first search for a transition on it,
//! with the shortest path to it.

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Lts, Rows};

use super::{explore, state_path, visited_from_initial, Flow, Path};

/// The verdict of [`find_event`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum EventResult<S> {
    /// No reachable state offers the event.
    Unreachable,
    /// The shortest path to a state offering the event, then the event.
    Reached(Path<S>),
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Searches `lts` breadth first for a reachable transition on `event`
/// (✓ for termination, RT-10's `terminates`).
pub fn find_event<L: Lts>(
    lts: &L,
    event: crate::lts::Event,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (EventResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = (|| {
        let mut visited = visited_from_initial(lts, &mut meter)?;
        let found = explore(
            &mut visited,
            &mut meter,
            lts.state_width(),
            |s: &[u8], out: &mut Rows<L::State>| lts.successor_rows(s, out),
            |visited, meter, i, succ| {
                for (label, t, h) in succ.iter() {
                    if label.event == event {
                        return Ok(Flow::Break((i, label, lts.decode(t))));
                    }
                    visited.insert(meter, h, t, i)?;
                }
                Ok(Flow::Continue)
            },
        )?;
        Ok(found.map(|(i, label, target)| {
            let mut path = state_path(lts, &visited, i);
            path.steps.push((label, target));
            path
        }))
    })();
    let result = match result {
        Ok(Some(path)) => EventResult::Reached(path),
        Ok(None) => EventResult::Unreachable,
        Err(stop) => EventResult::Inconclusive(stop),
    };
    (result, meter.finish())
}
