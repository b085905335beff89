//! An edit inside one element of a buffer leaves the other elements'
//! inputs alone, at medium durability, so that salsa re-validates their
//! results without walking what they depend on (`hir::element::Element`):
//! checked from salsa's event log.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use robosim_hir::{file_diagnostics, load_workspace, Durability, File, RootDatabase, RuleSet, Workspace};
use robosim_test_support::generated;

fn user_file(db: &RootDatabase, ws: Workspace) -> File {
    *ws.files(db).iter().find(|f| !f.is_library(db)).unwrap()
}

/// What salsa did for one keystroke: queries executed and memos
/// re-validated, by query name.
#[derive(Debug, Default)]
struct Keystroke {
    executed: BTreeMap<String, usize>,
    validated: BTreeMap<String, usize>,
}

impl Keystroke {
    fn validated(&self, q: &str) -> usize {
        self.validated.get(q).copied().unwrap_or(0)
    }
}

type Log = Arc<Mutex<Vec<(bool, String)>>>;

fn logged_db() -> (RootDatabase, Log) {
    let log: Log = Arc::default();
    let sink = log.clone();
    let db = RootDatabase::with_event_log(move |e| {
        let (executed, key) = match e.kind {
            salsa::EventKind::WillExecute { database_key } => (true, database_key),
            salsa::EventKind::DidValidateMemoizedValue { database_key } => (false, database_key),
            _ => return,
        };
        let name = format!("{key:?}").split('(').next().unwrap_or("").to_string();
        sink.lock().unwrap().push((executed, name));
    });
    (db, log)
}

/// Sets `text` as an editor's host does (with the prior parse, at low
/// durability) and checks the file, returning what salsa did and the
/// number of RS:SM6 problems.
fn keystroke(db: &mut RootDatabase, log: &Log, ws: Workspace, file: File, text: &str) -> (Keystroke, usize) {
    log.lock().unwrap().clear();
    robosim_hir::edit_text(db, file, text.to_string(), Durability::LOW);
    let sm6 = file_diagnostics(db, ws, file).iter().filter(|d| d.code == "RS:SM6").count();
    let mut k = Keystroke::default();
    for (executed, name) in std::mem::take(&mut *log.lock().unwrap()) {
        *if executed { &mut k.executed } else { &mut k.validated }.entry(name).or_default() += 1;
    }
    (k, sm6)
}

/// The memos that only the results of the untouched elements' rules and
/// problems depend on: re-validated only if salsa walks those results'
/// dependencies, which their durability spares it.
const INNER: &[&str] = &[
    "element_lowered",
    "element_summary",
    "element_defs",
    "element_nodes",
    "element_members",
    "element_specs",
    "element_usages",
    "element_problems",
    "element_rules",
    "element_cycles",
    "element_marks",
    "name_place",
    "use_places",
    "context_places",
];

#[test]
fn an_edit_inside_one_machine_does_not_revalidate_the_other_elements() {
    for copies in [8, 24] {
        let (mut db, log) = logged_db();
        let good = generated::generated_robosim(copies);
        let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
        let file = user_file(&db, ws);
        assert!(file_diagnostics(&db, ws, file).is_empty());
        let at = good.find(&format!("stm SimSMovement{} {{", copies / 2)).unwrap();
        let guard = at + good[at..].find("not $obstacle").unwrap() + "not ".len();
        let bad = format!("{}{}", &good[..guard], &good[guard + 1..]);
        let elements = copies * 5;
        let mut inner_total = Vec::new();
        for (k, text) in [&bad, &good, &bad, &good, &bad].into_iter().enumerate() {
            let (did, sm6) = keystroke(&mut db, &log, ws, file, text);
            assert_eq!(sm6, usize::from(k % 2 == 0), "{did:?}");
            if k == 0 {
                // The first edit of the machine lowers its input's
                // durability: everything of medium durability is
                // re-validated once, walking its dependencies.
                assert!(did.validated("element_lowered") >= elements - 1, "{did:?}");
                continue;
            }
            // From the second edit on: the untouched elements' results
            // that the file's diagnostics read are re-validated without
            // walking their dependencies, so that the memos underneath are
            // not even looked at (a few are: those of the machine's
            // controller and module, which read the machine).
            let inner: usize = INNER.iter().map(|q| did.validated(q)).sum();
            assert!(inner <= 12, "{copies} copies, edit {k}: {inner} inner memos re-validated: {did:?}");
            inner_total.push(inner);
            if k == 4 {
                eprintln!("{copies} copies, last edit: {did:?}");
            }
            // What is re-validated at all: the one result per element the
            // file's diagnostics read (`element_report`), and a constant.
            let all: usize = did.validated.values().sum();
            assert!(all <= elements + 40, "{copies} copies, edit {k}: {all} re-validated: {did:?}");
            // Re-executed: the machine's queries and a few file-level
            // ones, whatever the number of elements.
            let executed: usize = did.executed.values().sum();
            assert!(executed <= 20, "{copies} copies, edit {k}: {executed} executed: {did:?}");
        }
        eprintln!("{copies} copies: inner memos re-validated per edit {inner_total:?}");
    }
}

/// Editing another element after the first moves the low durability to
/// it, and the diagnostics stay those of a fresh check.
#[test]
fn editing_one_element_then_another_keeps_the_diagnostics_right() {
    let (mut db, log) = logged_db();
    let good = generated::generated_robosim(6);
    let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
    let file = user_file(&db, ws);
    let guard = |copy: usize, text: &str| {
        let at = text.find(&format!("stm SimSMovement{copy} {{")).unwrap();
        at + text[at..].find("not $obstacle").unwrap() + "not ".len()
    };
    let mut text = good.clone();
    for (step, copy) in [2, 2, 4, 4, 2, 5].into_iter().enumerate() {
        let g = guard(copy, &text);
        text = format!("{}{}", &text[..g], &text[g + 1..]);
        let (_, sm6) = keystroke(&mut db, &log, ws, file, &text);
        assert_eq!(sm6, 1, "step {step}");
        // Put the `$` back.
        text = format!("{}${}", &text[..g], &text[g..]);
        let (did, sm6) = keystroke(&mut db, &log, ws, file, &text);
        assert_eq!(sm6, 0, "step {step}: {did:?}");
        let mut fresh = RootDatabase::default();
        let fws = load_workspace(&mut fresh, [("gen.rst".to_string(), text.clone())], RuleSet::Paper);
        let a: Vec<_> = file_diagnostics(&db, ws, file).iter().map(|d| (d.range, d.code.clone())).collect();
        let b: Vec<_> =
            file_diagnostics(&fresh, fws, user_file(&fresh, fws)).iter().map(|d| (d.range, d.code.clone())).collect();
        assert_eq!(a, b, "step {step}");
    }
    assert_eq!(text, good);
}
