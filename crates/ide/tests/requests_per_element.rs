//! Requests right after a keystroke work on the element around the cursor
//! (issue 22): after an edit inside one machine, go to definition and
//! completion there re-execute none of the file-level queries (the file's
//! definitions, its resolution, its behaviour resolution, its members),
//! read from salsa's event log; and their answers, and the hover's, are
//! those of a fresh host given the same text.

use std::sync::{Arc, Mutex};

use robosim_hir::RootDatabase;
use robosim_ide::{AnalysisHost, Durability, FileId, RuleSet, TextSize};
use robosim_test_support::generated;

/// The queries that look at the whole file.
const FILE_LEVEL: &[&str] = &["file_defs(", "file_resolution(", "body_resolution(", "file_members("];

fn logging_host() -> (AnalysisHost, Arc<Mutex<Vec<String>>>) {
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = log.clone();
    let db = RootDatabase::with_event_log(move |e| {
        if let salsa::EventKind::WillExecute { database_key } = e.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    });
    (AnalysisHost::with_db(db, RuleSet::Paper), log)
}

fn file_level(ran: &[String]) -> Vec<&String> {
    ran.iter().filter(|q| FILE_LEVEL.iter().any(|f| q.starts_with(f))).collect()
}

/// The answers compared with a fresh host's.
#[derive(Debug, PartialEq)]
struct Answers {
    definition: String,
    hover: String,
    completions: Vec<String>,
}

fn answers(host: &AnalysisHost, file: FileId, name: TextSize, blank: TextSize) -> Answers {
    let a = host.analysis();
    Answers {
        definition: format!("{:?}", a.goto_definition(file, name).unwrap()),
        hover: format!("{:?}", a.hover_with_diagnostics(file, name, &[]).unwrap()),
        completions: a.completions(file, blank).unwrap().into_iter().map(|c| c.label).collect(),
    }
}

#[test]
fn requests_after_an_edit_inside_one_machine_read_that_machine_only() {
    let text = generated::generated_model(600);
    let (mut host, log) = logging_host();
    let file = host.set_file("/w/gen.rct", text.clone(), None, Durability::LOW);
    let machines = text.matches("\nstm Machine").count();
    assert!(machines >= 4, "{machines} machines");
    // The middle machine: a use of its variable in an entry action, and
    // the start of the statement after it (where completion lists names).
    let at = text.find(&format!("stm Machine{} {{", machines / 2)).unwrap();
    let entry = at + text[at..].find("; count").unwrap();
    let name = entry + "; count".len();
    let blank = entry + "; ".len();
    let _ = host.analysis().diagnostics(file).unwrap();
    let _ = answers(&host, file, TextSize::from(name as u32), TextSize::from(blank as u32));

    for round in 1..4 {
        // A space before the `;`, more each round: the names move by it.
        let mut edited = text.clone();
        edited.insert_str(entry, &" ".repeat(round));
        host.set_file("/w/gen.rct", edited.clone(), None, Durability::LOW);
        let (name, blank) = (TextSize::from((name + round) as u32), TextSize::from((blank + round) as u32));
        let a = host.analysis();
        let ran = |what: &str, f: &dyn Fn()| {
            log.lock().unwrap().clear();
            f();
            let ran = std::mem::take(&mut *log.lock().unwrap());
            (what.to_string(), ran)
        };
        let definition = ran("definition", &|| {
            let (_, targets) = a.goto_definition(file, name).unwrap().expect("a name");
            assert_eq!(targets.len(), 1);
            assert_eq!(targets[0].name, format!("count{}", machines / 2));
        });
        let completion = ran("completion", &|| {
            let items = a.completions(file, blank).unwrap();
            assert!(items.iter().any(|c| c.label == format!("count{}", machines / 2)), "{items:?}");
        });
        // The hover's own sections read the element as well, but its
        // tock-CSP section (`robosim_semantics::hover`) reads the whole
        // file's model, which resolves the whole file: not per element yet.
        let h = a.hover_with_diagnostics(file, name, &[]).unwrap().expect("a hover");
        assert!(h.markdown.contains(&format!("var count{} : nat", machines / 2)), "{}", h.markdown);
        for (what, ran) in [&definition, &completion] {
            assert!(file_level(ran).is_empty(), "{what} after edit {round} re-executed {:?}", file_level(ran));
        }
        drop(a);

        let mut fresh = AnalysisHost::new(RuleSet::Paper);
        let fresh_file = fresh.set_file("/w/gen.rct", edited, None, Durability::LOW);
        let got = answers(&host, file, name, blank);
        let want = answers(&fresh, fresh_file, name, blank);
        // File ids differ between the two hosts; the rest must not.
        let strip = |s: &str| s.replace(&format!("{fresh_file:?}"), "F").replace(&format!("{file:?}"), "F");
        assert_eq!(strip(&got.definition), strip(&want.definition));
        assert_eq!(got.hover, want.hover);
        assert_eq!(got.completions, want.completions);
    }
}
