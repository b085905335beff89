//! `robosim verify`: runs the assertions of the workspace's assertion files
//! with the native checker and reports verdicts, statistics and
//! counterexamples (a table for people, one JSON object for machines).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use robosim_ide::diagram::render_marked;
use robosim_ide::verify::{
    counterexample_table, Budget, Counterexample, Location, Options, Profile, Report, Semantics, Stats, Step, Verdict,
};
use serde_json::{json, Value};

use crate::workspace::{done, Workspace};
use crate::{fail, Format};

/// The command's arguments.
pub struct Args {
    pub format: Format,
    pub profile: Profile,
    pub max_states: Option<u64>,
    pub timeout: Option<f64>,
    pub threads: Option<usize>,
    /// The buffer assumed for asynchronous connections.
    pub async_buffer: Option<robosim_ide::verify::AsyncBuffer>,
    /// Where to draw the counterexamples on diagrams, if anywhere.
    pub diagrams: Option<PathBuf>,
    pub paths: Vec<PathBuf>,
}

pub fn run(args: Args) -> ExitCode {
    let ws = match Workspace::load(&args.paths, robosim_ide::RuleSet::Paper) {
        Ok(ws) => ws,
        Err(e) => return fail(e),
    };
    let mut budget = Budget::default();
    if let Some(n) = args.max_states {
        budget.max_states = n;
    }
    if let Some(t) = args.timeout {
        if !(t.is_finite() && t > 0.0) {
            return fail("--timeout takes a positive number of seconds");
        }
        budget.timeout = Some(Duration::from_secs_f64(t));
    }
    if let Some(n) = args.threads {
        budget = budget.with_threads(n.max(1));
    }
    let opts = Options { profile: args.profile, budget, async_buffer: args.async_buffer };
    // A progress line on a terminal, for checks that take a while.
    let show_progress = std::io::stderr().is_terminal() && matches!(args.format, Format::Human);
    let started = Instant::now();
    let last = Mutex::new(Instant::now());
    let progress = |s: &Stats| {
        if !show_progress || started.elapsed() < Duration::from_millis(500) {
            return;
        }
        if let Ok(mut l) = last.lock() {
            if l.elapsed() >= Duration::from_millis(200) {
                *l = Instant::now();
                eprint!("\r  exploring: {} states, {} transitions, ply {} …   ", s.states, s.transitions, s.plies);
            }
        }
    };
    let reports = done(ws.analysis.verify_workspace(&opts, Some(&progress)));
    if show_progress && started.elapsed() >= Duration::from_millis(500) {
        eprint!("\r{}\r", " ".repeat(72));
    }
    if let Some(dir) = &args.diagrams {
        match draw_counterexamples(&ws, &reports, dir) {
            Ok(n) => eprintln!("robosim: drew {n} counterexample diagrams in {}", dir.display()),
            Err(e) => return fail(format!("cannot write diagrams to `{}`: {e}", dir.display())),
        }
    }
    let out = std::io::stdout();
    let result = match args.format {
        Format::Json => writeln!(out.lock(), "{}", to_json(&ws, &reports)),
        Format::Human => {
            let mut text = render_human(&ws, &reports, args.profile);
            // A verdict that holds only under the buffer (RoboTool's, or the
            // one assumed instead) says so.
            {
                let b = args.async_buffer.unwrap_or(robosim_ide::verify::AsyncBuffer::ROBOTOOL);
                let assumption = b.describe();
                if reports.iter().any(|r| r.notes.iter().any(|n| n.contains(&assumption))) {
                    text.push_str(&format!("assumed: {assumption}\n"));
                }
            }
            write!(out.lock(), "{text}")
        }
    };
    if let Err(e) = result {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            return fail(format!("cannot write the report: {e}"));
        }
    }
    ExitCode::from(exit_status(&reports))
}

/// Draws each counterexample on the diagrams of the machines it passes
/// through: `DIR/ASSERTION.ELEMENT.svg` (`ASSERTION.untimed.ELEMENT.svg`
/// for the untimed analysis), the states and transitions of its
/// steps highlighted with their cycles. Returns how many files were written.
fn draw_counterexamples(ws: &Workspace, reports: &[Report], dir: &std::path::Path) -> std::io::Result<usize> {
    std::fs::create_dir_all(dir)?;
    let mut written = 0;
    for r in reports {
        let Some(c) = &r.counterexample else { continue };
        for f in ws.files.iter().take(ws.user_files) {
            for d in done(ws.analysis.diagram_models(f.id)) {
                if d.region.is_none() {
                    continue;
                }
                // RT-8: the untimed analysis's witness beside the timed one's.
                let semantics = if r.semantics == Semantics::Untimed { ".untimed" } else { "" };
                let name = format!("{}{semantics}.{}.svg", r.name, d.qualified_name.replace("::", "."));
                if let Some(marked) = render_marked(d, std::slice::from_ref(c)) {
                    std::fs::write(dir.join(name), marked.svg)?;
                    written += 1;
                }
            }
        }
    }
    Ok(written)
}

/// 0 when every assertion passes, 1 when one fails, 3 when none fails but
/// some could not be decided.
fn exit_status(reports: &[Report]) -> u8 {
    if reports.iter().any(|r| r.verdict == Verdict::Fail) {
        1
    } else if reports.iter().all(|r| r.verdict == Verdict::Pass) {
        0
    } else {
        3
    }
}

/// A (0-based line, column) pair.
type LineCol = (u32, u32);

/// The start and end of `loc` in its file, when the file is loaded.
fn position(ws: &Workspace, loc: &Location) -> Option<(LineCol, LineCol)> {
    let i = ws.files.iter().position(|f| f.path == loc.file)?;
    Some((ws.line_col(i, loc.range.start()), ws.line_col(i, loc.range.end())))
}

