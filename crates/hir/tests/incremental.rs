//! Incrementality, read from salsa's event log: editing inside one machine
//! re-executes the queries of that file only; other files' results are
//! reused (their inputs from the edited file, its position-free summary,
//! did not change).

use std::sync::{Arc, Mutex};

use robosim_hir::{file_diagnostics, load_workspace, File, RootDatabase, RuleSet};

const TYPES: &str = "package lib\ninterface Moves { move(v : real) }\ninterface Sensors { event obstacle }\n";
const MACHINE: &str = "package app\nimport lib::*\nstm M {\n  requires Moves uses Sensors\n  var speed : real = 1.0\n  initial i\n  state S { entry move(speed) }\n  transition t { from i to S }\n  transition u { from S to S trigger obstacle action speed = speed + 1 }\n}\n";
const CONTROLLER: &str = "package app\nimport lib::*\ncontroller C { requires Moves uses Sensors sref m = M connection C on obstacle to m on obstacle }\n";

fn executions(log: &Mutex<Vec<String>>) -> Vec<String> {
    std::mem::take(&mut *log.lock().unwrap())
}

fn count(log: &[String], query: &str) -> usize {
    log.iter().filter(|e| e.contains(&format!("{query}("))).count()
}

#[test]
fn editing_a_machine_body_reuses_other_files() {
    let log = Arc::new(Mutex::new(Vec::new()));
    let sink = log.clone();
    let mut db = RootDatabase::with_event_log(move |e| {
        if let salsa::EventKind::WillExecute { database_key } = e.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    });
    let ws = load_workspace(
        &mut db,
        [
            ("types.rct".to_string(), TYPES.to_string()),
            ("machine.rct".to_string(), MACHINE.to_string()),
            ("controller.rct".to_string(), CONTROLLER.to_string()),
        ],
        RuleSet::Paper,
    );
    let user: Vec<File> = ws.files(&db).iter().copied().filter(|f| !f.is_library(&db)).collect();
    let check_all = |db: &RootDatabase| -> usize { user.iter().map(|f| file_diagnostics(db, ws, *f).len()).sum() };
    assert_eq!(check_all(&db), 0, "the workspace is well formed");
    let first = executions(&log);
    assert_eq!(count(&first, "file_diagnostics"), 3, "{first:?}");

    // Nothing changed: nothing re-executes.
    check_all(&db);
    assert!(executions(&log).is_empty());

    // Edit an action inside the machine (the statement, not a declaration).
    let machine = user[1];
    assert_eq!(machine.path(&db), "machine.rct");
    // The first edit of the machine lowers its input's durability, and
    // salsa does not backdate results that became less durable: what reads
    // the machine runs once more then (see `hir::element::Element`).
    let warm = MACHINE.replace("speed = speed + 1", "speed = speed + 2");
    robosim_hir::set_text(&mut db, machine, warm, None, robosim_hir::Durability::LOW);
    assert_eq!(check_all(&db), 0);
    executions(&log);
    let edited = MACHINE.replace("speed = speed + 1", "speed = speed * 2 + 1");
    robosim_hir::set_text(&mut db, machine, edited, None, robosim_hir::Durability::LOW);
    assert_eq!(check_all(&db), 0);
    let after = executions(&log);
    // The edited file is re-parsed and re-checked…
    assert_eq!(count(&after, "parse"), 1, "{after:?}");
    // (The file's definitions are not even put together: everything
    // reads the elements'.)
    assert_eq!(count(&after, "file_defs"), 0, "{after:?}");
    assert_eq!(count(&after, "file_diagnostics"), 1, "{after:?}");
    // …the machine's summary is recomputed but equal (so the file's is not
    // even recomputed), and the other files' checks are reused: one
    // execution each of the per-file queries, not three.
    assert_eq!(count(&after, "element_summary"), 1, "{after:?}");
    assert_eq!(count(&after, "file_summary"), 0, "{after:?}");
    // The rules run per element: the machine's only (the controller in
    // the other file reads the machine's position-free usage, equal).
    assert_eq!(count(&after, "element_rules"), 1, "{after:?}");
    assert_eq!(count(&after, "element_cycles"), 1, "{after:?}");
    // Resolution and typing run per element: the machine's only, and the
    // whole file's behaviour is not resolved at all.
    assert_eq!(count(&after, "element_problems"), 1, "{after:?}");
    assert_eq!(count(&after, "body_resolution"), 0, "{after:?}");
    assert_eq!(count(&after, "workspace_index"), 0, "{after:?}");

    // Adding a declaration changes the summary: dependants re-run.
    let declared = MACHINE.replace("var speed : real = 1.0", "var speed : real = 1.0\n  var extra : nat");
    robosim_hir::set_text(&mut db, machine, declared, None, robosim_hir::Durability::LOW);
    check_all(&db);
    let after = executions(&log);
    assert_eq!(count(&after, "workspace_index"), 1, "{after:?}");
}

