//! Every model of `../shared/corpus` parses losslessly and without syntax
//! errors, except the six files the corpus MANIFEST lists as rejected by
//! RoboTool's grammar, which get a precise SYN-01 where the MANIFEST says.

use std::path::{Path, PathBuf};

use robosim_syntax::{parse, FileKind, Severity};

use robosim_test_support::inputs::model_files;

fn corpus_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus")
}

/// The MANIFEST's "Files that RoboTool's current grammar rejects", with the
/// text the first error must point at and a fragment of its message.
const REJECTED: &[(&str, &str, &str)] = &[
    ("robo-star__robochart-alpha-algorithm/aggregation.rct", "trigger", "empty `trigger`"),
    ("robo-star__robochart-alpha-algorithm/communication.rct", "trigger", "empty `trigger`"),
    ("UoY-RoboStar__SLEEC-TK/examples/ALMI/verification.assertions", "sleec", "SLEEC"),
    (
        "UoY-RoboStar__SLEEC-TK/sleec-core/Examples/FireFighter/robochart/firefighter-valid-conformance.assertions",
        "sleec",
        "SLEEC",
    ),
    (
        "UoY-RoboStar__SLEEC-TK/sleec-core/Examples/FireFighter/robochart/jss_running_example-conformance.assertions",
        "sleec",
        "SLEEC",
    ),
    (
        "UoY-RoboStar__SLEEC-TK/sleec-core/Examples/RAD-AssistiveDressingRobot/robochart/rad.assertions",
        "sleec",
        "SLEEC",
    ),
];

#[test]
fn corpus_parses() {
    let root = corpus_root();
    assert!(root.is_dir(), "the corpus must be at {} (../shared beside the project)", root.display());
    let mut files = Vec::new();
    model_files(&root, &mut files);
    assert!(files.len() >= 80, "expected the 82 corpus model files, found {}", files.len());
    let mut failures = Vec::new();
    let mut rejected_seen = 0;
    for path in &files {
        let rel = path.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
        let bytes = std::fs::read(path).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let kind = FileKind::from_path(path).unwrap();
        let parse = parse(&text, kind);
        assert_eq!(parse.syntax_node().text().to_string(), text, "{rel}: tree text differs from the file");
        let errors: Vec<_> = parse.errors().iter().filter(|e| e.severity == Severity::Error).collect();
        if let Some((_, at, msg)) = REJECTED.iter().find(|(f, _, _)| *f == rel) {
            rejected_seen += 1;
            let Some(first) = errors.first() else {
                failures.push(format!("{rel}: expected a SYN-01 error, got none"));
                continue;
            };
            let first_at = text.find(&format!("{at} ")).or_else(|| text.find(at)).unwrap();
            // The first error is on the first offending keyword of its kind.
            let err_text = &text[first.range];
            if err_text != *at || !first.message.contains(msg) || first.code() != "SYN-01" {
                failures.push(format!("{rel}: first error {:?} at {:?} ({:?})", first.message, first.range, err_text));
            }
            if *at == "sleec" && usize::from(first.range.start()) != first_at {
                failures.push(format!("{rel}: first SLEEC error is not at the first SLEEC item"));
            }
        } else if !errors.is_empty() {
            for e in errors {
                let line = text[..usize::from(e.range.start())].lines().count();
                failures.push(format!("{rel}:{line}: {} ({:?})", e.message, &text[e.range]));
            }
        }
    }
    assert_eq!(rejected_seen, REJECTED.len(), "not every rejected file was found");
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn legacy_empty_trigger_is_quick_fix_ready() {
    // Deleting exactly the reported range must leave a file without errors.
    let root = corpus_root();
    for rel in [
        "robo-star__robochart-alpha-algorithm/aggregation.rct",
        "robo-star__robochart-alpha-algorithm/communication.rct",
    ] {
        let mut text = std::fs::read_to_string(root.join(rel)).unwrap();
        loop {
            let p = parse(&text, FileKind::RoboChart);
            let Some(e) = p.errors().iter().find(|e| e.severity == Severity::Error) else {
                break;
            };
            assert!(e.message.contains("empty `trigger`"), "{rel}: unexpected {e:?}");
            assert_eq!(&text[e.range], "trigger");
            text.replace_range(std::ops::Range::<usize>::from(e.range), "");
        }
    }
}
