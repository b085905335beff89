//! Running the assertions of a workspace's assertion files: find what each
//! one names, compile it, run the check, and explain the result in the
//! modeller's terms (verdict, statistics, a counterexample grouped by cycle
//! and mapped to source).

use std::time::Instant;

use robosim_hir::model::assertion_file;
use robosim_hir::{Db, File, TextRange, Workspace};

use crate::algo::{
    check_determinism, find_deadlock, find_divergence, find_event, find_timed_deadlock, find_timelock, refines,
    DeadlockResult, DeterminismResult, DivergenceResult, EventResult, Path, RefinementCex, RefinementResult,
    SemanticModel, TimedDeadlockResult, TimelockResult,
};
use crate::assertions::{AssertionDecl, AssertionFile, AssertionKind, SemanticModelName, Value};
use crate::budget::{Budget, ProgressFn, Stats};
use crate::design::{shared_events, DesignLts, Reach};
use crate::ir::{Design, Instr, Val};
use crate::lower::{lower_element, ConstValue, DomainDefaults, Unsupported};
use crate::lts::{Event, Label, Lts, TAU, TICK, TOCK};
use crate::machine::{Act, Offer};
use crate::pack::{Packed, VectorLts};
use crate::sched::{Constrained, Registers, State};
use crate::sim::SimModule;
use robosim_hir::target::{Scope, Subject as Target};

pub use crate::ir::AsyncBuffer;
pub use crate::sched::Profile;
pub use crate::untimed::Semantics;

mod params;
mod robosim;
mod semantics;

/// How to run checks.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The semantics.
    pub profile: Profile,
    /// Limits on the search.
    pub budget: Budget,
    /// The buffer assumed for asynchronous connections between machines or
    /// controllers (none: RoboTool's one-place overwriting buffer, RT-12).
    pub async_buffer: Option<AsyncBuffer>,
}

/// The outcome of one assertion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The assertion, as written (with its `not`), holds.
    Pass,
    /// It does not hold.
    Fail,
    /// The search ran out of budget or met a run-time error.
    Inconclusive,
    /// The engine cannot check this assertion (yet): see the reason.
    Unsupported,
}

impl Verdict {
    /// `pass`, `fail`, `inconclusive`, `unsupported`.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::Inconclusive => "inconclusive",
            Verdict::Unsupported => "unsupported",
        }
    }
}

/// A source location.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file's path.
    pub file: String,
    /// The range in it.
    pub range: TextRange,
}

/// One step of a counterexample.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    /// The event as the check sees it (`registerRead.i_obstacle.true`,
    /// `tock`), or the hidden design event in parentheses (`(moveCall.1.0)`),
    /// or `τ` for an internal step.
    pub event: String,
    /// Whether the event is visible (register reads and writes, `tock`).
    pub visible: bool,
    /// The cycle it belongs to (0-based).
    pub cycle: u32,
    /// Time units elapsed before it.
    pub time: u32,
    /// What the design did, in words, if it moved.
    pub description: Option<String>,
    /// Where in the model.
    pub location: Option<Location>,
}

/// A counterexample.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Counterexample {
    /// `deadlock`, …
    pub kind: &'static str,
    /// The steps from the initial state.
    pub steps: Vec<Step>,
    /// Why nothing more can happen at the end, one sentence per line.
    pub explanation: Vec<String>,
    /// Source locations involved in the stuck point.
    pub stuck_at: Vec<Location>,
    /// For a refinement: what the specification (the design) does on the
    /// same visible trace, its own hidden steps located in its source.
    pub specification: Vec<Step>,
}

/// The report on one assertion.
#[derive(Debug, Clone)]
pub struct Report {
    /// The assertion file's path.
    pub file: String,
    /// The assertion's name.
    pub name: String,
    /// Its text, on one line.
    pub text: String,
    /// Its range in the file.
    pub range: TextRange,
    /// The assertion name's range.
    pub name_range: TextRange,
    /// The verdict.
    pub verdict: Verdict,
    /// Search statistics.
    pub stats: Stats,
    /// Why (unsupported, inconclusive), or a one-line summary of a failure.
    pub reason: Option<String>,
    /// For a failure (or a negated assertion that passes): the witness.
    pub counterexample: Option<Counterexample>,
    /// Notes (domains used, saturated arithmetic …).
    pub notes: Vec<String>,
    /// The semantics it was checked in (RT-8: a plain assertion has a
    /// report for each).
    pub semantics: Semantics,
}

/// Runs every assertion of the workspace made of `files` (path, text) and
/// the bundled library, with the paper's rule set: for tests, fuzzing and
/// embedding, where there is no database yet.
pub fn verify_texts(files: impl IntoIterator<Item = (String, String)>, opts: &Options) -> Vec<Report> {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&db, files, robosim_hir::RuleSet::Paper);
    verify_workspace(&db, ws, opts, None)
}

/// Runs every assertion of every assertion file of the workspace.
pub fn verify_workspace(db: &dyn Db, ws: Workspace, opts: &Options, progress: Option<ProgressFn>) -> Vec<Report> {
    let mut out = Vec::new();
    for &file in ws.files(db) {
        if file.is_library(db) || !file.kind(db).is_assertions() {
            continue;
        }
        out.extend(verify_file(db, ws, file, opts, progress));
    }
    out
}

/// The assertion files of the workspace, read.
fn all_assertion_files(db: &dyn Db, ws: Workspace) -> Vec<(File, AssertionFile)> {
    ws.files(db)
        .iter()
        .filter(|f| !f.is_library(db) && f.kind(db).is_assertions())
        .map(|&f| (f, assertion_file(db, f).clone()))
        .collect()
}

/// Runs the assertions of one file.
pub fn verify_file(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    opts: &Options,
    progress: Option<ProgressFn>,
) -> Vec<Report> {
    let read = assertion_file(db, file).clone();
    let others = all_assertion_files(db, ws);
    read.assertions.iter().flat_map(|a| verify_assertion(db, ws, file, &read, &others, a, opts, progress)).collect()
}

