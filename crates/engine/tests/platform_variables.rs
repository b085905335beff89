//! Variables of the robotic platform (paper §5.2, Rules 1, 2 and 8:
//! "platform variables are outputs of the robotic system … any update to
//! such a variable is visible"). In a RoboChart module, an assignment to a
//! variable the platform provides is the visible update `set_x.v`, urgent
//! (the platform cannot refuse it), and the new value is what every machine
//! reads; under the simulation assumptions it is written to the register
//! `registerWrite.o_x.v`, at most once per period. In RoboSim, a variable
//! required in the output context is written the same way (`$x = e`), and
//! one required in the input context is read from its register at the start
//! of every cycle (`registerRead.i_x.v`, no presence flag).

use robosim_engine::verify::{trace_text, Counterexample, Options, Profile, Report, Verdict};

#[path = "support/timed.rs"]
mod timed;
use timed::verify_workspace;

fn verify(files: &[(&str, &str)], profile: Profile) -> Vec<Report> {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        files.iter().map(|(p, t)| (p.to_string(), t.to_string())),
        robosim_hir::RuleSet::Paper,
    );
    let reports = verify_workspace(&db, ws, &Options { profile, ..Options::default() }, None);
    for r in &reports {
        println!("{} {:?} {} {:?}", r.name, r.verdict, r.stats.states, r.reason);
        if let Some(cx) = &r.counterexample {
            println!("  {}", trace_text(&cx.steps));
            println!("  {:?}", cx.explanation);
        }
    }
    reports
}

/// (name, verdict, states) of each report.
fn verdicts(reports: &[Report]) -> Vec<(String, Verdict, u64)> {
    reports.iter().map(|r| (r.name.clone(), r.verdict, r.stats.states)).collect()
}

fn expect(reports: &[Report], expected: &[(&str, Verdict, u64)]) {
    let expected: Vec<(String, Verdict, u64)> = expected.iter().map(|(n, v, s)| (n.to_string(), *v, *s)).collect();
    assert_eq!(verdicts(reports), expected);
}

/// `report`'s counterexample, after checking its trace and its one-line
/// explanation.
fn counterexample<'r>(report: &'r Report, trace: &str, explanation: &str) -> &'r Counterexample {
    let cx = report.counterexample.as_ref().unwrap_or_else(|| panic!("{}: no counterexample", report.name));
    assert_eq!(trace_text(&cx.steps), trace, "{}", report.name);
    assert_eq!(cx.explanation, [explanation], "{}", report.name);
    cx
}

/// A design whose machine `Setter` sets the platform's `speed` on entering
/// each of its states, and with `reader` (transitions from `W`, empty for
/// none), a machine `Reader` that reads it and may report it.
fn design(setter_entries: (&str, &str), reader: &str) -> String {
    let (reader_machine, sref, ops) = if reader.is_empty() {
        (String::new(), "", "")
    } else {
        (
            format!(
                "stm Reader {{
                   requires PV requires Ops
                   initial i state W {{ }} state R {{ }}
                   transition t0 {{ from i to W }}
                   {reader}
                 }}"
            ),
            "sref r = Reader",
            "provides Ops",
        )
    };
    let requires_ops = if reader.is_empty() { "" } else { "requires Ops" };
    format!(
        "package pd
         interface PV {{ var speed : nat }}
         interface Sen {{ event obstacle }}
         interface Ops {{ report(v : nat) }}
         stm Setter {{
           requires PV uses Sen
           initial i
           state A {{ entry {} }}
           state B {{ entry {} }}
           transition t0 {{ from i to A }}
           transition t1 {{ from A to B trigger obstacle }}
           transition t2 {{ from B to A trigger obstacle }}
         }}
         {reader_machine}
         controller C {{ requires PV {requires_ops} uses Sen sref s = Setter {sref}
           connection C on obstacle to s on obstacle }}
         module Mod {{ robotic platform P {{ provides PV {ops} uses Sen }} cref c = C
           connection P on obstacle to c on obstacle ( _async ) }}",
        setter_entries.0, setter_entries.1
    )
}

const NO_READER: &str = "";

/// The simulation of [`design`] with `NO_READER` and entries that wait a
/// cycle: `$speed` is written on entering A and B (`values`).
fn simulation(values: (u32, u32)) -> String {
    format!(
        "package ps
         interface PV {{ var speed : nat }}
         interface Sen {{ event obstacle }}
         stm SSetter {{
           cycleDef cycle == 1
           input context {{ uses Sen }}
           output context {{ requires PV }}
           initial i
           state A {{ entry $speed = {} ; exec }}
           state AW {{ }}
           state B {{ entry $speed = {} ; exec }}
           state BW {{ }}
           transition t0 {{ from i to A }}
           transition a {{ from A to AW }}
           transition a1 {{ from AW to B condition $obstacle }}
           transition a2 {{ from AW to AW exec condition not $obstacle }}
           transition b {{ from B to BW }}
           transition b1 {{ from BW to A condition $obstacle }}
           transition b2 {{ from BW to BW exec condition not $obstacle }}
         }}
         controller SC {{ cycleDef cycle == 1 uses Sen requires PV sref s = SSetter
           connection SC on obstacle to s on obstacle }}
         module SMod {{ cycleDef cycle == 1 robotic platform P {{ provides PV uses Sen }} cref c = SC
           connection P on obstacle to c on obstacle ( _async ) }}",
        values.0, values.1
    )
}

