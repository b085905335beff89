//! Verification in the editor, independent of any protocol: what can be
//! checked from where (code lenses on assertions, simulations and the
//! modules they simulate), running a check on a snapshot with the native
//! engine (`robosim-engine`), and presenting its results as lens titles,
//! diagnostics and hovers.
//!
//! Results are not kept here: the caller runs checks (in the background,
//! with its own cancellation) and hands the reports back as [`Verified`]
//! values when it asks for titles, diagnostics or hovers. Reports use the
//! paths files were added under, and byte ranges.

use std::fmt::Write;

use robosim_engine::assertions::{
    read_assertions, AssertionDecl, AssertionFile, AssertionKind, SemanticModelName, SimulationDecl,
};
pub use robosim_engine::budget::{Budget, ProgressFn, Stats};
use robosim_engine::verify::verify_assertion;
pub use robosim_engine::verify::{
    counterexample_table, AsyncBuffer, Counterexample, Location, Options, Profile, Report, Semantics, Step, Verdict,
};
use robosim_hir::defs::{file_defs, DefKind};
use robosim_hir::index::resolve_item;
use robosim_hir::{parse, Db, File, Severity, Workspace};
use robosim_syntax::{FileKind, TextRange, TextSize};

use crate::{Diagnostic, FileId, RelatedInfo};

/// The code of verification diagnostics.
pub const VERIFY_CODE: &str = "RS-VERIFY";

/// What a verification run checks.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VerifyTarget {
    /// The assertion `name` of the assertion file at `path`.
    Assertion {
        /// The assertion file.
        path: String,
        /// The assertion's name.
        name: String,
    },
    /// The schedulability of the simulation `name` declared in the
    /// assertion file at `path`: the `… is schedulable` assertions about it
    /// in the workspace's assertion files, or, when there are none, `name
    /// is schedulable` itself.
    Simulation {
        /// The assertion file declaring the simulation.
        path: String,
        /// The simulation's name.
        name: String,
    },
}

impl VerifyTarget {
    /// The assertion file the target is in.
    pub fn path(&self) -> &str {
        match self {
            VerifyTarget::Assertion { path, .. } | VerifyTarget::Simulation { path, .. } => path,
        }
    }

    /// The assertion's or simulation's name.
    pub fn name(&self) -> &str {
        match self {
            VerifyTarget::Assertion { name, .. } | VerifyTarget::Simulation { name, .. } => name,
        }
    }

    /// What a progress report calls the run: `S1`, `schedulability of P1`.
    pub fn describe(&self) -> String {
        match self {
            VerifyTarget::Assertion { name, .. } => format!("assertion {name}"),
            VerifyTarget::Simulation { name, .. } => format!("schedulability of {name}"),
        }
    }
}

/// A place from which a check can be started.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct VerifyLens {
    /// Where the lens goes: the assertion's, simulation's or module's name.
    pub range: TextRange,
    /// What it checks.
    pub target: VerifyTarget,
    /// For assertions: the assertion's name range in its file (the same
    /// file), to find its last report. `None` for schedulability lenses.
    pub assertion_range: Option<TextRange>,
    /// For schedulability lenses: the simulation's cycle period, when it
    /// gives one.
    pub cycle: Option<i64>,
}

/// A report with the semantics it was computed under.
#[derive(Debug, Clone)]
pub struct Verified {
    /// The engine's report.
    pub report: Report,
    /// The semantics used.
    pub profile: Profile,
}

/// The assertion files of the workspace, read.
fn assertion_files(db: &dyn Db, ws: Workspace) -> Vec<(File, AssertionFile)> {
    ws.files(db)
        .iter()
        .filter(|f| !f.is_library(db) && f.kind(db).is_assertions())
        .map(|&f| (f, read_assertions(&parse(db, f).syntax_node())))
        .collect()
}

/// The user file at `path`.
fn file_at(db: &dyn Db, ws: Workspace, path: &str) -> Option<File> {
    ws.files(db).iter().copied().find(|f| f.path(db) == path)
}

