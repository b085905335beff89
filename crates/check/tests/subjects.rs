//! What an assertion's `with` clause may give (robotool-facts RT-11):
//! enumeration literals as constants' values (`set to IType::L2`).

use robosim_check::verify::{verify_texts, Options, Report, Semantics, Verdict};

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
