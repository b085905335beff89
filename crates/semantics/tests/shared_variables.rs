//! RT-16 in the export: a variable a controller provides to several
//! machines lives in the controller's memory; a machine's write is
//! forwarded to every other machine's own copy by hidden steps, one
//! machine after another, and a machine reads its own copy, so it may see
//! the old value meanwhile. The exported CSPm is loaded and run by our
//! evaluator (the engine's cross-check, `export_semantics.rs`, compares it
//! with `robosim verify` on the fixtures `rt16_*`, `rt18_race_after_time`,
//! `schedulability_shared_variables` and `platform_variables_*`).

use robosim_cspm::{Evaluator, Label, Limits, Lts, Module, NoNames};
use robosim_semantics::{export_workspace, Export, Options, OutFile};

/// `p` writes 1 into `x`, then sends `o` to `q` and `o2` to `r`, which
/// report the value of their copy on `seen` and `heard`.
const MODEL: &str = "interface I { event o event o2 event seen : nat event heard : nat }
interface V { var x : nat }
stm P { uses I requires V initial i state S { entry x = 1 ; o ; o2 } transition t { from i to S } }
stm Q { uses I requires V initial i state S { } state T { entry seen!x }
  transition t { from i to S } transition u { from S to T trigger o } }
stm R { uses I requires V initial i state S { } state T { entry heard!x }
  transition t { from i to S } transition u { from S to T trigger o2 } }
controller C { uses I var x : nat sref p = P sref q = Q sref r = R
  connection p on o to q on o connection p on o2 to r on o2
  connection q on seen to C on seen connection r on heard to C on heard }
";

/// The export of `model`, which is well-formed (RoboTool generates CSPm
/// only for models it accepts).
fn export(model: &str) -> Export {
    export_checked(model, true)
}

/// The export of `model`, well-formed if `well_formed`.
fn export_checked(model: &str, well_formed: bool) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws =
        robosim_hir::load_workspace(&mut db, [("m.rct".to_string(), model.to_string())], robosim_hir::RuleSet::Paper);
    let errors: Vec<String> = ws
        .files(&db)
        .iter()
        .flat_map(|&f| robosim_hir::file_diagnostics(&db, ws, f))
        .filter(|d| d.severity == robosim_hir::Severity::Error)
        .map(|d| format!("{} {}", d.code, d.message))
        .collect();
    assert_eq!(errors.is_empty(), well_formed, "{errors:?}\n{model}");
    export_workspace(&db, ws, &Options::default())
}

/// The definitions of `files` (the scripts left out), loaded without an
/// error.
fn load(files: &[OutFile]) -> Module {
    let text: String = files.iter().map(|f| f.text()).filter(|t| !t.contains("\ninclude \"")).collect();
    let m = Module::check(&text, &NoNames);
    assert!(m.is_ok(), "{:?}\n{text}", m.diagnostics());
    m
}

fn lts(m: &Module, process: &str) -> Lts {
    let mut ev = Evaluator::new(m, &NoNames, Limits::default());
    ev.eval_text(process).and_then(|p| ev.lts_of(&p)).unwrap_or_else(|d| panic!("{process}: {}", d.message))
}

/// The text of the file holding `what` in `files`.
fn text_of(files: &[OutFile], what: &str) -> String {
    files.iter().map(|f| f.text()).find(|t| t.contains(what)).unwrap_or_else(|| panic!("no {what}"))
}

