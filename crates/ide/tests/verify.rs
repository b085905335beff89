//! Verification in the editor, without a protocol: lenses, runs on a
//! snapshot, and the results as titles, diagnostics and hovers, on the
//! paper's GT-3 design (`tests/data/verify/gt3`).

use robosim_ide::verify::{format_seconds, lens_title, shorten, Budget, Options, Profile, Report, Semantics, Verdict};
use robosim_ide::{AnalysisHost, Durability, FileId, Severity, TextSize, Verified, VerifyTarget};

const DESIGN: &str = include_str!("../../../tests/data/verify/gt3/design.rct");
const CHECKS: &str = include_str!("../../../tests/data/verify/gt3/checks.rsa");

fn host(extra: &[(&str, &str)]) -> AnalysisHost {
    let mut host = AnalysisHost::default();
    host.set_file("/w/design.rct", DESIGN.to_string(), None, Durability::LOW);
    host.set_file("/w/checks.rsa", CHECKS.to_string(), None, Durability::LOW);
    for (path, text) in extra {
        host.set_file(path, text.to_string(), None, Durability::LOW);
    }
    host
}

fn file(host: &AnalysisHost, path: &str) -> FileId {
    host.file_id(path).unwrap()
}

fn assertion(name: &str) -> VerifyTarget {
    VerifyTarget::Assertion { path: "/w/checks.rsa".into(), name: name.into() }
}

fn simulation(path: &str, name: &str) -> VerifyTarget {
    VerifyTarget::Simulation { path: path.into(), name: name.into() }
}

fn opts() -> Options {
    Options { profile: Profile::RoboTool3, budget: Budget::default().with_threads(1), async_buffer: None }
}

fn run(host: &AnalysisHost, target: &VerifyTarget) -> Vec<Report> {
    host.analysis().verify(target, &opts(), None).unwrap().unwrap()
}

fn offset_of(text: &str, needle: &str) -> TextSize {
    TextSize::from(text.find(needle).unwrap() as u32)
}

#[test]
fn lenses_on_assertions_simulations_and_modules() {
    let host = host(&[("/w/sim.rst", "stm S { initial i }")]);
    let a = host.analysis();
    let lenses = a.verify_lenses(file(&host, "/w/checks.rsa")).unwrap();
    let summary: Vec<(String, VerifyTarget, Option<i64>)> =
        lenses.iter().map(|l| (CHECKS[l.range].to_string(), l.target.clone(), l.cycle)).collect();
    assert_eq!(
        summary,
        [
            ("P1".to_string(), simulation("/w/checks.rsa", "P1"), Some(1)),
            ("S1".to_string(), assertion("S1"), None),
            ("S2".to_string(), assertion("S2"), None),
        ]
    );
    assert_eq!(lenses[1].assertion_range, Some(lenses[1].range));
    assert_eq!(lenses[0].assertion_range, None);
    let titles: Vec<String> = lenses.iter().map(|l| lens_title(l, &[], false)).collect();
    assert_eq!(titles, ["▶ Check schedulability (cycle 1)", "▶ Verify", "▶ Verify"]);
    assert_eq!(lens_title(&lenses[1], &[], true), "⏳ verifying… (click to restart)");

    // The module the simulation is of.
    let module = a.verify_lenses(file(&host, "/w/design.rct")).unwrap();
    assert_eq!(module.len(), 1);
    assert_eq!(&DESIGN[module[0].range], "CFootBot");
    assert_eq!(module[0].target, simulation("/w/checks.rsa", "P1"));
    assert_eq!(module[0].cycle, Some(1));
    // Nothing on RoboSim files.
    assert!(a.verify_lenses(file(&host, "/w/sim.rst")).unwrap().is_empty());
}

