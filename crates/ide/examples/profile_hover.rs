//! Times a hover and a go-to-definition sent right after a keystroke in the
//! middle of the generated 10,000-line model (nothing computed for the new
//! text yet), and what they wait for: `cargo run --release -p robosim-ide
//! --example profile_hover [ROUNDS]`.
use robosim_test_support::generated;

use std::time::Instant;

use robosim_hir::{RuleSet, TextSize};
use robosim_ide::AnalysisHost;
use salsa::Durability;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let rounds: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(6);
    let text = generated::generated_model(10_000);
    let mut host = AnalysisHost::new(RuleSet::Paper);
    let file = host.set_file("gen.rct", text.clone(), None, Durability::LOW);
    let _ = host.analysis().diagnostics(file);
    // Hover and definition alternate between the edited text and the
    // original, so each comes right after a change.
    let at = text.find("entry move(3.0, 4003)").unwrap_or(text.len() / 2);
    let edit = text[at..].find(';').map_or(at, |i| at + i);
    // The variable after `;`: `count500 = …`.
    let var = edit + 2;
    for round in 0..rounds {
        let mut t = text.clone();
        t.insert_str(edit, &" ".repeat(round + 1));
        host.set_file("gen.rct", t, None, Durability::LOW);
        let a = host.analysis();
        let offset = TextSize::from((var + round + 1) as u32);
        let start = Instant::now();
        // As the language server does: with the diagnostics shown.
        let h = a.hover_with_diagnostics(file, offset, &[]).ok().flatten();
        let hover = start.elapsed();
        // A write waits for every snapshot to be dropped.
        drop(a);
        host.set_file("gen.rct", text.clone(), None, Durability::LOW);
        let a = host.analysis();
        let start = Instant::now();
        let d = a.goto_definition(file, TextSize::from(var as u32)).ok();
        let def = start.elapsed();
        drop(a);
        eprintln!(
            "round {round}: hover {:.2} ms ({}), definition {:.2} ms ({})",
            hover.as_secs_f64() * 1e3,
            h.map_or(0, |h| h.markdown.len()),
            def.as_secs_f64() * 1e3,
            d.map_or(0, |d| format!("{d:?}").len())
        );
    }
}