const SOUNDNESS: &str = "simulation S of pd::Mod { cycleDef cycle == 1 }
    assertion A : S is schedulable
    assertion R : ps::SMod refines S in the failures divergences model
    assertion C : S refines ps::SMod in the failures divergences model
    assertion D : ps::SMod is deadlock-free";

#[test]
fn two_updates_in_one_cycle_cannot_be_scheduled() {
    // Setting `speed` on entry, then reacting to an obstacle read in the same
    // cycle, updates it twice in one period: a simulation writes each
    // register once per cycle, and the update cannot wait.
    let d = design(("speed = 1", "speed = 2"), NO_READER);
    let reports = verify(
        &[("d.rct", &d), ("a.rsa", "simulation S of pd::Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable")],
        Profile::RoboTool3,
    );
    expect(&reports, &[("A", Verdict::Fail, 10)]);
    let cx = counterexample(
        &reports[0],
        "registerRead.i_obstacle.true (set_speed.1) registerWrite.o_speed.1 (obstacle.in)",
        "c::s (in B) must set speed = 2 now (updates of platform variables cannot be delayed), but `speed` was \
         already written in this cycle (one write per output per cycle)",
    );
    // The stuck point is B's entry action.
    let at = &cx.stuck_at[0];
    assert_eq!(&d[usize::from(at.range.start())..usize::from(at.range.end())], "speed = 2");
}

#[test]
fn other_machines_read_the_value_set() {
    // Reader leaves W only once `speed` is 2, which Setter sets in B.
    let d = design(
        ("speed = 1 ; wait(1)", "speed = 2 ; wait(1)"),
        "transition t1 { from W to R condition speed == 2 action report(speed) }",
    );
    let rsa = "assertion Q : c::r::R is reachable in pd::Mod
        assertion N : pd::Mod is deadlock-free";
    let reports = verify(&[("d.rct", &d), ("a.rsa", rsa)], Profile::RoboTool3);
    expect(&reports, &[("Q", Verdict::Pass, 7), ("N", Verdict::Pass, 12)]);
    let q = reports[0].counterexample.as_ref().expect("a trace to R");
    assert_eq!(trace_text(&q.steps), "set_speed.1 tock obstacle.in set_speed.2 reportCall.2");
    // Never set to 2: R is out of reach.
    let d =
        design(("speed = 1 ; wait(1)", "speed = 1 ; wait(1)"), "transition t1 { from W to R condition speed == 2 }");
    let reports = verify(&[("d.rct", &d), ("a.rsa", rsa)], Profile::RoboTool3);
    assert_eq!(reports[0].verdict, Verdict::Fail);
}

#[test]
fn a_simulation_writing_the_variable_is_sound() {
    let d = design(("speed = 1 ; wait(1)", "speed = 2 ; wait(1)"), NO_READER);
    let s = simulation((1, 2));
    let files = [("d.rct", d.as_str()), ("s.rst", s.as_str()), ("a.rsa", SOUNDNESS)];
    let reports = verify(&files, Profile::RoboTool3);
    expect(
        &reports,
        &[("A", Verdict::Pass, 23), ("R", Verdict::Pass, 38), ("C", Verdict::Pass, 38), ("D", Verdict::Pass, 31)],
    );
    let reports = verify(&files, Profile::Paper2019);
    expect(
        &reports,
        &[("A", Verdict::Pass, 30), ("R", Verdict::Pass, 54), ("C", Verdict::Pass, 45), ("D", Verdict::Pass, 43)],
    );
}

#[test]
fn a_simulation_writing_a_wrong_value_is_not_sound() {
    let d = design(("speed = 1 ; wait(1)", "speed = 2 ; wait(1)"), NO_READER);
    let s = simulation((1, 1));
    let reports = verify(&[("d.rct", &d), ("s.rst", &s), ("a.rsa", SOUNDNESS)], Profile::RoboTool3);
    expect(
        &reports,
        &[("A", Verdict::Pass, 23), ("R", Verdict::Fail, 13), ("C", Verdict::Fail, 16), ("D", Verdict::Pass, 31)],
    );
    counterexample(
        &reports[1],
        "registerRead.i_obstacle.true registerWrite.o_speed.1 tock registerRead.i_obstacle.true",
        "the implementation refuses every event the specification must offer: one of {registerWrite.o_speed.2}",
    );
}

