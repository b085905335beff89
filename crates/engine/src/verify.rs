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

mod explain;
mod fdr_error;
mod robosim;
mod semantics;

use explain::*;
pub use explain::{counterexample_table, trace_text};
pub(crate) use explain::{describe_move, domains_note};

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
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
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

/// The native LTS of the model element `a`'s subject names, in
/// `semantics`, with `a`'s constants, explored in full (at most
/// `max_states` states), its events named as RoboTool's CSPm names them
/// (`p::M::go.in`, `tock`; a machine's or controller's `M::terminate`
/// before ✓): the implementation side of the CSPm bridge's checks, for
/// cross-checking the engine against the CSPm export
/// (`tests/export_semantics.rs`). RoboChart elements only, as the bridge.
#[allow(clippy::too_many_arguments)]
pub fn subject_lts(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    read: &AssertionFile,
    others: &[(File, AssertionFile)],
    a: &AssertionDecl,
    semantics: Semantics,
    opts: &Options,
    max_states: usize,
) -> Result<robosim_cspm::Lts, String> {
    let cx = Cx { db, ws, file, read, others, a, async_buffer: opts.async_buffer, semantics };
    crate::csp::subject_lts(&cx, max_states)
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
    if matches!(report.verdict, Verdict::Pass | Verdict::Fail) {
        if let Some(note) = old_style_types_note(cx.read) {
            report.notes.push(note);
        }
        // An assertion that uses the blocks stops at their error itself.
        if let Some(error) = crate::csp::script_error(cx) {
            report.notes.push(format!(
                "FDR stops on RoboTool's script of this file ({error}) and, as it loads a script whole, checks \
                 none of the file's assertions until that is fixed; this verdict does not depend on the `csp` \
                 blocks: it is FDR's once they are fixed"
            ));
        }
    }
    if report.stats.seconds == 0.0 {
        report.stats.seconds = started.elapsed().as_secs_f64();
    }
    report
}

/// RT-7: `nametype nat = …` (`int`, `real`) in a `csp` block is read as
/// `core_nat` (…), as the RoboTool generators that named the types so did
/// — the FDR results recorded for the Alpha Algorithm's `model.assertions`
/// rest on it. RoboTool 3 copies the line as it is (defining `nat` only)
/// and, its `Instantiations` block replacing the generated
/// `instantiations.csp`, leaves `core_nat` undefined: the verdict says so.
fn old_style_types_note(read: &AssertionFile) -> Option<String> {
    let old: Vec<&str> = read
        .instantiations
        .types
        .iter()
        .map(|(n, ..)| n.as_str())
        .filter(|n| matches!(*n, "nat" | "int" | "real"))
        .collect();
    if old.is_empty() {
        return None;
    }
    let names: Vec<String> = old.iter().map(|n| format!("`{n}`")).collect();
    let core: Vec<String> = old.iter().map(|n| format!("`core_{n}`")).collect();
    Some(format!(
        "the {} {} of this file's `csp` block {} read as {}, as the older RoboTool generators whose FDR results \
         are recorded named them (RT-7); RoboTool 3's script defines only {} and, the `Instantiations` block \
         replacing its generated defaults, leaves {} undefined (FDR stops): write `nametype core_nat = …` for \
         RoboTool 3",
        if old.len() == 1 { "type" } else { "types" },
        names.join(", "),
        if old.len() == 1 { "was" } else { "were" },
        core.join(", "),
        names.join(", "),
        core.join(", ")
    ))
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
        // RT-11: parameters by the operation's declaration, also when the
        // assertion names it through a reference (`with parameter n of D::o`).
        out.extend(robosim_hir::target::parameters_in(scope, self.a)?.into_iter().map(|b| ConstValue {
            name: b.name,
            of: b.of,
            value: b.value as Val,
        }));
        Ok(out)
    }

    /// The bounded types, constants and functions the assertion's own file
    /// instantiates (`nametype core_X = {a..b}`, `X_c = v`, `f(x) = e`):
    /// RoboTool's script for one assertion file includes that file's `csp`
    /// blocks only (RT-7), so another file's `Instantiations` never applies.
    fn defaults(&self) -> DomainDefaults {
        let r = self.read;
        let mut defaults = DomainDefaults {
            async_buffer: self.async_buffer,
            replaced: r.csp_blocks.iter().any(|b| b.name == "Instantiations"),
            robosim_script: self.file.kind(self.db) == robosim_hir::FileKind::SimAssertions,
            ..DomainDefaults::default()
        };
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
        defaults.functions.extend(r.instantiations.functions.iter().cloned());
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
            // A design, or a RoboSim operation (RT-11), on its own has no period.
            Target::Design { name, loc, .. } | Target::SimOperation { name, loc, .. } => (name, *loc, Some(1)),
        };
        let inner = match target {
            Target::Design { inner, .. } | Target::SimOperation { inner, .. } => inner.as_deref(),
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
        Target::SimOperation { name, .. } => {
            return Err(format!(
                "`{name}` is a RoboSim operation: comparing it with another process is not supported by the native \
                 checker yet (its own properties are: deadlock freedom, determinism, divergence freedom, \
                 termination, reachability, timelock freedom)"
            ))
        }
    })
}

