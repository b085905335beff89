//! libcspm's own test suite (`../shared/reference/libcspm/tests`, read in
//! place) run against this crate: per folder, files under `should_pass`
//! must pass and files under `should_fail` must fail, as libcspm's
//! `tests/Main.hs` decides it:
//! - parser: the text parses without errors;
//! - typechecker, desugar: parsing and checking (names; we have no full type
//!   inference yet, so most `should_fail` type errors are not caught);
//! - evaluator: checking, then every `test…` name evaluates to `true` and
//!   every `procTest…` compiles to an LTS (libcspm also compares a printed
//!   form of the process, which we do not reproduce).
//!
//! The test prints the pass rate per folder and fails if a folder drops
//! below the count recorded in `FLOOR`.

use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_cspm::{Evaluator, Limits, Module, NoNames, Severity};

/// Passing files per folder reached when this test was written (out of the
/// totals printed). Raise them when the crate improves; never lower them.
const FLOOR: &[(&str, usize)] = &[("parser", 74), ("typechecker", 123), ("evaluator", 82), ("desugar", 2)];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/libcspm/tests")
}

fn csp_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            csp_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "csp") {
            out.push(p);
        }
    }
}

/// Whether the file passes (`Ok`) or fails with a reason (`Err`).
fn run(section: &str, text: &str) -> Result<(), String> {
    if section == "parser" {
        let p = robosim_cspm::parse(text);
        return match p.errors().first() {
            Some(e) => Err(e.to_string()),
            None => Ok(()),
        };
    }
    let m = Module::check(text, &NoNames);
    if let Some(e) = m.diagnostics().iter().find(|d| d.severity == Severity::Error) {
        return Err(e.to_string());
    }
    if section != "evaluator" {
        return Ok(());
    }
    let limits = Limits { time: Duration::from_secs(3), max_states: 50_000, ..Limits::default() };
    let mut ev = Evaluator::new(&m, &NoNames, limits);
    for n in m.defined_names() {
        if n.starts_with("procTest") {
            ev.lts(&n).map_err(|e| format!("{n}: {e}"))?;
        } else if n.starts_with("test") {
            match ev.value(&n) {
                Ok(robosim_cspm::Value::Bool(true)) => {}
                Ok(v) => return Err(format!("{n} = {v}")),
                Err(e) => return Err(format!("{n}: {e}")),
            }
        }
    }
    Ok(())
}

#[test]
fn libcspm_suite() {
    let root = root();
    assert!(root.is_dir(), "libcspm's tests must be at {}", root.display());
    let verbose = std::env::var_os("CSPM_VERBOSE").is_some();
    let mut below = Vec::new();
    for &(section, floor) in FLOOR {
        let (mut passed, mut total) = (0, 0);
        for (dir, expect_pass) in [("should_pass", true), ("should_fail", false)] {
            let mut files = Vec::new();
            csp_files(&root.join(section).join(dir), &mut files);
            for f in files {
                total += 1;
                let bytes = std::fs::read(&f).unwrap();
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let sec = section.to_owned();
                // Deep recursion in the tests needs a big stack.
                let outcome = std::thread::Builder::new()
                    .stack_size(256 << 20)
                    .spawn(move || run(&sec, &text))
                    .unwrap()
                    .join()
                    .unwrap_or_else(|_| Err("panicked".to_owned()));
                assert!(!matches!(&outcome, Err(m) if m == "panicked"), "{}: panicked", f.display());
                if outcome.is_ok() == expect_pass {
                    passed += 1;
                } else if verbose {
                    eprintln!("  {section}/{dir}/{}: {:?}", f.file_name().unwrap().to_string_lossy(), outcome);
                }
            }
        }
        println!("{section}: {passed}/{total} ({:.0} %)", 100.0 * passed as f64 / total.max(1) as f64);
        if passed < floor {
            below.push(format!("{section}: {passed} < {floor}"));
        }
    }
    assert!(below.is_empty(), "pass rate dropped: {}", below.join(", "));
}
