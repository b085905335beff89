//! Helpers shared by the tests that check and run the exported CSPm with
//! our own CSPm front end and evaluator.
#![allow(dead_code)]

use std::collections::HashMap;

use robosim_cspm::{Evaluator, Label, Limits, Lts, Module, NoNames, Severity};
use robosim_semantics::{Export, OutFile};

/// The exported file `name`'s text.
pub fn text(e: &Export, name: &str) -> String {
    e.files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).text()
}

/// The script `main` with `extra` appended, checked with its includes: no
/// errors, and the module to evaluate.
pub fn checked(e: &Export, main: &str, extra: &str) -> Module {
    let files: HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |name: &str| files.get(name).cloned();
    let src = format!("{}\n{extra}\n", files[main]);
    let m = Module::check_with_includes(&src, &NoNames, &load);
    let errors: Vec<String> =
        m.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{d:?}")).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    m
}

/// The states after the visible `trace` (τ steps anywhere).
pub fn after(lts: &Lts, trace: &[&str]) -> Vec<u32> {
    let mut cur = lts.tau_closure(vec![lts.initial]);
    for name in trace {
        let Some(e) = lts.event(name) else { return Vec::new() };
        let next: Vec<u32> = cur
            .iter()
            .flat_map(|&s| lts.transitions[s as usize].iter().filter(|(l, _)| *l == Label::Event(e)).map(|(_, t)| *t))
            .collect();
        cur = lts.tau_closure(next);
    }
    cur
}

/// Whether the process can do `trace` and then terminate (✓).
pub fn terminates_after(lts: &Lts, trace: &[&str]) -> bool {
    after(lts, trace).iter().any(|&s| lts.transitions[s as usize].iter().any(|(l, _)| *l == Label::Tick))
}

/// The export of `files` (path, text) in RoboTool 3's profile.
pub fn export_files(files: Vec<(String, String)>) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    robosim_semantics::export_workspace(
        &db,
        ws,
        &robosim_semantics::Options { profile: robosim_semantics::Profile::RoboTool3 },
    )
}

/// The text of the file `name` of `files`.
pub fn file_text(files: &[OutFile], name: &str) -> String {
    files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).text()
}

/// The script `name` of `files` with its includes, and the errors
/// robosim-cspm finds in it.
pub fn load(files: &[OutFile], name: &str) -> (Module, Vec<String>) {
    let texts: HashMap<String, String> = files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let get = |n: &str| texts.get(n).cloned();
    let script = texts.get(name).unwrap_or_else(|| panic!("no {name} in {:?}", texts.keys()));
    let m = Module::check_with_includes(script, &NoNames, &get);
    let errors = m.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{d}")).collect();
    (m, errors)
}

/// The value of `expr` in the script, printed.
pub fn eval(m: &Module, expr: &str) -> String {
    let mut ev = Evaluator::new(m, &NoNames, Limits::default());
    ev.eval_text(expr).map(|v| v.to_string()).unwrap_or_else(|d| format!("error: {}", d.message))
}

/// `trace` with RoboSim's cycle and register events named as the element
/// module `m`'s own, as RoboTool declares them (`registerWrite.o_x.1` is
/// `M::registerWrite.M::o_x.1`, `endexec` is `M::endexec`); other events
/// are kept.
pub fn own(m: &str, trace: &[&str]) -> Vec<String> {
    trace
        .iter()
        .map(|e| match e.split_once('.') {
            Some((c @ ("registerRead" | "registerWrite"), rest)) => format!("{m}::{c}.{m}::{rest}"),
            _ if matches!(*e, "endexec" | "terminate") => format!("{m}::{e}"),
            _ => e.to_string(),
        })
        .collect()
}

/// The `&str`s of `v` (for [`after`] and [`terminates_after`]).
pub fn refs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// The verdict of the trace refinement `assert spec [T= imp :[tau
/// priority]: {tock}` (as written by the export) in `m`: every trace of
/// `spec` (✓ included) is one of `imp`, whose `tock` is refused where it
/// has an internal step.
pub fn trace_refines(m: &Module, spec: &str, imp: &str) -> bool {
    let mut ev = Evaluator::new(m, &NoNames, Limits::default());
    let mut lts =
        |p: &str| ev.eval_text(p).and_then(|v| ev.lts_of(&v)).unwrap_or_else(|d| panic!("{p}: {}", d.message));
    let (spec, mut imp) = (lts(spec), lts(imp));
    if let Some(tock) = imp.event("tock") {
        for t in imp.transitions.iter_mut() {
            if t.iter().any(|(l, _)| *l == Label::Tau) {
                t.retain(|(l, _)| *l != Label::Event(tock));
            }
        }
    }
    // Each state of `spec` with the set of states `imp` can be in after
    // the same trace.
    let start = (spec.initial, imp.tau_closure(vec![imp.initial]));
    let mut seen = std::collections::HashSet::new();
    let mut todo = vec![start];
    while let Some((s, set)) = todo.pop() {
        if !seen.insert((s, set.clone())) {
            continue;
        }
        for (l, t) in &spec.transitions[s as usize] {
            let next: Vec<u32> = match l {
                Label::Tau => set.clone(),
                Label::Tick => {
                    if !set.iter().any(|&i| imp.transitions[i as usize].iter().any(|(l, _)| *l == Label::Tick)) {
                        return false;
                    }
                    continue;
                }
                Label::Event(e) => {
                    let Some(e) = imp.event(&spec.events[*e as usize]) else { return false };
                    let step: Vec<u32> = set
                        .iter()
                        .flat_map(|&i| {
                            imp.transitions[i as usize].iter().filter(|(l, _)| *l == Label::Event(e)).map(|(_, t)| *t)
                        })
                        .collect();
                    if step.is_empty() {
                        return false;
                    }
                    imp.tau_closure(step)
                }
            };
            todo.push((*t, next));
        }
    }
    true
}
