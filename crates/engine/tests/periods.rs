//! The period a RoboSim element is simulated with is hir's one choice
//! (`robosim_hir::cycle::simulation_period`): the least positive period
//! that the element's `cycleDef` and those of its components admit, not
//! the number written next to `cycle`. Each case compares a module whose
//! cycleDefs are written one way with a reference module that says
//! `cycle == N`: the two are equal exactly when the chosen period is `N`.

use robosim_engine::verify::{verify_workspace, Options, Report, Verdict};

/// A module `name` around a machine that reads `i` and calls `op()` when it
/// is present, with the cycleDefs of the module, the controller and the
/// machine (`None`: `cycle >= 1`, which admits every period). The model is
/// well-formed (`robosim check` reports nothing).
fn module(name: &str, module: Option<&str>, controller: Option<&str>, machine: Option<&str>) -> String {
    let cd = |c: Option<&str>| format!("cycleDef {}", c.unwrap_or("cycle >= 1"));
    format!(
        "stm M{name} {{ {m} input context {{ uses I }} output context {{ requires O }}
           initial i0 state S {{ }} transition t {{ from i0 to S }}
           transition u {{ from S to S exec condition $i action $op() }}
           transition w {{ from S to S exec condition not $i }} }}
         controller C{name} {{ {c} uses I requires O sref m = M{name}
           connection C{name} on i to m on i ( _async ) }}
         module {name} {{ {d} robotic platform P{name} {{ uses I provides O }} cref c = C{name}
           connection P{name} on i to c on i ( _async ) }}\n",
        m = cd(machine),
        c = cd(controller),
        d = cd(module),
    )
}

/// The workspace of one case.
fn workspace(text: String, assertion: &str) -> (robosim_hir::RootDatabase, robosim_hir::Workspace) {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        [("m.rst".to_string(), text), ("a.rsa".to_string(), assertion.to_string())],
        robosim_hir::RuleSet::Paper,
    );
    (db, ws)
}

/// `Mod equals Ref`, where `Ref` has period `reference` at every level.
fn equals(reference: u32, m: Option<&str>, c: Option<&str>, s: Option<&str>) -> Report {
    let eq = format!("cycle == {reference}");
    let text = format!(
        "interface I {{ event i }} interface O {{ op() }}\n{}{}",
        module("Ref", Some(&eq), Some(&eq), Some(&eq)),
        module("Mod", m, c, s)
    );
    let (db, ws) = workspace(text, "assertion A : Mod equals Ref");
    // The model is well-formed: the period comes from feasible cycleDefs.
    let errors: Vec<_> = ws
        .files(&db)
        .iter()
        .flat_map(|f| robosim_hir::file_diagnostics(&db, ws, *f).iter().cloned())
        .filter(|d| d.severity == robosim_hir::Severity::Error)
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    let mut reports = verify_workspace(&db, ws, &Options::default(), None);
    assert_eq!(reports.len(), 1);
    reports.remove(0)
}

#[track_caller]
fn assert_verdict(r: &Report, verdict: Verdict) {
    assert_eq!(r.verdict, verdict, "{:?} {:?} {:?}", r.reason, r.counterexample, r.notes);
}

/// The case: `cycle > 2` at every level is period 3 (it used to be
/// explored with period 2, which the model forbids).
#[test]
fn greater_than_is_the_least_period_above() {
    let gt = Some("cycle > 2");
    assert_verdict(&equals(3, gt, gt, gt), Verdict::Pass);
    assert_verdict(&equals(2, gt, gt, gt), Verdict::Fail);
}

#[test]
fn at_least_includes_the_bound() {
    let ge = Some("cycle >= 2");
    assert_verdict(&equals(2, ge, ge, ge), Verdict::Pass);
    assert_verdict(&equals(3, ge, ge, ge), Verdict::Fail);
}

#[test]
fn less_than_is_the_least_positive_period() {
    let lt = Some("cycle < 5");
    assert_verdict(&equals(1, lt, lt, lt), Verdict::Pass);
    assert_verdict(&equals(4, lt, lt, lt), Verdict::Fail);
}

/// The conjunction of the levels decides: the module says `cycle >= 2`,
/// the controller `cycle < 5`, the machine `cycle % 3 == 0`: period 3.
#[test]
fn the_levels_are_conjoined() {
    let r = equals(3, Some("cycle >= 2"), Some("cycle < 5"), Some("cycle % 3 == 0"));
    assert_verdict(&r, Verdict::Pass);
    let r = equals(3, Some("cycle >= 2 /\\ cycle < 5 /\\ cycle % 3 == 0"), None, None);
    assert_verdict(&r, Verdict::Pass);
    // Only the machine restricts the period: the module takes it.
    assert_verdict(&equals(4, None, None, Some("cycle > 3")), Verdict::Pass);
    assert_verdict(&equals(1, None, None, Some("cycle > 3")), Verdict::Fail);
}

/// No common period: not a verdict, the reason names the rule. (Module and
/// controller agree, and controller and machine agree, so the paper's
/// rules M2 and C2, which look one level down, accept the model; but no
/// period satisfies all three.)
#[test]
fn an_infeasible_conjunction_is_refused_with_its_rule() {
    let text = format!(
        "interface I {{ event i }} interface O {{ op() }}\n{}{}",
        module("Ref", Some("cycle == 1"), Some("cycle == 1"), Some("cycle == 1")),
        module("Mod", Some("cycle >= 3"), None, Some("cycle < 2"))
    );
    let (db, ws) = workspace(text, "assertion A : Mod equals Ref");
    let r = verify_workspace(&db, ws, &Options::default(), None).remove(0);
    assert_verdict(&r, Verdict::Unsupported);
    let reason = r.reason.unwrap_or_default();
    assert!(reason.contains("no positive period satisfies the cycleDef of `Mod`"), "{reason}");
    assert!(reason.contains("RS:M2/RS:C2"), "{reason}");
}

/// A constant in the cycleDef takes the assertion's value, else its
/// initialiser.
#[test]
fn constants_in_cycle_defs() {
    let text = format!(
        "interface I {{ event i }} interface O {{ op() }}\n{}{}",
        module("Ref", Some("cycle == 2"), Some("cycle == 2"), Some("cycle == 2")),
        module("Mod", Some("cycle == K"), None, None).replace("module Mod {", "module Mod { const K : nat = 2")
    );
    for (assertion, verdict) in [
        ("assertion A : Mod equals Ref", Verdict::Pass),
        ("assertion A : Mod equals Ref with constant K of Mod set to 3", Verdict::Fail),
    ] {
        let (db, ws) = workspace(text.clone(), assertion);
        let r = verify_workspace(&db, ws, &Options::default(), None).remove(0);
        assert_verdict(&r, verdict);
    }
}