/// The verification lenses of `file`: on each assertion and simulation of
/// an assertion file; on each RoboChart module that a simulation of the
/// workspace's assertion files simulates.
pub(crate) fn lenses(db: &dyn Db, ws: Workspace, file: File) -> Vec<VerifyLens> {
    if file.is_library(db) {
        return Vec::new();
    }
    let path = file.path(db).clone();
    let mut out = Vec::new();
    match file.kind(db) {
        FileKind::Assertions | FileKind::SimAssertions => {
            let read = read_assertions(&parse(db, file).syntax_node());
            for a in &read.assertions {
                if a.name.is_empty() {
                    continue;
                }
                out.push(VerifyLens {
                    range: a.name_range,
                    target: VerifyTarget::Assertion { path: path.clone(), name: a.name.clone() },
                    assertion_range: Some(a.name_range),
                    cycle: None,
                });
            }
            for s in &read.simulations {
                if s.name.is_empty() {
                    continue;
                }
                out.push(VerifyLens {
                    range: s.name_range,
                    target: VerifyTarget::Simulation { path: path.clone(), name: s.name.clone() },
                    assertion_range: None,
                    cycle: s.cycle.as_ref().and_then(|c| c.as_int()),
                });
            }
        }
        FileKind::RoboChart => {
            let defs = file_defs(db, file);
            let modules: Vec<_> = defs.iter().filter(|(_, d)| d.kind == DefKind::Module).collect();
            if modules.is_empty() {
                return out;
            }
            for (sim_file, read) in assertion_files(db, ws) {
                for s in &read.simulations {
                    if s.name.is_empty() || s.of.is_empty() {
                        continue;
                    }
                    let found = resolve_item(db, ws, sim_file, &s.of, |k| {
                        matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine)
                    });
                    let Some(loc) = found.first().filter(|l| l.file == file) else { continue };
                    let Some(id) = loc.def(db) else { continue };
                    let Some((_, module)) = modules.iter().find(|(m, _)| *m == id) else { continue };
                    out.push(VerifyLens {
                        range: module.name_range,
                        target: VerifyTarget::Simulation { path: sim_file.path(db).clone(), name: s.name.clone() },
                        assertion_range: None,
                        cycle: s.cycle.as_ref().and_then(|c| c.as_int()),
                    });
                }
            }
        }
        FileKind::RoboSim => {}
    }
    out.sort_by_key(|l| (l.range.start(), l.target.clone()));
    out
}

/// Checks that `target` names an assertion or simulation of an assertion
/// file of the workspace; says what is wrong otherwise.
pub(crate) fn check_target(db: &dyn Db, ws: Workspace, target: &VerifyTarget) -> Result<(), String> {
    let (_, read) = target_file(db, ws, target)?;
    match target {
        VerifyTarget::Assertion { name, path } => read
            .assertions
            .iter()
            .find(|a| a.name == *name)
            .map(|_| ())
            .ok_or_else(|| format!("`{path}` has no assertion `{name}`")),
        VerifyTarget::Simulation { name, path } => {
            read.simulation(name).map(|_| ()).ok_or_else(|| format!("`{path}` declares no simulation `{name}`"))
        }
    }
}

fn target_file(db: &dyn Db, ws: Workspace, target: &VerifyTarget) -> Result<(File, AssertionFile), String> {
    let path = target.path();
    let file = file_at(db, ws, path)
        .filter(|f| !f.is_library(db))
        .ok_or_else(|| format!("`{path}` is not a file of the workspace"))?;
    if !file.kind(db).is_assertions() {
        return Err(format!("`{path}` is not an assertion file (.rsa or .assertions)"));
    }
    Ok((file, read_assertions(&parse(db, file).syntax_node())))
}

