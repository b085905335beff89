//! Which semantics an assertion is checked in (robotool-facts RT-8), and
//! what differs in RoboChart's untimed one (RT-9, RT-10 without `tock`).

use super::*;
use crate::algo::find_divergence;
use crate::untimed::untime;

/// Whether the assertion means something in the untimed semantics: `Ok`
/// for properties of RoboChart elements and refinements between them, in a
/// RoboChart assertion file (.assertions); the reason otherwise (RoboSim and `simulation … of …` elements are timed
/// only, as RoboTool generates no untimed script for them; schedulability
/// is about cycles; timelock freedom about time passing).
pub(super) fn has_untimed_reading(cx: &Cx<'_>) -> Result<(), String> {
    let a = cx.a;
    if cx.file.kind(cx.db) == robosim_hir::FileKind::SimAssertions {
        // RoboTool's RoboSim generator writes a timed script only (the
        // reference's `csp-gen/sim/` has no untimed library).
        return Err("the assertions of a RoboSim assertion file (.rsa) are checked in the timed semantics only".into());
    }
    match &a.kind {
        AssertionKind::DeadlockFree
        | AssertionKind::DivergenceFree
        | AssertionKind::Deterministic
        | AssertionKind::Terminates => designs(cx, &[&a.subject]),
        AssertionKind::Reachable { machine, .. } => designs(cx, &[machine]),
        AssertionKind::Refines { other, model, .. } | AssertionKind::Equals { other, model, .. } => {
            if *model == SemanticModelName::TickTock {
                return Err("the tick-tock model is about `tock`, which the untimed semantics does not have".into());
            }
            designs(cx, &[&a.subject, other])
        }
        AssertionKind::Schedulable => {
            Err("schedulability is a property of cycles: it is checked in the timed semantics only".into())
        }
        AssertionKind::TimelockFree => Err(
            "timelock freedom is about time passing: the untimed semantics has no `tock`, so it is checked timed only"
                .into(),
        ),
        other => Err(format!("`{}` assertions are checked in the timed semantics only", other.label())),
    }
}

/// For a check in the untimed semantics, why it cannot be made (the
/// kinds every semantics answers alike pass through).
pub(super) fn check_untimed_reading(cx: &Cx<'_>) -> Result<(), String> {
    match (&cx.semantics, &cx.a.kind) {
        (Semantics::Timed, _) => Ok(()),
        (_, AssertionKind::ClockInitialised { .. } | AssertionKind::Probabilistic { .. }) => Ok(()),
        _ => has_untimed_reading(cx),
    }
}

/// Whether each of `paths` is a RoboChart element (not RoboSim, not a
/// simulation of one): those have an untimed semantics.
fn designs(cx: &Cx<'_>, paths: &[&[String]]) -> Result<(), String> {
    for path in paths {
        let name = path.join("::");
        // RT-7, RT-8: a `csp` block of this file is in RoboTool's untimed
        // script too, unless it is a `timed csp` block.
        if crate::csp::is_block(cx, path) {
            if path.last().and_then(|n| cx.read.csp_block(n)).is_some_and(|b| b.timed) {
                return Err(format!(
                    "`{name}` is a `timed csp` block: it exists only in RoboTool's timed script (RT-8), so it is \
                     checked in the timed semantics only"
                ));
            }
            continue;
        }
        match cx.target(path)? {
            Target::Design { .. } => {}
            Target::Simulation { .. } | Target::SimOperation { .. } => {
                return Err(format!(
                    "`{name}` is a RoboSim element: RoboSim has only a timed semantics (RoboTool generates no \
                     untimed script for it)"
                ))
            }
            Target::Constrained { .. } => {
                return Err(format!(
                    "`{name}` is a simulation of a RoboChart element, which runs in cycles: it is checked in the \
                     timed semantics only"
                ))
            }
        }
    }
    Ok(())
}

impl Cx<'_> {
    /// `design` in the semantics checked: as compiled (timed), or with its
    /// time constructs read as RoboTool's untimed semantics reads them.
    pub(crate) fn in_semantics(&self, design: Design) -> Result<Design, String> {
        match self.semantics {
            Semantics::Timed => Ok(design),
            Semantics::Untimed => untime(&design).map_err(|u| {
                let u = Unsupported { message: u.message, location: u.location };
                format!("in the untimed semantics: {}", unsupported_reason(self.db, self.ws, &u))
            }),
        }
    }

    /// A RoboChart element's LTS in the semantics checked.
    pub(super) fn plain<'a>(&self, lts: DesignLts<'a>) -> DesignLts<'a> {
        match self.semantics {
            Semantics::Timed => lts,
            Semantics::Untimed => lts.without_time(),
        }
    }
}

/// `deadlock-free` in the untimed semantics: FDR's `:[deadlock free]` in
/// the failures-divergences model (RT-9), so no reachable state where
/// nothing can happen (termination aside) and no divergence either (a
/// divergent process may refuse everything).
pub(super) fn deadlock_free(
    lts: &Side<'_>,
    name: &str,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) -> Result<Outcome, crate::budget::Stop> {
    let (r, stats) = find_deadlock(lts, &opts.budget, progress);
    report.stats = stats;
    match r {
        DeadlockResult::Deadlock(path) => {
            return Ok((
                false,
                Some(("deadlock", path, "nothing can happen here, and it has not terminated".into())),
                format!("{name} can deadlock"),
            ))
        }
        DeadlockResult::Inconclusive(stop) => return Err(stop),
        DeadlockResult::Free => {}
    }
    let (r, stats) = find_divergence(lts, &opts.budget, progress);
    report.stats.states = report.stats.states.max(stats.states);
    report.stats.transitions = report.stats.transitions.max(stats.transitions);
    report.stats.seconds += stats.seconds;
    match r {
        DivergenceResult::Free => Ok((true, None, format!("{name} never deadlocks and never diverges"))),
        DivergenceResult::Divergent { path, .. } => Ok((
            false,
            Some((
                "divergence",
                path,
                "from here it can compute forever, and in the failures-divergences model a divergent process \
                 may refuse everything"
                    .into(),
            )),
            format!("{name} can diverge, so it is not deadlock-free in the failures-divergences model"),
        )),
        DivergenceResult::Inconclusive(stop) => Err(stop),
    }
}

/// `terminates` in the untimed semantics is decided only for processes
/// that cannot diverge: RT-10 reads it as "✓ is reachable and the process
/// deadlocks only after ✓", and whether a divergence counts against it (as
/// it would in the older generators' failures-divergences encoding) is
/// not established.
pub(super) fn terminates_without_divergence(lts: &Side<'_>, name: &str, opts: &Options) -> Result<(), String> {
    match find_divergence(lts, &opts.budget, None).0 {
        DivergenceResult::Free => Ok(()),
        DivergenceResult::Divergent { .. } => Err(format!(
            "{name} can diverge: whether RoboTool's untimed encoding of termination counts a divergence \
             against it is not established, so it is not decided"
        )),
        DivergenceResult::Inconclusive(stop) => Err(stop.reason(&opts.budget)),
    }
}
