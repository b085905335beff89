//! RT-12 in the export: an asynchronous connection between two controllers
//! of a module is RoboTool's one-place buffer that overwrites (the
//! generated `Buffer0` of `reference/alpha-algorithm/csp-gen/timed/defs/
//! main_AggregationSoftware.csp`): the sender never blocks, an unread
//! value is lost when the next one arrives, both transfers are hidden and,
//! timed, go before `tock`. The exported CSPm is loaded and run by our
//! evaluator (as the engine's cross-check does, `export_semantics.rs`,
//! which compares it with the engine on `export_async_lost_value`).

use robosim_cspm::{Evaluator, Label, Limits, Lts, Module, NoNames};
use robosim_semantics::{export_workspace, Export, Options, OutFile};

/// `CS` sends 1 then 2 at once and goes on to `Sent`; `CR` waits a time
/// unit (untimed: not at all, RT-9), then receives and reports the value
/// to the platform on `got`.
const MODEL: &str = "interface Out { event out : nat }
interface In { event inp : nat }
interface Got { event got : nat }
stm S { uses Out initial i state A { entry out!1 ; out!2 } state Sent { }
  transition t0 { from i to A } transition t1 { from A to Sent } }
stm R { uses In uses Got var x : nat
  initial i state W { entry wait(1) } state G { entry got!x }
  transition t0 { from i to W } transition t1 { from W to G trigger inp?x } transition t2 { from G to G trigger inp?x } }
controller CS { uses Out sref s = S connection s on out to CS on out }
controller CR { uses In uses Got sref r = R connection CR on inp to r on inp connection r on got to CR on got }
module Mod { robotic platform P { uses Got } cref cs = CS cref cr = CR
  connection cs on out to cr on inp ( _async ) connection cr on got to P on got ( _async ) }
";

fn export(model: &str) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws =
        robosim_hir::load_workspace(&mut db, [("m.rct".to_string(), model.to_string())], robosim_hir::RuleSet::Paper);
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

/// The module's text in `files`.
fn module_text(files: &[OutFile]) -> String {
    files.iter().map(|f| f.text()).find(|t| t.contains("RoboChart module Mod")).expect("the module Mod")
}

#[test]
fn the_module_composes_robotools_buffer_on_both_whole_channels() {
    let e = export(MODEL);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    for files in [&e.files, &e.untimed] {
        // Every name defined and every prefix with its channel's fields.
        let problems = robosim_semantics::lint::check(files);
        assert!(problems.is_empty(), "{problems:#?}");
        let t = module_text(files);
        for line in [
            "Buffer1__ = CS::out.out?x0__ -> Buffer1Full__(x0__)",
            "Buffer1Full__(x0__) = CS::out.out?y0__ -> Buffer1Full__(y0__) [] CR::inp.in!x0__ -> Buffer1__",
        ] {
            assert!(t.lines().any(|l| l.trim() == line), "{line}\n{t}");
        }
        // Both channels whole, in the synchronisation and in the hiding.
        let flat: String = t.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(flat.contains("Buffer1__ [| {| CS::out, CR::inp |} |]"), "{t}");
        assert!(flat.contains("\\ {| CS::out, CR::inp |}"), "{t}");
    }
}

#[test]
fn timed_the_sender_never_blocks_and_an_unread_value_is_lost() {
    let e = export(MODEL);
    let m = load(&e.files);
    let d = lts(&m, "Mod::D__(0)");
    // 1 and 2 are both sent before time passes; 2 overwrites 1, which `CR`
    // never receives.
    assert!(d.has_trace(&["tock", "Mod::got.out.2", "tock"]));
    let one = d.event("Mod::got.out.1");
    assert!(!d.transitions.iter().flatten().any(|(l, _)| one.is_some_and(|e| *l == Label::Event(e))));
    assert!(!d.has_trace(&["Mod::got.out.2"]), "`CR` waits a time unit first");
    // The sender is in `Sent` before the first `tock`, `CR` still waiting:
    // it did not wait for the receiver. `VS__` shows the states entered.
    let vs = lts(&m, "Mod::VS__(0)");
    let sent = vs.event("CS::s::entered__.CS::s::SID_Sent").expect("the entry of `Sent` in VS__");
    let tock = vs.event("tock").expect("tock");
    assert!(reaches_without(&vs, Label::Event(sent), Label::Event(tock)));
    // And with a synchronous connection it cannot: `S` waits in `A` for
    // `CR` to take 1, after a `tock`.
    let sync = export(&MODEL.replace("cr on inp ( _async )", "cr on inp"));
    let vs = lts(&load(&sync.files), "Mod::VS__(0)");
    let sent = vs.event("CS::s::entered__.CS::s::SID_Sent").expect("the entry of `Sent` in VS__");
    let tock = vs.event("tock").expect("tock");
    assert!(!reaches_without(&vs, Label::Event(sent), Label::Event(tock)));
    assert!(reaches_without(&vs, Label::Event(tock), Label::Event(sent)));
}

