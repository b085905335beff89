//! Requests right after a keystroke work on the element around the cursor
//! (issue 22): after an edit inside one machine, go to definition,
//! completion and hover (its tock-CSP section included) there re-execute
//! none of the file-level queries (the file's definitions, its resolution,
//! its behaviour resolution, its members, its types, its model), read from
//! salsa's event log; and their answers are those of a fresh host given
//! the same text.

use std::sync::{Arc, Mutex};

use robosim_hir::RootDatabase;
use robosim_ide::{AnalysisHost, Durability, FileId, RuleSet, TextSize};
use robosim_test_support::generated;

/// The queries that look at the whole file.
const FILE_LEVEL: &[&str] = &[
    "file_defs(",
    "file_resolution(",
    "body_resolution(",
    "file_members(",
    "expr_types(",
    "file_model(",
    "cycle_infos(",
    "csp_names(",
];

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
    /// The hovers with a tock-CSP section.
    terms: Vec<String>,
}

fn answers(host: &AnalysisHost, file: FileId, name: TextSize, blank: TextSize, terms: &[TextSize]) -> Answers {
    let a = host.analysis();
    Answers {
        definition: format!("{:?}", a.goto_definition(file, name).unwrap()),
        hover: format!("{:?}", a.hover_with_diagnostics(file, name, &[]).unwrap()),
        completions: a.completions(file, blank).unwrap().into_iter().map(|c| c.label).collect(),
        terms: terms.iter().map(|&t| format!("{:?}", a.hover_with_diagnostics(file, t, &[]).unwrap())).collect(),
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
    // Hovers with a tock-CSP term: a transition of the edited machine,
    // after the edit; the next machine's name (its process); a trigger of
    // the machine before.
    let call = entry + text[entry..].find("transition t").unwrap() + "transition t".len();
    let next = text.find(&format!("stm Machine{} {{", machines / 2 + 1)).unwrap() + "stm Mach".len();
    let before = text.find(&format!("stm Machine{} {{", machines / 2 - 1)).unwrap();
    let trigger = before + text[before..].find("trigger reading").unwrap() + "trigger rea".len();
    let terms =
        |round: usize| [call, next, trigger].map(|t| TextSize::from((t + if t > entry { round } else { 0 }) as u32));
    let _ = host.analysis().diagnostics(file).unwrap();
    let _ = answers(&host, file, TextSize::from(name as u32), TextSize::from(blank as u32), &terms(0));

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
        let hover = ran("hover", &|| {
            let h = a.hover_with_diagnostics(file, name, &[]).unwrap().expect("a hover");
            assert!(h.markdown.contains(&format!("var count{} : nat", machines / 2)), "{}", h.markdown);
        });
        drop(a);
        // Each term hover first after an edit of the machine (the edit
        // invalidated the edited machine's model, and moved the next
        // machine's).
        let mut term_hovers = Vec::new();
        for (k, at) in terms(round).into_iter().enumerate() {
            if k > 0 {
                edit_away_and_back(&mut host, &edited, entry);
            }
            let a = host.analysis();
            log.lock().unwrap().clear();
            let h = a.hover_with_diagnostics(file, at, &[]).unwrap().expect("a hover");
            // The machines of this model are not exported (fractional
            // reals): the hover says so by having no term; the RoboSim
            // test below has terms.
            assert!(!h.markdown.contains("tock-CSP"), "{}", h.markdown);
            term_hovers.push((format!("term hover {k}"), std::mem::take(&mut *log.lock().unwrap())));
        }
        for (what, ran) in [&definition, &completion, &hover].into_iter().chain(&term_hovers) {
            assert!(file_level(ran).is_empty(), "{what} after edit {round} re-executed {:?}", file_level(ran));
        }

        let mut fresh = AnalysisHost::new(RuleSet::Paper);
        let fresh_file = fresh.set_file("/w/gen.rct", edited, None, Durability::LOW);
        let got = answers(&host, file, name, blank, &terms(round));
        let want = answers(&fresh, fresh_file, name, blank, &terms(round));
        // File ids differ between the two hosts; the rest must not.
        let strip = |s: &str| s.replace(&format!("{fresh_file:?}"), "F").replace(&format!("{file:?}"), "F");
        assert_eq!(strip(&got.definition), strip(&want.definition));
        assert_eq!(got.hover, want.hover);
        assert_eq!(got.completions, want.completions);
        assert_eq!(got.terms, want.terms);
    }
}

