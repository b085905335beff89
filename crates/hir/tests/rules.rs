//! Data-driven rule tests. Each folder of `test_data/rules` is a workspace
//! (all its model files, plus the bundled library). Directives in `//`
//! comments of its files say what must hold:
//!
//! - `// expect: CODE` — at least one diagnostic with CODE;
//! - `// expect-none: CODE` — no diagnostic with CODE;
//! - `// rules: robotool` — check under the `robotool` rule set.
//!
//! The whole diagnostic list is also snapshotted in `expected.txt` (refresh
//! with `UPDATE_EXPECT=1 cargo test -p robosim-hir --test rules`), so new
//! false positives show up as a diff.

use std::path::{Path, PathBuf};

use robosim_hir::{file_diagnostics, load_workspace, RootDatabase, RuleSet};
use robosim_syntax::line_index::LineIndex;
use robosim_syntax::FileKind;

fn model_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if FileKind::from_path(&p).is_some() {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Renders the diagnostics of a workspace folder, one per line.
pub fn render(dir: &Path, rules: RuleSet) -> (String, Vec<String>) {
    let files = model_files(dir);
    let texts: Vec<(String, String)> = files
        .iter()
        .map(|p| {
            let rel = p.strip_prefix(dir).unwrap().to_string_lossy().replace('\\', "/");
            (rel, std::fs::read_to_string(p).unwrap())
        })
        .collect();
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, texts.clone(), rules);
    let mut lines = Vec::new();
    let mut codes = Vec::new();
    for f in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
        let text = f.text(&db);
        let idx = LineIndex::new(text);
        for d in file_diagnostics(&db, ws, *f) {
            let s = idx.line_col(text, d.range.start());
            let e = idx.line_col(text, d.range.end());
            lines.push(format!(
                "{}:{}:{}-{}:{} {} {}: {}",
                f.path(&db),
                s.line + 1,
                s.col + 1,
                e.line + 1,
                e.col + 1,
                d.severity.as_str(),
                d.code,
                d.message
            ));
            for r in &d.related {
                let rt = r.file.text(&db);
                let ri = LineIndex::new(rt);
                let rs = ri.line_col(rt, r.range.start());
                lines.push(format!("    related {}:{}:{}: {}", r.file.path(&db), rs.line + 1, rs.col + 1, r.message));
            }
            codes.push(d.code.clone());
        }
    }
    (lines.join("\n") + "\n", codes)
}

#[test]
fn rule_fixtures() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/rules");
    let mut dirs: Vec<PathBuf> =
        std::fs::read_dir(&root).unwrap().flatten().map(|e| e.path()).filter(|p| p.is_dir()).collect();
    dirs.sort();
    assert!(!dirs.is_empty());
    let mut failures = Vec::new();
    for dir in dirs {
        let mut expect = Vec::new();
        let mut expect_none = Vec::new();
        let mut rules = RuleSet::Paper;
        for f in model_files(&dir) {
            for line in std::fs::read_to_string(&f).unwrap().lines() {
                let l = line.trim();
                if let Some(c) = l.strip_prefix("// expect:") {
                    expect.extend(c.split_whitespace().map(str::to_string));
                } else if let Some(c) = l.strip_prefix("// expect-none:") {
                    expect_none.extend(c.split_whitespace().map(str::to_string));
                } else if l.starts_with("// rules: robotool") {
                    rules = RuleSet::RoboTool;
                }
            }
        }
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            !expect.is_empty() || !expect_none.is_empty(),
            "{name}: no `// expect:` or `// expect-none:` directive"
        );
        let (text, codes) = render(&dir, rules);
        for c in &codes {
            if robosim_hir::codes::rule(c).is_none() {
                failures.push(format!("{name}: code {c} is not in the rule catalogue (codes.rs)"));
            }
        }
        for c in &expect {
            if !codes.contains(c) {
                failures.push(format!("{name}: expected a {c} diagnostic, got:\n{text}"));
            }
        }
        for c in &expect_none {
            if codes.contains(c) {
                failures.push(format!("{name}: expected no {c} diagnostic, got:\n{text}"));
            }
        }
        expect_test::expect_file![dir.join("expected.txt")].assert_eq(&text);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
