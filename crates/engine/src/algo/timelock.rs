//! Timelock (robotool-facts.md RT-10): a reachable stable state that
//! refuses `tock`. RoboTool has no generated encoding of `timelock-free`;
//! its authors' expectations are those of the tick-tock model with every
//! event of the element refusable: the environment may refuse any visible
//! event, so a stable state (no τ) where `tock` is not enabled stops time.
//! That covers a state with no transition at all, a state that offers only
//! urgent events (a platform call, a RoboSim register read or write,
//! `endexec`), and termination (the state after ✓ offers nothing, and a
//! state offering only ✓ refuses `tock` too).
//!
//! Unstable states are not checked: τ has priority over `tock`, so time
//! never passes there; a τ cycle without a stable state is a divergence,
//! which [`find_divergence`](super::find_divergence) reports.

use crate::budget::{Budget, Meter, ProgressFn, Stats, Stop};
use crate::lts::{Lts, Rows, TAU, TOCK};

use super::{explore, state_path, visited_from_initial, Flow, Path};

/// The verdict of [`find_timelock`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TimelockResult<S> {
    /// Every reachable stable state lets time pass.
    Free,
    /// The shortest path (in steps, τ included) to a stable state that
    /// refuses `tock`: the first one in breadth-first order.
    Timelock(Path<S>),
    /// The budget ran out first.
    Inconclusive(Stop),
}

/// Searches `lts` for a reachable stable state that refuses `tock`,
/// breadth first.
pub fn find_timelock<L: Lts>(
    lts: &L,
    budget: &Budget,
    progress: Option<ProgressFn>,
) -> (TimelockResult<L::State>, Stats) {
    let mut meter = Meter::new(budget, progress);
    let result = match search(lts, &mut meter) {
        Ok(Some(path)) => TimelockResult::Timelock(path),
        Ok(None) => TimelockResult::Free,
        Err(stop) => TimelockResult::Inconclusive(stop),
    };
    (result, meter.finish())
}

fn search<L: Lts>(lts: &L, meter: &mut Meter<'_>) -> Result<Option<Path<L::State>>, Stop> {
    let mut visited = visited_from_initial(lts, meter)?;
    let found = explore(
        &mut visited,
        meter,
        lts.state_width(),
        |s: &[u8], out: &mut Rows<L::State>| lts.successor_rows(s, out),
        |visited, meter, i, succ| {
            if !succ.iter().any(|(label, _, _)| label.event == TAU || label.event == TOCK) {
                return Ok(Flow::Break(i));
            }
            for (_, t, h) in succ.iter() {
                visited.insert(meter, h, t, i)?;
            }
            Ok(Flow::Continue)
        },
    )?;
    Ok(found.map(|i| state_path(lts, &visited, i)))
}
