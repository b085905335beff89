//! The formatter's guarantees, checked on every real model we have: the
//! corpus (`../shared/corpus`), this repository's examples and the parser's
//! `ok` fixtures.
//!
//! - only whitespace changes: the tokens other than whitespace are the same
//!   before and after (line comments compared without their line break and
//!   trailing blanks, which are whitespace);
//! - formatting is idempotent;
//! - a file with a syntax error is refused, not mangled.

use std::path::{Path, PathBuf};

use robosim_fmt::{format, FormatError, Indent, Options};
use robosim_syntax::{lexer, parse, FileKind, Severity, SyntaxKind};

use inputs::model_files;
use robosim_test_support::inputs;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every corpus model, example and parser `ok` fixture.
fn all_inputs() -> Vec<PathBuf> {
    let corpus = root().join("../shared/corpus");
    assert!(corpus.is_dir(), "the corpus must be at {} (../shared beside the project)", corpus.display());
    let mut files = Vec::new();
    model_files(&corpus, &mut files);
    assert!(files.len() >= 80, "expected the 82 corpus model files, found {}", files.len());
    let n = files.len();
    model_files(&root().join("examples"), &mut files);
    assert!(files.len() >= n + 8, "expected the examples");
    let n = files.len();
    model_files(&root().join("crates/syntax/test_data/parser/ok"), &mut files);
    assert!(files.len() >= n + 100, "expected the parser fixtures");
    files
}

/// The tokens formatting must keep, as (kind, text), computed independently
/// of the formatter's own check.
fn kept(text: &str, kind: FileKind) -> Vec<(SyntaxKind, String)> {
    let (tokens, _) = lexer::lex(text, kind);
    let mut at = 0;
    let mut out = Vec::new();
    for t in tokens {
        let s = &text[at..at + usize::from(t.len)];
        at += usize::from(t.len);
        match t.kind {
            SyntaxKind::WHITESPACE => {}
            SyntaxKind::LINE_COMMENT => {
                out.push((t.kind, s.trim_end_matches([' ', '\t', '\r', '\n']).to_string()));
            }
            k => out.push((k, s.to_string())),
        }
    }
    out
}

fn has_errors(text: &str, kind: FileKind) -> bool {
    parse(text, kind).errors().iter().any(|e| e.severity == Severity::Error)
}

fn check_file(path: &Path, text: &str, opts: &Options, failures: &mut Vec<String>) -> bool {
    let kind = FileKind::from_path(path).unwrap();
    let name = path.strip_prefix(root()).unwrap_or(path).display().to_string();
    match format(text, kind, opts) {
        Ok(out) => {
            if kept(text, kind) != kept(&out, kind) {
                failures.push(format!("{name}: the tokens changed"));
            }
            if out.lines().any(|l| l.ends_with([' ', '\t']) && !l.trim_start().starts_with("*")) {
                // Only block comments, strings and CSP text may keep
                // trailing blanks (their text is never touched).
                let bad = out.lines().filter(|l| l.ends_with([' ', '\t'])).count();
                let inside_tokens = trailing_blanks_inside_tokens(&out, kind);
                if bad > inside_tokens {
                    failures.push(format!("{name}: {bad} lines end with blanks"));
                }
            }
            match format(&out, kind, opts) {
                Ok(again) if again == out => {}
                Ok(again) => failures.push(format!("{name}: not idempotent\n{}", first_difference(&out, &again))),
                Err(e) => failures.push(format!("{name}: the output does not format again: {e}")),
            }
            true
        }
        Err(FormatError::Syntax { .. }) if has_errors(text, kind) => false,
        Err(e) => {
            failures.push(format!("{name}: {e}"));
            false
        }
    }
}

/// Lines of `text` that end with a blank inside a multi-line token.
fn trailing_blanks_inside_tokens(text: &str, kind: FileKind) -> usize {
    let (tokens, _) = lexer::lex(text, kind);
    let mut at = 0;
    let mut n = 0;
    for t in tokens {
        let s = &text[at..at + usize::from(t.len)];
        at += usize::from(t.len);
        if matches!(t.kind, SyntaxKind::BLOCK_COMMENT | SyntaxKind::CSP_TEXT | SyntaxKind::STRING) {
            n += s.split('\n').rev().skip(1).filter(|l| l.trim_end_matches('\r').ends_with([' ', '\t'])).count();
        }
    }
    n
}

fn first_difference(a: &str, b: &str) -> String {
    for (i, (x, y)) in a.lines().zip(b.lines()).enumerate() {
        if x != y {
            return format!("line {}:\n  first:  {x:?}\n  second: {y:?}", i + 1);
        }
    }
    format!("lengths {} and {}", a.len(), b.len())
}

#[test]
fn whitespace_only_and_idempotent_on_every_known_model() {
    let mut failures = Vec::new();
    let mut formatted = 0;
    let mut refused = 0;
    for path in all_inputs() {
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        for opts in [Options::default(), Options { indent: Indent::Tab, max_width: 60 }] {
            if check_file(&path, &text, &opts, &mut failures) {
                formatted += 1;
            } else {
                refused += 1;
            }
        }
    }
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n"));
    // Only the six corpus files RoboTool rejects have syntax errors.
    assert_eq!(refused, 2 * 6, "formatted {formatted}");
}

/// Our own examples are already in the canonical style.
#[test]
fn examples_are_formatted() {
    let mut files = Vec::new();
    model_files(&root().join("examples"), &mut files);
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let out = format(&text, FileKind::from_path(&path).unwrap(), &Options::default()).unwrap();
        if out != text {
            panic!("{} is not in the canonical style:\n{}", path.display(), first_difference(&text, &out));
        }
    }
}
