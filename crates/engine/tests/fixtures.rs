//! Data-driven verification tests: each folder of `test_data/verify` is a
//! workspace (models and assertion files) checked as `robosim verify`
//! checks it.
//!
//! Two things are compared, so that a fixture cannot pass merely by
//! recording what the engine happens to say:
//!
//! - **The verdicts, stated by hand.** Every assertion has a line
//!   `// expect NAME: VERDICT` in its file (or `// expect NAME: timed
//!   VERDICT, untimed VERDICT` when the two analyses of a plain assertion
//!   differ, RT-8), written from RoboTool's meaning with the reason beside
//!   it. A report without an expectation, or an expectation without a
//!   report, fails the test.
//! - **Everything else, as a snapshot** (`test_data/verify/NAME.txt`): the
//!   reason, the notes, the counterexample's steps with their lines and
//!   columns, the explanation and the state and transition counts, so that
//!   a change in any of them is seen in review. `UPDATE_EXPECT=1`
//!   refreshes the snapshots (never the hand-written verdicts).
//!
//! A line `// option NAME: VALUE` in any file of a fixture sets an option
//! of the whole check, as the command line would: `profile: paper2019`
//! (`--profile`), `async-buffer: 2:block` (`--async-buffer`),
//! `max-states: 3` (`--max-states`). Two options
//! shape the workspace and the reports: `include: examples/paper/design.rct`
//! adds a file of the repository (under its file name), so that a fixture
//! can check an example without a copy that would drift from it; and
//! `semantics: timed` (or `untimed`) keeps only the reports of that
//! analysis, for included assertions whose other analysis (RT-8) the
//! fixture is not about. `include` may name a folder: its model files,
//! under their paths relative to it (the corpus's projects, in
//! `../shared`). `only: FILE` keeps the reports of the files whose name
//! ends with FILE, and `only: FILE: A B …` of those assertions of it (a
//! project's assertions the fixture is about). `timeout: SECONDS` bounds
//! each check's time (`--timeout`).
//!
//! Beside the verdict, a fixture may state by hand what else a report
//! must show, so that a refreshed snapshot cannot lose it unseen. Each
//! line names an assertion, optionally one analysis (`timed`, `untimed`);
//! it holds of every report it names, and must name one:
//!
//! - `// expect-trace NAME: KIND: TRACE`: the counterexample's kind and
//!   visible events (`trace_text`), or `none` for no counterexample;
//! - `// expect-reason NAME: TEXT`: the reason contains TEXT;
//! - `// expect-note NAME: TEXT` / `// expect-no-note NAME: TEXT`: some /
//!   no note contains TEXT;
//! - `// expect-explanation NAME: TEXT`: a line of the counterexample's
//!   explanation contains TEXT;
//! - `// expect-states NAME: N`: the check explored N states;
//! - `// expect-same NAME: OTHER`: the same verdict, states and
//!   counterexample (kind and trace) as OTHER in the same analysis.
//!
//! For example `// expect-trace B untimed: trace: o.out`.
//!
//! **Every fixture is well-formed** (no file of it, included files too,
//! has an error: `robosim check` accepts it): RoboTool generates CSPm only
//! for models its validator accepts, so a verdict on an ill-formed model
//! states nothing RoboTool + FDR would say. A fixture whose point is an
//! ill-formed or unusual input (a reason for refusing something, a name
//! FDR would not resolve either) says so with `// option ill-formed:
//! REASON`; the runner then asserts that it does have an error, so the
//! option cannot outlive its reason.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use robosim_engine::verify::{
    trace_text, verify_workspace, AsyncBuffer, Options, Profile, Report, Semantics, Step, Verdict,
};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/verify")
}

/// The files of a fixture folder, as (name relative to it, text).
fn files(dir: &Path) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| robosim_test_support::inputs::is_model_file(p))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (name, text)
        })
        .collect();
    out.sort();
    out
}

