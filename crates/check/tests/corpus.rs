//! Every assertion of the reference corpus (../shared/corpus), each project
//! as its own workspace: no panic, a bounded run, and a reason for every
//! verdict that is not a plain pass or fail.

use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_check::verify::{verify_workspace, Options, Verdict};

#[path = "../../syntax/tests/support/inputs.rs"]
mod inputs;
use inputs::model_files;

#[test]
fn corpus_assertions_are_answered() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    assert!(corpus.is_dir(), "the corpus is expected at {}", corpus.display());
    let mut projects: Vec<PathBuf> =
        std::fs::read_dir(&corpus).unwrap().filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_dir()).collect();
    projects.sort();
    let mut opts = Options::default();
    opts.budget.max_states = 100_000;
    opts.budget.timeout = Some(Duration::from_secs(5));
    let mut total = 0;
    for project in projects {
        let mut paths = Vec::new();
        model_files(&project, &mut paths);
        let files: Vec<(String, String)> = paths
            .iter()
            .filter_map(|p| {
                Some((p.display().to_string(), String::from_utf8_lossy(&std::fs::read(p).ok()?).into_owned()))
            })
            .collect();
        let db = robosim_hir::RootDatabase::default();
        let ws = robosim_hir::load_workspace(&db, files, robosim_hir::RuleSet::Paper);
        for r in verify_workspace(&db, ws, &opts, None) {
            total += 1;
            println!(
                "{} {}: {} ({} states) {}",
                r.file,
                r.name,
                r.verdict.name(),
                r.stats.states,
                r.reason.clone().unwrap_or_default()
            );
            if matches!(r.verdict, Verdict::Unsupported | Verdict::Inconclusive) {
                assert!(r.reason.as_deref().is_some_and(|s| !s.is_empty()), "{} {}: no reason", r.file, r.name);
            }
        }
    }
    assert!(total > 40, "the corpus has dozens of assertions, found {total}");
}
