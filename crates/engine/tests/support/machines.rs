//! What the engine's construct tests share: small RoboChart machines over
//! one interface, checked against their assertions, and their outcomes
//! compared with a table.

#![allow(dead_code)] // Each test binary uses a different part.

use robosim_engine::verify::{trace_text, verify_texts, Options, Report, Semantics, Verdict};

/// The events and operation every machine of these tests may use.
pub const INTERFACE: &str = "interface I { event e event f event o event v : nat op() }";

/// Checks `assertions` on `model` (machines and controllers using `I`):
/// the timed analysis, which these constructs are about (the untimed one
/// of a plain assertion, RT-8, is tested in `untimed.rs`).
pub fn run(model: &str, assertions: &str) -> Vec<Report> {
    let reports = verify_texts(
        [("m.rct".to_string(), format!("{INTERFACE}\n{model}")), ("a.assertions".to_string(), assertions.into())],
        &Options::default(),
    );
    reports.into_iter().filter(|r| r.semantics == Semantics::Timed).collect()
}

/// Each report's name and verdict, with the counterexample's kind and
/// trace (or the reason it was not checked).
pub fn outcomes(reports: &[Report]) -> Vec<(String, Verdict, String)> {
    reports
        .iter()
        .map(|r| {
            let cex = r.counterexample.as_ref().map(|c| format!("{}: {}", c.kind, trace_text(&c.steps)));
            let reason = r.reason.clone().filter(|_| r.verdict == Verdict::Unsupported);
            (r.name.clone(), r.verdict, cex.or(reason).unwrap_or_default())
        })
        .collect()
}

/// Asserts the outcomes of `reports`, in order.
pub fn expect(reports: &[Report], expected: &[(&str, Verdict, &str)]) {
    let want: Vec<(String, Verdict, String)> =
        expected.iter().map(|(n, v, c)| (n.to_string(), *v, c.to_string())).collect();
    assert_eq!(outcomes(reports), want, "{reports:#?}");
}
