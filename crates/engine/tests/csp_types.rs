//! `csp` blocks over the model's structured values and RoboTool's
//! generated defaults, in the shapes of the corpus's properties: events
//! carrying a tuple whose component is a record (the skill properties of
//! roboarch-examples' `exploreVOut : Velocities * nat`), a function
//! declared without a body that returns a tuple (RT-2, remote
//! inspection's `waypoint_inverse`), `RUN(Events)` in the traces model,
//! and an input set with a value outside the channel's type.

use robosim_engine::verify::{trace_text, verify_texts, Options, Report, Verdict};

/// `M` learns a priority `k` (`prio`), and on each `go` sets the field `a`
/// of its record `v` (default `(| a = 0, b = 0 |)`) to 1 and sends
/// `out!(| v, k |)`: a tuple whose first component is the record.
const SKILL: &str = "package p
record V {
  a : nat
  b : nat
}
interface I { event go event prio : nat event out : V * nat }
stm M {
  uses I
  var v : V
  var k : nat
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B trigger prio?k }
  transition t2 { from B to B trigger go action v.a = 1 ; out!(| v, k |) }
  transition t3 { from B to B trigger prio?k }
}
";

/// `W` receives a position `at?pos` and says `far` unless `pos` is
/// `home(1)`; `home` has no body, so (no `Instantiations` block replacing
/// RoboTool's generated ones) it returns `(0, 0)` (RT-2).
const PLACES: &str = "package q
function home(n : nat) : nat * nat { }
interface J { event at : nat * nat event far }
stm W {
  uses J
  var pos : nat * nat
  initial i
  state A { }
  junction j
  transition t0 { from i to A }
  transition t1 { from A to j trigger at?pos }
  transition t2 { from j to A condition pos == home(1) }
  transition t3 { from j to A condition pos != home(1) action far }
}
";

fn run(model: &str, package: &str, assertions: &str) -> Vec<Report> {
    verify_texts(
        [
            ("m.rct".to_string(), model.to_string()),
            ("a.assertions".to_string(), format!("import {package}::*\n{assertions}")),
        ],
        &Options::default(),
    )
}

fn report<'a>(reports: &'a [Report], name: &str) -> &'a Report {
    reports.iter().find(|r| r.name == name).unwrap_or_else(|| panic!("no report {name}"))
}

/// The verdict and the counterexample's trace (or the reason).
fn outcome(r: &Report) -> (Verdict, String) {
    let cex = r.counterexample.as_ref().map(|c| format!("{}: {}", c.kind, trace_text(&c.steps)));
    (r.verdict, cex.unwrap_or_else(|| r.reason.clone().unwrap_or_default()))
}

/// RoboTool's CSPm gives `out` the type `p_V * core_nat`, a record being
/// the tuple of its fields: the event `M` sends is
/// `p::M::out.out.((1, 0), k)`. A spec that ranges over the record type
/// (`w <- p_V`, as EBS6 does with `Types_Velocities`) with the priority
/// last received holds (FDR: `[T=` passes, every `out` carries the last
/// `prio`); one that expects priority 0 fails at the first `out` after a
/// non-zero `prio`, and one that expects the record `(0, 0)` fails at
/// the first `out`, since `v.a = 1` ran before it. Time passes anywhere
/// in the specs (`Timed(et)` with `et(_) = 0`), as it does in the model.
#[test]
fn events_carrying_a_tuple_with_a_record() {
    let reports = run(
        SKILL,
        "p",
        "timed csp Prio csp-begin
et(_) = 0
Timed(et) {
  Prio = p::M::prio.in?x -> Con(x)
  Con(x) = p::M::prio.in?y -> Con(y)
    [] p::M::go.in -> |~| ev : { p::M::out.out.(w, x) | w <- p_V } @ ev -> Con(x)
  Zero = p::M::prio.in?x -> ZCon
  ZCon = p::M::prio.in?y -> ZCon [] p::M::go.in -> ([] w : p_V @ p::M::out.out.(w, 0) -> ZCon)
  Fresh = p::M::prio.in?x -> FCon(x)
  FCon(x) = p::M::prio.in?y -> FCon(y) [] p::M::go.in -> p::M::out.out.((0, 0), x) -> FCon(x)
}
csp-end
timed csp Zero csp-begin
csp-end
timed csp Fresh csp-begin
csp-end
timed assertion T1 : M refines Prio in the traces model
timed assertion T2 : M refines Zero in the traces model
timed assertion T3 : M refines Fresh in the traces model
",
    );
    assert_eq!(report(&reports, "T1").verdict, Verdict::Pass, "{reports:#?}");
    assert_eq!(
        outcome(report(&reports, "T2")),
        (Verdict::Fail, "trace: p::M::prio.in.1 p::M::go.in p::M::out.out.((1, 0), 1)".to_string())
    );
    assert_eq!(
        outcome(report(&reports, "T3")),
        (Verdict::Fail, "trace: p::M::prio.in.0 p::M::go.in p::M::out.out.((1, 0), 0)".to_string())
    );
}

