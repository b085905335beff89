//! Any bytes as a model file, checked in a workspace with the bundled
//! library and a well-formed companion file: parse, resolve and every rule
//! run without panicking.

#![no_main]

use libfuzzer_sys::fuzz_target;
use robosim_hir::{file_diagnostics, load_workspace, RootDatabase, RuleSet};

const COMPANION: &str = "interface IEv { event obstacle }\ninterface IOps { move(v : real) }\n";

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else { return };
    let ext = ["rct", "rst", "assertions", "rsa"][(selector % 4) as usize];
    let text = String::from_utf8_lossy(rest).into_owned();
    let rules = if selector & 4 == 0 { RuleSet::Paper } else { RuleSet::RoboTool };
    let db = RootDatabase::default();
    let ws = load_workspace(
        &db,
        [(format!("fuzz.{ext}"), text), ("companion.rct".to_string(), COMPANION.to_string())],
        rules,
    );
    for f in ws.files(&db) {
        if !f.is_library(&db) {
            let _ = file_diagnostics(&db, ws, *f);
        }
    }
});