/// Whether `lts` can perform `target` without performing `avoid` first.
fn reaches_without(lts: &Lts, target: Label, avoid: Label) -> bool {
    let mut seen = vec![false; lts.states()];
    let mut todo = vec![lts.initial];
    seen[lts.initial as usize] = true;
    while let Some(s) = todo.pop() {
        for &(l, t) in &lts.transitions[s as usize] {
            if l == target {
                return true;
            }
            if l != avoid && !seen[t as usize] {
                seen[t as usize] = true;
                todo.push(t);
            }
        }
    }
    false
}

#[test]
fn untimed_the_receiver_may_take_the_first_value_before_the_second_arrives() {
    let e = export(MODEL);
    let m = load(&e.untimed);
    let d = lts(&m, "Mod::D__(0)");
    for trace in [&["Mod::got.out.1", "Mod::got.out.2"][..], &["Mod::got.out.2"]] {
        assert!(d.has_trace(trace), "{trace:?}");
    }
    // Once 2 is sent, 1 is taken or lost: never received after 2.
    assert!(!d.has_trace(&["Mod::got.out.2", "Mod::got.out.1"]));
    assert!(!d.has_trace(&["Mod::got.out.1", "Mod::got.out.1"]));
}

/// What RT-12 does not pin down is refused with the reason, never
/// exported as something else.
#[test]
fn asynchronous_connections_the_facts_do_not_pin_down_are_refused() {
    let machines = "interface I { event e : nat }
stm P { uses I initial i state S { entry e!1 } transition t { from i to S } }
stm Q { uses I var x : nat initial i state S { } transition t { from i to S } transition u { from S to S trigger e?x } }
controller C { uses I sref p = P sref q = Q connection p on e to q on e ( _async ) }";
    let twice = MODEL.replace(
        "connection cr on got to P on got ( _async ) }",
        "connection cr on got to P on got ( _async ) connection cs on out to P on got ( _async ) }",
    );
    let mult = MODEL.replace("cr on inp ( _async )", "cr on inp ( _async ) [ mult ]");
    let types = MODEL.replace("interface In { event inp : nat }", "interface In { event inp : int }");
    for (model, why) in [
        (
            machines.to_string(),
            "4:45: controller C is not exported: asynchronous connections between two machines of a controller are \
             not exported: they have no semantics (RC:Cn11), and RoboTool's buffer is pinned down between two \
             controllers only (RT-12)",
        ),
        (
            twice,
            "12:3: module Mod is not exported: the event `out` has an asynchronous connection and another one: \
             RoboTool's buffer is known for an event connected once only (RT-12)",
        ),
        (types, "12:3: module Mod is not exported: the connected events have different types"),
        (
            mult,
            "12:3: module Mod is not exported: a bidirectional (`[ mult ]`) asynchronous connection between \
             controllers is not exported: RoboTool's buffer is known one way only, from the connection's source \
             (RT-12)",
        ),
    ] {
        let e = export(&model);
        let messages: Vec<String> = e.warnings.iter().map(|w| format!("{}:{}: {}", w.line, w.col, w.message)).collect();
        assert_eq!(messages, [why], "{model}");
    }
}

/// A value of several components goes through the buffer whole, and is
/// overwritten whole.
#[test]
fn a_tuple_goes_through_the_buffer() {
    let model = MODEL
        .replace("event out : nat", "event out : nat * boolean")
        .replace("event inp : nat", "event inp : nat * boolean")
        .replace("event got : nat", "event got : nat * boolean")
        .replace("var x : nat", "var x : nat * boolean")
        .replace("entry out!1 ; out!2", "entry out!(| 1, true |) ; out!(| 2, false |)");
    let e = export(&model);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    let m = load(&e.files);
    let d = lts(&m, "Mod::D__(0)");
    assert!(d.has_trace(&["tock", "Mod::got.out.(2, false)", "tock"]), "{:?}", d.events);
    let first = d.event("Mod::got.out.(1, true)").expect("the event");
    assert!(!d.transitions.iter().flatten().any(|(l, _)| *l == Label::Event(first)));
}
