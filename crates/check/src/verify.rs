//! Running the assertions of a workspace's assertion files: find what each
//! one names, compile it, run the check, and explain the result in the
//! modeller's terms (verdict, statistics, a counterexample grouped by cycle
//! and mapped to source).

use std::time::Instant;

use robosim_hir::defs::DefKind;
use robosim_hir::index::resolve_item;
use robosim_hir::{parse, Db, File, TextRange, Workspace};

use crate::algo::{find_deadlock, DeadlockResult, Path};
use crate::assertions::{read_assertions, AssertionDecl, AssertionFile, AssertionKind, Override, Value};
use crate::budget::{Budget, ProgressFn, Stats};
use crate::ir::{Design, Instr, Val};
use crate::lower::{lower_design, ConstValue, DomainDefaults, Unsupported};
use crate::lts::{Label, Lts, TAU, TOCK};
use crate::machine::{Act, Offer};
use crate::sched::{Constrained, State};

pub use crate::sched::Profile;

/// How to run checks.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The semantics.
    pub profile: Profile,
    /// Limits on the search.
    pub budget: Budget,
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
        .map(|&f| (f, read_assertions(&parse(db, f).syntax_node())))
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
    let read = read_assertions(&parse(db, file).syntax_node());
    let others = all_assertion_files(db, ws);
    read.assertions.iter().map(|a| verify_assertion(db, ws, file, &read, &others, a, opts, progress)).collect()
}

/// Runs one assertion of `file` (read as `read`).
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
) -> Report {
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
    };
    if let Some(p) = a.problems.first() {
        report.reason = Some(format!("the assertion is incomplete: {}", p.message));
        return report;
    }
    match &a.kind {
        AssertionKind::Schedulable => schedulable(db, ws, file, read, others, a, opts, progress, &mut report),
        AssertionKind::Refines { .. } | AssertionKind::Equals { .. } => {
            report.reason = Some("refinement checks are not supported by the native checker yet".into());
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

#[allow(clippy::too_many_arguments)]
fn schedulable(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    read: &AssertionFile,
    others: &[(File, AssertionFile)],
    a: &AssertionDecl,
    opts: &Options,
    progress: Option<ProgressFn>,
    report: &mut Report,
) {
    // `S` is a simulation declared in this file or another assertion file.
    let name = a.subject.join("::");
    let found = read
        .simulation(&name)
        .map(|s| (file, s))
        .or_else(|| others.iter().find_map(|(f, r)| r.simulation(a.subject.last()?).map(|s| (*f, s))));
    let Some((sim_file, sim)) = found else {
        report.reason = Some(format!("`{name}` is not a `simulation … of …` declaration"));
        return;
    };
    let Some(loc) = resolve_item(db, ws, sim_file, &sim.of, |k| {
        matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine)
    })
    .into_iter()
    .next() else {
        report.reason = Some(format!("`{}` is not a RoboChart module, controller or machine", sim.of.join("::")));
        return;
    };
    // The period: an override of the assertion, else the simulation's.
    let mut period = sim.cycle.as_ref().and_then(Value::as_int);
    let mut consts = Vec::new();
    for o in &a.overrides {
        match o {
            Override::CycleDef { of, value, .. } if of.last() == Some(&sim.name) => {
                period = value.as_int();
            }
            Override::Constant { name, of, value, .. } => match value.as_int() {
                Some(v) => consts.push(ConstValue { name: name.clone(), of: of.clone(), value: v }),
                None => {
                    let Value::Bool(b) = value else {
                        report.reason =
                            Some(format!("the value of constant `{name}` is not an integer or boolean literal"));
                        return;
                    };
                    consts.push(ConstValue { name: name.clone(), of: of.clone(), value: *b as Val });
                }
            },
            _ => {}
        }
    }
    let Some(period) = period.filter(|p| *p >= 1 && *p <= 1_000) else {
        report.reason =
            Some(format!("`{}` has no cycle period from 1 to 1000: give one with `cycleDef cycle == N`", sim.name));
        return;
    };
    let mut defaults = DomainDefaults::default();
    for (f, r) in std::iter::once((file, read)).chain(others.iter().map(|(f, r)| (*f, r))) {
        let _ = f;
        for (name, lo, hi, _) in &r.instantiations.types {
            defaults.set(name, *lo, *hi);
        }
    }
    let design = match lower_design(db, ws, loc, &consts, &defaults) {
        Ok(d) => d,
        Err(u) => {
            report.reason = Some(unsupported_reason(&u));
            return;
        }
    };
    let lts = match Constrained::new(&design, period as u32, opts.profile) {
        Ok(l) => l,
        Err(e) => {
            report.reason = Some(e);
            return;
        }
    };
    report.notes.push(domains_note(&design));
    let (result, stats) = find_deadlock(&lts, &opts.budget, progress);
    report.stats = stats;
    if let Some(err) = lts.error() {
        report.verdict = Verdict::Inconclusive;
        report.reason = Some(format!("the model met a run-time error: {err}"));
        return;
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
            return;
        }
    };
    let pass = holds != a.negated;
    report.verdict = if pass { Verdict::Pass } else { Verdict::Fail };
    report.reason = Some(if holds {
        format!("{} can be scheduled in cycles of period {period}", design.name)
    } else {
        format!("{} cannot be scheduled in cycles of period {period}", design.name)
    });
}

