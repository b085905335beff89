//! Data-driven snapshots: every input `test_data/NAME.{rct,rst,assertions,rsa}`
//! (badly formatted on purpose) is formatted and compared with
//! `test_data/expected/NAME.EXT`. The expected output must itself be a fixed
//! point. After an intended change of style, refresh the snapshots with
//! `UPDATE_EXPECT=1 cargo test -p robosim-fmt --test snapshots` and review
//! the diff.

use std::path::{Path, PathBuf};

use robosim_fmt::{format, FormatError, Options};
use robosim_syntax::FileKind;

fn inputs() -> Vec<(PathBuf, FileKind)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data");
    let mut out: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .filter_map(|p| FileKind::from_path(&p).map(|k| (p, k)))
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(out.len() >= 8, "expected the inputs in {}", dir.display());
    out
}

#[test]
fn formatted_inputs_match_their_snapshots() {
    let mut kinds = Vec::new();
    for (path, kind) in inputs() {
        let text = std::fs::read_to_string(&path).unwrap();
        let out = format(&text, kind, &Options::default()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let expected = path.parent().unwrap().join("expected").join(path.file_name().unwrap());
        expect_test::expect_file![expected].assert_eq(&out);
        let again = format(&out, kind, &Options::default()).unwrap();
        assert_eq!(again, out, "{}: the canonical form is not a fixed point", path.display());
        kinds.push(kind);
    }
    for kind in FileKind::ALL {
        assert!(kinds.contains(&kind), "no input of kind {kind:?}");
    }
}

#[test]
fn files_with_syntax_errors_are_refused() {
    let cases = [
        ("stm M { state S { entry x = 1; } }", FileKind::RoboChart, "1:30: `;` separates statements"),
        ("stm M {\n  transition t { from a b }\n}", FileKind::RoboChart, "2:25: expected `to`"),
        ("interface I { event e", FileKind::RoboChart, "expected `}`"),
        ("stm M { transition t { from a to b trigger e } }", FileKind::RoboSim, "RoboSim transitions have no"),
        ("assertion A : M is", FileKind::Assertions, "expected a property"),
        ("simulation S of M { cycleDef }", FileKind::SimAssertions, "expected an expression"),
        ("function f() : int { postcondition s^t }", FileKind::RoboChart, "escaped name"),
    ];
    for (text, kind, want) in cases {
        match format(text, kind, &Options::default()) {
            Err(e @ FormatError::Syntax { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(want), "{text:?}: {msg}");
            }
            other => panic!("{text:?}: expected a syntax error, got {other:?}"),
        }
    }
}