/// Edits the text away from `edited` and back (another space at `at`,
/// removed), so that the next request is the first after an edit of the
/// machine.
fn edit_away_and_back(host: &mut AnalysisHost, edited: &str, at: usize) {
    edit_away_and_back_at(host, "/w/gen.rct", edited, at);
}

/// The tock-CSP terms of hovers after a keystroke in one RoboSim machine:
/// on a transition of that machine, on a transition of a machine before
/// it, on the names of a machine, a controller and a module after it.
/// Each is the first request after an edit; none re-executes a file-level
/// query or lowers another element's model than the one hovered (and, for
/// a controller or module, those it instantiates); each is a fresh host's.
#[test]
fn tock_csp_hovers_after_an_edit_read_the_hovered_element() {
    let text = generated::generated_robosim(24);
    let (mut host, log) = logging_host();
    let file = host.set_file("/w/gen.rst", text.clone(), None, Durability::LOW);
    let copy = |k: usize, what: &str| {
        let at = text.find(&format!("stm SimSMovement{k} {{")).unwrap();
        at + text[at..].find(what).unwrap()
    };
    let guard = copy(12, "condition not $obstacle") + "condition not ".len();
    let sites = [
        ("edited machine's transition", copy(12, "transition t1") + "transition t".len()),
        ("earlier machine's transition", copy(5, "transition t2") + "transition t".len()),
        ("later machine's name", text.find("stm SimSMovement20 {").unwrap() + "stm Sim".len()),
        ("later controller's name", text.find("controller SimMovement20 {").unwrap() + "controller Sim".len()),
        ("later module's name", text.find("module SimCFootBot20 {").unwrap() + "module Sim".len()),
    ];
    let _ = host.analysis().diagnostics(file).unwrap();
    // Each hover once (what an element's hover reads of others is then
    // memoised, as in an editor after the first hovers).
    for (_, at) in sites {
        let _ = host.analysis().hover_with_diagnostics(file, TextSize::from(at as u32), &[]).unwrap();
    }
    for round in 1..4 {
        let mut edited = text.clone();
        edited.insert_str(guard, &" ".repeat(round));
        for (what, at) in sites {
            // Away and back: the hover is the first request after an edit.
            edit_away_and_back_at(&mut host, "/w/gen.rst", &edited, guard);
            let at = TextSize::from((at + if at > guard { round } else { 0 }) as u32);
            let a = host.analysis();
            log.lock().unwrap().clear();
            let h = a.hover_with_diagnostics(file, at, &[]).unwrap().expect("a hover");
            let ran = std::mem::take(&mut *log.lock().unwrap());
            assert!(h.markdown.contains("tock-CSP"), "{what}: {}", h.markdown);
            assert!(file_level(&ran).is_empty(), "{what} after edit {round} re-executed {:?}", file_level(&ran));
            // The hovered element's model is lowered again only if it is
            // the edited one; the hover also reads the models of what the
            // element uses and instantiates (its interfaces, machines,
            // controller): moved if the edit was before them, never
            // lowered again.
            let items = ran.iter().filter(|q| q.starts_with("element_items(")).count();
            let edited_one = usize::from(what.starts_with("edited"));
            assert_eq!(items, edited_one, "{what} after edit {round}: {ran:?}");
            let models = ran.iter().filter(|q| q.starts_with("element_model(")).count();
            assert!(models <= 6, "{what} after edit {round}: {ran:?}");
            drop(a);
            let mut fresh = AnalysisHost::new(RuleSet::Paper);
            let fresh_file = fresh.set_file("/w/gen.rst", edited.clone(), None, Durability::LOW);
            let want = fresh.analysis().hover_with_diagnostics(fresh_file, at, &[]).unwrap();
            assert_eq!(Some(h), want, "{what} after edit {round}");
        }
    }
}

/// [`edit_away_and_back`] for the file at `path`.
fn edit_away_and_back_at(host: &mut AnalysisHost, path: &str, edited: &str, at: usize) {
    let mut other = edited.to_string();
    other.insert(at, ' ');
    host.set_file(path, other, None, Durability::LOW);
    host.set_file(path, edited.to_string(), None, Durability::LOW);
}