#[test]
fn the_controller_forwards_each_write_to_the_other_machines_one_after_another() {
    let e = export(MODEL);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    for (files, tock) in [(&e.files, " [] tock -> Memory__x"), (&e.untimed, "")] {
        let problems = robosim_semantics::lint::check(files);
        assert!(problems.is_empty(), "{problems:#?}");
        let t = text_of(files, "RoboChart controller C");
        let flat: String = t.split_whitespace().collect::<Vec<_>>().join(" ");
        // Each machine's write, then the others' copies in order.
        let memory = format!(
            "Memory__x = C::p::set_x?w__ -> C::q::set_EXT_x!w__ -> C::r::set_EXT_x!w__ -> Memory__x \
             [] C::q::set_x?w__ -> C::p::set_EXT_x!w__ -> C::r::set_EXT_x!w__ -> Memory__x \
             [] C::r::set_x?w__ -> C::p::set_EXT_x!w__ -> C::q::set_EXT_x!w__ -> Memory__x{tock} [] terminate -> SKIP"
        );
        assert!(flat.contains(&memory), "{memory}\n{t}");
        // The machines with their writes visible, the memory's channels hidden.
        for m in ["p", "q", "r"] {
            assert!(flat.contains(&format!("C::{m}::DS__(id__)")), "{t}");
            assert!(flat.contains(&format!("C::{m}::set_x, C::{m}::set_EXT_x")), "{t}");
        }
        // A machine's own module: its writes and its copy's updates exported.
        let p = text_of(files, "RoboChart state machine C::p");
        assert!(p.contains("channel set_x, set_EXT_x : core_nat"), "{p}");
        assert!(p.contains("set_EXT_x?v__ -> Memory__(v__)"), "{p}");
    }
}

#[test]
fn timed_a_machine_may_read_its_old_copy_until_the_write_reaches_it() {
    let e = export(MODEL);
    let m = load(&e.files);
    let d = lts(&m, "C::D__(0)");
    // `q` and `r` see 1, or 0 while the write is still on its way; all
    // before time passes (the forwarding is urgent).
    for trace in [
        &["C::seen.out.1", "C::heard.out.1"][..],
        &["C::seen.out.0", "C::heard.out.0"],
        &["C::seen.out.0", "C::heard.out.1"],
        &["C::heard.out.1", "C::seen.out.0"],
        &["C::heard.out.0", "C::seen.out.1"],
    ] {
        assert!(d.has_trace(trace), "{trace:?}");
    }
    // On its own, a machine keeps its variable: nothing visible of it.
    let p = lts(&m, "C::p::D__(0)");
    let visible = |e: &str| {
        let e = p.event(e);
        p.transitions.iter().flatten().any(|(l, _)| e.is_some_and(|e| *l == Label::Event(e)))
    };
    assert!(visible("C::p::o.out"));
    assert!(!visible("C::p::set_x.1") && !visible("C::p::set_EXT_x.0"), "{:?}", p.events);
}

#[test]
fn untimed_the_same_interleavings() {
    let e = export(MODEL);
    let m = load(&e.untimed);
    let d = lts(&m, "C::D__(0)");
    for trace in [&["C::seen.out.1", "C::heard.out.1"][..], &["C::seen.out.0", "C::heard.out.0"]] {
        assert!(d.has_trace(trace), "{trace:?}");
    }
}