/// A RoboSim module reading the platform's `level` every cycle and raising
/// `alarm` at `threshold`.
fn watcher(package: &str, threshold: u32) -> String {
    format!(
        "package {package}
         interface Lvl {{ var level : nat }}
         interface Out {{ var alarm : boolean }}
         stm Watch {{
           cycleDef cycle == 1
           input context {{ requires Lvl }}
           output context {{ requires Out }}
           initial i
           state S {{ }}
           transition t0 {{ from i to S }}
           transition hi {{ from S to S exec condition $level >= {threshold} action $alarm = true }}
           transition lo {{ from S to S exec condition $level < {threshold} }}
         }}
         controller C {{ cycleDef cycle == 1 requires Lvl requires Out sref w = Watch }}
         module M {{ cycleDef cycle == 1 robotic platform P {{ provides Lvl provides Out }} cref c = C }}"
    )
}

#[test]
fn robosim_input_variables_are_read_every_cycle() {
    let a = watcher("pi", 2);
    let b = watcher("pj", 1);
    let rsa = "assertion D : pi::M is deadlock-free
        assertion T : pi::M is deterministic
        assertion R : pj::M refines pi::M in the traces model
        assertion E : pi::M refines pi::M in the failures divergences model";
    let reports = verify(&[("a.rst", &a), ("b.rst", &b), ("a.rsa", rsa)], Profile::RoboTool3);
    // `alarm` is never initialised: its memory starts true (RT-4).
    expect(
        &reports,
        &[("D", Verdict::Pass, 25), ("T", Verdict::Pass, 19), ("R", Verdict::Fail, 22), ("E", Verdict::Pass, 28)],
    );
    // Level 1 raises the alarm of `pj` only; the action of an exec
    // transition runs after the next cycle's reads.
    let r = reports[2].counterexample.as_ref().expect("R's counterexample");
    assert_eq!(trace_text(&r.steps), "registerRead.i_level.1 tock registerRead.i_level.0 registerWrite.o_alarm.true");
}

#[test]
fn unsupported_uses_of_platform_variables_say_why() {
    // A RoboSim machine's own `requires` of a variable (RS:SM4), writing an
    // input, and receiving into a platform variable.
    let own = watcher("pi", 2).replace("input context { requires Lvl }", "requires Lvl input context { }");
    let write_input = watcher("pi", 2).replace("$alarm = true", "$level = 1");
    let receive = design(("obstacle?speed", "skip"), NO_READER).replace("event obstacle", "event obstacle : nat");
    for (text, file, why) in [
        (own.as_str(), "m.rst", "required by the machine itself"),
        (write_input.as_str(), "m.rst", "`level` is an input of the machine"),
        (receive.as_str(), "m.rct", "receiving into `speed`"),
    ] {
        let element = if file == "m.rst" { "pi::M" } else { "pd::Mod" };
        let rsa = format!("assertion D : {element} is deadlock-free");
        let reports = verify(&[(file, text), ("a.rsa", &rsa)], Profile::RoboTool3);
        assert_eq!(reports[0].verdict, Verdict::Unsupported);
        let reason = reports[0].reason.clone().unwrap_or_default();
        assert!(reason.contains(why), "{reason}");
    }
}

/// The register events a check numbers: a variable's read carries its value
/// alone, an event's its presence flag (and value); writes carry the value.
#[test]
fn register_events_of_variables() {
    use robosim_engine::lower::{lower_design, DomainDefaults};
    use robosim_engine::sched::Registers;
    let text = watcher("pi", 2).replace("interface Out {", "interface Pings { event ping : nat } interface Out {");
    let text = text.replace("input context { requires Lvl }", "input context { requires Lvl uses Pings }");
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&db, [("w.rst".to_string(), text)], robosim_hir::RuleSet::Paper);
    let file = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model file");
    let path = ["pi".to_string(), "Watch".to_string()];
    let loc = robosim_hir::index::resolve_item(&db, ws, file, &path, |_| true)[0];
    let design = lower_design(&db, ws, loc, &[], &DomainDefaults::default()).expect("supported");
    let regs = Registers::new(&[&design], Profile::RoboTool3).expect("registers");
    let name = |e| regs.table.name(e).expect("a register event");
    assert_eq!(name(regs.read("level", true, Some(2)).expect("level")), "registerRead.i_level.2");
    assert_eq!(name(regs.read("ping", true, Some(1)).expect("ping")), "registerRead.i_ping.true.1");
    assert_eq!(name(regs.read("ping", false, Some(0)).expect("ping")), "registerRead.i_ping.false.0");
    assert_eq!(name(regs.write("alarm", &[1]).expect("alarm")), "registerWrite.o_alarm.true");
}