/// The files the `// option include: PATH` lines of `files` name, PATH
/// relative to the repository's root: a file under its name, a folder's
/// model files under their paths relative to it.
fn included(files: &[(String, String)]) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    // Lossy: a corpus file need not be UTF-8 (as `robosim verify` reads it).
    let read = |p: &Path| {
        String::from_utf8_lossy(&std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).into_owned()
    };
    let mut out = Vec::new();
    for (_, text) in files {
        for line in text.lines() {
            let Some(path) = line.trim_start().strip_prefix("// option include:") else { continue };
            let path = root.join(path.trim());
            if path.is_dir() {
                let mut paths = Vec::new();
                robosim_test_support::inputs::model_files(&path, &mut paths);
                assert!(!paths.is_empty(), "{}: no model files", path.display());
                for p in paths {
                    let name = p.strip_prefix(&path).expect("under the folder").to_string_lossy().into_owned();
                    out.push((name, read(&p)));
                }
            } else {
                let name = path.file_name().expect("a file name").to_string_lossy().into_owned();
                out.push((name, read(&path)));
            }
        }
    }
    out
}

/// The verdict a line `// expect NAME: …` states for each semantics.
#[derive(Debug)]
struct Expected {
    timed: Option<Verdict>,
    untimed: Option<Verdict>,
    /// `file:line` of the expectation, for messages.
    at: String,
}

fn verdict(word: &str, at: &str) -> Verdict {
    match word {
        "pass" => Verdict::Pass,
        "fail" => Verdict::Fail,
        "inconclusive" => Verdict::Inconclusive,
        "unsupported" => Verdict::Unsupported,
        _ => panic!("{at}: `{word}` is not a verdict (pass, fail, inconclusive, unsupported)"),
    }
}

/// Reads the `// expect` lines of the fixture's files. `// expect A: pass`
/// expects `pass` in whichever analyses the assertion has; `timed fail,
/// untimed pass` names each.
fn expectations(files: &[(String, String)]) -> BTreeMap<String, Expected> {
    let mut out = BTreeMap::new();
    for (name, text) in files {
        for (i, line) in text.lines().enumerate() {
            let Some(rest) = line.trim_start().strip_prefix("// expect ") else { continue };
            let at = format!("{name}:{}", i + 1);
            let (assertion, verdicts) =
                rest.split_once(':').unwrap_or_else(|| panic!("{at}: `// expect NAME: VERDICT`"));
            // The reason may follow the verdicts after ` — `.
            let verdicts = verdicts.split(" — ").next().unwrap_or_default().trim();
            let mut e = Expected { timed: None, untimed: None, at: at.clone() };
            for part in verdicts.split(',').map(str::trim) {
                match part.split_once(' ') {
                    Some(("timed", v)) => e.timed = Some(verdict(v.trim(), &at)),
                    Some(("untimed", v)) => e.untimed = Some(verdict(v.trim(), &at)),
                    None => {
                        let v = verdict(part, &at);
                        e.timed = Some(v);
                        e.untimed = Some(v);
                    }
                    Some(_) => panic!("{at}: `{part}`: write `VERDICT` or `timed VERDICT, untimed VERDICT`"),
                }
            }
            assert!(
                out.insert(assertion.trim().to_string(), e).is_none(),
                "{at}: a second expectation for {assertion}"
            );
        }
    }
    out
}

/// What a line `// expect-KIND NAME [SEMANTICS]: VALUE` states of a report.
#[derive(Debug)]
struct Fact {
    kind: String,
    name: String,
    semantics: Option<Semantics>,
    value: String,
    /// `file:line` of the line, for messages.
    at: String,
}

