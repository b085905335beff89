//! RT-2: a function declared without a body (or with pre- and
//! postconditions but no `result == e`) returns its result type's default
//! — 0, `true`, the first literal, the empty set, component-wise for
//! tuples — which RoboTool writes into the generated instantiations under
//! its CSPm name, the package's name first (the reference's
//! `instantiations.csp`: `Mathematics_random() = 0`). RT-7: a `csp` block
//! of an assertion file defining that name replaces the default in that
//! file's script; a block named `Instantiations` replaces the generated
//! defaults, so a function it does not define has no definition there.
//! The exported scripts load and evaluate with robosim-cspm; the engine's
//! fixture `export_rt02_bodiless_functions_of_a_package` states the
//! verdicts, which `export_semantics.rs` compares with the export's.

use std::path::Path;

use robosim_semantics::Export;

mod support;
use support::{eval, export_files, file_text, load};

const FIXTURE: &str = "export_rt02_bodiless_functions_of_a_package";

/// The fixture's files, with `extra` assertion files beside them.
fn export_with(extra: &[(&str, &str)]) -> Export {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify").join(FIXTURE);
    let mut paths = Vec::new();
    robosim_test_support::inputs::model_files(&dir, &mut paths);
    let mut files: Vec<(String, String)> =
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).expect("a model file"))).collect();
    files.extend(extra.iter().map(|(n, t)| (n.to_string(), t.to_string())));
    export_files(files)
}

#[test]
fn the_generated_instantiations_define_the_defaults_by_robotool_s_names() {
    let e = export_with(&[]);
    assert!(e.warnings.is_empty(), "{:#?}", e.warnings);
    for files in [&e.files, &e.untimed] {
        let inst = file_text(files, "instantiations.csp");
        for line in
            ["\np_random() = 0\n", "\np_pick(x) = p_Mode_Idle\n", "\np_flag() = true\n", "\np_origin() = (0, 0)\n"]
        {
            assert!(inst.contains(line), "{line:?} in {inst}");
        }
        // The machine calls them by those names.
        let model = file_text(files, "m.csp");
        assert!(model.contains("p_random() == 0") && model.contains("p_pick(1) == p_Mode_Busy"), "{model}");
        let (m, errors) = load(files, "a_assertions.csp");
        assert!(errors.is_empty(), "{errors:#?}");
        assert_eq!(eval(&m, "p_random()"), "0");
        assert_eq!(eval(&m, "p_pick(1)"), "p_Mode_Idle");
        // `postcondition not result` does not change RoboTool's default.
        assert_eq!(eval(&m, "p_flag()"), "true");
        assert_eq!(eval(&m, "p_origin()"), "(0, 0)");
    }
}

#[test]
fn a_block_defining_robotool_s_name_replaces_the_default_in_its_file_only() {
    let b = "import p::*\ncsp Defs csp-begin\np_random() = 1\ncsp-end\nassertion R : M::R is reachable in M\n";
    let e = export_with(&[("b.assertions", b)]);
    assert!(e.warnings.is_empty(), "{:#?}", e.warnings);
    for files in [&e.files, &e.untimed] {
        let (m, errors) = load(files, "b_assertions.csp");
        assert!(errors.is_empty(), "{errors:#?}");
        let script = file_text(files, "b_assertions.csp");
        // Its own instantiations, without the default of `p_random`.
        assert!(!script.contains("include \"instantiations.csp\""), "{script}");
        assert!(!script.contains("p_random() = 0"), "{script}");
        assert!(script.contains("-- function p::random (m.rct:9:1): no body, its result type's default (RT-2): defined by a `csp` block of this assertion file"), "{script}");
        assert!(script.contains("\np_random() = 1\n"), "{script}");
        assert_eq!(eval(&m, "p_random()"), "1");
        assert_eq!(eval(&m, "p_flag()"), "true");
        // The other file keeps the generated default.
        let (m, errors) = load(files, "a_assertions.csp");
        assert!(errors.is_empty(), "{errors:#?}");
        assert_eq!(eval(&m, "p_random()"), "0");
    }
}

