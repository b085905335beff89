//! RT-11: operations as assertion subjects in the export. Each test
//! exports a real small model (the engine's fixtures where they exist),
//! pins the CSPm written for the operation's process and assertions,
//! checks the whole script with our CSPm front end, and runs the
//! operation's process with our CSPm evaluator to see the events the
//! engine's fixture states.

use std::path::{Path, PathBuf};

use robosim_cspm::{Evaluator, Limits, NoNames};

mod support;
use robosim_semantics::{export_workspace, lint, Export, Options, Profile};
use support::{checked, text};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify").join(name)
}

fn export_files(files: Vec<(String, String)>) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile: Profile::RoboTool3 })
}

fn export_dir(dir: &Path) -> Export {
    let mut paths = Vec::new();
    robosim_test_support::inputs::model_files(dir, &mut paths);
    let files =
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).expect("a model file"))).collect();
    export_files(files)
}

/// The event `name` of `lts`, as written or declared in a module (FDR
/// prints `M::e.out` for a module's channel `e`): the one event whose
/// name ends with `::name`.
fn full_name(lts: &robosim_cspm::Lts, name: &str) -> String {
    if lts.event(name).is_some() {
        return name.to_string();
    }
    let suffix = format!("::{name}");
    let found: Vec<&String> = lts.events.iter().filter(|e| e.ends_with(&suffix)).collect();
    assert!(found.len() <= 1, "`{name}` is ambiguous: {found:?}");
    found.first().map_or_else(|| name.to_string(), |e| e.to_string())
}

