//! Per-element diagnostics: an edit inside one machine re-executes that
//! element's queries only (read from salsa's event log), and after any
//! sequence of edits the diagnostics of the edited database are those of a
//! fresh one, and so is its model (`hir::model`, put together from the
//! elements').

use robosim_test_support::generated;

use std::sync::{Arc, Mutex};

use robosim_hir::element::{element_list, Element};
use robosim_hir::element_rules::{element_cycles, element_rules};
use robosim_hir::{file_diagnostics, load_workspace, parse, Diagnostic, File, RootDatabase, RuleSet, Workspace};
use salsa::plumbing::AsId;

/// The user file of a one-file workspace.
fn user_file(db: &RootDatabase, ws: Workspace) -> File {
    *ws.files(db).iter().find(|f| !f.is_library(db)).unwrap()
}

/// Sets `text` as an editor's host does: with the previous text and parse.
fn edit(db: &mut RootDatabase, file: File, text: String) {
    robosim_hir::edit_text(db, file, text, robosim_hir::Durability::LOW);
}

#[test]
fn an_edit_inside_one_machine_reruns_that_element_only() {
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = log.clone();
    let mut db = RootDatabase::with_event_log(move |e| {
        if let salsa::EventKind::WillExecute { database_key } = e.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    });
    let good = generated::generated_robosim(6);
    let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
    let file = user_file(&db, ws);
    // The keys of the machine's rule queries (salsa names a query taking
    // the workspace and the element by an id of its own), read from the
    // log as they are computed first.
    let (machine_id, after, rule_keys) = {
        let elements: &[Element] = element_list(&db, file);
        // Two interfaces, a machine, a controller and a module per copy.
        assert_eq!(elements.len(), 6 * 5);
        let i = elements.iter().position(|e| e.name(&db) == "SimSMovement3").unwrap();
        log.lock().unwrap().clear();
        element_rules(&db, ws, elements[i]);
        element_cycles(&db, ws, elements[i]);
        let ran = std::mem::take(&mut *log.lock().unwrap());
        let key = |q: &str| ran.iter().find(|e| e.starts_with(&format!("{q}("))).cloned().unwrap();
        (format!("{:?}", elements[i].as_id()), elements.len() - i, [key("element_rules"), key("element_cycles")])
    };
    assert!(file_diagnostics(&db, ws, file).is_empty());

    let at = good.find("stm SimSMovement3 {").unwrap();
    let guard = at + good[at..].find("not $obstacle").unwrap() + "not ".len();
    let bad = format!("{}{}", &good[..guard], &good[guard + 1..]);
    for (k, text) in [&bad, &good, &bad, &good].into_iter().enumerate() {
        log.lock().unwrap().clear();
        edit(&mut db, file, text.clone());
        let sm6: Vec<_> = file_diagnostics(&db, ws, file).iter().filter(|d| d.code == "RS:SM6").cloned().collect();
        assert_eq!(sm6.len(), usize::from(k % 2 == 0), "{sm6:?}");
        if let Some(d) = sm6.first() {
            // Positions re-attached: the range is the name's in the file.
            assert_eq!(&text[d.range], "obstacle");
            assert_eq!(usize::from(d.range.start()), guard);
        }
        let ran = std::mem::take(&mut *log.lock().unwrap());
        if k == 0 {
            // The first edit of an element lowers its input's durability
            // (`hir::element::Element`), and salsa does not backdate a
            // result that became less durable: what reads the machine
            // (its controller's rules, the file's duplicate check) runs
            // once more. From the second edit on, only the machine's.
            continue;
        }
        let runs = |q: &str| ran.iter().filter(|e| e.starts_with(&format!("{q}("))).cloned().collect::<Vec<_>>();
        // The element's rules run once; every other element's results are
        // reused (the tracked struct of an element is its salsa key).
        assert_eq!(runs("element_problems").len(), 1, "{ran:?}");
        for q in ["element_lowered", "element_defs", "element_nodes"] {
            assert_eq!(runs(q), [format!("{q}({machine_id})")], "{ran:?}");
        }
        assert!(runs("element_members").len() <= 1, "{ran:?}");
        // Nothing resolves or types the whole file.
        for q in ["body_resolution", "type_checks", "file_resolution"] {
            assert!(runs(q).is_empty(), "{q}: {ran:?}");
        }
        // The rules run for the machine only: its controller and module
        // read it through position-free queries (members, cycle
        // specifications, usages, name places), which are equal after
        // the edit, so their rules are not run again.
        for (q, key) in ["element_rules", "element_cycles"].into_iter().zip(&rule_keys) {
            assert_eq!(&runs(q), std::slice::from_ref(key), "{ran:?}");
        }
        for q in ["element_specs", "element_usages"] {
            assert!(runs(q).len() <= 1, "{q}: {ran:?}");
        }
        // No rule query over the whole file, and the file's definitions
        // are not put together.
        for q in ["top_duplicates", "size_checks", "cycle_infos", "file_defs", "file_checks", "more_checks"] {
            assert!(runs(q).is_empty(), "{q}: {ran:?}");
        }
    }

    // Adding a state shifts the definition ids of the elements after the
    // machine: theirs are computed again (ids are the file's), those
    // before are not.
    log.lock().unwrap().clear();
    let state = at + good[at..].find("junction j0").unwrap();
    let more = format!("{}state Extra {{ }}\n\t{}", &good[..state], &good[state..]);
    edit(&mut db, file, more);
    assert!(file_diagnostics(&db, ws, file).is_empty());
    let ran = std::mem::take(&mut *log.lock().unwrap());
    let defs = ran.iter().filter(|e| e.starts_with("element_defs(")).count();
    assert_eq!(defs, after, "{ran:?}");
}

