//! Schedulability (`S is schedulable`) on small models, one construct at a
//! time, and on the paper's running example against the reference oracle
//! (`../shared/spec/semantics_oracle.py`, run with python3).

use robosim_engine::verify::{trace_text, verify_texts, Options, Profile, Report, Verdict};

/// Runs the assertions of `rsa` over the design `rct`.
fn run(rct: &str, rsa: &str) -> Vec<Report> {
    run_with(rct, rsa, Profile::RoboTool3)
}

fn run_with(rct: &str, rsa: &str, profile: Profile) -> Vec<Report> {
    verify_texts(
        [("design.rct".to_string(), rct.to_string()), ("checks.rsa".to_string(), rsa.to_string())],
        &Options { profile, ..Options::default() },
    )
}

/// A module around one machine `M` with the platform events and operations
/// of interface `I` (inputs `i`, `v`; outputs `o`, `w`; operations `op`, `op2(x)`).
fn module(machine: &str) -> String {
    format!(
        "interface I {{ event i event v : nat event o event w : nat op() op2(x : nat) }}
         enumeration Colour {{ Red Green Blue }}
         {machine}
         controller C {{ uses I requires I sref m = M
           connection C on i to m on i connection C on v to m on v
           connection m on o to C on o connection m on w to C on w }}
         module Mod {{ robotic platform P {{ uses I provides I }} cref c = C
           connection P on i to c on i connection P on v to c on v
           connection c on o to P on o connection c on w to P on w }}"
    )
}

/// `Mod` checked with period `p`: (verdict of `is schedulable`, states, trace).
fn sched(machine: &str, p: u32) -> (Verdict, u64, String) {
    let rsa = format!("simulation S of Mod {{ cycleDef cycle == {p} }}\nassertion A : S is schedulable");
    let r = run(&module(machine), &rsa).remove(0);
    let trace = r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default();
    (r.verdict, r.stats.states, if r.verdict == Verdict::Unsupported { r.reason.unwrap_or_default() } else { trace })
}

