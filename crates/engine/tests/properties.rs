//! Properties of one element: a RoboChart design on its own (the paper's
//! Figure 1) and RoboSim modules — deadlock, timelock and divergence
//! freedom, determinism, reachability of a state.

use robosim_engine::verify::{trace_text, Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

fn example(name: &str) -> String {
    std::fs::read_to_string(format!("{}/../../examples/paper/{name}", env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("examples/paper/{name}: {e}"))
}

fn run(files: &[(&str, String)]) -> Vec<Report> {
    verify_texts(files.iter().map(|(p, t)| (p.to_string(), t.clone())), &Options::default())
}

/// Each report's name, verdict and counterexample kind.
fn verdicts(reports: &[Report]) -> Vec<(&str, Verdict, Option<&str>)> {
    reports.iter().map(|r| (r.name.as_str(), r.verdict, r.counterexample.as_ref().map(|c| c.kind))).collect()
}

/// examples/paper/design.assertions: the assertions RoboTool users write
/// about Figure 1 (clock initialisation is not checked natively yet).
#[test]
fn the_running_examples_design() {
    let reports = run(&[("design.rct", example("design.rct")), ("design.assertions", example("design.assertions"))]);
    let got: Vec<(String, Verdict)> = reports.iter().map(|r| (r.name.clone(), r.verdict)).collect();
    let expected = [
        ("D1", Verdict::Pass),
        ("D2", Verdict::Pass),
        ("D3", Verdict::Pass),
        ("D4", Verdict::Pass),
        ("D5", Verdict::Pass),
        ("D6", Verdict::Unsupported),
    ];
    assert_eq!(got, expected.map(|(n, v)| (n.to_string(), v)).to_vec(), "{reports:#?}");
    // D4 (`is not deterministic`) passes with a witness: after the stop
    // the design may or may not let time pass (wait([0, 1]) is internal).
    let d4 = &reports[3];
    let c = d4.counterexample.as_ref().expect("a witness");
    assert_eq!(c.kind, "nondeterminism");
    assert!(trace_text(&c.steps).contains("stopCall"), "{}", trace_text(&c.steps));
    // D3 (`is not timelock-free`, RT-10): the witness ends where the
    // design must call the platform, which may refuse the call.
    let d3 = &reports[2];
    let c = d3.counterexample.as_ref().expect("a witness");
    assert_eq!(c.kind, "timelock");
    assert_eq!(trace_text(&c.steps), "");
    assert!(c.explanation.iter().any(|e| e.contains("moveCall") && e.contains("RT-10")), "{:?}", c.explanation);
    // D5: the shortest way into Turning.
    let d5 = &reports[4];
    assert_eq!(
        trace_text(&d5.counterexample.as_ref().expect("a witness").steps),
        "moveCall.1.0 tock obstacle.in stopCall"
    );
}

/// One RoboChart machine per property, failing it.
#[test]
fn failing_properties() {
    let rct = "interface I { event e op() }
        stm Stuck { requires I initial i state S { } transition t { from i to S } }
        stm Loop { requires I var n : nat initial i junction J state S { }
          transition t { from i to J } transition a { from J to J action n = 1 } }
        stm Call { requires I initial i state S { entry op(); op() } transition t { from i to S } }
        stm Late { uses I initial i state S { entry (wait(2) <{1}) } transition t { from i to S } }
        stm Choice { uses I initial i state S { } state T { }
          transition t { from i to S } transition a { from S to T trigger e } transition b { from S to S trigger e } }";
    let asserts = "assertion A : Stuck is deadlock-free
        assertion B : Loop is divergence-free
        assertion C : Choice is deterministic
        assertion D : Stuck::S is reachable in Stuck
        assertion E : Call is timelock-free
        assertion F : Late is timelock-free";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    let got = verdicts(&reports);
    assert_eq!(
        got,
        vec![
            ("A", Verdict::Fail, Some("timed deadlock")),
            ("B", Verdict::Fail, Some("divergence")),
            ("C", Verdict::Fail, Some("nondeterminism")),
            ("D", Verdict::Pass, Some("reachability")),
            // RT-10: the platform may refuse the urgent call `op()`.
            ("E", Verdict::Fail, Some("timelock")),
            ("F", Verdict::Fail, Some("timelock")),
        ],
        "{reports:#?}"
    );
    // Why time cannot pass at the timelock.
    assert_eq!(
        reports[5].counterexample.as_ref().unwrap().explanation[1..],
        ["Late: the deadline of a statement `<{…}` has run out".to_string()]
    );
}

/// Refinement between two RoboChart machines, their events matched by
/// name: `X refines Y` is `Y ⊑ X` in the failures-divergences model.
#[test]
fn refinement_between_designs() {
    let rct = "interface I { event e event o }
        stm Spec { uses I initial i state S { } transition t { from i to S }
          transition a { from S to S trigger e action o } }
        stm Same { uses I initial i state A { } transition t { from i to A }
          transition a { from A to A trigger e action o } }
        stm Eager { uses I initial i state S { } transition t { from i to S }
          transition a { from S to S trigger e action o } transition b { from S to S action o } }
        stm Lazy { uses I initial i state S { } transition t { from i to S } }";
    let asserts = "assertion A : Same refines Spec
        assertion B : Eager refines Spec
        assertion C : Lazy refines Spec in the traces model
        assertion D : Lazy refines Spec";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    let got = verdicts(&reports);
    assert_eq!(
        got,
        vec![
            ("A", Verdict::Pass, None),
            // Eager may go for `o` without `e`, refusing `e` meanwhile.
            ("B", Verdict::Fail, Some("refusal")),
            // Lazy does less: a traces refinement, not a failures one.
            ("C", Verdict::Pass, None),
            ("D", Verdict::Fail, Some("refusal")),
        ],
        "{reports:#?}"
    );
}

/// The tick-tock model (semantics.md §7.5): a choice made once and for all
/// (`Once`) against the same choice made again whenever a time unit has
/// passed (`Again`). FD cannot tell them apart; tick-tock sees that once
/// `Once` has refused `b` and let time pass, it can no longer do `b`.
#[test]
fn tick_tock_refinement_of_designs() {
    let rct = "interface I { event a event b }
        stm Once { uses I initial i junction j state A { } state B { } final F
          transition t0 { from i to j } transition ta { from j to A } transition tb { from j to B }
          transition ea { from A to F trigger a } transition eb { from B to F trigger b } }
        stm Again { uses I clock C initial i junction j state A { } state B { } final F
          transition t0 { from i to j } transition ta { from j to A #C } transition tb { from j to B #C }
          transition ra { from A to j condition since(C) >= 1 } transition rb { from B to j condition since(C) >= 1 }
          transition ea { from A to F trigger a } transition eb { from B to F trigger b } }";
    let asserts = "assertion FD1 : Once refines Again in the failures divergences model
        assertion FD2 : Again refines Once in the failures divergences model
        assertion TT1 : Once refines Again in the tick-tock model
        assertion TT2 : Again does not refine Once in the tick-tock model
        assertion TT3 : Once equals Once in the tick-tock model";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    let got = verdicts(&reports);
    assert_eq!(
        got,
        vec![
            ("FD1", Verdict::Pass, None),
            ("FD2", Verdict::Pass, None),
            ("TT1", Verdict::Pass, None),
            ("TT2", Verdict::Pass, Some("refusal")),
            ("TT3", Verdict::Pass, None),
        ],
        "{reports:#?}"
    );
    // The witness: `Again` lets a time unit pass in A, chooses again, and
    // in B refuses the `a` that `Once` must still offer.
    let c = reports[3].counterexample.as_ref().expect("a witness");
    assert_eq!(trace_text(&c.steps), "tock");
    assert!(c.explanation[0].ends_with("one of {tock, a.in}"), "{:?}", c.explanation);
}

/// A platform operation and an event of the same name: the trigger `stop`
/// is the event, the call `stop()` the operation (their channels differ:
/// `stop.in` and `stopCall`).
#[test]
fn an_event_and_an_operation_of_the_same_name() {
    let rct = "interface Ops { stop() }
        interface Evs { event stop }
        stm S { requires Ops uses Evs initial i state A { } state B { entry stop() }
          transition t0 { from i to A } transition t1 { from A to B trigger stop } }";
    let asserts = "assertion R : S::B is reachable in S";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    assert_eq!(verdicts(&reports), vec![("R", Verdict::Pass, Some("reachability"))], "{reports:#?}");
    assert_eq!(trace_text(&reports[0].counterexample.as_ref().unwrap().steps), "stop.in");
}

/// `terminates` (RT-10): ✓ is reachable, and the process deadlocks only
/// after ✓.
#[test]
fn termination() {
    let rct = "interface I { event e }
        stm Ends { initial i final f transition t { from i to f } }
        stm Waits { initial i state S { } transition t { from i to S } }
        stm Late { initial i state S { entry (wait(2) <{1}) } final f
          transition t { from i to S } transition u { from S to f } }
        stm Maybe { uses I initial i state S { } final f
          transition t { from i to S } transition u { from S to f trigger e } }";
    let asserts = "assertion A : Ends terminates
        assertion B : Waits terminates
        assertion C : Late terminates
        assertion D : Maybe terminates
        assertion E : Waits does not terminate";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    assert_eq!(
        verdicts(&reports),
        vec![
            ("A", Verdict::Pass, Some("termination")),
            // Only time passes: no deadlock, but no ✓ either.
            ("B", Verdict::Fail, None),
            // The deadline cannot be met: nothing can happen before ✓.
            ("C", Verdict::Fail, Some("deadlock")),
            // After e it terminates; meanwhile time passes.
            ("D", Verdict::Pass, Some("termination")),
            ("E", Verdict::Pass, None),
        ],
        "{reports:#?}"
    );
    let d = reports[3].counterexample.as_ref().expect("a witness");
    assert_eq!(trace_text(&d.steps), "e.in ✓");
}
