//! RT-7: each assertion file's script has its own instantiations. A file
//! whose `csp` blocks set nothing includes the generated defaults
//! (`instantiations.csp`); a file whose blocks set core types or constant
//! values has them in its own script, which then does not include
//! `instantiations.csp` (as RoboTool's script of a file with an
//! `Instantiations` block, `reference/alpha-algorithm/csp-gen/timed/
//! model_assertions.csp`, includes none). The engine's fixtures
//! `rt07_instantiations_per_file` and `rt07_constants_per_file` state the
//! verdicts; `export_semantics.rs` compares them with the export's.

use std::collections::HashMap;
use std::path::Path;

use robosim_cspm::{Module, NoNames, Severity};
use robosim_semantics::{export_workspace, Export, Options, Profile};

fn export_fixture(name: &str) -> Export {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify").join(name);
    let files = robosim_test_support::inputs::read_model_files(&dir);
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile: Profile::RoboTool3 })
}

/// The script `name` of `files`, checked with its includes: no errors.
fn checked(files: &[robosim_semantics::OutFile], name: &str) -> String {
    let texts: HashMap<String, String> = files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |n: &str| texts.get(n).cloned();
    let script = texts.get(name).unwrap_or_else(|| panic!("no {name} in {:?}", texts.keys()));
    let m = Module::check_with_includes(script, &NoNames, &load);
    let errors: Vec<String> =
        m.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{d:?}")).collect();
    assert!(errors.is_empty(), "{name}: {errors:#?}");
    script.clone()
}

#[test]
fn a_block_s_core_types_hold_in_its_own_script_only() {
    let e = export_fixture("rt07_instantiations_per_file");
    for files in [&e.files, &e.untimed] {
        let inst = files.iter().find(|f| f.name == "instantiations.csp").expect("instantiations.csp").text();
        assert!(inst.contains("nametype core_nat = {0..2}\n"), "{inst}");
        let default = checked(files, "default_assertions.csp");
        assert!(default.contains("include \"instantiations.csp\"\n"), "{default}");
        assert!(!default.contains("nametype core_nat"), "{default}");
        let wide = checked(files, "wide_assertions.csp");
        assert!(!wide.contains("include \"instantiations.csp\""), "{wide}");
        assert!(wide.contains("nametype core_nat = {0..3}\n"), "{wide}");
        // The block's line, defined by the script's instantiations instead.
        assert!(wide.contains("-- (in this script's instantiations or robosim_defs.csp) nametype core_nat"), "{wide}");
    }
}

#[test]
fn a_block_s_constant_values_hold_in_its_own_script_only() {
    let e = export_fixture("rt07_constants_per_file");
    let inst = e.files.iter().find(|f| f.name == "instantiations.csp").expect("instantiations.csp").text();
    assert!(inst.contains("\nconst_M_k = 0\n"), "{inst}");
    let default = checked(&e.files, "default_assertions.csp");
    assert!(default.contains("include \"instantiations.csp\"\n"), "{default}");
    assert!(!default.contains("const_M_k ="), "{default}");
    let set = checked(&e.files, "set_assertions.csp");
    assert!(!set.contains("include \"instantiations.csp\""), "{set}");
    assert!(set.contains("\nconst_M_k = 1\n"), "{set}");
    assert!(set.contains("-- (set in this script's instantiations) const_M_k = 1"), "{set}");
}

/// A block defining a name of RoboTool's library again (`OneStep`, which
/// RoboTool's timed script includes from core_timed_defs.csp whatever the
/// blocks say) makes FDR stop on RoboTool's script: the export copies the
/// line as written, so FDR stops on its script too, and says why in a
/// warning (leaving the line out would check another specification). The
/// engine's fixture `csp_bridge_errors_a_block_redefining_a_library_name`
/// reports the same error.
#[test]
fn a_block_redefining_a_library_name_is_copied_and_fdr_s_error_reported() {
    let e = export_fixture("csp_bridge_errors_a_block_redefining_a_library_name");
    let warning = e
        .warnings
        .iter()
        .find(|w| w.message.contains("`OneStep` is defined by RoboTool's library"))
        .unwrap_or_else(|| panic!("{:#?}", e.warnings));
    assert!(warning.message.contains("FDR stops on the script of this file"), "{}", warning.message);
    assert!(warning.path.ends_with("a.assertions"), "{}", warning.path);
    assert_eq!((warning.line, warning.col), (9, 1));
    let texts: HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let script = &texts["a_assertions.csp"];
    assert!(script.contains("\nOneStep(_) = 1\n"), "{script}");
    let load = |n: &str| texts.get(n).cloned();
    let m = Module::check_with_includes(script, &NoNames, &load);
    let errors: Vec<String> =
        m.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| d.message.clone()).collect();
    assert!(errors.iter().any(|m| m.contains("`OneStep` is defined more than once")), "{errors:#?}");
}
