//! RT-19 for RoboSim: a machine's calls of operations defined in the model
//! (without `$`). Inside a controller that defines the operation, the
//! machine runs it (as the native checker inlines it: its `exec` ends the
//! machine's cycle, its register writes are the machine's); on its own,
//! a call is the urgent visible call event (RoboTool's `CALL__op =
//! EDeadline(opCall, 0)`, the reference's
//! `csp-gen/sim/defs/pkg223_aggregation_sim_Movement.csp`). Each test
//! exports a real model (the bundled lawnmower, the engine's fixture
//! `rt19_robosim_machine_runs_its_controller_operation`), pins the CSPm
//! written, checks it with our CSPm front end and runs it with our
//! evaluator.

use std::path::{Path, PathBuf};

use robosim_cspm::{Evaluator, Limits, NoNames};

mod support;
use robosim_semantics::{export_workspace, lint, Export, Options, Profile};
use support::{after, checked, own, refs, terminates_after, text};

fn export_files(files: Vec<(String, String)>, profile: Profile) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile })
}

fn export_dir(dir: &Path) -> Export {
    let mut paths = Vec::new();
    robosim_test_support::inputs::model_files(dir, &mut paths);
    let files =
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).expect("a model file"))).collect();
    export_files(files, Profile::RoboTool3)
}

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../engine/test_data/verify/rt19_robosim_machine_runs_its_controller_operation")
}

fn warnings(e: &Export) -> Vec<String> {
    e.warnings.iter().map(|w| format!("{}:{}: {}", w.line, w.col, w.message)).collect()
}

/// The bundled lawnmower simulation (`examples/lawnmower`): `SimMower`'s
/// `Avoiding` calls `turnAway(s)`, which its controller `SimMowerCtrl`
/// defines. Everything is exported, without warnings: on its own the
/// machine calls `turnAwayCall.s` (urgent); inside the controller it runs
/// `CALL__turnAway(s)`, the operation's process `OP_turnAway::D__`.
#[test]
fn the_lawnmower_simulation_runs_its_controller_operation() {
    let e = export_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/lawnmower"));
    assert_eq!(warnings(&e), Vec::<String>::new());
    let sim = text(&e, "lawnmower_sim.csp");
    assert!(!sim.contains("NOT EXPORTED"), "{sim}");
    expect_test::expect_file!["robosim_calls/lawnmower_sim.csp"].assert_eq(&sim);
    let asserts = text(&e, "lawnmower_2_assertions.csp");
    for name in ["R1", "D1"] {
        let at = asserts.find(&format!("-- assertion {name} :")).expect("the assertion");
        assert!(asserts[at..].lines().nth(1).is_some_and(|l| l.starts_with("assert ")), "{name}: {asserts}");
    }
    checked(&e, "lawnmower_2_assertions.csp", "");
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
}

