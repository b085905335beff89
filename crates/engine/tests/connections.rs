//! Connections the engine interprets beyond synchronous ones: asynchronous
//! connections between controllers, through RoboTool's one-place buffer
//! that overwrites (robotool-facts.md RT-12) or the buffer the user
//! assumes instead, and platform events connected both ways (`[ mult ]`).

use robosim_engine::verify::{trace_text, AsyncBuffer, Options, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_texts;

fn verify(files: &[(&str, &str)], async_buffer: Option<AsyncBuffer>) -> Vec<Report> {
    let opts = Options { async_buffer, ..Options::default() };
    let reports = verify_texts(files.iter().map(|(p, t)| (p.to_string(), t.to_string())), &opts);
    for r in &reports {
        println!("{} {:?} {} {:?} {:?}", r.name, r.verdict, r.stats.states, r.reason, r.notes);
        if let Some(cx) = &r.counterexample {
            println!("  {}", trace_text(&cx.steps));
        }
    }
    reports
}

/// Controller `CS` sends 1 then 2 at once on `out`; controller `CR`, after
/// waiting a time unit, receives them on `inp` (asynchronously), going to
/// `G1` or `G2` after receiving 1 or 2, and on from there.
const MODEL: &str = "
    interface Out { event out : nat }
    interface In { event inp : nat }
    stm S { uses Out initial i state A { entry out!1 ; out!2 } transition t { from i to A } }
    stm R {
      uses In var x : nat
      initial i junction J state W { entry wait(1) } state G1 { } state G2 { }
      transition t0 { from i to W }
      transition t1 { from W to J trigger inp?x }
      transition g1 { from J to G1 condition x == 1 }
      transition g2 { from J to G2 condition x == 2 }
      transition n1 { from G1 to J trigger inp?x }
    }
    controller CS { uses Out sref s = S connection s on out to CS on out }
    controller CR { uses In sref r = R connection CR on inp to r on inp }
    module Mod { robotic platform P { } cref cs = CS cref cr = CR
      connection cs on out to cr on inp ( _async ) }";

/// Reachability of `G1` and `G2`; and as nothing happens after the
/// values are received, a timed deadlock ("only time passes").
const CHECKS: &str = "assertion G1 : cr::r::G1 is reachable in Mod
    assertion G2 : cr::r::G2 is reachable in Mod
    assertion D : Mod is not deadlock-free";

fn buffer(text: &str) -> Option<AsyncBuffer> {
    Some(AsyncBuffer::parse(text).expect("a buffer"))
}

fn verdicts(reports: &[Report]) -> Vec<(String, Verdict, u64)> {
    reports.iter().map(|r| (r.name.clone(), r.verdict, r.stats.states)).collect()
}

fn expect(reports: &[Report], expected: &[(&str, Verdict, u64)]) {
    let expected: Vec<(String, Verdict, u64)> = expected.iter().map(|(n, v, s)| (n.to_string(), *v, *s)).collect();
    assert_eq!(verdicts(reports), expected);
}

/// RT-12: without an assumed buffer, an asynchronous connection between
/// controllers is RoboTool's one-place buffer that overwrites (the
/// generated `Buffer0`), and every verdict says so.
#[test]
fn without_an_assumed_buffer_robotools_is_used() {
    let reports = verify(&[("m.rct", MODEL), ("a.assertions", CHECKS)], None);
    expect(&reports, &[("G1", Verdict::Fail, 6), ("G2", Verdict::Pass, 6), ("D", Verdict::Pass, 6)]);
    let g2 = reports[1].counterexample.as_ref().expect("a trace to G2");
    assert_eq!(trace_text(&g2.steps), "(cs.s.out.1) (cs.s.out.2) tock (cs.s.out.2)");
    let default = "asynchronous connections buffer 1 value; when full, a new value replaces the oldest \
                   (RoboTool's default buffer)";
    for r in &reports {
        assert!(r.notes.iter().any(|n| n.contains(default)), "{:?}", r.notes);
    }
}

/// Per buffer: the verdicts (G1, G2, D) with their states, and the
/// shortest trace to G2 (the hidden communications are the connection's).
/// A buffer assumption, its verdicts and its trace to G2.
type BufferCase = (&'static str, [(Verdict, u64); 3], &'static str);

const BUFFERS: &[BufferCase] = &[
    // 2 replaces 1 in the buffer, and is all R receives.
    (
        "1:overwrite",
        [(Verdict::Fail, 6), (Verdict::Pass, 6), (Verdict::Pass, 6)],
        "(cs.s.out.1) (cs.s.out.2) tock (cs.s.out.2)",
    ),
    // The sender waits for R to take 1 before it sends 2.
    (
        "1:block",
        [(Verdict::Pass, 6), (Verdict::Pass, 9), (Verdict::Pass, 9)],
        "(cs.s.out.1) tock (cs.s.out.1) (cs.s.out.2) (cs.s.out.2)",
    ),
    // Both values wait in the buffer.
    (
        "2:overwrite",
        [(Verdict::Pass, 6), (Verdict::Pass, 8), (Verdict::Pass, 8)],
        "(cs.s.out.1) (cs.s.out.2) tock (cs.s.out.1) (cs.s.out.2)",
    ),
];

#[test]
fn what_the_receiver_gets_depends_on_the_buffer() {
    for &(b, expected, trace) in BUFFERS {
        let reports = verify(&[("m.rct", MODEL), ("a.assertions", CHECKS)], buffer(b));
        let names = ["G1", "G2", "D"];
        expect(&reports, &names.iter().zip(expected).map(|(n, (v, s))| (*n, v, s)).collect::<Vec<_>>());
        let g2 = reports[1].counterexample.as_ref().expect("a trace to G2");
        assert_eq!(trace_text(&g2.steps), trace, "{b}");
        // Every report states the assumption it holds under.
        let assumption = buffer(b).expect("a buffer").describe();
        assert!(reports.iter().all(|r| r.notes.iter().any(|n| n.contains(&assumption))), "{b}");
    }
    assert!(buffer("1:overwrite")
        .expect("a buffer")
        .describe()
        .contains("buffer 1 value; when full, a new value replaces the oldest (RoboTool's default buffer)"));
    assert!(buffer("2:block").expect("a buffer").describe().ends_with(
        "when full, the sender waits (assumed with `--async-buffer`; RoboTool's default buffer is `1:overwrite`)"
    ));
}

#[test]
fn buffer_assumptions_are_read_strictly() {
    assert_eq!(AsyncBuffer::parse("3"), Ok(AsyncBuffer { size: 3, overwrite: true }));
    assert_eq!(AsyncBuffer::parse("2:block"), Ok(AsyncBuffer { size: 2, overwrite: false }));
    for bad in ["0", "9:overwrite", "x", "1:drop", ""] {
        assert!(AsyncBuffer::parse(bad).is_err(), "{bad}");
    }
}

/// A platform event connected both ways (`[ mult ]`): the machine receives
/// `e.in` and sends `e.out`, two channels of their own.
#[test]
fn platform_events_connected_both_ways() {
    let model = "
        interface E { event e : nat }
        stm M { uses E var x : nat initial i state S { }
          transition t0 { from i to S }
          transition t1 { from S to S trigger e?x action e!(x + 1) } }
        controller C { uses E sref m = M connection C on e to m on e [ mult ] }
        module Mod { robotic platform P { uses E } cref c = C connection P on e to c on e ( _async ) [ mult ] }";
    let checks = "assertion D : Mod is deterministic
        assertion N : Mod is deadlock-free";
    let rsa = "simulation Sim of Mod { cycleDef cycle == 1 }
        assertion A : Sim is schedulable";
    let reports = verify(&[("m.rct", model), ("a.assertions", checks), ("a.rsa", rsa)], None);
    expect(&reports, &[("D", Verdict::Pass, 7), ("N", Verdict::Pass, 7), ("A", Verdict::Pass, 31)]);
    // Answering twice in a cycle: the input and the output are registers
    // of their own, and the output's is written twice (the second output
    // cannot wait for the next cycle: its deadline is 0).
    let twice = model.replace("action e!(x + 1)", "action e!(x + 1); e!x <{0}");
    let reports = verify(&[("m.rct", &twice), ("a.rsa", rsa)], None);
    assert_eq!(reports[0].verdict, Verdict::Fail);
    let cx = reports[0].counterexample.as_ref().expect("a counterexample");
    assert_eq!(trace_text(&cx.steps), "registerRead.i_e.true.0 (e.in.0) (e.out.1) registerWrite.o_e.1");
}
