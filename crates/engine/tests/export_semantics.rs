//! The two back ends agree on what a model *does*: for the models of the
//! engine's verdict fixtures (`test_data/verify/*/`), each element's
//! process as the CSPm export writes it (the process the export's own
//! `assert` line checks, e.g. `p::M::D__(0, const_p_M_k)`), compiled to an
//! explicit LTS by our CSPm evaluator, is equivalent to the element's
//! native LTS (the one the engine's CSPm bridge checks `csp` blocks
//! against: events named as RoboTool's CSPm names them, `M::terminate`
//! before ✓ for machines and controllers): refinement both ways in the
//! traces, then stable-failures, then failures-divergences models, in the
//! timed semantics (`tock` an ordinary visible event, as in FDR) and in
//! RoboChart's untimed one (RT-9: the export's untimed script against the
//! engine's untimed LTS).
//!
//! Each element is `agree`, `disagree` (with the shortest distinguishing
//! behaviour the refinement check finds) or `not comparable` (why: a side
//! refuses the element, the evaluator lacks something, a bound, or a
//! fixture assuming another asynchronous buffer than RoboTool's, which is
//! the only one the export writes: its buffered elements). Known
//! disagreements are listed in [`KNOWN`] with which side is wrong per
//! RoboTool's generated CSPm (`reference/alpha-algorithm/csp-gen/timed`)
//! and `robotool-facts.md`: the test fails when a new one appears or a
//! listed one goes away.
//!
//! Verdicts too: the reachability and the refinement assertions of the
//! fixtures, RoboChart's and RoboSim's (whose elements' whole LTSs are not
//! compared yet, so that verdicts, `csp` blocks naming RoboTool's
//! per-element events included, are their only comparison), as FDR would
//! answer the export's `assert` lines (each side evaluated by our CSPm
//! evaluator, RoboSim's `:[tau priority]: {tock}` applied) and as the
//! engine answers them ([`REACH_KNOWN`], [`REFINE_KNOWN`]).
//!
//! `XCHECK_VERBOSE=1` prints every element's outcome.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_cspm::{Evaluator, Label as CspLabel, Limits, Module, NoNames};
use robosim_engine::algo::explicit::ExplicitLts;
use robosim_engine::algo::{refines, RefinementCex, RefinementResult, SemanticModel};
use robosim_engine::budget::Budget;
use robosim_engine::lts::{Event, Lts};
use robosim_engine::verify::{subject_lts, AsyncBuffer, Options, Semantics};
use robosim_hir::defs::DefKind;
use robosim_hir::index::file_summary;

/// Why each known disagreement is one (see [`KNOWN`]).
const RECORDS: &str = "value representation, not behaviour: the export writes a record value as RoboTool's datatype `R_rec.0.false`, the bridge (hir::csp_names) as a tuple `(0, false)`; the reference has no record to settle it";

/// Known disagreements: (fixture, element, the start of the outcome,
/// which side is wrong and why).
#[rustfmt::skip]
const KNOWN: &[(&str, &str, &str, &str)] = &[
    ("csp_bridge_record_constants_of_generated_processes", "p::R", "traces: the engine has trace ⟨p::R::go.in, p::R::out.out", RECORDS),
    ("csp_types_an_untimed_contract_in_the_timed_semantics", "p::M", "traces: the engine has trace ⟨p::M::prio.in.0, p::M::go.in, p::M::out.out", RECORDS),
    ("csp_types_events_carrying_a_tuple_with_a_record", "p::M", "traces: the engine has trace ⟨p::M::prio.in.0, p::M::go.in, p::M::out.out", RECORDS),
    ("structured_records", "M", "traces: the engine has trace ⟨M::e.in.(0, false)⟩", RECORDS),
];

/// Most states of either side's LTS.
const MAX_STATES: usize = 20_000;

/// The outcome of one element.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Outcome {
    /// Equivalent in the failures-divergences model (so in all three):
    /// the states of the export's and the engine's LTS.
    Agree(usize, usize),
    /// Not equivalent: the model and the first distinguishing behaviour.
    Disagree(String),
    /// Not compared, and why.
    NotComparable(String),
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Outcome::Agree(a, b) => write!(f, "agree ({a} / {b} states)"),
            Outcome::Disagree(why) => write!(f, "disagree: {why}"),
            Outcome::NotComparable(why) => write!(f, "not comparable: {why}"),
        }
    }
}