/// Reads the `// expect-…` lines of the fixture's files.
fn facts(files: &[(String, String)]) -> Vec<Fact> {
    let mut out = Vec::new();
    for (file, text) in files {
        for (i, line) in text.lines().enumerate() {
            let Some(rest) = line.trim_start().strip_prefix("// expect-") else { continue };
            let at = format!("{file}:{}", i + 1);
            let (head, value) = rest.split_once(':').unwrap_or_else(|| panic!("{at}: `// expect-KIND NAME: VALUE`"));
            let mut words = head.split_whitespace();
            let (Some(kind), Some(name)) = (words.next(), words.next()) else {
                panic!("{at}: `// expect-KIND NAME [SEMANTICS]: VALUE`")
            };
            let semantics = words.next().map(|w| match w {
                "timed" => Semantics::Timed,
                "untimed" => Semantics::Untimed,
                _ => panic!("{at}: `{w}` is not a semantics (timed, untimed)"),
            });
            assert!(
                ["trace", "reason", "note", "no-note", "explanation", "states", "same"].contains(&kind),
                "{at}: `expect-{kind}` is not a fact (trace, reason, note, no-note, explanation, states, same)"
            );
            let value = value.trim().to_string();
            out.push(Fact { kind: kind.to_string(), name: name.to_string(), semantics, value, at });
        }
    }
    out
}

/// A counterexample as `KIND: TRACE`, or `none`.
fn trace_of(r: &Report) -> String {
    r.counterexample.as_ref().map_or("none".to_string(), |c| format!("{}: {}", c.kind, trace_text(&c.steps)))
}

/// Whether `r` shows `fact`; if not, what it shows instead.
fn holds(fact: &Fact, r: &Report, reports: &[Report]) -> Result<(), String> {
    let v = fact.value.as_str();
    let ok = match fact.kind.as_str() {
        "trace" => trace_of(r).trim_end() == v,
        "reason" => r.reason.as_deref().is_some_and(|x| x.contains(v)),
        "note" => r.notes.iter().any(|n| n.contains(v)),
        "no-note" => !r.notes.iter().any(|n| n.contains(v)),
        "explanation" => r.counterexample.as_ref().is_some_and(|c| c.explanation.iter().any(|e| e.contains(v))),
        "states" => v.parse::<u64>().unwrap_or_else(|e| panic!("{}: {e}", fact.at)) == r.stats.states,
        "same" => {
            let other = reports
                .iter()
                .find(|o| o.name == v && o.semantics == r.semantics)
                .ok_or_else(|| format!("no {:?} report {v}", r.semantics))?;
            let shown = |x: &Report| (x.verdict, x.stats.states, trace_of(x));
            if shown(r) == shown(other) {
                return Ok(());
            }
            return Err(format!("{:?}, where {v} has {:?}", shown(r), shown(other)));
        }
        _ => unreachable!("checked by `facts`"),
    };
    if ok {
        return Ok(());
    }
    let c = r.counterexample.as_ref();
    Err(match fact.kind.as_str() {
        "trace" => trace_of(r),
        "reason" => format!("{:?}", r.reason),
        "note" | "no-note" => format!("{:?}", r.notes),
        "explanation" => format!("{:?}", c.map(|c| &c.explanation)),
        _ => r.stats.states.to_string(),
    })
}

/// What the `// option NAME: VALUE` lines of a fixture's files set.
struct Setup {
    /// The options of the check.
    opts: Options,
    /// Why the fixture is ill-formed (`None`: it must be well-formed).
    ill_formed: Option<String>,
    /// The one semantics whose reports are kept (`None`: both).
    semantics: Option<Semantics>,
    /// The reports kept: of a file whose name ends with the first, named
    /// one of the second (empty: any name).
    only: Option<(String, Vec<String>)>,
}