#[test]
fn an_instantiations_block_leaves_what_it_does_not_define_undefined() {
    // RoboTool's script of this file has no `p_pick`, `p_flag`,
    // `p_origin`: FDR stops on `M`, which calls them. The export refuses the
    // assertions about `M` (as the native checker does); the script loads.
    let c = "import p::*\ncsp Instantiations csp-begin\np_random() = 2\ncsp-end\n\
             assertion R : M::R is reachable in M\n";
    let e = export_with(&[("c.assertions", c)]);
    for f in ["p_pick", "p_flag", "p_origin"] {
        let w = e.warnings.iter().find(|w| w.message.contains(&format!("does not define `{f}`")));
        let w = w.unwrap_or_else(|| panic!("no warning about {f}: {:#?}", e.warnings));
        assert!(w.path.ends_with("c.assertions") && w.line == 2 && w.col == 1, "{w:?}");
        assert!(w.message.contains("FDR stops on the undefined name") && w.message.contains("RT-7"), "{w:?}");
    }
    assert!(!e.warnings.iter().any(|w| w.message.contains("define `p_random`")), "{:#?}", e.warnings);
    let r = e.warnings.iter().find(|w| w.message.starts_with("assertion R is not exported: "));
    let r = r.unwrap_or_else(|| panic!("{:#?}", e.warnings));
    assert!(r.message.contains("`M::R` calls `p_flag`") || r.message.contains("`M` calls `p_flag`"), "{r:?}");
    for files in [&e.files, &e.untimed] {
        let script = file_text(files, "c_assertions.csp");
        assert!(!script.contains("include \"instantiations.csp\""), "{script}");
        assert!(
            script.contains("(RT-2): NOT IN ROBOTOOL'S SCRIPT: this assertion file's `csp Instantiations` block"),
            "{script}"
        );
        assert!(script.contains("NOT EXPORTED: `M"), "{script}");
        let (m, errors) = load(files, "c_assertions.csp");
        assert!(errors.is_empty(), "{errors:#?}");
        assert_eq!(eval(&m, "p_random()"), "2");
    }
}

#[test]
fn a_block_defining_the_bare_name_of_a_package_s_function_is_not_used() {
    let d = "import p::*\ncsp Defs csp-begin\nrandom() = 1\ncsp-end\nassertion R : M::R is reachable in M\n";
    let e = export_with(&[("d.assertions", d)]);
    let [w] = e.warnings.as_slice() else { panic!("{:#?}", e.warnings) };
    assert!(w.path.ends_with("d.assertions") && w.line == 3, "{w:?}");
    assert!(
        w.message.starts_with("this defines `random`, but RoboTool's CSPm calls the model's function `p_random`"),
        "{w:?}"
    );
    let (m, errors) = load(&e.files, "d_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
    // The block's `random` is copied, and the calls keep the default.
    assert_eq!(eval(&m, "random()"), "1");
    assert_eq!(eval(&m, "p_random()"), "0");
}

#[test]
fn functions_of_no_arguments_and_of_the_default_package() {
    let model = "interface I { event e }\n\
        function two() : nat { postcondition result == 2 }\n\
        function none() : Set(nat) { }\n\
        function scale(x : nat) : nat { precondition x > 0 postcondition result in {1, 2} }\n\
        stm M { uses I initial i state S { } transition t { from i to S condition two() == 2 action e } }\n";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("a.assertions".into(), "assertion D : M is deadlock-free\n".into()),
    ]);
    assert!(e.warnings.is_empty(), "{:#?}", e.warnings);
    let inst = file_text(&e.files, "instantiations.csp");
    assert!(inst.contains("\nnone() = {}\n") && inst.contains("\nscale(x) = 0\n"), "{inst}");
    // A function defined by `result == e` stays RoboTool's `f() = e`, in
    // the model's file.
    assert!(file_text(&e.files, "m.csp").contains("\ntwo() = 2\n"), "{}", file_text(&e.files, "m.csp"));
    let (m, errors) = load(&e.files, "a_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(eval(&m, "two()"), "2");
    assert_eq!(eval(&m, "none()"), "{}");
    assert_eq!(eval(&m, "scale(2)"), "0");
}