/// The fixtures' directories, sorted.
fn fixtures() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/verify");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("fixtures")
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs
}

/// The fixture's model files (its assertion files left out: both sides then
/// take RoboTool's default instantiations), or why it is not compared.
fn model_files(dir: &Path) -> Result<Vec<(String, String)>, String> {
    let mut out = Vec::new();
    let mut names: Vec<PathBuf> =
        std::fs::read_dir(dir).expect("fixture").filter_map(|e| Some(e.ok()?.path())).collect();
    names.sort();
    for p in names {
        let name = p.file_name().unwrap_or_default().to_string_lossy().into_owned();
        match p.extension().and_then(|e| e.to_str()) {
            Some("rct") => out.push((name, std::fs::read_to_string(&p).expect("model file"))),
            Some("rst") => {
                return Err("a RoboSim model: its elements' whole LTSs are not compared yet (the export's \
                            processes take the period and read with τ priority over `tock`); its verdicts are"
                    .into())
            }
            _ => {}
        }
    }
    if out.is_empty() {
        return Err("no RoboChart model file".into());
    }
    Ok(out)
}

/// The elements of the workspace's model files: (qualified name, kind),
/// machines first, then controllers, then modules.
fn elements(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace) -> Vec<(String, DefKind)> {
    let mut out = Vec::new();
    for &f in ws.files(db).iter() {
        if f.is_library(db) || f.kind(db).is_assertions() {
            continue;
        }
        let s = file_summary(db, f);
        for it in s.items.iter() {
            if matches!(it.kind, DefKind::Module | DefKind::Controller | DefKind::StateMachine) {
                let mut path = s.package.clone();
                path.push(it.name.clone());
                out.push((path.join("::"), it.kind));
            }
        }
    }
    let rank = |k: &DefKind| match k {
        DefKind::StateMachine => 0,
        DefKind::Controller => 1,
        _ => 2,
    };
    out.sort_by(|a, b| rank(&a.1).cmp(&rank(&b.1)).then(a.0.cmp(&b.0)));
    out
}

/// The buffer a fixture assumes for asynchronous connections with a line
/// `// option async-buffer: …` (read as `tests/fixtures.rs` reads it), if
/// it is not RoboTool's (RT-12, one place that overwrites).
fn assumed_buffer(dir: &Path) -> Option<String> {
    let mut names: Vec<PathBuf> =
        std::fs::read_dir(dir).expect("fixture").filter_map(|e| Some(e.ok()?.path())).collect();
    names.sort();
    names.iter().filter_map(|p| std::fs::read_to_string(p).ok()).find_map(|text| {
        text.lines().find_map(|l| {
            let value = l.trim_start().strip_prefix("// option async-buffer:")?.trim();
            (AsyncBuffer::parse(value).ok()? != AsyncBuffer::ROBOTOOL).then(|| value.to_string())
        })
    })
}

/// The controllers and modules (qualified names) with an asynchronous
/// connection between two of their components: those the buffer is part
/// of.
fn buffered_elements(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace) -> BTreeSet<String> {
    use robosim_hir::model::{item, End, Item};
    let mut out = BTreeSet::new();
    for &f in ws.files(db).iter().filter(|f| !f.is_library(db) && !f.kind(db).is_assertions()) {
        let s = file_summary(db, f);
        for (index, it) in s.items.iter().enumerate() {
            let loc = robosim_hir::index::ItemLoc { file: f, index: index as u32 };
            let component = |e: &End| matches!(e, End::Controller(_) | End::Machine(_));
            let connections = match item(db, ws, loc) {
                Some(Item::Module(x)) => &x.connections,
                Some(Item::Controller(c)) => &c.connections,
                _ => continue,
            };
            if connections.iter().any(|c| c.is_async && component(&c.from_end) && component(&c.to_end)) {
                let mut path = s.package.clone();
                path.push(it.name.clone());
                out.insert(path.join("::"));
            }
        }
    }
    out
}

