//! No input makes the crate panic, hang or overflow the stack of a default
//! 2 MiB test thread: deep nesting, long lines, runaway recursion, huge
//! numbers, and pseudo-random token soup, each parsed, checked and
//! evaluated under default or small limits.

use std::time::Duration;

use robosim_cspm::{parse, Code, Evaluator, Limits, Module, NoNames, Value};

fn run(text: &str, limits: Limits) {
    let p = parse(text);
    assert_eq!(p.syntax_node().text().to_string(), text);
    let m = Module::check(text, &NoNames);
    let mut ev = Evaluator::new(&m, &NoNames, limits);
    for n in m.defined_names().into_iter().take(30) {
        if let Ok(v @ Value::Proc(_)) = ev.value(&n) {
            let _ = ev.lts_of(&v);
        }
    }
}

fn small() -> Limits {
    Limits { max_states: 2_000, max_set: 5_000, time: Duration::from_millis(500), ..Limits::default() }
}

#[test]
fn deep_nesting_and_long_lines() {
    run(&format!("P = {}STOP{}", "(".repeat(5000), ")".repeat(5000)), small());
    run(&format!("x = {}1", "-".repeat(5000)), small());
    run(&format!("x = {}1{}", "{".repeat(3000), "}".repeat(3000)), small());
    run(&format!("channel a\nP = {}STOP", "a -> ".repeat(3000)), small());
    run(&format!("x = {}", vec!["1"; 100_000].join(" + ")), small());
    // Just below the parser's bound: the deepest tree the later passes walk.
    run(&format!("x = {}1{}", "(1 + ".repeat(140), ")".repeat(140)), small());
    run(&format!("channel a\nP = {}STOP{}", "(a -> STOP [] ".repeat(140), ")".repeat(140)), small());
    run(&format!("x = <{}>", vec!["1"; 100_000].join(", ")), small());
}

#[test]
fn runaway_evaluations_hit_limits() {
    let cases = [
        ("f(n) = 1 + f(n+1)\nx = f(0)", "x"),
        ("f(n) = if n == 0 then 0 else 1 + f(n-1)\nx = f(1000000)", "x"),
        ("x = card({0..100000000})", "x"),
        ("x = 9223372036854775807 + 1", "x"),
        ("channel tock\nTimed(\\ _ @ 1000000000) { channel a\nP = a -> STOP }", "P"),
        ("channel c : {0..9}.{0..9}.{0..9}.{0..9}.{0..9}\nP = ||| x : {| c |} @ x -> STOP", "P"),
        ("P = P", "P"),
        ("channel a\nP = a -> P ||| P", "P"),
    ];
    for (text, name) in cases {
        let m = Module::check(text, &NoNames);
        let mut ev = Evaluator::new(&m, &NoNames, small());
        let r = ev.value(name).and_then(|v| match v {
            Value::Proc(_) => ev.lts_of(&v).map(|_| Value::Bool(true)),
            v => Ok(v),
        });
        let code = r.expect_err(text).code;
        assert!(matches!(code, Code::Limit | Code::Runtime | Code::Unresolved), "{text}: {code:?}");
    }
}

#[test]
fn token_soup() {
    const WORDS: &[&str] = &[
        "P", "Q", "x", "c", "a", "1", "0", "=", "->", "[]", "|~|", "|||", "[|", "|]", "{", "}", "{|", "|}", "<", ">",
        "(", ")", ",", ".", "?", "!", "@", "\\", ";", "&", "if", "then", "else", "let", "within", "channel",
        "datatype", "|", ":", "<-", "[[", "]]", "STOP", "SKIP", "\n", "Timed", "tock", "WAIT", "..", "#", "^", "not",
        "==", "+", "/\\",
    ];
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..3000 {
        let mut text = String::new();
        let n = (seed % 40) as usize + 1;
        for _ in 0..n {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            text.push_str(WORDS[(seed % WORDS.len() as u64) as usize]);
            text.push(' ');
        }
        run(&format!("channel a, c : {{0,1}}\nchannel tock\n{text}"), small());
    }
}
