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

const FUNCTIONS: &str = "enumeration Mode { Idle Busy }
    interface I { event zero event yes event idle event chosen }
    function scale(x : nat) : nat { }
    function ready() : boolean { precondition true }
    function mode() : Mode { }
    function choose(s : Set(nat)) : nat { precondition s != {} postcondition result in s }
    stm M { uses I
      initial i state S { } state Z { } state Y { } state D { } state C { }
      transition t { from i to S }
      transition a { from S to Z condition scale(2) == 0 action zero }
      transition b { from S to Y condition ready() action yes }
      transition c { from S to D condition mode() == Mode::Idle action idle }
      transition d { from S to C condition choose({1, 2}) == 0 action chosen } }";

/// RT-2: a function without a body returns its result type's default —
/// 0, `true`, the first literal — even when its postcondition says
/// otherwise (`choose` returns 0, not a member of `{1, 2}`), and each
/// verdict names the defaults it rests on.
#[test]
fn bodiless_functions_return_the_default_of_their_type() {
    let reports = run(
        FUNCTIONS,
        "assertion Z : M::Z is reachable in M
         assertion Y : M::Y is reachable in M
         assertion D : M::D is reachable in M
         assertion C : M::C is reachable in M",
    );
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(got, [("Z", Verdict::Pass), ("Y", Verdict::Pass), ("D", Verdict::Pass), ("C", Verdict::Pass)]);
    let notes = reports[0].notes.join("\n");
    for d in [
        "function scale(x) = 0 (RT-2)",
        "function ready() = true (RT-2)",
        "function mode() = Mode_Idle (RT-2)",
        "function choose(s) = 0 (RT-2)",
    ] {
        assert!(notes.contains(d), "{d}: {notes}");
    }
    // With the defaults, `scale(2)` is 0: the guard `scale(2) == 1` never holds.
    let other = run(&FUNCTIONS.replace("scale(2) == 0", "scale(2) == 1"), "assertion Z : M::Z is reachable in M");
    assert_eq!(other[0].verdict, Verdict::Fail, "{other:#?}");
}

/// RT-2 and RT-7: a CSPm definition in the assertion file wins over the
/// default (and the notes do not claim one); an `Instantiations` block
/// replaces the generated defaults, so a function it does not define has
/// no definition at all and the check is refused, not guessed; a function
/// defined by `result == e` is not given a default either.
#[test]
fn defined_functions_are_not_defaults() {
    let defined = run(FUNCTIONS, "csp Defs csp-begin\nscale(x) = x + 1\ncsp-end\nassertion Z : M::Z is reachable in M");
    assert_eq!(defined[0].verdict, Verdict::Fail, "{defined:#?}");
    assert!(!defined[0].notes.join("\n").contains("function scale"), "{:?}", defined[0].notes);
    let replaced =
        run(FUNCTIONS, "csp Instantiations csp-begin\nscale(x) = x\ncsp-end\nassertion Z : M::Z is reachable in M");
    let reason = replaced[0].reason.clone().unwrap_or_default();
    assert_eq!(replaced[0].verdict, Verdict::Unsupported);
    assert!(reason.starts_with("`ready` has no definition the native checker can read"), "{reason}");
    assert!(reason.contains("RT-7"), "{reason}");
    let post = run(
        &FUNCTIONS.replace(
            "function scale(x : nat) : nat { }",
            "function scale(x : nat) : nat { postcondition result == x }",
        ),
        "assertion Z : M::Z is reachable in M",
    );
    assert_eq!(post[0].verdict, Verdict::Unsupported);
    assert!(post[0].reason.as_deref().unwrap_or_default().contains("result == …"), "{post:#?}");
}

