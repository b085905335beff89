//! The export names and composes the model as RoboTool 3's generator does
//! (`../shared/reference/alpha-algorithm/csp-gen`), so that users' `csp`
//! blocks, written against RoboTool's names, work on it: operations a
//! machine calls (RT-19), machines inside controllers (`pkg::C::r`), and
//! the `csp` blocks themselves (RT-7).

use robosim_semantics::{export_workspace, Export, Options, Profile};

/// A library operation `lib::Stop` (it calls the platform's `halt()`),
/// a machine `M` that requires `Stop()`, a controller `C` that provides
/// it by `opref` and refers to `M`, and a controller `D` with its own
/// `Stop` and an inline machine `S`.
const LIB: &str = "package lib
interface Halt { halt() }
operation Stop() { requires Halt initial i final f transition t { from i to f action halt() } }";

const APP: &str = "package app
import lib::*
interface Stops { Stop() }
interface E { event go }
stm M {
  requires Stops uses E const k : nat = 2
  initial i state A { }
  transition t0 { from i to A } transition t1 { from A to A trigger go action Stop() }
}
controller C { requires Halt uses E opref r0 = lib::Stop sref s = M connection C on go to s on go }
controller D {
  requires Halt uses E
  operation Stop() { requires Halt initial i final f transition t { from i to f action halt() } }
  stm S {
    requires Stops uses E
    initial i state A { }
    transition t0 { from i to A } transition t1 { from A to A trigger go action Stop() }
  }
  connection D on go to S on go
}";

fn export(files: &[(&str, &str)]) -> Export {
    let files: Vec<(String, String)> = files.iter().map(|(p, t)| (p.to_string(), t.to_string())).collect();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile: Profile::RoboTool3 })
}

fn file(e: &Export, name: &str) -> String {
    e.files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).text()
}

/// The text of the module declared by `module <name>` at `indent`
/// spaces, up to its `endmodule`.
fn module(text: &str, name: &str, indent: usize) -> String {
    let head = format!("{}module {name}\n", " ".repeat(indent));
    let start = text.find(&head).unwrap_or_else(|| panic!("no module {name} at {indent}:\n{text}"));
    let end = format!("\n{}endmodule", " ".repeat(indent));
    let len = text[start..].find(&end).expect("endmodule");
    text[start..start + len].to_string()
}

/// Errors of FDR's language (as `robosim-cspm` reads it) in the script of
/// the assertion file `script`, with the files it includes.
fn cspm_errors(e: &Export, script: &str) -> Vec<String> {
    let files: std::collections::HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |name: &str| files.get(name).cloned();
    let m = robosim_cspm::Module::check_with_includes(&files[script], &robosim_cspm::NoNames, &load);
    m.diagnostics().iter().filter(|d| d.severity == robosim_cspm::Severity::Error).map(|d| format!("{d:?}")).collect()
}