#[test]
fn a_file_with_a_prior_parse_reparses_only_the_edited_member() {
    use robosim_hir::{parse, Prior};
    let text = format!("{MACHINE}stm Other {{ initial j }}\n");
    let db = &mut RootDatabase::default();
    let ws = load_workspace(db, [("machine.rct".to_string(), text.clone())], RuleSet::Paper);
    let file = *ws.files(db).iter().find(|f| !f.is_library(db)).unwrap();
    let old = parse(db, file).clone();
    let edited = text.replace("speed + 1", "speed + 2");
    let prior = Some(Prior { text: text.as_str().into(), parse: old.clone() });
    robosim_hir::set_text(db, file, edited.clone(), prior, robosim_hir::Durability::LOW);
    let new = parse(db, file).clone();
    assert_eq!(new, robosim_syntax::parse(&edited, robosim_syntax::FileKind::RoboChart));
    // The machine after the edited one is the very same green node: only
    // `M` was parsed again.
    let last = |p: &robosim_syntax::Parse| {
        let node = p.syntax_node().last_child().unwrap();
        let green = node.green();
        green as *const _ as usize
    };
    assert_eq!(last(&old), last(&new), "`Other` was parsed again");
    // A prior that does not match the text is still only a hint.
    let prior = Some(Prior {
        text: "stm Z {}".into(),
        parse: robosim_syntax::parse("stm Z {}", robosim_syntax::FileKind::RoboChart),
    });
    robosim_hir::set_text(db, file, text.clone(), prior, robosim_hir::Durability::LOW);
    assert_eq!(*parse(db, file), robosim_syntax::parse(&text, robosim_syntax::FileKind::RoboChart));
}

#[test]
fn editing_a_machine_body_reuses_the_names_of_assertion_files() {
    let log = Arc::new(Mutex::new(Vec::new()));
    let sink = log.clone();
    let mut db = RootDatabase::with_event_log(move |e| {
        if let salsa::EventKind::WillExecute { database_key } = e.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    });
    let assertions =
        "import app::*\nimport lib::*\nassertion A : M is deadlock-free\nassertion B : Nothing is deadlock-free\n";
    let ws = load_workspace(
        &mut db,
        [
            ("types.rct".to_string(), TYPES.to_string()),
            ("machine.rct".to_string(), MACHINE.to_string()),
            ("a.assertions".to_string(), assertions.to_string()),
        ],
        RuleSet::Paper,
    );
    let user: Vec<File> = ws.files(&db).iter().copied().filter(|f| !f.is_library(&db)).collect();
    let lnk = |db: &RootDatabase| -> Vec<String> {
        user.iter().flat_map(|f| file_diagnostics(db, ws, *f)).map(|d| format!("{} {}", d.code, d.message)).collect()
    };
    let first = lnk(&db);
    assert_eq!(first.len(), 1, "{first:?}");
    assert!(first[0].starts_with("LNK-01 cannot resolve `Nothing`"), "{first:?}");
    let machine = user[1];
    assert_eq!(machine.path(&db), "machine.rct");
    // As above: the first edit lowers the durability.
    let warm = MACHINE.replace("speed = speed + 1", "speed = speed + 2");
    robosim_hir::set_text(&mut db, machine, warm, None, robosim_hir::Durability::LOW);
    lnk(&db);
    executions(&log);
    let edited = MACHINE.replace("speed = speed + 1", "speed = speed * 2 + 1");
    robosim_hir::set_text(&mut db, machine, edited, None, robosim_hir::Durability::LOW);
    assert_eq!(lnk(&db), first);
    let after = executions(&log);
    // The assertion file's names read the machine's position-free summary
    // only: they are not looked up again.
    assert_eq!(count(&after, "assertion_name_problems"), 0, "{after:?}");
}