/// Runs the check of `target`: one report per assertion checked.
pub(crate) fn run(
    db: &dyn Db,
    ws: Workspace,
    target: &VerifyTarget,
    opts: &Options,
    progress: Option<ProgressFn>,
) -> Result<Vec<Report>, String> {
    let (file, read) = target_file(db, ws, target)?;
    let others = assertion_files(db, ws);
    match target {
        VerifyTarget::Assertion { name, path } => {
            let a = read
                .assertions
                .iter()
                .find(|a| a.name == *name)
                .ok_or_else(|| format!("`{path}` has no assertion `{name}`"))?;
            Ok(verify_assertion(db, ws, file, &read, &others, a, opts, progress))
        }
        VerifyTarget::Simulation { name, path } => {
            let sim = read.simulation(name).ok_or_else(|| format!("`{path}` declares no simulation `{name}`"))?;
            let mut reports = Vec::new();
            for (f, r) in &others {
                for a in &r.assertions {
                    if names_simulation(*f, r, a, file, sim, &others) {
                        reports.extend(verify_assertion(db, ws, *f, r, &others, a, opts, progress));
                    }
                }
            }
            if reports.is_empty() {
                let a = ad_hoc_schedulable(sim);
                reports.extend(verify_assertion(db, ws, file, &read, &others, &a, opts, progress));
            }
            Ok(reports)
        }
    }
}

/// Whether `a`, an assertion of `f` (read as `r`), is a schedulability
/// assertion about `sim`, declared in `sim_file`: its subject is found as
/// the engine finds it, in its own file first, then in the first assertion
/// file that declares a simulation of that name.
fn names_simulation(
    f: File,
    r: &AssertionFile,
    a: &AssertionDecl,
    sim_file: File,
    sim: &SimulationDecl,
    all: &[(File, AssertionFile)],
) -> bool {
    if a.kind != AssertionKind::Schedulable || !a.problems.is_empty() {
        return false;
    }
    let full = a.subject.join("::");
    if r.simulation(&full).is_some() {
        return f == sim_file && full == sim.name;
    }
    let Some(last) = a.subject.last() else { return false };
    all.iter().find(|(_, o)| o.simulation(last).is_some()).is_some_and(|(o, _)| *o == sim_file && *last == sim.name)
}

/// `S is schedulable` for the simulation `S`, located at its declaration.
fn ad_hoc_schedulable(sim: &SimulationDecl) -> AssertionDecl {
    AssertionDecl {
        name: sim.name.clone(),
        name_range: sim.name_range,
        range: sim.range,
        text: format!("{} is schedulable", sim.name),
        subject: vec![sim.name.clone()],
        subject_range: sim.name_range,
        negated: false,
        kind: AssertionKind::Schedulable,
        timed: None,
        model: SemanticModelName::Default,
        model_range: None,
        overrides: Vec::new(),
        problems: Vec::new(),
    }
}

/// The verdict of several reports together: a failure if one fails, else
/// inconclusive, else unsupported, else a pass.
pub fn overall_verdict<'a>(reports: impl IntoIterator<Item = &'a Report>) -> Option<Verdict> {
    let mut worst: Option<Verdict> = None;
    let rank = |v: Verdict| match v {
        Verdict::Pass => 0,
        Verdict::Unsupported => 1,
        Verdict::Inconclusive => 2,
        Verdict::Fail => 3,
    };
    for r in reports {
        if worst.is_none_or(|w| rank(r.verdict) > rank(w)) {
            worst = Some(r.verdict);
        }
    }
    worst
}

/// `0.4 ms`, `12 ms`, `3.2 s`.
pub fn format_seconds(seconds: f64) -> String {
    let ms = seconds * 1000.0;
    if ms < 10.0 {
        format!("{ms:.1} ms")
    } else if ms < 1000.0 {
        format!("{ms:.0} ms")
    } else {
        format!("{seconds:.1} s")
    }
}

/// The first line of `text`, at most `max` characters (with `…` when cut).
pub fn shorten(text: &str, max: usize) -> String {
    let line = text.lines().next().unwrap_or("").trim();
    if line.chars().count() <= max {
        return line.to_string();
    }
    let cut: String = line.chars().take(max.saturating_sub(1)).collect();
    format!("{}…", cut.trim_end())
}

