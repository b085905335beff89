//! The host and its snapshots: changing inputs, workspace-wide queries,
//! memoisation across edits, and cancellation of queries on stale
//! snapshots.

use std::sync::{Arc, Mutex};

use robosim_ide::{AnalysisHost, Durability, FileKind, RuleSet, SymbolKind, TextRange, TextSize};

fn names(host: &AnalysisHost, query: &str) -> Vec<String> {
    host.analysis().workspace_symbols(query, 100).unwrap().into_iter().map(|s| s.name).collect()
}

#[test]
fn edits_keep_the_file_and_change_the_results() {
    let mut host = AnalysisHost::default();
    let a = host.set_file("/w/a.rct", "stm A { initial i }".into(), None, Durability::LOW);
    let before = host.analysis().document_symbols(a).unwrap();
    assert_eq!(before[0].name, "A");
    let again = host.set_file("/w/a.rct", "stm B { initial i }".into(), None, Durability::LOW);
    assert_eq!(a, again);
    let after = host.analysis().document_symbols(a).unwrap();
    assert_eq!(after[0].name, "B");
    assert_eq!(host.analysis().file_text(a).unwrap().as_ref(), "stm B { initial i }");
    assert_eq!(host.file_id("/w/a.rct"), Some(a));
}

#[test]
fn language_comes_from_the_extension_or_the_caller() {
    let mut host = AnalysisHost::default();
    let sim = host.set_file("/w/s.rst", String::new(), None, Durability::LOW);
    assert_eq!(host.analysis().file_kind(sim).unwrap(), FileKind::RoboSim);
    let untitled = host.set_file("untitled:1", String::new(), Some(FileKind::RoboSim), Durability::LOW);
    assert_eq!(host.analysis().file_kind(untitled).unwrap(), FileKind::RoboSim);
    let unknown = host.set_file("untitled:2", String::new(), None, Durability::LOW);
    assert_eq!(host.analysis().file_kind(unknown).unwrap(), FileKind::RoboChart);
}

#[test]
fn removing_files_and_the_library() {
    let mut host = AnalysisHost::default();
    host.set_file("/w/a.rct", "stm Cutter { initial i }".into(), None, Durability::LOW);
    assert_eq!(names(&host, "Cutter"), ["Cutter"]);
    assert!(host.remove_file("/w/a.rct"));
    assert!(!host.remove_file("/w/a.rct"));
    assert!(names(&host, "Cutter").is_empty());
    assert!(host.user_files().is_empty());
    // The library stays whatever happens.
    assert!(!host.remove_file("<stdlib>/core.rct"));
    assert!(names(&host, "real").contains(&"real".to_string()));
}

#[test]
fn workspace_symbols_rank_exact_prefix_substring_subsequence() {
    let mut host = AnalysisHost::default();
    host.set_file(
        "/w/a.rct",
        "stm Cutter { state Cut { } state ShortCut { } state CxUxT { } initial i }".into(),
        None,
        Durability::LOW,
    );
    assert_eq!(names(&host, "cut"), ["Cut", "Cutter", "ShortCut", "CxUxT"]);
    let found = host.analysis().workspace_symbols("shortcut", 10).unwrap();
    assert_eq!(found[0].kind, SymbolKind::State);
    assert_eq!(found[0].container_name.as_deref(), Some("Cutter"));
    assert_eq!(found[0].path, "/w/a.rct");
    assert_eq!(host.analysis().workspace_symbols("", 3).unwrap().len(), 3);
    // At equal rank, the user's declarations come before the library's.
    host.set_file("/w/b.rct", "type real".into(), None, Durability::LOW);
    let reals = host.analysis().workspace_symbols("real", 10).unwrap();
    assert_eq!(reals[0].path, "/w/b.rct");
    assert!(reals.iter().any(|s| s.path == "<stdlib>/core.rct"));
}

