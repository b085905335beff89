//! Which semantics an assertion is checked in (RT-8): a plain `assertion`
//! in both the timed and the untimed one (a report for each, timed first),
//! `timed assertion` in the timed one, `untimed assertion` in the untimed
//! one — never a verdict of one semantics passed off as the other's.

use robosim_engine::verify::{verify_workspace, Options, Report, Semantics, Verdict};

const MODEL: &str = "interface I { event e }
stm M { uses I initial i state S { } transition t { from i to S } transition u { from S to S trigger e } }";

fn run(assertion: &str) -> Vec<Report> {
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(
        &db,
        [("m.rct".to_string(), MODEL.to_string()), ("a.assertions".to_string(), assertion.to_string())],
        robosim_hir::RuleSet::Paper,
    );
    verify_workspace(&db, ws, &Options::default(), None)
}

fn semantics(reports: &[Report]) -> Vec<(Semantics, Verdict)> {
    reports.iter().map(|r| (r.semantics, r.verdict)).collect()
}

#[test]
fn a_plain_assertion_is_reported_in_both_semantics() {
    let r = run("assertion A : M is deadlock-free");
    assert_eq!(semantics(&r), [(Semantics::Timed, Verdict::Pass), (Semantics::Untimed, Verdict::Pass)], "{r:?}");
    assert!(r.iter().all(|r| r.name == "A"));
}

#[test]
fn a_timed_assertion_is_checked_in_the_timed_semantics_only() {
    let r = run("timed assertion A : M is deadlock-free");
    assert_eq!(semantics(&r), [(Semantics::Timed, Verdict::Pass)], "{r:?}");
}

#[test]
fn an_untimed_assertion_is_checked_in_the_untimed_semantics_only() {
    let r = run("untimed assertion A : M is deadlock-free");
    assert_eq!(semantics(&r), [(Semantics::Untimed, Verdict::Pass)], "{r:?}");
    assert_eq!(r[0].reason.as_deref(), Some("M never deadlocks and never diverges"));
}