/// Runs one assertion of `file` (read as `read`): a report for each
/// semantics it is checked in (RT-8), the timed one first. A plain
/// assertion about a RoboChart element is checked in both; one that only
/// has a timed meaning (RoboSim, simulations, schedulability,
/// timelock-freedom) in the timed semantics only.
#[allow(clippy::too_many_arguments)]
pub fn verify_assertion(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    read: &AssertionFile,
    others: &[(File, AssertionFile)],
    a: &AssertionDecl,
    opts: &Options,
    progress: Option<ProgressFn>,
) -> Vec<Report> {
    let cx = |semantics| Cx { db, ws, file, read, others, a, async_buffer: opts.async_buffer, semantics };
    let timing = robosim_hir::target::timing(a);
    let mut out = Vec::new();
    if timing.timed {
        out.push(verify_in(&cx(Semantics::Timed), opts, progress));
    }
    if timing.untimed && (!timing.timed || semantics::has_untimed_reading(&cx(Semantics::Untimed)).is_ok()) {
        out.push(verify_in(&cx(Semantics::Untimed), opts, progress));
    }
    out
}

/// Runs one assertion in one semantics.
fn verify_in(cx: &Cx<'_>, opts: &Options, progress: Option<ProgressFn>) -> Report {
    let (db, file, a) = (cx.db, cx.file, cx.a);
    let started = Instant::now();
    let mut report = Report {
        file: file.path(db).clone(),
        name: a.name.clone(),
        text: a.text.clone(),
        range: a.range,
        name_range: a.name_range,
        verdict: Verdict::Unsupported,
        stats: Stats::default(),
        reason: None,
        counterexample: None,
        notes: Vec::new(),
        semantics: cx.semantics,
    };
    if let Some(p) = a.problems.first() {
        report.reason = Some(format!("the assertion is incomplete: {}", p.message));
        return report;
    }
    if let Err(why) = semantics::check_untimed_reading(cx) {
        report.reason = Some(why);
        return report;
    }
    match &a.kind {
        AssertionKind::Schedulable => schedulable(cx, opts, progress, &mut report),
        AssertionKind::Refines { other, model, .. } => {
            refinement(cx, other, *model, false, opts, progress, &mut report)
        }
        AssertionKind::Equals { other, model, .. } => refinement(cx, other, *model, true, opts, progress, &mut report),
        AssertionKind::DeadlockFree
        | AssertionKind::TimelockFree
        | AssertionKind::DivergenceFree
        | AssertionKind::Deterministic
        | AssertionKind::Terminates
        | AssertionKind::Reachable { .. } => property(cx, opts, progress, &mut report),
        AssertionKind::Probabilistic { .. } => {
            report.reason = Some("probabilistic properties are checked with PRISM".into());
        }
        AssertionKind::ClockInitialised { .. } => {
            // RT-10: RoboTool's authors commented such assertions out.
            report.reason = Some(
                "`clock … is initialised` assertions are not supported by RoboTool 3's semantics either \
                 (it generates no encoding for them), so there is no verdict to match"
                    .into(),
            );
        }
        other => {
            report.reason = Some(format!("`{}` assertions are not supported by the native checker yet", other.label()));
        }
    }
    if report.stats.seconds == 0.0 {
        report.stats.seconds = started.elapsed().as_secs_f64();
    }
    report
}

/// Everything an assertion's check needs from the workspace.
pub(crate) struct Cx<'a> {
    pub(crate) db: &'a dyn Db,
    pub(crate) ws: Workspace,
    pub(crate) file: File,
    pub(crate) read: &'a AssertionFile,
    others: &'a [(File, AssertionFile)],
    pub(crate) a: &'a AssertionDecl,
    /// The buffer assumed for asynchronous connections, if any.
    async_buffer: Option<AsyncBuffer>,
    /// The semantics checked in.
    pub(crate) semantics: Semantics,
}

impl Cx<'_> {
    /// What `path`, a side of the assertion, denotes (hir's one reading).
    pub(crate) fn target(&self, path: &[String]) -> Result<Target, String> {
        let scope = Scope { db: self.db, ws: self.ws, file: self.file, read: self.read, others: self.others };
        match robosim_hir::target::subject(scope, self.a, path)? {
            Target::Simulation { name, inner: Some(_), .. } => Err(format!(
                "`{name}` is a RoboSim state machine declared inside its controller: the native checker \
                 takes top-level RoboSim machines, controllers and modules only so far (check the controller)"
            )),
            target => Ok(target),
        }
    }

    /// The constant values the assertion gives.
    pub(crate) fn constants(&self) -> Result<Vec<ConstValue>, String> {
        let scope = Scope { db: self.db, ws: self.ws, file: self.file, read: self.read, others: self.others };
        let mut out: Vec<ConstValue> = robosim_hir::target::bindings_in(scope, self.a)?
            .into_iter()
            .map(|b| ConstValue { name: b.name, of: b.of, value: b.value as Val })
            .collect();
        out.extend(params::parameter_values(self.a)?);
        Ok(out)
    }

    /// The bounded types, from `nametype core_X = {a..b}` lines.
    fn defaults(&self) -> DomainDefaults {
        let mut defaults = DomainDefaults {
            async_buffer: self.async_buffer,
            replaced: self.read.csp_blocks.iter().any(|b| b.name == "Instantiations"),
            ..DomainDefaults::default()
        };
        for r in std::iter::once(self.read).chain(self.others.iter().map(|(_, r)| r)) {
            for (name, lo, hi, _) in &r.instantiations.types {
                defaults.set(name, *lo, *hi);
            }
            for (name, value, _) in &r.instantiations.constants {
                let v = match value {
                    Value::Int(v) => *v,
                    Value::Bool(b) => *b as Val,
                    Value::Other(_) => continue,
                };
                defaults.constants.push((name.clone(), v));
            }
            // A function's clauses come from one file: this assertion's
            // first, then the others'.
            let known: Vec<String> = defaults.functions.iter().map(|f| f.name.clone()).collect();
            defaults.functions.extend(r.instantiations.functions.iter().filter(|f| !known.contains(&f.name)).cloned());
        }
        defaults
    }

    /// The compiled element of `target` and its period.
    pub(crate) fn compile(&self, target: &Target, consts: &[ConstValue]) -> Result<(Design, u32), String> {
        self.compile_with_types(target, consts, &[])
    }

    /// [`Cx::compile`] with bounded types `(core_X, lo, hi)` the assertion
    /// file's `csp` blocks define (evaluated by the CSPm engine, so also
    /// when written as more than a plain range).
    pub(crate) fn compile_with_types(
        &self,
        target: &Target,
        consts: &[ConstValue],
        types: &[(String, Val, Val)],
    ) -> Result<(Design, u32), String> {
        let (name, loc, period) = match target {
            Target::Constrained { name, loc, period, .. } | Target::Simulation { name, loc, period, .. } => {
                (name, *loc, *period)
            }
            // A design on its own has no period.
            Target::Design { name, loc, .. } => (name, *loc, Some(1)),
        };
        let inner = match target {
            Target::Design { inner, .. } => inner.as_deref(),
            _ => None,
        };
        let Some(period) = period.filter(|p| (1..=1_000).contains(p)) else {
            return Err(format!("`{name}` has no cycle period from 1 to 1000: give one with `cycleDef cycle == N`"));
        };
        let mut defaults = self.defaults();
        for (name, lo, hi) in types {
            defaults.set(name, *lo, *hi);
        }
        let design = lower_element(self.db, self.ws, loc, inner, consts, &defaults)
            .map_err(|u| unsupported_reason(self.db, self.ws, &u))?;
        Ok((design, period as u32))
    }
}

