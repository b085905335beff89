//! The bridge between the CSPm of assertion files' `csp` blocks and the
//! native engine: `M refines Spec` (and `equals`) where `Spec` is defined
//! in a `csp` block of the assertion's own file, in the traces, failures
//! and failures-divergences models, in the timed semantics and (RT-8) the
//! untimed one, each with its own RoboTool script ([`script::Script`]).
//!
//! - The script holds RoboTool's library ([`robosim_hir::csp_defs`], the
//!   text the CSPm export writes too): in the timed script its tock-CSP
//!   operators (`StartBy`, `EDeadline`, …); the untimed script has neither
//!   them nor `tock` nor the `timed csp` blocks, so a block that needs time
//!   makes it unloadable, as in FDR.
//! - The bounded types a block defines (`nametype core_real = …`) are
//!   evaluated by the CSPm engine and the model is compiled over them.
//! - The block sees the model's names as RoboTool's generated CSPm spells
//!   them ([`robosim_hir::csp_names`], through [`host::Host`]) and its own
//!   file's other blocks, concatenated as RoboTool's generated script does
//!   (RT-7), and nothing else.
//! - The specification is compiled to an explicit LTS by the CSPm
//!   evaluator, with the constants' instantiation (or default) values: an
//!   assertion's `with constant` binds only inside the model (issue 18).
//! - The implementation is the element's native LTS (with the `with`
//!   bindings); both sides number their events in one table
//!   ([`events::Names`]); a model event with no CSPm name, or a value of the
//!   model's events outside the block's view, is an error, never a silent
//!   drop.
//! - A RoboSim machine or controller (RT-20, RT-21) is its cycle LTS
//!   ([`crate::sim::SimModule`], RoboTool 3's reading), its events as
//!   RoboTool's CSPm declares them in the element's module
//!   (`M::registerRead.M::i_x.b.v`, `M::registerWrite.M::o_x.v`,
//!   `M::endexec`, `M::terminate`), an absent read with any value (its
//!   `registerRead.i_x?x__`), and τ has priority over `tock` (RT-10:
//!   `Spec [T= M::D__(…) :[tau priority]: {tock}`).
//! - A counterexample lists the model's steps with the events in CSPm
//!   names and says where the specification is defined (block and line)
//!   and what it offered instead.

mod events;
mod host;
mod lts;
mod native;
mod script;

use robosim_cspm::{Code, Evaluator, Limits, Module, Severity};
use robosim_hir::csp_names::csp_names;
use robosim_hir::TextRange;

use crate::algo::{refines, RefinementCex, RefinementResult, SemanticModel};
use crate::budget::ProgressFn;
use crate::lts::{Event, Label, Lts, TAU, TOCK};
use crate::pack::VectorLts;
use crate::untimed::Semantics;
use crate::verify::{Counterexample, Cx, Options, Report, Step, Verdict};

use self::events::Names;
use self::host::Host;
use self::lts::{Imp, SpecLts};
use self::script::Script;

/// Whether `path`, a side of the assertion, is a `csp` block of the
/// assertion's own file rather than a model element.
pub(crate) fn is_block(cx: &Cx<'_>, path: &[String]) -> bool {
    matches!(path, [name] if cx.read.csp_block(name).is_some()) && cx.target(path).is_err()
}

/// `subject refines other` / `equals` with a `csp` block on one side.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refinement(
    cx: &Cx<'_>,
    other: &[String],
    model: SemanticModel,
    both_ways: bool,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) {
    if let Err(e) = run(cx, other, model, both_ways, opts, progress, report) {
        report.verdict = e.0;
        report.reason = Some(e.1);
    }
}

/// The element `cx`'s assertion names, compiled and explored in full (see
/// [`crate::verify::subject_lts`]).
pub(crate) fn subject_lts(cx: &Cx<'_>, max_states: usize) -> Result<robosim_cspm::Lts, String> {
    let names = csp_names(cx.db, cx.ws);
    let bindings = cx.constants()?;
    let mut c = native::compile(cx, names, &cx.a.subject, &bindings, &[])?;
    native::explicit(&mut c, max_states)
}

type Outcome = Result<(), (Verdict, String)>;

