//! How machines compose in a controller, as RoboTool's generated CSPm
//! composes them (../shared/spec/robotool-facts.md RT-13, RT-14, RT-15, RT-19):
//! events connected to nothing are hidden, one sender and several
//! receivers synchronise all at once, and a machine checked on its own
//! calls its controller's operations as visible, urgent events.

use robosim_engine::verify::Verdict;

mod support;
use support::machines::{expect, run};

/// RT-15: a machine's events connected to nothing are hidden inside the
/// controller, not refused: the input `v?x` happens on its own with any
/// value (an internal choice), and so does the output `e`.
#[test]
fn events_connected_to_nothing_are_hidden() {
    let model = "
        stm M { uses I var x : nat initial i junction J state S { } state A { entry f } state B { entry o }
          transition t { from i to S } transition u { from S to J trigger v?x action e }
          transition a { from J to A condition x == 0 } transition b { from J to B condition x == 2 } }
        controller Ctl { uses I sref m = M connection m on f to Ctl on f connection m on o to Ctl on o }";
    let reports = run(
        model,
        "assertion A : Ctl::m::A is reachable in Ctl
         assertion B : Ctl::m::B is reachable in Ctl
         assertion D : Ctl is deterministic",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, "reachability: (Ctl.m.v.0) (Ctl.m.e)"),
            ("B", Verdict::Pass, "reachability: (Ctl.m.v.2) (Ctl.m.e)"),
            // Which of f and o follows is the machine's own choice: after
            // the hidden steps, f may be refused.
            ("D", Verdict::Fail, "nondeterminism: (Ctl.m.v.2) (Ctl.m.e)"),
        ],
    );
}

/// RT-14: one sender and two receivers synchronise all at once: `o`
/// happens only when both Q (ready after a time unit) and R (ready at
/// once) accept it, so R does not receive before the `tock`.
#[test]
fn a_sender_and_several_receivers_synchronise_at_once() {
    let model = "
        stm P { uses I initial i state S { entry o } transition t { from i to S } }
        stm Q { uses I initial i state W { entry wait(1) } state S { } state T { entry f }
          transition t { from i to W } transition w { from W to S } transition u { from S to T trigger o } }
        stm R { uses I initial i state S { } state T { entry e }
          transition t { from i to S } transition u { from S to T trigger o } }
        controller Ctl { uses I sref p = P sref q = Q sref r = R
          connection p on o to q on o connection p on o to r on o
          connection q on f to Ctl on f connection r on e to Ctl on e }";
    let reports = run(
        model,
        "assertion A : Ctl::r::T is reachable in Ctl
         assertion B : Ctl is deadlock-free",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, "reachability: tock (Ctl.p.o)"),
            // Both outputs, then only time passes.
            ("B", Verdict::Fail, "timed deadlock: tock (Ctl.p.o) f.out e.out"),
        ],
    );
}

/// RT-19: a machine declared in a controller and checked on its own
/// treats the controller's operations as undefined: a call is the
/// visible event `turnCall`, urgent (time cannot pass before it), not the
/// operation's body.
#[test]
fn a_machine_on_its_own_calls_its_controllers_operations_as_events() {
    let model = "
        interface Ops { turn() }
        controller C { uses I requires I
          operation turn() { requires I initial i final f transition t { from i to f action op() } }
          stm M { uses I requires Ops initial i state S { } state T { } transition t { from i to S }
            transition u { from S to T trigger e action turn() } } }
        stm Lazy { uses I requires Ops initial i state S { } state T { } transition t { from i to S }
          transition u { from S to T trigger e action wait(1); turn() } }";
    let reports = run(
        model,
        "assertion A : C::M::T is reachable in C::M
         assertion B : Lazy refines C::M in the traces model",
    );
    expect(
        &reports,
        &[
            ("A", Verdict::Pass, "reachability: e.in turnCall"),
            // Lazy lets a time unit pass before the call; C::M cannot.
            ("B", Verdict::Fail, "trace: e.in tock"),
        ],
    );
}

/// RT-13: `_async` between a machine and its controller's boundary is a
/// plain renaming: no buffer, so the machine's output is the controller's
/// event itself (visible, in order, and the machine waits for it), exactly
/// as with a synchronous connection; and no report mentions a buffer.
#[test]
fn async_to_the_controller_boundary_is_a_renaming() {
    let model = "
        stm M { uses I initial i state S { entry o; f } state T { } transition t { from i to S }
          transition u { from S to T } }
        controller Ctl { uses I sref m = M connection m on o to Ctl on o ( _async ) connection m on f to Ctl on f }
        controller Sync { uses I sref m = M connection m on o to Sync on o connection m on f to Sync on f }";
    let reports = run(
        model,
        "assertion A : Ctl::m::T is reachable in Ctl
         assertion B : Ctl refines Sync
         assertion C : Sync refines Ctl",
    );
    expect(
        &reports,
        &[("A", Verdict::Pass, "reachability: o.out f.out"), ("B", Verdict::Pass, ""), ("C", Verdict::Pass, "")],
    );
    assert!(reports.iter().all(|r| r.notes.iter().all(|n| !n.contains("buffer"))), "{reports:#?}");
}