/// The engine's fixture: `M` (writes move.1, calls step(2), ends its cycle
/// at t1's `exec`, then reaches F) inside `C`, which defines `step` (`exec`,
/// then move.k): move.1, the cycle ended in step's `exec`, move.2 in the
/// next, the machine's own `exec` ends that one, then ✓ in the third. On
/// its own: move.1 and the urgent `stepCall.2` in the first cycle, ✓ in
/// the second. Each cycle ends with the visible `endexec`, and the end
/// with `terminate` (RT-21: a machine or a controller on its own).
#[test]
fn a_machine_runs_its_controller_operation_and_calls_it_on_its_own() {
    let e = export_dir(&fixture());
    // Every operation a controller defines is also exported on its own
    // (RT-11), where one requiring variables is refused; run by M3 it is
    // exported (`C3 equals CS4` in the fixture).
    assert_eq!(
        warnings(&e),
        ["144:5: operation CInc::inc is not exported on its own: it requires variables: RoboTool's process for it on \
          its own (`OP_…::O__`) has no memory for them, so it reads them with visible events at every step \
          (`get_x?x`, values chosen by the environment) and writes or resets them with visible events (`set_x!v`, \
          `clockReset`), which `robosim verify` does not model yet (check a machine that calls it)"]
    );
    let model = text(&e, "m.csp");
    assert!(model.contains("CALL__inc =\n          CInc::OP_inc::D__(id__) [[ CInc::OP_inc::get_n <- get_n, CInc::OP_inc::set_n <- set_n ]]\n"), "{model}");
    expect_test::expect_file!["robosim_calls/m.csp"].assert_eq(&model);
    let m = checked(
        &e,
        "a_assertions.csp",
        "InC__ = C::D__(0, 1)\nAlone__ = M::D__(0, 1)\nSpec__ = CS::D__(0, 1)\nInC3__ = CInc::D__(0, 1)",
    );
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let in_c = ev.lts("InC__").unwrap();
    // Each element's own names, as RoboTool's (`C::registerWrite.C::o_move.1`).
    let cycles = [
        "registerWrite.o_move.1",
        "endexec",
        "tock",
        "registerWrite.o_move.2",
        "endexec",
        "tock",
        "endexec",
        "terminate",
    ];
    let early = [&cycles[..5], &["terminate"]].concat();
    let (c_cycles, c_early) = (own("C", &cycles), own("C", &early));
    // Not at the end of the second cycle.
    assert!(terminates_after(&in_c, &refs(&c_cycles)), "{:?}", in_c.events);
    // The writes are urgent, and step's `exec` ends the first cycle.
    assert!(
        after(&in_c, &["tock"]).is_empty()
            && after(&in_c, &refs(&own("C", &["registerWrite.o_move.1", "registerWrite.o_move.2"]))).is_empty()
    );
    assert!(!terminates_after(&in_c, &refs(&c_early)) && !in_c.events.iter().any(|e| e.contains("stepCall")));
    // As Spec writes it out (its own states counted apart).
    let spec = ev.lts("Spec__").unwrap();
    assert!(terminates_after(&spec, &refs(&own("CS", &cycles))) && !terminates_after(&spec, &refs(&own("CS", &early))));
    // inc() raises M3's own n, which M3 writes: as Spec.
    let in_c3 = ev.lts("InC3__").unwrap();
    assert!(
        terminates_after(&in_c3, &refs(&own("CInc", &cycles)))
            && !terminates_after(&in_c3, &refs(&own("CInc", &early)))
    );
    let alone = ev.lts("Alone__").unwrap();
    let first = ["registerWrite.o_move.1", "M::stepCall.2", "endexec", "tock"];
    let ends = own("M", &[&first[..], &["endexec", "terminate"]].concat());
    assert!(terminates_after(&alone, &refs(&ends)), "{:?}", alone.events);
    assert!(after(&alone, &refs(&own("M", &["registerWrite.o_move.1", "tock"]))).is_empty());
    let twice = own("M", &["registerWrite.o_move.1", "M::stepCall.2", "registerWrite.o_move.2"]);
    assert!(after(&alone, &refs(&twice)).is_empty());
    assert!(after(&alone, &refs(&own("M", &[&first[..], &["registerWrite.o_move.2"]].concat()))).is_empty());
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
}

