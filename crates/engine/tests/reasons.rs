//! Assertions the engine cannot decide say why, precisely: periods out of
//! range, unknown elements, values that are not literals, budgets spent.

use std::time::Duration;

use robosim_engine::verify::{trace_text, Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

const DESIGN: &str = "interface I { event i op() }
    stm M { uses I requires I const k : nat initial i0 state S { entry op(); wait(1) }
      transition t { from i0 to S } transition u { from S to S } }
    controller C { uses I requires I sref m = M connection C on i to m on i }
    module Mod { robotic platform P { uses I provides I } cref c = C connection P on i to c on i }";

fn run(rsa: &str, opts: &Options) -> Vec<Report> {
    verify_texts([("m.rct".to_string(), DESIGN.to_string()), ("a.rsa".to_string(), rsa.to_string())], opts)
}

fn reason(r: &Report) -> &str {
    r.reason.as_deref().unwrap_or_default()
}

#[test]
fn undecided_assertions_say_why() {
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }
        simulation Z of Mod { cycleDef cycle == 0 }
        simulation N of Nowhere { cycleDef cycle == 1 }
        assertion A : Z is schedulable with constant k of M set to 1 .
        assertion B : S is schedulable with constant k of M set to 1, cycleDef of S set to 5000 .
        assertion C : N is schedulable
        assertion D : S is schedulable with constant k of M set to k + 1 .
        assertion E : S is schedulable
        assertion F : T is schedulable
        assertion G : S is schedulable with constant k of M set to 1 .";
    let reports = run(rsa, &Options::default());
    let by = |n: &str| reports.iter().find(|r| r.name == n).unwrap_or_else(|| panic!("{n}"));
    for (name, expected) in [
        ("A", "no cycle period from 1 to 1000"),
        ("B", "no cycle period from 1 to 1000"),
        ("C", "is not a RoboChart module, controller or machine"),
        ("D", "is not an integer, boolean or enumeration literal"),
        ("F", "is not a simulation, module, controller or machine"),
    ] {
        let r = by(name);
        assert_eq!(r.verdict, Verdict::Unsupported, "{name}: {:?}", r.reason);
        assert!(reason(r).contains(expected), "{name}: {}", reason(r));
    }
    assert_eq!(by("G").verdict, Verdict::Pass, "{:?}", by("G").reason);
    // A constant without a value takes RoboTool's default (RT-1), and the
    // verdict says so.
    let e = by("E");
    assert_ne!(e.verdict, Verdict::Unsupported, "{:?}", e.reason);
    assert!(e.notes.iter().any(|n| n.contains("(RT-1)") && n.contains("k = 0")), "{:?}", e.notes);
}

#[test]
fn spent_budgets_are_inconclusive() {
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }
        assertion A : S is schedulable with constant k of M set to 1 .";
    let mut opts = Options::default();
    opts.budget.max_states = 3;
    let r = run(rsa, &opts).remove(0);
    assert_eq!(r.verdict, Verdict::Inconclusive);
    assert!(reason(&r).contains('3'), "{}", reason(&r));
    let mut opts = Options::default();
    opts.budget.timeout = Some(Duration::ZERO);
    let r = run(rsa, &opts).remove(0);
    assert!(matches!(r.verdict, Verdict::Inconclusive | Verdict::Pass), "{:?}", r.verdict);
}

