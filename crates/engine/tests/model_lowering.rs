//! What the engine reads from the hir model that it once missed in the
//! syntax: a communication's guard `e[| g |]` is refused (it was ignored,
//! which explored communications the model forbids), and a parenthesised
//! type is its inner type.

use robosim_engine::verify::Verdict;

mod support;
use support::machines::{expect, run};

#[test]
fn guarded_communications_are_refused() {
    let machines = "
        stm G { uses I var x : nat initial i state S { } state T { }
          transition t { from i to S } transition a { from S to T trigger v[| x > 0 |]?x } }
        stm H { uses I var x : nat initial i state S { entry v[| x > 0 |]?x } transition t { from i to S } }";
    let reports = run(machines, "assertion A : G is deadlock-free\nassertion B : H is deadlock-free");
    expect(
        &reports,
        &[
            ("A", Verdict::Unsupported, "guarded communications `v[| … |]` are not supported yet (m.rct:4:76)"),
            ("B", Verdict::Unsupported, "guarded communications `v[| … |]` are not supported yet (m.rct:5:63)"),
        ],
    );
}

#[test]
fn a_parenthesised_type_is_its_inner_type() {
    let machines = "
        stm P { uses I var x : (nat) = 1 initial i state S { entry v!x } final F
          transition t { from i to S } transition u { from S to F } }
        stm Q { uses I var x : nat = 1 initial i state S { entry v!x } final F
          transition t { from i to S } transition u { from S to F } }";
    let reports = run(machines, "assertion A : P refines Q\nassertion B : Q refines P");
    expect(&reports, &[("A", Verdict::Pass, ""), ("B", Verdict::Pass, "")]);
}
