//! Every `csp … csp-begin … csp-end` block of the assertion files of
//! `../shared/corpus` and `../shared/reference` (read in place) parses
//! without errors; every block that uses only names it defines itself
//! also checks, and each of its definitions evaluates (processes to LTSs).

use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_cspm::{Code, Evaluator, Limits, Module, NoNames, Severity, Value};
use robosim_syntax::{parse, FileKind};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    for p in rd.flatten().map(|e| e.path()) {
        if p.is_dir() {
            files(&p, out);
        } else if p.extension().is_some_and(|e| e == "assertions" || e == "rsa") {
            out.push(p);
        }
    }
}

/// The CSPm text of each block of one assertion file.
fn blocks(path: &Path) -> Vec<String> {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let Some(kind) = FileKind::from_path(path) else { return Vec::new() };
    let p = parse(&text, kind);
    p.tree()
        .csp_blocks()
        .filter_map(|b| b.csp_text())
        .filter_map(|t| {
            let s = t.text();
            let s = s.strip_prefix("csp-begin")?;
            Some(s.strip_suffix("csp-end").unwrap_or(s).to_owned())
        })
        .collect()
}

#[test]
fn real_blocks_parse_check_and_evaluate() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    let mut paths = Vec::new();
    files(&base.join("corpus"), &mut paths);
    files(&base.join("reference"), &mut paths);
    paths.sort();
    let (mut total, mut own, mut evaluated, mut processes) = (0, 0, 0, 0);
    let mut failures = Vec::new();
    for path in &paths {
        let rel = path.strip_prefix(&base).unwrap().display().to_string();
        for text in blocks(path) {
            total += 1;
            let p = robosim_cspm::parse(&text);
            assert_eq!(p.syntax_node().text().to_string(), text, "{rel}: not lossless");
            if let Some(e) = p.errors().first() {
                failures.push(format!("{rel}: {e} ({:?})", &text[e.range]));
                continue;
            }
            let m = Module::check(&text, &NoNames);
            if m.diagnostics().iter().any(|d| d.code == Code::Unresolved) {
                if std::env::var_os("CSPM_VERBOSE").is_some() {
                    for d in m.diagnostics().iter().filter(|d| d.code == Code::Unresolved) {
                        eprintln!("{rel}: {d} {:?}", &text[d.range]);
                    }
                }
                continue; // Uses the model's names: the bridge's business.
            }
            own += 1;
            if let Some(e) = m.diagnostics().iter().find(|d| d.severity == Severity::Error) {
                failures.push(format!("{rel}: {e} ({:?})", &text[e.range]));
                continue;
            }
            let text2 = text.clone();
            let r = std::thread::Builder::new()
                .stack_size(256 << 20)
                .spawn(move || {
                    let m = Module::check(&text2, &NoNames);
                    let limits = Limits { time: Duration::from_secs(5), ..Limits::default() };
                    let mut ev = Evaluator::new(&m, &NoNames, limits);
                    let mut procs = 0;
                    for n in m.defined_names() {
                        let v = ev.value(&n).map_err(|e| format!("{n}: {e}"))?;
                        if let Value::Proc(_) = v {
                            let l = ev.lts_of(&v).map_err(|e| format!("{n}: {e}"))?;
                            assert!(l.states() > 0);
                            procs += 1;
                        }
                    }
                    Ok::<usize, String>(procs)
                })
                .unwrap()
                .join()
                .unwrap_or_else(|_| Err("panicked".to_owned()));
            match r {
                Ok(n) => {
                    evaluated += 1;
                    processes += n;
                }
                Err(e) => failures.push(format!("{rel}: {e}")),
            }
        }
    }
    println!("{total} blocks parse; {own} use only their own names; {evaluated} of those evaluate ({processes} processes compiled)");
    assert!(total >= 50, "expected the corpus csp blocks, found {total}");
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
