//! Times each query of the complete check after toggling `$` in one guard
//! of the generated 11,641-line RoboSim model (the keystroke of issue 22):
//! `cargo run --release -p robosim-hir --example profile_toggle [ROUNDS]
//! [plain]` (`plain`: after two timed toggles, the first of which lowers
//! the edited element's durability, the complete check alone, as the
//! language server runs it, without asking for each query first).
use robosim_hir::*;
use robosim_test_support::generated;

use std::time::Instant;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let good = generated::generated_robosim(120);
    let middle = good.find("SimSMovement60 {").unwrap();
    let at = middle + good[middle..].find("not $obstacle").unwrap() + "not ".len();
    let bad = format!("{}{}", &good[..at], &good[at + 1..]);
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| !f.is_library(&db)).unwrap();
    let t = Instant::now();
    let n = file_diagnostics(&db, ws, file).len();
    eprintln!("cold: {:?} ({n} diagnostics)", t.elapsed());
    let rounds: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(6);
    let plain = std::env::args().nth(2).is_some_and(|a| a == "plain");
    for round in 0..rounds {
        let text = if round % 2 == 0 { &bad } else { &good };
        if plain && round >= 2 {
            plain_round(&mut db, ws, file, text.clone());
        } else {
            toggle_round(&mut db, ws, file, text.clone());
        }
    }
}

#[inline(never)]
fn plain_round(db: &mut RootDatabase, ws: Workspace, file: File, text: String) {
    let start = Instant::now();
    edit_text(db, file, text, Durability::LOW);
    let n = file_diagnostics(db, ws, file).len();
    eprintln!("total {:.2} ms ({n})", start.elapsed().as_secs_f64() * 1e3);
}

#[inline(never)]
fn toggle_round(db: &mut RootDatabase, ws: Workspace, file: File, text: String) {
    let mut laps = Vec::new();
    let start = Instant::now();
    let mut last = Instant::now();
    let mut lap = |name: &'static str| {
        laps.push((name, last.elapsed()));
        last = Instant::now();
    };
    // The parse and the elements' inputs (`hir::set_text`).
    edit_text(db, file, text, Durability::LOW);
    lap("set_text");
    let _ = parse(db, file);
    lap("parse");
    let _ = element::file_elements(db, file);
    lap("file_elements");
    for (e, _) in element::file_elements(db, file) {
        let _ = element::element_problems(db, ws, *e);
    }
    lap("element_problems");
    let _ = index::file_summary(db, file);
    lap("file_summary");
    let _ = index::workspace_index(db, ws);
    lap("workspace_index");
    for e in element::element_list(db, file) {
        let _ = element_rules::element_cycles(db, ws, *e);
    }
    lap("element_cycles");
    prefetch_rules(db, ws, file);
    lap("element_rules");
    let n = file_diagnostics(db, ws, file).len();
    lap("rest of file_diagnostics");
    let total = start.elapsed();
    let laps: Vec<String> = laps.iter().map(|(n, d)| format!("{n} {:.2}", d.as_secs_f64() * 1e3)).collect();
    eprintln!("total {:.2} ms ({n}): {}", total.as_secs_f64() * 1e3, laps.join(", "));
}