fn unsupported_reason(u: &Unsupported) -> String {
    match &u.location {
        Some((file, range)) => {
            format!("{} ({file} at {}..{})", u.message, u32::from(range.start()), u32::from(range.end()))
        }
        None => u.message.clone(),
    }
}

fn domains_note(design: &Design) -> String {
    let doms: Vec<String> = design.domains.iter().map(|(n, d)| format!("{n} = {{{}..{}}}", d.lo, d.hi)).collect();
    let mut s = format!("domains: {}", doms.join(", "));
    if !design.constants.is_empty() {
        let cs: Vec<String> = design.constants.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        s.push_str(&format!("; constants: {}", cs.join(", ")));
    }
    s
}

/// The steps of a path, with the design's moves identified and located.
fn path_steps(lts: &Constrained<'_>, design: &Design, path: &Path<State>) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut prev: &State = &path.initial;
    let mut cycle = 0u32;
    let mut time = 0u32;
    let mut after_tock = false;
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

/// Which machine moved between `prev` and `next`, and what it did.
fn describe_move(design: &Design, prev: &[i32], next: &[i32], _label: &Label) -> (Option<String>, Option<Location>) {
    for m in &design.machines {
        let ctl = |st: &[i32]| (m.leaf(st), m.pc(st));
        if ctl(prev) == ctl(next) {
            continue;
        }
        let mut moves = Vec::new();
        if m.moves(prev, &mut moves).is_err() {
            continue;
        }
        let file = design.files.get(m.file as usize).cloned().unwrap_or_default();
        // The move whose effect matches (a tock, or a settle after it, is not in `moves`).
        for mv in &moves {
            let mut trial = prev.to_vec();
            if m.apply(&mut trial, &design.clocks, mv.act, None).is_err() {
                continue;
            }
            if ctl(&trial) != ctl(next) {
                continue;
            }
            let at = |n: Option<u16>| n.map(|n| m.nodes[n as usize].name.clone()).unwrap_or_else(|| "-".into());
            return match mv.act {
                Act::Fire(t) | Act::Junction(t) => {
                    let tr = &m.transitions[t as usize];
                    let what = format!(
                        "{}: takes {} ({} → {})",
                        m.name, tr.name, m.nodes[tr.source as usize].name, m.nodes[tr.target as usize].name,
                    );
                    (Some(what), Some(Location { file, range: tr.range }))
                }
                Act::Comm => {
                    let pc = m.pc(prev) as usize;
                    let what = match &m.code[pc] {
                        Instr::Out { urgent: true, .. } => "calls the platform operation",
                        Instr::Out { .. } => "outputs",
                        _ => "receives",
                    };
                    let range = m.code_ranges.get(pc).copied();
                    (
                        Some(format!("{}: {what} in {}", m.name, at(m.leaf(prev)))),
                        range.map(|range| Location { file, range }),
                    )
                }
                Act::Choose(n) => {
                    let pc = m.pc(prev) as usize;
                    let range = m.code_ranges.get(pc).copied();
                    (
                        Some(format!("{}: the wait interval resolves to {n}", m.name)),
                        range.map(|range| Location { file, range }),
                    )
                }
                Act::Exec => (Some(format!("{}: writes a shared variable", m.name)), None),
            };
        }
        return (Some(format!("{}: now {}", m.name, m.describe(next))), None);
    }
    (None, None)
}

fn deadlock_counterexample(lts: &Constrained<'_>, design: &Design, path: &Path<State>) -> Counterexample {
    let steps = path_steps(lts, design, path);
    let last: &State = path.steps.last().map(|(_, s)| s).unwrap_or(&path.initial);
    let mut explanation = Vec::new();
    let mut stuck_at = Vec::new();
    let time = steps.iter().filter(|s| s.event == "tock").count();
    let written = lts.written(last);
    let phase = lts.phase(last);
    for (mname, mv) in lts.design_moves(last) {
        let Some(m) = design.machines.iter().find(|m| m.name == mname) else { continue };
        let file = design.files.get(m.file as usize).cloned().unwrap_or_default();
        let pc = m.pc(last) as usize;
        if let Offer::Out { chan, args } = &mv.offer {
            let c = &design.channels[*chan as usize];
            let call = format!("{}({})", c.name, args.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", "));
            let urgent = matches!(m.code.get(pc), Some(Instr::Out { urgent: true, .. }));
            let mut line =
                format!("{mname} ({}) must {} {call} now", m.describe(last), if urgent { "call" } else { "output" });
            if urgent {
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
            if let Some(&range) = m.code_ranges.get(pc) {
                stuck_at.push(Location { file, range });
            }
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
    Counterexample { kind: "deadlock", steps, explanation, stuck_at }
}

/// The LTS's events of a step, for tests: visible names, hidden ones in
/// parentheses, τ left out.
pub fn trace_text(steps: &[Step]) -> String {
    steps.iter().filter(|s| s.event != "τ").map(|s| s.event.clone()).collect::<Vec<_>>().join(" ")
}