fn json_location(ws: &Workspace, loc: &Location) -> Value {
    match position(ws, loc) {
        Some((s, e)) => json!({
            "file": loc.file,
            "range": {"start": {"line": s.0, "character": s.1}, "end": {"line": e.0, "character": e.1}},
        }),
        None => json!({ "file": loc.file }),
    }
}

fn json_step(ws: &Workspace, s: &Step) -> Value {
    json!({
        "event": s.event,
        "visible": s.visible,
        "cycle": s.cycle,
        "time": s.time,
        "description": s.description,
        "location": s.location.as_ref().map(|l| json_location(ws, l)),
    })
}

fn json_counterexample(ws: &Workspace, c: &Counterexample) -> Value {
    json!({
        "kind": c.kind,
        "steps": c.steps.iter().map(|s| json_step(ws, s)).collect::<Vec<_>>(),
        "explanation": c.explanation,
        "stuckAt": c.stuck_at.iter().map(|l| json_location(ws, l)).collect::<Vec<_>>(),
        "specification": c.specification.iter().map(|s| json_step(ws, s)).collect::<Vec<_>>(),
    })
}

/// `{"assertions": [...]}`: one entry per assertion and semantics it is
/// checked in (`"semantics"`: `timed` or `untimed`, RT-8), so a plain
/// assertion about a RoboChart element has two, timed first.
pub fn to_json(ws: &Workspace, reports: &[Report]) -> Value {
    let list: Vec<Value> = reports
        .iter()
        .map(|r| {
            let at = Location { file: r.file.clone(), range: r.range };
            json!({
                "file": r.file,
                "name": r.name,
                "text": r.text,
                "range": json_location(ws, &at)["range"].clone(),
                "semantics": r.semantics.name(),
                "verdict": r.verdict.name(),
                "states": r.stats.states,
                "transitions": r.stats.transitions,
                "seconds": r.stats.seconds,
                "counterexample": r.counterexample.as_ref().map(|c| json_counterexample(ws, c)),
                "reason": r.reason,
                "notes": r.notes,
            })
        })
        .collect();
    json!({ "assertions": list })
}

/// The assertion's claim without its keyword, name and `with …` clauses.
fn headline(text: &str) -> &str {
    let body = text.split_once(':').map_or(text, |(_, b)| b.trim());
    body.split_once(" with ").map_or(body, |(b, _)| b).trim_end_matches(" .").trim_end_matches('.').trim()
}

fn short_location(ws: &Workspace, loc: &Location) -> String {
    match position(ws, loc) {
        Some((s, _)) => format!("{}:{}:{}", loc.file, s.0 + 1, s.1 + 1),
        None => loc.file.clone(),
    }
}

/// The verdict table, then the details of each failure.
pub fn render_human(ws: &Workspace, reports: &[Report], profile: Profile) -> String {
    let mut s = String::new();
    if reports.is_empty() {
        s.push_str("no assertions found (assertions live in .rsa and .assertions files)\n");
        return s;
    }
    let mut file = "";
    for r in reports {
        if r.file != file {
            file = &r.file;
            s.push_str(&format!("{file}\n"));
        }
        let stats = if r.stats.states > 0 {
            format!("  ({} states, {} transitions, {:.3} s)", r.stats.states, r.stats.transitions, r.stats.seconds)
        } else {
            String::new()
        };
        s.push_str(&format!(
            "  {:<13} {}{}: {}{stats}\n",
            r.verdict.name(),
            r.name,
            semantics_tag(reports, r),
            headline(&r.text)
        ));
        if r.verdict != Verdict::Pass {
            if let Some(reason) = &r.reason {
                s.push_str(&format!("                {reason}\n"));
            }
        }
        if let Some(c) = &r.counterexample {
            if r.verdict == Verdict::Fail {
                render_counterexample(&mut s, ws, c);
            }
        }
    }
    let count = |v: Verdict| reports.iter().filter(|r| r.verdict == v).count();
    // RT-8: an assertion checked in both semantics counts once, its
    // verdicts once per semantics.
    let mut names: Vec<(&str, &str)> = reports.iter().map(|r| (r.file.as_str(), r.name.as_str())).collect();
    names.dedup();
    let analyses = if names.len() == reports.len() {
        String::new()
    } else {
        format!("; {} analyses, timed and untimed", reports.len())
    };
    s.push_str(&format!(
        "verified {} assertions ({}{analyses}): {} pass, {} fail, {} inconclusive, {} unsupported\n",
        names.len(),
        profile.name(),
        count(Verdict::Pass),
        count(Verdict::Fail),
        count(Verdict::Inconclusive),
        count(Verdict::Unsupported)
    ));
    s
}

/// ` [untimed]`, ` [timed]` after an assertion's name when it is checked in
/// the untimed semantics (RT-8: a plain assertion in both, side by side);
/// nothing for an assertion checked timed only.
fn semantics_tag(reports: &[Report], r: &Report) -> String {
    let both = reports.iter().any(|o| o.file == r.file && o.name == r.name && o.semantics != r.semantics);
    if both || r.semantics == Semantics::Untimed {
        format!(" [{}]", r.semantics.name())
    } else {
        String::new()
    }
}

/// A counterexample grouped by cycle, indented under its assertion.
fn render_counterexample(s: &mut String, ws: &Workspace, c: &Counterexample) {
    let pad = "                ";
    s.push_str(&format!("{pad}{} reached by:\n", c.kind));
    for line in counterexample_table(c, &|l| short_location(ws, l)).lines() {
        s.push_str(&format!("{pad}  {line}\n"));
    }
}