/// Why an element of a fixture that assumes the buffer `buffer` is not
/// compared.
fn another_buffer(buffer: &str) -> String {
    format!(
        "the fixture assumes the buffer `{buffer}` (`// option async-buffer`); the export writes RoboTool's only \
         (RT-12: one place, overwritten)"
    )
}

/// The name of the assertion about the `i`th element.
fn assertion_name(i: usize) -> String {
    format!("xcheck{i}")
}

/// The assertion file that names every element: `P refines P`, so that the
/// export writes the element's process in its `assert` line.
fn assertion_file(elements: &[(String, DefKind)], sem: Semantics) -> String {
    elements
        .iter()
        .enumerate()
        .map(|(i, (path, _))| {
            format!("{} assertion {} : {path} refines {path} in the failures model\n", keyword(sem), assertion_name(i))
        })
        .collect()
}

/// The assertion keyword of a semantics.
fn keyword(sem: Semantics) -> &'static str {
    match sem {
        Semantics::Timed => "timed",
        Semantics::Untimed => "untimed",
    }
}

/// The exported workspace: the CSPm of everything but the assertion
/// scripts, and each of our assertions' implementation process.
struct Exported {
    text: String,
    /// Assertion name → the process its `assert` line checks.
    processes: BTreeMap<String, String>,
    /// Element → why the export refuses it (`-- NOT EXPORTED: …`).
    refused: BTreeMap<String, String>,
}

fn export(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace, sem: Semantics) -> Exported {
    let comment = format!("-- {} assertion ", keyword(sem));
    let ex = robosim_semantics::export_workspace(db, ws, &robosim_semantics::Options::default());
    let mut text = String::new();
    let mut processes = BTreeMap::new();
    let mut refused = BTreeMap::new();
    let files = match sem {
        Semantics::Timed => &ex.files,
        Semantics::Untimed => &ex.untimed,
    };
    for f in files {
        let t = f.text();
        if let Ok(dir) = std::env::var("XCHECK_DUMP") {
            let _ = std::fs::write(format!("{dir}/{}", f.name), &t);
        }
        if t.contains("\ninclude \"") {
            // `-- timed assertion xcheck0 : …` then `assert Spec [F= Imp`.
            let mut current = None;
            for l in t.lines() {
                if let Some(rest) = l.strip_prefix(comment.as_str()) {
                    current = rest.split(" : ").next().map(str::to_string);
                } else if let (Some(name), Some((_, imp))) = (&current, l.split_once(" [F= ")) {
                    if l.starts_with("assert ") {
                        processes.insert(name.clone(), imp.trim().to_string());
                    }
                    current = None;
                }
            }
            continue;
        }
        // `-- NOT EXPORTED: state machine p::M` then `--   m.rct:1:2: why`.
        let mut lines = t.lines().peekable();
        while let Some(l) = lines.next() {
            let Some(what) = l.strip_prefix("-- NOT EXPORTED: ") else { continue };
            let Some(path) = ["state machine ", "controller ", "module "].iter().find_map(|k| what.strip_prefix(k))
            else {
                continue;
            };
            let why = lines
                .peek()
                .and_then(|n| n.strip_prefix("--   "))
                .map_or("", |w| w.split_once(": ").map_or(w, |(_, w)| w));
            refused.insert(path.to_string(), why.to_string());
        }
        text.push_str(&t);
        text.push('\n');
    }
    Exported { text, processes, refused }
}

/// Both sides' LTSs over one event numbering.
struct Pair {
    export: ExplicitLts,
    engine: ExplicitLts,
}

impl Pair {
    fn new(export: &robosim_cspm::Lts, engine: &robosim_cspm::Lts) -> Pair {
        let mut names: Vec<String> = vec!["τ".into(), "✓".into(), "tock".into()];
        let mut export = ExplicitLts::from_cspm(export, &mut names);
        let mut engine = ExplicitLts::from_cspm(engine, &mut names);
        export.names = names.clone();
        engine.names = names;
        Pair { export, engine }
    }
}