#[test]
fn a_definition_beyond_what_hir_reads_replaces_the_default_too() {
    // RoboTool copies the block whole: `let … within` is CSPm all the same.
    let b = "import p::*\ncsp Defs csp-begin\np_pick(x) = let y = p_Mode_Busy within y\ncsp-end\n\
             assertion P : M::P is reachable in M\n";
    let e = export_with(&[("b.assertions", b)]);
    assert!(e.warnings.is_empty(), "{:#?}", e.warnings);
    let (m, errors) = load(&e.files, "b_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(eval(&m, "p_pick(1)"), "p_Mode_Busy");
    assert_eq!(eval(&m, "p_random()"), "0");
}

#[test]
fn the_values_a_block_gives_widen_its_script_s_types() {
    // RT-5: RoboTool's types cover the values of the model's expressions,
    // `random()` among them, evaluated with the script's definitions.
    let model = "package p\nfunction random() : real { }\ninterface I { event e }\n\
                 stm M { uses I var x : real initial i state S { }\n\
                 transition t { from i to S action x = random() ; e } }\n";
    let b = "import p::*\ncsp Defs csp-begin\np_random() = 5\ncsp-end\nassertion D : M is deadlock-free\n";
    let d = "import p::*\ncsp Defs csp-begin\nrandom() = 5\ncsp-end\nassertion D : M is deadlock-free\n";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("b.assertions".into(), b.into()),
        ("d.assertions".into(), d.into()),
    ]);
    let script = file_text(&e.files, "b_assertions.csp");
    assert!(script.contains("\nnametype core_real = { -2..5}\n"), "{script}");
    let (m, errors) = load(&e.files, "b_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(eval(&m, "p_random()"), "5");
    // `random` is not what the model calls: no widening, the shared types.
    let script = file_text(&e.files, "d_assertions.csp");
    assert!(script.contains("include \"instantiations.csp\""), "{script}");
    assert!(file_text(&e.files, "instantiations.csp").contains("\nnametype core_real = { -2..2}\n"));
}

#[test]
fn a_function_named_as_a_cspm_builtin_is_refused() {
    // RoboTool would write `card(s) = 0` beside CSPm's own `card`.
    let model = "interface I { event e }\nfunction card(x : nat) : nat { }\n\
                 stm M { uses I initial i state S { } transition t { from i to S condition card(1) == 0 action e } }\n";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("a.assertions".into(), "assertion D : M is deadlock-free\n".into()),
    ]);
    let w = e.warnings.iter().find(|w| w.message.contains("reserved in CSPm"));
    let w = w.unwrap_or_else(|| panic!("{:#?}", e.warnings));
    assert!(w.message.contains("RoboTool's CSPm name `card` of the function `card` is reserved in CSPm"), "{w:?}");
    assert!(!file_text(&e.files, "instantiations.csp").contains("card"));
}

#[test]
fn a_function_returning_a_primitive_type_is_refused() {
    // RT-2 gives no default for a primitive type (`type ID`).
    let model = "type ID\ninterface I { event e }\nfunction who() : ID { }\nfunction pair() : nat * ID { }\n\
                 stm M { uses I var x : ID initial i state S { } transition t { from i to S action x = who() ; e } }\n\
                 stm N { uses I var y : nat * ID initial i state S { } transition t { from i to S action y = pair() ; e } }\n";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("a.assertions".into(), "assertion D : M is deadlock-free\n".into()),
    ]);
    for f in ["who", "pair"] {
        let w = e.warnings.iter().find(|w| w.message.contains(&format!("the function `{f}` has no body")));
        let w = w.unwrap_or_else(|| panic!("{f}: {:#?}", e.warnings));
        assert!(
            w.message.contains("the primitive type `ID`, whose default in RoboTool's CSPm is not established"),
            "{w:?}"
        );
    }
    assert!(!file_text(&e.files, "instantiations.csp").contains("who"));
}

#[test]
fn a_call_through_a_defined_function_counts_too() {
    // `twice` is RoboTool's `p_twice(x) = p_scale(x) + p_scale(x)`: a
    // machine calling it calls `p_scale`, which the block leaves undefined.
    let model = "package p\ninterface I { event e }\nfunction scale(x : nat) : nat { }\n\
                 function twice(x : nat) : nat { postcondition result == scale(x) + scale(x) }\n\
                 stm M { uses I initial i state S { } transition t { from i to S condition twice(1) == 0 action e } }\n";
    let a = "import p::*\ncsp Instantiations csp-begin\nnametype core_nat = {0..3}\ncsp-end\n\
             assertion D : M is deadlock-free\n";
    let e = export_files(vec![("m.rct".into(), model.into()), ("a.assertions".into(), a.into())]);
    let w = e.warnings.iter().find(|w| w.message.starts_with("assertion D is not exported: "));
    let w = w.unwrap_or_else(|| panic!("{:#?}", e.warnings));
    assert!(w.message.contains("`M` calls `p_scale`"), "{w:?}");
    assert!(file_text(&e.files, "m.csp").contains("p_twice(x) ="), "{}", file_text(&e.files, "m.csp"));
}
