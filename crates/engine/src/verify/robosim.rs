//! RoboSim's visible end of a cycle in comparisons (robotool-facts RT-21).

use super::*;
use crate::ir::Level;

/// The two sides of a refinement, `(implementation, specification)`. A
/// RoboSim machine or controller shows `endexec` and `terminate` on its
/// own (RT-21); the cycle-constrained design it may be compared with has
/// neither, so then the comparison is at a module's alphabet (both
/// hidden), and the report says so. Two RoboSim elements keep their own.
pub(super) fn constrained_alphabet<'a>(
    (imp, imp_d): (Side<'a>, &Design),
    (spec, spec_d): (Side<'a>, &Design),
    report: &mut Report,
) -> (Side<'a>, Side<'a>) {
    let mut note = |level: Level| {
        if level != Level::Module {
            report.notes.push(
                "the RoboSim side's `endexec` and `terminate` are hidden for this comparison with a \
                 cycle-constrained design (as in a module, RT-21)"
                    .into(),
            );
        }
    };
    match (imp, spec) {
        (Side::Sim(s), d @ Side::Design(_)) => {
            note(imp_d.level);
            (Side::Sim(s.hiding_end()), d)
        }
        (d @ Side::Design(_), Side::Sim(s)) => {
            note(spec_d.level);
            (d, Side::Sim(s.hiding_end()))
        }
        pair => pair,
    }
}
