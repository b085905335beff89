//! Incremental reparsing gives exactly the tree and errors of a full parse,
//! on every model of the corpus, our examples and the benchmark model, under
//! edits that keep a member whole, break it, or reach across members; and
//! it does take the incremental path for ordinary typing inside a member.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use robosim_syntax::{parse, reparse, try_reparse, FileKind, Parse};

use robosim_test_support::generated;
use robosim_test_support::inputs::{model_files, MODEL, SOUP};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Model files (not assertion files: those always parse whole) of the
/// corpus and of examples/.
fn models() -> Vec<(PathBuf, String, FileKind)> {
    let mut files = Vec::new();
    model_files(&repo().join("../shared/corpus"), &mut files);
    model_files(&repo().join("examples"), &mut files);
    files
        .into_iter()
        .filter_map(|p| {
            let kind = FileKind::from_path(&p)?;
            let text = std::fs::read_to_string(&p).ok()?;
            (!kind.is_assertions()).then_some((p, text, kind))
        })
        .collect()
}

/// Reparses and compares with a full parse; true when the incremental
/// path was taken.
fn check(old: &Parse, old_text: &str, new_text: &str, what: &dyn Fn() -> String) -> bool {
    let full = parse(new_text, old.file_kind());
    let inc = try_reparse(old, old_text, new_text);
    if let Some(inc) = &inc {
        assert_eq!(inc.syntax_node().text().to_string(), new_text, "{}: text", what());
        if inc != &full {
            panic!("{}\nincremental:\n{}\nfull:\n{}", what(), inc.debug_dump(), full.debug_dump());
        }
    }
    assert_eq!(reparse(old, old_text, new_text), full, "{}", what());
    inc.is_some()
}

/// Edits that keep a member well formed, break it, or cross its bounds.
const EDITS: &[&str] = &[" ", "x", "\n", ";", "}", "{", "/*", "\"", "//", "state Z { }", "0", "stm", "csp-begin"];

#[test]
fn every_model_under_edits() {
    let files = models();
    assert!(files.len() > 50, "the corpus was not found beside the checkout");
    let (mut incremental, mut total) = (0, 0);
    for (path, text, kind) in &files {
        let old = parse(text, *kind);
        // A dozen positions per file, on character boundaries.
        let step = (text.len() / 12).max(1);
        for at in (0..text.len()).step_by(step).filter(|&i| text.is_char_boundary(i)) {
            for edit in EDITS {
                let mut new = text.clone();
                new.insert_str(at, edit);
                total += 1;
                incremental +=
                    check(&old, text, &new, &|| format!("{}: insert {edit:?} at {at}", path.display())) as usize;
            }
            // Delete the character at `at`.
            if let Some(c) = text[at..].chars().next() {
                let mut new = text.clone();
                new.replace_range(at..at + c.len_utf8(), "");
                total += 1;
                incremental += check(&old, text, &new, &|| format!("{}: delete at {at}", path.display())) as usize;
            }
        }
    }
    // Most positions are inside members; most edits there keep them whole.
    assert!(incremental * 4 > total, "only {incremental} of {total} edits were reparsed incrementally");
}

#[test]
fn typing_inside_a_machine_stays_incremental_and_exact() {
    // Type a statement into an entry action of the benchmark model, one
    // character at a time, then delete it again, reparsing each new text
    // from the previous incremental result, as the editor does.
    let mut text = generated::generated_model(600);
    let mut current = parse(&text, FileKind::RoboChart);
    let at = text.find("exit stop()").unwrap() - 3;
    let typed = "; count0 = count0 + 1";
    let mut steps = Vec::new();
    for i in 1..=typed.len() {
        let mut t = text.clone();
        t.insert_str(at, &typed[..i]);
        steps.push(t);
    }
    for i in (0..typed.len()).rev() {
        let mut t = text.clone();
        t.insert_str(at, &typed[..i]);
        steps.push(t);
    }
    for (n, new) in steps.into_iter().enumerate() {
        assert!(
            check(&current, &text, &new, &|| format!("step {n}: {:?}", &new[at..at + 24])),
            "step {n} was not incremental"
        );
        current = reparse(&current, &text, &new);
        text = new;
    }
}

#[test]
fn errors_inside_outside_and_around_the_member() {
    // An error before the edited machine, one inside it, one after it: the
    // inside one is replaced, the later one moves with the edit.
    let text = "stm A { state S { entry x = } }\nstm B {\n  state T { entry y = 1 }\n  transition t { from T to }\n}\nstm C { initial }\n";
    let old = parse(text, FileKind::RoboChart);
    assert_eq!(old.errors().len(), 3, "{}", old.debug_dump());
    let at = text.find("y = 1").unwrap() + 5;
    for insert in ["0", " + 2", "; z = 3", " +"] {
        let mut new = text.to_string();
        new.insert_str(at, insert);
        assert!(check(&old, text, &new, &|| format!("insert {insert:?}")), "{insert:?} was not incremental");
    }
    // Fixing the error inside B.
    let fixed = text.replace("from T to }", "from T to T }");
    assert!(check(&old, text, &fixed, &|| "fix".to_string()));
    assert_eq!(reparse(&old, text, &fixed).errors().len(), 2);
}

#[test]
fn edits_that_must_not_be_incremental() {
    let text = MODEL;
    let old = parse(text, FileKind::RoboChart);
    let m = text.find("stm M").unwrap();
    let cases = [
        // The member's first token.
        (m, m + 3, "stmx"),
        // Its closing brace.
        (text.find("\n}\nmodule").unwrap() + 1, text.find("\n}\nmodule").unwrap() + 2, ""),
        // An unterminated comment or string opened inside.
        (m + 10, m + 10, "/*"),
        (m + 10, m + 10, "\""),
        // Between members.
        (m - 1, m - 1, "  "),
        // Across two members.
        (m + 10, text.find("module").unwrap() + 3, ""),
    ];
    for (start, end, insert) in cases {
        let mut new = text.to_string();
        new.replace_range(start..end, insert);
        assert!(!check(&old, text, &new, &|| format!("{start}..{end} {insert:?}")), "{start}..{end} {insert:?}");
    }
    // Assertion files always parse whole.
    let a = "assertion a : M is deadlock-free\n";
    let old = parse(a, FileKind::Assertions);
    assert!(try_reparse(&old, a, "assertion b : M is deadlock-free\n").is_none());
    // The same text: the same parse.
    assert!(try_reparse(&old, a, a).is_some_and(|p| p == old));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random replacements with words of all four languages, anywhere in the
    /// small model, chained from one reparse to the next.
    #[test]
    fn random_edits_match_a_full_parse(
        edits in proptest::collection::vec((0usize..10_000, 0usize..12, proptest::collection::vec(0..SOUP.len(), 0..4)), 1..6),
        robosim in any::<bool>(),
    ) {
        let kind = if robosim { FileKind::RoboSim } else { FileKind::RoboChart };
        let mut text = MODEL.to_string();
        let mut current = parse(&text, kind);
        for (at, len, words) in edits {
            let mut start = at % (text.len() + 1);
            while !text.is_char_boundary(start) {
                start -= 1;
            }
            let mut end = (start + len).min(text.len());
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            let insert: String = words.iter().map(|&w| SOUP[w]).collect::<Vec<_>>().join(" ");
            let mut new = text.clone();
            new.replace_range(start..end, &insert);
            check(&current, &text, &new, &|| format!("{start}..{end} {insert:?} in\n{text}"));
            current = reparse(&current, &text, &new);
            text = new;
        }
    }
}