/// A machine declared inside its controller is named `C::M`: it is checked
/// on its own, calling the controller's operations as call events (RT-19).
#[test]
fn machines_inside_controllers_are_checked_on_their_own() {
    let rct = "interface I { event e op() } interface Ops { turn() }
        controller C { uses I requires I
          operation turn() { requires I initial i final f transition t { from i to f action op(); (wait(1) <{0}) } }
          stm M { uses I requires Ops initial i state S { } state T { } transition t { from i to S }
            transition u { from S to T trigger e action turn() } }
          stm Idle { uses I initial i state S { } transition t { from i to S } } }";
    let reports = verify_texts(
        [
            ("m.rct".to_string(), rct.to_string()),
            (
                "a.assertions".to_string(),
                "assertion A : C::M::T is reachable in C::M\nassertion B : C::Idle is deadlock-free\n\
                 assertion D : C::Nothing is deadlock-free"
                    .into(),
            ),
        ],
        &Options::default(),
    );
    let got: Vec<(Verdict, String)> = reports
        .iter()
        .map(|r| {
            (
                r.verdict,
                r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_else(|| reason(r).to_string()),
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![
            // e, then the controller's operation: on its own, the machine
            // calls it as an undefined operation, a visible call (RT-19),
            // not its body (`opCall`).
            (Verdict::Pass, "e.in turnCall".to_string()),
            // Only time passes in S.
            (Verdict::Fail, String::new()),
            (Verdict::Unsupported, "`C::Nothing` is not a simulation, module, controller or machine".to_string()),
        ],
        "{reports:#?}"
    );
}

/// A clock compared with a value above the greatest clock value would stop
/// below it and the guard would never hold: refused, as RoboTool's
/// generator does, with the instantiation that widens the clocks.
#[test]
fn clocks_compared_above_their_range_are_refused() {
    let rct = "interface I { op() }
        stm M { requires I clock C initial i state S { } state T { entry op() }
          transition t { from i to S action #C } transition u { from S to T condition since(C) >= 12 } }";
    let check = |csp: &str| {
        let asserts = format!("{csp}\nassertion A : M is deadlock-free");
        verify_texts(
            [("m.rct".to_string(), rct.to_string()), ("a.assertions".to_string(), asserts)],
            &Options::default(),
        )
        .remove(0)
    };
    let r = check("");
    assert_eq!(r.verdict, Verdict::Unsupported);
    assert_eq!(
        reason(&r),
        "`M::C` is compared with 12, above the greatest clock value 10 (`core_clock_type = {0..10}`): widen it \
         with `nametype core_clock_type = {0..12}` in a `csp` block of an assertion file (m.rct:3:87)"
    );
    // Widened, T is reached after 12 time units and only time passes there.
    let r = check("csp Clocks csp-begin\nnametype core_clock_type = {0..12}\ncsp-end");
    assert_eq!(r.verdict, Verdict::Fail, "{r:#?}");
    let trace = trace_text(&r.counterexample.as_ref().unwrap().steps);
    assert!(trace.starts_with(&format!("{}opCall", "tock ".repeat(12))), "{trace}");
}

/// Two RoboSim controllers connected to each other: once refused (how
/// the event passes between their cycles was not pinned down); RT-22 now
/// says it goes through a memory cell read one cycle later (tested in
/// `robosim_facts.rs`), so the module is decided: it reads `obstacle`
/// every cycle, so time never passes alone.
#[test]
fn connected_robosim_controllers_are_decided() {
    let sim = "interface Sen { event obstacle } interface Link { event near } interface Ops { stop() }
        stm A { cycleDef cycle == 1 input context { uses Sen } output context { uses Link }
          initial i state S { } transition t0 { from i to S }
          transition t1 { from S to S exec condition $obstacle action $near } }
        stm B { cycleDef cycle == 1 input context { uses Link } output context { requires Ops }
          initial i state S { } transition t0 { from i to S }
          transition t1 { from S to S exec condition $near action $stop() } }
        controller CA { cycleDef cycle == 1 uses Sen uses Link sref a = A
          connection CA on obstacle to a on obstacle connection a on near to CA on near }
        controller CB { cycleDef cycle == 1 uses Link requires Ops sref b = B connection CB on near to b on near }
        module M { cycleDef cycle == 1 robotic platform P { uses Sen provides Ops } cref ca = CA cref cb = CB
          connection P on obstacle to ca on obstacle ( _async ) connection ca on near to cb on near }";
    let reports = verify_texts(
        [("s.rst".to_string(), sim.to_string()), ("a.rsa".to_string(), "assertion D : M is deadlock-free".to_string())],
        &Options::default(),
    );
    assert_eq!(reports[0].verdict, Verdict::Pass, "{:?}", reports[0].reason);
}

/// Probabilistic properties (checked by RoboTool with PRISM) are listed as
/// unsupported, with that reason, next to the assertions that are checked.
#[test]
fn probabilistic_properties_are_for_prism() {
    let assertions = "const t : core::nat
        constants K : Mod::c::m::k set to 1
        prob property P1 : Prob=? of [ Finally Mod::c::m::k == t ] with constants K
        prob property P2 : Prob >= 0.5 of [ Globally not deadlock ]
        assertion D : M is deadlock-free with constant k of M set to 1";
    let reports = verify_texts(
        [("m.rct".to_string(), DESIGN.to_string()), ("a.assertions".to_string(), assertions.to_string())],
        &Options::default(),
    );
    let got: Vec<(&str, Verdict, &str)> = reports.iter().map(|r| (r.name.as_str(), r.verdict, reason(r))).collect();
    assert_eq!(got[0], ("P1", Verdict::Unsupported, "probabilistic properties are checked with PRISM"));
    assert_eq!(got[1], ("P2", Verdict::Unsupported, "probabilistic properties are checked with PRISM"));
    assert_eq!(got[2].0, "D");
    assert_ne!(got[2].1, Verdict::Unsupported, "{:?}", got[2]);
}