/// Any element of a check, as one LTS type.
enum Side<'a> {
    Design(Constrained<'a>),
    Sim(SimModule<'a>),
    Plain(DesignLts<'a>),
}

impl Side<'_> {
    /// The state vector of a packed state.
    fn values(&self, st: &Packed) -> State {
        match self {
            Side::Design(l) => l.values(st),
            Side::Sim(l) => l.values(st),
            Side::Plain(l) => l.values(st),
        }
    }

    fn error(&self) -> Option<String> {
        match self {
            Side::Design(l) => l.error(),
            Side::Sim(l) => l.error(),
            Side::Plain(l) => l.error(),
        }
    }
}

impl Lts for Side<'_> {
    type State = Packed;

    fn initial(&self) -> Packed {
        match self {
            Side::Design(l) => l.initial(),
            Side::Sim(l) => l.initial(),
            Side::Plain(l) => l.initial(),
        }
    }

    fn successors(&self, st: &Packed, out: &mut Vec<(Label, Packed)>) {
        match self {
            Side::Design(l) => l.successors(st, out),
            Side::Sim(l) => l.successors(st, out),
            Side::Plain(l) => l.successors(st, out),
        }
    }

    fn event_name(&self, e: crate::lts::Event) -> String {
        match self {
            Side::Design(l) => l.event_name(e),
            Side::Sim(l) => l.event_name(e),
            Side::Plain(l) => l.event_name(e),
        }
    }

    fn state_bytes(&self, st: &Packed) -> usize {
        match self {
            Side::Design(l) => l.state_bytes(st),
            Side::Sim(l) => l.state_bytes(st),
            Side::Plain(l) => l.state_bytes(st),
        }
    }

    fn state_width(&self) -> usize {
        match self {
            Side::Design(l) => l.state_width(),
            Side::Sim(l) => l.state_width(),
            Side::Plain(l) => l.state_width(),
        }
    }

    fn encode(&self, st: &Packed, row: &mut [u8]) {
        match self {
            Side::Design(l) => l.encode(st, row),
            Side::Sim(l) => l.encode(st, row),
            Side::Plain(l) => l.encode(st, row),
        }
    }

    fn decode(&self, row: &[u8]) -> Packed {
        match self {
            Side::Design(l) => l.decode(row),
            Side::Sim(l) => l.decode(row),
            Side::Plain(l) => l.decode(row),
        }
    }

    fn successor_rows(&self, row: &[u8], out: &mut crate::lts::Rows<Packed>) {
        match self {
            Side::Design(l) => l.successor_rows(row, out),
            Side::Sim(l) => l.successor_rows(row, out),
            Side::Plain(l) => l.successor_rows(row, out),
        }
    }
}

fn side<'a>(
    target: &Target,
    design: &'a Design,
    period: u32,
    regs: &Registers,
    profile: Profile,
) -> Result<Side<'a>, String> {
    Ok(match target {
        Target::Constrained { .. } => {
            Side::Design(Constrained::with_registers(design, period, profile, Some(regs), false)?)
        }
        Target::Simulation { .. } => Side::Sim(SimModule::with_profile(design, period, regs, profile)?),
        Target::Design { name, .. } => {
            return Err(format!(
                "`{name}` is a RoboChart element: it can be compared with another RoboChart element, or as `simulation S of {name}` with a simulation"
            ))
        }
    })
}

/// The LTS of `target` on its own (for properties of one element).
fn single<'a>(target: &Target, design: &'a Design, period: u32, profile: Profile) -> Result<Side<'a>, String> {
    Ok(match target {
        Target::Design { .. } => Side::Plain(DesignLts::new(design)?),
        _ => {
            let regs = Registers::new(&[design], profile)?;
            side(target, design, period, &regs, profile)?
        }
    })
}

#[allow(clippy::too_many_arguments)]
fn schedulable(cx: &Cx<'_>, opts: &Options, progress: Option<ProgressFn>, report: &mut Report) {
    let a = cx.a;
    let mut run = || -> Result<(), String> {
        let target = cx.target(&a.subject)?;
        let Target::Constrained { .. } = target else {
            return Err(format!("`{}` is not a `simulation … of …` declaration", a.subject.join("::")));
        };
        let (design, period) = cx.compile(&target, &cx.constants()?)?;
        let lts = Constrained::new(&design, period, opts.profile)?;
        report.notes.push(domains_note(&design));
        let (result, stats) = find_deadlock(&lts, &opts.budget, progress);
        report.stats = stats;
        if let Some(err) = lts.error() {
            report.verdict = Verdict::Inconclusive;
            report.reason = Some(format!("the model met a run-time error: {err}"));
            return Ok(());
        }
        let holds = match result {
            DeadlockResult::Free => true,
            DeadlockResult::Deadlock(path) => {
                report.counterexample = Some(deadlock_counterexample(&lts, &design, &path));
                false
            }
            DeadlockResult::Inconclusive(stop) => {
                report.verdict = Verdict::Inconclusive;
                report.reason = Some(stop.reason(&opts.budget));
                return Ok(());
            }
        };
        report.verdict = if holds != a.negated { Verdict::Pass } else { Verdict::Fail };
        report.reason = Some(if holds {
            format!("{} can be scheduled in cycles of period {period}", design.name)
        } else {
            format!("{} cannot be scheduled in cycles of period {period}", design.name)
        });
        Ok(())
    };
    if let Err(e) = run() {
        report.verdict = Verdict::Unsupported;
        report.reason = Some(e);
    }
}

