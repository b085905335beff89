//! Functions a model declares without a body, given a meaning in CSPm by
//! an instantiation block of an assertion file (as RoboTool users do for
//! FDR): inlined at each call.

use robosim_engine::verify::{trace_text, Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

const MODEL: &str = "enumeration Level { Low Mid High }
    interface I { event alarm event level : Level }
    function atLeast(a : Level, b : Level) : boolean { }
    function scale(x : nat) : nat { }
    stm M { uses I var l : Level var n : nat initial i state S { } state A { } state B { }
      transition t { from i to S }
      transition u { from S to A trigger level?l }
      transition v { from A to B condition atLeast(l, Level::Mid) action n = scale(2); alarm }
      transition w { from A to S condition not atLeast(l, Level::Mid) }
      transition x { from B to S condition n == 3 } }";

fn run(csp: &str, asserts: &str) -> Vec<Report> {
    verify_texts(
        [
            ("m.rct".to_string(), MODEL.to_string()),
            ("a.assertions".to_string(), format!("csp Instantiations csp-begin\n{csp}\ncsp-end\n{asserts}")),
        ],
        &Options::default(),
    )
}

const DEFINITIONS: &str = "lvl(Level_Low) = 1
lvl(Level_Mid) = 2
lvl(Level_High) = 3
atLeast(a, b) = lvl(a) >= lvl(b)
scale(x) = if x > 1 then x + 1 else 0";

/// The definitions decide which levels raise the alarm and what `n`
/// becomes: `alarm` follows `Mid` and `High` only (the shortest way to `B`
/// is `Mid`, printed as RoboTool's CSPm constructor), and the machine
/// comes back to `S` (n = scale(2) = 3).
#[test]
fn definitions_are_inlined_at_each_call() {
    let reports = run(
        DEFINITIONS,
        "assertion A : M::B is reachable in M
         assertion B : M is deadlock-free
         assertion C : M is deterministic",
    );
    let got: Vec<(Verdict, String)> = reports
        .iter()
        .map(|r| (r.verdict, r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default()))
        .collect();
    assert_eq!(
        got,
        vec![
            (Verdict::Pass, "level.in.Level_Mid alarm.out".to_string()),
            (Verdict::Pass, String::new()),
            (Verdict::Pass, String::new()),
        ],
        "{reports:#?}"
    );
    // With Low ranked as Mid, Low is the shortest way to B.
    let low = run(
        DEFINITIONS.replace("lvl(Level_Low) = 1", "lvl(Level_Low) = 2").as_str(),
        "assertion A : M::B is reachable in M",
    );
    assert_eq!(trace_text(&low[0].counterexample.as_ref().unwrap().steps), "level.in.Level_Low alarm.out");
    // With scale(2) = 0 the machine stays in A: a timed deadlock.
    let stuck = run(&DEFINITIONS.replace("x + 1", "0"), "assertion B : M is deadlock-free");
    assert_eq!(stuck[0].verdict, Verdict::Fail);
    assert_eq!(trace_text(&stuck[0].counterexample.as_ref().unwrap().steps), "level.in.Level_Mid alarm.out");
}

/// What cannot be inlined says why.
#[test]
fn missing_or_partial_definitions_are_refused() {
    let reason = |csp: &str| run(csp, "assertion A : M is deadlock-free").remove(0).reason.unwrap_or_default();
    let none = reason("nametype core_nat = {0..3}");
    assert!(none.starts_with("`atLeast` has no definition the native checker can read"), "{none}");
    let partial = reason(&DEFINITIONS.replace("lvl(Level_High) = 3", ""));
    assert!(partial.starts_with("the CSPm clauses of `lvl` do not cover every value"), "{partial}");
    let unknown = reason(&DEFINITIONS.replace("lvl(a) >= lvl(b)", "lvl(a) >= limit"));
    assert!(unknown.starts_with("`limit` in a CSPm definition is not known"), "{unknown}");
}
