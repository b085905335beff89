//! Every assertion of the reference corpus (../shared/corpus), each RoboTool
//! project (`inputs::corpus_projects`) as its own workspace: no panic, a bounded run, and a reason for every
//! verdict that is not a plain pass or fail.

use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_engine::verify::{verify_workspace, Options, Semantics, Verdict};

use inputs::model_files;
use robosim_test_support::inputs;

/// One corpus project as its own workspace.
fn load_project(project: &Path) -> (robosim_hir::RootDatabase, robosim_hir::Workspace) {
    let mut paths = Vec::new();
    model_files(project, &mut paths);
    let files: Vec<(String, String)> = paths
        .iter()
        .filter_map(|p| Some((p.display().to_string(), String::from_utf8_lossy(&std::fs::read(p).ok()?).into_owned())))
        .collect();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    (db, ws)
}

#[test]
fn corpus_assertions_are_answered() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    assert!(corpus.is_dir(), "the corpus is expected at {}", corpus.display());
    let mut projects: Vec<PathBuf> =
        std::fs::read_dir(&corpus).unwrap().filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_dir()).collect();
    projects.sort();
    // RoboTool's projects (a repository may hold several, MANIFEST.md).
    let projects: Vec<PathBuf> = projects.iter().flat_map(|r| inputs::corpus_projects(r)).collect();
    let mut opts = Options::default();
    opts.budget.max_states = 100_000;
    opts.budget.timeout = Some(Duration::from_secs(5));
    let mut total = 0;
    for project in projects {
        let (db, ws) = load_project(&project);
        for r in verify_workspace(&db, ws, &opts, None) {
            total += 1;
            println!(
                "{} {} [{}]: {} ({} states) {}",
                r.file,
                r.name,
                r.semantics.name(),
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

/// The reports on the Alpha Algorithm's `model.assertions` named in
/// `names`: (name, verdict, states).
fn alpha_algorithm(opts: &Options, names: &[&str]) -> Vec<(String, Verdict, u64)> {
    let project =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/robo-star__robochart-alpha-algorithm");
    let mut paths = Vec::new();
    model_files(&project, &mut paths);
    let files: Vec<(String, String)> =
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).unwrap())).collect();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    verify_workspace(&db, ws, opts, None)
        .into_iter()
        // The timed analysis (both: the fixture `untimed_alpha_algorithm_in_both_semantics`).
        .filter(|r| r.semantics == Semantics::Timed)
        .filter(|r| r.file.ends_with("model.assertions") && names.contains(&r.name.as_str()))
        .map(|r| (r.name, r.verdict, r.stats.states))
        .collect()
}

/// The Alpha Algorithm's RoboChart assertions, whose machines call
/// `random()` and `floor(x)`, defined in CSPm in its instantiations: the
/// verdicts FDR recorded for them (semantics.md §9.4, GT-28).
#[test]
fn alpha_algorithm_assertions_match_fdr() {
    let got: Vec<(String, Verdict)> = alpha_algorithm(&Options::default(), &["a1", "a2", "a3", "a4", "a5", "a6"])
        .into_iter()
        .map(|(n, v, _)| (n, v))
        .collect();
    let expected = [
        // `Communication is deterministic`: FDR says false.
        ("a1", Verdict::Fail),
        ("a2", Verdict::Pass),
        ("a3", Verdict::Pass),
        // `Movement is not deterministic`: FDR says it is not.
        ("a4", Verdict::Pass),
        ("a5", Verdict::Pass),
        ("a6", Verdict::Pass),
    ];
    assert_eq!(got, expected.map(|(n, v)| (n.to_string(), v)).to_vec());
}

/// The Alpha Algorithm's module, whose controllers are connected
/// asynchronously: through RoboTool's one-place overwriting buffer (RT-12,
/// the generated `Buffer0`, used when none is assumed) it is
/// non-deterministic, divergence-free and deadlock-free, as FDR recorded
/// (a7, a8, a9 true: robotool-facts.md); and so under a blocking one.
#[test]
fn alpha_algorithm_module_under_assumed_buffers() {
    let run = |buffer: Option<&str>| {
        let async_buffer = buffer.map(|b| robosim_engine::verify::AsyncBuffer::parse(b).expect("a buffer"));
        alpha_algorithm(&Options { async_buffer, ..Options::default() }, &["a7", "a8", "a9"])
    };
    for buffer in [None, Some("1:overwrite"), Some("1:block")] {
        // Its uninitialised booleans start true (RT-4): 3,898 states, not
        // the 4,144 of false.
        let expected = [("a7", Verdict::Pass, 11), ("a8", Verdict::Pass, 3898), ("a9", Verdict::Pass, 3898)];
        assert_eq!(run(buffer), expected.map(|(n, v, s)| (n.to_string(), v, s)).to_vec(), "{buffer:?}");
    }
}

