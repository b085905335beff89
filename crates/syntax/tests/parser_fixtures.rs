//! Data-driven parser tests: every input under `test_data/parser/ok` parses
//! without syntax errors, every input under `test_data/parser/err` gets at
//! least one, and each input's tree and messages match the snapshot next to
//! it (`NAME.txt`). After an intended change, refresh the snapshots with
//! `UPDATE_EXPECT=1 cargo test -p robosim-syntax --test parser_fixtures`
//! and review the diff.

use std::path::{Path, PathBuf};

use robosim_syntax::{parse, FileKind, Severity};

fn inputs(dir: &str) -> Vec<(PathBuf, FileKind)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/parser").join(dir);
    let mut out: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter_map(|p| FileKind::from_path(&p).map(|k| (p, k)))
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(!out.is_empty(), "no inputs in {}", root.display());
    out
}

fn check_dir(dir: &str, want_errors: bool) {
    let mut wrong = Vec::new();
    for (path, kind) in inputs(dir) {
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let p = parse(&text, kind);
        assert_eq!(p.syntax_node().text().to_string(), text, "{}: not lossless", path.display());
        let errors = p.errors().iter().filter(|e| e.severity == Severity::Error).count();
        if (errors > 0) != want_errors {
            wrong.push(format!("{}: {errors} errors\n{}", path.display(), messages(&p)));
        }
        let mut snap = path.clone().into_os_string();
        snap.push(".txt");
        expect_test::expect_file![PathBuf::from(snap)].assert_eq(&p.debug_dump());
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

fn messages(p: &robosim_syntax::Parse) -> String {
    p.errors().iter().map(|e| format!("  {:?} {:?}: {}\n", e.severity, e.range, e.message)).collect()
}

#[test]
fn ok_inputs_parse_without_errors() {
    check_dir("ok", false);
}

#[test]
fn err_inputs_report_errors() {
    check_dir("err", true);
}