#[test]
fn a_failure_as_diagnostic_title_and_hover() {
    let host = host(&[]);
    let reports = run(&host, &assertion("S1"));
    assert_eq!(reports.len(), 1);
    let r = &reports[0];
    assert_eq!((r.name.as_str(), r.verdict), ("S1", Verdict::Fail));

    let lens = host.analysis().verify_lenses(file(&host, "/w/checks.rsa")).unwrap().remove(1);
    assert_eq!(lens_title(&lens, &[r], false), "✘ fail — re-run");

    let verified = [Verified { report: r.clone(), profile: Profile::RoboTool3 }];
    let checks = file(&host, "/w/checks.rsa");
    let diags = host.analysis().verify_diagnostics(checks, &verified).unwrap();
    assert_eq!(diags.len(), 1);
    let d = &diags[0];
    assert_eq!((d.code.as_str(), d.severity), ("RS-VERIFY", Severity::Error));
    assert_eq!(&CHECKS[d.range], "S1");
    assert_eq!(d.message, "CFootBot cannot be scheduled in cycles of period 1");
    assert!(d.related.iter().all(|rel| rel.path == "/w/design.rct" && rel.file == file(&host, "/w/design.rct")));
    assert_eq!(&DESIGN[d.related[0].range], "move(lv, 0)");
    assert_eq!(d.related[0].message, "cycle 0, t = 0: (moveCall.1.0) — mv::sm: calls the platform operation in Moving");
    let stuck = d.related.last().unwrap();
    assert_eq!(&DESIGN[stuck.range], "move(0, av)");
    assert!(stuck.message.starts_with("mv::sm (in Turning) must call move(0, 15) now"), "{}", stuck.message);
    // None on the design itself.
    assert!(host.analysis().verify_diagnostics(file(&host, "/w/design.rct"), &verified).unwrap().is_empty());

    let at = offset_of(CHECKS, "S1 :") + TextSize::from(1);
    let h = host.analysis().hover_with_verification(checks, at, None, &verified).unwrap().unwrap();
    assert_eq!(&CHECKS[h.range], "S1");
    let expected_table = "deadlock reached by:\n\n```text\ncycle 0  t = 0\n  read   i_obstacle.true\n  \
                          design (moveCall.1.0)  mv::sm: calls the platform operation in Moving  --> design.rct:33:15\n";
    assert!(h.markdown.contains(expected_table), "{}", h.markdown);
    assert!(h.markdown.starts_with("**Last verification:** fail · 23 states, 25 transitions, "), "{}", h.markdown);
    assert!(h.markdown.contains(" · robotool3\n\nCFootBot cannot be scheduled"), "{}", h.markdown);
    assert!(h.markdown.contains("\n\ndomains: "), "{}", h.markdown);
    // The declaration's hover follows.
    assert!(h.markdown.ends_with("```robosim\nassertion S1\n```"), "{}", h.markdown);
    // Elsewhere, and without results, the usual hover.
    let plain = host.analysis().hover_with_verification(checks, at, None, &[]).unwrap().unwrap();
    assert!(!plain.markdown.contains("Last verification"));
    assert_eq!(Some(plain), host.analysis().hover(checks, at).unwrap());
}

#[test]
fn a_simulation_runs_the_assertions_about_it() {
    let host = host(&[]);
    let reports = run(&host, &simulation("/w/checks.rsa", "P1"));
    let verdicts: Vec<(&str, Verdict)> = reports.iter().map(|r| (r.name.as_str(), r.verdict)).collect();
    assert_eq!(verdicts, [("S1", Verdict::Fail), ("S2", Verdict::Pass)]);
    let lens = host.analysis().verify_lenses(file(&host, "/w/design.rct")).unwrap().remove(0);
    let refs: Vec<&Report> = reports.iter().collect();
    assert_eq!(lens_title(&lens, &refs, false), "✘ fail — re-run");
    let pass = &reports[1];
    let title = lens_title(&lens, &[pass], false);
    assert_eq!(title, format!("✔ pass · {} states · {}", pass.stats.states, format_seconds(pass.stats.seconds)));
    // A pass has no diagnostic.
    let verified = [Verified { report: pass.clone(), profile: Profile::RoboTool3 }];
    assert!(host.analysis().verify_diagnostics(file(&host, "/w/checks.rsa"), &verified).unwrap().is_empty());
}

#[test]
fn a_simulation_without_assertions_is_checked_as_is() {
    let extra = "simulation P3 of paper_design::CFootBot { cycleDef cycle == 3 }\n";
    let host = host(&[("/w/extra.rsa", extra)]);
    let reports = run(&host, &simulation("/w/extra.rsa", "P3"));
    assert_eq!(reports.len(), 1);
    let r = &reports[0];
    assert_eq!((r.name.as_str(), r.text.as_str(), r.file.as_str()), ("P3", "P3 is schedulable", "/w/extra.rsa"));
    assert_eq!(&extra[r.name_range], "P3");
    // The design's constants have no values without an assertion to give
    // them: RoboTool's defaults (RT-1), which the report names. With PI =
    // av = 0 the design cannot be scheduled.
    assert_eq!(r.verdict, Verdict::Fail, "{:?}", r.reason);
    assert!(r.notes.iter().any(|n| n.contains("sm::PI = 0 (RT-1)")), "{:?}", r.notes);
    let verified = [Verified { report: r.clone(), profile: Profile::RoboTool3 }];
    let diags = host.analysis().verify_diagnostics(file(&host, "/w/extra.rsa"), &verified).unwrap();
    assert_eq!(diags.len(), 1);
    assert_eq!(&extra[diags[0].range], "P3");
    // Two simulations of the module: two lenses on it.
    let lenses = host.analysis().verify_lenses(file(&host, "/w/design.rct")).unwrap();
    let cycles: Vec<Option<i64>> = lenses.iter().map(|l| l.cycle).collect();
    assert_eq!(cycles, [Some(1), Some(3)]);
}