fn options(files: &[(String, String)]) -> Setup {
    let mut setup = Setup { opts: Options::default(), ill_formed: None, semantics: None, only: None };
    let opts = &mut setup.opts;
    for (name, text) in files {
        for (i, line) in text.lines().enumerate() {
            let Some(rest) = line.trim_start().strip_prefix("// option ") else { continue };
            let at = format!("{name}:{}", i + 1);
            let (option, value) = rest.split_once(':').unwrap_or_else(|| panic!("{at}: `// option NAME: VALUE`"));
            let value = value.trim();
            match option.trim() {
                "profile" => {
                    opts.profile = match value {
                        "robotool3" => Profile::RoboTool3,
                        "paper2019" => Profile::Paper2019,
                        _ => panic!("{at}: `{value}` is not a profile (robotool3, paper2019)"),
                    }
                }
                "async-buffer" => {
                    opts.async_buffer = Some(AsyncBuffer::parse(value).unwrap_or_else(|e| panic!("{at}: {e}")))
                }
                "max-states" => opts.budget.max_states = value.parse().unwrap_or_else(|e| panic!("{at}: {e}")),
                "timeout" => {
                    let secs = value.parse().unwrap_or_else(|e| panic!("{at}: {e}"));
                    opts.budget.timeout = Some(std::time::Duration::from_secs(secs));
                }
                "ill-formed" => {
                    assert!(!value.is_empty(), "{at}: `// option ill-formed: REASON` needs its reason");
                    setup.ill_formed = Some(value.to_string())
                }
                "semantics" => {
                    setup.semantics = Some(match value {
                        "timed" => Semantics::Timed,
                        "untimed" => Semantics::Untimed,
                        _ => panic!("{at}: `{value}` is not a semantics (timed, untimed)"),
                    })
                }
                "only" => {
                    let (file, names) = value.split_once(':').unwrap_or((value, ""));
                    let names = names.split_whitespace().map(str::to_string).collect();
                    setup.only = Some((file.trim().to_string(), names));
                }
                "include" => {}
                other => panic!(
                    "{at}: `{other}` is not an option (profile, async-buffer, max-states, timeout, ill-formed, \
                     semantics, include, only)"
                ),
            }
        }
    }
    setup
}

/// The errors of the fixture's files, as `robosim check` reports them.
fn errors(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace) -> Vec<String> {
    ws.files(db)
        .iter()
        .flat_map(|&f| robosim_hir::file_diagnostics(db, ws, f))
        .filter(|d| d.severity == robosim_hir::Severity::Error)
        .map(|d| format!("{} {}", d.code, d.message))
        .collect()
}

/// `line:column` (1-based, in characters) of a byte offset.
fn line_col(text: &str, offset: usize) -> String {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or_default().chars().count() + 1;
    format!("{line}:{col}")
}

fn step(out: &mut String, texts: &BTreeMap<&str, &str>, i: usize, s: &Step) {
    let _ = write!(out, "    {:>2}. {}", i + 1, s.event);
    if let Some(d) = &s.description {
        let _ = write!(out, " — {d}");
    }
    if let Some(l) = &s.location {
        let text = texts.get(l.file.as_str()).copied().unwrap_or_default();
        let _ = write!(out, " @ {} {}", l.file, line_col(text, l.range.start().into()));
    }
    out.push('\n');
}

/// A report as the snapshot shows it.
fn render(out: &mut String, texts: &BTreeMap<&str, &str>, r: &Report) {
    let semantics = match r.semantics {
        Semantics::Timed => "timed",
        Semantics::Untimed => "untimed",
    };
    let _ = writeln!(
        out,
        "{} [{semantics}]: {} — {} states, {} transitions",
        r.name,
        r.verdict.name(),
        r.stats.states,
        r.stats.transitions
    );
    if let Some(reason) = &r.reason {
        let _ = writeln!(out, "  reason: {reason}");
    }
    for n in &r.notes {
        let _ = writeln!(out, "  note: {n}");
    }
    if let Some(c) = &r.counterexample {
        let _ = writeln!(out, "  counterexample ({}):", c.kind);
        for (i, s) in c.steps.iter().enumerate() {
            step(out, texts, i, s);
        }
        if !c.specification.is_empty() {
            let _ = writeln!(out, "  the specification:");
            for (i, s) in c.specification.iter().enumerate() {
                step(out, texts, i, s);
            }
        }
        for e in &c.explanation {
            let _ = writeln!(out, "  explanation: {e}");
        }
        for l in &c.stuck_at {
            let text = texts.get(l.file.as_str()).copied().unwrap_or_default();
            let _ = writeln!(out, "  stuck at: {} {}", l.file, line_col(text, l.range.start().into()));
        }
    }
}

