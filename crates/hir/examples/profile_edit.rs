//! Times each query of the semantic model after a one-character edit in the
//! middle of the generated 10,000-line model.
use robosim_hir::*;
use robosim_test_support::generated;

use std::time::Instant;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let text = generated::generated_model(10_000);
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, [("gen.rct".to_string(), text.clone())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| !f.is_library(&db)).unwrap();
    let t = Instant::now();
    let n = file_diagnostics(&db, ws, file).len();
    eprintln!("cold: {:?} ({n} diagnostics)", t.elapsed());
    let mid = text.find("entry move(3.0, 4003)").unwrap_or(text.len() / 2);
    let pos = text[mid..].find(';').unwrap() + mid;
    let rounds: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(6);
    for round in 0..rounds {
        edit_round(&mut db, ws, file, &text, pos, round);
    }
}

#[inline(never)]
fn edit_round(db: &mut RootDatabase, ws: Workspace, file: File, text: &str, pos: usize, round: usize) {
    {
        let mut t2 = text.to_string();
        t2.insert_str(pos, &" ".repeat(round + 1));
        // As the editor's host does: the previous text and its parse go
        // along, so that only the edited machine is parsed again.
        edit_text(db, file, t2, Durability::LOW);
        let mut last = Instant::now();
        let mut lap = |name: &str| {
            let e = last.elapsed();
            eprintln!("  {name}: {:.2} ms", e.as_secs_f64() * 1e3);
            last = Instant::now();
        };
        let start = Instant::now();
        let _ = parse(db, file);
        lap("parse");
        let _ = defs::file_defs(db, file);
        lap("file_defs");
        let _ = index::file_summary(db, file);
        lap("file_summary");
        let _ = index::workspace_index(db, ws);
        lap("workspace_index");
        let _ = index::file_scope(db, ws, file);
        lap("file_scope");
        let _ = resolve::file_members(db, ws, file);
        lap("file_members");
        let _ = resolve::file_resolution(db, ws, file);
        lap("file_resolution");
        let _ = body::body_resolution(db, ws, file);
        lap("body_resolution");
        let n = file_diagnostics(db, ws, file).len();
        lap("rest of file_diagnostics");
        eprintln!("round {round}: total {:.2} ms ({n})", start.elapsed().as_secs_f64() * 1e3);
    }
}
