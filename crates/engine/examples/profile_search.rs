//! Runs one search several times in one process, to count its instructions
//! under callgrind (the difference between 1 and 3 repetitions is the cost
//! of two searches, without the set-up):
//!
//! `cargo run --release -p robosim-engine --example profile_search -- torus W REPS`
//! (the engine bench's torus, `W × W` states) or
//! `... -- design N K REPS` (the generated `N × K` design's schedulability) or
//! `... -- refine N K REPS` (its simulation's soundness: FD refinement).

use robosim_engine::algo::{find_deadlock, refines, DeadlockResult, RefinementResult, SemanticModel};
use robosim_engine::budget::Budget;
use robosim_engine::generate;
use robosim_engine::ir::Design;
use robosim_engine::lower::{lower_design, DomainDefaults};
use robosim_engine::lts::{Event, Label, Lts, FIRST_VISIBLE};
use robosim_engine::sched::{Constrained, Profile, Registers};
use robosim_engine::sim::SimModule;

/// The engine bench's torus (`benches/engine.rs`), without extra work.
struct Torus(u64);

impl Lts for Torus {
    type State = u64;

    fn initial(&self) -> u64 {
        0
    }

    fn successors(&self, s: &u64, out: &mut Vec<(Label, u64)>) {
        const A: Event = FIRST_VISIBLE;
        let w = self.0;
        let (x, y) = (s / w, s % w);
        out.push((Label::plain(A), ((x + 1) % w) * w + y));
        out.push((Label::plain(A + 1), x * w + (y + 1) % w));
        out.push((Label::plain(A + 2), ((x * 7 + 3) % w) * w + (y * 5 + 1) % w));
        out.push((Label::TAU, y * w + x));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize| -> usize {
        args.get(i).and_then(|a| a.parse().ok()).expect("usage: torus W REPS | design N K REPS | refine N K REPS")
    };
    let budget = Budget::default().with_threads(1);
    match args.first().map(String::as_str) {
        Some("torus") => {
            let l = Torus(num(1) as u64);
            for _ in 0..num(2) {
                let (r, s) = find_deadlock(&l, &budget, None);
                assert_eq!(r, DeadlockResult::Free);
                println!("{} states, {} transitions, {} bytes", s.states, s.transitions, s.bytes);
            }
        }
        Some("design") => {
            let d = compile(generate::design(num(1), num(2)), "m.rct");
            let lts = Constrained::new(&d, 1, Profile::RoboTool3).expect("encodable");
            for _ in 0..num(3) {
                let (r, s) = find_deadlock(&lts, &budget, None);
                let verdict = if matches!(r, DeadlockResult::Free) { "free" } else { "deadlock" };
                println!("{verdict}: {} states, {} transitions, {} bytes", s.states, s.transitions, s.bytes);
            }
        }
        Some("refine") => {
            let d = compile(generate::design(num(1), num(2)), "m.rct");
            let s = compile(generate::simulation(num(1), num(2)), "s.rst");
            let regs = Registers::new(&[&d, &s], Profile::RoboTool3).expect("registers");
            let spec = Constrained::with_registers(&d, 1, Profile::RoboTool3, Some(&regs), false).expect("spec");
            let imp = SimModule::new(&s, 1, &regs).expect("simulation");
            for _ in 0..num(3) {
                let (r, st) = refines(&spec, &imp, SemanticModel::FailuresDivergences, &budget, None);
                let verdict = if matches!(r, RefinementResult::Holds) { "holds" } else { "fails" };
                println!("{verdict}: {} pairs, {} transitions, {} bytes", st.states, st.transitions, st.bytes);
            }
        }
        _ => panic!("usage: torus W REPS | design N K REPS | refine N K REPS"),
    }
}

/// The module `Mod` of the file `path` holding `text`, compiled.
fn compile(text: String, path: &str) -> Design {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, [(path.to_string(), text)], robosim_hir::RuleSet::Paper);
    let file = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model file");
    let loc = robosim_hir::index::resolve_item(&db, ws, file, &["Mod".to_string()], |_| true)[0];
    lower_design(&db, ws, loc, &[], &DomainDefaults::default()).expect("supported")
}
