//! RoboTool's defaults where the model gives no value (robotool-facts
//! RT-1, RT-4): a constant without a value takes its type's default (0,
//! the first literal, `true`), an uninitialised boolean starts `true`, and
//! a verdict that rests on a default says so in its notes.

use robosim_engine::verify::{Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

fn run(rct: &str, assertions: &str) -> Vec<Report> {
    verify_texts(
        [("m.rct".to_string(), rct.to_string()), ("a.assertions".to_string(), assertions.to_string())],
        &Options::default(),
    )
}

const MODEL: &str = "interface I { event zero event one event yes event first }
    enumeration Mode { Idle Busy }
    stm M { uses I const k : nat const b : boolean const m : Mode var flag : boolean
      initial i state S { } state Z { } state O { } state Y { } state F { }
      transition t { from i to S }
      transition a { from S to Z condition k == 0 action zero }
      transition c { from S to O condition k == 1 action one }
      transition d { from S to Y condition b /\\ flag action yes }
      transition e { from S to F condition m == Mode::Idle action first } }";

/// Reachability of each state shows the value each default took.
#[test]
fn constants_and_booleans_take_robotools_defaults() {
    let reports = run(
        MODEL,
        "assertion Z : M::Z is reachable in M
         assertion O : M::O is reachable in M
         assertion Y : M::Y is reachable in M
         assertion F : M::F is reachable in M",
    );
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    // k = 0, not 1; b and flag are true; m is Idle.
    assert_eq!(got, [("Z", Verdict::Pass), ("O", Verdict::Fail), ("Y", Verdict::Pass), ("F", Verdict::Pass)]);
    let notes = reports[0].notes.join("\n");
    for d in [
        "constant M::k = 0 (RT-1)",
        "constant M::b = true (RT-1)",
        "constant M::m = Mode_Idle (RT-1)",
        "variable M::flag starts true (RT-4)",
    ] {
        assert!(notes.contains(d), "{d}: {notes}");
    }
}

/// A value from the assertion or an initialiser is not a default, and
/// the notes do not claim one.
#[test]
fn given_values_are_not_defaults() {
    let model = MODEL.replace("var flag : boolean", "var flag : boolean = false");
    let reports = run(
        &model,
        "assertion O : M::O is reachable in M with constant k of M set to 1, and constant b of M set to true",
    );
    assert_eq!(reports[0].verdict, Verdict::Pass, "{reports:#?}");
    let notes = reports[0].notes.join("\n");
    assert!(!notes.contains("constant M::k"), "{notes}");
    assert!(!notes.contains("flag"), "{notes}");
}

/// RT-6: division never fails — RoboTool wraps every divisor so that
/// `x / 0` is `x / 1` — so a division by zero is neither an error nor
/// inconclusive, and the machine goes on with `x`.
#[test]
fn division_by_zero_divides_by_one() {
    let model = "interface I { event five event other }
        stm M { uses I var x : nat = 5 var y : nat = 0
          initial i state S { } state Five { } state Other { }
          transition t { from i to S action x = x / y }
          transition a { from S to Five condition x == 5 action five }
          transition b { from S to Other condition x != 5 action other } }";
    let reports = run(
        model,
        "assertion F : M::Five is reachable in M
         assertion O : M::Other is reachable in M",
    );
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(got, [("F", Verdict::Pass), ("O", Verdict::Fail)], "{reports:#?}");
}

/// RT-3: a primitive type the model declares (`type ID`) ranges over
/// {0, 1} when no assertion file gives it a range, and the notes say so:
/// an input of type ID offers 0 and 1, and nothing else.
#[test]
fn primitive_types_range_over_zero_and_one() {
    let model = "type ID
        interface I { event pick : ID event one event two }
        stm M { uses I var who : ID
          initial i state S { } state P { } state One { } state Two { }
          transition t { from i to S }
          transition p { from S to P trigger pick?who }
          transition a { from P to One condition who == 1 action one }
          transition b { from P to Two condition who == 2 action two } }";
    let reports = run(
        model,
        "assertion O : M::One is reachable in M
         assertion T : M::Two is reachable in M",
    );
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(got, [("O", Verdict::Pass), ("T", Verdict::Fail)], "{reports:#?}");
    assert!(reports[0].notes.join("\n").contains("type ID = {0, 1} (RT-3)"), "{:?}", reports[0].notes);
}

/// RT-5: the number types are bounded once for the project (RoboTool's
/// one `instantiations.csp`), widened by the literals of every model, not
/// only the checked element's. Here `B` alone would bound `nat` to
/// {0..2}, where `x + 1` sticks at 2; `A`'s literal 5 widens it, so `x`
/// reaches 3 and `Big` is reachable, as in RoboTool.
#[test]
fn number_types_are_bounded_by_the_whole_project() {
    let model = "stm A { var y : nat initial i state S { } transition t { from i to S action y = 5 } }
        stm B { var x : nat initial i state S { } state Big { }
          transition t { from i to S }
          transition u { from S to S condition x <= 2 action x = x + 1 }
          transition v { from S to Big condition x > 2 } }";
    let reports = run(model, "assertion R : B::Big is reachable in B");
    assert_eq!(reports.len(), 1);
    assert_eq!(reports[0].verdict, Verdict::Pass, "{:?}", reports[0].reason);
}