/// One construct per case: the machine, the period, the verdict of
/// `S is schedulable`, the states explored, and the counterexample's trace
/// (hidden design events in parentheses) or the reason it is unsupported.
const CASES: &[(&str, &str, u32, Verdict, u64, &str)] = &[
    ("idle machine", "stm M { uses I initial i0 state S { } transition t { from i0 to S } }", 1, Verdict::Pass, 32, ""),
    (
        "one call per cycle",
        "stm M { requires I initial i0 state S { entry op(); wait(1) } transition t { from i0 to S }
         transition u { from S to S } }",
        1, Verdict::Pass, 143, "",
    ),
    (
        "two calls in one cycle",
        "stm M { requires I initial i0 state S { entry op(); op() } transition t { from i0 to S } }",
        1, Verdict::Fail, 31, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op",
    ),
    (
        "calls of two operations in one cycle",
        "stm M { requires I initial i0 state S { entry op(); op2(1) } transition t { from i0 to S } }",
        1, Verdict::Pass, 79, "",
    ),
    (
        "a call due between samples",
        "stm M { requires I initial i0 state S { entry op(); wait(1); op2(2); wait(1) } transition t { from i0 to S }
         transition u { from S to S } }",
        2, Verdict::Fail, 39, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op tock",
    ),
    (
        // The guard sees the value of `x` before the input (as in RoboChart).
        "an input trigger binding a value, guarded output",
        "stm M { uses I var x : nat initial i0 state S { } transition t { from i0 to S }
         transition u { from S to S trigger v?x condition x < 2 action w!(x + 1) } }",
        1, Verdict::Pass, 118, "",
    ),
    (
        // Outputs are delayable: the second waits for the next cycle.
        "an output event twice in a cycle",
        "stm M { uses I initial i0 state S { } transition t { from i0 to S }
         transition u { from S to S trigger i action o; o } }",
        1, Verdict::Pass, 144, "",
    ),
    (
        "wait interval at period 1",
        "stm M { requires I initial i0 state S { entry op(); wait([1, 2]) } transition t { from i0 to S }
         transition u { from S to S } }",
        1, Verdict::Pass, 271, "",
    ),
    (
        "wait interval with period 2",
        "stm M { requires I initial i0 state S { entry op(); wait([1, 2]) } transition t { from i0 to S }
         transition u { from S to S } }",
        2, Verdict::Fail, 95, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op tock",
    ),
    (
        "clock guard with since",
        "stm M { requires I clock C initial i0 state S { entry op() } state T { }
         transition t { from i0 to S action #C } transition u { from S to T condition since(C) >= 2 }
         transition w { from T to S action #C } }",
        1, Verdict::Pass, 239, "",
    ),
    (
        "sinceEntry guard with an odd delay at period 2",
        "stm M { requires I initial i0 state S { entry op() } state T { entry op2(0) }
         transition t { from i0 to S } transition u { from S to T condition sinceEntry(S) >= 3 }
         transition w { from T to S condition sinceEntry(T) >= 3 } }",
        2, Verdict::Fail, 108, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op tock tock registerRead.i_i.true registerRead.i_v.true.0 tock",
    ),
    (
        "composite state: entry, inner initial, exit order",
        "stm M { requires I initial i0
           state A { entry op() exit op2(1) initial j state B { } transition tb { from j to B } }
           state D { }
           transition t { from i0 to A } transition u { from A to D trigger i } }",
        1, Verdict::Pass, 115, "",
    ),
    (
        "junction choosing on a variable, with if and arithmetic",
        "stm M { requires I var n : nat initial i0 junction J state S { entry n = n + 1; if n > 1 then op() else op2(n) end; wait(1) }
         transition t { from i0 to S } transition u { from S to J }
         transition a { from J to S condition n < 2 } transition b { from J to S condition n >= 2 action n = 0 } }",
        1, Verdict::Pass, 287, "",
    ),
    (
        "enumeration variable",
        "stm M { requires I var c : Colour = Colour::Red initial i0 state S { entry if c == Colour::Blue then op() end; wait(1) }
         transition t { from i0 to S } transition u { from S to S action c = Colour::Blue } }",
        1, Verdict::Pass, 127, "",
    ),
    (
        "termination",
        "stm M { requires I initial i0 final F transition t { from i0 to F action op() } }",
        1, Verdict::Pass, 39, "",
    ),
    (
        // One call per cycle in the during action, which the trigger interrupts.
        "during action",
        "stm M { requires I uses I initial i0 state S { during op2(1); wait(1); op2(1); wait(1) } state T { }
         transition t { from i0 to S } transition u { from S to T trigger i } transition w { from T to S trigger i } }",
        1, Verdict::Pass, 327, "",
    ),
    (
        "during action calling twice in a cycle",
        "stm M { requires I initial i0 state S { during op2(1); op2(1) } transition t { from i0 to S } }",
        1, Verdict::Fail, 31, "registerRead.i_i.true registerRead.i_v.true.0 (op2Call.1) registerWrite.o_op2.1",
    ),
    (
        // The environment must offer i within a time unit; if it does not,
        // that is its timelock, not a scheduling failure (TLFree).
        "input with a deadline",
        "stm M { uses I requires I initial i0 state S { entry (i <{1}); op() } transition t { from i0 to S } }",
        1, Verdict::Pass, 115, "",
    ),
    (
        // The during action and the substate's entry call in different cycles.
        "during action of a composite state alongside its substate",
        "stm M { requires I initial i0 state S { during op() initial j state T { entry wait(1); op2(1) }
         transition a { from j to T } } transition t { from i0 to S } }",
        1, Verdict::Pass, 143, "",
    ),
    (
        // Both call op in the first cycle: the during action starts after
        // the substate's entry (RT-17), then runs in parallel with it.
        "during action of a composite state calling in the substate's cycle",
        "stm M { requires I initial i0 state S { during op() initial j state T { entry op() }
         transition a { from j to T } } transition t { from i0 to S } }",
        1, Verdict::Fail, 31, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op",
    ),
    (
        // The environment must offer i within a time unit of entering S:
        // its timelock, not a scheduling failure (TLFree).
        "transition deadline on an input",
        "stm M { uses I requires I initial i0 state S { entry op() } state T { } transition t { from i0 to S }
         transition u { from S to T trigger i <{1} } }",
        1, Verdict::Pass, 127, "",
    ),
    (
        // Taken at once, the self-loop calls op again in the same cycle.
        "transition deadline on an input, re-entering its source",
        "stm M { uses I requires I initial i0 state S { entry op() } transition t { from i0 to S }
         transition u { from S to S trigger i <{1} } }",
        1, Verdict::Fail, 43, "registerRead.i_i.true registerRead.i_v.true.0 (opCall) registerWrite.o_op (i.in)",
    ),
    (
        "probabilistic junctions are refused",
        "stm M { requires I initial i0 probabilistic P state S { } transition t { from i0 to P }
         transition a { from P to S probability 0.5 } transition b { from P to S probability 0.5 } }",
        1, Verdict::Unsupported, 0, "probabilistic junctions have no meaning",
    ),
];

