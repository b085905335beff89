//! Products and finite sets: tuple variables and events (one slot, one
//! event parameter printed as one field per component), bitmask sets, and
//! the alpha-algorithm's `Communication` machine of the corpus.

use std::path::Path;

use robosim_engine::verify::{trace_text, Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

fn run(files: &[(&str, String)]) -> Vec<Report> {
    verify_texts(files.iter().map(|(p, t)| (p.to_string(), t.clone())), &Options::default())
}

const MODEL: &str = r#"type ID
interface I { event recv : ID }
interface P { event out : ID }
interface T { event pair : ID * ID }
stm Collect3 {
  uses I
  var seen : Set(ID)
  var x : ID
  initial i
  state Listen { }
  state Done { }
  transition t0 { from i to Listen }
  transition t1 { from Listen to Listen trigger recv ? x action seen = union(seen, {x}) }
  transition t2 { from Listen to Done condition size(seen) == 3 }
}
stm Collect4 {
  uses I
  var seen : Set(ID)
  var x : ID
  initial i
  state Listen { }
  state Done { }
  transition t0 { from i to Listen }
  transition t1 { from Listen to Listen trigger recv ? x action seen = union(seen, {x}) }
  transition t2 { from Listen to Done condition card(seen) == 4 }
}
stm Sender {
  uses T
  initial i
  state S { entry pair ! (| 2, 0 |) }
  transition t0 { from i to S }
}
stm Receiver {
  uses T uses P
  var p : ID * ID
  initial i
  state W { }
  state G { entry out ! (p[2]); p[2] = 1; out ! (p[2]) }
  transition t0 { from i to W }
  transition t1 { from W to G trigger pair ? p condition p == (| 0, 0 |) }
  transition t2 { from W to W trigger pair ? p condition p != (| 0, 0 |) and 2 in {p[1], 1} }
}
controller C {
  uses P
  sref s = Sender
  sref r = Receiver
  connection s on pair to r on pair
  connection r on out to C on out
}
stm Ops {
  uses I
  var s : Set(ID) = {0, 1}
  var t : Set(ID)
  var q : ID * boolean = (| 2, true |)
  initial i
  state A { }
  state B { }
  transition t0 { from i to A action t = diff(s, {0}) }
  transition t1 { from A to B condition (inter(s, t) == {1}) /\ subset(t, s) /\ not subset(s, t) /\ (size(union(s, t)) == 2) /\ member(1, t) /\ q[2] /\ (q == (| 2, true |)) /\ (t != s) }
}
stm Ops2 {
  uses I
  var s : Set(ID) = {0, 1}
  var t : Set(ID)
  var q : ID * boolean = (| 2, true |)
  initial i
  state A { }
  state B { }
  transition t0 { from i to A action t = diff(s, {0}) }
  transition t1 { from A to B condition (inter(s, t) == {1}) /\ subset(t, s) /\ subset(s, t) /\ (size(union(s, t)) == 2) /\ member(1, t) /\ q[2] /\ (q == (| 2, true |)) /\ (t != s) }
}
stm Big {
  uses I
  var s : Set(nat)
  initial i
  state A { }
  transition t0 { from i to A action s = {40} }
}
"#;

const ASSERTIONS: &str = r#"csp inst csp-begin
nametype ID = {0..2}
csp-end
assertion A : Collect3 is deadlock-free
assertion B : Collect4 is deadlock-free
assertion D : Collect4 is deterministic
assertion E : Sender is deadlock-free
assertion F : C is deadlock-free
assertion G : Ops::B is reachable in Ops
assertion G2 : Ops2::B is reachable in Ops2
assertion H : Big is deadlock-free
"#;

#[test]
fn tuples_and_sets() {
    let reports = run(&[("m.rct", MODEL.to_string()), ("a.assertions", ASSERTIONS.to_string())]);
    let got: Vec<(&str, Verdict, u64)> = reports.iter().map(|r| (r.name.as_str(), r.verdict, r.stats.states)).collect();
    assert_eq!(
        got,
        vec![
            // Collecting the three IDs lets the guard `size(seen) == 3` end it.
            ("A", Verdict::Fail, 16),
            // Four IDs never come.
            ("B", Verdict::Pass, 13),
            ("D", Verdict::Pass, 13),
            ("E", Verdict::Fail, 2),
            // A tuple exchanged between two machines, then projected.
            ("F", Verdict::Fail, 4),
            // Set operations, tuple equality and projection in a guard.
            ("G", Verdict::Pass, 2),
            ("G2", Verdict::Fail, 1),
            // RT-5: `{40}` widens no domain (set elements are not among
            // the expressions RoboTool collects), so 40 is outside Set(nat).
            ("H", Verdict::Inconclusive, 1),
        ],
        "{reports:#?}"
    );
    let trace = |i: usize| trace_text(&reports[i].counterexample.as_ref().expect("a counterexample").steps);
    assert_eq!(trace(0), "recv.in.0 recv.in.1 recv.in.2");
    assert_eq!(trace(3), "pair.out.2.0");
    assert_eq!(trace(4), "(C.s.pair.2.0) out.out.0 out.out.1");
    let reason = reports[7].reason.as_deref().unwrap_or_default();
    assert!(reason.contains("a tuple component or set element outside its type"), "{reason}");
}

/// robo-star/robochart-alpha-algorithm: `Communication` receives
/// `ID * ID` pairs and collects neighbours in a `Set(ID)`. A receive can
/// race the timeout `since(RCC) >= RC` (a triggerless transition), so the
/// machine is not deterministic; it never deadlocks nor diverges.
#[test]
fn alpha_algorithm_communication() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/robo-star__robochart-alpha-algorithm");
    let mut files = Vec::new();
    for e in std::fs::read_dir(&dir).expect("the corpus").flatten() {
        let p = e.path();
        if robosim_syntax::FileKind::from_path(&p).is_some() {
            files.push((p.display().to_string(), std::fs::read_to_string(&p).unwrap()));
        }
    }
    let files: Vec<(&str, String)> = files.iter().map(|(p, t)| (p.as_str(), t.clone())).collect();
    let mut got: Vec<(String, Verdict, u64)> = run(&files)
        .iter()
        .filter(|r| ["A1", "A2", "A3", "a1", "a2", "a3"].contains(&r.name.as_str()))
        .map(|r| (r.name.clone(), r.verdict, r.stats.states))
        .collect();
    got.sort_by(|a, b| a.0.cmp(&b.0));
    let expected = [
        ("A1", Verdict::Fail, 11),
        ("A2", Verdict::Pass, 102),
        ("A3", Verdict::Pass, 102),
        ("a1", Verdict::Fail, 11),
        ("a2", Verdict::Pass, 102),
        ("a3", Verdict::Pass, 102),
    ];
    assert_eq!(got, expected.map(|(n, v, s)| (n.to_string(), v, s)).to_vec());
}

