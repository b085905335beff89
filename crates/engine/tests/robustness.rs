//! Broken and mutated models never make the verifier panic or hang: every
//! assertion gets a verdict or a reason, within small budgets.

use std::time::Duration;

use robosim_engine::verify::{verify_workspace, Options, Verdict};

fn example(name: &str) -> String {
    std::fs::read_to_string(format!("{}/../../examples/paper/{name}", env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("examples/paper/{name}: {e}"))
}

/// A small deterministic generator (no dependency needed for this).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self, n: usize) -> usize {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// `text` with one edit: a deleted span, a duplicated line, a swapped pair
/// of lines or a number changed.
fn mutate(text: &str, rng: &mut Lcg) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match rng.next(4) {
        0 => {
            let a = rng.next(text.len());
            let b = (a + 1 + rng.next(40)).min(text.len());
            let (a, b) = (floor(text, a), floor(text, b));
            return format!("{}{}", &text[..a], &text[b..]);
        }
        1 => {
            let i = rng.next(out.len());
            let l = out[i].clone();
            out.insert(i, l);
        }
        2 => {
            let (i, j) = (rng.next(out.len()), rng.next(out.len()));
            out.swap(i, j);
        }
        _ => {
            let i = rng.next(out.len());
            out[i] = out[i].replace('1', "7").replace('0', "4");
        }
    }
    out.join("\n")
}

fn floor(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[test]
fn mutated_models_get_verdicts_or_reasons() {
    let files = ["design.rct", "simulation.rst", "simulation_alt.rst", "assertions.rsa", "design.assertions"];
    let originals: Vec<String> = files.iter().map(|f| example(f)).collect();
    let mut opts = Options::default();
    opts.budget.max_states = 20_000;
    opts.budget.timeout = Some(Duration::from_secs(2));
    let mut rng = Lcg(7);
    let mut verdicts = [0usize; 4];
    for _ in 0..60 {
        let which = rng.next(files.len());
        let mut texts = originals.clone();
        texts[which] = mutate(&texts[which], &mut rng);
        let mut db = robosim_hir::RootDatabase::default();
        let ws = robosim_hir::load_workspace(
            &mut db,
            files.iter().map(|f| f.to_string()).zip(texts),
            robosim_hir::RuleSet::Paper,
        );
        for r in verify_workspace(&db, ws, &opts, None) {
            verdicts[r.verdict as usize] += 1;
            if matches!(r.verdict, Verdict::Unsupported | Verdict::Inconclusive) {
                assert!(r.reason.as_deref().is_some_and(|s| !s.is_empty()), "{}: no reason", r.name);
            }
        }
    }
    println!("pass/fail/inconclusive/unsupported: {verdicts:?}");
    assert!(verdicts[0] > 0 && verdicts[1] + verdicts[3] > 0, "{verdicts:?}");
}

/// Binary junk and an empty workspace.
#[test]
fn junk_is_answered() {
    let mut db = robosim_hir::RootDatabase::default();
    let junk = String::from_utf8_lossy(&(0..2000u32).map(|i| (i * 7919 % 251) as u8).collect::<Vec<_>>()).into_owned();
    let ws = robosim_hir::load_workspace(
        &mut db,
        [
            ("junk.rct".to_string(), junk.clone()),
            ("junk.rsa".to_string(), format!("assertion A : X is schedulable\n{junk}")),
        ],
        robosim_hir::RuleSet::Paper,
    );
    for r in verify_workspace(&db, ws, &Options::default(), None) {
        assert_ne!(r.verdict, Verdict::Pass, "{r:?}");
    }
}