/// Why a block could not be compiled: the verdict, the reason, and whether
/// a bound of the evaluator was reached.
type BlockError = (Verdict, String, bool);

/// The most events `Events` may hold.
const MAX_EVENTS: usize = 20_000;

/// An explicit LTS's transitions, state by state, in the shared numbering.
type Transitions = Vec<Vec<(Label, u32)>>;

fn unsupported(msg: impl Into<String>) -> (Verdict, String) {
    (Verdict::Unsupported, msg.into())
}

#[allow(clippy::too_many_arguments)]
fn run(
    cx: &Cx<'_>,
    other: &[String],
    model: SemanticModel,
    both_ways: bool,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) -> Outcome {
    let a = cx.a;
    let names = csp_names(cx.db, cx.ws);
    // The blocks first: FDR rejects a script with an unknown name whichever
    // assertion uses it.
    let script = Script::of(cx);
    let timed = cx.semantics == Semantics::Timed;
    let resolving = Host::resolving(names, timed);
    let checked = check_script(cx, &script, &resolving)?;
    let (imp_block, spec_block) = (is_block(cx, &a.subject), is_block(cx, other));
    let bindings = cx.constants().map_err(unsupported)?;
    if imp_block && !bindings.is_empty() {
        return Err(unsupported(
            "`with constant` on an assertion whose implementation is a `csp` block is not supported by the CSPm \
             bridge yet",
        ));
    }
    // The side that is a model element, if any.
    let native_path: Option<&[String]> = match (imp_block, spec_block) {
        (false, _) => Some(&a.subject),
        (true, false) => Some(other),
        (true, true) => None,
    };
    let limits = Limits {
        max_states: usize::try_from(opts.budget.max_states).unwrap_or(usize::MAX).min(Limits::default().max_states),
        time: opts.budget.timeout.unwrap_or(Limits::default().time),
        cancel: opts.budget.cancel.clone(),
        ..Limits::default()
    };
    let types = bounded_types(&checked, &resolving, &limits)?;
    let mut compiled =
        native_path.map(|p| native::compile(cx, names, p, &bindings, &types)).transpose().map_err(unsupported)?;
    // Generated processes the blocks apply, with the constants' values as
    // the script has them.
    let procs = {
        let ev = std::cell::RefCell::new(Evaluator::new(&checked, &resolving, limits.clone()));
        let constant = |k: &str| ev.borrow_mut().value(k).ok();
        native::processes(cx, names, &script.text, &constant, &types, limits.max_states).map_err(unsupported)?
    };
    if compiled.as_ref().is_some_and(|c| c.sim.is_some()) && opts.profile != crate::sched::Profile::RoboTool3 {
        report.notes.push(
            "the RoboSim element is read as RoboTool 3 does (whose generated CSPm names the blocks use: \
             `M::registerWrite.M::o_x.v` at once), whatever the profile chosen"
                .into(),
        );
    }
    let own = compiled.as_ref().map(|c| c.own.clone()).unwrap_or_default();
    let mut domains: rustc_hash::FxHashMap<String, crate::ir::Dom> =
        compiled.as_ref().map(|c| c.design.domains.iter().cloned().collect()).unwrap_or_default();
    // Without a model side, the model's channels range over the blocks'
    // bounded types.
    for (name, lo, hi) in &types {
        domains.entry(name.clone()).or_insert(crate::ir::Dom { lo: *lo, hi: *hi });
    }
    let host = Host {
        names,
        own: own.into_iter().map(|(k, v)| (k, v.into_iter().map(|s| s.into_iter().collect()).collect())).collect(),
        domains,
        processes: procs,
        resolve_only: false,
        timed,
    };
    let module = check_script(cx, &script, &host)?;
    let uses_events = module.defined_names().iter().all(|n| n != "Events") && script.mentions("Events");
    if uses_events && model != SemanticModel::Traces {
        return Err(unsupported(
            "the specification uses `Events`, which in RoboTool's script holds every channel of the generated \
             CSPm (internal ones too); refusals of it can only be checked with FDR, or in the traces model",
        ));
    }
    let mut ev = Evaluator::new(&module, &host, limits.clone());
    host.declare_registers(&mut ev);
    if uses_events {
        // `Events` holds the channels met so far: `tock` (which RoboTool's
        // script declares) and the model's channels.
        let _ = ev.value("tock");
        if spec_block && !imp_block && script.used().iter().all(|t| events_only_run(t)) {
            // Only the element's own channels (the implementation's
            // events, `M::terminate` among them): see `events_only_run`.
            let mut own: Vec<String> = host.own.keys().cloned().collect();
            own.extend(
                compiled.as_ref().filter(|c| c.shows_terminate()).map(|c| format!("{}::terminate", c.element.module)),
            );
            own.sort();
            for n in &own {
                let _ = ev.value(n);
            }
            report.notes.push(
                "`Events` is read as the events of the element's own channels (and of the channels the blocks \
                 name): it only appears as `RUN(Events)`/`CHAOS(Events)`, with no hiding or renaming, so in \
                 the traces model the other channels' events cannot change the verdict"
                    .into(),
            );
        } else {
            for n in names.iter() {
                if matches!(n.kind, robosim_hir::csp_names::CspKind::Channel { .. }) {
                    let _ = ev.value(&n.name);
                }
            }
        }
        // Processes over a large `Events` cost the evaluator dearly.
        if let Ok(robosim_cspm::Value::Set(all)) = ev.value("Events") {
            if all.len() > MAX_EVENTS {
                return Err(unsupported(format!(
                    "`Events` holds {} events here (every channel of every element of the model, over its \
                     types): more than the {MAX_EVENTS} the CSPm bridge takes",
                    all.len()
                )));
            }
        }
    }
    let mut ids = compiled.as_mut().map(|c| std::mem::take(&mut c.ids)).unwrap_or_else(Names::empty);
    let terminate =
        compiled.as_ref().filter(|c| c.shows_terminate()).map(|c| format!("{}::terminate", c.element.module));
    let terminate = terminate.map(|t| ids.id(&t));
    // The blocks' sides, compiled by the CSPm evaluator.
    // Compiling a block may reach a bound (`Code::Limit`): said apart.
    let block = |ev: &mut Evaluator, ids: &mut Names, name: &str| -> Result<(Transitions, String), BlockError> {
        let lts = ev.lts(name).map_err(|d| {
            // A generated process the bridge cannot give is unsupported,
            // not a run-time error of the script.
            let verdict = match d.code {
                _ if d.message.contains("the CSPm bridge") => Verdict::Unsupported,
                Code::Limit | Code::Cancelled | Code::Runtime => Verdict::Inconclusive,
                _ => Verdict::Unsupported,
            };
            (verdict, format!("`{name}` could not be compiled: {}", d.message), d.code == Code::Limit)
        })?;
        // Every value of a model channel must be one of the model's (FDR
        // rejects an event outside its channel's type).
        let at = definition(&script.text, name).map(|r| script.locate(cx, r)).unwrap_or_default();
        for v in &lts.event_values {
            host.check_event(v).map_err(|e| (Verdict::Unsupported, format!("`{name}` {at}: {e}"), false))?;
        }
        let map: Vec<Event> = lts.events.iter().map(|n| ids.id(n)).collect();
        let trans = lts
            .transitions
            .iter()
            .map(|ts| ts.iter().map(|(l, t)| (crate::algo::explicit::label_of_cspm(l, &map), *t)).collect())
            .collect();
        Ok((trans, at))
    };
    let spec_name = other.join("::");
    let imp_name = a.subject.join("::");
    let spec_side = match spec_block.then(|| block(&mut ev, &mut ids, &spec_name)).transpose() {
        Ok(side) => side,
        // A specification too large to compile, against a model element:
        // its traces may still show that the refinement fails.
        Err((verdict, why, true)) if !imp_block && !both_ways && model != SemanticModel::Traces => {
            let mut ev = Evaluator::new(&module, &host, Limits { traces_only: true, ..limits.clone() });
            host.declare_registers(&mut ev);
            let traces = block(&mut ev, &mut ids, &spec_name)
                .map_err(|(_, t, _)| (verdict, format!("{why}; up to traces: {t}")))?;
            let c = compiled.as_ref().ok_or_else(|| (verdict, why.clone()))?;
            let side = Side { model, terminate, ids: &ids, script: &script };
            by_traces(c, traces, (&spec_name, &why), side, opts, progress, report)?;
            // The refinement fails (`by_traces` found a trace).
            report.verdict = if a.negated { Verdict::Pass } else { Verdict::Fail };
            return Ok(());
        }
        Err((verdict, why, _)) => return Err((verdict, why)),
    };
    let imp_side = imp_block.then(|| block(&mut ev, &mut ids, &imp_name)).transpose().map_err(|(v, w, _)| (v, w))?;
    for (side, name) in [(&spec_side, &spec_name), (&imp_side, &imp_name)] {
        if let Some((trans, at)) = side {
            report.notes.push(format!("`{name}` {at}: {} states", trans.len()));
        }
    }
    let holds = match (compiled, spec_side, imp_side) {
        // A model element refines a block.
        (Some(c), Some((trans, at)), None) => {
            let spec = SpecLts { trans, names: &ids };
            let native = c.lts().map_err(unsupported)?;
            let imp = Imp { inner: &native, terminate, names: &ids, tau_priority: c.sim.is_some() };
            report.notes.push(crate::verify::domains_note(&c.design));
            let explain =
                |cex: &RefinementCex<_>| counterexample(&imp, &spec, &c.design, cex, &native, &spec_name, &at);
            let holds = decide(&spec, &imp, model, both_ways, opts, progress, report, &ids, &explain, &script)?;
            if let Some(err) = native.error() {
                return Err((Verdict::Inconclusive, format!("the model met a run-time error: {err}")));
            }
            holds
        }
        // A block refines a model element.
        (Some(c), None, Some((trans, at))) => {
            let imp = SpecLts { trans, names: &ids };
            let native = c.lts().map_err(unsupported)?;
            let spec = Imp { inner: &native, terminate, names: &ids, tau_priority: c.sim.is_some() };
            report.notes.push(crate::verify::domains_note(&c.design));
            let explain = |cex: &RefinementCex<u32>| explicit_counterexample(&imp, cex, &spec_name, &at);
            let holds = decide(&spec, &imp, model, both_ways, opts, progress, report, &ids, &explain, &script)?;
            if let Some(err) = native.error() {
                return Err((Verdict::Inconclusive, format!("the model met a run-time error: {err}")));
            }
            holds
        }
        // Two blocks.
        (None, Some((strans, at)), Some((itrans, _))) => {
            let spec = SpecLts { trans: strans, names: &ids };
            let imp = SpecLts { trans: itrans, names: &ids };
            let explain = |cex: &RefinementCex<u32>| explicit_counterexample(&imp, cex, &spec_name, &at);
            decide(&spec, &imp, model, both_ways, opts, progress, report, &ids, &explain, &script)?
        }
        _ => return Err(unsupported("neither side of the assertion is a `csp` block")),
    };
    if holds {
        report.reason = Some(format!("{imp_name} {} {spec_name}", if both_ways { "equals" } else { "refines" }));
    }
    report.verdict = if holds != a.negated { Verdict::Pass } else { Verdict::Fail };
    Ok(())
}

