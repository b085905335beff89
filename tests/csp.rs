//! `robosim csp`: snapshots of the export of the paper's running example
//! (`examples/paper`), the export of the construct fixture
//! (`tests/data/csp/features`) and of the data-type fixture
//! (`tests/data/csp/types`), the structural checker over them, and the
//! exit codes (0 all exported, 1 something not exported but the rest
//! written, 2 usage or I/O problems).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use robosim_semantics::{export_workspace, lint, Options, Profile};

fn robosim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robosim-e2e"))
}

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data").join(p)
}

fn paper() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/paper")
}

/// A fresh, empty folder for one test's output.
fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("robosim-csp-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Compares every file written in `dir` (the timed script is in the output
/// folder's `timed/`, as RoboTool writes it) with `tests/data/csp/<snapshots>/`,
/// and checks that no snapshot is left without a file.
fn compare(dir: &Path, snapshots: &str) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for n in &names {
        let got = std::fs::read_to_string(dir.join(n)).unwrap();
        expect_test::expect_file![format!("data/csp/{snapshots}/{n}")].assert_eq(&got);
    }
    let snap_dir = data(&format!("csp/{snapshots}"));
    if std::env::var_os("UPDATE_EXPECT").is_none() {
        for e in std::fs::read_dir(&snap_dir).unwrap() {
            let n = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(names.contains(&n), "snapshot {n} has no exported file");
        }
    }
    names
}

fn run(args: &[&str], paths: &[PathBuf]) -> Output {
    robosim().arg("csp").args(args).args(paths).output().unwrap()
}