/// What the export does not run inside a machine yet, which the native
/// checker inlines, is refused with that reason (not a wrong one): an
/// operation with an `exec`-triggered transition, or requiring a clock;
/// the paper2019 profile gives operations no process. A platform
/// operation called without `$` (RS:SM6) keeps its message.
#[test]
fn calls_the_export_cannot_run_are_refused_with_the_reason() {
    let model = |op_body: &str, call: &str| {
        format!(
            "interface MoveI {{ move(l : nat) }}
interface SoftI {{ step() }}
interface Clk {{ clock K }}
stm M {{ cycleDef cycle == 1 requires SoftI input context {{ }} output context {{ requires MoveI }}
  initial i state A {{ entry {call} }} transition t0 {{ from i to A }} }}
controller C {{ cycleDef cycle == 1 requires MoveI
  operation step() {{ {op_body} input context {{ }} output context {{ requires MoveI }} }}
  sref m = M }}"
        )
    };
    let refusal = |text: String, profile: Profile| {
        let e = export_files(vec![("m.rst".into(), text)], profile);
        let w = warnings(&e);
        w.into_iter().find(|w| w.contains("state machine C::m is not exported")).unwrap_or_default()
    };
    let exec_trigger = "initial i state S { } final f transition t { from i to S } transition u { from S to f exec }";
    assert_eq!(
        refusal(model(exec_trigger, "step()"), Profile::RoboTool3),
        "5:29: state machine C::m is not exported: the RoboSim operation `step` is not exported inside a machine: \
         it has an `exec`-triggered transition, which the export does not run inside a calling machine yet \
         (`robosim verify` does)"
    );
    let clock = "requires Clk initial i final f transition t { from i to f action #K }";
    assert_eq!(
        refusal(model(clock, "step()"), Profile::RoboTool3),
        "5:29: state machine C::m is not exported: the RoboSim operation `step` is not exported inside a machine: \
         it requires clocks (the machine's), which the export does not run inside a calling machine yet \
         (`robosim verify` does)"
    );
    let plain = "initial i final f transition t { from i to f action $move(1) }";
    assert!(refusal(model(plain, "step()"), Profile::Paper2019).ends_with(
        "the RoboSim operation `step` is not exported inside a machine: the paper2019 profile gives operations no \
         process of their own (Rules 1–13), so calls of them are not exported"
    ));
    assert_eq!(
        refusal(model(plain, "move(1)"), Profile::RoboTool3),
        "5:29: state machine C::m is not exported: `move(…)` in a RoboSim machine must be an output: `$move(…)`"
    );
    // Written as it must be, it is exported.
    assert_eq!(refusal(model(plain, "step()"), Profile::RoboTool3), "");
}

/// An event of both I/O contexts of a RoboSim machine is read from its
/// input register and written to its output register (as the native
/// checker reads it, and as RoboTool's reference `Communication` has
/// `broadcast`): both registers are declared, the machine's own write
/// and its controller's operation's go to `o_b` (the export used to
/// write `registerWrite.o_b` without declaring `o_b`). The paper2019
/// profile cannot name both registers.
#[test]
fn an_event_of_both_contexts_is_read_and_written() {
    let model = "interface E { event b : nat }
interface SoftI { notify() }
stm M { cycleDef cycle == 1 requires SoftI
  input context { uses E } output context { uses E }
  initial i state A { entry $b!1 ; exec ; notify() } final F
  transition t0 { from i to A } transition t1 { from A to F exec } }
controller C { cycleDef cycle == 1 uses E
  operation notify() { input context { } output context { uses E }
    initial j final f transition t { from j to f action $b!2 } }
  sref m = M }";
    // The paper's registers are `bU` both ways: refused, with the reason.
    let paper = export_files(vec![("m.rst".into(), model.into())], Profile::Paper2019);
    assert!(
        warnings(&paper).iter().any(|w| w.ends_with(
            "state machine M is not exported: `b` is an event of both I/O contexts: the paper2019 profile names its \
             input and output registers alike (`bU`), which CSPm cannot declare twice"
        )),
        "{:#?}",
        warnings(&paper)
    );
    let e = export_files(vec![("m.rst".into(), model.into())], Profile::RoboTool3);
    assert_eq!(warnings(&e), Vec::<String>::new());
    let defs = text(&e, "robosim_defs.csp");
    assert!(defs.contains("datatype InputRegister = i_b.Bool.core_nat\n"), "{defs}");
    assert!(defs.contains("datatype OutputRegister = o_b.core_nat\n"), "{defs}");
    let m = checked(&e, "main.csp", "InC__ = C::D__(0, 1)\nAlone__ = M::D__(0, 1)");
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let in_c = ev.lts("InC__").unwrap();
    let cycles = ["registerRead.i_b.false.0", "registerWrite.o_b.1", "endexec", "tock", "registerRead.i_b.true.2"];
    let second = ["registerWrite.o_b.2", "endexec", "tock"];
    let trace = own("C", &[&cycles[..], &second[..]].concat());
    assert!(!after(&in_c, &refs(&trace)).is_empty(), "{:?}", in_c.events);
    let alone = ev.lts("Alone__").unwrap();
    let second = ["M::notifyCall", "endexec", "tock"];
    let trace = own("M", &[&cycles[..], &second[..]].concat());
    assert!(!after(&alone, &refs(&trace)).is_empty(), "{:?}", alone.events);
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
}