/// The corpus's untimed skill contracts (EBS1–6, EBCS1) are read in the
/// timed semantics too (RT-8), where the machine lets time pass before its
/// first event and the contract, which never mentions `tock`, does not:
/// FDR's `[F=` fails on the trace ⟨tock⟩.
#[test]
fn an_untimed_contract_in_the_timed_semantics() {
    let reports = run(
        SKILL,
        "p",
        "csp Contract csp-begin
All = {| p::M::go, p::M::prio, p::M::out |}
Contract = [] ev : {| p::M::prio.in |} @ ev -> CHAOS(All)
csp-end
assertion C1 : M refines Contract in the failures model
",
    );
    let c1 = report(&reports, "C1");
    assert_eq!(outcome(c1), (Verdict::Fail, "trace: tock".to_string()));
    assert_eq!(
        c1.counterexample.as_ref().unwrap().explanation[0],
        "the model can perform `tock` where the specification cannot"
    );
}

/// `home(1)` is `(0, 0)` (RT-2): `far` follows every position but the
/// origin, so `Far` holds (FDR: `[T=` passes) and `Near`, which puts the
/// exception at `(0, 1)`, fails at the origin. `RUN(Events)` after the first event accepts anything in the
/// traces model; before it, an untimed spec refuses `tock` (TestReq, RL).
#[test]
fn a_bodiless_function_returning_a_tuple_and_run_events() {
    let reports = run(
        PLACES,
        "q",
        "timed csp Far csp-begin
et(_) = 0
Timed(et) {
  Far = q::W::at.in?(x, y) -> (if (x, y) == (0, 0) then Far else q::W::far.out -> Far)
  Near = q::W::at.in?(x, y) -> (if (x, y) == (0, 1) then Near else q::W::far.out -> Near)
  Start = q::W::at.in?p -> RUN(Events)
}
csp-end
timed csp Near csp-begin
csp-end
timed csp Start csp-begin
csp-end
csp Untimed csp-begin
Untimed = q::W::at.in?p -> RUN(Events)
csp-end
timed assertion F1 : W refines Far in the traces model
timed assertion F2 : W refines Near in the traces model
timed assertion F3 : W refines Start in the traces model
timed assertion F4 : W refines Untimed in the traces model
",
    );
    assert_eq!(report(&reports, "F1").verdict, Verdict::Pass, "{reports:#?}");
    // `Near` wants `far` after the origin; `W` stays quiet there and takes
    // the next position, which `Near` refuses.
    assert_eq!(
        outcome(report(&reports, "F2")),
        (Verdict::Fail, "trace: q::W::at.in.(0, 0) q::W::at.in.(0, 0)".to_string())
    );
    let f3 = report(&reports, "F3");
    assert_eq!(f3.verdict, Verdict::Pass, "{f3:#?}");
    assert!(f3.notes.iter().any(|n| n.starts_with("`Events` is read as the events of the element's own channels")));
    assert_eq!(outcome(report(&reports, "F4")), (Verdict::Fail, "trace: tock".to_string()));
}

