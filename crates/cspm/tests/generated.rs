//! RoboTool's own generated CSPm for the Alpha Algorithm
//! (`../shared/reference/alpha-algorithm/csp-gen`, read in place, with its
//! `include`s): every top-level file checks without an error, the
//! operations' processes compile to LTSs, and `model_assertions.csp`, whose
//! csp blocks use RoboTool-1 names, reports exactly those as unresolved.

use std::path::{Path, PathBuf};

use robosim_cspm::{Code, Evaluator, Limits, Module, NoNames, Severity};

fn gen() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/alpha-algorithm/csp-gen")
}

fn check(path: &Path) -> Module {
    let dir = path.parent().unwrap().to_path_buf();
    let load = move |f: &str| std::fs::read(dir.join(f)).ok().map(|b| String::from_utf8_lossy(&b).into_owned());
    let text = String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned();
    Module::check_with_includes(&text, &NoNames, &load)
}

#[test]
fn top_level_files_check() {
    let mut checked = 0;
    for dir in ["", "timed"] {
        let mut files: Vec<_> = std::fs::read_dir(gen().join(dir))
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "csp"))
            .collect();
        files.sort();
        for f in files {
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            // Included by the others (its names come from them).
            if name == "instantiations.csp" || name == "model_assertions.csp" {
                continue;
            }
            let m = check(&f);
            let errors: Vec<_> = m.diagnostics().iter().filter(|d| d.severity == Severity::Error).collect();
            assert!(errors.is_empty(), "{}: {errors:?}", f.display());
            checked += 1;
        }
    }
    assert!(checked >= 38, "expected the generated files, found {checked}");
}

#[test]
fn robotool1_names_are_unresolved() {
    let m = check(&gen().join("model_assertions.csp"));
    let unresolved: std::collections::BTreeSet<_> =
        m.diagnostics().iter().filter(|d| d.code == Code::Unresolved).map(|d| d.message.clone()).collect();
    let expected = [
        "`AggregationSoftware_O` is not defined",
        "`AggregationSoftware_broadcast` is not defined",
        "`AggregationSoftware_obstacle` is not defined",
        "`AggregationSoftware_receive` is not defined",
        "`Position` is not defined",
        "`moveRet` is not defined",
    ];
    assert_eq!(unresolved.iter().map(String::as_str).collect::<Vec<_>>(), expected);
}

#[test]
fn operations_compile_to_ltss() {
    let r = std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(move || {
            let m = check(&gen().join("timed/pkg223_main_coreassertions.csp"));
            let limits = Limits { max_stack: 48 << 20, max_depth: 100_000, ..Limits::default() };
            let mut ev = Evaluator::new(&m, &NoNames, limits);
            ["P_pkg223_main_OP_tStop", "P_pkg223_main_OP_deadlineCheck"]
                .iter()
                .map(|p| ev.lts(p).map(|l| l.states()).map_err(|e| format!("{p}: {e}")))
                .collect::<Result<Vec<_>, _>>()
        })
        .unwrap()
        .join()
        .unwrap();
    let sizes = r.unwrap();
    assert!(sizes.iter().all(|&n| n > 10), "{sizes:?}");
}