/// RT-19: on its own a machine leaves the operations it requires
/// undefined, as call events (reference `defs/pkg223__Communication.csp`
/// declares `channel normal_Communication_Receive_t2_opCall`, …), even
/// when an operation of that name exists; inside its controller the
/// controller's operation is inlined (`CALL__op`), wherever it is declared
/// (`opref r0 = lib::Stop`), and its own calls become the machine's.
#[test]
fn a_machine_calls_its_operations_on_its_own_and_runs_its_controllers() {
    let e = export(&[("lib.rct", LIB), ("app.rct", APP)]);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>());
    let app = file(&e, "app.csp");
    // On its own: `StopCall`, urgent (RT-19), and no definition of Stop.
    let m = module(&app, "M", 2);
    assert!(m.contains("channel StopCall\n") && m.contains("EDeadline(StopCall, 0)"), "{m}");
    assert!(!m.contains("CALL__") && !m.contains("haltCall"), "{m}");
    // Inside C, as RoboTool's `pkg223_::CommunicationC::stm_ref0`: the
    // controller's operation, its platform call the machine's.
    let c = module(&app, "C", 2);
    let s = module(&c, "s", 4);
    // The operation `lib::Stop` is RoboTool's `lib::OP_Stop` (as the
    // reference's `pkg223_main::OP_tStop`).
    assert!(s.contains("CALL__Stop = lib::OP_Stop::D__(id__) [[ lib::OP_Stop::haltCall <- haltCall ]]"), "{s}");
    let lib = file(&e, "lib.csp");
    assert!(
        lib.contains(
            "module lib
"
        ) && module(&lib, "OP_Stop", 2).contains(
            "channel haltCall
"
        ),
        "{lib}"
    );
    assert!(s.contains("channel haltCall\n") && !s.contains("StopCall"), "{s}");
    // The controller composes that instance; its constants are named
    // after the reference (RoboTool: `const_pkg223__CommunicationC_stm_ref0_id`).
    assert!(c.contains("D__(id__, const_app_C_s_k) =") && c.contains("app::C::s::D__(id__, const_app_C_s_k)"), "{c}");
    let inst = file(&e, "instantiations.csp");
    assert!(inst.contains("const_app_C_s_k = 2") && inst.contains("const_app_M_k = 2"), "{inst}");
    // An inline machine is `app::D::S`, with D's own operation, which is
    // RoboTool's `app::D::OP_Stop` (as `pkg223_::CommunicationC::OP_…`).
    let d = module(&app, "D", 2);
    let s = module(&d, "S", 4);
    assert!(s.contains("CALL__Stop = app::D::OP_Stop::D__(id__) [[ app::D::OP_Stop::haltCall <- haltCall ]]"), "{s}");
    assert!(d.contains("\n    module OP_Stop\n"), "{d}");
}

