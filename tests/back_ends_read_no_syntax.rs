//! The back ends translate from the semantic model (`robosim_hir::model`),
//! never from syntax trees (docs/architecture.md): no `rowan`, no syntax
//! nodes, tokens or kinds, no `ast` helpers and no parse in their sources;
//! the diagrams not the definition tables (`robosim_hir::defs`) either.

use std::path::{Path, PathBuf};

/// The crates that read no syntax: the engine, the CSPm export and the
/// diagrams.
const SYNTAX_FREE: &[&str] = &["engine", "semantics", "diagram"];

/// What reading syntax looks like in source text.
const FORBIDDEN: &[&str] = &[
    "rowan",
    "SyntaxNode",
    "SyntaxToken",
    "SyntaxElement",
    "SyntaxKind",
    "robosim_syntax::ast",
    "robosim_hir::parse",
    "syntax_node()",
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn the_back_ends_read_the_model_not_syntax() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates");
    for name in SYNTAX_FREE {
        let mut files = Vec::new();
        rust_files(&crates.join(name).join("src"), &mut files);
        assert!(files.len() > 5, "crates/{name}/src: {files:?}");
        for file in files {
            let text = std::fs::read_to_string(&file).expect("readable");
            for (n, line) in text.lines().enumerate() {
                if let Some(word) = FORBIDDEN.iter().find(|w| line.contains(**w)) {
                    panic!(
                        "{}:{}: `{word}` — crates/{name} must read the hir model, not syntax",
                        file.display(),
                        n + 1
                    );
                }
            }
        }
    }
}

/// The diagrams are drawn from the lowered model (`robosim_hir::model`),
/// not from the per-file definition tables it is lowered from.
#[test]
fn the_diagrams_read_the_model_not_the_definition_tables() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates/diagram/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    assert!(files.len() > 5, "crates/diagram/src: {files:?}");
    for file in files {
        let text = std::fs::read_to_string(&file).expect("readable");
        for (n, line) in text.lines().enumerate() {
            if let Some(word) = ["hir::defs", "file_defs"].iter().find(|w| line.contains(**w)) {
                panic!("{}:{}: `{word}` — crates/diagram must read `robosim_hir::model`", file.display(), n + 1);
            }
        }
    }
}