/// The definitions put together from the elements' are those of a
/// lowering of the whole file.
#[test]
fn elements_put_together_are_the_file() {
    let broken = "package p\nimport q::*\nstm A { var x : nat initial i state S { entry x = 1 } transition t { from i to S } }\n\
                  stm A { clock C transition u { from a to b #C condition since(C) > 1 } }\n\
                  stm ( }\ncontroller K { sref m = A connection K on e to m on e ( _async ) }\n\
                  interface I { event e : Seq(nat) op(a : nat, b : vector(real, 2)) }\n\
                  enumeration E { L(nat) M }\nfunction f(n : nat) : nat { precondition n > 0 }\n";
    for (path, text) in [
        ("gen.rst", generated::generated_robosim(3)),
        ("gen.rct", generated::generated_model(300)),
        ("broken.rct", broken.to_string()),
    ] {
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, [(path.to_string(), text)], RuleSet::Paper);
        for &f in ws.files(&db) {
            let whole = robosim_hir::defs::lower_file(&parse(&db, f).syntax_node());
            assert_eq!(robosim_hir::defs::file_defs(&db, f), &whole, "{}", f.path(&db));
        }
    }
}

/// A small deterministic generator (xorshift), so that failures replay.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Pieces of text the random edits insert: some of RoboSim's syntax, names
/// of the model (renaming, duplicating and breaking elements) and broken
/// tokens.
const SOUP: &[&str] = &[
    "$",
    " ",
    "\n",
    "x",
    "obstacle",
    "not ",
    "}",
    "{",
    "stm ",
    "SimSMovement0",
    "SimMovement1",
    "state Q { }\n",
    "transition tz { from j0 to DMoving }\n",
    "var v : nat\n",
    "#MBC ",
    "(",
    ")",
    ";",
    "== 2",
    "interface I { }\n",
    "controller SimMovement0 { }\n",
    "/\\ true",
    "event obstacle\n",
    "1",
    "// c\n",
];

/// The diagnostics without the salsa ids of their files (two databases
/// number their inputs alike, but the comparison need not rely on it).
fn rendered(db: &RootDatabase, diags: &[Diagnostic]) -> Vec<String> {
    diags
        .iter()
        .map(|d| {
            let related: Vec<_> = d.related.iter().map(|r| (r.file.path(db).clone(), r.range, &r.message)).collect();
            format!("{:?} {:?} {} {} {related:?}", d.range, d.severity, d.code, d.message)
        })
        .collect()
}