/// Assertions reach the same processes: a machine inside a controller by
/// `pkg::C::S`, and `with constant k of M` binds the machine's constant
/// under its controller's reference. The script is valid CSPm.
#[test]
fn assertions_name_the_instances_and_bind_their_constants() {
    let asserts = "assertion a1: app::M is deadlock-free
assertion a2: app::C is deadlock-free with constant k of M set to 5
assertion a3: app::D::S is deadlock-free";
    let e = export(&[("lib.rct", LIB), ("app.rct", APP), ("a.assertions", asserts)]);
    let script = file(&e, "a_assertions.csp");
    assert!(script.contains("app::M::D__(0, const_app_M_k)"), "{script}");
    assert!(script.contains("app::C::D__(0, 5)"), "{script}");
    assert!(script.contains("app::D::S::D__(0)"), "{script}");
    let errors = cspm_errors(&e, "a_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
}

/// RT-7: a block is copied whole. Definitions of names the export does not
/// make (old-style `nametype ID`, `nametype nat`) stay, so that the specs
/// using them resolve; those the export makes (`core_nat`, whose bounds
/// the script's own instantiations take from the block, and `Plus`) stay commented, as
/// a second definition would be an error.
#[test]
fn instantiations_blocks_keep_the_names_the_export_does_not_define() {
    let asserts = "csp Instantiations csp-begin
nametype ID = {0,1}
nametype nat = {0..4}
nametype core_nat = {0..3}
Plus(e1,e2,T) = if member(e1+e2,T) then e1+e2 else e1
csp-end
csp Spec csp-begin
Spec = |~| x : ID @ app::M::go.in -> SKIP
csp-end
assertion a1: Spec refines app::M in the traces model";
    let e = export(&[("lib.rct", LIB), ("app.rct", APP), ("a.assertions", asserts)]);
    let script = file(&e, "a_assertions.csp");
    for kept in ["\nnametype ID = {0,1}\n", "\nnametype nat = {0..4}\n"] {
        assert!(script.contains(kept), "{kept} {script}");
    }
    for commented in [
        "-- (in this script's instantiations or robosim_defs.csp) nametype core_nat = {0..3}",
        "-- (in this script's instantiations or robosim_defs.csp) Plus(",
    ] {
        assert!(script.contains(commented), "{commented} {script}");
    }
    let errors = cspm_errors(&e, "a_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
}

/// An event of a product type carries one value, a tuple, its channel
/// declared with RoboTool's set of tuples (reference
/// `defs/Communication.csp`: `channel receive: InOut.{(x0__,x1__) | x0__
/// <- main_ID,x1__ <- main_ID}`): an output is `pair.out.(2, 0)`, an input
/// binds the tuple.
#[test]
fn an_event_of_a_product_type_carries_a_tuple() {
    let model = "interface I { event pair : nat * nat }
stm M { uses I var p : nat * nat initial i state S { } state T { entry pair!(| 2, 0 |) }
  transition t0 { from i to S } transition t1 { from S to T trigger pair?p } }";
    let e = export(&[("m.rct", model)]);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>());
    let m = file(&e, "m.csp");
    assert!(m.contains("channel pair : InOut.{(x0__, x1__) | x0__ <- core_nat, x1__ <- core_nat}\n"), "{m}");
    let text: String = e.files.iter().map(|f| f.text()).filter(|t| !t.contains("\ninclude \"")).collect();
    let module = robosim_cspm::Module::check(&text, &robosim_cspm::NoNames);
    assert!(module.is_ok(), "{:?}", module.diagnostics());
    let mut ev = robosim_cspm::Evaluator::new(&module, &robosim_cspm::NoNames, robosim_cspm::Limits::default());
    let lts = ev.eval_text("M::D__(0)").and_then(|p| ev.lts_of(&p)).expect("the machine's LTS");
    assert!(lts.has_trace(&["M::pair.in.(1, 2)", "M::pair.out.(2, 0)"]));
}

/// RoboTool names channels by the model's names even where they clash
/// with CSPm's: an event `out` is `channel out` (not `out_`), the call of
/// an operation `set` is `setCall` (not `set_Call`), in the machine, its
/// controller and its module, as `csp` blocks and the engine's CSPm
/// bridge write them. A module whose own channel is `out` hides InOut's
/// constructor `out`, so it writes that direction `out'`
/// (robosim_defs.csp); the script is valid CSPm.
#[test]
fn events_and_calls_keep_names_that_clash_with_cspm() {
    let model = "package p
interface E { event out : nat event go }
interface Ops { set(x : nat) }
stm M { uses E requires Ops
  initial i state A { }
  transition t0 { from i to A } transition t1 { from A to A trigger go action out!1 ; set(2) } }
stm N { uses E event relay : nat var x : nat
  initial i state A { } transition t0 { from i to A } transition t1 { from A to A trigger out?x action relay!x } }
controller C { uses E requires Ops sref m = M sref n = N
  connection C on go to m on go connection m on out to n on out connection n on relay to C on out }
module Mod { robotic platform P { uses E provides Ops } cref c = C
  connection P on go to c on go ( _async ) connection c on out to P on out ( _async ) }";
    let asserts = "assertion a1: p::Mod is deadlock-free";
    let e = export(&[("m.rct", model), ("a.assertions", asserts)]);
    let text = file(&e, "m.csp");
    let m = module(&text, "M", 2);
    assert!(m.contains("channel out : InOut.core_nat\n") && m.contains("channel setCall : core_nat\n"), "{m}");
    assert!(m.contains("Delayable(out.out'.1)") && !m.contains("out_ ") && !m.contains("set_Call"), "{m}");
    let n = module(&text, "N", 2);
    assert!(n.contains("out__.TID_t1.in?x__in"), "{n}");
    let c = module(&text, "C", 2);
    assert!(c.contains("channel out : InOut.core_nat\n") && c.contains("channel setCall : core_nat\n"), "{c}");
    assert!(c.contains("p::C::m::out.out'.") && c.contains("p::C::n::out.in."), "{c}");
    let defs = file(&e, "robosim_defs.csp");
    assert!(defs.contains("\nout' = out\n") && !defs.contains("in' = in"), "{defs}");
    let errors = cspm_errors(&e, "a_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
}
