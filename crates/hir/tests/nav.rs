//! Navigation: definition, references and descriptions across files.

use robosim_hir::nav::{describe, find_references, symbol_at, symbol_declaration, Symbol};
use robosim_hir::{load_workspace, RootDatabase, RuleSet};
use robosim_syntax::TextSize;

const TYPES: &str = "package lib\n// The obstacle sensor.\n// Fires once per obstacle.\ninterface Sensors {\n  // Distance to the obstacle, in cm.\n  event obstacle : nat\n}\n";
const MACHINE: &str = "package app\nimport lib::*\nstm M {\n  uses Sensors\n  var d : nat\n  initial i\n  state S { }\n  transition t { from i to S }\n  transition u { from S to S trigger obstacle?d condition d > 3 }\n}\n";

fn offset_of(text: &str, needle: &str, nth: usize) -> TextSize {
    let mut start = 0;
    for _ in 0..nth {
        start += text[start..].find(needle).unwrap() + 1;
    }
    TextSize::from((start + text[start..].find(needle).unwrap() + 1) as u32)
}

#[test]
fn definition_references_and_hover_across_files() {
    let db = RootDatabase::default();
    let ws = load_workspace(
        &db,
        [("types.rct".into(), TYPES.into()), ("machine.rct".into(), MACHINE.into())],
        RuleSet::Paper,
    );
    let files: Vec<_> = ws.files(&db).iter().copied().filter(|f| !f.is_library(&db)).collect();
    let (types, machine) = (files[0], files[1]);

    // Go to definition of `obstacle` in the trigger.
    let sym = symbol_at(&db, ws, machine, offset_of(MACHINE, "obstacle", 0)).expect("a symbol");
    assert!(matches!(sym, Symbol::Reference(_)));
    let decl = symbol_declaration(&db, &sym).expect("resolved");
    assert_eq!(decl.file, types);
    assert_eq!(&TYPES[decl.name_range], "obstacle");

    // Hover text: signature, container and the comment above.
    let d = describe(&db, decl);
    assert_eq!(d.signature, "event obstacle : nat");
    assert_eq!(d.container.as_deref(), Some("in interface `Sensors`"));
    assert_eq!(d.doc.as_deref(), Some("Distance to the obstacle, in cm."));

    // References to the variable `d`: the input binding and the condition.
    let var = symbol_declaration(&db, &symbol_at(&db, ws, machine, offset_of(MACHINE, "d :", 0)).unwrap()).unwrap();
    let refs = find_references(&db, ws, var);
    let texts: Vec<&str> = refs.iter().map(|(_, r)| &MACHINE[*r]).collect();
    assert_eq!(texts, ["d", "d"], "{refs:?}");

    // The interface's doc comment spans two lines.
    let iface =
        symbol_declaration(&db, &symbol_at(&db, ws, machine, offset_of(MACHINE, "Sensors", 0)).unwrap()).unwrap();
    assert_eq!(describe(&db, iface).doc.as_deref(), Some("The obstacle sensor.\nFires once per obstacle."));
}
