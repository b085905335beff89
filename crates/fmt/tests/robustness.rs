//! Hostile and unusual inputs: the formatter never panics, refuses files
//! with syntax errors, survives deep nesting on a small stack, and keeps its
//! guarantees (whitespace only, idempotent) on every model of the corpus,
//! the examples and the parser fixtures with their whitespace scrambled and
//! comments sprinkled in.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use robosim_fmt::{format, FormatError, Options};
use robosim_syntax::{lexer, parse, FileKind, Severity, SyntaxKind};

use inputs::{model_files, MODEL, SOUP};
use robosim_test_support::inputs;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn kept(text: &str, kind: FileKind) -> Vec<(SyntaxKind, String)> {
    let (tokens, _) = lexer::lex(text, kind);
    let mut at = 0;
    let mut out = Vec::new();
    for t in tokens {
        let s = &text[at..at + usize::from(t.len)];
        at += usize::from(t.len);
        match t.kind {
            SyntaxKind::WHITESPACE => {}
            SyntaxKind::LINE_COMMENT => out.push((t.kind, s.trim_end_matches([' ', '\t', '\r', '\n']).to_string())),
            k => out.push((k, s.to_string())),
        }
    }
    out
}

fn clean(text: &str, kind: FileKind) -> bool {
    !parse(text, kind).errors().iter().any(|e| e.severity == Severity::Error)
}

/// Formats on a thread with a 2 MB stack (the size of a test thread), so a
/// recursion that would overflow in the editor shows up here.
fn format_on_small_stack(text: String, kind: FileKind) -> Result<String, FormatError> {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || format(&text, kind, &Options::default()))
        .unwrap()
        .join()
        .expect("formatter thread panicked")
}

/// A small deterministic generator, so a failure names its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// `text` with every whitespace run replaced by a random non-empty one, and
/// comments inserted into some of them. Tokens are untouched.
fn scramble(text: &str, kind: FileKind, seed: u64) -> String {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let (tokens, _) = lexer::lex(text, kind);
    let mut out = String::with_capacity(text.len() * 2);
    let mut at = 0;
    for t in tokens {
        let s = &text[at..at + usize::from(t.len)];
        at += usize::from(t.len);
        if t.kind != SyntaxKind::WHITESPACE {
            out.push_str(s);
            continue;
        }
        let piece = match rng.below(12) {
            0 => "\n",
            1 => "\n\n\n",
            2 => "\t",
            3 => "  \n\t ",
            4 => " /* c */ ",
            5 => "\n/* c\n  d */\n",
            6 => " // c\n",
            7 => "\n// c\n\n",
            8 => " /* c */\n",
            _ => " ",
        };
        out.push_str(piece);
    }
    out
}

/// Checks the guarantees on `text`; `formatted` counts the files that were
/// formatted (not refused).
fn check(text: &str, kind: FileKind, what: &str, formatted: &mut usize) -> Option<String> {
    let out = match format(text, kind, &Options::default()) {
        Ok(out) => out,
        Err(FormatError::Syntax { .. }) if !clean(text, kind) => return None,
        Err(e) => return Some(format!("{what}: {e}")),
    };
    *formatted += 1;
    if kept(text, kind) != kept(&out, kind) {
        return Some(format!("{what}: tokens changed"));
    }
    match format(&out, kind, &Options::default()) {
        Ok(again) if again == out => None,
        Ok(again) => {
            let line = out.lines().zip(again.lines()).position(|(a, b)| a != b).unwrap_or(0);
            Some(format!(
                "{what}: not idempotent at line {}\n--- once:\n{}\n--- twice:\n{}",
                line + 1,
                out.lines().skip(line.saturating_sub(3)).take(7).collect::<Vec<_>>().join("\n"),
                again.lines().skip(line.saturating_sub(3)).take(7).collect::<Vec<_>>().join("\n"),
            ))
        }
        Err(e) => Some(format!("{what}: output does not format again: {e}")),
    }
}

