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
    let mut db = RootDatabase::default();
    let ws = load_workspace(
        &mut db,
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

/// `symbol_at` resolves behaviour only around the offset; at every offset
/// of every example and corpus model it must find what resolving the whole
/// file finds.
#[test]
fn symbol_at_agrees_with_whole_file_resolution() {
    use robosim_hir::defs::file_defs;
    use robosim_hir::nav::references_in;
    use robosim_syntax::TextRange;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut projects: Vec<std::path::PathBuf> = vec![root.join("examples/paper"), root.join("examples/lawnmower")];
    let corpus = root.join("../shared/corpus");
    let mut stack = vec![corpus];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            if e.path().is_dir() {
                stack.push(e.path());
                projects.push(e.path());
            }
        }
    }
    let mut checked = 0usize;
    for dir in projects {
        let files: Vec<(String, String)> = std::fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path())
            .filter(|p| robosim_syntax::FileKind::from_path(p).is_some_and(|k| !k.is_assertions()))
            .map(|p| (p.display().to_string(), std::fs::read_to_string(&p).unwrap_or_default()))
            .collect();
        if files.is_empty() {
            continue;
        }
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, files, RuleSet::Paper);
        for &file in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
            let all = references_in(&db, ws, file);
            let len = file.text(&db).len() as u32;
            for o in 0..=len {
                let offset = TextSize::from(o);
                let hit = |r: TextRange| r.contains_inclusive(offset);
                let expected = all.iter().filter(|r| hit(r.range)).min_by_key(|r| r.range.len()).cloned();
                let sym = symbol_at(&db, ws, file, offset);
                let got = match &sym {
                    Some(Symbol::Reference(r)) => Some(r.clone()),
                    _ => None,
                };
                assert_eq!(got, expected, "{} at {o}", file.path(&db));
                checked += usize::from(got.is_some());
                // Declarations (read from the element around the offset,
                // or the declaring one) at the file's positions.
                let defs = file_defs(&db, file);
                let declared = defs
                    .iter()
                    .filter(|(_, d)| !d.name.is_empty() && hit(d.name_range))
                    .min_by_key(|(_, d)| d.name_range.len())
                    .map(|(id, _)| id);
                match &sym {
                    Some(Symbol::Declaration(d)) => assert_eq!(Some(d.def), declared, "{} at {o}", file.path(&db)),
                    _ => assert!(got.is_some() || declared.is_none(), "{} at {o}: no declaration", file.path(&db)),
                }
                if let Some(d) = sym.as_ref().and_then(|s| symbol_declaration(&db, s)) {
                    let want = file_defs(&db, d.file).def(d.def);
                    assert_eq!(
                        (d.name_range, d.full_range),
                        (want.name_range, want.range),
                        "{} at {o}",
                        file.path(&db)
                    );
                }
            }
        }
    }
    assert!(checked > 10_000, "only {checked} offsets with a reference");
}
