//! Any bytes as CSPm: parsed (lossless), checked, and every definition
//! evaluated and, for processes, compiled to an LTS under small bounds —
//! no panic, no hang, no stack overflow.

#![no_main]

use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use robosim_cspm::{parse, Evaluator, Limits, Module, NoNames, Value};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let p = parse(&text);
    assert_eq!(p.syntax_node().text().to_string(), *text);
    let m = Module::check(&text, &NoNames);
    for d in m.diagnostics() {
        assert!(usize::from(d.range.end()) <= text.len());
    }
    let limits = Limits {
        max_depth: 120,
        max_set: 2_000,
        max_states: 2_000,
        time: Duration::from_millis(200),
        cancel: None,
        max_stack: 256 << 10,
    };
    let mut ev = Evaluator::new(&m, &NoNames, limits);
    for name in m.defined_names().into_iter().take(20) {
        if let Ok(v @ Value::Proc(_)) = ev.value(&name) {
            let _ = ev.lts_of(&v);
        }
    }
});
