//! Assertions whose specification is a `csp` block of the assertion file,
//! decided natively: the block's CSPm (with the model's names as RoboTool
//! spells them) compiled to an LTS and checked against the element's
//! native LTS, in the shapes real projects use — cycles of a machine's
//! events, time windows inside `Timed(OneStep)`, contracts `let PRE … within`.

use robosim_engine::verify::{trace_text, Report, Verdict};

mod support;
use support::csp::{outcome, MACHINES};

fn run(assertions: &str) -> Vec<Report> {
    support::csp::run(MACHINES, assertions)
}

fn report<'a>(reports: &'a [Report], name: &str) -> &'a Report {
    reports.iter().find(|r| r.name == name).unwrap_or_else(|| panic!("no report {name}"))
}

/// Traces refinement of a machine against a cycle of its events (time may
/// pass anywhere: `Timed(et)` with `et(_) = 0`), passing and failing, and
/// the constants a spec sees: their defaults, not the `with` override.
#[test]
fn a_machine_against_a_cycle_of_its_events() {
    let reports = run("timed csp Cycle csp-begin
et(_) = 0
Timed(et) {
  Cycle = p::M::go.in -> p::M::speed.out.const_p_M_k -> p::M::done.out -> Cycle
}
csp-end

timed csp NoSpeed csp-begin
Timed(et) {
  NoSpeed = p::M::go.in -> p::M::done.out -> NoSpeed
}
csp-end

timed assertion A1 : M refines Cycle in the traces model
timed assertion A2 : M refines NoSpeed in the traces model
timed assertion A3 : M refines Cycle in the traces model with constant k of M set to 1
timed assertion A4 : M does not refine NoSpeed in the traces model
");
    let a1 = report(&reports, "A1");
    assert_eq!(a1.verdict, Verdict::Pass, "{a1:#?}");
    assert_eq!(a1.reason.as_deref(), Some("M refines Cycle"));
    // The spec's own LTS, reported.
    assert!(a1.notes.iter().any(|n| n == "`Cycle` in `csp` block `Cycle` at line 5: 3 states"), "{:?}", a1.notes);

    let a2 = report(&reports, "A2");
    assert_eq!(outcome(a2), (Verdict::Fail, "trace: p::M::go.in p::M::speed.out.0".to_string()));
    let c = a2.counterexample.as_ref().unwrap();
    assert_eq!(c.explanation[0], "the model can perform `p::M::speed.out.0` where the specification cannot");
    assert_eq!(
        c.explanation[1],
        "the specification `NoSpeed` (`csp` block `NoSpeed` at line 11) after ⟨p::M::go.in, p::M::speed.out.0⟩ does not allow it"
    );
    // The model's steps are located in the model.
    assert!(c.steps.iter().any(|s| s.location.is_some()), "{:#?}", c.steps);

    // `with constant` binds inside the model only: the spec keeps k = 0.
    let a3 = report(&reports, "A3");
    assert_eq!(outcome(a3), (Verdict::Fail, "trace: p::M::go.in p::M::speed.out.1".to_string()));
    // A negated assertion that holds.
    assert_eq!(report(&reports, "A4").verdict, Verdict::Pass);
}

/// Time windows as FDR reads `Timed(OneStep)`: one `tock` after every
/// event. `Slow` waits a unit before `done` and after it; `Fast` does not.
#[test]
fn time_windows_inside_timed_one_step() {
    let reports = run("timed csp Window csp-begin
OneStep(_) = 1
Timed(OneStep) {
  Window = p::Slow::go.in -> p::Slow::done.out -> Window
  Quick = p::Fast::go.in -> p::Fast::done.out -> Quick
}
csp-end
timed csp Quick csp-begin
csp-end
timed assertion W1 : Slow refines Window in the traces model
timed assertion W2 : Fast refines Quick in the traces model
");
    assert_eq!(outcome(report(&reports, "W1")).0, Verdict::Pass, "{reports:#?}");
    // `Fast` answers without letting the unit pass.
    assert_eq!(outcome(report(&reports, "W2")), (Verdict::Fail, "trace: p::Fast::go.in p::Fast::done.out".to_string()));
}

/// A contract in the shape of the corpus's skill properties, in the
/// failures model: before `go`, anything but `go`; then `speed` or
/// `done`; then anything. Time passes anywhere (`tock` is in `All`).
#[test]
fn contracts_let_pre_within() {
    let reports = run("csp Events csp-begin
All = {| p::M::go, p::M::speed, p::M::done, tock |}
csp-end
csp Contract csp-begin
Contract = let
    PRE = |~| ev : diff(All, {p::M::go.in}) @ ev -> PRE
          |~| p::M::go.in -> CON
    CON = |~| ev : union({| p::M::speed.out |}, {tock}) @ ev -> CON
          |~| p::M::done.out -> POS
    POS = CHAOS(All)
  within PRE
csp-end
csp Eager csp-begin
Eager = p::M::go.in -> Eager [] tock -> Eager
csp-end
assertion C1 : M refines Contract in the failures model
assertion C2 : M refines Eager in the failures model
");
    assert_eq!(report(&reports, "C1").verdict, Verdict::Pass, "{reports:#?}");
    // `Eager` must always offer `go` or `tock`: after `go`, M refuses both
    // until it has spoken.
    let c2 = report(&reports, "C2");
    assert_eq!(c2.verdict, Verdict::Fail, "{c2:#?}");
    let c = c2.counterexample.as_ref().unwrap();
    assert_eq!(c.kind, "refusal", "{c:#?}");
    assert_eq!(trace_text(&c.steps), "p::M::go.in");
    assert_eq!(
        c.explanation[0],
        "the model can offer only {tock, p::M::speed.out.0}, where the specification, after the same trace, offers all of {tock, p::M::go.in}"
    );
}

/// What cannot be decided is said, never guessed: names RoboTool 3 does not
/// generate, values outside the model's domains, `Events` in a failures
/// check, CSPm on the implementation side.
#[test]
fn errors_are_reported_not_decided() {
    let reports = run("csp Old csp-begin
Old = M_go -> Old
csp-end
assertion E1 : M refines Old in the traces model
");
    let (v, why) = outcome(report(&reports, "E1"));
    assert_eq!(v, Verdict::Unsupported);
    assert!(
        why.contains("unresolved name") && why.contains("`M_go` is not defined") && why.contains("line 3"),
        "{why}"
    );

    let reports = run("csp Big csp-begin
Big = p::M::go.in -> p::M::speed.out.7 -> Big
csp-end
assertion E2 : M refines Big in the traces model
");
    let (v, why) = outcome(report(&reports, "E2"));
    assert_eq!(v, Verdict::Unsupported);
    assert_eq!(
        why,
        "`Big` in `csp` block `Big` at line 3: FDR stops with an error: the value `p::M::speed.out.7` is invalid as \
         it is not within the set of values defined for the channel `p::M::speed`; in particular its field 2 `7` is \
         not a member of the set {0, 1, 2} (the model's values: a value outside the model's domain)"
    );

    let reports = run("csp All csp-begin
All = RUN(Events)
csp-end
assertion E3 : M refines All in the failures model
assertion E4 : M refines All in the traces model
");
    let (v, why) = outcome(report(&reports, "E3"));
    assert_eq!(v, Verdict::Unsupported);
    assert!(why.contains("`Events`"), "{why}");
    assert_eq!(report(&reports, "E4").verdict, Verdict::Pass, "{reports:#?}");

    // RoboTool's tock-CSP library is loaded as RoboTool defines it
    // (`robosim_hir::csp_defs`): `Late` offers only `done`, within 2 units.
    let reports = run("timed csp Late csp-begin
Late = EDeadline(p::M::done.out, 2)
csp-end
timed assertion E5 : M refines Late in the traces model
");
    assert_eq!(outcome(report(&reports, "E5")), (Verdict::Fail, "trace: p::M::go.in".to_string()));
}

/// CSPm on the implementation side: a block that wraps the machine's
/// generated process (`p::M::O__(id__, constants)`) with hiding and
/// renaming; the process is the machine's native LTS.
#[test]
fn wrappers_of_generated_processes() {
    let reports = run("timed csp Cycle csp-begin
et(_) = 0
Timed(et) {
  Cycle = p::M::go.in -> p::M::speed.out.const_p_M_k -> p::M::done.out -> Cycle
}
csp-end
timed csp NoSpeed csp-begin
Timed(et) {
  NoSpeed = p::M::go.in -> p::M::done.out -> NoSpeed
}
csp-end
timed csp Other csp-begin
Timed(et) {
  Other = p::Fast::go.in -> p::Fast::done.out -> Other
}
csp-end
csp Same csp-begin
Same = p::M::O__(0, const_p_M_k)
csp-end
csp Quiet csp-begin
Quiet = p::M::O__(1, const_p_M_k) \\ {| p::M::speed |}
csp-end
csp Renamed csp-begin
Renamed = Quiet [[ p::M::go.in <- p::Fast::go.in, p::M::done.out <- p::Fast::done.out ]]
csp-end
csp Bound csp-begin
Bound = p::M::O__(0, 2)
csp-end
timed assertion I1 : M equals Same
timed assertion I2 : Quiet refines NoSpeed in the traces model
timed assertion I3 : Quiet refines Cycle in the traces model
timed assertion I4 : Renamed refines Other in the traces model
timed assertion I5 : Same refines Cycle in the failures model
timed assertion I6 : Bound refines Cycle in the traces model
");
    // The generated process is the machine itself, both ways.
    assert_eq!(outcome(report(&reports, "I1")).0, Verdict::Pass, "{reports:#?}");
    assert_eq!(outcome(report(&reports, "I2")).0, Verdict::Pass, "{reports:#?}");
    assert_eq!(outcome(report(&reports, "I3")), (Verdict::Fail, "trace: p::M::go.in p::M::done.out".to_string()));
    assert_eq!(outcome(report(&reports, "I4")).0, Verdict::Pass, "{reports:#?}");
    assert_eq!(outcome(report(&reports, "I5")).0, Verdict::Pass, "{reports:#?}");
    let (v, why) = outcome(report(&reports, "I6"));
    assert_eq!(v, Verdict::Unsupported);
    assert!(why.contains("constant values other than the model's (0)"), "{why}");
}

/// A record-valued constant given to the generated process
/// (`p::R::O__(0, const_p_R_z)`): its value is RoboTool's default record
/// (RT-1: each field's default, `(| x = 0, y = 0 |)`), the one the native
/// LTS was compiled with, so the application is the machine itself; the
/// verdict's notes show the record by its fields, not by its code.
#[test]
fn record_constants_of_generated_processes() {
    let model = "package p
interface I { event go event out : V }
datatype V { x : nat y : nat }
stm R {
  uses I
  const z : V
  initial i
  state A { }
  transition t0 { from i to A }
  transition t1 { from A to A trigger go action out!z }
}
";
    let reports = support::csp::run(
        model,
        "csp Same csp-begin
Same = p::R::O__(0, const_p_R_z)
csp-end
timed assertion I1 : R equals Same
timed assertion D : R is deadlock-free
",
    );
    assert_eq!(outcome(report(&reports, "I1")).0, Verdict::Pass, "{reports:#?}");
    let d = report(&reports, "D");
    assert_eq!(d.verdict, Verdict::Pass, "{d:#?}");
    let notes = d.notes.join("\n");
    assert!(notes.contains("R::z = (| x = 0, y = 0 |)"), "{notes}");
    assert!(notes.contains("constant R::z = (| x = 0, y = 0 |) (RT-1)"), "{notes}");
}
