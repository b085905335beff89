//! The semantic checks over `../shared/corpus`, one workspace per folder of
//! model files (each such folder held one RoboTool project). Under the
//! `robotool` rule set every model is error-free, except the syntax errors
//! of the six files RoboTool's grammar rejects and the deliberately
//! ill-formed fixtures of robochart2text-epsilon. Under both rule sets the
//! complete diagnostic list is snapshotted, so that any new diagnostic on a
//! real model shows up for review.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use robosim_hir::{file_diagnostics, load_workspace, RootDatabase, RuleSet, Severity};
use robosim_syntax::line_index::LineIndex;
use robosim_syntax::FileKind;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus")
}

fn project_dirs(root: &Path) -> Vec<PathBuf> {
    let mut dirs = BTreeSet::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if FileKind::from_path(&p).is_some() {
                dirs.insert(d.clone());
            }
        }
    }
    dirs.into_iter().collect()
}

fn check(rules: RuleSet) -> (String, Vec<String>) {
    let root = corpus();
    let mut out = String::new();
    let mut unexpected_errors = Vec::new();
    for dir in project_dirs(&root) {
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.is_file() && FileKind::from_path(p).is_some())
            .collect();
        files.sort();
        let texts: Vec<(String, String)> = files
            .iter()
            .map(|p| {
                let rel = p.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
                (rel, String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned())
            })
            .collect();
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, texts, rules);
        for f in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
            let text = f.text(&db);
            let idx = LineIndex::new(text);
            for d in file_diagnostics(&db, ws, *f) {
                if d.code == "SYN-01" || d.code == "SYN-02" {
                    continue; // the syntax corpus test covers these
                }
                let s = idx.line_col(text, d.range.start());
                let line = format!(
                    "{}:{}:{} {} {}: {}\n",
                    f.path(&db),
                    s.line + 1,
                    s.col + 1,
                    d.severity.as_str(),
                    d.code,
                    d.message
                );
                if d.severity == Severity::Error && !f.path(&db).contains("robochart2text-epsilon") {
                    unexpected_errors.push(line.clone());
                }
                out.push_str(&line);
            }
        }
    }
    (out, unexpected_errors)
}

#[test]
fn corpus_under_robotool_rules() {
    let (text, errors) = check(RuleSet::RoboTool);
    assert!(errors.is_empty(), "errors on models RoboTool accepts:\n{}", errors.concat());
    expect_test::expect_file!["corpus_robotool.txt"].assert_eq(&text);
}

#[test]
fn corpus_under_paper_rules() {
    let (text, _) = check(RuleSet::Paper);
    expect_test::expect_file!["corpus_paper.txt"].assert_eq(&text);
}

/// `../shared/reference/alpha-algorithm` as one project: the RoboChart
/// model, RoboTool's RoboChart-to-RoboSim output (`rc2rs/robochart`,
/// `rc2rs/robosim`, which redeclare `type ID` and name interfaces no import
/// reaches) and every assertion file. RoboTool generated CSPm from all of
/// it, so neither rule set finds an error, except the names RoboTool 1
/// generated that the csp blocks of `b1` and `b2` still use.
#[test]
fn reference_alpha_algorithm_is_error_free() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/alpha-algorithm");
    let mut texts = Vec::new();
    for dir in project_dirs(&root) {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            if p.is_file() && FileKind::from_path(&p).is_some() {
                let rel = p.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
                texts.push((rel, std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    texts.sort();
    assert!(texts.iter().any(|(p, _)| p.starts_with("rc2rs/robosim/")), "reference not found");
    for rules in [RuleSet::Paper, RuleSet::RoboTool] {
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, texts.clone(), rules);
        let mut errors = Vec::new();
        let mut unresolved = BTreeSet::new();
        for f in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
            for d in file_diagnostics(&db, ws, *f).iter().filter(|d| d.severity == Severity::Error) {
                if d.code == "CSP-N01" && f.path(&db) == "model.assertions" {
                    unresolved.insert(f.text(&db)[d.range].to_owned());
                    continue;
                }
                errors.push(format!("{} {}: {}", f.path(&db), d.code, d.message));
            }
        }
        assert!(errors.is_empty(), "{rules:?}: errors on the reference RoboTool accepted:\n{}", errors.join("\n"));
        // The csp blocks of `b1` and `b2` use RoboTool 1's names, which
        // RoboTool 3 no longer generates (the type is now `main_Position`,
        // the events `main::AggregationSoftware::receive`): FDR rejects
        // them too.
        let expected: &[&str] = match rules {
            RuleSet::Paper => &[
                "AggregationSoftware_O",
                "AggregationSoftware_broadcast",
                "AggregationSoftware_obstacle",
                "AggregationSoftware_receive",
                "Position",
                "moveCall",
                "moveRet",
            ],
            RuleSet::RoboTool => &[],
        };
        assert_eq!(unresolved.iter().map(String::as_str).collect::<Vec<_>>(), expected, "{rules:?}");
    }
}