/// A refinement counterexample as text: the trace, and what goes wrong
/// after it.
fn describe(imp: &ExplicitLts, cex: &RefinementCex<usize>) -> String {
    let name = |e: &Event| imp.event_name(*e);
    let set = |es: &[Event]| format!("{{{}}}", es.iter().map(name).collect::<Vec<_>>().join(", "));
    match cex {
        RefinementCex::Trace { path, .. } => {
            format!("trace ⟨{}⟩", path.trace().iter().map(name).collect::<Vec<_>>().join(", "))
        }
        RefinementCex::Refusal { path, offered, acceptances } => format!(
            "after ⟨{}⟩ a stable state offers only {}; the other side must accept one of {}",
            path.trace().iter().map(name).collect::<Vec<_>>().join(", "),
            set(offered),
            acceptances.iter().map(|a| set(a)).collect::<Vec<_>>().join(" or ")
        ),
        RefinementCex::TockRefusal { path, offered, .. } => format!(
            "after ⟨{}⟩ time passes offering only {}",
            path.trace().iter().map(name).collect::<Vec<_>>().join(", "),
            set(offered)
        ),
        RefinementCex::Divergence { path, .. } => {
            format!("divergence after ⟨{}⟩", path.trace().iter().map(name).collect::<Vec<_>>().join(", "))
        }
    }
}

/// Refinement both ways in each model, the weakest first: the first
/// failure, or equivalence.
fn compare(pair: &Pair) -> Outcome {
    let budget = Budget {
        max_states: 4 * MAX_STATES as u64,
        timeout: Some(Duration::from_secs(10)),
        threads: 1,
        ..Budget::default()
    };
    for (model, mname) in [
        (SemanticModel::Traces, "traces"),
        (SemanticModel::Failures, "failures"),
        (SemanticModel::FailuresDivergences, "failures-divergences"),
    ] {
        for (spec, imp, who) in [(&pair.export, &pair.engine, "the engine"), (&pair.engine, &pair.export, "the export")]
        {
            match refines(spec, imp, model, &budget, None).0 {
                RefinementResult::Holds => {}
                RefinementResult::Fails(cex) => {
                    return Outcome::Disagree(format!("{mname}: {who} has {}", describe(imp, &cex)))
                }
                RefinementResult::Inconclusive(stop) => {
                    return Outcome::NotComparable(format!("refinement check out of budget: {}", stop.reason(&budget)))
                }
            }
        }
    }
    Outcome::Agree(pair.export.len(), pair.engine.len())
}

/// Each element of a fixture's models, compared.
fn check_fixture(dir: &Path, sem: Semantics) -> Vec<(String, Outcome)> {
    let fixture = dir.file_name().unwrap_or_default().to_string_lossy().into_owned();
    let files = match model_files(dir) {
        Ok(f) => f,
        Err(why) => return vec![(fixture, Outcome::NotComparable(why))],
    };
    // The elements first, then the assertions about them.
    let elems = {
        let mut db = robosim_hir::RootDatabase::default();
        let ws = robosim_hir::load_workspace(&mut db, files.clone(), robosim_hir::RuleSet::Paper);
        elements(&db, ws)
    };
    let mut all = files;
    all.push(("xcheck.assertions".to_string(), assertion_file(&elems, sem)));
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, all, robosim_hir::RuleSet::Paper);
    let exported = export(&db, ws, sem);
    let module = Module::check(&exported.text, &NoNames);
    if let Some(d) = module.diagnostics().iter().find(|d| d.severity == robosim_cspm::Severity::Error) {
        return vec![(fixture, Outcome::NotComparable(format!("the export does not load: {d}")))];
    }
    let file = *ws.files(&db).iter().find(|f| f.path(&db).ends_with("xcheck.assertions")).expect("the assertion file");
    let others: Vec<_> = ws
        .files(&db)
        .iter()
        .filter(|f| !f.is_library(&db) && f.kind(&db).is_assertions())
        .map(|&f| (f, robosim_hir::model::assertion_file(&db, f).clone()))
        .collect();
    let read = robosim_hir::model::assertion_file(&db, file).clone();
    let opts = Options::default();
    let (buffer, buffered) = (assumed_buffer(dir), buffered_elements(&db, ws));
    let mut out = Vec::new();
    for (i, (path, _)) in elems.iter().enumerate() {
        let name = assertion_name(i);
        let place = format!("{fixture} {path}");
        if let Some(b) = buffer.as_ref().filter(|_| buffered.contains(path)) {
            out.push((place, Outcome::NotComparable(another_buffer(b))));
            continue;
        }
        let Some(a) = read.assertions.iter().find(|a| a.name == name) else {
            out.push((place, Outcome::NotComparable("our assertion was not read".into())));
            continue;
        };
        let outcome = (|| {
            let engine = subject_lts(&db, ws, file, &read, &others, a, sem, &opts, MAX_STATES)
                .map_err(|e| format!("the engine: {e}"))?;
            let process = exported.processes.get(&name).ok_or_else(|| match exported.refused.get(path) {
                Some(why) => format!("the export refuses it: {why}"),
                None => "the export writes no refinement for the element".to_string(),
            })?;
            let limits = Limits { max_states: MAX_STATES, time: Duration::from_secs(10), ..Limits::default() };
            let mut ev = Evaluator::new(&module, &NoNames, limits);
            let export = ev
                .eval_text(process)
                .and_then(|v| ev.lts_of(&v))
                .map_err(|d| format!("the evaluator, on `{process}`: {}", d.message))?;
            Ok::<_, String>(compare(&Pair::new(&export, &engine)))
        })()
        .unwrap_or_else(Outcome::NotComparable);
        out.push((place, outcome));
    }
    out
}