/// Booleans and enumeration literals in events and platform calls are
/// printed by name (enumerations as RoboTool's CSPm constructors), not by
/// their codes.
#[test]
fn booleans_and_enumerations_are_printed_by_name() {
    let rct = "enumeration Mode { Idle Busy }
        interface I { event flag : boolean event mode : Mode set(m : Mode, b : boolean) }
        stm M { uses I requires I var b : boolean var m : Mode initial i state S { } state T { }
          transition t { from i to S }
          transition u { from S to T trigger mode?m action flag!true; set(Mode::Idle, false) } }";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", "assertion A : M::T is reachable in M".into())]);
    assert_eq!(reports[0].verdict, Verdict::Pass, "{reports:#?}");
    let steps = &reports[0].counterexample.as_ref().expect("a witness").steps;
    assert_eq!(trace_text(steps), "mode.in.Mode_Idle flag.out.true setCall.Mode_Idle.false");
}

/// Records of numeric fields are tuples of their fields: literals, field
/// access in guards and actions, and events carrying them.
#[test]
fn records() {
    let rct = "datatype R { a : nat b : boolean }
        interface I { event e : R event o : nat }
        stm M { uses I var r : R var q : R initial i junction J state S { } state T { }
          transition t { from i to S action q = R(| b = true, a = 2 |) }
          transition u { from S to J trigger e?r }
          transition v { from J to T condition r.b /\\ r.a < q.a action o!(r.a + 1) }
          transition w { from J to S condition else } }";
    let asserts = "assertion A : M::T is reachable in M\nassertion B : M is deadlock-free";
    let reports = run(&[("m.rct", rct.to_string()), ("a.assertions", asserts.to_string())]);
    let traces: Vec<(Verdict, String)> = reports
        .iter()
        .map(|r| (r.verdict, r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default()))
        .collect();
    // The first record received with b true and a below 2: (0, true).
    assert_eq!(traces[0], (Verdict::Pass, "e.in.0.1 o.out.1".to_string()), "{reports:#?}");
    assert_eq!(traces[1], (Verdict::Fail, "e.in.0.1 o.out.1".to_string()));
    // The output happens on the transition out of the junction: between
    // states, so no state is named.
    let out = reports[0].counterexample.as_ref().unwrap().steps.iter().find(|s| s.event == "o.out.1").unwrap();
    assert_eq!(out.description.as_deref(), Some("M: outputs"));
}