/// What [`by_traces`] checks besides the two sides.
struct Side<'a> {
    model: SemanticModel,
    terminate: Option<Event>,
    ids: &'a Names,
    script: &'a Script,
}

/// `model`-refinement of the model `c` against a specification too large
/// to compile in full (`why`), compiled up to traces (`trans`, defined
/// `at`: [`robosim_cspm::Limits::traces_only`]). Refinement in the
/// failures and failures-divergences models implies traces refinement
/// (for failures-divergences, of a specification with no τ: a divergence
/// of the full one would be an unguarded recursion, an error of the
/// traces compilation), so a trace of the model the specification does
/// not have makes it fail: then `Ok`, with the counterexample in `report`.
/// Otherwise the first error, `why` among them: no verdict.
fn by_traces(
    c: &native::Compiled<'_>,
    (trans, at): (Transitions, String),
    (spec_name, why): (&str, &str),
    side: Side<'_>,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) -> Outcome {
    let inconclusive = |more: &str| (Verdict::Inconclusive, format!("{why}; {more}"));
    if side.model == SemanticModel::FailuresDivergences && trans.iter().flatten().any(|(l, _)| l.event == TAU) {
        return Err(inconclusive("its traces could not stand for it either (it has internal steps)"));
    }
    let states = trans.len();
    let spec = SpecLts { trans, names: side.ids };
    let native = c.lts().map_err(unsupported)?;
    let imp = Imp { inner: &native, terminate: side.terminate, names: side.ids, tau_priority: c.sim.is_some() };
    let explain = |cex: &RefinementCex<_>| counterexample(&imp, &spec, &c.design, cex, &native, spec_name, &at);
    let (model, ids, script) = (SemanticModel::Traces, side.ids, side.script);
    let holds = decide(&spec, &imp, model, false, opts, progress, report, ids, &explain, script)?;
    if let Some(err) = native.error() {
        return Err((Verdict::Inconclusive, format!("the model met a run-time error: {err}")));
    }
    if holds {
        return Err(inconclusive(
            "up to traces (its internal choices read as external ones, which keeps every trace) the model refines \
             it, so only its refusals are left unchecked",
        ));
    }
    report.notes.push(crate::verify::domains_note(&c.design));
    report.notes.push(format!(
        "`{spec_name}` {at} is too large to compile in full ({}); compiled up to traces (its internal choices read \
         as external ones, which keeps every trace: {states} states), it lacks a trace of the model, and \
         refinement in the {} model implies refinement of traces, so it fails too",
        why.rsplit(": ").next().unwrap_or(why),
        if side.model == SemanticModel::Failures { "failures" } else { "failures-divergences" }
    ));
    Ok(())
}

