//! An edit to any text, reparsed incrementally from the old tree: the
//! result is exactly a full parse of the new text, and nothing panics.
//! Input layout: two bytes of position, one byte of deleted length, one
//! byte of inserted length, the inserted bytes, then the old text.

#![no_main]

use libfuzzer_sys::fuzz_target;
use robosim_syntax::{parse, reparse, FileKind};

fuzz_target!(|data: &[u8]| {
    let [lo, hi, del, ins, rest @ ..] = data else { return };
    let ins = (*ins as usize).min(rest.len());
    let insert = String::from_utf8_lossy(&rest[..ins]);
    let old = String::from_utf8_lossy(&rest[ins..]).into_owned();
    let mut start = (usize::from(*lo) | usize::from(*hi) << 8) % (old.len() + 1);
    while !old.is_char_boundary(start) {
        start -= 1;
    }
    let mut end = (start + usize::from(*del)).min(old.len());
    while !old.is_char_boundary(end) {
        end -= 1;
    }
    let mut new = old.clone();
    new.replace_range(start..end, &insert);
    for kind in [FileKind::RoboChart, FileKind::RoboSim] {
        let before = parse(&old, kind);
        assert_eq!(reparse(&before, &old, &new), parse(&new, kind));
    }
});
