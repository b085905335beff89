//! Any bytes as a model (RoboChart design or RoboSim simulation) verified
//! against fixed assertions, within small budgets and under a buffer
//! assumed for asynchronous connections: lowering, the semantics and every
//! check run without panicking.

#![no_main]

use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use robosim_engine::verify::{verify_workspace, AsyncBuffer, Options};
use robosim_hir::{load_workspace, RootDatabase, RuleSet};

const ASSERTIONS: &str = "simulation S of Mod { cycleDef cycle == 1 }
assertion A : S is schedulable
assertion B : Sim refines S
assertion C : Sim is deadlock-free
assertion D : M is deterministic
assertion E : Mod is divergence-free";

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else { return };
    let ext = if selector & 1 == 0 { "rct" } else { "rst" };
    let text = String::from_utf8_lossy(rest).into_owned();
    let db = RootDatabase::default();
    let ws = load_workspace(
        &db,
        [(format!("fuzz.{ext}"), text), ("checks.rsa".to_string(), ASSERTIONS.to_string())],
        RuleSet::Paper,
    );
    // The selector's next bits choose the buffer assumed for asynchronous
    // connections (none, one place either way, or two places).
    let async_buffer = match (selector >> 1) & 3 {
        0 => None,
        1 => Some(AsyncBuffer { size: 1, overwrite: true }),
        2 => Some(AsyncBuffer { size: 1, overwrite: false }),
        _ => Some(AsyncBuffer { size: 2, overwrite: true }),
    };
    let mut opts = Options { async_buffer, ..Options::default() };
    opts.budget.max_states = 5_000;
    opts.budget.timeout = Some(Duration::from_millis(200));
    opts.budget.threads = 1;
    let _ = verify_workspace(&db, ws, &opts, None);
});
