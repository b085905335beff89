//! What an assertion may name and give (robotool-facts RT-11): instance
//! paths as subjects, enumeration literals as constants' values (`set to
//! IType::L2`).

use robosim_engine::verify::{trace_text, verify_texts, Options, Report, Semantics, Verdict};

const MODEL: &str = "enumeration Mode { Slow Fast }
enumeration Colour { Red }
interface I { event e }
stm M {
  uses I const k : Mode
  initial i state S { } state A { } state B { }
  transition t { from i to S }
  transition a { from S to A condition k == Mode::Slow }
  transition b { from S to B condition k == Mode::Fast }
}";

/// The timed reports on `assertions` about `MODEL`.
fn run(assertions: &str) -> Vec<Report> {
    verify_texts(
        [("m.rct".to_string(), MODEL.to_string()), ("a.assertions".to_string(), assertions.to_string())],
        &Options::default(),
    )
    .into_iter()
    .filter(|r| r.semantics == Semantics::Timed)
    .collect()
}

/// RT-11: `set to Mode::Fast` gives `k` the literal `Fast`, so `B` is
/// reachable and `A` is not; without a value `k` is the first literal,
/// `Slow` (RT-1).
#[test]
fn rt11_enumeration_literals_as_values() {
    let reports = run("assertion F : M::B is reachable in M with constant k of M set to Mode::Fast
        assertion G : M::A is reachable in M with constant k of M set to Mode::Fast
        assertion H : M::A is reachable in M with constant k of M set to Mode::Slow
        assertion D : M::A is reachable in M");
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(got, [("F", Verdict::Pass), ("G", Verdict::Fail), ("H", Verdict::Pass), ("D", Verdict::Pass)]);
    assert_eq!(reports[0].reason.as_deref(), Some("M::B is reachable in M"));
    assert_eq!(reports[1].reason.as_deref(), Some("M::A is not reachable in M"));
}

/// RT-11: a value that is not a literal of the constant's enumeration is
/// refused with the reason, never converted.
#[test]
fn rt11_values_of_another_type_are_refused() {
    let reports = run("assertion A : M is deadlock-free with constant k of M set to Mode::Medium
        assertion B : M is deadlock-free with constant k of M set to Colour::Red
        assertion C : M is deadlock-free with constant k of M set to Size::Big
        assertion D : M is deadlock-free with constant k of M set to 1 + 1");
    let got: Vec<(&str, Verdict, &str)> =
        reports.iter().map(|r| (r.name.as_str(), r.verdict, r.reason.as_deref().unwrap_or(""))).collect();
    assert_eq!(
        got,
        [
            ("A", Verdict::Unsupported, "`Medium` is not a literal of the enumeration `Mode`"),
            (
                "B",
                Verdict::Unsupported,
                "a constant `k` of the workspace is not of the enumeration `Colour`: `Colour::Red` cannot be its value"
            ),
            ("C", Verdict::Unsupported, "`Size` is not an enumeration"),
            ("D", Verdict::Unsupported, "the value of constant `k` is not an integer, boolean or enumeration literal"),
        ]
    );
}

/// RT-11: instance paths. `C::s` (a machine reference of a controller) is
/// the machine it references on its own, `Mod::c` (a controller reference
/// of a module) the controller: the same verdicts and state counts as
/// naming them directly; `D::o` (an operation reference) is the operation
/// on its own. A machine of a controller with operations (RT-19: inlined
/// or visible?) is refused with the reason.
#[test]
fn rt11_instance_paths() {
    let model = "interface I { event e op() }
stm M { uses I initial i state S { } state T { }
  transition t { from i to S } transition u { from S to T trigger e } }
controller C { uses I sref s = M connection C on e to s on e }
operation Op() { initial i final F transition t { from i to F } }
controller D { uses I sref s = M opref o = Op connection D on e to s on e }
module Mod { robotic platform P { uses I } cref c = C connection P on e to c on e }";
    let reports: Vec<Report> = verify_texts(
        [
            ("m.rct".to_string(), model.to_string()),
            (
                "a.assertions".to_string(),
                "timed assertion A : C::s is deadlock-free
                 timed assertion B : M is deadlock-free
                 timed assertion G : Mod::c is deadlock-free
                 timed assertion H : C is deadlock-free
                 timed assertion J : Mod::c::s is deadlock-free
                 timed assertion K : D::s is deadlock-free
                 timed assertion L : D::o is deadlock-free"
                    .to_string(),
            ),
        ],
        &Options::default(),
    );
    let got: Vec<(&str, Verdict, u64)> = reports.iter().map(|r| (r.name.as_str(), r.verdict, r.stats.states)).collect();
    // T is a timed deadlock (only time passes there), reached the same way.
    assert_eq!(
        got[..5],
        [
            ("A", Verdict::Fail, 2),
            ("B", Verdict::Fail, 2),
            ("G", Verdict::Fail, 2),
            ("H", Verdict::Fail, 2),
            ("J", Verdict::Fail, 2)
        ],
        "{reports:#?}"
    );
    let trace = |k: usize| reports[k].counterexample.as_ref().map(|c| trace_text(&c.steps));
    assert_eq!(trace(0), trace(1));
    assert_eq!(trace(2), trace(3));
    assert_eq!(got[5].1, Verdict::Unsupported);
    assert!(reports[5]
        .reason
        .as_deref()
        .unwrap()
        .starts_with("`D::s` is a machine of a controller that defines operations"));
    // `D::o` is the operation `Op` on its own: it terminates, no deadlock.
    assert_eq!(got[6].1, Verdict::Pass, "{:?}", reports[6]);
}

/// RT-11: `with constant z of X` where `X` is the machine, the controller
/// that requires `z`, or the module whose platform provides it: the value
/// reaches the machine either way (`T` is reachable only when `z == 1`).
/// A constant `X` does not lead to is refused, never left at its default.
#[test]
fn rt11_constants_through_the_hierarchy() {
    let model = "interface I { event e }
interface K { const z : nat }
stm M { uses I requires K initial i state S { } state T { }
  transition t { from i to S } transition u { from S to T condition z == 1 } transition w { from T to S trigger e } }
controller C { uses I requires K sref s = M connection C on e to s on e }
module Mod { robotic platform P { uses I provides K } cref c = C connection P on e to c on e }";
    let reports: Vec<Report> = verify_texts(
        [
            ("m.rct".to_string(), model.to_string()),
            (
                "a.assertions".to_string(),
                "timed assertion A : M::T is reachable in M with constant z of M set to 1
                 timed assertion B : M::T is reachable in Mod with constant z of Mod set to 1
                 timed assertion C : M::T is reachable in Mod with constant z of C set to 1
                 timed assertion D : M::T is reachable in Mod with constant z of M set to 1
                 timed assertion E : M::T is reachable in Mod
                 timed assertion F : M::T is reachable in Mod with constant y of M set to 1
                 timed assertion G : M::T is reachable in Mod with constant y of Mod set to 1
                 timed assertion H : M::T is reachable in Mod with constant y of C set to 1"
                    .to_string(),
            ),
        ],
        &Options::default(),
    );
    let got: Vec<(&str, Verdict, &str)> =
        reports.iter().map(|r| (r.name.as_str(), r.verdict, r.reason.as_deref().unwrap_or(""))).collect();
    assert_eq!(
        got,
        [
            ("A", Verdict::Pass, "M::T is reachable in M"),
            ("B", Verdict::Pass, "M::T is reachable in Mod"),
            ("C", Verdict::Pass, "M::T is reachable in Mod"),
            ("D", Verdict::Pass, "M::T is reachable in Mod"),
            // RT-1: z is 0 by default.
            ("E", Verdict::Fail, "M::T is not reachable in Mod"),
            ("F", Verdict::Unsupported, "the state machine `M` has no constant `y`"),
            ("G", Verdict::Unsupported, "no state machine of the module `Mod` requires a constant `y`"),
            ("H", Verdict::Unsupported, "no state machine of the controller `C` requires a constant `y`"),
        ]
    );
}

const OPERATION: &str = "interface I { event a event b }
operation Op(n : nat) { uses I
  initial i state S { } final f
  transition t { from i to S }
  transition u { from S to f condition n == 0 action a }
  transition v { from S to S condition n > 0 action b } }
stm M { uses I const n : nat
  initial i state S { } final f
  transition t { from i to S }
  transition u { from S to f condition n == 0 action a }
  transition v { from S to S condition n > 0 action b } }";

/// RT-11: an operation checked on its own is RoboTool's `O__` of it: its
/// body as a process that terminates at its final state, its parameters
/// constants — `with parameter n of Op set to v`, else RoboTool's
/// `param_n = 0`, noted. It gets the verdicts, state counts and
/// counterexamples of the machine with the same body and a constant.
#[test]
fn rt11_operations_as_subjects() {
    let kinds = ["is deadlock-free", "is deterministic", "is divergence-free", "terminates"];
    let mut text = String::new();
    for (k, kind) in kinds.iter().enumerate() {
        text.push_str(&format!("assertion O{k} : Op {kind}\nassertion M{k} : M {kind}\n"));
        text.push_str(&format!(
            "assertion P{k} : Op {kind} with parameter n of Op set to 1\nassertion N{k} : M {kind} with constant n of M set to 1\n"
        ));
    }
    for semantics in [Semantics::Timed, Semantics::Untimed] {
        let reports: Vec<Report> = verify_texts(
            [("m.rct".to_string(), OPERATION.to_string()), ("a.assertions".to_string(), text.clone())],
            &Options::default(),
        )
        .into_iter()
        .filter(|r| r.semantics == semantics)
        .collect();
        assert_eq!(reports.len(), 16);
        for pair in reports.chunks(2) {
            let (op, m) = (&pair[0], &pair[1]);
            assert_ne!(op.verdict, Verdict::Unsupported, "{op:#?}");
            assert_eq!((op.verdict, op.stats.states), (m.verdict, m.stats.states), "{op:#?} {m:#?}");
            let trace = |r: &Report| r.counterexample.as_ref().map(|c| trace_text(&c.steps));
            assert_eq!(trace(op).is_some(), trace(m).is_some());
        }
        // With n = 0 the operation ends after `a`; with n = 1 it never ends.
        assert_eq!([reports[12].verdict, reports[14].verdict], [Verdict::Pass, Verdict::Fail], "{reports:#?}");
        assert!(reports[0].notes.join("\n").contains("parameter Op::n = 0 (RT-11)"), "{:?}", reports[0].notes);
        assert!(!reports[2].notes.join("\n").contains("parameter Op::n"), "{:?}", reports[2].notes);
    }
}
