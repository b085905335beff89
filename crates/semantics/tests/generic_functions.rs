//! Functions whose signatures use generic types (`?X`). A CSPm function is
//! untyped, so RoboTool's definition of one without a body is its result
//! type's default whatever the arguments (RT-2: `g_same(a, b) = true`),
//! and a call passes each argument at its own type. Where a generic
//! type's values are needed — the default of a generic result, a
//! definition over generic types — the export refuses, with the reason
//! the native checker gives (`hir::model::Function::generic_refusal`).
//! The engine's fixtures `functions_generic_parameters_without_a_body` and
//! `functions_generic_result_or_definition_refused` state the verdicts,
//! which `export_semantics.rs` compares with the export's.

use std::path::Path;

use robosim_semantics::Export;

mod support;
use support::{eval, export_files, file_text, load};

/// The export of the engine's fixture `name`.
fn export_fixture(name: &str) -> Export {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify").join(name);
    export_files(robosim_test_support::inputs::read_model_files(&dir))
}

#[test]
fn generic_parameters_give_robotool_s_untyped_defaults() {
    let e = export_fixture("functions_generic_parameters_without_a_body");
    assert!(e.warnings.is_empty(), "{:#?}", e.warnings);
    for files in [&e.files, &e.untimed] {
        let inst = file_text(files, "instantiations.csp");
        for line in [
            "\n-- function g::same (g.rct:7:1): no body, its result type's default (RT-2)\ng_same(a, b) = true\n",
            "\ng_differ(a, b) = true\n",
            "\ng_count(s) = 0\n",
            "\ng_shift(m, k) = g_Mode_Idle\n",
        ] {
            assert!(inst.contains(line), "{line:?} in {inst}");
        }
        // The machine passes each argument at its own type: tuples of
        // numbers, of an enumeration literal, a set.
        let model = file_text(files, "g.csp");
        for call in [
            "set_ok!g_differ(x, true) ->",
            "set_n!g_count({x, 2}) ->",
            "set_m!g_shift((g_Mode_Busy, x), 1) ->",
            "[] g_same((x, 1), (2, 0)) & internal__.TID_a -> Memory__(x, ok, n, m)",
        ] {
            assert!(model.contains(call), "{call:?} in {model}");
        }
        let (m, errors) = load(files, "a_assertions.csp");
        assert!(errors.is_empty(), "{errors:#?}");
        // One definition for every instantiation of `?X`.
        assert_eq!(eval(&m, "g_same((1, 1), (2, 0))"), "true");
        assert_eq!(eval(&m, "g_same((g_Mode_Idle, 1), (g_Mode_Busy, 0))"), "true");
        assert_eq!(eval(&m, "g_differ(1, true)"), "true");
        assert_eq!(eval(&m, "g_count({1, 2})"), "0");
        assert_eq!(eval(&m, "g_shift((g_Mode_Busy, 1), 1)"), "g_Mode_Idle");
    }
}

#[test]
fn a_generic_result_or_a_definition_over_generic_types_is_refused() {
    let e = export_fixture("functions_generic_result_or_definition_refused");
    let why = |f: &str| {
        let w = e.warnings.iter().find(|w| w.message.contains(&format!("the function `{f}`")));
        w.unwrap_or_else(|| panic!("no warning about {f}: {:#?}", e.warnings)).clone()
    };
    let pick = why("pick");
    assert!(pick.path.ends_with("h.rct") && (pick.line, pick.col) == (11, 41), "{pick:?}");
    assert!(
        pick.message.ends_with(
            "the function `pick` has no body and its result type `?X` is generic: its default (RT-2) depends on the \
             type `?X` stands for in each call, which RoboTool's CSPm does not establish; calls of it are not \
             supported yet"
        ),
        "{pick:?}"
    );
    let first = why("first");
    assert!(first.path.ends_with("h.rct") && (first.line, first.col) == (16, 40), "{first:?}");
    assert!(
        first.message.ends_with(
            "the function `first` is defined by its postconditions and the parameter `p` has the generic type \
             `?X * nat`: calls of a function defined over generic types are not supported yet"
        ),
        "{first:?}"
    );
    for a in ["P1", "Q1"] {
        assert!(e.warnings.iter().any(|w| w.message.starts_with(&format!("assertion {a} is not exported"))), "{a}");
    }
    assert!(!file_text(&e.files, "instantiations.csp").contains("h_pick"));
    assert!(!file_text(&e.files, "h.csp").contains("h_first("));
}

#[test]
fn a_type_the_export_does_not_support_is_named_as_written() {
    // A part of a product: the message shows the type as written, not
    // the model's data structure.
    let model = "interface I { event e }\n\
                 stm M { uses I var v : nat * (nat <-> nat) initial i state S { } transition t { from i to S action e } }\n";
    let e = export_files(vec![
        ("m.rct".into(), model.into()),
        ("a.assertions".into(), "assertion D : M is deadlock-free\n".into()),
    ]);
    let w = e.warnings.iter().find(|w| w.message.contains("is not exported: `v`"));
    let w = w.unwrap_or_else(|| panic!("{:#?}", e.warnings));
    assert!(
        w.message.ends_with(
            "`v`: the type `nat <-> nat` is not supported by the export yet (booleans, numbers, enumerations, \
             primitive types, records, products, sets and sequences are)"
        ),
        "{w:?}"
    );
}