/// `X refines Y` (Y ⊑ X), `X equals Y` (both), in the named model.
fn refinement(
    cx: &Cx<'_>,
    other: &[String],
    model: SemanticModelName,
    both_ways: bool,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) {
    let a = cx.a;
    let model = match model {
        SemanticModelName::Traces => SemanticModel::Traces,
        SemanticModelName::Failures => SemanticModel::Failures,
        SemanticModelName::FailuresDivergences | SemanticModelName::Default => SemanticModel::FailuresDivergences,
        SemanticModelName::TickTock => SemanticModel::TickTock,
    };
    // A side defined in a `csp` block of this file: the CSPm bridge.
    if crate::csp::is_block(cx, other) || crate::csp::is_block(cx, &a.subject) {
        return crate::csp::refinement(cx, other, model, both_ways, opts, progress, report);
    }
    let mut run = || -> Result<(), String> {
        let consts = cx.constants()?;
        let imp_t = cx.target(&a.subject)?;
        let spec_t = cx.target(other)?;
        let (imp_d, imp_p) = cx.compile(&imp_t, &consts)?;
        let (spec_d, spec_p) = cx.compile(&spec_t, &consts)?;
        let (imp_d, spec_d) = (cx.in_semantics(imp_d)?, cx.in_semantics(spec_d)?);
        let (imp, spec) = match (&imp_t, &spec_t) {
            // Two RoboChart designs: their own events, matched by name.
            (Target::Design { .. }, Target::Design { .. }) => {
                let events = shared_events(&[&spec_d, &imp_d])?;
                (
                    Side::Plain(cx.plain(DesignLts::with_events(&imp_d, &events)?)),
                    Side::Plain(cx.plain(DesignLts::with_events(&spec_d, &events)?)),
                )
            }
            _ => {
                let regs = Registers::new(&[&spec_d, &imp_d], opts.profile)?;
                let imp = side(&imp_t, &imp_d, imp_p, &regs, opts.profile)?;
                let spec = side(&spec_t, &spec_d, spec_p, &regs, opts.profile)?;
                robosim::constrained_alphabet((imp, &imp_d), (spec, &spec_d), report)
            }
        };
        report.notes.push(domains_note(&spec_d));
        // Both sides usually share domains and constants: one note then.
        let imp_note = domains_note(&imp_d);
        if !report.notes.contains(&imp_note) {
            report.notes.push(imp_note);
        }
        let mut directions = vec![(&spec, &imp, &spec_d, &imp_d, "")];
        if both_ways {
            directions.push((&imp, &spec, &imp_d, &spec_d, " (converse)"));
        }
        let mut holds = true;
        for (sp, im, sp_design, im_design, which) in directions {
            let (result, stats) = refines(sp, im, model, &opts.budget, progress);
            report.stats.states += stats.states;
            report.stats.transitions += stats.transitions;
            report.stats.seconds += stats.seconds;
            if let Some(err) = sp.error().or_else(|| im.error()) {
                report.verdict = Verdict::Inconclusive;
                report.reason = Some(format!("the model met a run-time error: {err}"));
                return Ok(());
            }
            match result {
                RefinementResult::Holds => {}
                RefinementResult::Fails(cex) => {
                    let mut c = refinement_counterexample(im, sp, im_design, &cex);
                    c.specification = specification_steps(sp, sp_design, &cex, &opts.budget);
                    report.counterexample = Some(c);
                    report.reason = Some(format!("refinement{which} fails: {}", describe_cex(im, sp, &cex)));
                    holds = false;
                    break;
                }
                RefinementResult::Inconclusive(stop) => {
                    report.verdict = Verdict::Inconclusive;
                    report.reason = Some(stop.reason(&opts.budget));
                    return Ok(());
                }
            }
        }
        if holds {
            report.reason = Some(format!(
                "{} {} {}",
                a.subject.join("::"),
                if both_ways { "equals" } else { "refines" },
                other.join("::")
            ));
        }
        report.verdict = if holds != a.negated { Verdict::Pass } else { Verdict::Fail };
        Ok(())
    };
    if let Err(e) = run() {
        report.verdict = Verdict::Unsupported;
        report.reason = Some(e);
    }
}

/// Why time cannot pass at `state`, a stable state without `tock`: what
/// it offers (which the environment may refuse), or that it has ended.
fn timelock_reason(lts: &Side<'_>, state: &Packed) -> String {
    let mut succ = Vec::new();
    lts.successors(state, &mut succ);
    let mut offered: Vec<String> = Vec::new();
    for (label, _) in &succ {
        let e = lts.event_name(label.event);
        if !offered.contains(&e) {
            offered.push(e);
        }
    }
    match offered.as_slice() {
        [] => "nothing can happen here, not even time passing".into(),
        [only] if only == "✓" => {
            "it has terminated: time cannot pass (RT-10 counts termination as a timelock)".into()
        }
        _ => format!(
            "time cannot pass until one of {{{}}} happens, and the environment may refuse them (RT-10)",
            offered.join(", ")
        ),
    }
}

