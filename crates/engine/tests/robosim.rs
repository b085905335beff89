//! The RoboSim semantics one construct at a time (Rules 1–13, RoboTool 3
//! profile): a tiny module per case, its timed deadlock freedom, timelock
//! freedom and divergence freedom, with the states explored.

use robosim_engine::verify::{verify_workspace, Options, Verdict};

/// A module around one RoboSim machine `M` with inputs `i`, `v : nat` and
/// output operations `op()`, `op2(x : nat)`.
fn module(machine: &str) -> String {
    format!(
        "interface I {{ event i event v : nat op() op2(x : nat) }}
         stm M {{ cycleDef cycle == 1 input context {{ uses I }} output context {{ requires I }} {machine} }}
         controller C {{ cycleDef cycle == 1 uses I requires I sref m = M
           connection C on i to m on i connection C on v to m on v }}
         module Mod {{ cycleDef cycle == 1 robotic platform P {{ uses I provides I }} cref c = C
           connection P on i to c on i connection P on v to c on v }}"
    )
}

/// (verdict, states) of `deadlock-free`, `timelock-free`, `divergence-free`.
fn properties(machine: &str) -> Vec<(Verdict, u64)> {
    let rsa =
        "assertion A : Mod is deadlock-free\nassertion B : Mod is timelock-free\nassertion C : Mod is divergence-free";
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        [("m.rst".to_string(), module(machine)), ("a.rsa".to_string(), rsa.to_string())],
        robosim_hir::RuleSet::Paper,
    );
    verify_workspace(&db, ws, &Options::default(), None).into_iter().map(|r| (r.verdict, r.stats.states)).collect()
}

use Verdict::{Fail, Pass};

/// The three verdicts of a case, with the states each check explored.
/// Timelock freedom fails at the initial state in every case: the cycle
/// starts with register reads, which are urgent and which the environment
/// may refuse (robotool-facts RT-10, RT-20).
type Expected = [(Verdict, u64); 3];

const CASES: &[(&str, &str, Expected)] = &[
    (
        "an exec self-loop: reads every cycle, nothing else",
        "initial i0 state S { } transition t { from i0 to S } transition u { from S to S exec }",
        [(Pass, 55), (Fail, 1), (Pass, 55)],
    ),
    (
        "one write per cycle",
        "initial i0 state S { entry $op() } transition t { from i0 to S } transition u { from S to S exec }",
        [(Pass, 71), (Fail, 1), (Pass, 71)],
    ),
    (
        "a register written twice in a cycle: the cycle cannot end",
        "initial i0 state S { entry $op(); $op() } transition t { from i0 to S } transition u { from S to S exec }",
        [(Pass, 23), (Fail, 1), (Pass, 23)],
    ),
    (
        // A divergence is also a timed deadlock in RoboTool's reading (the
        // hidden tocks and the loop together diverge).
        "a loop without exec diverges",
        "initial i0 state S { } transition t { from i0 to S } transition u { from S to S }",
        [(Fail, 23), (Fail, 1), (Fail, 15)],
    ),
    (
        "exec as a statement splits an action over cycles",
        "initial i0 state S { entry $op(); exec; $op(); exec; $op2(1) } transition t { from i0 to S }
         transition u { from S to S exec }",
        [(Pass, 231), (Fail, 1), (Pass, 231)],
    ),
    (
        "an input read with its value drives an output",
        "var x : nat initial i0 state S { } transition t { from i0 to S }
         transition u { from S to S exec condition $v?x action $op2(x) }
         transition w { from S to S exec condition not $v }",
        [(Pass, 255), (Fail, 1), (Pass, 255)],
    ),
    (
        // `$v?x` binds on a transition out of a junction too: x leaves 2,
        // and the loop without exec (a divergence) becomes reachable.
        "an input read with its value from a junction",
        "var x : nat = 2 initial i0 junction J state S { } state T { } transition t { from i0 to S }
         transition u { from S to J exec } transition a { from J to T condition $v?x }
         transition b { from J to S condition else } transition c { from T to T condition x != 2 }
         transition d { from T to S exec condition x == 2 }",
        [(Fail, 89), (Fail, 1), (Fail, 55)],
    ),
    (
        "a junction with no enabled way out is stuck",
        "initial i0 junction J state S { } transition t { from i0 to J } transition a { from J to S condition $i }
         transition u { from S to S exec }",
        [(Pass, 59), (Fail, 1), (Pass, 59)],
    ),
    (
        "termination ends the module",
        "initial i0 final F transition t { from i0 to F action $op() }",
        [(Pass, 39), (Fail, 1), (Pass, 39)],
    ),
    (
        // The 3 of the conditions widens no number type (RT-5: RoboTool's
        // RoboSim lists hold no condition), so the inputs read range over
        // `core_nat = {0..2}` (215 states, not the 268 of `{0..3}`).
        "clocks advance by the period: a decision every third cycle",
        "clock C initial i0 state S { } transition t { from i0 to S action #C }
         transition u { from S to S exec condition since(C) >= 3 action #C; $op() }
         transition w { from S to S exec condition since(C) < 3 }",
        [(Pass, 215), (Fail, 1), (Pass, 215)],
    ),
];

#[test]
fn constructs() {
    let mut failures = Vec::new();
    for (name, machine, expected) in CASES {
        let got = properties(machine);
        println!("{name}: {got:?}");
        let ok = got.len() == 3 && got.iter().zip(expected).all(|(g, e)| g == e);
        if !ok {
            failures.push(format!("{name}: expected {expected:?}, got {got:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
