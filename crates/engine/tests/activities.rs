//! What a state does alongside its substates and transitions, from the end
//! of its entry action until a transition leaves it (the exporter's
//! `Activity__S`): the deadline timer of transitions with `<{d}`, and the
//! during action of a composite state, which runs in parallel with the
//! substates. Each is checked against an equivalent machine written
//! without it (refinement both ways), and by the exact counterexample of a
//! machine that differs from it.

use robosim_engine::verify::{verify_texts, Options, Verdict};

mod support;
use support::machines::{expect, outcomes, run};

/// A transition deadline `<{d}` on a trigger is the statement deadline on
/// the same communication: it must happen within `d` time units of the
/// end of the source's entry action.
#[test]
fn a_transition_deadline_is_a_deadline_on_its_trigger() {
    let machines = "
        stm D { uses I var x : nat initial i state S { } state T { }
          transition t { from i to S } transition a { from S to T trigger v?x <{2} } }
        stm DS { uses I var x : nat initial i state W { entry (v?x <{2}) } state T { }
          transition t { from i to W } transition a { from W to T } }
        stm DF { uses I var x : nat initial i state S { } state T { }
          transition t { from i to S } transition a { from S to T trigger v?x } }";
    let reports = run(
        machines,
        "assertion A : D refines DS
         assertion B : DS refines D
         assertion C : DF refines D
         assertion E : D refines DF",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, ""),
            ("B", Verdict::Pass, ""),
            // Without the deadline a third time unit may pass.
            ("C", Verdict::Fail, "trace: tock tock tock"),
            // With it, after two the input is all that is left.
            ("E", Verdict::Fail, "refusal: tock tock"),
        ],
    );
}

/// The timer is the state's, not the transition's: re-entering the state
/// restarts it; leaving it stops it before the target's entry action; in a
/// composite state it keeps running while the substates move.
#[test]
fn a_deadline_timer_lives_as_long_as_its_state() {
    let machines = "
        stm R { uses I var x : nat initial i state S { } transition t { from i to S }
          transition a { from S to S trigger v?x <{1} } }
        stm RS { uses I var x : nat initial i state W { entry (v?x <{1}) } transition t { from i to W }
          transition a { from W to W } }
        stm L { uses I initial i state S { } state T { entry wait(3) } state U { }
          transition t { from i to S } transition a { from S to T trigger e <{1} } transition b { from T to U } }
        stm N { uses I initial i
          state C { initial j state A { } state B { } transition x { from j to A } transition y { from A to B trigger f } }
          state T { } transition t { from i to C } transition out { from C to T trigger e <{2} } }
        stm NF { uses I initial i
          state C { initial j state A { } state B { } transition x { from j to A } transition y { from A to B trigger f } }
          state T { } transition t { from i to C } transition out { from C to T trigger e } }";
    let reports = run(
        machines,
        "assertion A : R refines RS
         assertion B : RS refines R
         assertion C : L::U is reachable in L
         assertion D : NF refines N
         assertion E : N::B is reachable in N",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, ""),
            ("B", Verdict::Pass, ""),
            // Three time units in T: the timer of S stopped with e.
            ("C", Verdict::Pass, "reachability: e.in tock tock tock"),
            // f does not restart the timer of C: after two time units, in
            // A or in B, only e is possible.
            ("D", Verdict::Fail, "trace: tock tock tock"),
            ("E", Verdict::Pass, "reachability: f.in"),
        ],
    );
}

/// A deadline on a transition whose guard is false is a timelock (as in
/// the CSP the exporter writes: the timer does not look at the guard).
#[test]
fn a_deadline_on_a_disabled_transition_is_a_timelock() {
    let machines = "
        stm G { uses I var n : nat initial i state S { } state T { }
          transition t { from i to S } transition a { from S to T trigger e <{3} condition n > 0 } }
        stm J { uses I initial i junction K state T { }
          transition t { from i to K } transition a { from K to T trigger e <{1} } }";
    let reports = run(machines, "assertion A : G is timelock-free\nassertion B : J is timelock-free");
    let got = outcomes(&reports);
    assert_eq!(got[0], ("A".into(), Verdict::Fail, "timelock: tock tock tock".into()), "{reports:#?}");
    // The explanation names the transition whose deadline ran out.
    assert_eq!(
        reports[0].counterexample.as_ref().unwrap().explanation,
        vec![
            "nothing can happen here, not even time passing".to_string(),
            "G: the deadline of `a` from S has run out".to_string()
        ]
    );
    assert_eq!(got[1].1, Verdict::Unsupported);
    assert!(got[1].2.starts_with("deadlines on transitions from junctions are not supported"), "{got:?}");
}