/// A short reason class for the summary.
fn class(o: &Outcome) -> String {
    match o {
        Outcome::Agree(..) => "agree".into(),
        Outcome::Disagree(why) => format!("disagree ({})", why.split(':').next().unwrap_or_default()),
        Outcome::NotComparable(why) => {
            let w: String = why.chars().take(60).collect();
            format!("not comparable ({w}…)")
        }
    }
}

/// Known disagreements of the untimed semantics (RT-9), as [`KNOWN`]: the
/// same elements and cause as the timed ones (how a record value is
/// written, not behaviour).
#[rustfmt::skip]
const KNOWN_UNTIMED: &[(&str, &str, &str, &str)] = &[
    ("csp_bridge_record_constants_of_generated_processes", "p::R", "traces: the engine has trace ⟨p::R::go.in, p::R::out.out", RECORDS),
    ("csp_types_an_untimed_contract_in_the_timed_semantics", "p::M", "traces: the engine has trace ⟨p::M::prio.in.0, p::M::go.in, p::M::out.out", RECORDS),
    ("csp_types_events_carrying_a_tuple_with_a_record", "p::M", "traces: the engine has trace ⟨p::M::prio.in.0, p::M::go.in, p::M::out.out", RECORDS),
    ("structured_records", "M", "traces: the engine has trace ⟨M::e.in.(0, false)⟩", RECORDS),
];

#[test]
fn the_export_and_the_engine_have_the_same_behaviour() {
    cross_check(Semantics::Timed, KNOWN);
}

#[test]
fn the_export_and_the_engine_have_the_same_untimed_behaviour() {
    cross_check(Semantics::Untimed, KNOWN_UNTIMED);
}

/// Every fixture's elements compared in `sem`: a disagreement not in
/// `known`, or one of `known` that no longer happens, fails.
fn cross_check(sem: Semantics, known: &[(&str, &str, &str, &str)]) {
    let mut results = Vec::new();
    for dir in fixtures() {
        results.extend(check_fixture(&dir, sem));
    }
    let verbose = std::env::var("XCHECK_VERBOSE").is_ok();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut problems = Vec::new();
    let mut seen = vec![false; known.len()];
    for (place, o) in &results {
        *counts.entry(class(o)).or_default() += 1;
        if verbose {
            eprintln!("{} {place}: {o}", keyword(sem));
        }
        if let Outcome::Disagree(why) = o {
            match known.iter().position(|(f, e, w, _)| place == &format!("{f} {e}") && why.starts_with(w)) {
                Some(k) => seen[k] = true,
                None => problems.push(format!("new disagreement: {place}: {why}")),
            }
        }
    }
    for (k, s) in seen.iter().enumerate() {
        if !s {
            problems.push(format!("known disagreement gone (remove it from the known table): {:?}", known[k]));
        }
    }
    eprintln!("{}: {} elements: {counts:#?}", keyword(sem), results.len());
    assert!(problems.is_empty(), "{problems:#?}");
}