#[test]
fn bad_targets() {
    let host = host(&[]);
    let opts = opts();
    let a = host.analysis();
    assert_eq!(a.check_verify_target(&assertion("S1")).unwrap(), Ok(()));
    assert_eq!(a.check_verify_target(&simulation("/w/checks.rsa", "P1")).unwrap(), Ok(()));
    for (target, message) in [
        (assertion("S9"), "`/w/checks.rsa` has no assertion `S9`"),
        (simulation("/w/checks.rsa", "P9"), "`/w/checks.rsa` declares no simulation `P9`"),
        (simulation("/w/design.rct", "P1"), "`/w/design.rct` is not an assertion file (.rsa or .assertions)"),
        (simulation("/w/none.rsa", "P1"), "`/w/none.rsa` is not a file of the workspace"),
    ] {
        assert_eq!(a.check_verify_target(&target).unwrap(), Err(message.to_string()));
        assert_eq!(a.verify(&target, &opts, None).unwrap().unwrap_err(), message);
    }
}

#[test]
fn titles_in_short() {
    assert_eq!(format_seconds(0.0004), "0.4 ms");
    assert_eq!(format_seconds(0.0123), "12 ms");
    assert_eq!(format_seconds(3.21), "3.2 s");
    assert_eq!(shorten("short\nsecond line", 60), "short");
    assert_eq!(shorten("a fairly long reason", 10), "a fairly…");
    assert_eq!(shorten("ééééé", 4), "ééé…");
}

/// Setting the same text again is no write: it does not wait for the
/// snapshots (a verification holds one while it runs).
#[test]
fn setting_the_same_text_does_not_wait_for_snapshots() {
    let mut host = host(&[]);
    let snapshot = host.analysis();
    let (tx, rx) = std::sync::mpsc::channel();
    let writer = std::thread::spawn(move || {
        host.set_file("/w/design.rct", DESIGN.to_string(), None, Durability::MEDIUM);
        tx.send(()).unwrap();
        host
    });
    let done = rx.recv_timeout(std::time::Duration::from_secs(10));
    drop(snapshot);
    let host = writer.join().unwrap();
    assert!(done.is_ok(), "setting the same text waited for the snapshot");
    assert!(!host.would_change("/w/design.rct", DESIGN, None));
    assert!(host.would_change("/w/design.rct", "", None));
    assert!(host.would_change("/w/new.rct", "", None));
}

/// RT-8: a plain assertion about a RoboChart element has a report in each
/// semantics: the lens shows both verdicts when they differ, each
/// diagnostic says which semantics it is about, the hover shows both.
/// RT-9: untimed, `wait(2)` is SKIP, so `Fast` has `Slow`'s traces.
#[test]
fn both_semantics_side_by_side() {
    const MODEL: &str = include_str!("../../../tests/data/verify/untimed/model.rct");
    const ASSERTIONS: &str = include_str!("../../../tests/data/verify/untimed/checks.assertions");
    let host = host(&[("/w/m.rct", MODEL), ("/w/a.assertions", ASSERTIONS)]);
    let target = VerifyTarget::Assertion { path: "/w/a.assertions".into(), name: "W".into() };
    let reports = run(&host, &target);
    let got: Vec<(Semantics, Verdict)> = reports.iter().map(|r| (r.semantics, r.verdict)).collect();
    assert_eq!(got, [(Semantics::Timed, Verdict::Fail), (Semantics::Untimed, Verdict::Pass)]);
    let a = host.analysis();
    let checks = file(&host, "/w/a.assertions");
    let lens = a.verify_lenses(checks).unwrap().remove(0);
    let refs: Vec<&Report> = reports.iter().collect();
    assert_eq!(lens_title(&lens, &refs, false), "timed ✘ fail · untimed ✔ pass — re-run");
    let verified: Vec<Verified> =
        reports.iter().map(|r| Verified { report: r.clone(), profile: Profile::RoboTool3 }).collect();
    let diags = a.verify_diagnostics(checks, &verified).unwrap();
    let messages: Vec<&str> = diags.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(
        messages,
        ["timed semantics: refinement fails: the model can perform `Fast::o.out` where the specification cannot"]
    );
    let at = offset_of(ASSERTIONS, "W :");
    let h = a.hover_with_verification(checks, at, None, &verified).unwrap().unwrap();
    let timed = h.markdown.find("**Last verification (timed semantics):** fail").expect(&h.markdown);
    let untimed = h.markdown.find("**Last verification (untimed semantics):** pass").expect(&h.markdown);
    assert!(timed < untimed, "{}", h.markdown);
    // Both pass: one title saying so.
    let pass: Vec<Report> = reports
        .iter()
        .cloned()
        .map(|mut r| {
            r.verdict = Verdict::Pass;
            r
        })
        .collect();
    let refs: Vec<&Report> = pass.iter().collect();
    assert!(
        lens_title(&lens, &refs, false).starts_with("✔ pass, timed and untimed · "),
        "{}",
        lens_title(&lens, &refs, false)
    );
}