/// An input set with a value outside the channel's type (RadiationMonitor
/// in remote inspection: `?reading:({60, 100})` where `core_real` stops
/// below 100): FDR's evaluator stops with an error on the event, so there
/// is no verdict; the bridge says which value, and `Events` used other
/// than as `RUN(Events)` is every channel's, as in RoboTool's script.
#[test]
fn a_value_outside_the_type_is_an_error() {
    let reports = run(
        PLACES,
        "q",
        "csp Big csp-begin
Big = q::W::at.in?p:({(0, 0), (0, 7)}) -> RUN(Events)
csp-end
csp Hidden csp-begin
Hidden = (q::W::at.in?p -> RUN(Events)) \\ {| q::W::far |}
csp-end
timed assertion B1 : W refines Big in the traces model
timed assertion B2 : W refines Hidden in the traces model
",
    );
    let (v, why) = outcome(report(&reports, "B1"));
    assert_eq!(v, Verdict::Unsupported);
    assert_eq!(
        why,
        "`Big` in `csp` block `Big` at line 3: FDR stops with an error: the value `q::W::at.in.(0, 7)` is invalid \
         as it is not within the set of values defined for the channel `q::W::at`; in particular its field 2 `(0, 7)` \
         is not a member of the set {(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2), (2, 0), (2, 1), (2, 2)} (the \
         model's values: a value outside the model's domain)"
    );
    // Hiding: `Events` is read in full (both machines' channels), and the
    // model's first `tock` is refused all the same.
    let b2 = report(&reports, "B2");
    assert_eq!(outcome(b2), (Verdict::Fail, "trace: tock".to_string()));
    assert!(!b2.notes.iter().any(|n| n.starts_with("`Events` is read as")), "{:?}", b2.notes);
}

/// `N` collects the literals it is given (`pick?l`) and says the set so
/// far: `chosen : Set(L)` carries a set of RoboTool's constructors
/// (`{s_L_X}`), as in the skills manager's `activeSkills : Set(Skills)`.
const SETS: &str = "package s
enumeration L { X Y }
interface K { event pick : L event chosen : Set(L) }
stm N {
  uses K
  var c : Set(L)
  var l : L
  initial i
  state A { }
  transition t0 { from i to A }
  transition t1 { from A to A trigger pick?l action c = union(c, {l}) ; chosen!c }
}
";

/// The block reads `Set(L)`'s values (every subset of `{s_L_X, s_L_Y}`),
/// and events carry sets both ways: N outputs the union of what it picked,
/// as Grow does (S1 passes); Last outputs only the last pick, which N does
/// not after picking `X` then `Y` (S2 fails there).
#[test]
fn events_carrying_a_set() {
    let reports = run(
        SETS,
        "s",
        "timed csp Grow csp-begin
et(_) = 0
Timed(et) {
  Grow = G({})
  G(c) = s::N::pick.in?l -> s::N::chosen.out!union(c, {l}) -> G(union(c, {l}))
}
csp-end
timed csp Last csp-begin
Timed(et) {
  Last = s::N::pick.in?l -> s::N::chosen.out!{l} -> Last
}
csp-end
timed assertion S1 : N refines Grow in the traces model
timed assertion S2 : N refines Last in the traces model
",
    );
    assert_eq!(report(&reports, "S1").verdict, Verdict::Pass);
    let s2 = report(&reports, "S2");
    assert_eq!(s2.verdict, Verdict::Fail);
    let trace = s2.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default();
    assert_eq!(
        trace,
        "s::N::pick.in.s_L_X s::N::chosen.out.{s_L_X} s::N::pick.in.s_L_Y s::N::chosen.out.{s_L_X, s_L_Y}"
    );
}