/// Every corpus assertion with a side in a `csp` block of its file goes to
/// the CSPm bridge (issue 18): none is turned away as "raw CSPm" any more;
/// each is decided or says precisely why not. The Alpha Algorithm's `b1`
/// and `b2` use RoboTool 1's names (`AggregationSoftware_receive`), which
/// RoboTool 3's CSPm does not have: an unresolved name, as FDR reports,
/// not a verdict.
#[test]
fn csp_assertions_are_decided_or_explained() {
    use robosim_engine::assertions::{read_assertions, AssertionKind};
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    let mut projects: Vec<PathBuf> =
        std::fs::read_dir(&corpus).unwrap().filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_dir()).collect();
    projects.sort();
    // RoboTool's projects (a repository may hold several, MANIFEST.md).
    let projects: Vec<PathBuf> = projects.iter().flat_map(|r| inputs::corpus_projects(r)).collect();
    let mut opts = Options::default();
    opts.budget.max_states = 100_000;
    // A wall-clock bound only against hangs: the states bound decides, so
    // that a loaded machine (CI) cannot turn a verdict into a timeout.
    opts.budget.timeout = Some(Duration::from_secs(60));
    let (mut csp, mut decided) = (0, Vec::new());
    // The assertions FDR itself stops on with an error (no verdict).
    let (mut alpha, mut errors) = (Vec::new(), Vec::new());
    for project in projects {
        let (db, ws) = load_project(&project);
        for &f in ws.files(&db) {
            if f.is_library(&db) || !f.kind(&db).is_assertions() {
                continue;
            }
            let read = read_assertions(&robosim_hir::parse(&db, f).syntax_node());
            let block = |p: &[String]| matches!(p, [n] if read.csp_block(n).is_some());
            let reports = robosim_engine::verify::verify_file(&db, ws, f, &opts, None);
            // A plain assertion has a report per semantics (RT-8), timed
            // first; both are printed, the timed one counted.
            for a in &read.assertions {
                let Some(r) = reports.iter().find(|r| r.name == a.name) else { continue };
                let uses_csp = match &a.kind {
                    AssertionKind::Refines { other, .. } | AssertionKind::Equals { other, .. } => {
                        block(other) || block(&a.subject)
                    }
                    _ => false,
                };
                if !uses_csp {
                    continue;
                }
                csp += 1;
                let reason = r.reason.clone().unwrap_or_default();
                for r in reports.iter().filter(|r| r.name == a.name) {
                    let why = r.reason.clone().unwrap_or_default();
                    println!("{} {} ({}): {} — {why}", r.file, r.name, r.semantics.name(), r.verdict.name());
                }
                assert!(!reason.contains("raw CSPm"), "{}: {reason}", r.name);
                assert!(!reason.is_empty(), "{}: no reason", r.name);
                if matches!(r.verdict, Verdict::Pass | Verdict::Fail) {
                    let file = r.file.rsplit_once("corpus/").map_or(r.file.as_str(), |(_, f)| f);
                    decided.push(format!("{file} {}: {}", r.name, r.verdict.name()));
                }
                // RmGuar reads `radiation_level.in.29`, the first of its
                // values outside `core_real = {-2..2}` (the conditions'
                // 30 and 60 are comparison operands, which widen nothing,
                // RT-5): FDR's evaluator stops on that value (libcspm's
                // `dotIsNotValidMessage`), so there is no verdict, and the
                // report says FDR's error.
                if a.name == "RadiationMonitorGuarantee" {
                    assert_eq!(r.verdict, Verdict::Unsupported);
                    assert!(
                        reason.starts_with("`RmGuar` in `csp` block `RmGuar` at line 60: FDR stops with an error: the value `RemoteInspectionController::RadiationMonitor::radiation_level.in.29` is invalid")
                            && reason.contains("its field 2 `29` is not a member of the set {-2, -1, 0, 1, 2}"),
                        "{reason}"
                    );
                    errors.push(r.name.clone());
                }
                if r.file.ends_with("alpha-algorithm/model.assertions") {
                    errors.push(r.name.clone());
                    alpha.push((r.name.clone(), r.verdict, reason));
                }
            }
        }
    }
    println!("{} of {csp} assertions on csp blocks decided, {} FDR errors", decided.len(), errors.len());
    assert_eq!(csp, 29, "the corpus has 29 assertions on csp blocks");
    // Every one is answered as FDR answers it: 26 verdicts, 3 errors.
    assert_eq!((decided.len(), errors.len()), (26, 3), "{errors:?}");
    // The decided ones, exactly (a regression fails here). Ours all fail in the
    // timed semantics (RT-8: a plain assertion is checked timed, and csp
    // blocks are read there), for the same reason FDR gives: the
    // specifications are untimed (no `tock`), and the element lets time
    // pass before the specification's first event (⟨tock⟩ is a trace of
    // the model, not of the spec). The skill contracts (EBS*, EBCS1) need
    // `exploreVOut : Velocities * nat` (a tuple with a record component);
    // TestReq and RL need `waypoint_inverse`'s RT-2 default `(0, 0)` and
    // `RUN(Events)` over the module's own channels.
    let explore = "UoY-RoboStar__roboarch-examples/ObstacleAvoidance/RoboChart/SkillExploreProperties.assertions";
    let skills = "UoY-RoboStar__roboarch-examples/ObstacleAvoidance/RoboChart/Skill";
    let remote = "autonomy-and-verification__robochart_remoteinspection/main.assertions";
    // The skills manager's contracts (both copies of the project): its
    // machine keeps `cycleSkills : Seq( Skills )` (at most two long) and
    // answers `getActiveSkills` with `activeSkills!currentlyActiveSkills`,
    // a set. Each specification ranges over `allSkillsManagerEvents`, which
    // lacks events of the machine's interfaces, `getProximityGapValue`
    // among them; in state `HandleRequests`, entered at once from
    // `Initialise`, the machine accepts `getProximityGapValue` (transition
    // `HandleValueQueriesReceivegetProximityGapValue`), so
    // ⟨…::getProximityGapValue.in⟩ is a trace of the machine and of no
    // specification: each failures refinement fails on that trace (in
    // either semantics; timed, ⟨tock⟩ fails too). EBSM4's `[] ev : S @`
    // bodies extend to the end of the line (`@` binds loosest in CSPm), so
    // its specification is an external choice of internal choices, too
    // large to compile in full: it is compiled up to traces, which
    // suffices for a failing trace.
    let manager = ["ObstacleAvoidance", "ObstacleAvoidance-Reduced"]
        .map(|p| format!("UoY-RoboStar__roboarch-examples/{p}/RoboChart/SkillsManagerProperties.assertions"));
    let sleec = "UoY-RoboStar__SLEEC-TK/sleec-core/Examples/FireFighter/robochart/jss_running_example-manual-conformance.assertions";
    let mut expected: Vec<String> = ["EBS1", "EBS2", "EBS3", "EBS4", "EBS5", "EBS6", "EBCS1"]
        .iter()
        .map(|n| format!("{explore} {n}: fail"))
        .chain(
            ["MoveProperties.assertions EBDS1", "MoveProperties.assertions EBDS2", "MoveProperties.assertions EBDS4"]
                .iter()
                .chain(&["ProximityProperties.assertions EBDS1", "ProximityProperties.assertions EBDS3"])
                .map(|n| format!("{skills}{n}: fail")),
        )
        .chain(["TestReq", "RL"].iter().map(|n| format!("{remote} {n}: fail")))
        .chain(manager.iter().flat_map(|m| {
            ["EBSM1", "EBSM2_ExplorePriority", "EBSM3_ExplorePriority", "EBSM4"].map(|n| format!("{m} {n}: fail"))
        }))
        // RoboTool's tock-CSP library (`EDeadline`): the SLEEC checks.
        .chain(
            ["RCheck1: fail", "RCheck2: fail", "RCheck3: pass", "RCheck4: fail"].iter().map(|n| format!("{sleec} {n}")),
        )
        .collect();
    expected.sort();
    decided.sort();
    assert_eq!(decided, expected);
    assert_eq!(alpha.len(), 2);
    for (name, verdict, reason) in &alpha {
        assert_eq!(*verdict, Verdict::Unsupported, "{name}");
        assert!(
            reason.contains("unresolved name") && reason.contains("`AggregationSoftware_receive` is not defined"),
            "{name}: {reason}"
        );
    }
}

/// The corpus's repositories with several RoboTool projects are read as
/// MANIFEST.md records them, so that the two copies of roboarch's
/// `Executive::Executive` are never one workspace's duplicates.
#[test]
fn repositories_with_several_projects_are_split() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    let names = |repo: &str| -> Vec<String> {
        let root = corpus.join(repo);
        inputs::corpus_projects(&root).iter().map(|p| p.strip_prefix(&root).unwrap().display().to_string()).collect()
    };
    assert_eq!(
        names("UoY-RoboStar__roboarch-examples"),
        ["ObstacleAvoidance/RoboChart", "ObstacleAvoidance-Reduced/RoboChart"]
    );
    assert_eq!(
        names("UoY-RoboStar__SLEEC-TK"),
        [
            "examples/ALMI",
            "sleec-core/Examples/FireFighter/robochart",
            "sleec-core/Examples/RAD-AssistiveDressingRobot/robochart"
        ]
    );
    assert_eq!(names("robo-star__robochart-alpha-algorithm"), [""]);
}