#[test]
fn diagnostics_are_the_semantic_models() {
    let files = [
        (
            "/w/a.rct".to_string(),
            "stm A { state S { } state S { } initial i transition t { from i to X } }".to_string(),
        ),
        ("/w/b.rct".to_string(), "stm A { initial i }\ninterface I { event e ; }".to_string()),
    ];
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files.clone(), RuleSet::Paper);
    let mut host = AnalysisHost::default();
    let ids: Vec<_> = files.iter().map(|(p, t)| host.set_file(p, t.clone(), None, Durability::LOW)).collect();
    let analysis = host.analysis();
    let mut seen_related = false;
    for (input, id) in ws.files(&db).iter().filter(|f| !f.is_library(&db)).zip(&ids) {
        let expected = robosim_hir::file_diagnostics(&db, ws, *input);
        let actual = analysis.diagnostics(*id).unwrap();
        assert_eq!(expected.len(), actual.len());
        assert!(!actual.is_empty());
        for (e, a) in expected.iter().zip(&actual) {
            assert_eq!((e.range, e.severity, &e.code, &e.message), (a.range, a.severity, &a.code, &a.message));
            assert_eq!(e.related.len(), a.related.len());
            for (er, ar) in e.related.iter().zip(&a.related) {
                seen_related = true;
                assert_eq!((er.range, &er.message, er.file.path(&db)), (ar.range, &ar.message, &ar.path));
            }
        }
    }
    // Not asserted: whether the semantic model reports related locations
    // for these files is its business.
    let _ = seen_related;
    let core = host.file_id("<stdlib>/core.rct").unwrap();
    assert!(analysis.diagnostics(core).unwrap().is_empty());
}

#[test]
fn syntax_diagnostics_are_the_syntax_part_of_all_diagnostics() {
    let mut host = AnalysisHost::default();
    let text = "stm A { var x : nat initial i state S { entry x = 1; } transition t { from i S } }";
    let file = host.set_file("/w/a.rct", text.into(), None, Durability::LOW);
    let a = host.analysis();
    let all: Vec<_> = a.diagnostics(file).unwrap().into_iter().filter(|d| d.is_syntax()).collect();
    let syntax = a.syntax_diagnostics(file).unwrap();
    assert_eq!(syntax.len(), 2);
    assert_eq!(all, syntax);
}

#[test]
fn semantic_diagnostics_carry_over_edits() {
    let mut host = AnalysisHost::default();
    let text = "stm A { initial i state S { } transition t { from i to X } }";
    let file = host.set_file("/w/a.rct", text.into(), None, Durability::LOW);
    let before = host.analysis().diagnostics(file).unwrap();
    let x = before.iter().find(|d| d.message.contains("`X`")).expect("an unresolved `X`").clone();
    // Six bytes inserted before the reference move it; an edit on it drops it.
    let edits = [robosim_ide::Edit { delete: TextRange::empty(0.into()), insert_len: 6.into() }];
    let moved = robosim_ide::carry_over(&before, file, &edits);
    let moved_x = moved.iter().find(|d| d.message == x.message).unwrap();
    assert_eq!(moved_x.range, x.range + TextSize::from(6));
    let on_it = [robosim_ide::Edit { delete: x.range, insert_len: 1.into() }];
    assert!(!robosim_ide::carry_over(&before, file, &on_it).iter().any(|d| d.message == x.message));
}

#[test]
fn rules_are_an_input() {
    let mut host = AnalysisHost::new(RuleSet::Paper);
    assert_eq!(host.rules(), RuleSet::Paper);
    host.set_rules(RuleSet::RoboTool);
    assert_eq!(host.rules(), RuleSet::RoboTool);
}

#[test]
fn editing_one_file_does_not_recompute_anothers_outline() {
    let log = Arc::new(Mutex::new(Vec::<String>::new()));
    let sink = log.clone();
    let db = robosim_hir::RootDatabase::with_event_log(move |e| {
        if let salsa::EventKind::WillExecute { database_key } = e.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    });
    let mut host = AnalysisHost::with_db(db, RuleSet::Paper);
    let a = host.set_file("/w/a.rct", "stm A { initial i }".into(), None, Durability::LOW);
    let b = host.set_file("/w/b.rct", "stm B { initial i }".into(), None, Durability::LOW);
    host.analysis().document_symbols(a).unwrap();
    host.analysis().document_symbols(b).unwrap();
    log.lock().unwrap().clear();
    host.set_file("/w/b.rct", "stm B2 { initial i }".into(), None, Durability::LOW);
    host.analysis().document_symbols(a).unwrap();
    assert!(!log.lock().unwrap().iter().any(|e| e.contains("document_symbols")), "{:?}", log.lock().unwrap());
    host.analysis().document_symbols(b).unwrap();
    assert!(log.lock().unwrap().iter().any(|e| e.contains("document_symbols")));
}

