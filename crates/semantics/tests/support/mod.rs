//! Helpers shared by the tests that check and run the exported CSPm with
//! our own CSPm front end and evaluator.
#![allow(dead_code)]

use std::collections::HashMap;

use robosim_cspm::{Label, Lts, Module, NoNames, Severity};
use robosim_semantics::Export;

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