/// Known reachability disagreements: (fixture, assertion, why).
const REACH_KNOWN: &[(&str, &str, &str)] = &[];

/// Whether the export's `assert` line holds, evaluated with our CSPm
/// evaluator: reachability is `assert not STOP [T= P \ diff(Events,
/// {entered})` (`is not reachable`: without `not`), which holds iff `P`
/// can (cannot) perform the entry.
fn export_reachability(module: &Module, line: &str) -> Result<bool, String> {
    let (negated, process) = match (line.strip_prefix("assert not STOP [T= "), line.strip_prefix("assert STOP [T= ")) {
        (Some(p), _) => (true, p),
        (_, Some(p)) => (false, p),
        _ => return Err(format!("not a reachability assertion: {line}")),
    };
    let limits = Limits { max_states: MAX_STATES, time: Duration::from_secs(10), ..Limits::default() };
    let mut ev = Evaluator::new(module, &NoNames, limits);
    let lts = ev.eval_text(process).and_then(|v| ev.lts_of(&v)).map_err(|d| format!("the evaluator: {}", d.message))?;
    let entered = lts.transitions.iter().flatten().any(|(l, _)| matches!(l, CspLabel::Event(_)));
    Ok(entered == negated)
}

/// Reachability verdicts: for every timed reachability assertion of the
/// fixtures' own assertion files (RoboChart and RoboSim), the export's `assert` (the
/// state's path resolved by hir, `robosim_hir::target::state`, in the
/// subject's `VS__` — a controller's or module's composes its machines')
/// and the engine decide alike; one side refusing where the other decides
/// is counted, not compared. Each refusal of a path naming no state or
/// several has the engine's very reason. Known disagreements are listed
/// in [`REACH_KNOWN`], with which side is wrong, as in [`KNOWN`].
#[test]
fn reachability_verdicts_agree() {
    let is_reach = |t: &str| t.contains(" is reachable in ") || t.contains(" is not reachable in ");
    let subject = |rest: &str| vec![rest.rsplit(" in ").next().unwrap_or_default().trim().to_string()];
    verdicts_agree("reachability", &is_reach, &subject, &export_reachability, REACH_KNOWN);
}

/// Known refinement disagreements: (fixture, assertion, why).
const REFINE_KNOWN: &[(&str, &str, &str)] = &[];

/// Refinement verdicts: for every timed refinement or equivalence
/// assertion of the fixtures' own assertion files (RoboChart and RoboSim), FDR's
/// answer to the export's `assert` lines (each side's process evaluated
/// with our CSPm evaluator, the refinement decided by the engine's
/// algorithm on those LTSs) and the engine's verdict agree; as
/// [`reachability_verdicts_agree`], with [`REFINE_KNOWN`].
#[test]
fn refinement_verdicts_agree() {
    let is_refine = |t: &str| t.contains(" refines ") || t.contains(" equals ") || t.contains(" refine ");
    let sides = |rest: &str| {
        let claim = rest.split_once(" : ").map_or(rest, |(_, c)| c);
        let words: Vec<&str> = claim.split_whitespace().collect();
        let first = words.first().copied().unwrap_or_default().to_string();
        let after = words.iter().position(|w| matches!(*w, "refines" | "refine" | "equals" | "to"));
        let second = after.and_then(|k| words.get(k + 1)).copied().unwrap_or_default().to_string();
        vec![first, second]
    };
    verdicts_agree("refinement", &is_refine, &sides, &export_refinement, REFINE_KNOWN);
}

