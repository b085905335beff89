//! Reachability assertions (RT-10: some trace reaches the state's
//! `entered`) as the export writes them, evaluated with our CSPm
//! evaluator, against verdicts stated by hand: in RoboSim controllers and
//! modules (whose `VS__` keeps the machines' `entered__` visible and whose
//! `D__` hides them), which the native checker does not decide yet.

use std::collections::HashMap;
use std::path::Path;
use std::time::Duration;

use robosim_cspm::{Evaluator, Label, Limits, Module, NoNames, Severity};
use robosim_semantics::{export_workspace, Export, Options, Profile};

fn export_fixture(name: &str) -> Export {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/test_data/verify").join(name);
    let files = robosim_test_support::inputs::read_model_files(&dir);
    export_files(files)
}

fn export_files(files: Vec<(String, String)>) -> Export {
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile: Profile::RoboTool3 })
}

/// The verdict of each reachability assertion of the script `script`:
/// `assert not STOP [T= P \ diff(Events, {entered})` (`is reachable`;
/// without `not`, `is not reachable`) holds iff `P` can (cannot) perform
/// the entry; `Err` with the reason when it is not exported.
fn verdicts(e: &Export, script: &str) -> HashMap<String, Result<bool, String>> {
    let texts: HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |n: &str| texts.get(n).cloned();
    let text = texts.get(script).unwrap_or_else(|| panic!("no {script} in {:?}", texts.keys()));
    let module = Module::check_with_includes(text, &NoNames, &load);
    let errors: Vec<String> =
        module.diagnostics().iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{d:?}")).collect();
    assert!(errors.is_empty(), "{script}: {errors:#?}");
    let mut out = HashMap::new();
    let mut lines = text.lines().peekable();
    while let Some(l) = lines.next() {
        let Some(rest) = l.strip_prefix("-- assertion ").or_else(|| l.strip_prefix("-- timed assertion ")) else {
            continue;
        };
        let name = rest.split(" : ").next().unwrap_or_default().trim().to_string();
        let mut next = lines.next().unwrap_or_default().to_string();
        while let Some(more) = lines.peek().filter(|l| l.starts_with(' ')) {
            next = format!("{next} {}", more.trim());
            lines.next();
        }
        if let Some(why) = next.strip_prefix("-- NOT EXPORTED: ") {
            out.insert(name, Err(why.to_string()));
            continue;
        }
        let (negated, process) =
            match (next.strip_prefix("assert not STOP [T= "), next.strip_prefix("assert STOP [T= ")) {
                (Some(p), _) => (true, p),
                (_, Some(p)) => (false, p),
                _ => panic!("{name}: not a reachability assertion: {next}"),
            };
        let limits = Limits { max_states: 50_000, time: Duration::from_secs(30), ..Limits::default() };
        let mut ev = Evaluator::new(&module, &NoNames, limits);
        let lts = ev.eval_text(process).and_then(|v| ev.lts_of(&v)).unwrap_or_else(|d| panic!("{name}: {}", d.message));
        let entered = lts.transitions.iter().flatten().any(|(l, _)| matches!(l, Label::Event(_)));
        out.insert(name, Ok(entered == negated));
    }
    out
}

/// RT-10, RT-20, RT-21: the engine's fixture
/// `export_robosim_container_reachability` (a machine in a controller in
/// a module), whose verdicts the engine leaves `unsupported`.
#[test]
fn reachability_in_robosim_controllers_and_modules() {
    let e = export_fixture("export_robosim_container_reachability");
    let got = verdicts(&e, "a_assertions.csp");
    let expected = [
        ("M1", true),  // R, after a cycle that reads `go` present
        ("M2", false), // Never: its only way in is guarded by `false`
        ("M3", true),  // F, a cycle after R
        ("C1", true),
        ("C2", false),
        ("C3", false), // `C::m::W is not reachable`: W is entered in the first cycle
        ("T1", false), // S's entry writes `op` twice in a cycle: it never ends, S is never `entered`
    ];
    for (name, verdict) in expected {
        assert_eq!(got.get(name), Some(&Ok(verdict)), "{name}: {got:#?}");
    }
    // D__ hides the machines' entries; VS__ shows them.
    let text = e.files.iter().find(|f| f.name == "m.csp").expect("m.csp").text();
    let texts: HashMap<String, String> = e.files.iter().map(|f| (f.name.clone(), f.text())).collect();
    let load = |n: &str| texts.get(n).cloned();
    let module = Module::check_with_includes(&texts["a_assertions.csp"], &NoNames, &load);
    for (process, shows) in [("Mod::D__(0, 1)", false), ("Mod::VS__(0, 1)", true), ("C::D__(0, 1)", false)] {
        let limits = Limits { max_states: 50_000, time: Duration::from_secs(30), ..Limits::default() };
        let mut ev = Evaluator::new(&module, &NoNames, limits);
        let lts =
            ev.eval_text(process).and_then(|v| ev.lts_of(&v)).unwrap_or_else(|d| panic!("{process}: {}", d.message));
        let done: Vec<&String> = lts
            .transitions
            .iter()
            .flatten()
            .filter_map(|(l, _)| match l {
                Label::Event(i) => Some(&lts.events[*i as usize]),
                _ => None,
            })
            .collect();
        let entries = done.iter().any(|n| n.contains("entered__"));
        assert_eq!(entries, shows, "{process}: {done:?}\n{text}");
    }
}

/// The export's node names share one namespace per machine (`SID_A_B`
/// for a state B in A, `Junction__A_j` for A's junction `j`), where
/// RoboTool nests a module per state: a state named `A_B`, a junction
/// named `A_j`, a state `Events_` beside `Events` (escaped as `Events_`)
/// get names of their own, and reachability finds each state by its own
/// (the engine's fixture `export_state_names_are_distinct`, whose
/// verdicts `export_semantics.rs` compares with the engine's too).
#[test]
fn states_whose_flat_names_would_meet_get_distinct_names() {
    let e = export_fixture("export_state_names_are_distinct");
    let text = e.files.iter().find(|f| f.name == "m.csp").expect("m.csp").text();
    for distinct in [
        "datatype SIDS = SID_A | SID_A_B | SID_A_B_2\n",
        "Junction__A_j =",
        "Junction__A_j_2 =",
        "Enter__A_B =",
        "Enter__A_B_2 =",
        "datatype SIDS = SID_Events_ | SID_Events__2\n",
    ] {
        assert!(text.contains(distinct), "{distinct}\nnot in\n{text}");
    }
    let got = verdicts(&e, "a_assertions.csp");
    for (name, verdict) in [("N1", true), ("N2", false), ("N3", true), ("K1", false), ("K2", true)] {
        assert_eq!(got.get(name), Some(&Ok(verdict)), "{name}: {got:#?}");
    }
}
