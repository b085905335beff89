//! The CSPm export of the Alpha Algorithm reference
//! (`../shared/reference/alpha-algorithm`), read by our CSPm front end and
//! evaluator, gives the verdicts FDR recorded for RoboTool's own script, in
//! both semantics (robotool-facts.md, "Results FDR recorded": a1
//! `Communication is deterministic` false; a2–a6 true, untimed and timed).
//!
//! Each `assert` the export writes for `model.assertions` in the untimed
//! script (RT-8, RT-9: `:[deadlock free [FD]]`) and in the timed one
//! (deadlock freedom as the prioritised, `tock`-hidden divergence check) is
//! evaluated to an LTS and checked with the engine's algorithms on it.
//! What is not exported is listed with the export's reason, so that the
//! test fails, to be extended, when it is.

use std::collections::HashMap;
use std::path::Path;
use std::time::Duration;

use robosim_cspm::{Evaluator, Limits, Module, NoNames};
use robosim_engine::algo::explicit::ExplicitLts;
use robosim_engine::algo::{check_determinism, find_deadlock, find_divergence};
use robosim_engine::algo::{DeadlockResult, DeterminismResult, DivergenceResult};
use robosim_engine::budget::Budget;
use robosim_semantics::OutFile;

/// Most states of an exported process's LTS.
const MAX_STATES: usize = 200_000;

/// The export of the reference project, every model and assertion file.
fn export_reference() -> robosim_semantics::Export {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/alpha-algorithm");
    let files = robosim_test_support::inputs::read_model_files(&dir);
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    robosim_semantics::export_workspace(&db, ws, &robosim_semantics::Options::default())
}

/// The assertions of `model_assertions.csp` in `files`: the assertion's
/// name (`a1`) → its `assert` text (several lines joined), or the NOT
/// EXPORTED reason.
fn asserts(files: &[OutFile]) -> Vec<(String, Result<String, String>)> {
    let text = files.iter().find(|f| f.name == "model_assertions.csp").expect("model_assertions.csp").text();
    let mut out = Vec::new();
    let mut lines = text.lines().peekable();
    while let Some(l) = lines.next() {
        let Some(rest) = l.strip_prefix("-- assertion ").or_else(|| l.strip_prefix("-- untimed assertion ")) else {
            continue;
        };
        let name = rest.split([':', ' ']).next().unwrap_or_default().to_string();
        let mut body = Vec::new();
        while let Some(n) = lines.next_if(|n| !n.trim().is_empty()) {
            body.push(n.trim());
        }
        let body = body.join(" ");
        out.push(match body.strip_prefix("-- NOT EXPORTED: ") {
            Some(why) => (name, Err(why.to_string())),
            None => (name, Ok(body)),
        });
    }
    out
}

/// FDR's verdict on one `assert` line: `assert [not] P :[property [FD]]`.
fn verdict(module: &Module, line: &str) -> Result<bool, String> {
    let line = line.strip_prefix("assert ").ok_or("not an assert")?;
    let (negated, line) = match line.strip_prefix("not ") {
        Some(l) => (true, l),
        None => (false, line),
    };
    let (process, property) = line.rsplit_once(" :[").ok_or("not a property check")?;
    // The timed script declares `Movement`'s channels (`moveCall :
    // core_real.core_real`, `core_real = {-2..180}`): `Events` is large.
    let limits =
        Limits { max_states: MAX_STATES, max_set: 2_000_000, time: Duration::from_secs(120), ..Limits::default() };
    let mut ev = Evaluator::new(module, &NoNames, limits);
    let lts = ev.eval_text(process).and_then(|v| ev.lts_of(&v)).map_err(|d| format!("`{process}`: {}", d.message))?;
    let lts = ExplicitLts::from_cspm(&lts, &mut vec!["τ".into(), "✓".into(), "tock".into()]);
    let budget =
        Budget { max_states: 4 * MAX_STATES as u64, timeout: Some(Duration::from_secs(120)), ..Budget::default() };
    let divergence_free = || match find_divergence(&lts, &budget, None).0 {
        DivergenceResult::Free => Ok(true),
        DivergenceResult::Divergent { .. } => Ok(false),
        DivergenceResult::Inconclusive(s) => Err(format!("{s:?}")),
    };
    let holds = match property {
        "deterministic [FD]]" => match check_determinism(&lts, &budget, None).0 {
            DeterminismResult::Deterministic => true,
            // FDR: a divergent process is not deterministic.
            DeterminismResult::Nondeterministic { .. } | DeterminismResult::Divergent { .. } => false,
            DeterminismResult::Inconclusive(s) => return Err(format!("{s:?}")),
        },
        "divergence free [FD]]" => divergence_free()?,
        // The failures-divergences model: a divergence may refuse everything.
        "deadlock free [FD]]" => match find_deadlock(&lts, &budget, None).0 {
            DeadlockResult::Free => divergence_free()?,
            DeadlockResult::Deadlock(_) => false,
            DeadlockResult::Inconclusive(s) => return Err(format!("{s:?}")),
        },
        p => return Err(format!("the property `{p}` is not read here")),
    };
    Ok(holds != negated)
}

