//! RoboTool's CSPm library in `csp` blocks (its tock-CSP operators and
//! state helpers, `robosim_hir::csp_defs`, shared with the export), and
//! `csp` blocks in RoboChart's untimed semantics (RT-8, RT-9).

use std::path::Path;
use std::time::Duration;

use robosim_engine::verify::{verify_workspace, Options, Report, Semantics, Verdict};

use robosim_test_support::inputs::model_files;

mod support;
use support::csp::{outcome, MACHINES};

/// Beside the shared machines (`MACHINES`: `M`, `Fast`, `Slow`), `Prompt`
/// answers `go` with `done` one time unit later, and urgently (`<{0}`). An
/// output without a deadline may wait for its receiver, time passing
/// meanwhile.
const PROMPT: &str = "stm Prompt {
  uses I
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B trigger go }
  transition t2 { from B to A action wait(1) ; done <{ 0 } }
}
";

fn run(assertions: &str) -> Vec<Report> {
    support::csp::run(&format!("{MACHINES}{PROMPT}"), assertions)
}

/// The report of `name` in `semantics`.
fn report<'a>(reports: &'a [Report], name: &str, semantics: Semantics) -> &'a Report {
    reports
        .iter()
        .find(|r| r.name == name && r.semantics == semantics)
        .unwrap_or_else(|| panic!("no {semantics:?} report {name}: {reports:#?}"))
}