/// A composite state's during action runs alongside its substates: its
/// output interleaves with their events, and stays possible after they
/// moved on.
#[test]
fn a_composite_during_action_runs_alongside_the_substates() {
    let machines = "
        stm P { uses I initial i
          state C { during o initial j state A { } state B { }
            transition x { from j to A } transition y { from A to B trigger e } }
          transition t { from i to C } }
        stm PS { uses I var done : boolean = false initial i
          state S { during o; done = true } state T { entry if not done then o end }
          transition t { from i to S } transition b { from S to T trigger e } }
        stm PF { uses I initial i
          state S { during o } state T { }
          transition t { from i to S } transition b { from S to T trigger e } }";
    let reports = run(
        machines,
        "assertion A : P refines PS
         assertion B : PS refines P
         assertion C : P refines PF in the traces model
         assertion D : PF refines P",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, ""),
            ("B", Verdict::Pass, ""),
            // A simple state's during action is interrupted by e; the
            // composite's is not.
            ("C", Verdict::Fail, "trace: e.in o.out"),
            // And after e, the composite's output is still offered.
            ("D", Verdict::Fail, "refusal: e.in"),
        ],
    );
}

/// The during action takes time and is interrupted by the composite
/// state's own transitions, as a simple state's is by its transitions.
#[test]
fn a_composite_during_action_is_interrupted_when_its_state_is_left() {
    let machines = "
        stm Q { uses I initial i
          state C { during o; wait(1); o initial j state A { } transition x { from j to A } }
          state T { } transition t { from i to C } transition z { from C to T trigger f } }
        stm QS { uses I initial i state S { during o; wait(1); o } state T { }
          transition t { from i to S } transition z { from S to T trigger f } }";
    let reports = run(
        machines,
        "assertion A : Q refines QS
         assertion B : QS refines Q
         assertion C : Q is deadlock-free",
    );
    expect(
        &reports,
        &[("A", Verdict::Pass, ""), ("B", Verdict::Pass, ""), ("C", Verdict::Fail, "timed deadlock: f.in")],
    );
}

/// The substates see the during action's writes, and its statement
/// deadlines bound it as they bound the main thread.
#[test]
fn a_composite_during_action_shares_the_machines_variables() {
    let machines = "
        stm W { uses I var n : nat initial i
          state C { during wait(1); n = 1 initial j state A { } state B { }
            transition x { from j to A } transition y { from A to B condition n == 1 } }
          transition t { from i to C } }
        stm K { uses I initial i
          state C { during (wait(2) <{1}) initial j state A { } transition x { from j to A } }
          transition t { from i to C } }";
    let reports = run(
        machines,
        "assertion A : W::B is reachable in W
         assertion B : W is deadlock-free
         assertion C : K is timelock-free",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, "reachability: tock"),
            ("B", Verdict::Fail, "timed deadlock: tock"),
            ("C", Verdict::Fail, "timelock: tock"),
        ],
    );
}

/// What the during action of a composite state may not do natively yet,
/// refused with the reason and place.
#[test]
fn composite_during_actions_that_are_refused() {
    let rct = "interface I { event e op() } interface Ops { turn() }
        stm X { requires I requires Ops initial i
          state C { during turn() initial j state A { } transition x { from j to A } }
          transition t { from i to C } }
        controller Ctl { uses I requires I
          operation turn() { requires I initial i final f transition t { from i to f action op() } }
          sref m = X connection Ctl on e to m on e }";
    let reports = verify_texts(
        [
            ("m.rct".to_string(), rct.to_string()),
            ("a.assertions".to_string(), "assertion A : Ctl is deadlock-free".into()),
        ],
        &Options::default(),
    );
    assert_eq!(reports[0].verdict, Verdict::Unsupported, "{reports:#?}");
    let reason = reports[0].reason.clone().unwrap_or_default();
    assert!(
        reason.starts_with("calls of operations defined in the model from the during action of a composite state"),
        "{reason}"
    );
    // The place is the call in the during action.
    assert!(reason.ends_with("(m.rct:3:28)"), "{reason}");
}

/// RoboSim: how a composite state's during action shares the cycle with
/// its substates (`exec`) is not pinned down, so it is refused.
#[test]
fn composite_during_actions_of_robosim_machines_are_refused() {
    let rst = "interface I { event i op() }
        stm M { cycleDef cycle == 1 input context { uses I } output context { requires I }
          initial i0 state S { during $op() initial j state T { } transition a { from j to T } transition b { from T to T exec } }
          transition t { from i0 to S } }
        controller C { cycleDef cycle == 1 uses I requires I sref m = M connection C on i to m on i }
        module Mod { cycleDef cycle == 1 robotic platform P { uses I provides I } cref c = C connection P on i to c on i }";
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        [("m.rst".to_string(), rst.to_string()), ("a.rsa".to_string(), "assertion A : Mod is deadlock-free".into())],
        robosim_hir::RuleSet::Paper,
    );
    let reports = robosim_engine::verify::verify_workspace(&db, ws, &Options::default(), None);
    assert_eq!(reports[0].verdict, Verdict::Unsupported, "{reports:#?}");
    let reason = reports[0].reason.clone().unwrap_or_default();
    assert!(reason.starts_with("during actions of composite RoboSim states are not supported"), "{reason}");
}