/// What the export makes of an assertion: FDR's verdict on what it
/// writes, or why it is not exported.
type Expected = Result<bool, &'static str>;

/// FDR's verdicts (robotool-facts.md), the same in both semantics.
const FDR: [(&str, bool); 6] = [("a1", false), ("a2", true), ("a3", true), ("a4", true), ("a5", true), ("a6", true)];

/// The assertions about `main::AggregationSoftware`, whose controllers are
/// connected asynchronously (RT-12: RoboTool's one-place buffer), timed:
/// its controller `MovementC` calls `Mathematics_floor`, which the file's
/// `csp Instantiations` block leaves undefined (see a4–a6), so they are
/// refused (b1 and b2 compare `csp` blocks naming RoboTool's
/// `AggregationSoftware_O`, not checked here).
const AGGREGATION: [(&str, Expected); 3] = [("a7", Err(UNDEFINED)), ("a8", Err(UNDEFINED)), ("a9", Err(UNDEFINED))];

/// Why the timed a7–a9 are not exported.
const UNDEFINED: &str = "`main::AggregationSoftware` calls `Mathematics_floor`, a function without a body that this \
     file's `csp Instantiations` block does not define: the block replaces RoboTool's generated defaults (RT-7), so \
     FDR stops on the undefined name; define it there (`Mathematics_floor(…) = …`)";

/// FDR's verdicts on the assertions about `main::AggregationSoftware`
/// (robotool-facts.md: a7 `… is not deterministic`, a8, a9 true), which
/// the untimed export writes, its buffer included.
const AGGREGATION_UNTIMED: [(&str, Expected); 3] = [("a7", Ok(true)), ("a8", Ok(true)), ("a9", Ok(true))];

/// Each assertion of `expected` is as expected in `files` (a script).
fn check_script(script: &str, files: &[OutFile], expected: &[(&str, Expected)]) {
    let texts: HashMap<String, String> = files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |n: &str| texts.get(n).cloned();
    // Names of RoboTool's script the model's own `csp` blocks use
    // (`AggregationSoftware_O`) are not defined: the rest loads.
    let module = Module::check_with_includes(&texts["model_assertions.csp"], &NoNames, &load);
    let found = asserts(files);
    for (name, want) in expected {
        let Some((_, got)) = found.iter().find(|(n, _)| n == name) else {
            panic!("{script} {name}: no such assertion in {found:#?}");
        };
        match (got, want) {
            (Ok(line), Ok(v)) => {
                let verdict = verdict(&module, line).unwrap_or_else(|e| panic!("{script} {name}: {e}"));
                assert_eq!(verdict, *v, "{script} {name}: {line}");
            }
            (Err(why), Err(w)) => assert_eq!(why, w, "{script} {name}"),
            (got, want) => panic!("{script} {name}: {got:?}, expected {want:?}"),
        }
    }
}

/// The untimed script: a1–a9 with FDR's verdicts. `Movement` is exported
/// untimed: its `wait(floor(…))` is `SKIP` (RT-9), so the bodiless `floor`
/// is never called; so is the module, with RoboTool's buffer between its
/// controllers (RT-12).
#[test]
fn the_untimed_export_of_the_alpha_algorithm_has_fdrs_verdicts() {
    let e = export_reference();
    let expected: Vec<(&str, Expected)> =
        FDR.iter().map(|&(n, v)| (n, Ok(v))).chain(AGGREGATION_UNTIMED.iter().cloned()).collect();
    check_script("untimed", &e.untimed, &expected);
}

/// The timed script: a1–a3 with FDR's verdicts; a4–a6 are about
/// `Movement`, whose `wait(floor(…))` calls `Mathematics_floor`, a
/// function without a body, which the `csp Instantiations` block of
/// model.assertions replaces the generated defaults without defining (it
/// defines `floor`, RT-2, RT-7): RoboTool's timed script does not load in
/// FDR (its FDR results are an older generation's), so they are refused.
#[test]
fn the_timed_export_of_the_alpha_algorithm_has_fdrs_verdicts() {
    let e = export_reference();
    let movement: Expected = Err("`Movement` calls `Mathematics_floor`, a function without a body that this file's \
         `csp Instantiations` block does not define: the block replaces RoboTool's generated defaults (RT-7), so FDR \
         stops on the undefined name; define it there (`Mathematics_floor(…) = …`)");
    let expected: Vec<(&str, Expected)> = FDR[..3]
        .iter()
        .map(|&(n, v)| (n, Ok(v)))
        .chain([("a4", movement), ("a5", movement), ("a6", movement)])
        .chain(AGGREGATION.iter().cloned())
        .collect();
    check_script("timed", &e.files, &expected);
}
