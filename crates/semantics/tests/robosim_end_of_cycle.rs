//! RT-20 and RT-21: what a RoboSim machine, controller and module show of
//! the end of a cycle. RoboTool's `D__` of a machine is
//! `timed_priority(STM \ internal_events)`, its `STM` hiding `startexec`
//! only (the reference's `csp-gen/sim/defs/pkg223_aggregation_sim_Movement.csp`):
//! `endexec` and `terminate` are visible, and after `endexec` a finished
//! machine offers `terminate` and `tock` alike. A controller shows one
//! `endexec` per cycle, after all its machines'; a module hides both.
//! The model is the engine's fixture `robosim_facts_the_end_of_a_cycle`
//! (whose assertions state RoboTool's verdicts): exported, checked with
//! our CSPm front end and run with our evaluator.

use std::path::Path;

use robosim_cspm::{Evaluator, Label, Limits, Lts, NoNames};

mod support;
use robosim_semantics::{export_workspace, lint, Export, Options, Profile};
use support::{after, checked, terminates_after, text};

/// The fixture's model (its assertions left out), exported in `profile`.
fn export(profile: Profile) -> Export {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify/robosim_facts_the_end_of_a_cycle/m.rst");
    let text = std::fs::read_to_string(path).expect("the fixture's model");
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, vec![("m.rst".into(), text)], robosim_hir::RuleSet::Paper);
    let e = export_workspace(&db, ws, &Options { profile });
    // Its controller `C2` is no clash with `robosim_defs.csp`'s
    // `model_shifting` (whose private helper is `C2` too).
    let problems = lint::check(&e.files);
    assert!(problems.is_empty(), "{problems:#?}");
    e
}

/// Whether some state reached by `trace` offers `event`.
fn offers_after(lts: &Lts, trace: &[&str], event: &str) -> bool {
    let Some(e) = lts.event(event) else { return false };
    after(lts, trace).iter().any(|&s| lts.transitions[s as usize].iter().any(|(l, _)| *l == Label::Event(e)))
}

/// Whether the process ever performs `event`.
fn ever(lts: &Lts, event: &str) -> bool {
    let Some(e) = lts.event(event) else { return false };
    lts.transitions.iter().flatten().any(|(l, _)| *l == Label::Event(e))
}

const PROCESSES: &str =
    "M__ = M::D__(0, 1)\nN__ = N::D__(0, 1)\nC__ = C::D__(0, 1)\nC2__ = C2::D__(0, 1)\nMod__ = Mod::D__(0, 1)";

/// A machine on its own: its `P__` hides `startexec` only, renaming the
/// transition-tagged `endexec__` to the visible `endexec`; its `D__`
/// keeps `terminate` visible. M (finished in its first cycle) writes,
/// ends the cycle, then `terminate` and `tock` compete; N (finished in its
/// second) only lets time pass after its first `endexec`.
#[test]
fn a_machine_on_its_own_shows_endexec_and_terminate() {
    let e = export(Profile::RoboTool3);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    let model = text(&e, "m.csp");
    assert!(model.contains("channel endexec__ : TIDS"), "{model}");
    assert!(
        model.contains("endexec__.t__ <- endexec |") && model.contains("\\ {| internal__, startexec |}"),
        "{model}"
    );
    // RoboTool's names are the machine's own (`M::endexec`, `M::registerWrite.M::o_op`).
    assert!(model.contains("  channel terminate, endexec\n  datatype RegisterDataOutput = o_op | o_op2.core_nat\n"));
    let m = checked(&e, "main.csp", PROCESSES);
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let mm = ev.lts("M__").unwrap();
    assert!(!ever(&mm, "M::startexec"));
    let written = ["M::registerWrite.M::o_op", "M::endexec"];
    assert!(terminates_after(&mm, &[&written[..], &["M::terminate"]].concat()), "{:?}", mm.events);
    // RT-20: `terminate` competes with `tock`; a finished machine keeps
    // ending cycles.
    assert!(offers_after(&mm, &written, "M::terminate") && offers_after(&mm, &written, "tock"));
    assert!(terminates_after(&mm, &[&written[..], &["tock", "M::endexec", "M::terminate"]].concat()));
    // `tock` waits for the cycle's end.
    assert!(after(&mm, &["M::registerWrite.M::o_op", "tock"]).is_empty());
    let n = ev.lts("N__").unwrap();
    let written = ["N::registerWrite.N::o_op", "N::endexec"];
    assert!(!offers_after(&n, &written, "N::terminate") && offers_after(&n, &written, "tock"));
    assert!(terminates_after(&n, &[&written[..], &["tock", "N::endexec", "N::terminate"]].concat()));
}

/// A controller shows one `endexec` per cycle, once every machine has
/// ended its own (they synchronise on it), and its `terminate`; a module
/// hides both, so it terminates at once (a hidden step before `tock`).
#[test]
fn a_controller_shows_its_own_endexec_and_a_module_hides_it() {
    let e = export(Profile::RoboTool3);
    let m = checked(&e, "main.csp", PROCESSES);
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let c = ev.lts("C__").unwrap();
    assert!(terminates_after(&c, &["C::registerWrite.C::o_op", "C::endexec", "C::terminate"]), "{:?}", c.events);
    assert!(offers_after(&c, &["C::registerWrite.C::o_op", "C::endexec"], "tock"));
    // M0 finishes in the first cycle, N0 in the second: one `endexec` per
    // cycle, `terminate` only once both have finished.
    let c2 = ev.lts("C2__").unwrap();
    assert!(terminates_after(&c2, &["C2::endexec", "tock", "C2::endexec", "C2::terminate"]), "{:?}", c2.events);
    assert!(
        after(&c2, &["C2::endexec", "C2::endexec"]).is_empty() && !offers_after(&c2, &["C2::endexec"], "C2::terminate")
    );
    let module = ev.lts("Mod__").unwrap();
    assert!(!ever(&module, "Mod::endexec") && !ever(&module, "Mod::terminate"), "{:?}", module.events);
    assert!(terminates_after(&module, &["Mod::registerWrite.Mod::o_op"]));
    assert!(after(&module, &["Mod::registerWrite.Mod::o_op", "tock"]).is_empty());
}

/// The paper's Rule 4 (paper2019 profile) ends the cycle without a
/// visible event: the machine's `endexec` and `terminate` stay hidden.
#[test]
fn the_paper_profile_hides_the_end_of_a_cycle() {
    let e = export(Profile::Paper2019);
    let m = checked(&e, "main.csp", "M0__ = M0::D__(0, 1)\nC2__ = C2::D__(0, 1)");
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    for (p, m) in [("M0__", "M0"), ("C2__", "C2")] {
        let lts = ev.lts(p).unwrap();
        let (end, term) = (format!("{m}::endexec"), format!("{m}::terminate"));
        assert!(!ever(&lts, &end) && !ever(&lts, &term) && lts.event(&term).is_some(), "{p}: {:?}", lts.events);
    }
}