/// The title of a lens: what it runs when nothing was run yet, the last
/// verdict after a run (`reports`: the reports of its last run; for an
/// assertion, its own), a notice while a run is going on.
pub fn lens_title(lens: &VerifyLens, reports: &[&Report], running: bool) -> String {
    if running {
        return "⏳ verifying… (click to restart)".to_string();
    }
    let Some(verdict) = overall_verdict(reports.iter().copied()) else {
        return match (&lens.target, lens.cycle) {
            (VerifyTarget::Assertion { .. }, _) => "▶ Verify".to_string(),
            (VerifyTarget::Simulation { .. }, Some(n)) => format!("▶ Check schedulability (cycle {n})"),
            (VerifyTarget::Simulation { .. }, None) => "▶ Check schedulability".to_string(),
        };
    };
    let first_reason = |v: Verdict| {
        let r = reports.iter().find(|r| r.verdict == v).and_then(|r| r.reason.as_deref()).unwrap_or("");
        shorten(r, 60)
    };
    // RT-8: an assertion checked in both semantics shows both verdicts
    // when they differ, and says so when they agree.
    let both = reports.iter().any(|r| r.semantics == Semantics::Timed)
        && reports.iter().any(|r| r.semantics == Semantics::Untimed);
    if both && matches!(lens.target, VerifyTarget::Assertion { .. }) {
        let of = |s: Semantics| overall_verdict(reports.iter().copied().filter(|r| r.semantics == s));
        let (timed, untimed) = (of(Semantics::Timed), of(Semantics::Untimed));
        if timed != untimed {
            let mark = |v: Option<Verdict>| match v {
                Some(Verdict::Pass) => "✔ pass",
                Some(Verdict::Fail) => "✘ fail",
                Some(Verdict::Inconclusive) => "⚠ inconclusive",
                Some(Verdict::Unsupported) => "unsupported",
                None => "-",
            };
            return format!("timed {} · untimed {} — re-run", mark(timed), mark(untimed));
        }
    }
    let semantics = if both { ", timed and untimed" } else { "" };
    match verdict {
        Verdict::Pass => {
            let states: u64 = reports.iter().map(|r| r.stats.states).sum();
            let seconds: f64 = reports.iter().map(|r| r.stats.seconds).sum();
            format!("✔ pass{semantics} · {states} states · {}", format_seconds(seconds))
        }
        Verdict::Fail => format!("✘ fail{semantics} — re-run"),
        Verdict::Inconclusive => format!("⚠ inconclusive: {}", first_reason(Verdict::Inconclusive)),
        Verdict::Unsupported => format!("unsupported: {}", first_reason(Verdict::Unsupported)),
    }
}

/// The diagnostics of the reports about assertions of `file`: an error for
/// a failure (with the counterexample's located steps and stuck points as
/// related locations), a warning for an inconclusive check, information
/// for an unsupported one, nothing for a pass.
pub(crate) fn diagnostics(db: &dyn Db, ws: Workspace, file: File, verified: &[Verified]) -> Vec<Diagnostic> {
    let path = file.path(db);
    let mut out = Vec::new();
    for v in verified {
        let r = &v.report;
        if r.file != *path {
            continue;
        }
        let severity = match r.verdict {
            Verdict::Pass => continue,
            Verdict::Fail => Severity::Error,
            Verdict::Inconclusive => Severity::Warning,
            Verdict::Unsupported => Severity::Info,
        };
        let message = match r.reason.as_deref().map(|m| m.lines().next().unwrap_or("").trim()) {
            Some(m) if !m.is_empty() => m.to_string(),
            _ => format!("{}: {}", r.name, r.verdict.name()),
        };
        // RT-8: which of an assertion's analyses this is.
        let message = if checked_both(verified, r) || r.semantics == Semantics::Untimed {
            format!("{} semantics: {message}", r.semantics.name())
        } else {
            message
        };
        let mut related = Vec::new();
        if r.verdict == Verdict::Fail {
            if let Some(c) = &r.counterexample {
                let mut add = |loc: &Location, message: String| {
                    if let Some(f) = file_at(db, ws, &loc.file) {
                        related.push(RelatedInfo {
                            file: FileId(f),
                            path: loc.file.clone(),
                            range: loc.range,
                            message,
                        });
                    }
                };
                for s in &c.steps {
                    let Some(loc) = &s.location else { continue };
                    let mut m = format!("cycle {}, t = {}: {}", s.cycle, s.time, s.event);
                    if let Some(d) = &s.description {
                        let _ = write!(m, " — {d}");
                    }
                    add(loc, m);
                }
                let why = c.explanation.join(" ");
                for loc in &c.stuck_at {
                    add(loc, if why.is_empty() { format!("stuck ({})", c.kind) } else { why.clone() });
                }
            }
        }
        let range = if r.name_range.is_empty() { r.range } else { r.name_range };
        out.push(Diagnostic { range, severity, code: VERIFY_CODE.to_string(), message, related });
    }
    out.sort_by_key(|d| (d.range.start(), d.range.end()));
    out
}