/// Runs `spec ⊑ imp` (and the converse for `equals`); a failure's
/// counterexample is made by `explain`. Whether it holds.
#[allow(clippy::too_many_arguments)]
fn decide<Sp: Lts, Im: Lts>(
    spec: &Sp,
    imp: &Im,
    model: SemanticModel,
    both_ways: bool,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
    ids: &Names,
    explain: &dyn Fn(&RefinementCex<Im::State>) -> Counterexample,
    script: &Script,
) -> Result<bool, (Verdict, String)> {
    let add = |report: &mut Report, stats: crate::budget::Stats| {
        report.stats.states += stats.states;
        report.stats.transitions += stats.transitions;
        report.stats.seconds += stats.seconds;
    };
    let (result, stats) = refines(spec, imp, model, &opts.budget, progress);
    add(report, stats);
    match result {
        RefinementResult::Holds => {}
        RefinementResult::Inconclusive(stop) => return Err((Verdict::Inconclusive, stop.reason(&opts.budget))),
        RefinementResult::Fails(cex) => {
            check_named(ids, &cex)?;
            let mut c = explain(&cex);
            let untimed = !script.mentions("tock") && !script.mentions("Timed");
            if untimed && script.timed && matches!(&cex, RefinementCex::Trace { event, .. } if event.event == TOCK) {
                c.explanation.push(
                    "the specification never lets time pass: it is untimed, and this check runs in the timed \
                     semantics (RT-8), where the model lets time pass; a plain (neither `timed` nor `untimed`) \
                     assertion is also checked, and reported, in the untimed semantics"
                        .into(),
                );
            }
            report.reason = Some(format!("refinement fails: {}", c.explanation[0]));
            report.counterexample = Some(c);
            return Ok(false);
        }
    }
    if both_ways {
        let (result, stats) = refines(imp, spec, model, &opts.budget, progress);
        add(report, stats);
        match result {
            RefinementResult::Holds => {}
            RefinementResult::Inconclusive(stop) => return Err((Verdict::Inconclusive, stop.reason(&opts.budget))),
            RefinementResult::Fails(cex) => {
                check_named(ids, &cex)?;
                report.reason =
                    Some(format!("refinement (converse) fails: the specification can {}", describe(spec, &cex)));
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// The counterexample of an implementation given in CSPm: its trace.
fn explicit_counterexample(
    imp: &SpecLts<'_>,
    cex: &RefinementCex<u32>,
    spec_name: &str,
    def_at: &str,
) -> Counterexample {
    let (kind, path) = cex_path(cex);
    let mut steps = Vec::new();
    let mut time = 0;
    for (label, _) in &path.steps {
        let event = if label.event == TAU { "τ".into() } else { imp.event_name(label.event) };
        steps.push(Step { event, visible: label.event != TAU, cycle: time, time, description: None, location: None });
        if label.event == TOCK {
            time += 1;
        }
    }
    let trace: Vec<String> = path.trace().iter().map(|e| imp.event_name(*e)).collect();
    let explanation =
        refused_by_spec(format!("the implementation can {}", describe(imp, cex)), spec_name, def_at, &trace);
    Counterexample { kind, steps, explanation, stuck_at: Vec::new(), specification: Vec::new() }
}

fn cex_path<S>(cex: &RefinementCex<S>) -> (&'static str, &crate::algo::Path<S>) {
    match cex {
        RefinementCex::Trace { path, .. } => ("trace", path),
        RefinementCex::Refusal { path, .. } => ("refusal", path),
        RefinementCex::TockRefusal { path, .. } => ("tock-refusal", path),
        RefinementCex::Divergence { path, .. } => ("divergence", path),
    }
}

/// The range of the top-level definition of `name` (`name = …` or
/// `name(…) = …` at the start of a line).
fn definition(text: &str, name: &str) -> Option<TextRange> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        if let Some(rest) = trimmed.strip_prefix(name) {
            if rest.trim_start().starts_with('=') || rest.starts_with('(') {
                let start = u32::try_from(offset + indent).ok()?;
                return Some(TextRange::at(start.into(), u32::try_from(name.len()).ok()?.into()));
            }
        }
        offset += line.len();
    }
    None
}

/// A bounded type's name and least and greatest values.
type BoundedType = (String, crate::ir::Val, crate::ir::Val);

/// The bounded types (`core_nat`, `core_int`, `core_real`,
/// `core_clock_type`) the file's blocks define, as the CSPm engine
/// evaluates them (`union({-2..2}, TemperatureRange)` too): the model is
/// compiled over exactly these values, as RoboTool's script has it.
fn bounded_types(module: &Module, host: &Host<'_>, limits: &Limits) -> Result<Vec<BoundedType>, (Verdict, String)> {
    let defined = module.defined_names();
    let mut ev = Evaluator::new(module, host, limits.clone());
    let mut out = Vec::new();
    for name in ["core_nat", "core_int", "core_real", "core_clock_type"] {
        if !defined.iter().any(|d| d == name) {
            continue;
        }
        let v = ev.value(name).map_err(|d| unsupported(format!("`{name}` could not be evaluated: {}", d.message)))?;
        let ints: Option<Vec<i64>> = match &v {
            robosim_cspm::Value::Set(s) => {
                s.iter().map(|x| if let robosim_cspm::Value::Int(i) = x { Some(*i) } else { None }).collect()
            }
            _ => None,
        };
        // A set of integers without gaps: the native checker's types are
        // ranges.
        match ints.as_deref() {
            Some([lo, .., hi]) if hi - lo + 1 == ints.as_ref().map_or(0, |v| v.len() as i64) => {
                out.push((name.to_string(), *lo, *hi))
            }
            Some([x]) => out.push((name.to_string(), *x, *x)),
            _ => {
                return Err(unsupported(format!(
                    "`{name}` is {v} here: the native checker takes a bounded type as a non-empty range of integers"
                )))
            }
        }
    }
    Ok(out)
}

/// The file's blocks read with the model's names, or why they cannot be
/// (an unknown name, a type error: FDR would not load the script either).
/// Where FDR stops on RoboTool's script of the assertion's file in the
/// semantics checked, if it does: an error of the file's `csp` blocks (an
/// unresolved name, a library name defined again, …) that FDR reports too.
/// FDR loads a script whole, so such an error stands for every assertion
/// of the file, whether it uses the blocks or not.
pub(crate) fn script_error(cx: &Cx<'_>) -> Option<String> {
    let timed = cx.semantics == Semantics::Timed;
    // RT-8: `timed csp` blocks are in the timed script only.
    if !cx.read.csp_blocks.iter().any(|b| timed || !b.timed) {
        return None;
    }
    let script = Script::of(cx);
    let host = Host::resolving(csp_names(cx.db, cx.ws), timed);
    let module = Module::check(&script.text, &host);
    let text = |d: &robosim_cspm::Diagnostic| script.text.get(std::ops::Range::<usize>::from(d.range)).unwrap_or("");
    // Not FDR's errors: what only our CSPm engine does not support, and
    // names RoboTool generates that the bridge does not give.
    let d = module.diagnostics().iter().find(|d| {
        d.severity == Severity::Error
            && d.code != Code::Unsupported
            && !(d.code == Code::Unresolved && host.unsupported(text(d)).is_some())
    })?;
    Some(format!("{}, {}: {}", script.locate(cx, d.range), d.code.as_str(), d.message))
}

fn check_script(cx: &Cx<'_>, script: &Script, host: &Host<'_>) -> Result<Module, (Verdict, String)> {
    let module = Module::check(&script.text, host);
    if let Some(d) = module.diagnostics().iter().find(|d| d.severity == Severity::Error) {
        let text = script.text.get(std::ops::Range::<usize>::from(d.range)).unwrap_or("");
        if let Some(why) = (d.code == Code::Unresolved).then(|| host.unsupported(text)).flatten() {
            return Err(unsupported(why));
        }
        // A `Timed` section needs `tock` too.
        let text = if d.message.contains("channel `tock`") { "tock" } else { text };
        if d.code == Code::Unresolved
            && cx.semantics == Semantics::Untimed
            && (text == "tock" || robosim_hir::csp_defs::defines(text, true))
        {
            // RT-8/RT-9: RoboTool's untimed script has no `tock` and no
            // tock-CSP library, so FDR cannot load it.
            return Err(unsupported(format!(
                "in the untimed semantics: `{text}` ({}) is defined only in RoboTool's timed script (tock-CSP); \
                 RoboTool's untimed script of this file does not define it, so FDR rejects that script (write the \
                 assertion `timed`, or the block without time)",
                script.locate(cx, d.range).trim_start_matches("in ")
            )));
        }
        let what = match d.code {
            Code::Unresolved => "an unresolved name (FDR would reject the script too)",
            Code::Unsupported => "a construct the CSPm engine does not support",
            _ => "an error (FDR would reject the script too)",
        };
        return Err(unsupported(format!(
            "the CSPm of this file's `csp` blocks has {what} {} ({}): {}",
            script.locate(cx, d.range),
            d.code.as_str(),
            d.message
        )));
    }
    Ok(module)
}

/// Whether every `Events` of `text` is the whole argument of `RUN` or
/// `CHAOS`, and `text` hides, projects and renames nothing. Then, in the
/// traces model, `Events` may be read as any set `E'` with Σ ⊆ `E'` ⊆
/// `Events`, Σ the implementation's events: without hiding or renaming
/// every CSP operator is compositional on traces restricted to Σ (a trace
/// of `P [| X |] Q`, `P ; Q`, `P /\ Q`, a choice or a prefix, over Σ, is
/// made of traces over Σ of its parts), and `RUN(E')`, `CHAOS(E')` have
/// the same traces over Σ as `RUN(Events)`; a trace of the implementation
/// is over Σ. The element's own channels give Σ, with the values its
/// events carry (each a value of the channel's type, so `E'` ⊆ `Events`).
fn events_only_run(text: &str) -> bool {
    let hides = text.char_indices().any(|(i, c)| c == '\\' && !text[..i].ends_with('/'));
    if hides || text.contains("[[") {
        return false;
    }
    let word = "Events";
    text.match_indices(word).all(|(i, _)| {
        let before = text[..i].trim_end();
        let after = text[i + word.len()..].trim_start();
        let ident = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '\'');
        if ident(text[..i].chars().next_back()) || ident(text[i + word.len()..].chars().next()) {
            return true; // Part of another name.
        }
        let Some(call) = before.strip_suffix('(') else { return false };
        let call = call.trim_end();
        let callee_ok = ["RUN", "CHAOS"].iter().any(|f| {
            call.strip_suffix(f).is_some_and(|rest| !ident(rest.chars().next_back()) && !rest.ends_with("::"))
        });
        callee_ok && after.starts_with(')')
    })
}

/// Whether `word` occurs in `text` as a whole identifier.
fn mentions(text: &str, word: &str) -> bool {
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        let ident = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '\'');
        !ident(before) && !ident(after)
    })
}

