//! No atomicity after time passes, and the threads of a machine as
//! RoboTool composes them (../shared/spec/robotool-facts.md RT-16, RT-17,
//! RT-18): each test is a small model whose verdict depends on an
//! interleaving the engine once hid, with the counterexample RoboTool's
//! semantics allows.

use robosim_engine::verify::Verdict;

mod support;
use support::machines::{expect, run};

/// RT-18: a composite state's during action `wait(1); x = x + 1` and a
/// substate's `wait(1)` end at the same `tock`. What each does next is a
/// hidden step of its own, so the substate's guard `[x == 0]` may be
/// evaluated before the write: the final state is reachable, and there the
/// machine can only let time pass (a timed deadlock). Running the threads
/// to their next stop inside the `tock` step hid both.
#[test]
fn a_guard_races_a_write_after_time_passes() {
    let machines = "
        stm R { uses I var x : nat initial i
          state C { during wait(1); x = x + 1
            initial j state A { } state B { entry wait(1) } final F
            transition a { from j to A } transition b { from A to B }
            transition c { from B to F condition x == 0 } transition d { from B to A condition x > 0 action o } }
          transition t { from i to C } }";
    let reports = run(
        machines,
        "assertion A : R::F is reachable in R
         assertion B : R is deadlock-free
         assertion C : R is deterministic",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, "reachability: tock"),
            ("B", Verdict::Fail, "timed deadlock: tock"),
            // After the tock the machine may or may not output `o` (F, or
            // back to A with x = 1): not deterministic.
            ("C", Verdict::Fail, "nondeterminism: tock"),
        ],
    );
}

/// RT-18 between machines of a controller: two machines' waits end at the
/// same `tock`; then one writes the controller's variable `x` and the
/// other evaluates a guard on it. The guard may see the old value, so `o`
/// is possible; the engine once ran the first machine's write inside the
/// `tock` step.
#[test]
fn a_guard_races_another_machines_write_after_time_passes() {
    let machines = "
        interface V { var x : nat }
        stm P { uses I requires V initial i state S { entry wait(1); x = 1 } transition t { from i to S } }
        stm Q { uses I requires V initial i state S { entry wait(1) } state T { entry o }
          transition t { from i to S } transition u { from S to T condition x == 0 } }
        controller Ctl { uses I provides V sref p = P sref q = Q connection q on o to Ctl on o }";
    let reports = run(machines, "assertion A : Ctl::q::T is reachable in Ctl");
    expect(&reports, &[("A", Verdict::Pass, "reachability: tock")]);
}

/// RT-17: a composite state's during action starts only after its initial
/// substate has finished its own entry action, not right after the
/// composite's entry: `o` follows `f`, and a junction on the way to the
/// initial substate never sees the during action's write.
#[test]
fn a_composite_during_action_starts_after_the_initial_substates_entry() {
    let machines = "
        stm D { uses I initial i
          state C { during o initial j state A { entry f } transition a { from j to A } }
          transition t { from i to C } }
        stm DS { uses I initial i state S { entry f; o } transition t { from i to S } }
        stm J { uses I var x : nat initial i
          state C { during x = 1 initial j junction k state A { } state B { }
            transition a { from j to k } transition b { from k to A condition x == 0 }
            transition c { from k to B condition x == 1 } }
          transition t { from i to C } }";
    let reports = run(
        machines,
        "assertion A : D refines DS
         assertion B : DS refines D
         assertion C : J::B is reachable in J
         assertion E : J::A is reachable in J",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, ""),
            ("B", Verdict::Pass, ""),
            ("C", Verdict::Fail, ""),
            ("E", Verdict::Pass, "reachability: "),
        ],
    );
}

/// RT-17: the during action runs once per entry of its composite state:
/// the substates' own transitions do not restart it (F, which needs two
/// runs, is not reachable by `e`s), and leaving and re-entering the
/// composite state does (`f`).
#[test]
fn a_composite_during_action_runs_once_per_entry() {
    let machines = "
        stm Once { uses I var x : nat initial i
          state C { during x = x + 1 initial j state A { } state B { } final F
            transition a { from j to A } transition b { from A to B trigger e } transition c { from B to A trigger e }
            transition d { from A to F condition x > 1 } }
          transition t { from i to C } }
        stm Again { uses I var x : nat initial i
          state C { during x = x + 1 initial j state A { } state B { } final F
            transition a { from j to A } transition b { from A to B trigger e } transition c { from B to A trigger e }
            transition d { from A to F condition x > 1 } }
          transition t { from i to C } transition z { from C to C trigger f } }";
    let reports = run(
        machines,
        "assertion A : Once::F is reachable in Once
         assertion B : Again::F is reachable in Again",
    );
    expect(&reports, &[("A", Verdict::Fail, ""), ("B", Verdict::Pass, "reachability: f.in")]);
}

/// RT-16: a variable the controller provides lives in the controller's
/// memory and each machine reads its own copy; a write reaches the other
/// machines' copies in hidden steps of their own. Q can therefore take
/// `o` while its copy of `x` is still 0, although P wrote 1 before sending
/// `o`; and once forwarded, Q sees 1.
#[test]
fn other_machines_see_a_shared_write_after_it_is_forwarded() {
    let machines = "
        interface V { var x : nat }
        stm P { uses I requires V initial i state S { entry x = 1; o } transition t { from i to S } }
        stm Q { uses I requires V initial i state S { } state Old { } state New { }
          transition t { from i to S }
          transition a { from S to Old trigger o condition x == 0 } transition b { from S to New trigger o condition x == 1 } }
        controller Ctl { uses I provides V sref p = P sref q = Q connection p on o to q on o }";
    let reports = run(
        machines,
        "assertion A : Ctl::q::Old is reachable in Ctl
         assertion B : Ctl::q::New is reachable in Ctl",
    );
    expect(
        &reports,
        &[("A", Verdict::Pass, "reachability: (Ctl.p.o)"), ("B", Verdict::Pass, "reachability: (Ctl.p.o)")],
    );
}
