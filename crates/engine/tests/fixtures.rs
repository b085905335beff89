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
//! `max-states: 3` (`--max-states`); and `well-formed: true` asserts that
//! no file of the fixture has an error (`robosim check` reports nothing),
//! for fixtures whose point is a verdict on a correct model. Two options
//! shape the workspace and the reports: `include: examples/paper/design.rct`
//! adds a file of the repository (under its file name), so that a fixture
//! can check an example without a copy that would drift from it; and
//! `semantics: timed` (or `untimed`) keeps only the reports of that
//! analysis, for included assertions whose other analysis (RT-8) the
//! fixture is not about.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use robosim_engine::verify::{verify_workspace, AsyncBuffer, Options, Profile, Report, Semantics, Step, Verdict};

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
/// relative to the repository's root.
fn included(files: &[(String, String)]) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut out = Vec::new();
    for (_, text) in files {
        for line in text.lines() {
            let Some(path) = line.trim_start().strip_prefix("// option include:") else { continue };
            let path = root.join(path.trim());
            let name = path.file_name().expect("a file name").to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            out.push((name, text));
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

/// The options the `// option NAME: VALUE` lines of the fixture's files
/// set: the options of the check, whether the fixture must be well-formed,
/// and the one semantics whose reports are kept (`None`: both).
fn options(files: &[(String, String)]) -> (Options, bool, Option<Semantics>) {
    let mut opts = Options::default();
    let mut well_formed = false;
    let mut semantics = None;
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
                "well-formed" => well_formed = value.parse().unwrap_or_else(|e| panic!("{at}: {e}")),
                "semantics" => {
                    semantics = Some(match value {
                        "timed" => Semantics::Timed,
                        "untimed" => Semantics::Untimed,
                        _ => panic!("{at}: `{value}` is not a semantics (timed, untimed)"),
                    })
                }
                "include" => {}
                other => panic!(
                    "{at}: `{other}` is not an option (profile, async-buffer, max-states, well-formed, semantics, include)"
                ),
            }
        }
    }
    (opts, well_formed, semantics)
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
    let (opts, well_formed, semantics) = options(&files);
    // As `verify_texts`, with the workspace at hand for its diagnostics.
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files.clone(), robosim_hir::RuleSet::Paper);
    let mut reports = verify_workspace(&db, ws, &opts, None);
    reports.retain(|r| semantics.is_none_or(|s| r.semantics == s));
    let texts: BTreeMap<&str, &str> = files.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    let mut problems = Vec::new();
    if well_formed {
        problems.extend(
            errors(&db, ws).into_iter().map(|e| format!("{}: an error in a well-formed fixture: {e}", dir.display())),
        );
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
