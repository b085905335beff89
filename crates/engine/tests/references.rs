//! Checks against references outside the repository's fixtures
//! (`test_data/verify`): the corpus's models and the reference oracle
//! (`../shared/spec/semantics_oracle.py`, run with python3), whose
//! verdicts and counterexamples the engine must reproduce.

use std::path::Path;

use robosim_engine::verify::{trace_text, verify_texts, Options, Profile, Report, Semantics, Verdict};

/// The timed reports of the assertions of `files`.
fn run(files: &[(&str, String)]) -> Vec<Report> {
    let files = files.iter().map(|(p, t)| (p.to_string(), t.clone()));
    verify_texts(files, &Options::default()).into_iter().filter(|r| r.semantics == Semantics::Timed).collect()
}

/// robo-star/robochart-alpha-algorithm: `Communication` receives
/// `ID * ID` pairs and collects neighbours in a `Set(ID)`. A receive can
/// race the timeout `since(RCC) >= RC` (a triggerless transition), so the
/// machine is not deterministic; it never deadlocks nor diverges.
#[test]
fn alpha_algorithm_communication() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/robo-star__robochart-alpha-algorithm");
    let mut files = Vec::new();
    for e in std::fs::read_dir(&dir).expect("the corpus").flatten() {
        let p = e.path();
        if robosim_syntax::FileKind::from_path(&p).is_some() {
            files.push((p.display().to_string(), std::fs::read_to_string(&p).unwrap()));
        }
    }
    let files: Vec<(&str, String)> = files.iter().map(|(p, t)| (p.as_str(), t.clone())).collect();
    let mut got: Vec<(String, Verdict, u64)> = run(&files)
        .iter()
        .filter(|r| ["A1", "A2", "A3", "a1", "a2", "a3"].contains(&r.name.as_str()))
        .map(|r| (r.name.clone(), r.verdict, r.stats.states))
        .collect();
    got.sort_by(|a, b| a.0.cmp(&b.0));
    let expected = [
        ("A1", Verdict::Fail, 11),
        ("A2", Verdict::Pass, 102),
        ("A3", Verdict::Pass, 102),
        ("a1", Verdict::Fail, 11),
        ("a2", Verdict::Pass, 102),
        ("a3", Verdict::Pass, 102),
    ];
    assert_eq!(got, expected.map(|(n, v, s)| (n.to_string(), v, s)).to_vec());
}

/// The paper's Figure 1 (examples/paper/design.rct) and its variants, as the
/// oracle names them.
fn figure1(variant: &str) -> String {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper/design.rct"))
        .expect("examples/paper/design.rct");
    let out = match variant {
        "Fig.1" => text.clone(),
        "Fig.1 without wait(1) in Moving" => text.replace("entry move(lv, 0); wait(1)", "entry move(lv, 0)"),
        "Fig.1 with wait([0,1]) fixed to 0" => text.replace("wait([0, 1])", "wait(0)"),
        v => panic!("unknown variant {v}"),
    };
    assert!(variant == "Fig.1" || out != text, "the variant edit of {variant} did not apply");
    out
}

/// The oracle's event names in ours (lv = 1, av = 15, registers `i_`/`o_`).
fn oracle_trace(t: &str) -> String {
    t.split_whitespace()
        .map(|e| match e {
            "registerRead.obstacle.True" => "registerRead.i_obstacle.true",
            "registerRead.obstacle.False" => "registerRead.i_obstacle.false",
            "(moveCall.lv.0)" => "(moveCall.1.0)",
            "(moveCall.0.av)" => "(moveCall.0.15)",
            "moveCall.lv.0" => "moveCall.1.0",
            "moveCall.0.av" => "moveCall.0.15",
            "registerWrite.moveU.true.lv.0" => "registerWrite.moveU.true.1.0",
            "registerWrite.moveU.true.0.av" => "registerWrite.moveU.true.0.15",
            "registerWrite.move.lv.0" => "registerWrite.o_move.1.0",
            "registerWrite.move.0.av" => "registerWrite.o_move.0.15",
            "registerWrite.stop" => "registerWrite.o_stop",
            "(obstacle)" => "(obstacle.in)",
            other => other,
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Every schedulability case of the oracle, in both profiles: same verdict
/// and, for failures, the same shortest counterexample event for event
/// (GT-3 in `paper2019` is the paper's published trace). The oracle's state
/// counts are not compared: it steps through every internal instruction,
/// we run straight-line code in one step.
#[test]
fn agrees_with_the_oracle_on_the_running_example() {
    let oracle = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/spec/semantics_oracle.py");
    let out = std::process::Command::new("python3").arg(oracle).output().expect("python3 runs the oracle");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let mut compared = 0;
    for line in text.lines().filter(|l| l.starts_with("robotool3 ") || l.starts_with("paper2019 ")) {
        let profile = if line.starts_with("paper2019") { Profile::Paper2019 } else { Profile::RoboTool3 };
        let rest = line["robotool3 ".len()..].trim_start();
        let (variant, rest) = rest.split_once("  p=").expect("variant and period");
        let variant = variant.trim();
        let p: u32 = rest[..1].parse().expect("period");
        let (verdict, trace) = match rest.split_once("NOT schedulable: ") {
            Some((_, t)) => (Verdict::Fail, oracle_trace(t)),
            None => (Verdict::Pass, String::new()),
        };
        let rsa = format!(
            "simulation S of paper_design::CFootBot {{ cycleDef cycle == {p} }}
             assertion A : S is schedulable with constant PI of paper_design::SMovement set to 45,
               constant av of paper_design::SMovement set to 15, and constant lv of paper_design::SMovement set to 1 ."
        );
        let files = [("design.rct".to_string(), figure1(variant)), ("checks.rsa".to_string(), rsa)];
        let r = verify_texts(files, &Options { profile, ..Options::default() }).remove(0);
        let got = r.counterexample.as_ref().map(|c| trace_text(&c.steps)).unwrap_or_default();
        assert_eq!((r.verdict, got.as_str()), (verdict, trace.as_str()), "{variant}, p = {p}, {profile:?}");
        compared += 1;
    }
    assert_eq!(compared, 24, "the oracle's schedulability lines");
}