/// `EDeadline(e, d)` and `StartBy(P, d)` as RoboTool defines them (inside
/// its `Timed(OneStep)` section): `e` within `d` time units. `Slow` lets a
/// unit pass before `done`, so it meets a deadline of 1, not of 0.
#[test]
fn event_deadlines_and_start_by() {
    let reports = run("timed csp Specs csp-begin
Timed(OneStep) {
  E0 = timed_priority(E0_)
  E0_ = p::Slow::go.in -> EDeadline(p::Slow::done.out, 0); E0_
  E1 = timed_priority(E1_)
  E1_ = p::Slow::go.in -> EDeadline(p::Slow::done.out, 1); E1_
  S0 = timed_priority(S0_)
  S0_ = p::Slow::go.in -> StartBy(p::Slow::done.out -> SKIP, 0); S0_
  S1 = timed_priority(S1_)
  S1_ = p::Slow::go.in -> StartBy(p::Slow::done.out -> SKIP, 1); S1_
  F0 = timed_priority(F0_)
  F0_ = p::Fast::go.in -> EDeadline(p::Fast::done.out, 0); F0_
  Loose = p::Slow::go.in -> EDeadline(p::Slow::done.out, 0); Loose
  P0 = timed_priority(P0_)
  P0_ = p::Prompt::go.in -> EDeadline(p::Prompt::done.out, 0); P0_
  P1 = timed_priority(P1_)
  P1_ = p::Prompt::go.in -> EDeadline(p::Prompt::done.out, 1); P1_
  Q1 = timed_priority(Q1_)
  Q1_ = p::Prompt::go.in -> StartBy(p::Prompt::done.out -> SKIP, 1); Q1_
}
csp-end
timed csp E0 csp-begin
csp-end
timed csp E1 csp-begin
csp-end
timed csp S0 csp-begin
csp-end
timed csp S1 csp-begin
csp-end
timed csp F0 csp-begin
csp-end
timed csp Loose csp-begin
csp-end
timed csp P0 csp-begin
csp-end
timed csp P1 csp-begin
csp-end
timed csp Q1 csp-begin
csp-end
timed assertion A1 : Slow refines E0 in the traces model
timed assertion A2 : Slow refines E1 in the traces model
timed assertion A3 : Slow refines S0 in the traces model
timed assertion A4 : Slow refines S1 in the traces model
timed assertion A5 : Fast refines F0 in the traces model
timed assertion A6 : Slow refines S1
timed assertion A7 : Slow refines Loose in the traces model
timed assertion A8 : Prompt refines P0 in the traces model
timed assertion A9 : Prompt refines P1 in the traces model
timed assertion A10 : Prompt refines Q1 in the traces model
");
    let t = Semantics::Timed;
    let fails = |name: &str, trace: &str| {
        assert_eq!(outcome(report(&reports, name, t)), (Verdict::Fail, format!("trace: {trace}")), "{name}");
    };
    // After `go`, a deadline of 0 refuses time; `Slow` waits a unit, and
    // its `done` may wait longer for the environment.
    fails("A1", "p::Slow::go.in tock");
    let c = report(&reports, "A1", t).counterexample.as_ref().unwrap();
    assert_eq!(c.explanation[0], "the model can perform `tock` where the specification cannot");
    fails("A2", "p::Slow::go.in tock tock");
    fails("A3", "p::Slow::go.in tock");
    fails("A4", "p::Slow::go.in tock tock");
    fails("A5", "p::Fast::go.in tock");
    // In the failures model the wait shows too: `done` is refused at once.
    assert_eq!(outcome(report(&reports, "A6", t)), (Verdict::Fail, "refusal: p::Slow::go.in".to_string()));
    // `Prompt` sends `done` one unit after `go`, urgently.
    fails("A8", "p::Prompt::go.in tock");
    assert_eq!(outcome(report(&reports, "A9", t)), (Verdict::Pass, "Prompt refines P1".to_string()));
    assert_eq!(outcome(report(&reports, "A10", t)), (Verdict::Pass, "Prompt refines Q1".to_string()));
    // RoboTool's deadlines are urgent only under `timed_priority`: the
    // `WAIT(0)` of `EDeadline` is `TSKIP`, which may let time pass before
    // it terminates (FDR's traces without priority allow the `tock`).
    assert_eq!(outcome(report(&reports, "A7", t)), (Verdict::Pass, "Slow refines Loose".to_string()));
}

/// `CRUN(A)` in the timed script lets time pass (`RUN(union(A, {tock}))`),
/// and `TCHAOS(A)` is the top of the order over `A`.
#[test]
fn crun_and_tchaos_in_the_timed_script() {
    let reports = run("timed csp C csp-begin
C = CRUN({| p::Fast::go, p::Fast::done |})
T = TCHAOS({| p::Fast::go, p::Fast::done |})
N = CRUN({| p::Fast::go |})
csp-end
timed csp T csp-begin
csp-end
timed csp N csp-begin
csp-end
timed assertion C1 : Fast refines C in the traces model
timed assertion C2 : Fast refines T
timed assertion C3 : Fast refines N in the traces model
");
    let t = Semantics::Timed;
    assert_eq!(outcome(report(&reports, "C1", t)), (Verdict::Pass, "Fast refines C".to_string()));
    assert_eq!(outcome(report(&reports, "C2", t)), (Verdict::Pass, "Fast refines T".to_string()));
    assert_eq!(
        outcome(report(&reports, "C3", t)),
        (Verdict::Fail, "trace: p::Fast::go.in p::Fast::done.out".to_string())
    );
}

/// A plain assertion on a plain `csp` block is checked in both semantics
/// (RT-8): timed, the untimed specification cannot let time pass; untimed
/// (no `tock`, `wait` is `SKIP`: RT-9) the model is read as RoboTool's
/// untimed script has it.
#[test]
fn plain_assertions_on_blocks_run_in_both_semantics() {
    let reports = run("csp Cycle csp-begin
Cycle = p::Slow::go.in -> p::Slow::done.out -> Cycle
NoDone = p::Slow::go.in -> NoDone
Start = p::Slow::go.in -> SKIP
csp-end
csp NoDone csp-begin
csp-end
csp Start csp-begin
csp-end
assertion P1 : Slow refines Cycle in the failures model
assertion P2 : Slow refines NoDone in the traces model
untimed assertion P3 : Slow refines Cycle
assertion P4 : Slow refines Start in the failures model
");
    let (t, u) = (Semantics::Timed, Semantics::Untimed);
    let p1 = report(&reports, "P1", t);
    assert_eq!(outcome(p1), (Verdict::Fail, "trace: tock".to_string()));
    assert_eq!(outcome(report(&reports, "P1", u)), (Verdict::Pass, "Slow refines Cycle".to_string()), "{reports:#?}");
    assert_eq!(
        outcome(report(&reports, "P2", u)),
        (Verdict::Fail, "trace: p::Slow::go.in p::Slow::done.out".to_string())
    );
    // `untimed` only: one report.
    assert!(reports.iter().filter(|r| r.name == "P3").all(|r| r.semantics == u));
    assert_eq!(report(&reports, "P3", u).verdict, Verdict::Pass);
    // Untimed, after `go` the spec terminates where the model offers
    // `done` and refuses termination.
    assert_eq!(outcome(report(&reports, "P4", u)), (Verdict::Fail, "refusal: p::Slow::go.in".to_string()));
}

/// RoboTool's untimed script has neither the `timed csp` blocks nor `tock`
/// nor the tock-CSP library: FDR cannot load it, so no untimed verdict.
#[test]
fn the_untimed_script_has_no_time() {
    let (t, u) = (Semantics::Timed, Semantics::Untimed);
    let reports = run("timed csp TB csp-begin
TB = p::Fast::go.in -> TB
csp-end
untimed assertion U1 : Fast refines TB in the traces model
assertion U2 : Fast refines TB in the traces model
");
    let u1 = report(&reports, "U1", u);
    assert_eq!(u1.verdict, Verdict::Unsupported);
    assert!(u1.reason.as_deref().unwrap().contains("`TB` is a `timed csp` block"), "{u1:#?}");
    // A plain assertion on a `timed csp` block: timed only.
    assert!(reports.iter().filter(|r| r.name == "U2").all(|r| r.semantics == t));
    assert_eq!(outcome(report(&reports, "U2", t)), (Verdict::Fail, "trace: tock".to_string()));

    // One block that needs time makes the whole untimed script invalid.
    let cases = [
        ("Deadline0 = p::Fast::go.in -> EDeadline(p::Fast::done.out, 0); Deadline0", "Deadline0", "EDeadline"),
        ("Deadline0 = tock -> Deadline0 [] p::Fast::go.in -> Deadline0", "Deadline0", "tock"),
        (
            "et(_) = 0\nTimed(et) {\nDeadline0 = p::Fast::go.in -> p::Fast::done.out -> Deadline0\n}",
            "Deadline0",
            "tock",
        ),
    ];
    for (block, name, missing) in cases {
        let reports = run(&format!(
            "csp {name} csp-begin\n{block}\ncsp-end\nassertion U3 : Fast refines {name} in the traces model\n"
        ));
        let r = report(&reports, "U3", u);
        assert_eq!(r.verdict, Verdict::Unsupported, "{block}");
        let why = r.reason.as_deref().unwrap();
        assert!(
            why.starts_with(&format!("in the untimed semantics: `{missing}` (`csp` block `{name}` at line"))
                && why.contains("is defined only in RoboTool's timed script"),
            "{block}: {why}"
        );
        // The timed reading of the same block is decided.
        assert!(matches!(report(&reports, "U3", t).verdict, Verdict::Pass | Verdict::Fail), "{block}");
    }
}

/// The corpus's SLEEC conformance checks (RoboTool's library: `StartBy`,
/// `CRUN`, `timed_priority`, `WAIT`; the block's `core_real` as
/// `union({-2..2}, TemperatureRange)`), with the verdicts FDR gives: the
/// machine reads `batteryCharged`, which the SLEEC rules' alphabet (and so
/// the specification) lacks; rule 3's check is vacuous (no measure: the
/// empty replicated parallel is `SKIP`, which refuses every capability).
#[test]
fn sleec_manual_conformance() {
    let project = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/corpus/UoY-RoboStar__SLEEC-TK/sleec-core/Examples/FireFighter/robochart");
    let mut paths = Vec::new();
    model_files(&project, &mut paths);
    let files: Vec<(String, String)> = paths
        .iter()
        .filter_map(|p| Some((p.display().to_string(), String::from_utf8_lossy(&std::fs::read(p).ok()?).into_owned())))
        .collect();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    let mut opts = Options::default();
    opts.budget.timeout = Some(Duration::from_secs(60));
    let reports: Vec<Report> = verify_workspace(&db, ws, &opts, None)
        .into_iter()
        .filter(|r| r.file.ends_with("jss_running_example-manual-conformance.assertions"))
        .collect();
    let t = Semantics::Timed;
    let trace = "trace: personNearby.false windSpeed.light temperature.36 CameraStart UAV::batteryCharged.in.false";
    for name in ["RCheck1", "RCheck2"] {
        assert_eq!(outcome(report(&reports, name, t)), (Verdict::Fail, trace.to_string()), "{name}");
    }
    // Rule 4 also watches `temperature`, read first from its memory.
    let trace = "trace: temperature.36 personNearby.false windSpeed.light CameraStart UAV::batteryCharged.in.false";
    assert_eq!(outcome(report(&reports, "RCheck4", t)), (Verdict::Fail, trace.to_string()));
    assert_eq!(outcome(report(&reports, "RCheck3", t)), (Verdict::Pass, "RC3 refines RSpec3".to_string()));
}
