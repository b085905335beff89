//! What the tests of `csp` blocks share: a package of small machines,
//! checked against a file of assertions and blocks that imports it, and
//! each outcome as a verdict with its counterexample.

#![allow(dead_code)] // Each test binary uses a different part.

use robosim_engine::verify::{trace_text, verify_texts, Options, Report, Verdict};

/// A package with an interface and machines that use it: `M` answers `go`
/// with `speed!k` and `done` at once, `Fast` with `done` at once, `Slow`
/// with `done` one time unit later (and rests one more).
pub const MACHINES: &str = "package p
interface I { event go event speed : nat event done }
stm M {
  uses I
  const k : nat
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B trigger go }
  transition t2 { from B to A action speed!k ; done }
}
stm Fast {
  uses I
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B trigger go }
  transition t2 { from B to A action done }
}
stm Slow {
  uses I
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B trigger go }
  transition t2 { from B to A action wait(1) ; done ; wait(1) }
}
";

/// Checks `assertions` (the package imported) against `model`.
pub fn run(model: &str, assertions: &str) -> Vec<Report> {
    verify_texts(
        [("m.rct".to_string(), model.to_string()), ("a.assertions".to_string(), format!("import p::*\n{assertions}"))],
        &Options::default(),
    )
}

/// The verdict and the counterexample's trace (or the reason).
pub fn outcome(r: &Report) -> (Verdict, String) {
    let cex = r.counterexample.as_ref().map(|c| format!("{}: {}", c.kind, trace_text(&c.steps)));
    (r.verdict, cex.unwrap_or_else(|| r.reason.clone().unwrap_or_default()))
}