#[test]
fn a_write_cancels_queries_on_older_snapshots() {
    let mut host = AnalysisHost::default();
    let mut text = String::new();
    for i in 0..3000 {
        text.push_str(&format!("stm M{i} {{ var x : nat initial i state S {{ }} transition t {{ from i to S }} }}\n"));
    }
    let file = host.set_file("/w/big.rct", text.clone(), None, Durability::LOW);
    let snapshot = host.analysis();
    let (started_tx, started_rx) = std::sync::mpsc::channel();
    let worker = std::thread::spawn(move || {
        let mut first = true;
        // Highlighting until a write cancels it: the snapshot is dropped as
        // soon as the query unwinds, which lets the write proceed.
        loop {
            let result = snapshot.highlight(file);
            if first {
                let _ = started_tx.send(());
                first = false;
            }
            if result.is_err() {
                return true;
            }
        }
    });
    started_rx.recv().unwrap();
    // Blocks until the worker's snapshot is gone.
    host.set_file("/w/big.rct", text + "\n", None, Durability::LOW);
    assert!(worker.join().unwrap());
    assert!(host.analysis().highlight(file).is_ok());
}

/// Deep nesting (capped by the parser) and hostile bytes: every feature
/// answers. This crate's own features run on a 2 MB stack (a thread's
/// default); the semantic model's diagnostics get the 16 MB the language
/// server gives its threads.
#[test]
fn features_survive_deep_nesting_and_garbage() {
    let mut deep = String::from("stm M { initial i ");
    for _ in 0..2000 {
        deep.push_str("state S { ");
    }
    let inputs = [deep, "(((((".repeat(3000), "\u{0}\u{1}}}}}{{{\u{1F600}$$$::*".repeat(500), String::new()];
    for (i, text) in inputs.into_iter().enumerate() {
        for ext in ["rct", "rst", "assertions", "rsa"] {
            let mut host = AnalysisHost::default();
            let file = host.set_file(&format!("/w/f{i}.{ext}"), text.clone(), None, Durability::LOW);
            let a = host.analysis();
            let end = TextSize::of(text.as_str());
            let own = a.clone();
            on_stack(2 << 20, move || {
                own.syntax_diagnostics(file).unwrap();
                own.document_symbols(file).unwrap();
                own.highlight(file).unwrap();
                own.folding_ranges(file).unwrap();
                let offsets = [0.into(), TextSize::from(u32::from(end) / 2), end, end + TextSize::from(10)];
                own.selection_ranges(file, &offsets).unwrap();
                own.workspace_symbols("s", 10).unwrap();
            });
            on_stack(16 << 20, move || {
                a.diagnostics(file).unwrap();
            });
        }
    }
}

fn on_stack(size: usize, f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new().stack_size(size).spawn(f).unwrap().join().unwrap();
}

#[test]
fn edits_to_a_buffer_give_what_a_fresh_parse_gives() {
    // Buffers (LOW durability) are reparsed from their previous tree; the
    // diagnostics must be those of a host that never saw the old text.
    let base =
        "stm A {\n  initial i\n  state S { entry x = 1 }\n  transition t { from i to S }\n}\nstm B { initial j }\n";
    let edits = [
        base.replace("x = 1", "x = 1 +"),
        base.replace("x = 1", "x = 1 + 2"),
        base.replace("from i to S", "from i to"),
        base.replace("from i to S", "from i to S trigger"),
        base.to_string(),
        base.replace("stm B { initial j }", "stm B { initial j state }"),
    ];
    let mut host = AnalysisHost::default();
    let a = host.set_file("/w/a.rct", base.into(), None, Durability::LOW);
    for text in edits {
        // As the server does: the previous version was checked first.
        let _ = host.analysis().syntax_diagnostics(a).unwrap();
        host.set_file("/w/a.rct", text.clone(), None, Durability::LOW);
        let mut fresh = AnalysisHost::default();
        let f = fresh.set_file("/w/a.rct", text.clone(), None, Durability::LOW);
        let render = |h: &AnalysisHost, id| {
            let a = h.analysis();
            (format!("{:?}", a.diagnostics(id).unwrap()), format!("{:?}", a.document_symbols(id).unwrap()))
        };
        assert_eq!(render(&host, a), render(&fresh, f), "after the edit to {text:?}");
    }
}
