//! The model per element (`hir::model::element_model`): put together, the
//! elements' models are the model of a lowering of the whole file, on
//! every model of the repository and of the corpus (and the CSPm modules
//! of the elements read without positions are `csp_names`'s); and after an edit in
//! one element, asking for another element's model lowers nothing again
//! (read from salsa's event log).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use robosim_hir::csp_names::{csp_modules, csp_names};
use robosim_hir::element::element_list;
use robosim_hir::model::{element_model, file_model, lower_file_model};
use robosim_hir::{load_workspace, Durability, File, RootDatabase, RuleSet, Workspace};
use robosim_test_support::generated;

/// Every folder under `root` holding model files, with those files and
/// the assertion files beside them (one workspace per folder).
fn folders(root: &Path, out: &mut BTreeMap<PathBuf, Vec<(String, String)>>) {
    let Ok(entries) = std::fs::read_dir(root) else { return };
    let mut entries: Vec<_> = entries.filter_map(|e| e.ok()).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if !p.ends_with("target") && !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.')) {
                folders(&p, out);
            }
        } else if p.extension().is_some_and(|x| matches!(x.to_str(), Some("rct" | "rst" | "assertions" | "rsa"))) {
            if let Ok(text) = std::fs::read_to_string(&p) {
                out.entry(root.to_path_buf()).or_default().push((p.display().to_string(), text));
            }
        }
    }
}

/// The model files of a workspace.
fn models(db: &RootDatabase, ws: Workspace) -> Vec<File> {
    ws.files(db).iter().copied().filter(|f| !f.is_library(db) && !f.kind(db).is_assertions()).collect()
}

#[test]
fn elements_put_together_are_the_whole_files_model() {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut all = BTreeMap::new();
    for root in ["../..", "../../../shared/corpus", "../../../shared/reference"] {
        folders(&here.join(root), &mut all);
    }
    let generated = [
        ("gen.rst".to_string(), generated::generated_robosim(3)),
        ("gen.rct".to_string(), generated::generated_model(300)),
    ];
    let (mut files, mut items) = (0, 0);
    for (dir, group) in all
        .into_iter()
        .map(|(d, g)| (d.display().to_string(), g))
        .chain(generated.into_iter().map(|g| ("generated".to_string(), vec![g])))
    {
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, group, RuleSet::Paper);
        let table: Vec<_> = csp_names(&db, ws).elements().iter().map(|e| (e.path.clone(), e.module.clone())).collect();
        assert_eq!(csp_modules(&db, ws), &table, "{dir}");
        for f in models(&db, ws) {
            let (pieces, whole) = (file_model(&db, ws, f), lower_file_model(&db, ws, f));
            assert_eq!(pieces, &whole, "{dir}: {}", f.path(&db));
            files += 1;
            items += whole.items.len();
        }
    }
    assert!(files > 500 && items > 2000, "{files} files, {items} items");
}

/// An edit inside one machine, then the model of another element (what
/// a hover there reads): nothing is lowered again, the other element's
/// model is only moved by the edit's length (or re-validated, a few memos,
/// when the edit was after it); the edited machine's model is
/// lowered again only when asked for. Either way it is a fresh lowering's.
#[test]
fn the_model_of_an_element_after_an_edit_in_another() {
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = log.clone();
    // Executed queries by name; re-validated memos as `validated`.
    let mut db = RootDatabase::with_event_log(move |e| {
        let name = match e.kind {
            salsa::EventKind::WillExecute { database_key } => format!("{database_key:?}"),
            salsa::EventKind::DidValidateMemoizedValue { .. } => "validated".to_string(),
            _ => return,
        };
        sink.lock().unwrap().push(name.split('(').next().unwrap_or("").to_string());
    });
    let good = generated::generated_robosim(24);
    let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
    let file = models(&db, ws)[0];
    let named = |db: &RootDatabase, name: &str| *element_list(db, file).iter().find(|e| e.name(db) == name).unwrap();
    let at = good.find("stm SimSMovement12 {").unwrap();
    let guard = at + good[at..].find("not $obstacle").unwrap() + "not ".len();
    let bad = format!("{}{}", &good[..guard], &good[guard + 1..]);
    // Every element's model, once.
    let _ = file_model(&db, ws, file);
    for (k, text) in [&bad, &good, &bad, &good].into_iter().enumerate() {
        robosim_hir::edit_text(&mut db, file, text.clone(), Durability::LOW);
        for (other, moved) in [("SimSMovement3", false), ("SimSMovement20", true), ("SimCFootBot20", true)] {
            log.lock().unwrap().clear();
            let e = named(&db, other);
            let model = element_model(&db, ws, e).clone();
            let ran = std::mem::take(&mut *log.lock().unwrap());
            let lowered = ran.iter().filter(|q| *q == "element_items").count();
            assert_eq!(lowered, 0, "edit {k}, {other}: {ran:?}");
            // Moved (the edit was before it) or re-validated as it was.
            assert_eq!(ran.iter().filter(|q| *q == "element_model").count(), usize::from(moved), "{ran:?}");
            // A handful of memos re-validated (the element's model and
            // what it was computed from, without walking underneath: their
            // inputs are of medium durability), whatever the number of
            // elements (120 here).
            // (The first edit lowers the machine's durability: what is of
            // medium durability is walked once, as in `durability.rs`.)
            let validated = ran.iter().filter(|q| *q == "validated").count();
            assert!(k == 0 || validated <= 4, "edit {k}, {other}: {validated} re-validated: {ran:?}");
            assert!(ran.len() - validated <= 3, "edit {k}, {other}: {ran:?}");
            let mut fresh = RootDatabase::default();
            let fws = load_workspace(&mut fresh, [("gen.rst".to_string(), text.clone())], RuleSet::Paper);
            let ff = models(&fresh, fws)[0];
            let whole = lower_file_model(&fresh, fws, ff);
            let id = model[0].0;
            assert_eq!(model, whole.items.iter().filter(|(d, _)| *d == id).cloned().collect::<Vec<_>>());
        }
        // The edited machine: lowered again, alone.
        log.lock().unwrap().clear();
        let machine = named(&db, "SimSMovement12");
        let _ = element_model(&db, ws, machine);
        let ran = std::mem::take(&mut *log.lock().unwrap());
        assert_eq!(ran.iter().filter(|q| *q == "element_items").count(), 1, "{ran:?}");
    }
}