/// Whether FDR's `assert [not] SPEC [M= IMP` holds, with our evaluator.
fn export_refinement(module: &Module, line: &str) -> Result<bool, String> {
    let rest = line.strip_prefix("assert ").ok_or_else(|| format!("not an assertion: {line}"))?;
    let (negated, rest) = match rest.strip_prefix("not ") {
        Some(r) => (true, r),
        None => (false, rest),
    };
    // RoboSim's checks give τ priority over `tock` (RT-10): applied to
    // both sides' LTSs below, as FDR applies it to the check.
    let (rest, tau_priority) = match rest.strip_suffix(" :[tau priority]: {tock}") {
        Some(r) => (r, true),
        None => (rest, false),
    };
    if rest.contains(":[") {
        return Err(format!("not compared (an option FDR applies): {line}"));
    }
    let (op, model) = [
        ("[FD=", SemanticModel::FailuresDivergences),
        ("[F=", SemanticModel::Failures),
        ("[T=", SemanticModel::Traces),
    ]
    .into_iter()
    .find(|(op, _)| rest.contains(op))
    .ok_or_else(|| format!("not a refinement: {line}"))?;
    let (spec, imp) = rest.split_once(op).expect("found");
    let limits = Limits { max_states: MAX_STATES, time: Duration::from_secs(10), ..Limits::default() };
    let mut ev = Evaluator::new(module, &NoNames, limits);
    let mut lts = |text: &str| {
        let mut lts = ev
            .eval_text(text.trim())
            .and_then(|v| ev.lts_of(&v))
            .map_err(|d| format!("the evaluator: {}", d.message))?;
        if tau_priority {
            prioritise_tau(&mut lts);
        }
        Ok::<_, String>(lts)
    };
    let (spec, imp) = (lts(spec)?, lts(imp)?);
    let mut names: Vec<String> = vec!["τ".into(), "✓".into(), "tock".into()];
    let spec = ExplicitLts::from_cspm(&spec, &mut names);
    let imp = ExplicitLts::from_cspm(&imp, &mut names);
    let budget = Budget {
        max_states: 4 * MAX_STATES as u64,
        timeout: Some(Duration::from_secs(10)),
        threads: 1,
        ..Budget::default()
    };
    match refines(&spec, &imp, model, &budget, None).0 {
        RefinementResult::Holds => Ok(!negated),
        RefinementResult::Fails(_) => Ok(negated),
        RefinementResult::Inconclusive(stop) => Err(format!("out of budget: {}", stop.reason(&budget))),
    }
}

/// FDR's `:[tau priority]: {tock}`: a state with a τ transition has no
/// `tock` transition.
fn prioritise_tau(lts: &mut robosim_cspm::Lts) {
    let Some(tock) = lts.event("tock") else { return };
    for out in lts.transitions.iter_mut() {
        if out.iter().any(|(l, _)| *l == CspLabel::Tau) {
            out.retain(|(l, _)| *l != CspLabel::Event(tock));
        }
    }
}

