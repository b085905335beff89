//! Which semantics an assertion is checked in (RT-8): a plain `assertion`
//! in both the timed and the untimed one, `timed assertion` in the timed
//! one, `untimed assertion` in the untimed one. The native checker runs
//! the timed semantics only: an untimed assertion is `unsupported` (never a
//! timed verdict passed off as an untimed one), and a plain one says that
//! RoboTool would also report its untimed analysis.

use robosim_check::verify::{verify_workspace, Options, Report, Verdict};

const MODEL: &str = "interface I { event e }
stm M { uses I initial i state S { } transition t { from i to S } transition u { from S to S trigger e } }";

fn run(assertion: &str) -> Report {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        [("m.rct".to_string(), MODEL.to_string()), ("a.assertions".to_string(), assertion.to_string())],
        robosim_hir::RuleSet::Paper,
    );
    let mut reports = verify_workspace(&db, ws, &Options::default(), None);
    assert_eq!(reports.len(), 1, "{reports:?}");
    reports.remove(0)
}

const UNTIMED_NOTE: &str = "RoboTool also reports this assertion in the untimed semantics (RT-8)";

#[test]
fn a_plain_assertion_says_the_untimed_analysis_was_not_run() {
    let r = run("assertion A : M is deadlock-free");
    assert_eq!(r.verdict, Verdict::Pass, "{r:?}");
    assert!(r.notes.iter().any(|n| n.contains(UNTIMED_NOTE)), "{:?}", r.notes);
}

#[test]
fn a_timed_assertion_is_checked_in_the_timed_semantics_only() {
    let r = run("timed assertion A : M is deadlock-free");
    assert_eq!(r.verdict, Verdict::Pass, "{r:?}");
    assert!(!r.notes.iter().any(|n| n.contains(UNTIMED_NOTE)), "{:?}", r.notes);
}

#[test]
fn an_untimed_assertion_is_not_given_a_timed_verdict() {
    let r = run("untimed assertion A : M is deadlock-free");
    assert_eq!(r.verdict, Verdict::Unsupported, "{r:?}");
    assert!(r.reason.as_deref().unwrap_or_default().contains("untimed semantics (RT-9"), "{:?}", r.reason);
}