/// Whether a property holds, its witness (kind, path, what happens at its
/// end), and the verdict in words.
type Outcome = (bool, Option<(&'static str, Path<Packed>, String)>, String);

/// A property of one element: `deadlock-free` (semantics.md §7.4: no
/// reachable state from which only time passes), `timelock-free` (no state
/// where nothing, not even time, can happen), `divergence-free`,
/// `deterministic`, `S is reachable in M`.
fn property(cx: &Cx<'_>, opts: &Options, progress: Option<ProgressFn>, report: &mut Report) {
    let a = cx.a;
    let mut run = || -> Result<(), String> {
        let subject = match &a.kind {
            AssertionKind::Reachable { machine, .. } => machine.clone(),
            _ => a.subject.clone(),
        };
        let target = cx.target(&subject)?;
        let (design, period) = cx.compile(&target, &cx.constants()?)?;
        let design = cx.in_semantics(design)?;
        let lts = match cx.semantics {
            Semantics::Timed => single(&target, &design, period, opts.profile)?,
            Semantics::Untimed => Side::Plain(DesignLts::new(&design)?.without_time()),
        };
        report.notes.push(domains_note(&design));
        let name = subject.join("::");
        if cx.semantics == Semantics::Untimed && a.kind == AssertionKind::Terminates {
            semantics::terminates_without_divergence(&lts, &name, opts)?;
        }
        // (holds, counterexample kind, path, explanation) or a stop.
        let outcome: Result<Outcome, crate::budget::Stop> = match &a.kind {
            AssertionKind::DeadlockFree if cx.semantics == Semantics::Untimed => {
                semantics::deadlock_free(&lts, &name, opts, progress, report)
            }
            AssertionKind::DeadlockFree => {
                let (r, stats) = find_timed_deadlock(&lts, &opts.budget, progress);
                report.stats = stats;
                match r {
                    TimedDeadlockResult::Free => {
                        Ok((true, None, format!("{name} never reaches a state where only time passes")))
                    }
                    TimedDeadlockResult::TimedDeadlock { path, .. } => Ok((
                        false,
                        Some(("timed deadlock", path, "from here only time passes".into())),
                        format!("{name} reaches a state where only time passes (a timed deadlock)"),
                    )),
                    TimedDeadlockResult::Inconclusive(stop) => Err(stop),
                }
            }
            AssertionKind::TimelockFree => {
                // RT-10: the environment may refuse every event, so a
                // stable state without `tock` stops time.
                let (r, stats) = find_timelock(&lts, &opts.budget, progress);
                report.stats = stats;
                match r {
                    TimelockResult::Free => Ok((true, None, format!("time can always pass in {name}"))),
                    TimelockResult::Timelock(path) => {
                        let why = timelock_reason(&lts, path.last());
                        Ok((false, Some(("timelock", path, why)), format!("{name} reaches a timelock")))
                    }
                    TimelockResult::Inconclusive(stop) => Err(stop),
                }
            }
            AssertionKind::Terminates => {
                // RT-10: ✓ is reachable, and the process deadlocks only
                // after ✓ (a state reached by ✓ is not a deadlock).
                let (r, stats) = find_deadlock(&lts, &opts.budget, progress);
                report.stats = stats;
                match r {
                    DeadlockResult::Deadlock(path) => Ok((
                        false,
                        Some(("deadlock", path, "nothing can happen here, and it has not terminated".into())),
                        format!("{name} can deadlock before it terminates"),
                    )),
                    DeadlockResult::Inconclusive(stop) => Err(stop),
                    DeadlockResult::Free => {
                        let (r, stats) = find_event(&lts, TICK, &opts.budget, progress);
                        report.stats.states += stats.states;
                        report.stats.transitions += stats.transitions;
                        report.stats.seconds += stats.seconds;
                        match r {
                            EventResult::Reached(path) => Ok((
                                true,
                                Some(("termination", path, "it terminates here".into())),
                                format!("{name} terminates, and deadlocks only after it has"),
                            )),
                            EventResult::Unreachable => Ok((false, None, format!("{name} never terminates"))),
                            EventResult::Inconclusive(stop) => Err(stop),
                        }
                    }
                }
            }
            AssertionKind::DivergenceFree => {
                let (r, stats) = find_divergence(&lts, &opts.budget, progress);
                report.stats = stats;
                match r {
                    DivergenceResult::Free => {
                        let without = if cx.semantics == Semantics::Timed { " without time passing" } else { "" };
                        Ok((true, None, format!("{name} never computes forever{without}")))
                    }
                    DivergenceResult::Divergent { path, .. } => Ok((
                        false,
                        Some(("divergence", path, "from here it can compute forever".into())),
                        format!("{name} can diverge"),
                    )),
                    DivergenceResult::Inconclusive(stop) => Err(stop),
                }
            }
            AssertionKind::Deterministic => {
                let (r, stats) = check_determinism(&lts, &opts.budget, progress);
                report.stats = stats;
                match r {
                    DeterminismResult::Deterministic => Ok((true, None, format!("{name} is deterministic"))),
                    DeterminismResult::Nondeterministic { path, event } => Ok((
                        false,
                        Some((
                            "nondeterminism",
                            path,
                            format!("here {} may be refused or performed", lts.event_name(event)),
                        )),
                        format!("{name} is not deterministic"),
                    )),
                    DeterminismResult::Divergent { path, .. } => Ok((
                        false,
                        Some(("divergence", path, "from here it can compute forever".into())),
                        format!("{name} can diverge, so it is not deterministic"),
                    )),
                    DeterminismResult::Inconclusive(stop) => Err(stop),
                }
            }
            AssertionKind::Reachable { state, .. } => {
                let Side::Plain(plain) = &lts else {
                    return Err("reachability is checked for RoboChart machines only so far".into());
                };
                let target_state = |st: &Packed| plain.in_state(&plain.values(st), state);
                let reach = Reach { lts: plain, target: &target_state };
                let (r, stats) = find_deadlock(&reach, &opts.budget, progress);
                report.stats = stats;
                let sname = state.join("::");
                match r {
                    DeadlockResult::Free => Ok((false, None, format!("{sname} is not reachable in {name}"))),
                    DeadlockResult::Deadlock(path) => Ok((
                        true,
                        Some(("reachability", path, format!("{sname} is entered here"))),
                        format!("{sname} is reachable in {name}"),
                    )),
                    DeadlockResult::Inconclusive(stop) => Err(stop),
                }
            }
            other => return Err(format!("`{}` assertions are not supported by the native checker yet", other.label())),
        };
        if let Some(err) = lts.error() {
            report.verdict = Verdict::Inconclusive;
            report.reason = Some(format!("the model met a run-time error: {err}"));
            return Ok(());
        }
        match outcome {
            Ok((holds, witness, reason)) => {
                if let Some((kind, path, why)) = witness {
                    let values = values_path(&path, |p| lts.values(p));
                    let steps = sim_steps(&lts, &design, &values);
                    let mut explanation = vec![why];
                    if kind == "timelock" {
                        let last = values.steps.last().map_or(&values.initial, |(_, s)| s);
                        explanation.extend(design.machines.iter().flat_map(|m| m.tock_blockers(last)));
                    }
                    explanation.extend(saturation_note(&steps));
                    report.counterexample = Some(Counterexample {
                        kind,
                        steps,
                        explanation,
                        stuck_at: Vec::new(),
                        specification: Vec::new(),
                    });
                }
                report.reason = Some(reason);
                report.verdict = if holds != a.negated { Verdict::Pass } else { Verdict::Fail };
            }
            Err(stop) => {
                report.verdict = Verdict::Inconclusive;
                report.reason = Some(stop.reason(&opts.budget));
            }
        }
        Ok(())
    };
    if let Err(e) = run() {
        report.verdict = Verdict::Unsupported;
        report.reason = Some(e);
    }
}

/// `{a, b}` with the events' names.
fn event_set<L: Lts>(lts: &L, events: &[Event]) -> String {
    format!("{{{}}}", events.iter().map(|e| lts.event_name(*e)).collect::<Vec<_>>().join(", "))
}

fn describe_cex<L: Lts, S: Lts, X>(imp: &L, spec: &S, cex: &RefinementCex<X>) -> String {
    let _ = spec;
    match cex {
        RefinementCex::Trace { event, .. } => {
            format!("the implementation can perform {} where the specification cannot", imp.event_name(event.event))
        }
        RefinementCex::Refusal { acceptances, .. } => {
            let sets: Vec<String> = acceptances.iter().map(|acc| event_set(imp, acc)).collect();
            format!("the implementation refuses every event the specification must offer: one of {}", sets.join(" or "))
        }
        RefinementCex::TockRefusal { offered, acceptances, .. } => {
            let offered: Vec<Event> = offered.iter().copied().filter(|&e| e != TOCK).collect();
            let then = if acceptances.is_empty() {
                "the specification cannot let time pass after the same trace".to_string()
            } else {
                let sets: Vec<String> = acceptances
                    .iter()
                    .map(|acc| event_set(imp, &acc.iter().copied().filter(|&e| e != TOCK).collect::<Vec<_>>()))
                    .collect();
                format!(
                    "the specification lets time pass after the same trace only while offering {}",
                    sets.join(" or ")
                )
            };
            format!(
                "the implementation lets time pass while offering only {} (tick-tock model); {then}",
                event_set(imp, &offered)
            )
        }
        RefinementCex::Divergence { .. } => "the implementation can compute forever without finishing its cycle".into(),
    }
}

fn refinement_counterexample<S: Lts>(
    imp: &Side<'_>,
    spec: &S,
    design: &Design,
    cex: &RefinementCex<Packed>,
) -> Counterexample {
    let (kind, path) = match cex {
        RefinementCex::Trace { path, .. } => ("trace", path),
        RefinementCex::Refusal { path, .. } => ("refusal", path),
        RefinementCex::TockRefusal { path, .. } => ("tock-refusal", path),
        RefinementCex::Divergence { path, .. } => ("divergence", path),
    };
    let steps = sim_steps(imp, design, &values_path(path, |p| imp.values(p)));
    let mut explanation = vec![describe_cex(imp, spec, cex)];
    explanation.extend(saturation_note(&steps));
    Counterexample { kind, steps, explanation, stuck_at: Vec::new(), specification: Vec::new() }
}

/// What the specification does on the counterexample's visible trace (up
/// to the offending event): the shortest run of `spec` with that trace,
/// found breadth first within a small budget, as located steps.
fn specification_steps(spec: &Side<'_>, design: &Design, cex: &RefinementCex<Packed>, budget: &Budget) -> Vec<Step> {
    let (path, drop_last) = match cex {
        // The offending step (an event, or the `tock` refused too much
        // before) is not the specification's.
        RefinementCex::Trace { path, .. } | RefinementCex::TockRefusal { path, .. } => (path, true),
        RefinementCex::Refusal { path, .. } | RefinementCex::Divergence { path, .. } => (path, false),
    };
    let mut trace: Vec<crate::lts::Event> = path.steps.iter().map(|(l, _)| l.event).filter(|&e| e != TAU).collect();
    if drop_last {
        trace.pop();
    }
    let limit = budget.max_states.min(200_000) as usize;
    let start = spec.initial();
    // (state, events of the trace done) → how it was reached.
    type Node = (Packed, usize);
    let mut parent: std::collections::HashMap<Node, Option<(Node, Label)>> = std::collections::HashMap::new();
    parent.insert((start.clone(), 0), None);
    let mut queue = std::collections::VecDeque::from([(start, 0usize)]);
    let mut found = None;
    let mut succ = Vec::new();
    while let Some((st, k)) = queue.pop_front() {
        if k == trace.len() {
            found = Some((st, k));
            break;
        }
        if parent.len() > limit {
            return Vec::new();
        }
        succ.clear();
        spec.successors(&st, &mut succ);
        for (label, next) in succ.drain(..) {
            let k2 = if label.event == TAU {
                k
            } else if label.event == trace[k] {
                k + 1
            } else {
                continue;
            };
            let key = (next, k2);
            if !parent.contains_key(&key) {
                parent.insert(key.clone(), Some(((st.clone(), k), label)));
                queue.push_back(key);
            }
        }
    }
    let Some(mut at) = found else { return Vec::new() };
    let mut steps = Vec::new();
    while let Some(Some((prev, label))) = parent.get(&at) {
        steps.push((*label, at.0.clone()));
        at = prev.clone();
    }
    steps.reverse();
    let packed = Path { initial: at.0, steps };
    sim_steps(spec, design, &values_path(&packed, |p| spec.values(p)))
}

/// The steps of a path of any LTS over a design's state vector.
/// A path of packed states as state vectors.
fn values_path(path: &Path<Packed>, values: impl Fn(&Packed) -> State) -> Path<State> {
    Path { initial: values(&path.initial), steps: path.steps.iter().map(|(l, s)| (*l, values(s))).collect() }
}

fn sim_steps<L: Lts>(lts: &L, design: &Design, path: &Path<State>) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut prev: &State = &path.initial;
    let (mut cycle, mut time, mut after_tock) = (0u32, 0u32, false);
    for (label, next) in &path.steps {
        let name = if label.event == TAU {
            if label.note != 0 {
                format!("({})", lts.event_name(label.note))
            } else {
                "τ".to_string()
            }
        } else {
            lts.event_name(label.event)
        };
        if name.starts_with("registerRead") && after_tock {
            cycle += 1;
            after_tock = false;
        }
        let (description, location) = describe_move(design, prev, next, label);
        steps.push(Step { event: name, visible: label.event != TAU, cycle, time, description, location });
        if label.event == TOCK {
            time += 1;
            after_tock = true;
        }
        prev = next;
    }
    steps
}

/// The reason with its place as `file:line:column` (1-based, columns in
/// characters as editors count them).
fn unsupported_reason(db: &dyn Db, ws: Workspace, u: &Unsupported) -> String {
    let Some((path, range)) = &u.location else {
        return u.message.clone();
    };
    let Some(file) = ws.files(db).iter().find(|f| f.path(db) == path) else {
        return format!("{} ({path})", u.message);
    };
    let text = file.text(db);
    let index = robosim_syntax::line_index::LineIndex::new(text);
    let at = index.line_col(text, range.start());
    format!("{} ({path}:{}:{})", u.message, at.line + 1, at.col + 1)
}

pub(crate) fn domains_note(design: &Design) -> String {
    let doms: Vec<String> = design.domains.iter().map(|(n, d)| format!("{n} = {{{}..{}}}", d.lo, d.hi)).collect();
    let mut s = format!("domains: {}", doms.join(", "));
    if !design.constants.is_empty() {
        let cs: Vec<String> = design.constants.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        s.push_str(&format!("; constants: {}", cs.join(", ")));
    }
    if let Some(b) = design.channels.iter().find_map(|c| c.buffer) {
        s.push_str(&format!("; {}", b.policy.describe()));
    }
    if !design.defaults.is_empty() {
        s.push_str(&format!("; RoboTool's defaults, as the model gives no value: {}", design.defaults.join(", ")));
    }
    s
}

/// The steps of a path, with the design's moves identified and located.
fn path_steps(lts: &Constrained<'_>, design: &Design, path: &Path<State>) -> Vec<Step> {
    sim_steps(lts, design, path)
}

/// Which machine moved between `prev` and `next`, and what it did.
pub(crate) fn describe_move(
    design: &Design,
    prev: &[i32],
    next: &[i32],
    _label: &Label,
) -> (Option<String>, Option<Location>) {
    for m in &design.machines {
        // The machine's control slots (leaf, pc, wait, transition, deadline,
        // and its activities' and timers'): two transitions can lead to the
        // same leaf and pc (exec ones do).
        let ctl = |st: &[i32]| m.control(st);
        if ctl(prev) == ctl(next) {
            continue;
        }
        let mut moves = Vec::new();
        if m.moves(prev, &mut moves).is_err() {
            continue;
        }
        // The move whose effect matches (a tock, or a settle after it, is not in `moves`).
        for mv in &moves {
            let mut trial = prev.to_vec();
            let mut saturated = false;
            if m.apply_noting(&mut trial, &design.clocks, mv.act, None, &mut saturated).is_err() {
                continue;
            }
            if ctl(&trial) != ctl(next) {
                continue;
            }
            let (what, at) = describe_act(design, m, mv.act, prev, next);
            let what = what.map(|w| if saturated { format!("{w} {SATURATED}") } else { w });
            return (what, at);
        }
        return (Some(format!("{}: now {}", m.name, m.describe(next))), None);
    }
    (None, None)
}

/// Marks a step whose arithmetic saturated.
const SATURATED: &str = "(arithmetic saturated)";

/// The note added to a counterexample that depends on saturation.
fn saturation_note(steps: &[Step]) -> Option<String> {
    let step = steps.iter().position(|s| s.description.as_deref().is_some_and(|d| d.ends_with(SATURATED)))?;
    Some(format!(
        "note: at step {} a result left its type and RoboTool's sticky arithmetic kept the left operand; \
         the verdict depends on the bounds of the types (widen them with `nametype core_X = {{a..b}}`)",
        step + 1
    ))
}

/// Where the instruction at `pc` of machine `m` is in the model.
fn code_location(design: &Design, m: &crate::ir::Machine, pc: usize) -> Option<Location> {
    let range = *m.code_ranges.get(pc)?;
    let file = m.code_files.get(pc).and_then(|&f| design.files.get(f as usize)).cloned().unwrap_or_default();
    Some(Location { file, range })
}

/// What machine `m` did by `act`, and where in the model.
fn describe_act(
    design: &Design,
    m: &crate::ir::Machine,
    act: Act,
    prev: &[i32],
    next: &[i32],
) -> (Option<String>, Option<Location>) {
    let at = |n: Option<u16>| n.map(|n| m.nodes[n as usize].name.clone()).unwrap_or_else(|| "-".into());
    let pc = m.pc(prev) as usize;
    let here = code_location(design, m, pc);
    match act {
        Act::Fire(t) | Act::Junction(t) => {
            let tr = &m.transitions[t as usize];
            let what = format!(
                "{}: takes {} ({} → {})",
                m.name, tr.name, m.nodes[tr.source as usize].name, m.nodes[tr.target as usize].name,
            );
            let file = design.files.get(tr.file as usize).cloned().unwrap_or_default();
            (Some(what), Some(Location { file, range: tr.range }))
        }
        Act::Comm => {
            let what = out_verb(&m.code[pc]).unwrap_or("receives");
            // Between states (on a transition out of a junction) there is
            // no state to name.
            let place = m.leaf(prev).map(|l| format!(" in {}", at(Some(l)))).unwrap_or_default();
            (Some(format!("{}: {what}{place}", m.name)), here)
        }
        Act::Choose(n) => (Some(format!("{}: the wait interval resolves to {n}", m.name)), here),
        Act::Exec if matches!(m.code.get(pc), Some(Instr::Wait)) => {
            (Some(format!("{}: goes on after its wait, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec => (Some(format!("{}: writes a shared variable, now {}", m.name, m.describe(next))), here),
        Act::ActivityComm(k) | Act::ActivityChoose(k, _) | Act::ActivityExec(k) => {
            let a = &m.activities[k as usize];
            let pc = prev[a.pc_slot as usize] as usize;
            let what = match (act, m.code.get(pc)) {
                (Act::ActivityChoose(_, n), _) => format!("the wait interval resolves to {n}"),
                (_, Some(i @ Instr::Out { .. })) => out_verb(i).unwrap_or_default().into(),
                (_, Some(Instr::In { .. })) => "receives".into(),
                (_, Some(Instr::Wait)) => "goes on after its wait".into(),
                _ => "writes a variable".into(),
            };
            let here = code_location(design, m, pc);
            (Some(format!("{}: {what} in the during action of {}", m.name, at(Some(a.state)))), here)
        }
    }
}

/// What a machine does at an output instruction, in words (none for other
/// instructions).
fn out_verb(instr: &Instr) -> Option<&'static str> {
    match instr {
        Instr::Out { store: Some(_), .. } => Some("updates the platform variable"),
        Instr::Out { urgent: true, .. } => Some("calls the platform operation"),
        Instr::Out { .. } => Some("outputs"),
        _ => None,
    }
}

fn deadlock_counterexample(lts: &Constrained<'_>, design: &Design, path: &Path<Packed>) -> Counterexample {
    let path = &values_path(path, |p| lts.values(p));
    let steps = path_steps(lts, design, path);
    let last: &State = path.steps.last().map(|(_, s)| s).unwrap_or(&path.initial);
    let mut explanation = Vec::new();
    let mut stuck_at = Vec::new();
    let time = steps.iter().filter(|s| s.event == "tock").count();
    let written = lts.written(last);
    let phase = lts.phase(last);
    for (mname, mv) in lts.design_moves(last) {
        let Some(m) = design.machines.iter().find(|m| m.name == mname) else { continue };
        let pc = m.pc(last) as usize;
        if let Offer::Out { chan, args } = &mv.offer {
            let c = &design.channels[*chan as usize];
            let values = args.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", ");
            let urgent = matches!(m.code.get(pc), Some(Instr::Out { urgent: true, .. }));
            let mut line = if c.var {
                format!(
                    "{mname} ({}) must set {} = {values} now (updates of platform variables cannot be delayed)",
                    m.describe(last),
                    c.name
                )
            } else {
                let call = format!("{}({values})", c.name);
                format!("{mname} ({}) must {} {call} now", m.describe(last), if urgent { "call" } else { "output" })
            };
            if urgent && !c.var {
                line.push_str(" (platform operation calls cannot be delayed)");
            }
            if written.contains(&c.name) {
                line.push_str(&format!(
                    ", but `{}` was already written in this cycle (one write per output per cycle)",
                    c.name
                ));
            } else {
                line.push_str(&format!(", but the cycle assumption forbids it: the simulation is {phase}"));
            }
            explanation.push(line);
            stuck_at.extend(code_location(design, m, pc));
        }
    }
    if explanation.is_empty() {
        explanation.push(format!(
            "at t = {time} nothing can happen: the design {}; the simulation is {phase}",
            design
                .machines
                .iter()
                .map(|m| format!("{} is {}", m.name, m.describe(last)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    explanation.extend(saturation_note(&steps));
    Counterexample { kind: "deadlock", steps, explanation, stuck_at, specification: Vec::new() }
}

/// A counterexample grouped by cycle, one line per step: reads, the
/// design's steps with their description and source (`locate` prints a
/// location), writes, time passing; then why nothing more can happen.
/// The command line and the editor's hover both show this table.
pub fn counterexample_table(c: &Counterexample, locate: &dyn Fn(&Location) -> String) -> String {
    let mut lines: Vec<String> = Vec::new();
    let mut cycle = u32::MAX;
    let mut tocks = 0;
    let flush = |lines: &mut Vec<String>, tocks: &mut u32| {
        if *tocks > 0 {
            let unit = if *tocks == 1 { "time unit passes" } else { "time units pass" };
            lines.push(format!("           {tocks} {unit}"));
            *tocks = 0;
        }
    };
    for step in &c.steps {
        if step.event == "tock" {
            tocks += 1;
            continue;
        }
        flush(&mut lines, &mut tocks);
        let (what, event) = if let Some(e) = step.event.strip_prefix("registerRead.") {
            ("read  ", e)
        } else if let Some(e) = step.event.strip_prefix("registerWrite.") {
            ("write ", e)
        } else if step.visible {
            ("event ", step.event.as_str())
        } else {
            ("design", step.event.as_str())
        };
        if !step.visible && step.description.is_none() && event == "τ" {
            continue;
        }
        if step.cycle != cycle {
            cycle = step.cycle;
            lines.push(format!("cycle {cycle}  t = {}", step.time));
        }
        let mut line = format!("  {what} {event}");
        if let Some(d) = &step.description {
            line.push_str(&format!("  {d}"));
        }
        if let Some(l) = &step.location {
            line.push_str(&format!("  --> {}", locate(l)));
        }
        lines.push(line);
    }
    flush(&mut lines, &mut tocks);
    lines.extend(c.explanation.iter().map(|e| format!("stuck: {e}")));
    lines.extend(c.stuck_at.iter().map(|l| format!("  --> {}", locate(l))));
    if !c.specification.is_empty() {
        lines.push("the specification, on the same trace:".into());
        let design_only: Vec<&Step> =
            c.specification.iter().filter(|s| !s.visible && s.description.is_some()).collect();
        for step in design_only {
            let mut line = format!("  design {}", step.event);
            if let Some(d) = &step.description {
                line.push_str(&format!("  {d}"));
            }
            if let Some(l) = &step.location {
                line.push_str(&format!("  --> {}", locate(l)));
            }
            lines.push(line);
        }
    }
    let mut s = lines.join("\n");
    s.push('\n');
    s
}

/// The LTS's events of a step, for tests: visible names, hidden ones in
/// parentheses, τ left out.
pub fn trace_text(steps: &[Step]) -> String {
    steps.iter().filter(|s| s.event != "τ").map(|s| s.event.clone()).collect::<Vec<_>>().join(" ")
}