/// Verdicts of one kind of assertion (`is_kind` of its text): for every
/// timed assertion of that kind of the fixtures' own assertion files, the
/// export's `assert` lines (evaluated by `eval`; all must hold) and the
/// engine decide alike. `subjects` names the elements an assertion checks
/// (from its text after `assertion `), to leave out those built on an
/// assumed buffer.
fn verdicts_agree(
    what: &str,
    is_kind: &dyn Fn(&str) -> bool,
    subjects: &dyn Fn(&str) -> Vec<String>,
    eval: &dyn Fn(&Module, &str) -> Result<bool, String>,
    known: &[(&str, &str, &str)],
) {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    let mut problems = Vec::new();
    let mut seen = vec![false; known.len()];
    for dir in fixtures() {
        let fixture = dir.file_name().unwrap_or_default().to_string_lossy().into_owned();
        let mut files = Vec::new();
        let mut names: Vec<PathBuf> =
            std::fs::read_dir(&dir).expect("fixture").filter_map(|e| Some(e.ok()?.path())).collect();
        names.sort();
        // RoboChart and RoboSim: verdicts need no event names shared by
        // the two sides, so RoboSim's are compared too (its assertions are
        // timed only, `-- assertion NAME : …`).
        if !names.iter().any(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("rct" | "rst"))) {
            continue;
        }
        for p in names {
            if matches!(p.extension().and_then(|e| e.to_str()), Some("rct" | "rst" | "assertions" | "rsa")) {
                let name = p.file_name().unwrap_or_default().to_string_lossy().into_owned();
                files.push((name, std::fs::read_to_string(&p).expect("fixture file")));
            }
        }
        if !files.iter().any(|(n, t)| (n.ends_with(".assertions") || n.ends_with(".rsa")) && is_kind(t)) {
            continue;
        }
        let mut db = robosim_hir::RootDatabase::default();
        let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
        let reports = robosim_engine::verify::verify_workspace(&db, ws, &Options::default(), None);
        let (buffer, buffered) = (assumed_buffer(&dir), buffered_elements(&db, ws));
        let ex = robosim_semantics::export_workspace(&db, ws, &robosim_semantics::Options::default());
        let texts: BTreeMap<String, String> = ex.files.iter().map(|f| (f.name.clone(), f.text())).collect();
        for script in texts.keys().filter(|n| texts[*n].contains("\ninclude \"")) {
            let load = |name: &str| texts.get(name).cloned();
            let module = Module::check_with_includes(&texts[script], &NoNames, &load);
            // `-- timed assertion NAME : …`, then its `assert` lines or
            // `-- NOT EXPORTED: why`.
            let mut lines = texts[script].lines().peekable();
            while let Some(l) = lines.next() {
                let Some(rest) = l.strip_prefix("-- timed assertion ").or_else(|| l.strip_prefix("-- assertion "))
                else {
                    continue;
                };
                if !is_kind(rest) {
                    continue;
                }
                let name = rest.split(" : ").next().unwrap_or_default().trim().to_string();
                // Its lines, continuations (indented) joined, up to a blank.
                let mut asserts: Vec<String> = Vec::new();
                while let Some(next) = lines.peek().filter(|l| {
                    !l.trim().is_empty() && !l.starts_with("-- timed assertion ") && !l.starts_with("-- assertion ")
                }) {
                    match (next.starts_with(' '), asserts.last_mut()) {
                        (true, Some(last)) => *last = format!("{last} {}", next.trim()),
                        _ => asserts.push(next.to_string()),
                    }
                    lines.next();
                }
                let place = format!("{fixture} {name}");
                if buffer.is_some() && subjects(rest).iter().any(|s| buffered.contains(s.as_str())) {
                    *counts.entry("not compared: the fixture assumes another buffer").or_default() += 1;
                    continue;
                }
                let Some(r) = reports.iter().find(|r| r.name == name && r.semantics == Semantics::Timed) else {
                    problems.push(format!("{place}: the engine has no timed report"));
                    continue;
                };
                let engine = match r.verdict {
                    robosim_engine::verify::Verdict::Pass => Some(true),
                    robosim_engine::verify::Verdict::Fail => Some(false),
                    _ => None,
                };
                let export = match asserts.first().and_then(|a| a.strip_prefix("-- NOT EXPORTED: ")) {
                    Some(why) => Err(why.to_string()),
                    None if asserts.is_empty() => Err("no assert line".to_string()),
                    None => asserts
                        .iter()
                        .filter(|a| a.starts_with("assert "))
                        .map(|a| eval(&module, a))
                        .collect::<Result<Vec<bool>, _>>()
                        .map(|v| v.iter().all(|x| *x)),
                };
                let outcome = match (&export, engine) {
                    (Ok(x), Some(e)) if *x == e => "agree",
                    (Ok(x), Some(e)) => {
                        match known.iter().position(|(f, n, _)| *f == fixture && *n == name) {
                            Some(k) => seen[k] = true,
                            None => {
                                problems.push(format!("new disagreement: {place}: the export says {x}, the engine {e}"))
                            }
                        }
                        "disagree"
                    }
                    (Err(why), None) if why.contains(" names ") => {
                        if r.reason.as_deref() != Some(why.as_str()) {
                            problems.push(format!("{place}: the export refuses ({why}), the engine ({:?})", r.reason));
                        }
                        "both refuse the path"
                    }
                    (Err(_), None) => "both refuse",
                    (Err(_), Some(_)) => "the export refuses",
                    (Ok(_), None) => "the engine refuses",
                };
                if std::env::var("XCHECK_VERBOSE").is_ok() {
                    eprintln!("{place}: {outcome}: export {export:?}, engine {:?} {:?}", r.verdict, r.reason);
                }
                *counts.entry(outcome).or_default() += 1;
            }
        }
    }
    for (k, s) in seen.iter().enumerate() {
        if !s {
            problems.push(format!("known disagreement gone (remove it from the {what} table): {:?}", known[k]));
        }
    }
    eprintln!("{what}: {counts:#?}");
    assert!(problems.is_empty(), "{problems:#?}");
    assert!(counts.get("agree").copied().unwrap_or(0) > 0, "no {what} assertion compared");
}
