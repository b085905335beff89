//! Schedulability checking speed: states per second and bytes per stored
//! state, on the paper's running example and on a generated design of `n`
//! machines × `k` states (each machine reacts to its own input by moving to
//! its next state and calling its own platform operation).
//!
//! `cargo bench -p robosim-check --bench schedulability`

use robosim_check::algo::{find_deadlock, DeadlockResult};
use robosim_check::budget::Budget;
use robosim_check::ir::Design;
use robosim_check::lower::{lower_design, ConstValue, DomainDefaults};
use robosim_check::sched::{Constrained, Profile};

fn main() {
    divan::main();
}

/// A module of `n` machines with `k` states each.
fn generated(n: usize, k: usize) -> String {
    let mut s = String::from("interface I {\n");
    for i in 0..n {
        s.push_str(&format!("    event e{i}\n    op{i}()\n"));
    }
    s.push_str("}\n");
    for i in 0..n {
        s.push_str(&format!("stm M{i} {{\n    uses I requires I\n    initial i0\n"));
        for j in 0..k {
            s.push_str(&format!("    state S{j} {{ entry op{i}(); wait(1) }}\n"));
        }
        s.push_str("    transition t { from i0 to S0 }\n");
        for j in 0..k {
            s.push_str(&format!("    transition t{j} {{ from S{j} to S{} trigger e{i} }}\n", (j + 1) % k));
        }
        s.push_str("}\n");
    }
    s.push_str("controller C {\n    uses I requires I\n");
    for i in 0..n {
        s.push_str(&format!("    sref m{i} = M{i}\n    connection C on e{i} to m{i} on e{i}\n"));
    }
    s.push_str("}\nmodule Mod {\n    robotic platform P { uses I provides I }\n    cref c = C\n");
    for i in 0..n {
        s.push_str(&format!("    connection P on e{i} to c on e{i}\n"));
    }
    s.push_str("}\n");
    s
}

fn design(text: &str, item: &str, consts: &[ConstValue]) -> Design {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&db, [("m.rct".to_string(), text.to_string())], robosim_hir::RuleSet::Paper);
    let file = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model file");
    let path: Vec<String> = item.split("::").map(String::from).collect();
    let loc = robosim_hir::index::resolve_item(&db, ws, file, &path, |_| true)[0];
    lower_design(&db, ws, loc, consts, &DomainDefaults::default()).expect("supported")
}

/// The search alone (the design is compiled once): (states, bytes stored).
fn check(design: &Design, p: u32) -> (u64, u64) {
    let lts = Constrained::new(design, p, Profile::RoboTool3).expect("encodable");
    let (result, stats) = find_deadlock(&lts, &Budget::default().with_threads(1), None);
    assert!(matches!(result, DeadlockResult::Free | DeadlockResult::Deadlock(_)));
    (stats.states, stats.bytes)
}

#[divan::bench(args = [(2, 4), (3, 4), (4, 4)])]
fn generated_design(bencher: divan::Bencher, (n, k): (usize, usize)) {
    let d = design(&generated(n, k), "Mod", &[]);
    let (states, bytes) = check(&d, 1);
    eprintln!("generated {n}×{k}: {states} states, {} bytes/state", bytes / states.max(1));
    bencher.counter(divan::counter::ItemsCount::new(states)).bench(|| check(&d, 1));
}

#[divan::bench]
fn running_example(bencher: divan::Bencher) {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper/design.rct"))
        .expect("examples/paper/design.rct");
    let consts: Vec<ConstValue> = [("PI", 45), ("av", 15), ("lv", 1)]
        .into_iter()
        .map(|(n, v)| ConstValue { name: n.into(), of: vec!["SMovement".into()], value: v })
        .collect();
    let d = design(&text, "paper_design::CFootBot", &consts);
    let (states, bytes) = check(&d, 1);
    eprintln!("running example: {states} states, {} bytes/state", bytes / states.max(1));
    bencher.counter(divan::counter::ItemsCount::new(states)).bench(|| check(&d, 1));
}