/// RT-5: `core_real` is widened by the values of the model's expressions,
/// each computed with the sticky arithmetic over the base ranges: `180 / 4`
/// is `Div(180, 4, {-2..2})`, which keeps 180, so `core_real = {-2..180}`;
/// the operands `180` and `4` widen nothing, and no `nat` expression
/// leaves {0..2}. In the widened domain the division gives 45.
#[test]
fn domains_are_widened_by_expression_values() {
    let model = "interface I { event quarter }
        stm M { uses I var y : real const half : real
          initial i state S { } state Q { }
          transition t { from i to S action y = 180 / 4 }
          transition a { from S to Q condition y == half action quarter } }";
    let reports = run(
        model,
        "assertion A : M::Q is reachable in M with constant half of M set to 45
         assertion B : M::Q is reachable in M with constant half of M set to 180",
    );
    let got: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(got, [("A", Verdict::Pass), ("B", Verdict::Fail)], "{reports:#?}");
    let notes = reports[0].notes.join("\n");
    assert!(notes.contains("core_real = {-2..180}, widened by the model's expressions (RT-5)"), "{notes}");
    // As RoboTool, the assertion's values widen nothing (`half = 45` is
    // only compared, never sent or stored: no error either).
    assert!(notes.contains("core_nat = {0..2}, core_int = {-2..2}, core_real = {-2..180}"), "{notes}");
    assert!(!notes.contains("widened by the constants"), "{notes}");
}

/// RT-5: the arithmetic is sticky in the domain of the expression's type:
/// `x + 1` is a `nat` sum, `Plus(x, 1, core_nat)`, so at `x == 2` it stays
/// 2 (core_nat = {0..2}) even though `core_real` reaches 180; `T` is never
/// reached.
#[test]
fn arithmetic_is_sticky_in_the_type_of_the_expression() {
    let model = "interface I { event up event top }
        stm M { uses I var x : nat var r : real
          initial i state S { } state T { }
          transition t { from i to S action r = 180 / 4 }
          transition u { from S to S condition x < 2 action x = x + 1 ; up }
          transition v { from S to T condition x + 1 > 2 action top } }";
    let reports = run(model, "assertion T : M::T is reachable in M");
    assert_eq!(reports[0].verdict, Verdict::Fail, "{reports:#?}");
    assert!(reports[0].notes.join("\n").contains("core_nat = {0..2}"), "{:?}", reports[0].notes);
}

/// RT-5: RoboTool's domain is `union(base, {min..max})`; when the values
/// do not reach the base range it is not one range ({0..2} ∪ {7}), which
/// the engine does not represent: refused with the reason, never widened
/// to {0..7}.
#[test]
fn a_domain_with_a_gap_is_refused() {
    let model = "interface I { event e }
        stm M { uses I var x : nat
          initial i state S { }
          transition t { from i to S action x = 7 ; e } }";
    let reports = run(model, "assertion A : M is deadlock-free");
    assert_eq!(reports[0].verdict, Verdict::Unsupported, "{reports:#?}");
    let reason = reports[0].reason.clone().unwrap_or_default();
    // `core_real` (computed first) has the same gap.
    assert!(reason.contains("∪ {7..7} (RT-5), not one range"), "{reason}");
}

/// RT-5 and RT-7 on the paper's design (examples/paper): RoboTool bounds
/// `core_real` by the model's expressions, {-2..2}, whatever values an
/// assertion gives the constants. Then `PI / av` is `Div(45, 15, {-2..2})`,
/// 45 by the sticky rule, and the clock `MBC` is compared with 45, beyond
/// `core_clock_type = {0..10}`: an error in RoboTool too ("core_clock_type
/// is not wide enough"), not a verdict (and `move(0, av)` would send 15
/// outside `core_real`, which FDR stops on: see the fixture
/// `rt5_assertion_constants`). With the `Instantiations` block of
/// examples/paper/design.assertions, `PI / av` is 3 and the check goes
/// through.
#[test]
fn the_papers_constants_need_the_types_given() {
    let design = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper/design.rct"))
        .expect("examples/paper/design.rct");
    let d1 = "assertion D1 : CFootBot is deadlock-free
        with constant PI of SMovement set to 45, constant av of SMovement set to 15,
        and constant lv of SMovement set to 1 .";
    for r in run(&design, &format!("import paper_design::*\n{d1}")) {
        assert_eq!(r.verdict, Verdict::Unsupported, "{r:#?}");
        let reason = r.reason.unwrap_or_default();
        assert!(
            reason.starts_with(
                "`mv::sm::MBC` is compared with 45, above the greatest clock value 10 (`core_clock_type = {0..10}`)"
            ),
            "{reason}"
        );
    }
    let block = "csp Instantiations csp-begin
        nametype core_nat = {0..45}
        nametype core_int = { -2..45}
        nametype core_real = { -2..45}
        csp-end";
    for r in run(&design, &format!("import paper_design::*\n{block}\n{d1}")) {
        assert_eq!(r.verdict, Verdict::Pass, "{r:#?}");
    }
}
