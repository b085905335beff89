//! RoboChart's untimed semantics in the export (robotool-facts RT-8, RT-9),
//! as RoboTool's untimed script writes it beside the timed one (the Alpha
//! Algorithm's `csp-gen/` against `csp-gen/timed/`): exact snapshots of
//! the untimed files of small models (`tests/untimed/*.csp`,
//! `UPDATE_EXPECT=1` refreshes them), the assertions each script holds, the
//! refusals (the native checker's, for the same reasons), and the untimed
//! output loaded by our CSPm front end.

use robosim_semantics::{export_workspace, Export, Options, OutFile};

fn export(files: &[(&str, &str)]) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &mut db,
        files.iter().map(|(n, t)| (n.to_string(), t.to_string())),
        robosim_hir::RuleSet::Paper,
    );
    export_workspace(&db, ws, &Options::default())
}

fn file<'a>(files: &'a [OutFile], name: &str) -> &'a OutFile {
    files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}"))
}

/// The CSPm errors of the untimed script loaded from each assertion file.
fn untimed_errors(e: &Export) -> Vec<String> {
    let texts: std::collections::HashMap<String, String> =
        e.untimed.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |n: &str| texts.get(n).cloned();
    let mut errors = Vec::new();
    for (n, t) in &texts {
        if t.contains("\ninclude \"") {
            let m = robosim_cspm::Module::check_with_includes(t, &robosim_cspm::NoNames, &load);
            errors.extend(
                m.diagnostics()
                    .iter()
                    .filter(|d| d.severity == robosim_cspm::Severity::Error)
                    .map(|d| format!("{n}: {d:?}")),
            );
        }
    }
    errors
}

const MODEL: &str = "interface I { event go event v : nat }
interface Ops { move(x : nat) }
stm M {
  uses I requires Ops
  var x : nat
  clock C
  initial i
  state S { entry wait(2); move(1); #C during v!x exit x = 1 }
  state T { }
  final f
  transition t0 { from i to S }
  transition t1 { from S to T trigger go condition since(C) >= 3 }
  transition t2 { from T to f trigger v?x action #C }
}
controller Ctl {
  uses I requires Ops sref m = M
  connection Ctl on go to m on go
  connection m on v to Ctl on v
}
module Mod {
  robotic platform P { uses I provides Ops }
  cref c = Ctl
  connection P on go to c on go ( _async )
  connection c on v to P on v ( _async )
}
";

const ASSERTIONS: &str = "assertion A1 : M is deadlock-free
untimed assertion A2 : Mod is deadlock-free
timed assertion A3 : M is deadlock-free
assertion A4 : M is deterministic
untimed assertion A5 : M is timelock-free
assertion A6 : M is timelock-free
untimed assertion A7 : S is reachable in M
assertion A8 : M refines Ctl in the failures model
untimed assertion A9 : M terminates
";

/// The untimed script of a machine, its controller and module: no `tock`,
/// `TimedPriority`, clocks or clock resets; `wait(2)` is `SKIP`, the
/// clock guard `true`, the call `moveCall.1 -> SKIP`, the output of the
/// during action a plain event; the untimed and plain assertions with
/// RoboTool's untimed encodings (deadlock freedom in the
/// failures-divergences model), the timed ones and those with no untimed
/// reading left to the timed script.
#[test]
fn the_untimed_script_of_a_machine() {
    let e = export(&[("m.rct", MODEL), ("a.assertions", ASSERTIONS)]);
    let names: Vec<&str> = e.untimed.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["robosim_defs.csp", "instantiations.csp", "m.csp", "a_assertions.csp"]);
    expect_test::expect_file!["untimed/m.csp"].assert_eq(&file(&e.untimed, "m.csp").text());
    expect_test::expect_file!["untimed/a_assertions.csp"].assert_eq(&file(&e.untimed, "a_assertions.csp").text());
    for f in &e.untimed {
        // The CSPm, comments aside.
        let t: String = f.text().lines().filter(|l| !l.trim_start().starts_with("--")).collect();
        for timed in ["tock", "TimedPriority", "EDeadline", "Wait(", "TStop", "reset_", "ClockTick"] {
            assert!(!t.contains(timed), "{} has `{timed}`:\n{t}", f.name);
        }
    }
    // A5 alone is refused (an untimed assertion with no untimed reading).
    let warnings: Vec<String> = e.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings,
        ["a.assertions:5:1: assertion A5 is not exported: timelock freedom is about time passing: the untimed \
          semantics has no `tock`, so it is checked timed only"]
    );
    // The timed script keeps the plain and timed assertions.
    let timed = file(&e.files, "a_assertions.csp").text();
    assert!(timed
        .contains("-- untimed assertion A2 : Mod is deadlock-free\n-- an untimed assertion: in the untimed script"));
    assert!(
        timed.contains("-- assertion A1 : M is deadlock-free\nassert (prioritise(\n   M::D__(0) [[ tock <- tock"),
        "{timed}"
    );
    assert!(untimed_errors(&e).is_empty(), "{:#?}", untimed_errors(&e));
}