#[test]
fn constructs() {
    let mut failures = Vec::new();
    for &(name, machine, p, verdict, states, text) in CASES {
        let got = sched(machine, p);
        let ok = got.0 == verdict
            && got.1 == states
            && (got.2 == text || (verdict == Verdict::Unsupported && got.2.contains(text)));
        println!("{name}: {:?} {} {:?}", got.0, got.1, got.2);
        if !ok {
            failures.push(format!("{name}: expected {verdict:?} {states} {text:?}, got {got:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// RoboTool does not widen the number types by the constants' values
/// (RT-5): the paper's PI = 45, av = 15 are given the types a RoboTool user
/// gives them, in an `Instantiations` block (RT-7), as
/// `examples/paper/assertions.rsa` does.
const TYPES: &str = "csp Instantiations csp-begin
nametype core_nat = {0..45}
nametype core_int = {-2..45}
nametype core_real = {-2..45}
csp-end
";

/// The paper's Figure 1 (examples/paper/design.rct) and its variants, as the
/// oracle names them.
fn figure1(variant: &str) -> String {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper/design.rct"))
        .expect("examples/paper/design.rct");
    let out = match variant {
        "Fig.1" => text.clone(),
        "Fig.1 without wait(1) in Moving" => text.replace("entry move(lv, 0); wait(1)", "entry move(lv, 0)"),
        "Fig.1 with wait([0,1]) fixed to 0" => text.replace("wait([0, 1])", "wait(0)"),
        v => panic!("unknown variant {v}"),
    };
    assert!(variant == "Fig.1" || out != text, "the variant edit of {variant} did not apply");
    out
}

/// The oracle's event names in ours (lv = 1, av = 15, registers `i_`/`o_`).
fn oracle_trace(t: &str) -> String {
    t.split_whitespace()
        .map(|e| match e {
            "registerRead.obstacle.True" => "registerRead.i_obstacle.true",
            "registerRead.obstacle.False" => "registerRead.i_obstacle.false",
            "(moveCall.lv.0)" => "(moveCall.1.0)",
            "(moveCall.0.av)" => "(moveCall.0.15)",
            "moveCall.lv.0" => "moveCall.1.0",
            "moveCall.0.av" => "moveCall.0.15",
            "registerWrite.moveU.true.lv.0" => "registerWrite.moveU.true.1.0",
            "registerWrite.moveU.true.0.av" => "registerWrite.moveU.true.0.15",
            "registerWrite.move.lv.0" => "registerWrite.o_move.1.0",
            "registerWrite.move.0.av" => "registerWrite.o_move.0.15",
            "registerWrite.stop" => "registerWrite.o_stop",
            "(obstacle)" => "(obstacle.in)",
            other => other,
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Every schedulability case of the oracle, in both profiles: same verdict
/// and, for failures, the same shortest counterexample event for event
/// (GT-3 in `paper2019` is the paper's published trace). The oracle's state
/// counts are not compared: it steps through every internal instruction,
/// we run straight-line code in one step.
#[test]
fn agrees_with_the_oracle_on_the_running_example() {
    let oracle = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/spec/semantics_oracle.py");
    let out = std::process::Command::new("python3").arg(oracle).output().expect("python3 runs the oracle");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let mut compared = 0;
    for line in text.lines().filter(|l| l.starts_with("robotool3 ") || l.starts_with("paper2019 ")) {
        let profile = if line.starts_with("paper2019") { Profile::Paper2019 } else { Profile::RoboTool3 };
        let rest = line["robotool3 ".len()..].trim_start();
        let (variant, rest) = rest.split_once("  p=").expect("variant and period");
        let variant = variant.trim();
        let p: u32 = rest[..1].parse().expect("period");
        let (verdict, trace) = match rest.split_once("NOT schedulable: ") {
            Some((_, t)) => (Verdict::Fail, oracle_trace(t)),
            None => (Verdict::Pass, String::new()),
        };
        let rsa = format!(
            "{TYPES}simulation S of paper_design::CFootBot {{ cycleDef cycle == {p} }}
             assertion A : S is schedulable with constant PI of paper_design::SMovement set to 45,
               constant av of paper_design::SMovement set to 15, and constant lv of paper_design::SMovement set to 1 ."
        );
        let r = run_with(&figure1(variant), &rsa, profile).remove(0);
        let got = r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default();
        assert_eq!((r.verdict, got.as_str()), (verdict, trace.as_str()), "{variant}, p = {p}, {profile:?}");
        compared += 1;
    }
    assert_eq!(compared, 24, "the oracle's schedulability lines");
}

/// Operations defined by the controller run inline in the calling machine
/// (their bodies are small machines): a call that takes a time unit, with
/// parameters, and one that calls the platform twice in one cycle.
#[test]
fn operations_defined_in_the_controller() {
    let model = |body: &str| {
        format!(
            "interface I {{ event e op() op2(x : nat) }}
             interface Ops {{ turn(n : nat) }}
             stm M {{ requires I requires Ops initial i0 state S {{ entry turn(2) }}
               transition t {{ from i0 to S }} transition u {{ from S to S trigger e }} }}
             controller C {{ uses I requires I
               operation turn(n : nat) {{ requires I initial i final f
                 transition t {{ from i to f action {body} }} }}
               sref m = M connection C on e to m on e }}
             module Mod {{ robotic platform P {{ uses I provides I }} cref c = C connection P on e to c on e }}"
        )
    };
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable";
    let check = |body: &str| {
        let r = run(&model(body), rsa).remove(0);
        (r.verdict, r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default(), r.reason)
    };
    // One call per cycle: the parameter reaches the platform.
    let (v, trace, reason) = check("op2(n); wait(1)");
    assert_eq!(v, Verdict::Pass, "{reason:?}");
    assert_eq!(trace, "");
    // Two calls of op2 in the same cycle: not schedulable, and the
    // counterexample shows the operation's parameter value.
    let (v, trace, reason) = check("op2(n); op2(n)");
    assert_eq!(v, Verdict::Fail, "{reason:?}");
    assert_eq!(trace, "registerRead.i_e.true (op2Call.2) registerWrite.o_op2.2");
}

/// Two machines of a controller connected synchronously: the sender's
/// output and the receiver's input happen together, hidden.
#[test]
fn machines_connected_synchronously() {
    let model = |action: &str| {
        format!(
            "interface I {{ event i op2(x : nat) }}
             interface L {{ event c : nat }}
             stm P {{ uses I uses L initial i0 state S {{ }} transition t {{ from i0 to S }}
               transition u {{ from S to S trigger i action c!2 }} }}
             stm Q {{ uses L requires I var x : nat initial i0 state S {{ }} transition t {{ from i0 to S }}
               transition u {{ from S to S trigger c?x action {action} }} }}
             controller C {{ uses I requires I sref p = P sref q = Q
               connection C on i to p on i connection p on c to q on c }}
             module Mod {{ robotic platform R {{ uses I provides I }} cref k = C connection R on i to k on i }}"
        )
    };
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable";
    let r = run(&model("op2(x)"), rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Pass, "{:?}", r.reason);
    let r = run(&model("op2(x); op2(x)"), rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    let trace = trace_text(&r.counterexample.as_ref().expect("a counterexample").steps);
    assert_eq!(trace, "registerRead.i_i.true (i.in) (k.p.c.2) (op2Call.2) registerWrite.o_op2.2");
}

/// Two machines sharing a variable the controller provides: one sets it on
/// an input, the other reacts to it.
#[test]
fn shared_variables() {
    let model = |extra: &str| {
        format!(
            "interface I {{ event i op() {extra} }}
             interface Sh {{ var n : nat }}
             stm A {{ uses I requires Sh initial i0 state S {{ }} transition t {{ from i0 to S }}
               transition u {{ from S to S trigger i action n = 1 }} }}
             stm B {{ requires I requires Sh initial i0 state S {{ }} transition t {{ from i0 to S }}
               transition u {{ from S to S condition n == 1 action op(); n = 0 }} }}
             controller C {{ uses I requires I provides Sh sref a = A sref b = B connection C on i to a on i }}
             module Mod {{ robotic platform R {{ uses I provides I }} cref k = C connection R on i to k on i }}"
        )
    };
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable";
    let r = run(&model(""), rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Pass, "{:?}", r.reason);
    assert!(r.stats.states > 10, "{}", r.stats.states);
    // B sees A's write: calling twice when it does is not schedulable.
    let twice = model("").replace("action op(); n = 0", "action op(); op(); n = 0");
    let r = run(&twice, rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    let platform = model("")
        .replace("robotic platform R { uses I provides I }", "robotic platform R { uses I provides I provides Sh }");
    // Provided by the platform, `n` is an output (tests/platform_variables.rs):
    // A's update and B's reset fall in one cycle, two writes of `n`.
    let r = run(&platform, rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    let trace = trace_text(&r.counterexample.as_ref().expect("a counterexample").steps);
    assert_eq!(trace, "registerRead.i_i.true (i.in) (set_n.1) registerWrite.o_n.1 (opCall) registerWrite.o_op");
}

/// A counterexample that depends on RoboTool's sticky arithmetic says so.
#[test]
fn saturation_is_noted() {
    // n counts 0, 1, 2 and sticks at 2 (nat is {0..2} here): op2 is then
    // called twice in a cycle, which the unbounded count would never do.
    let m = "stm M { requires I uses I var n : nat initial i0 state S { } transition t { from i0 to S }
             transition u { from S to S trigger i action n = n + 1; if n == 2 then op2(n); op2(n) end } }";
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable";
    let r = run(&module(m), rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    let c = r.counterexample.expect("a counterexample");
    assert!(c.explanation.iter().all(|e| !e.contains("sticky")), "no saturation on the way: {:?}", c.explanation);
    let m2 = m.replace("if n == 2", "if n == 2 /\\ n + 1 == 2");
    let r = run(&module(&m2), rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    let c = r.counterexample.expect("a counterexample");
    assert!(c.explanation.iter().any(|e| e.contains("sticky arithmetic")), "{:?}", c.explanation);
}

/// RoboTool's instantiation blocks: a primitive type the model declares
/// gets its range from `nametype`, a constant with no value its value from
/// `Machine_k = v` (as RoboTool's generated instantiations name them);
/// without them, RoboTool's defaults.
#[test]
fn instantiations_give_types_and_constants() {
    let m = "type ID
             stm M { requires I const k : nat var who : ID initial i0
               state S { entry who = 1; op2(k); wait(1) } transition t { from i0 to S } transition u { from S to S } }";
    let block = "csp Instantiations csp-begin\nnametype ID = {0..1}\nM_k = 2\ncsp-end\n";
    let rsa = format!("{block}simulation S of Mod {{ cycleDef cycle == 1 }}\nassertion A : S is schedulable");
    let r = run(&module(m), &rsa).remove(0);
    assert_eq!(r.verdict, Verdict::Pass, "{:?}", r.reason);
    assert!(r.notes.iter().any(|n| n.contains("M::k = 2") || n.contains("m::k = 2")), "{:?}", r.notes);
    // Without them, RoboTool's defaults (RT-1, RT-3), which the notes name.
    let r = run(&module(m), "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable").remove(0);
    assert_eq!(r.verdict, Verdict::Pass, "{:?}", r.reason);
    let notes = r.notes.join("\n");
    assert!(notes.contains("type ID = {0, 1} (RT-3)"), "{notes}");
    assert!(notes.contains("constant c::m::k = 0 (RT-1)"), "{notes}");
}

/// An operation defined in another file (another package) than the
/// machine that calls it: its body's names resolve in its own file, and
/// the counterexample's steps point into that file.
#[test]
fn operations_defined_in_another_file() {
    let ops = "package ops
        interface Events { event e }
        interface Calls { op() op2(x : nat) }
        operation turn(n : nat) { requires Calls initial i final f
          transition t { from i to f action op2(n); op2(n) } }";
    let main = "import ops::*
        interface Ops { turn(n : nat) }
        stm M { uses Events requires Ops initial i0 state S { entry turn(2) }
          transition t { from i0 to S } transition u { from S to S trigger e } }
        controller C { uses Events requires Calls opref turn = ops::turn sref m = M connection C on e to m on e }
        module Mod { robotic platform P { uses Events provides Calls } cref c = C
          connection P on e to c on e ( _async ) }";
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable";
    let r = verify_texts(
        [
            ("ops.rct".to_string(), ops.to_string()),
            ("main.rct".to_string(), main.to_string()),
            ("checks.rsa".to_string(), rsa.to_string()),
        ],
        &Options::default(),
    )
    .remove(0);
    assert_eq!(r.verdict, Verdict::Fail, "{r:#?}");
    let c = r.counterexample.as_ref().unwrap();
    assert_eq!(trace_text(&c.steps), "registerRead.i_e.true (op2Call.2) registerWrite.o_op2.2");
    let call = c.steps.iter().find(|s| s.event == "(op2Call.2)").unwrap();
    assert_eq!(call.location.as_ref().unwrap().file, "ops.rct");
    assert_eq!(c.stuck_at.iter().map(|l| l.file.as_str()).collect::<Vec<_>>(), ["ops.rct"]);
}
