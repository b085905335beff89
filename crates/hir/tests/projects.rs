//! RoboTool resolves names per Eclipse project (robotool-facts, issue 17
//! item 6): two projects of one workspace may declare the same qualified
//! names, each file sees its own project's, and a package of another
//! project is not visible.

use robosim_hir::nav::{symbol_at, symbol_declaration};
use robosim_hir::{file_diagnostics, load_workspace, File, RootDatabase, RuleSet, Workspace};
use robosim_syntax::TextSize;
use salsa::Setter;

const TYPES_A: &str = "package p\ninterface I { event e }\n";
const TYPES_B: &str = "package p\ninterface I { event f : nat }\n";
const MACHINE: &str =
    "package q\nimport p::*\nstm M {\n  uses I\n  initial i\n  state S { }\n  transition t { from i to S }\n}\n";
const OTHER: &str =
    "package r\nimport p::*\nstm N {\n  uses I\n  initial i\n  state S { }\n  transition t { from i to S }\n}\n";

fn workspace(db: &mut RootDatabase, projects: &[&str]) -> (Workspace, Vec<File>) {
    let ws = load_workspace(
        db,
        [
            ("ws/a/types.rct".to_string(), TYPES_A.to_string()),
            ("ws/a/m.rct".to_string(), MACHINE.to_string()),
            ("ws/b/types.rct".to_string(), TYPES_B.to_string()),
            ("ws/b/m.rct".to_string(), MACHINE.to_string()),
            ("ws/c/n.rct".to_string(), OTHER.to_string()),
        ],
        RuleSet::Paper,
    );
    ws.set_projects(db).to(projects.iter().map(|p| p.to_string()).collect());
    let files = ws.files(db).iter().copied().filter(|f| !f.is_library(db)).collect();
    (ws, files)
}

fn codes(db: &RootDatabase, ws: Workspace, file: File) -> Vec<String> {
    file_diagnostics(db, ws, file).iter().map(|d| d.code.to_string()).collect()
}

#[test]
fn each_project_resolves_its_own_names() {
    let mut db = RootDatabase::default();
    let (ws, files) = workspace(&mut db, &["ws/a", "ws/b/", "ws/c"]);
    let (a_types, a_m, b_types, b_m, c_n) = (files[0], files[1], files[2], files[3], files[4]);
    // The same qualified names in two projects are no duplicates.
    for f in [a_types, a_m, b_types, b_m] {
        assert_eq!(codes(&db, ws, f), Vec::<String>::new(), "{}", f.path(&db));
    }
    // `uses I` in each project's machine means that project's interface.
    let at = TextSize::from(MACHINE.find("uses I").unwrap() as u32 + 5);
    for (m, types) in [(a_m, a_types), (b_m, b_types)] {
        let decl = symbol_declaration(&db, &symbol_at(&db, ws, m, at).expect("a symbol")).expect("resolved");
        assert_eq!(decl.file, types, "{}", m.path(&db));
    }
    // Project c holds no package `p`: its import and `uses I` do not
    // reach into the other projects.
    let d = file_diagnostics(&db, ws, c_n);
    let import = d.iter().find(|d| d.code == "RC-PKG-02").expect("the import of another project's package");
    assert_eq!(&OTHER[import.range], "p");
    assert_eq!(
        import.message,
        "`import p::*` matches no package or element of this file's project: `p` is in the project at `ws/a`, and RoboTool resolves names within a project"
    );
    assert!(d.iter().any(|d| d.code == "LNK-03" && &OTHER[d.range] == "I"), "{d:?}");
}

#[test]
fn without_projects_the_workspace_is_one_scope() {
    let mut db = RootDatabase::default();
    let (ws, files) = workspace(&mut db, &[]);
    // Today's reading when no `.project` is found: every file sees every
    // other, so the second declarations of `p::I` and `q::M` clash.
    assert!(codes(&db, ws, files[2]).iter().any(|c| c == "RC-PKG-01"), "{:?}", codes(&db, ws, files[2]));
    assert!(codes(&db, ws, files[3]).iter().any(|c| c == "RC-PKG-01"));
    assert!(!codes(&db, ws, files[4]).iter().any(|c| c == "LNK-01"));
}