#[test]
fn scrambled_whitespace_and_comments_keep_the_guarantees() {
    let mut files = Vec::new();
    model_files(&root().join("examples"), &mut files);
    model_files(&root().join("crates/syntax/test_data/parser/ok"), &mut files);
    model_files(&root().join("crates/fmt/test_data"), &mut files);
    let corpus = root().join("../shared/corpus");
    if corpus.is_dir() {
        model_files(&corpus, &mut files);
    }
    let mut failures = Vec::new();
    let (mut tried, mut formatted) = (0, 0);
    for path in &files {
        let text = String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned();
        let kind = FileKind::from_path(path).unwrap();
        for seed in 1..=4 {
            let scrambled = scramble(&text, kind, seed);
            tried += 1;
            if std::env::var_os("SHOW_SCRAMBLED").is_some_and(|v| path.ends_with(&v)) {
                eprintln!("{scrambled}\n=====\n{}", format(&scrambled, kind, &Options::default()).unwrap());
            }
            let what = format!("{} (seed {seed})", path.display());
            if let Some(f) = check(&scrambled, kind, &what, &mut formatted) {
                failures.push(f);
            }
        }
    }
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n\n"));
    // Scrambling keeps tokens, so only the files that had errors to begin
    // with (the corpus's rejected files and those of the fmt fixtures that
    // test refusal) are refused.
    assert!(formatted * 100 >= tried * 95, "only {formatted} of {tried} scrambled files were formatted");
}

/// Nesting as deep as the parser accepts (it caps nesting at 384 levels,
/// shared by all constructs), formatted on a 2 MB stack.
#[test]
fn deep_nesting_on_a_small_stack() {
    let n = 300;
    let cases = [
        format!("stm M {{ {}{} }}", "state S { ".repeat(n), "}".repeat(n)),
        format!("stm M {{\n{}{} }}", "state S {\n".repeat(n), "}\n".repeat(n)),
        format!("stm M {{ state S {{ entry {}skip{} }} }}", "(".repeat(n), ")".repeat(n)),
        format!("interface I {{ var x : {}int{} }}", "Set(".repeat(n), ")".repeat(n)),
        format!("function f() : int {{ postcondition {}1{} }}", "(\n".repeat(n), ")".repeat(n)),
        format!("function f() : int {{ postcondition {}1 }}", "- ".repeat(n)),
        format!("function f() : int {{ postcondition {}1{} }}", "{".repeat(n), "}".repeat(n)),
        format!("function f() : int {{ postcondition {}1{} }}", "if true then 1 else\n".repeat(n), " end".repeat(n)),
        format!("stm M {{ state S {{ entry {}skip{} }} }}", "if true then skip else\n".repeat(n), " end".repeat(n)),
    ];
    for text in cases {
        let out = format_on_small_stack(text.clone(), FileKind::RoboChart)
            .unwrap_or_else(|e| panic!("{e} in {}", &text[..80]));
        assert_eq!(kept(&text, FileKind::RoboChart), kept(&out, FileKind::RoboChart));
        assert_eq!(format_on_small_stack(out.clone(), FileKind::RoboChart).unwrap(), out);
    }
    // Deeper than the parser accepts: refused with the parser's error.
    for kind in FileKind::ALL {
        let text =
            format!("function f() : int {{ postcondition result == {}1{} }}\n", "(".repeat(5000), ")".repeat(5000));
        match format_on_small_stack(text, kind) {
            Err(FormatError::Syntax { .. }) => {}
            other => panic!("{kind:?}: {other:?}"),
        }
    }
    let text = format!("stm M {{ {} }}", "state S { ".repeat(3000));
    assert!(format_on_small_stack(text, FileKind::RoboChart).is_err());
}