/// Whether the process can do the visible `trace` (names as in
/// [`full_name`]).
fn has(lts: &robosim_cspm::Lts, trace: &[&str]) -> bool {
    let names: Vec<String> = trace.iter().map(|n| full_name(lts, n)).collect();
    lts.has_trace(&names.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Whether the process can do the visible `trace` and then terminate (✓).
fn terminates_after(lts: &robosim_cspm::Lts, trace: &[&str]) -> bool {
    let mut cur = lts.tau_closure(vec![lts.initial]);
    for name in trace {
        let Some(e) = lts.event(&full_name(lts, name)) else { return false };
        let next: Vec<u32> = cur
            .iter()
            .flat_map(|&s| {
                lts.transitions[s as usize].iter().filter(|(l, _)| *l == robosim_cspm::Label::Event(e)).map(|(_, t)| *t)
            })
            .collect();
        cur = lts.tau_closure(next);
    }
    cur.iter().any(|&s| lts.transitions[s as usize].iter().any(|(l, _)| *l == robosim_cspm::Label::Tick))
}

/// A RoboChart controller's operation is exported as RoboTool names it
/// (`C::OP_Op`, as the reference's `pkg223_::CommunicationC::OP_…`, with
/// `D__`, `VS__`, `O__` taking `id__` and the parameters), called or not.
/// `C::Op` and `Mod::c::Op` are subjects with their parameters (`with
/// parameter n of C::Op set to 1`, or of `Op`); comparing the operation
/// with another process is refused with its reason.
#[test]
fn controller_operations_are_subjects_as_robotool_names_them() {
    let e = export_dir(&fixture("rt11_controller_operations"));
    let model = text(&e, "m.csp");
    for line in [
        "  endmodule\n  module OP_Op\n",
        "    D__(id__, n) = TimedPriority(P__(id__, n) \\ {| entered__ |})\n    VS__(id__, n) = P__(id__, n)\n    \
         O__(id__, n) = sbisim(D__(id__, n))\n  endmodule\n",
        "    TimedPriority(\n      C::Idle::D__(id__) [[ C::Idle::terminate <- terminate ]] [| {| terminate |} |> SKIP)\n",
        "module Mod\nexports\n  -- Its end (RoboTool's `terminate`, per module).\n  channel terminate\n  \
         -- Events and operation calls.\n  -- D__: the module's semantics; VS__: with its machines' `entered__` \
         visible (reachability);\n  -- O__: D__ compressed (parameters: id__).\n  \
         D__(id__) =\n    TimedPriority(\n      \
         (C::D__(id__) [[ C::terminate <- terminate ]] [| {| terminate |} |> SKIP) \\ {| terminate |})\n  \
         VS__(id__) =\n    TimedPriority(\n      \
         (C::VS__(id__) [[ C::terminate <- terminate ]] [| {| terminate |} |> SKIP) \\ {| terminate |})\n",
    ] {
        assert!(model.contains(line), "{line}\nnot in\n{model}");
    }
    assert!(!model.contains("NOT EXPORTED"), "{model}");
    let asserts = text(&e, "a_assertions.csp");
    for block in [
        "-- assertion T0 : C::Op terminates\nassert not CHAOS(Events) [T= C::OP_Op::D__(0, 0)\n\
         assert (C::OP_Op::D__(0, 0) ; RUN({terminated__})) :[deadlock free [F]]\n",
        "-- assertion T1 : C::Op terminates with parameter n of C::Op set to 1\n\
         assert not CHAOS(Events) [T= C::OP_Op::D__(0, 1)\n",
        "-- assertion D0 : C::Op is deterministic\nassert C::OP_Op::D__(0, 0) :[deterministic [FD]]\n",
        "-- assertion M0 : Mod::c::Op terminates\nassert not CHAOS(Events) [T= C::OP_Op::D__(0, 0)\n",
        "-- assertion M1 : Mod::c::Op is deadlock-free with parameter n of Op set to 1\nassert (prioritise(\n   \
         C::OP_Op::D__(0, 1) [[ tock <- tock, tock <- tock' ]],",
    ] {
        assert!(asserts.contains(block), "{block}\nnot in\n{asserts}");
    }
    let warnings: Vec<String> = e.warnings.iter().map(|w| format!("{}:{}: {}", w.line, w.col, w.message)).collect();
    assert_eq!(
        warnings,
        ["13:1: assertion E0 is not exported: comparing the operation's process with another process is not \
          exported: their events are channels of different CSPm modules (`C::OP_Op`, `OP_Top`), which FDR would never \
          match, while `robosim verify` matches them by name"]
    );
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
    // What the engine's fixture says: n == 0, `a` then ✓; n == 1, `b` forever.
    let m = checked(&e, "a_assertions.csp", "X0__ = C::OP_Op::D__(0, 0)\nX1__ = C::OP_Op::D__(0, 1)");
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let x0 = ev.lts("X0__").unwrap();
    assert!(terminates_after(&x0, &["a.out"]), "{:?}", x0.events);
    assert!(!has(&x0, &["b.out"]), "{:?}", x0.events);
    let x1 = ev.lts("X1__").unwrap();
    assert!(has(&x1, &["b.out", "tock", "b.out"]), "{:?}", x1.events);
    assert!(!has(&x1, &["a.out"]) && !terminates_after(&x1, &["b.out"]));
}

/// An operation reference (`opref o = ops::Count`) is the operation it
/// references, also through a module's controller reference, and the
/// parameter `with parameter n of D::o` gives is the referenced
/// operation's; a parameter the operation lacks, or an `of` that names no
/// operation, leaves the assertion out with the reason.
#[test]
fn operation_references_are_their_operations() {
    let e = export_dir(&fixture("rt11_parameters_through_references"));
    let asserts = text(&e, "a_assertions.csp");
    for block in [
        "-- assertion T0 : D::o terminates\nassert not CHAOS(Events) [T= ops::OP_Count::D__(0, 0)\n",
        "-- assertion T1 : D::o terminates with parameter n of D::o set to 1\n\
         assert not CHAOS(Events) [T= ops::OP_Count::D__(0, 1)\n",
        "-- assertion T2 : Mod::d::o terminates with parameter n of Mod::d::o set to 1\n\
         assert not CHAOS(Events) [T= ops::OP_Count::D__(0, 1)\n",
        "-- assertion T3 : D::o terminates with parameter n of ops::Count set to 1\n\
         assert not CHAOS(Events) [T= ops::OP_Count::D__(0, 1)\n",
        "-- assertion T4 : D::o terminates with parameter m of D::o set to 1\n\
         -- NOT EXPORTED: the operation `D::o` (`Count`) has no parameter `m`\n",
        "-- assertion T5 : D::o terminates with parameter n of D::p set to 1\n-- NOT EXPORTED: `D::p` is not an \
         operation",
    ] {
        assert!(asserts.contains(block), "{block}\nnot in\n{asserts}");
    }
    checked(&e, "a_assertions.csp", "");
}

/// RT-11: a RoboSim operation as a subject is RoboTool's process for it on
/// its own, `OP_…::D__(id__, params)` (`C::OP_op` for one a controller
/// declares): no cycle around it, `terminate` (its final state) hidden so
/// that it ends with ✓, a `$` platform call the urgent register write, an
/// `exec` statement a visible `endexec -> startexec` with time passing
/// before either, a call of another operation the urgent call event, its
/// own clocks and variables in its hidden memory; under `TimedPriority`.
/// The engine's fixture `rt11_robosim_operations` states each verdict;
/// every assertion it checks is written, the ones it refuses are left out
/// with the same reason.
#[test]
fn robosim_operations_are_robotools_op_processes() {
    let e = export_dir(&fixture("rt11_robosim_operations"));
    let model = text(&e, "m.csp");
    let once = "-- RoboSim operation Once, on its own (RT-11)
module OP_Once
  -- Transition identifiers.
  datatype TIDS = TID_t
  channel internal__ : TIDS
exports
  -- `exec`: `endexec`, then `startexec`, both visible (RT-11).
  channel endexec, startexec
  -- State identifiers (final states too); `entered__` marks the entry into a state.
  datatype SIDS = SID_f
  channel entered__ : SIDS
  -- Its own end, cycle and registers, as RoboTool declares them per element (`M::terminate`,
  -- `M::endexec`, `M::registerRead.M::i_x`, `M::registerWrite.M::o_x`).
  channel terminate
  datatype RegisterDataOutput = o_move.core_nat
  channel registerWrite : RegisterDataOutput
  -- RoboTool's process for the operation on its own: P__ with `terminate` (its final state)
  -- visible; D__: its semantics, terminating at its final state; VS__: with `entered__`
  -- visible (reachability); O__: D__ compressed (parameters: id__).
  P__(id__) =
    let
      Behaviour__ = Junction__i
      Junction__i =
        internal__.TID_t -> (EDeadline(registerWrite.o_move.1, 0) ; entered__.SID_f -> Ending__)
        [] tock -> Junction__i
      Ending__ = terminate -> SKIP
      Memory__ = tock -> Memory__ [] internal__.TID_t -> Memory__ [] terminate -> SKIP
    within
      TimedPriority(
        (Behaviour__ [| {| internal__, tock, terminate |} |] Memory__) \\ {| internal__ |})
  D__(id__) = TimedPriority(((P__(id__) \\ {| entered__ |}) [| {terminate} |> SKIP) \\ {terminate})
  VS__(id__) = TimedPriority((P__(id__) [| {terminate} |> SKIP) \\ {terminate})
  O__(id__) = sbisim(D__(id__))
endmodule
";
    assert!(model.contains(once), "{model}");
    for piece in [
        // `exec` in an action: time may pass before `endexec` and `startexec`.
        "      Exec__ = endexec -> StartExec__ [] tock -> Exec__
      StartExec__ = startexec -> SKIP [] tock -> StartExec__
      Junction__i =
        internal__.TID_t ->
             reset_C ->
               (EDeadline(registerWrite.o_move.0, 0)
                ; Exec__
                ; EDeadline(registerWrite.o_move.1, 0)
                ; Enter__S)
        [] tock -> Junction__i
",
        // A call of another operation: the urgent call event.
        "  -- Calls of other operations (urgent).\n  channel helperCall : core_nat\n",
        "        internal__.TID_t -> (EDeadline(helperCall.2, 0) ; entered__.SID_f -> Ending__)\n        [] tock -> Junction__i\n",
        // Parameters after `id__`.
        "  D__(id__, k) =\n    TimedPriority(((P__(id__, k) \\ {| entered__ |}) [| {terminate} |> SKIP) \\ {terminate})\n",
        // An operation the controller declares, in its module.
        "  endmodule\n  module OP_Inner\n",
    ] {
        assert!(model.contains(piece), "{piece}\nnot in\n{model}");
    }
    let asserts = text(&e, "a_assertions.csp");
    for block in [
        "-- assertion O1 : Once terminates\nassert not CHAOS(Events) [T= OP_Once::D__(0)\n\
         assert (OP_Once::D__(0) ; RUN({terminated__})) :[deadlock free [F]]\n",
        "-- assertion O4 : Once is timelock-free\nassert TimelockFree__(diff(Events, {tock})) [F= OP_Once::D__(0)\n",
        "-- assertion T5 : Twice::S is reachable in Twice\n\
         assert not STOP [T= (OP_Twice::VS__(0) \\ diff(Events, {OP_Twice::entered__.OP_Twice::SID_S}))\n",
        "-- assertion L2 : Loop terminates with parameter k of Loop set to 1\n\
         assert not CHAOS(Events) [T= OP_Loop::D__(0, 1)\n",
        "-- assertion L4 : C::o terminates with parameter k of C::o set to 1\n\
         assert not CHAOS(Events) [T= OP_Loop::D__(0, 1)\n",
        "-- assertion L9 : Mod::c::o terminates with parameter k of Loop set to 0\n\
         assert not CHAOS(Events) [T= OP_Loop::D__(0, 0)\n",
        "-- assertion I2 : Mod::c::Inner terminates\nassert not CHAOS(Events) [T= C::OP_Inner::D__(0)\n",
        "-- assertion N2 : Count is deterministic\nassert OP_Count::D__(0) :[deterministic [FD]]\n",
    ] {
        assert!(asserts.contains(block), "{block}\nnot in\n{asserts}");
    }
    // Refused as the engine refuses them, with the reason.
    let refused: Vec<(&str, &str)> = asserts
        .split("-- assertion ")
        .skip(1)
        .filter_map(|b| {
            let id = b.split(' ').next()?;
            let why = b.split("-- NOT EXPORTED: ").nth(1)?;
            Some((id, why.lines().next()?))
        })
        .collect();
    let ids: Vec<&str> = refused.iter().map(|(id, _)| *id).collect();
    assert_eq!(ids, ["L6", "L7", "R3", "R4", "R0", "R1", "R2", "I3"], "{refused:#?}");
    for (id, why) in [
        ("R3", "the RoboSim operation `Nested` is not exported on its own: it has an `exec` inside a composite state"),
        ("R4", "the RoboSim operation `Reset` is not exported on its own: it requires clocks: RoboTool's process"),
        ("R0", "the RoboSim operation `Step` is not exported on its own: it requires variables: RoboTool's process"),
        ("R1", "the RoboSim operation `ExecTrigger` is not exported on its own: it has an `exec`-triggered transition"),
        ("R2", "comparing the operation's process with another process is not exported"),
    ] {
        assert!(refused.iter().any(|(i, w)| *i == id && w.starts_with(why)), "{id}: {refused:#?}");
    }
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
    // The events the engine's fixture states, run with our CSPm evaluator,
    // on the fixture's operations alone: the evaluator mistakes the
    // machine `C::M`'s private `endexec : TIDS` for the operations'
    // `endexec` (a name clash FDR's modules do not have).
    let src = std::fs::read_to_string(fixture("rt11_robosim_operations/m.rst")).unwrap();
    let ops_only = src[..src.find("controller C {").expect("the controller")].to_string();
    let e = export_files(vec![("m.rst".into(), ops_only)]);
    let m = checked(
        &e,
        "main.csp",
        "Once__ = OP_Once::D__(0)\nTwice__ = OP_Twice::D__(0)\nLoop0__ = OP_Loop::D__(0, 0)\n\
         Loop1__ = OP_Loop::D__(0, 1)\nCaller__ = OP_Caller::D__(0)\nSignal__ = OP_Signal::D__(0)\n\
         Count__ = OP_Count::D__(0)\nStuck__ = OP_Stuck::D__(0)",
    );
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    // RoboTool's operation modules have their own registers (RT-11).
    let once = ev.lts("Once__").unwrap();
    assert!(terminates_after(&once, &["OP_Once::registerWrite.OP_Once::o_move.1"]), "{:?}", once.events);
    // Urgent: time does not pass before the write.
    assert!(!has(&once, &["tock"]) && !terminates_after(&once, &[]), "{:?}", once.events);
    let twice = ev.lts("Twice__").unwrap();
    let exec = [
        "OP_Twice::registerWrite.OP_Twice::o_move.0",
        "tock",
        "OP_Twice::endexec",
        "tock",
        "OP_Twice::startexec",
        "OP_Twice::registerWrite.OP_Twice::o_move.1",
    ];
    assert!(has(&twice, &exec), "{:?}", twice.events);
    // Time passed at the `exec` counts for `since(C) >= 1`; without it, S
    // waits one time unit.
    assert!(!terminates_after(&twice, &exec[..4]) && terminates_after(&twice, &exec));
    let fast = [
        "OP_Twice::registerWrite.OP_Twice::o_move.0",
        "OP_Twice::endexec",
        "OP_Twice::startexec",
        "OP_Twice::registerWrite.OP_Twice::o_move.1",
    ];
    assert!(!terminates_after(&twice, &fast) && terminates_after(&twice, &[&fast[..], &["tock"]].concat()));
    assert!(terminates_after(&ev.lts("Loop0__").unwrap(), &[]));
    let loop1 = ev.lts("Loop1__").unwrap();
    let cycle = ["OP_Loop::endexec", "OP_Loop::startexec"];
    assert!(has(&loop1, &[&cycle[..], &cycle[..]].concat()));
    assert!(!terminates_after(&loop1, &[]) && !terminates_after(&loop1, &cycle));
    assert!(terminates_after(&ev.lts("Caller__").unwrap(), &["helperCall.2"]));
    assert!(terminates_after(&ev.lts("Signal__").unwrap(), &["OP_Signal::registerWrite.OP_Signal::o_done.2"]));
    let count = ev.lts("Count__").unwrap();
    let cycle = ["OP_Count::endexec", "OP_Count::startexec"];
    assert!(terminates_after(&count, &[&cycle[..], &cycle[..]].concat()));
    assert!(!terminates_after(&count, &cycle));
    // Only time passes in S (a timed deadlock, RT-10).
    let stuck = ev.lts("Stuck__").unwrap();
    assert!(
        has(&stuck, &["tock", "tock", "tock"])
            && !has(&stuck, &["OP_Stuck::endexec"])
            && !terminates_after(&stuck, &[])
    );
}

/// RC:C1: a controller without state machines is not a RoboChart
/// controller RoboTool accepts: it is refused with that reason, but the
/// operation it declares is still exported and checked on its own.
#[test]
fn a_controller_without_machines_is_refused_but_its_operations_are_not() {
    let model = "interface I { event a }
controller C { uses I operation Op() { uses I initial i final f transition t { from i to f action a } } }";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("a.assertions".into(), "assertion T : C::Op terminates".into()),
    ]);
    let warnings: Vec<String> = e.warnings.iter().map(|w| format!("{}:{}: {}", w.line, w.col, w.message)).collect();
    assert_eq!(
        warnings,
        ["2:12: controller C is not exported: a controller without state machines (RC:C1: RoboTool requires at least one)"]
    );
    let asserts = text(&e, "a_assertions.csp");
    assert!(asserts.contains("assert not CHAOS(Events) [T= C::OP_Op::D__(0)\n"), "{asserts}");
    let m = checked(&e, "a_assertions.csp", "X__ = C::OP_Op::D__(0)");
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    assert!(terminates_after(&ev.lts("X__").unwrap(), &["a.out"]));
}

/// The paper2019 profile (Rules 1–13) gives a RoboSim operation no process
/// of its own: an assertion on one is left out with that reason, never
/// exported against the cycle-based machine translation.
#[test]
fn paper2019_has_no_robosim_operation_process() {
    let model = "interface MoveI { move(l : nat) }
operation Once() { initial i final f transition t { from i to f action $move(1) }
  output context { requires MoveI } input context { } }";
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &mut db,
        [("m.rst".to_string(), model.to_string()), ("a.rsa".to_string(), "assertion O : Once terminates".to_string())],
        robosim_hir::RuleSet::Paper,
    );
    let e = export_workspace(&db, ws, &Options { profile: Profile::Paper2019 });
    let asserts = text(&e, "a_assertions.csp");
    assert!(
        asserts.contains(
            "-- NOT EXPORTED: the RoboSim operation `Once` on its own is RoboTool 3's process `OP_…::O__` (RT-11): \
             the paper2019 profile has none\n"
        ),
        "{asserts}"
    );
    assert!(!asserts.contains("assert "), "{asserts}");
}