fn check_fixture(dir: &Path) -> Vec<String> {
    let mut files = files(dir);
    files.extend(included(&files));
    let expected = expectations(&files);
    let facts = facts(&files);
    let Setup { opts, ill_formed, semantics, only } = options(&files);
    // As `verify_texts`, with the workspace at hand for its diagnostics.
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files.clone(), robosim_hir::RuleSet::Paper);
    let mut reports = verify_workspace(&db, ws, &opts, None);
    reports.retain(|r| semantics.is_none_or(|s| r.semantics == s));
    if let Some((file, names)) = &only {
        reports.retain(|r| r.file.ends_with(file.as_str()) && (names.is_empty() || names.contains(&r.name)));
    }
    let texts: BTreeMap<&str, &str> = files.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    let mut problems = Vec::new();
    let errors = errors(&db, ws);
    match &ill_formed {
        None => problems.extend(errors.into_iter().map(|e| {
            format!("{}: an error in a well-formed fixture (or `// option ill-formed: REASON`): {e}", dir.display())
        })),
        Some(reason) if errors.is_empty() => {
            problems.push(format!("{}: `ill-formed: {reason}`, but no file of the fixture has an error", dir.display()))
        }
        Some(_) => {}
    }
    let mut snapshot = String::new();
    for r in &reports {
        render(&mut snapshot, &texts, r);
        let Some(e) = expected.get(&r.name) else {
            problems.push(format!("{}: {} has no `// expect {}: …` line", dir.display(), r.name, r.name));
            continue;
        };
        let want = match r.semantics {
            Semantics::Timed => e.timed,
            Semantics::Untimed => e.untimed,
        };
        match want {
            Some(v) if v == r.verdict => {}
            Some(v) => problems.push(format!(
                "{} ({}): {} [{:?}] is {}, expected {}{}",
                dir.display(),
                e.at,
                r.name,
                r.semantics,
                r.verdict.name(),
                v.name(),
                r.reason.as_deref().map(|x| format!(" — {x}")).unwrap_or_default()
            )),
            None => problems.push(format!(
                "{} ({}): {} has no expectation for {:?}",
                dir.display(),
                e.at,
                r.name,
                r.semantics
            )),
        }
    }
    for (name, e) in &expected {
        if !reports.iter().any(|r| &r.name == name) {
            problems.push(format!("{} ({}): no assertion named {name} was checked", dir.display(), e.at));
        }
    }
    for f in &facts {
        let named: Vec<&Report> =
            reports.iter().filter(|r| r.name == f.name && f.semantics.is_none_or(|s| r.semantics == s)).collect();
        if named.is_empty() {
            problems.push(format!("{} ({}): no report {} {:?} was made", dir.display(), f.at, f.name, f.semantics));
        }
        for r in named {
            if let Err(got) = holds(f, r, &reports) {
                problems.push(format!(
                    "{} ({}): {} [{:?}]: expect-{} {}, got {got}",
                    dir.display(),
                    f.at,
                    r.name,
                    r.semantics,
                    f.kind,
                    f.value
                ));
            }
        }
    }
    let snap = dir.with_extension("txt");
    expect_test::expect_file![snap].assert_eq(&snapshot);
    problems
}

#[test]
fn verify_fixtures() {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(fixtures())
        .expect("test_data/verify")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 3, "{dirs:?}");
    let problems: Vec<String> = dirs.iter().flat_map(|d| check_fixture(d)).collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