/// The guarantees for any input that formats: whitespace only, idempotent.
fn holds_if_formatted(text: &str, kind: FileKind) -> Result<(), TestCaseError> {
    if let Ok(out) = format(text, kind, &Options::default()) {
        prop_assert!(clean(text, kind));
        prop_assert_eq!(kept(text, kind), kept(&out, kind));
        prop_assert_eq!(format(&out, kind, &Options::default()), Ok(out.clone()));
    } else {
        prop_assert!(!clean(text, kind));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        for kind in FileKind::ALL {
            holds_if_formatted(&text, kind)?;
        }
    }

    #[test]
    fn token_soup_never_panics(words in proptest::collection::vec(prop::sample::select(SOUP), 0..300)) {
        let text = words.join(" ");
        for kind in FileKind::ALL {
            holds_if_formatted(&text, kind)?;
        }
    }

    /// Sequences of valid members with random separators: these parse, so
    /// the layout rules (not just the refusal) are exercised.
    #[test]
    fn random_valid_members_keep_the_guarantees(
        stm in members(RC_STM),
        ctrl in members(RC_CONTROLLER),
        op in members(RS_OPERATION),
    ) {
        let text = format!("stm M {{{stm}}}\ncontroller C {{{ctrl}}}");
        prop_assert!(clean(&text, FileKind::RoboChart), "{}", text);
        holds_if_formatted(&text, FileKind::RoboChart)?;
        let text = format!("operation op() {{{op}}}");
        prop_assert!(clean(&text, FileKind::RoboSim), "{}", text);
        holds_if_formatted(&text, FileKind::RoboSim)?;
    }

    #[test]
    fn truncated_models_never_panic(cut in 0usize..MODEL.len()) {
        if MODEL.is_char_boundary(cut) {
            holds_if_formatted(&MODEL[..cut], FileKind::RoboChart)?;
        }
    }
}

/// A block body: members from `pool` with random whitespace and comments
/// between them.
fn members(pool: &'static [&'static str]) -> impl Strategy<Value = String> {
    proptest::collection::vec((prop::sample::select(GAPS), prop::sample::select(pool)), 0..30)
        .prop_map(|parts| parts.iter().map(|(g, m)| format!("{g}{m}")).collect::<String>() + "\n")
}

const GAPS: &[&str] = &[" ", "\n", "\n\n\n", "\t", " // note\n", " /* note */ ", "\n/* a\n b */\n", "\n  "];

const NODES: [&str; 6] = [
    "initial i",
    "final f",
    "junction j",
    "state S { }",
    "state S { entry x = 1; y = 2 exit skip }",
    "state S {\n initial i state T { during #C } transition t { from i to T } }",
];

const RC_STM: &[&str] = &[
    NODES[0],
    NODES[1],
    NODES[2],
    NODES[3],
    NODES[4],
    NODES[5],
    "var x : int = 1, y : Set(int) = {1, 2}",
    "const k : real",
    "clock C",
    "requires I",
    "event e : nat",
    "transition t { from a to b }",
    "transition t { from a to b trigger e?x #C #D <{ 1 } condition x > 0 /\\ y action f(1); x = (1 + 2) * 3 }",
    "transition t {\nfrom a\nto b\ncondition\nif x then 1 else 2 end == 1\naction if x then\nskip\nelse\nwait(1)\nend }",
    "transition t { from a to b condition forall x : nat |\n x > 0 @\n f(x,\n y) }",
];

const RC_CONTROLLER: &[&str] = &[
    "var x : int = 1",
    "requires I",
    "uses J",
    "sref s = M",
    "connection C on e to s on e ( _async )",
    "connection C on e to s on e [ mult ]",
    "event e : nat",
    "operation op(x : int) { terminates initial i }",
    "stm N { initial i }",
    "stm N { }",
];

const RS_OPERATION: &[&str] = &[
    NODES[0],
    NODES[1],
    NODES[2],
    NODES[3],
    NODES[4],
    NODES[5],
    "var x : int = 1",
    "clock C",
    "requires I",
    "terminates",
    "input context { uses I }",
    "output context { event e : int event f }",
    "transition t { from a to b exec condition $e?x : (x > 0) action $out!1; exec }",
    "transition t { from a to b exec #C condition $e action $out.1 ; $op(1) }",
];
