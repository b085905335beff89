//! A hand-written CSPm specification against a large module, end to end
//! (parse, evaluate, compile the specification's LTS, normalise, refine):
//! issue 18's benchmark of a specification of about 3,000 states against a
//! module of about 300,000.
//!
//! The module is `generate::design(4, 8)` (four machines of eight states
//! that call an operation, wait a unit and move on an input). The
//! specification counts each machine's events modulo 8 and lets time pass
//! in step: four counters synchronised on `tock`, 8^4 = 4,096 states. A
//! machine makes 16 events per round, so each counter is a function of its
//! machine's state: the product is no larger than the module. The
//! specification allows every trace of the module, so the check explores
//! the whole product and passes. The plain deadlock check of the same
//! module is measured beside it, for the cost of the specification.
//!
//! `cargo bench -p robosim-engine --bench csp_spec`

use robosim_engine::generate::design;
use robosim_engine::verify::{verify_texts, Options, Report, Semantics, Verdict};

fn main() {
    divan::main();
}

const MACHINES: usize = 4;
const STATES: usize = 8;
const MODULO: usize = 8;

fn spec() -> String {
    let mut a = String::from("timed csp Spec csp-begin\n");
    for i in 0..MACHINES {
        a.push_str(&format!(
            "C{i}(c) = Mod::e{i}.in -> C{i}((c+1)%{MODULO}) [] Mod::op{i}Call -> C{i}((c+1)%{MODULO}) [] tock -> C{i}(c)\n"
        ));
    }
    let mut par = format!("C{}(0)", MACHINES - 1);
    for i in (0..MACHINES - 1).rev() {
        par = format!("C{i}(0) [| {{tock}} |] ({par})");
    }
    a.push_str(&format!("Spec = {par}\ncsp-end\n"));
    a
}

fn run(assertion: &str) -> Report {
    let files = [
        ("m.rct".to_string(), design(MACHINES, STATES)),
        ("a.assertions".to_string(), format!("{}{assertion}\n", spec())),
    ];
    let mut opts = Options::default();
    opts.budget.max_states = 50_000_000;
    let mut reports = verify_texts(files, &opts);
    reports.retain(|r| r.semantics == Semantics::Timed);
    assert_eq!(reports.len(), 1, "{reports:#?}");
    reports.remove(0)
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn spec_refinement(bencher: divan::Bencher) {
    let r = run("timed assertion S : Mod refines Spec in the traces model");
    assert_eq!(r.verdict, Verdict::Pass, "{r:#?}");
    eprintln!(
        "csp spec vs module: {} states (pairs), {} transitions, {:.2} s",
        r.stats.states, r.stats.transitions, r.stats.seconds
    );
    bencher.bench(|| run("timed assertion S : Mod refines Spec in the traces model").stats.states);
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn module_deadlock(bencher: divan::Bencher) {
    let r = run("timed assertion D : Mod is deadlock-free");
    eprintln!(
        "module deadlock-free: {} ({} states, {} transitions, {:.2} s)",
        r.verdict.name(),
        r.stats.states,
        r.stats.transitions,
        r.stats.seconds
    );
    bencher.bench(|| run("timed assertion D : Mod is deadlock-free").stats.states);
}
