//! RT-11: operations as assertion subjects in the export. Each test
//! exports a real small model (the engine's fixtures where they exist),
//! pins the CSPm written for the operation's process and assertions,
//! checks the whole script with our CSPm front end, and runs the
//! operation's process with our CSPm evaluator to see the events the
//! engine's fixture states.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use robosim_cspm::{Evaluator, Limits, Module, NoNames, Severity};
use robosim_semantics::{export_workspace, lint, Export, Options, Profile};

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

fn text(e: &Export, name: &str) -> String {
    e.files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).text()
}

/// The script FDR loads (the assertion file), with `extra` appended,
/// checked with its includes: no errors, and the module to evaluate.
fn checked(e: &Export, main: &str, extra: &str) -> Module {
    let files: HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |name: &str| files.get(name).cloned();
    let src = format!("{}\n{extra}\n", files[main]);
    let m = Module::check_with_includes(&src, &NoNames, &load);
    let errors: Vec<String> =
        m.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{d:?}")).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    m
}

/// Whether the process can do the visible `trace` and then terminate (✓).
fn terminates_after(lts: &robosim_cspm::Lts, trace: &[&str]) -> bool {
    let mut cur = lts.tau_closure(vec![lts.initial]);
    for name in trace {
        let Some(e) = lts.event(name) else { return false };
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

/// A RoboChart controller with operations and no machines is exported
/// (its process terminates at once, as `robosim verify` reads it), its
/// operation as RoboTool names it (`C::OP_Op`, with `D__`, `VS__`, `O__`
/// taking `id__` and the parameters), and so is the module that contains
/// it. `C::Op` and `Mod::c::Op` are subjects with their parameters
/// (`with parameter n of C::Op set to 1`, or of `Op`); comparing the
/// operation with another process is refused with its reason.
#[test]
fn controller_operations_are_subjects_as_robotool_names_them() {
    let e = export_dir(&fixture("rt11_controller_operations"));
    let model = text(&e, "m.csp");
    for line in [
        "module C\nexports\n  module OP_Op\n",
        "    D__(id__, n) = TimedPriority(P__(id__, n) \\ {| entered__ |})\n    VS__(id__, n) = P__(id__, n)\n    \
         O__(id__, n) = sbisim(D__(id__, n))\n  endmodule\n",
        "  D__(id__) = TimedPriority(SKIP)\n",
        "module Mod\nexports\n  -- Events and operation calls.\n  -- D__: the module's semantics; O__: compressed \
         (parameters: id__).\n  D__(id__) = TimedPriority(C::D__(id__))\n",
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
          exported: their events are channels of different CSPm modules (`C::OP_Op`, `Top`), which FDR would never \
          match, while `robosim verify` matches them by name"]
    );
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
    // What the engine's fixture says: n == 0, `a` then ✓; n == 1, `b` forever.
    let m = checked(&e, "a_assertions.csp", "X0__ = C::OP_Op::D__(0, 0)\nX1__ = C::OP_Op::D__(0, 1)\nC0__ = C::D__(0)");
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    let x0 = ev.lts("X0__").unwrap();
    assert!(terminates_after(&x0, &["a.out"]), "{:?}", x0.events);
    assert!(!x0.has_trace(&["b.out"]), "{:?}", x0.events);
    let x1 = ev.lts("X1__").unwrap();
    assert!(x1.has_trace(&["b.out", "tock", "b.out"]), "{:?}", x1.events);
    assert!(!x1.has_trace(&["a.out"]) && !terminates_after(&x1, &["b.out"]));
    assert!(terminates_after(&ev.lts("C0__").unwrap(), &[]));
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
        "-- assertion T0 : D::o terminates\nassert not CHAOS(Events) [T= ops_Count::D__(0, 0)\n",
        "-- assertion T1 : D::o terminates with parameter n of D::o set to 1\n\
         assert not CHAOS(Events) [T= ops_Count::D__(0, 1)\n",
        "-- assertion T2 : Mod::d::o terminates with parameter n of Mod::d::o set to 1\n\
         assert not CHAOS(Events) [T= ops_Count::D__(0, 1)\n",
        "-- assertion T3 : D::o terminates with parameter n of ops::Count set to 1\n\
         assert not CHAOS(Events) [T= ops_Count::D__(0, 1)\n",
        "-- assertion T4 : D::o terminates with parameter m of D::o set to 1\n\
         -- NOT EXPORTED: the operation `D::o` (`Count`) has no parameter `m`\n",
        "-- assertion T5 : D::o terminates with parameter n of D::p set to 1\n-- NOT EXPORTED: `D::p` is not an \
         operation",
    ] {
        assert!(asserts.contains(block), "{block}\nnot in\n{asserts}");
    }
    checked(&e, "a_assertions.csp", "");
}