/// The hover section of the last report on the assertion name at
/// `offset`: verdict and statistics, the reason, the notes and the
/// counterexample as a table by cycle.
pub(crate) fn hover_section(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
    verified: &[Verified],
) -> Option<(TextRange, String)> {
    let path = file.path(db);
    let v = verified.iter().rev().find(|v| v.report.file == *path && v.report.name_range.contains_inclusive(offset))?;
    // RT-8: the assertion's reports in each semantics, side by side
    // (timed first).
    let mut mine: Vec<&Verified> =
        verified.iter().filter(|o| o.report.file == *path && o.report.name_range == v.report.name_range).collect();
    mine.sort_by_key(|o| o.report.semantics == Semantics::Untimed);
    let sections: Vec<String> = mine.iter().map(|o| hover_report(db, ws, path, o, mine.len() > 1)).collect();
    Some((v.report.name_range, sections.join("\n\n---\n\n")))
}

/// Whether the assertion of `r` has reports in both semantics.
fn checked_both(verified: &[Verified], r: &Report) -> bool {
    verified
        .iter()
        .any(|o| o.report.file == r.file && o.report.name_range == r.name_range && o.report.semantics != r.semantics)
}

/// One report in a hover; `tagged`: says which semantics it is about.
fn hover_report(db: &dyn Db, ws: Workspace, path: &str, v: &Verified, tagged: bool) -> String {
    let r = &v.report;
    let mut s = if tagged || r.semantics == Semantics::Untimed {
        format!("**Last verification ({} semantics):** {}", r.semantics.name(), r.verdict.name())
    } else {
        format!("**Last verification:** {}", r.verdict.name())
    };
    if r.stats.states > 0 || r.stats.transitions > 0 {
        let _ = write!(
            s,
            " · {} states, {} transitions, {}",
            r.stats.states,
            r.stats.transitions,
            format_seconds(r.stats.seconds)
        );
    }
    let _ = write!(s, " · {}", v.profile.name());
    if let Some(reason) = &r.reason {
        let _ = write!(s, "\n\n{reason}");
    }
    for n in &r.notes {
        let _ = write!(s, "\n\n{n}");
    }
    if let Some(c) = &r.counterexample {
        let _ = write!(
            s,
            "\n\n{} reached by:\n\n```text\n{}```",
            c.kind,
            robosim_engine::verify::counterexample_table(c, &|l| short_location(db, ws, path, l))
        );
    }
    s
}

/// `path:line:col` of a location, the path relative to the directory of
/// `from` when it is below it.
fn short_location(db: &dyn Db, ws: Workspace, from: &str, loc: &Location) -> String {
    let dir = std::path::Path::new(from).parent();
    let shown = dir
        .and_then(|d| std::path::Path::new(&loc.file).strip_prefix(d).ok())
        .filter(|p| !p.as_os_str().is_empty())
        .map(|p| p.to_string_lossy().into_owned())
        .unwrap_or_else(|| loc.file.clone());
    match file_at(db, ws, &loc.file) {
        Some(f) => {
            let lc = crate::line_index(db, f).line_col(f.text(db), loc.range.start());
            format!("{shown}:{}:{}", lc.line + 1, lc.col + 1)
        }
        None => shown,
    }
}
