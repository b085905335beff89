//! The back ends translate from the semantic model (`robosim_hir::model`),
//! never from syntax trees (docs/architecture.md): no `rowan`, no syntax
//! nodes, tokens or kinds, no `ast` helpers and no parse in their sources.

use std::path::{Path, PathBuf};

/// The crates that read no syntax. `semantics` (the CSPm export) and
/// `diagram` join the list once they translate from the model.
const SYNTAX_FREE: &[&str] = &["engine"];

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