#[test]
fn paper_example_export() {
    let dir = out_dir("paper");
    let out = run(&["-o", dir.to_str().unwrap()], &[paper()]);
    let stderr = text(&out.stderr);
    // Only the clock-initialisation assertion of design.assertions is not
    // exported: the rest is written, and the exit status says so.
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("design.assertions:54:1: assertion D6 is not exported"), "{stderr}");
    assert_eq!(stderr.matches("warning:").count(), 1, "{stderr}");
    assert!(stderr.contains("wrote 11 files to") && stderr.contains("(4 untimed, 7 timed in timed/)"), "{stderr}");
    // RoboTool's layout: the untimed script (RT-9) of the RoboChart files
    // in the folder, the timed one in `timed/`.
    let mut untimed: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    untimed.sort();
    assert_eq!(untimed, ["design.csp", "design_assertions.csp", "instantiations.csp", "robosim_defs.csp"]);
    let u = std::fs::read_to_string(dir.join("design_assertions.csp")).unwrap();
    assert!(u.contains("assert paper_design::CFootBot::D__(0, 45, 1, 15) :[deadlock free [FD]]"), "{u}");
    let names = compare(&dir.join("timed"), "paper");
    assert_eq!(
        names,
        [
            "assertions_assertions.csp",
            "design.csp",
            "design_assertions.csp",
            "instantiations.csp",
            "robosim_defs.csp",
            "simulation.csp",
            "simulation_alt.csp"
        ]
    );
    let design = std::fs::read_to_string(dir.join("timed").join("design_assertions.csp")).unwrap();
    assert!(design.contains("-- NOT EXPORTED: clock initialisation checks"), "{design}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn paper_example_assertions() {
    let dir = out_dir("paper-asserts");
    let out = run(&["-o", dir.to_str().unwrap()], &[paper()]);
    assert_eq!(out.status.code(), Some(1));
    let a = std::fs::read_to_string(dir.join("timed").join("assertions_assertions.csp")).unwrap();
    // Schedulability (§6.2) with the constants of the assertion and the
    // simulation's period; soundness as FD refinement of the constrained
    // design by the simulation; timed deadlock freedom (§7.4).
    for needle in [
        "include \"design.csp\"",
        "assert PConstrained::TLF(0, 1, 45, 1, 15) :[deadlock free [F]] :[tau priority]: {tock}",
        "assert not PConstrained2::TLF(0, 2, 45, 1, 15) :[deadlock free [F]] :[tau priority]: {tock}",
        "assert PConstrained::D__(0, 1, 45, 1, 15)\n  [FD= paper_sim::SimCFootBot::D__(0, 1, 45, 1, 15) :[tau priority]: {tock}",
        "paper_sim_alt::SimCFootBot::D__(0, 1, 45, 1, 15) [[ tock <- tock, tock <- tock' ]]",
    ] {
        assert!(a.contains(needle), "missing `{needle}` in\n{a}");
    }
    let sim = std::fs::read_to_string(dir.join("timed").join("simulation.csp")).unwrap();
    // Rule 6: exec as trigger; robotool3 outputs: urgent register writes.
    assert!(sim.contains("endexec__.TID_t2 -> (StartExec__ ; Junction__j0)"), "{sim}");
    assert!(sim.contains("EDeadline(registerWrite.o_move.lv.0, 0)"), "{sim}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn features_export_and_stdout() {
    // Without -o, every file goes to stdout, each after a header line.
    let out = run(&[], &[data("csp/features")]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    for f in ["robosim_defs.csp", "instantiations.csp", "features.csp", "features_sim.csp", "main.csp"] {
        assert!(stdout.contains(&format!("-- ==== timed/{f} ====\n")), "no {f} in\n{stdout}");
    }
    let dir = out_dir("features");
    let out = run(&["-o", dir.to_str().unwrap()], &[data("csp/features")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    compare(&dir.join("timed"), "features_out");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn data_types_export() {
    // Products, records, sets and sequences on events and variables.
    let dir = out_dir("types");
    let out = run(&["-o", dir.to_str().unwrap()], &[data("csp/types")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    compare(&dir.join("timed"), "types_out");
    let _ = std::fs::remove_dir_all(&dir);
}

fn export(paths: &[PathBuf], profile: Profile) -> robosim_semantics::Export {
    let mut files = Vec::new();
    for p in paths {
        let mut found = Vec::new();
        if p.is_dir() {
            for e in std::fs::read_dir(p).unwrap() {
                found.push(e.unwrap().path());
            }
        } else {
            found.push(p.clone());
        }
        found.sort();
        for f in found {
            if robosim_syntax::FileKind::from_path(&f).is_some() {
                files.push((f.display().to_string(), std::fs::read_to_string(&f).unwrap()));
            }
        }
    }
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    export_workspace(&db, ws, &Options { profile })
}

#[test]
fn exports_pass_the_structural_checker() {
    for profile in [Profile::RoboTool3, Profile::Paper2019] {
        for p in [paper(), data("csp/features"), data("csp/types")] {
            let e = export(std::slice::from_ref(&p), profile);
            let mut problems = lint::check(&e.files);
            problems.extend(lint::check(&e.untimed));
            assert!(problems.is_empty(), "{} ({profile:?}): {problems:#?}", p.display());
        }
    }
}

#[test]
fn unsupported_constructs_are_reported_and_the_rest_written() {
    let dir = out_dir("unsupported");
    let model = data("csp/unsupported.rct");
    let out = run(&["-o", dir.to_str().unwrap()], &[model]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("unsupported.rct:13:9: state machine unsupported::Funs is not exported: `f`: the type `nat -> nat` is not supported"),
        "{stderr}"
    );
    assert!(
        stderr
            .contains("operation unsupported::Raise is not exported: `level` is a variable of the operation's caller"),
        "{stderr}"
    );
    assert!(
        stderr.contains(
            "controller unsupported::AsyncMachines is not exported: asynchronous connections between two machines \
             of a controller are not exported"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("WithAsync"), "{stderr}");
    assert!(
        stderr.contains(
            "module unsupported::WithVars is not exported: platform variables (`battery`) are not exported yet"
        ),
        "{stderr}"
    );
    assert!(
        stderr.contains(
            "module unsupported::WithProvidedVars is not exported: platform variables (`speed`) are not exported yet"
        ),
        "{stderr}"
    );
    // RT-16: a value received into a variable the controller provides to
    // several machines is written by `set_level` after the event, through
    // the controller's memory, as any write (it was refused).
    assert!(!stderr.contains("SharesLevel"), "{stderr}");
    assert_eq!(stderr.matches("warning:").count(), 5, "{stderr}");
    let csp = std::fs::read_to_string(dir.join("timed").join("unsupported.csp")).unwrap();
    assert!(csp.contains("-- NOT EXPORTED: state machine unsupported::Funs"), "{csp}");
    assert!(csp.contains("-- NOT EXPORTED: operation unsupported::Raise"), "{csp}");
    assert!(
        csp.contains("  module SharesLevel\n") && csp.contains("lv__.TID_u.in?level__in -> set_level!level__in"),
        "{csp}"
    );
    // RT-12: the module's controllers linked by RoboTool's buffer.
    assert!(
        csp.contains("  module WithAsync\n") && csp.contains("Buffer1__ = unsupported::CS::p.out -> Buffer1Full__"),
        "{csp}"
    );
    // The machine that is supported is exported, in its package's module
    // (RoboTool's `unsupported::Fine`).
    assert!(csp.contains("module unsupported\n") && csp.contains("  module Fine\n"), "{csp}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn usage_and_io_errors() {
    let out = robosim().arg("csp").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = run(&[], &[data("csp/no/such/path.rct")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("cannot read"), "{}", text(&out.stderr));
    let out = run(&["--semantics", "fdr5"], &[paper()]);
    assert_eq!(out.status.code(), Some(2));
    // -o naming a file, not a folder.
    let blocker = out_dir("blocker");
    std::fs::write(&blocker, "x").unwrap();
    let out = run(&["-o", blocker.to_str().unwrap()], &[data("csp/features")]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let _ = std::fs::remove_file(&blocker);
}

#[test]
fn paper_example_export_paper2019() {
    let dir = out_dir("paper2019");
    let out = run(&["--semantics", "paper2019", "-o", dir.to_str().unwrap()], &[paper()]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("warning:").count(), 1, "{stderr}");
    compare(&dir.join("timed"), "paper2019");
    let sim = std::fs::read_to_string(dir.join("timed").join("simulation.csp")).unwrap();
    // Rule 7: outputs go to the buffer; Rule 4: written at the cycle's end,
    // true ones in order, the others false.
    assert!(sim.contains("entered__.SID_SMoving -> stmout.moveU.true.lv.0 -> Rest__SMoving"), "{sim}");
    assert!(sim.contains("registerWrite.moveU.false?x0__?x1__ -> SKIP"), "{sim}");
    let a = std::fs::read_to_string(dir.join("timed").join("assertions_assertions.csp")).unwrap();
    assert!(a.contains("<External, union(Writes, {tock})>"), "{a}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn paper2019_profile() {
    let out = run(&["--semantics", "paper2019"], &[paper().join("design.rct")]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // Platform calls return (moveRet) in the paper's semantics.
    assert!(stdout.contains("EDeadline(moveCall.lv.0, 0) ; EDeadline(moveRet, 0)"), "{stdout}");
}