#[test]
fn random_edits_give_what_a_fresh_check_gives() {
    let edits: usize = std::env::var("ROBOSIM_RANDOM_EDITS").ok().and_then(|n| n.parse().ok()).unwrap_or(10_000);
    random_edits("gen.rst", &generated::generated_robosim(1), edits, 0x9e37_79b9_7f4a_7c15);
}

/// A RoboChart model whose rules relate elements: problems and related
/// locations in one element found by another's rules (a recursion through
/// top-level operations, a machine that receives through an operation, a
/// module connection reversed inside its controller, copies of names).
const RELATED: &str = "interface Ops { a() b() op() }
interface E { event e event ping : nat }
operation a() { requires Ops initial i state S { entry b() } transition t { from i to S } }
operation b() { requires Ops initial i state S { entry a() } transition t { from i to S } }
stm M { uses E requires Ops var x : nat initial i state S { entry op(); e } transition t { from i to S } }
controller C {
  uses E requires Ops
  opref oa = a
  opref ob = b
  operation op() { uses E var x : nat initial i state S { entry ping?x } final f transition t { from i to S } transition u { from S to f } }
  sref m = M
  connection m on ping to C on ping
  connection m on e to C on e
}
controller D { uses E sref m = M connection C on e to m on e }
module Mod {
  robotic platform P { uses E provides Ops }
  cref c = C
  connection P on e to c on e ( _async )
}
stm M { initial i }
";

#[test]
fn random_edits_of_related_elements_give_what_a_fresh_check_gives() {
    let edits: usize =
        std::env::var("ROBOSIM_RANDOM_EDITS").ok().and_then(|n| n.parse().ok()).map_or(2_000, |n: usize| n / 5);
    random_edits("related.rct", RELATED, edits, 0x2545_f491_4f6c_dd1d);
}

/// Applies `edits` random edits to `start` (restarting from it now and
/// then), comparing after each the diagnostics of the edited database with
/// those of a fresh one.
fn random_edits(path: &str, start: &str, edits: usize, seed: u64) {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, [(path.to_string(), start.to_string())], RuleSet::Paper);
    let file = user_file(&db, ws);
    let mut text = start.to_string();
    let mut rng = Rng(seed);
    for k in 0..edits {
        // Restart from the clean model now and then, so that the text does
        // not drift into noise.
        if k % 200 == 0 && k > 0 {
            text = start.to_string();
        }
        let at = {
            let mut at = rng.below(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            at
        };
        let mut end = (at + rng.below(12)).min(text.len());
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let insert = if rng.below(3) == 0 { "" } else { SOUP[rng.below(SOUP.len())] };
        text.replace_range(at..end, insert);
        edit(&mut db, file, text.clone());
        let incremental = rendered(&db, file_diagnostics(&db, ws, file));
        let whole = robosim_hir::defs::lower_file(&parse(&db, file).syntax_node());
        assert_eq!(robosim_hir::defs::file_defs(&db, file), &whole, "edit {k}");
        // From scratch: a new database.
        let mut fresh_db = RootDatabase::default();
        let fws = load_workspace(&mut fresh_db, [(path.to_string(), text.clone())], RuleSet::Paper);
        let fresh = rendered(&fresh_db, file_diagnostics(&fresh_db, fws, user_file(&fresh_db, fws)));
        assert_eq!(incremental, fresh, "edit {k}: {at}..{end} := {insert:?}\n{text}");
        // The model put together from the elements' (what hovers read, one
        // element at a time) is a fresh lowering of the whole file.
        let model = format!("{:?}", robosim_hir::model::file_model(&db, ws, file));
        let fresh_model =
            format!("{:?}", robosim_hir::model::lower_file_model(&fresh_db, fws, user_file(&fresh_db, fws)));
        assert_eq!(model, fresh_model, "edit {k}: {at}..{end} := {insert:?}\n{text}");
    }
}
