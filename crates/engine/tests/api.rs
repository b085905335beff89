//! What the engine's API promises that a verification fixture
//! (`test_data/verify`, run by `fixtures.rs`) cannot state: how options
//! are read and described, budgets that depend on the clock, and the
//! numbering of the events a lowering produces.

use std::time::Duration;

use robosim_engine::verify::{verify_texts, AsyncBuffer, Options, Semantics, Verdict};

fn buffer(text: &str) -> AsyncBuffer {
    AsyncBuffer::parse(text).expect("a buffer")
}

/// `--async-buffer` (robotool-facts.md RT-12): a size from 1 to 8 and an
/// optional policy; nothing else.
#[test]
fn buffer_assumptions_are_read_strictly() {
    assert_eq!(AsyncBuffer::parse("3"), Ok(AsyncBuffer { size: 3, overwrite: true }));
    assert_eq!(AsyncBuffer::parse("2:block"), Ok(AsyncBuffer { size: 2, overwrite: false }));
    for bad in ["0", "9:overwrite", "x", "1:drop", ""] {
        assert!(AsyncBuffer::parse(bad).is_err(), "{bad}");
    }
}

/// The note every report under a buffer assumption carries says whether it
/// is RoboTool's own buffer or one the user assumed.
#[test]
fn buffer_assumptions_are_described() {
    assert!(buffer("1:overwrite")
        .describe()
        .contains("buffer 1 value; when full, a new value replaces the oldest (RoboTool's default buffer)"));
    assert!(buffer("2:block").describe().ends_with(
        "when full, the sender waits (assumed with `--async-buffer`; RoboTool's default buffer is `1:overwrite`)"
    ));
}

/// A check whose time is up before it starts is inconclusive (or, on a
/// machine fast enough to finish before the first look at the clock,
/// decided); never a wrong verdict. (A spent state budget is the fixture
/// `reasons_spent_state_budget`.)
#[test]
fn a_spent_timeout_is_inconclusive() {
    let design = "interface I { event i op() }
        stm M { uses I requires I const k : nat initial i0 state S { entry op(); wait(1) }
          transition t { from i0 to S } transition u { from S to S } }
        controller C { uses I requires I sref m = M connection C on i to m on i }
        module Mod { robotic platform P { uses I provides I } cref c = C connection P on i to c on i }";
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }
        assertion A : S is schedulable with constant k of M set to 1 .";
    let mut opts = Options::default();
    opts.budget.timeout = Some(Duration::ZERO);
    let reports =
        verify_texts([("m.rct".to_string(), design.to_string()), ("a.rsa".to_string(), rsa.to_string())], &opts);
    let r = reports.iter().find(|r| r.semantics == Semantics::Timed).expect("the timed report");
    assert!(matches!(r.verdict, Verdict::Inconclusive | Verdict::Pass), "{:?}", r.verdict);
}

/// A RoboSim module reading the platform's `level` every cycle and raising
/// `alarm` at 2, its machine's input context extended with an event.
const WATCHER: &str = "package pi
    interface Pings { event ping : nat }
    interface Lvl { var level : nat }
    interface Out { var alarm : boolean }
    stm Watch {
      cycleDef cycle == 1
      input context { requires Lvl uses Pings }
      output context { requires Out }
      initial i
      state S { }
      transition t0 { from i to S }
      transition hi { from S to S exec condition $level >= 2 action $alarm = true }
      transition lo { from S to S exec condition $level < 2 }
    }
    controller C { cycleDef cycle == 1 requires Lvl requires Out sref w = Watch }
    module M { cycleDef cycle == 1 robotic platform P { provides Lvl provides Out } cref c = C }";

/// The register events a check numbers: a variable's read carries its value
/// alone, an event's its presence flag (and value); writes carry the value.
#[test]
fn register_events_of_variables() {
    use robosim_engine::lower::{lower_design, DomainDefaults};
    use robosim_engine::sched::Registers;
    let text = WATCHER.to_string();
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&db, [("w.rst".to_string(), text)], robosim_hir::RuleSet::Paper);
    let file = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model file");
    let path = ["pi".to_string(), "Watch".to_string()];
    let loc = robosim_hir::index::resolve_item(&db, ws, file, &path, |_| true)[0];
    let design = lower_design(&db, ws, loc, &[], &DomainDefaults::default()).expect("supported");
    let regs = Registers::new(&[&design], robosim_engine::verify::Profile::RoboTool3).expect("registers");
    let name = |e| regs.table.name(e).expect("a register event");
    assert_eq!(name(regs.read("level", true, Some(2)).expect("level")), "registerRead.i_level.2");
    assert_eq!(name(regs.read("ping", true, Some(1)).expect("ping")), "registerRead.i_ping.true.1");
    assert_eq!(name(regs.read("ping", false, Some(0)).expect("ping")), "registerRead.i_ping.false.0");
    assert_eq!(name(regs.write("alarm", &[1]).expect("alarm")), "registerWrite.o_alarm.true");
}
