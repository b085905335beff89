//! Schedulability checking speed: states per second and bytes per stored
//! state, on the paper's running example and on a generated design of `n`
//! machines × `k` states (each machine reacts to its own input by moving to
//! its next state and calling its own platform operation).
//!
//! Refinement (soundness) speed: state pairs per second, on the running
//! example (Figure 3 against Figure 1) and on a generated design of `n`
//! machines × `k` states with its simulation.
//!
//! `cargo bench -p robosim-engine --bench schedulability`

use robosim_engine::algo::{find_deadlock, refines, DeadlockResult, RefinementResult, SemanticModel};
use robosim_engine::budget::Budget;
use robosim_engine::generate;
use robosim_engine::ir::Design;
use robosim_engine::lower::{lower_design, ConstValue, DomainDefaults};
use robosim_engine::sched::{Constrained, Profile, Registers};
use robosim_engine::sim::SimModule;

fn main() {
    divan::main();
}

fn design(text: &str, item: &str, consts: &[ConstValue]) -> Design {
    compile(text, "m.rct", item, consts)
}

fn compile(text: &str, path: &str, item: &str, consts: &[ConstValue]) -> Design {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, [(path.to_string(), text.to_string())], robosim_hir::RuleSet::Paper);
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
    let d = design(&generate::design(n, k), "Mod", &[]);
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

/// `sim` refines the constrained `design` (period 1): (pairs, holds).
fn soundness(design: &Design, sim: &Design) -> (u64, bool) {
    let regs = Registers::new(&[design, sim], Profile::RoboTool3).expect("registers");
    let spec = Constrained::with_registers(design, 1, Profile::RoboTool3, Some(&regs), false).expect("spec");
    let imp = SimModule::new(sim, 1, &regs).expect("simulation");
    let (r, stats) = refines(&spec, &imp, SemanticModel::FailuresDivergences, &Budget::default().with_threads(1), None);
    (stats.states, matches!(r, RefinementResult::Holds))
}

#[divan::bench(args = [(1, 3), (2, 3), (3, 3)])]
fn refinement_generated(bencher: divan::Bencher, (n, k): (usize, usize)) {
    let d = design(&generate::design(n, k), "Mod", &[]);
    let s = compile(&generate::simulation(n, k), "s.rst", "Mod", &[]);
    let (pairs, holds) = soundness(&d, &s);
    assert!(holds, "the generated simulation is sound");
    eprintln!("refinement {n}×{k}: {pairs} pairs");
    bencher.counter(divan::counter::ItemsCount::new(pairs)).bench(|| soundness(&d, &s));
}

#[divan::bench]
fn refinement_running_example(bencher: divan::Bencher) {
    let read = |f: &str| {
        std::fs::read_to_string(format!("{}/../../examples/paper/{f}", env!("CARGO_MANIFEST_DIR"))).expect("example")
    };
    let consts = |m: &str| -> Vec<ConstValue> {
        [("PI", 45), ("av", 15), ("lv", 1)]
            .into_iter()
            .map(|(n, v)| ConstValue { name: n.into(), of: vec![m.into()], value: v })
            .collect()
    };
    let d = compile(&read("design.rct"), "design.rct", "paper_design::CFootBot", &consts("SMovement"));
    let s = compile(&read("simulation.rst"), "sim.rst", "paper_sim::SimCFootBot", &consts("SimSMovement"));
    let (pairs, holds) = soundness(&d, &s);
    assert!(holds, "Figure 3 is sound");
    eprintln!("refinement running example: {pairs} pairs");
    bencher.counter(divan::counter::ItemsCount::new(pairs)).bench(|| soundness(&d, &s));
}