/// A failure that involves a model event with no CSPm name cannot be
/// trusted: the specification could not have named it.
fn check_named<S>(ids: &Names, cex: &RefinementCex<S>) -> Outcome {
    let (path, extra): (_, Vec<Event>) = match cex {
        RefinementCex::Trace { path, .. } | RefinementCex::Divergence { path, .. } => (path, Vec::new()),
        RefinementCex::Refusal { path, offered, acceptances }
        | RefinementCex::TockRefusal { path, offered, acceptances } => {
            (path, offered.iter().chain(acceptances.iter().flatten()).copied().collect())
        }
    };
    let unnamed = path.steps.iter().map(|(l, _)| l.event).chain(extra).find(|&e| ids.unnamed(e));
    match unnamed {
        Some(e) => Err(unsupported(format!(
            "the model's event `{}` has no name in RoboTool's CSPm, so the specification cannot refer to it",
            ids.name(e)
        ))),
        None => Ok(()),
    }
}

fn event_set<L: Lts>(lts: &L, events: &[Event]) -> String {
    format!("{{{}}}", events.iter().map(|e| lts.event_name(*e)).collect::<Vec<_>>().join(", "))
}

/// What the implementation does that the specification does not allow.
fn describe<L: Lts, S>(imp: &L, cex: &RefinementCex<S>) -> String {
    match cex {
        RefinementCex::Trace { event, .. } => {
            format!("perform `{}` where the specification cannot", imp.event_name(event.event))
        }
        RefinementCex::Refusal { offered, acceptances, .. } => {
            let sets: Vec<String> = acceptances.iter().map(|acc| event_set(imp, acc)).collect();
            format!(
                "offer only {}, where the specification, after the same trace, offers all of {}",
                event_set(imp, offered),
                if sets.is_empty() {
                    "its events".to_string()
                } else {
                    sets.join(" (or all of ") + &")".repeat(sets.len() - 1)
                }
            )
        }
        RefinementCex::TockRefusal { offered, .. } => {
            format!("let time pass offering only {}", event_set(imp, offered))
        }
        RefinementCex::Divergence { .. } => "diverge (compute forever)".into(),
    }
}

