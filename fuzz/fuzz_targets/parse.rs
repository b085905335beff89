//! Any bytes, parsed as each of the four languages: no panic, no hang, no
//! stack overflow, and the tree's text is exactly the input.

#![no_main]

use libfuzzer_sys::fuzz_target;
use robosim_syntax::{parse, FileKind};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    for kind in FileKind::ALL {
        let p = parse(&text, kind);
        assert_eq!(p.syntax_node().text().to_string(), *text);
        for e in p.errors() {
            assert!(usize::from(e.range.end()) <= text.len());
        }
    }
});