/// What `robosim verify` refuses, refused with its reasons; receiving into
/// a shared variable, which it no longer refuses, exported.
#[test]
fn two_types_and_two_initial_values_are_refused() {
    let receive = "interface I { event e : nat }
interface V { var x : nat }
stm P { uses I requires V initial i state S { entry e!1 } transition t { from i to S } }
stm Q { uses I requires V initial i state S { } transition t { from i to S } transition u { from S to S trigger e?x } }
controller C { uses I var x : nat sref p = P sref q = Q connection p on e to q on e }";
    let two = |w: &str| {
        format!(
            "interface V {{ var x : nat }}
interface W {{ {w} }}
stm P {{ requires V initial i state S {{ entry x = 1 }} transition t {{ from i to S }} }}
stm Q {{ requires W initial i state S {{ }} transition t {{ from i to S }} }}
controller C {{ var x : nat sref p = P sref q = Q }}"
        )
    };
    // Through an operation the controller defines: it writes the caller's
    // copy (RT-23).
    let through_an_operation = "interface I { event e : nat }
interface V { var x : nat }
interface Ops { take() }
stm P { uses I requires V initial i state S { entry e!1 } transition t { from i to S } }
stm Q { uses I requires V requires Ops initial i state S { entry take() } transition t { from i to S } }
controller C { uses I var x : nat sref p = P sref q = Q connection p on e to q on e
  operation take() { uses I requires V initial i state W { } final f
    transition t { from i to W } transition u { from W to f trigger e?x } } }";
    // A module's machines count together: `a` alone in `C1` is exported,
    // the module of `C1` and `C2` is not.
    let in_a_module = "interface I { event e : nat }
interface V { var x : nat }
stm A { uses I requires V initial i state S { } transition t { from i to S } transition u { from S to S trigger e?x } }
stm B { initial i state S { } transition t { from i to S } }
controller C1 { uses I var x : nat sref a = A connection C1 on e to a on e }
controller C2 { sref b = B }
module Mod { robotic platform P { uses I } cref c1 = C1 cref c2 = C2 connection P on e to c1 on e ( _async ) }";
    // RT-16: a value received into a shared variable is written by
    // `set_x` after the event, through the controller's memory, as any
    // write: exported (the engine's LTSs of these models equal the
    // export's: `rt16_receiving_into_a_shared_variable*` in
    // crates/engine/tests/export_semantics.rs).
    for model in [in_a_module, through_an_operation, receive] {
        let e = export_checked(model, true);
        let messages: Vec<&String> = e.warnings.iter().map(|w| &w.message).collect();
        assert!(messages.is_empty(), "{model}: {messages:?}");
        assert!(e.files.iter().any(|f| f.text().contains("in?x__in -> set_x!x__in")), "{model}");
        let problems = robosim_semantics::lint::check(&e.files);
        assert!(problems.is_empty(), "{model}: {problems:#?}");
    }
    for (model, why) in [
        (two("var x : int"), "5:12: controller C is not exported: `x` is required with two different types"),
        (
            two("var x : nat = 1"),
            "5:12: controller C is not exported: `x` is required with different initial values: `robosim verify` \
             starts every copy with the first machine's, the export each machine with its own",
        ),
    ] {
        // Two types are ill-formed (RC:C3), refused all the same.
        let e = export_checked(&model, !why.contains("two different types"));
        let messages: Vec<String> = e.warnings.iter().map(|w| format!("{}:{}: {}", w.line, w.col, w.message)).collect();
        assert_eq!(messages, [why], "{model}");
    }
}

/// Two controllers of a module each keep their own `x`, even of the same
/// name: `a`'s write reaches `d` (beside it in `C1`), never `b` (in `C2`).
#[test]
fn each_controller_keeps_its_own_variable() {
    let model = "interface V { var x : nat }
stm A { requires V initial i state S { entry x = 1 } transition t { from i to S } }
stm B { requires V initial i state S { } state Seen { }
  transition t { from i to S } transition u { from S to Seen condition x == 1 } }
controller C1 { var x : nat sref a = A sref d = B }
controller C2 { var x : nat sref b = B }
module Mod { robotic platform P { } cref c1 = C1 cref c2 = C2 }";
    let e = export(model);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    let m = load(&e.files);
    let c1 = text_of(&e.files, "RoboChart controller C1");
    let c1: String = c1.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(c1.contains("Memory__x = C1::a::set_x?w__ -> C1::d::set_EXT_x!w__ -> Memory__x"), "{c1}");
    // `C2` has one machine: its memory is `b`'s own.
    assert_eq!(c1.matches("Memory__x =").count(), 1, "{c1}");
    let vs = lts(&m, "Mod::VS__(0)");
    let entered = |e: &str| {
        let e = vs.event(e);
        vs.transitions.iter().flatten().any(|(l, _)| e.is_some_and(|e| *l == Label::Event(e)))
    };
    assert!(entered("C1::d::entered__.C1::d::SID_Seen"), "{:?}", vs.events);
    assert!(!entered("C2::b::entered__.C2::b::SID_Seen"), "{:?}", vs.events);
}