/// The untimed library: RoboTool's untimed definitions, no time.
#[test]
fn the_untimed_shared_definitions_have_no_time() {
    let e = export(&[("m.rct", MODEL)]);
    let defs = file(&e.untimed, "robosim_defs.csp").text();
    assert!(defs.contains("RoboTool's library (state helpers, core functions), as in its untimed script."), "{defs}");
    assert!(!defs.contains("tock") && !defs.contains("Timed(OneStep)") && !defs.contains("TimedPriority"), "{defs}");
    // No assertion file: the untimed script's main.csp includes the rest.
    let main = file(&e.untimed, "main.csp").text();
    assert!(main.contains("include \"m.csp\""), "{main}");
}

/// What has no established untimed reading is refused in the untimed
/// script with the native checker's reasons (`robosim-engine`'s
/// `untimed.rs`), while the timed script exports it: a deadline, a clock
/// read outside a guard, `sinceEntry`, a clock comparison inside a larger
/// guard, `condition else` beside a clock guard. Each untimed assertion
/// about such a machine warns; the timed export does not.
#[test]
fn constructs_without_an_untimed_reading_are_refused() {
    let cases = [
        ("state S { entry wait(1) <{2} }", "", "has a deadline `<{d}`"),
        ("state S { }", "transition u { from S to S trigger go <{2} }", "has a deadline `<{d}`"),
        ("state S { entry x = since(C) }", "", "uses the clock `C` outside a guard"),
        ("state S { }", "transition u { from S to S trigger go condition sinceEntry(S) > 1 }", "uses `sinceEntry`"),
        (
            "state S { }",
            "transition u { from S to S trigger go condition since(C) > 1 /\\ x > 0 }",
            "combines a comparison of a clock with other conditions",
        ),
        (
            "state S { }",
            "transition u { from S to S condition since(C) > 1 } transition w { from S to S condition else }",
            "is a `condition else` next to the clock guard of `u`",
        ),
    ];
    for (state, trans, why) in cases {
        let model = format!(
            "interface I {{ event go }} stm M {{ uses I var x : nat clock C initial i {state}
               transition t {{ from i to S }} {trans} }}"
        );
        let e = export(&[("m.rct", &model), ("a.assertions", "untimed assertion U : M is deadlock-free")]);
        let untimed = file(&e.untimed, "m.csp").text();
        assert!(untimed.contains("NOT EXPORTED: state machine M") && untimed.contains(why), "{why}:\n{untimed}");
        let timed = file(&e.files, "m.csp").text();
        assert!(!timed.contains("NOT EXPORTED"), "{why}:\n{timed}");
        let warnings: Vec<&str> = e.warnings.iter().map(|w| w.message.as_str()).collect();
        assert_eq!(warnings, ["assertion U is not exported in the untimed semantics: `M` is not exported"], "{why}");
    }
}

/// RoboSim has only a timed semantics, and so do `timed csp` blocks and
/// RoboSim assertion files (RT-8): a plain assertion about them is in the
/// timed script only, without a warning; an `untimed` one is refused with
/// the reason.
#[test]
fn robosim_and_timed_blocks_are_timed_only() {
    let rct = "interface I { event go } stm M { uses I initial i state S { } transition t { from i to S } }";
    let rst = "interface J { event go } stm R { cycleDef cycle == 1 input context { uses J } output context { }
        initial i state S { } transition t { from i to S } transition u { from S to S exec } }";
    let asserts = "timed csp TB csp-begin TB = STOP csp-end
assertion P1 : R is deadlock-free
assertion P2 : TB is deadlock-free
untimed assertion U1 : R is deadlock-free
assertion P3 : M is deadlock-free
";
    let rsa = "untimed assertion U2 : R is deadlock-free";
    // With no RoboChart assertion file, the untimed script's main.csp
    // includes the rest.
    let only_rsa = export(&[("m.rct", rct), ("r.rst", rst), ("s.rsa", rsa)]);
    let names: Vec<&str> = only_rsa.untimed.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["robosim_defs.csp", "instantiations.csp", "m.csp", "main.csp"]);
    let e = export(&[("m.rct", rct), ("r.rst", rst), ("a.assertions", asserts), ("s.rsa", rsa)]);
    let names: Vec<&str> = e.untimed.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["robosim_defs.csp", "instantiations.csp", "m.csp", "a_assertions.csp"]);
    let a = file(&e.untimed, "a_assertions.csp").text();
    assert!(!a.contains("TB = STOP"), "a `timed csp` block in the untimed script:\n{a}");
    for line in [
        "-- checked in the timed semantics only: `R` is a RoboSim element: RoboSim has only a timed semantics",
        "-- checked in the timed semantics only: `TB` is a `timed csp` block",
        "-- NOT EXPORTED: `R` is a RoboSim element",
        "assert M::D__(0) :[deadlock free [FD]]",
    ] {
        assert!(a.contains(line), "no `{line}` in\n{a}");
    }
    let warnings: Vec<String> = e.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings,
        [
            "a.assertions:4:1: assertion U1 is not exported: `R` is a RoboSim element: RoboSim has only a timed \
             semantics (RoboTool generates no untimed script for it)",
            "s.rsa:1:1: assertion U2 is not exported: the assertions of a RoboSim assertion file (.rsa) are checked \
             in the timed semantics only"
        ],
        "{warnings:#?}"
    );
    assert!(untimed_errors(&e).is_empty(), "{:#?}", untimed_errors(&e));
}
