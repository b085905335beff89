//! Data-driven parser tests: every input under `test_data/parser/ok`
//! parses without errors, every input under `test_data/parser/err` gets at
//! least one, and each input's tree and messages match the snapshot next to
//! it (`NAME.csp.txt`). After an intended change, refresh the snapshots with
//! `UPDATE_EXPECT=1 cargo test -p robosim-cspm --test parser_fixtures` and
//! review the diff.

use std::path::{Path, PathBuf};

fn check_dir(dir: &str, want_errors: bool) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/parser").join(dir);
    let mut inputs: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "csp"))
        .collect();
    inputs.sort();
    assert!(!inputs.is_empty(), "no inputs in {}", root.display());
    let mut wrong = Vec::new();
    for path in inputs {
        let text = std::fs::read_to_string(&path).unwrap();
        let p = robosim_cspm::parse(&text);
        assert_eq!(p.syntax_node().text().to_string(), text, "{}: not lossless", path.display());
        if p.errors().is_empty() == want_errors {
            wrong.push(format!("{}: {:?}", path.display(), p.errors()));
        }
        let mut snap = path.clone().into_os_string();
        snap.push(".txt");
        expect_test::expect_file![PathBuf::from(snap)].assert_eq(&p.debug_dump());
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn ok_inputs_parse_without_errors() {
    check_dir("ok", false);
}

#[test]
fn err_inputs_report_errors() {
    check_dir("err", true);
}