/// The LTS of `target` on its own (for properties of one element).
fn single<'a>(target: &Target, design: &'a Design, period: u32, profile: Profile) -> Result<Side<'a>, String> {
    Ok(match target {
        // RT-11: a RoboSim operation is a process of its own (`OP_…::O__`),
        // without a machine's cycle: see `DesignLts` for its `exec`s.
        Target::Design { .. } | Target::SimOperation { .. } => Side::Plain(DesignLts::new(design)?),
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
            let (verdict, reason) = fdr_error::runtime_error(&err, &design.domains);
            (report.verdict, report.reason) = (verdict, Some(reason));
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
/// Names the channels of `d` after the element, as RoboTool's module
/// does (`M::e`).
fn qualify_events(d: &mut crate::ir::Design) {
    let element = d.name.clone();
    for c in &mut d.channels {
        c.name = format!("{element}::{}", c.name);
    }
}

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
        let (mut imp_d, mut spec_d) = (cx.in_semantics(imp_d)?, cx.in_semantics(spec_d)?);
        let (imp, spec) = match (&imp_t, &spec_t) {
            // Two RoboChart designs. RoboTool declares each element's events
            // in the element's own CSPm module (`M::e`, `N::e`; the
            // reference's `defs/aggregation_Movement.csp`): FDR identifies
            // the events of two processes only when they are the same
            // element's. So the events of two different elements are told
            // apart by the element's name; `tock` and ✓ stay shared. (To
            // compare two elements' behaviours, rename one's events in a
            // `csp` block: `N::D__(0) [[ N::e <- M::e ]]`.)
            (Target::Design { loc: li, inner: ii, .. }, Target::Design { loc: ls, inner: is, .. }) => {
                if (li, ii) != (ls, is) {
                    qualify_events(&mut imp_d);
                    qualify_events(&mut spec_d);
                    report.notes.push(format!(
                        "`{}` and `{}` are different elements: RoboTool declares each one's events in its own \
                         CSPm module, so FDR never identifies an event of one with an event of the other (rename \
                         them in a `csp` block to compare their behaviours)",
                        a.subject.join("::"),
                        other.join("::")
                    ));
                }
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
                let (verdict, reason) = fdr_error::runtime_error(&err, &im_design.domains);
                (report.verdict, report.reason) = (verdict, Some(reason));
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
                    // A cycle of hidden steps alone is a divergence, which
                    // RoboTool's encoding (RT-10: `tock` hidden, then
                    // divergence-free) rejects alike; say which it is.
                    TimedDeadlockResult::TimedDeadlock { path, cycle }
                        if cycle.iter().all(|(l, _)| l.event != TOCK) =>
                    {
                        Ok((
                            false,
                            Some(("divergence", path, "from here it can compute forever".into())),
                            format!(
                                "{name} can run hidden steps forever without time passing (a divergence, which \
                                 RoboTool's timed deadlock check fails too)"
                            ),
                        ))
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
                // The design's slots come first in the states of every LTS
                // built on it: a RoboSim cycle or the simulation
                // constraints around it change when the states are
                // entered, not how a state is recognised.
                let d = match &lts {
                    Side::Plain(l) => l.design(),
                    Side::Sim(l) => l.design(),
                    // No generated example shows what RoboTool makes of a
                    // state of a `simulation` of a RoboChart design.
                    Side::Design(_) => {
                        return Err("reachability under a `simulation`'s assumptions is not established: check the \
                                    RoboChart design or the RoboSim model"
                            .into())
                    }
                };
                let nodes = d.state_nodes(state)?;
                let target_state = |st: &Packed| d.in_nodes(&lts.values(st), &nodes);
                let reach = Reach { lts: &lts, target: &target_state };
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
            let (verdict, reason) = fdr_error::runtime_error(&err, &design.domains);
            (report.verdict, report.reason) = (verdict, Some(reason));
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
