//! Hostile inputs: deep nesting, huge lines, random bytes. The parser must
//! return (no panic, no stack overflow) with a lossless tree.

use proptest::prelude::*;
use robosim_syntax::{parse, FileKind};

use robosim_test_support::inputs::{MODEL, SOUP};

/// Parses on a thread with a small stack (the size of a test thread), so a
/// recursion that would overflow in the editor or the CLI shows up here.
fn parse_on_small_stack(text: String, kind: FileKind) -> robosim_syntax::Parse {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || {
            let p = parse(&text, kind);
            assert_eq!(p.syntax_node().text().to_string(), text);
            // Walk the whole tree too: consumers must be able to.
            let _ = p.debug_dump();
            p
        })
        .unwrap()
        .join()
        .expect("parser thread panicked")
}

#[test]
fn five_thousand_nested_parens() {
    for kind in FileKind::ALL {
        let open = "(".repeat(5000);
        let close = ")".repeat(5000);
        let text = format!("function f() : int {{ postcondition result == {open}1{close} }}\n");
        let p = parse_on_small_stack(text, kind);
        if !kind.is_assertions() {
            assert!(p.errors().iter().any(|e| e.message.contains("nesting is too deep")), "{kind:?}");
        }
        let unclosed = format!("stm M {{ state S {{ entry x = {open}\n");
        parse_on_small_stack(unclosed, kind);
    }
}

#[test]
fn deep_nesting_of_every_construct() {
    let n = 3000;
    let cases = [
        format!("stm M {{ {} }}", "state S { ".repeat(n)),
        format!("stm M {{ state S {{ entry {}skip{} }} }}", "(".repeat(n), ")".repeat(n)),
        format!("interface I {{ var x : {}int{} }}", "Set(".repeat(n), ")".repeat(n)),
        format!("interface I {{ var x : {}int }}", "int -> ".repeat(n)),
        format!("function f() : int {{ postcondition {}1 }}", "- ".repeat(n)),
        format!("function f() : int {{ postcondition {}1 }}", "not ".repeat(n)),
        format!("function f() : int {{ postcondition {}1{} }}", "{".repeat(n), "}".repeat(n)),
        format!("function f() : int {{ postcondition {}1 }}", "if true then 1 else ".repeat(n)),
        format!("stm M {{ state S {{ entry {}skip }} }}", "if true then skip else ".repeat(n)),
    ];
    for text in cases {
        parse_on_small_stack(text, FileKind::RoboChart);
    }
}

#[test]
fn one_megabyte_line() {
    let text = format!("interface I {{ var x : int = {} }}", "1 + ".repeat(250_000) + "1");
    let p = parse_on_small_stack(text, FileKind::RoboChart);
    // Too long to nest: one clear error, the rest kept flat.
    assert_eq!(p.errors().len(), 1, "{:?}", p.errors());
    assert!(p.errors()[0].message.contains("too many operators"));
    let selections = format!("interface I {{ var x : int = a{} }}", ".b".repeat(300_000));
    let p = parse_on_small_stack(selections, FileKind::RoboChart);
    assert!(p.errors()[0].message.contains("too many selections"));
    let junk = "é$~`\\".repeat(200_000);
    parse_on_small_stack(junk, FileKind::RoboSim);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        for kind in FileKind::ALL {
            let p = parse(&text, kind);
            prop_assert_eq!(p.syntax_node().text().to_string(), text.clone());
        }
    }

    #[test]
    fn token_soup_never_panics(words in proptest::collection::vec(prop::sample::select(SOUP), 0..300)) {
        let text = words.join(" ");
        for kind in FileKind::ALL {
            let p = parse(&text, kind);
            prop_assert_eq!(p.syntax_node().text().to_string(), text.clone());
        }
    }

    #[test]
    fn truncated_model_keeps_structure_before_the_cut(cut in 0usize..MODEL.len()) {
        let text = &MODEL[..cut];
        if text.is_char_boundary(cut) {
            let p = parse(text, FileKind::RoboChart);
            prop_assert_eq!(p.syntax_node().text().to_string(), text);
        }
    }
}