/// The counterexample: the model's steps, events in CSPm names, and where
/// the specification is and what it allowed.
fn counterexample<L: Lts<State = crate::pack::Packed>>(
    imp: &Imp<'_, L>,
    spec: &SpecLts<'_>,
    design: &crate::ir::Design,
    cex: &RefinementCex<lts::ImpState<crate::pack::Packed>>,
    native: &native::NativeLts<'_>,
    spec_name: &str,
    def_at: &str,
) -> Counterexample {
    let (kind, path) = match cex {
        RefinementCex::Trace { path, .. } => ("trace", path),
        RefinementCex::Refusal { path, .. } => ("refusal", path),
        RefinementCex::TockRefusal { path, .. } => ("tock-refusal", path),
        RefinementCex::Divergence { path, .. } => ("divergence", path),
    };
    let mut steps = Vec::new();
    let mut prev = native.values(&path.initial.inner);
    let mut time = 0;
    for (label, st) in &path.steps {
        let next = native.values(&st.inner);
        let event = label.shown(|e| imp.event_name(e), |n| native.event_name(n));
        let (description, location) = crate::verify::describe_move(design, &prev, &next, label);
        steps.push(Step { event, visible: label.event != TAU, cycle: time, time, description, location });
        if label.event == TOCK {
            time += 1;
        }
        prev = next;
    }
    let trace: Vec<String> = path.trace().iter().map(|e| spec.event_name(*e)).collect();
    let explanation = refused_by_spec(format!("the model can {}", describe(imp, cex)), spec_name, def_at, &trace);
    Counterexample { kind, steps, explanation, stuck_at: Vec::new(), specification: Vec::new() }
}

/// The explanation of a refinement counterexample: what the other side can
/// do, and where the specification (its block and line) refuses it.
fn refused_by_spec(can: String, spec_name: &str, def_at: &str, trace: &[String]) -> Vec<String> {
    vec![
        can,
        format!(
            "the specification `{spec_name}` ({}) after ⟨{}⟩ does not allow it",
            def_at.trim_start_matches("in "),
            trace.join(", ")
        ),
    ]
}
