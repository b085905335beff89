//! Checks against references outside the repository's fixtures
//! (`test_data/verify`): the corpus's models and the reference oracle
//! (`../shared/spec/semantics_oracle.py`, run with python3), whose
//! verdicts and counterexamples the engine must reproduce.

use std::path::Path;

use robosim_engine::verify::{verify_texts, Options, Report, Semantics, Verdict};

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
