//! End-to-end tests of `robosim verify`: verdicts on the paper's running
//! example, the JSON contract, the human rendering of a counterexample and
//! the exit codes.

use std::path::{Path, PathBuf};
use std::process::Command;

use expect_test::expect_file;

fn robosim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robosim-e2e"))
}

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/verify")
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

fn json(args: &[&str], path: &Path) -> (Option<i32>, serde_json::Value) {
    let out = robosim().arg("verify").args(args).args(["--format", "json"]).arg(path).output().unwrap();
    let v = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!("{e}: {}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
    });
    (out.status.code(), v)
}

fn find<'a>(v: &'a serde_json::Value, file: &str, name: &str) -> &'a serde_json::Value {
    v["assertions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["file"].as_str().unwrap().ends_with(file) && a["name"] == name)
        .unwrap_or_else(|| panic!("no assertion {name} of {file} in {v:#}"))
}

/// GT-1, GT-2a and GT-2b of the running example (Figure 1 with PI = 45,
/// av = 15, lv = 1): schedulable with period 1, not with 2 or 3.
#[test]
fn running_example_schedulability() {
    let (code, v) = json(&[], &examples().join("paper"));
    let s1 = find(&v, "assertions.rsa", "S1");
    assert_eq!(s1["verdict"], "pass", "{s1:#}");
    assert_eq!(s1["counterexample"], serde_json::Value::Null);
    assert!(s1["states"].as_u64().unwrap() > 0);
    let s2 = find(&v, "assertions.rsa", "S2");
    assert_eq!(s2["verdict"], "pass", "{s2:#}");
    // `is not schedulable` passes with the deadlock as its witness.
    let steps = s2["counterexample"]["steps"].as_array().unwrap();
    let events: Vec<&str> = steps.iter().map(|s| s["event"].as_str().unwrap()).filter(|e| *e != "τ").collect();
    assert_eq!(
        events.join(" "),
        "registerRead.i_obstacle.true (moveCall.1.0) registerWrite.o_move.1.0 tock tock \
         registerRead.i_obstacle.true (obstacle.in) (stopCall) registerWrite.o_stop tock"
    );
    // The design's steps point at the model: move(lv, 0) in Moving's entry.
    let call = steps.iter().find(|s| s["event"] == "(moveCall.1.0)").unwrap();
    assert!(call["location"]["file"].as_str().unwrap().ends_with("design.rct"));
    assert_eq!(call["location"]["range"]["start"], serde_json::json!({"line": 33, "character": 14}));
    assert_eq!(steps.last().unwrap()["cycle"], 1);
    assert_eq!(find(&v, "assertions.rsa", "S3")["verdict"], "pass");
    // GT-4, GT-5: Figures 3 and 4 are sound; their modules deadlock-free.
    for name in ["R1", "R2", "D1", "D2"] {
        let r = find(&v, "assertions.rsa", name);
        assert_eq!(r["verdict"], "pass", "{r:#}");
    }
    // The design's own properties (deadlock, divergence and timelock
    // freedom, nondeterminism, reachability of Turning).
    for name in ["D1", "D2", "D3", "D4", "D5"] {
        let r = find(&v, "design.assertions", name);
        assert_eq!(r["verdict"], "pass", "{r:#}");
    }
    // Clock initialisation has no semantics in RoboTool 3 (RT-10):
    // unsupported, with the reason.
    let d6 = find(&v, "design.assertions", "D6");
    assert_eq!(d6["verdict"], "unsupported");
    assert!(d6["reason"].as_str().unwrap().contains("not supported by RoboTool 3's semantics"), "{d6:#}");
    // No failure, some unsupported: exit 3.
    assert_eq!(code, Some(3));
}

/// GT-22 to GT-24: the square-trajectory robot of the paper's Section 7.1
/// and its variations, schedulable for the periods the paper states and
/// not for the others, in both profiles; every assertion passes (exit 0).
#[test]
fn square_schedulability_in_both_profiles() {
    for profile in ["robotool3", "paper2019"] {
        let (code, v) = json(&["--semantics", profile], &examples().join("square"));
        let names: Vec<(&str, &str)> = v["assertions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| (a["name"].as_str().unwrap(), a["verdict"].as_str().unwrap()))
            .collect();
        let expected = ["F1", "F2", "V1", "V2", "V4", "V3", "V8", "W1", "W2"].map(|n| (n, "pass"));
        assert_eq!(names, expected.to_vec(), "{profile}: {v:#}");
        assert_eq!(code, Some(0), "{profile}");
        // Period 2 fails at the end of the first side (5 time units), the
        // platform call of the turn falling between two cycles.
        let f2 = find(&v, "square.rsa", "F2");
        let steps = f2["counterexample"]["steps"].as_array().unwrap();
        assert!(
            steps.iter().any(|s| s["description"].as_str().is_some_and(|d| d.contains("takes corner"))),
            "{profile}: {f2:#}"
        );
    }
}

/// The lawnmower example: its design's properties hold, it is schedulable
/// with period 1, its simulation is sound (`$bump?s` binds `s` on a
/// transition out of a junction), and it refines its csp block's
/// specification (read by the CSPm bridge with RoboTool's names).
#[test]
fn lawnmower_example_verifies() {
    let (code, v) = json(&[], &examples().join("lawnmower"));
    let got: Vec<(&str, &str, &str)> = v["assertions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| (a["name"].as_str().unwrap(), a["semantics"].as_str().unwrap(), a["verdict"].as_str().unwrap()))
        .collect();
    // RT-8: the plain assertions about the design in both semantics, the
    // `timed` ones and those about the simulation in the timed one.
    let expected = [
        ("L1", "timed", "pass"),
        ("L1", "untimed", "pass"),
        ("L2", "timed", "pass"),
        ("L2", "untimed", "pass"),
        ("L3", "timed", "pass"),
        ("L4", "timed", "pass"),
        ("L4", "untimed", "pass"),
        ("L5", "timed", "pass"),
        ("L5", "untimed", "pass"),
        ("L6", "timed", "pass"),
        ("L7", "timed", "pass"),
        ("S1", "timed", "pass"),
        ("R1", "timed", "pass"),
        ("D1", "timed", "pass"),
    ];
    assert_eq!(got, expected, "{v:#}");
    assert_eq!(code, Some(0));
}

/// GT-3: without the wait(1) the design cannot be scheduled; the
/// counterexample is the paper's, rendered by cycle with source locations.
#[test]
fn unschedulable_variant_counterexample() {
    let out = robosim().current_dir(data()).args(["verify", "gt3"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8(out.stdout).unwrap();
    let text: String = text
        .lines()
        .map(|l| match l.find("  (") {
            // Timings vary from run to run.
            Some(i) if l.contains(" s)") => format!("{}{}", &l[..i], "  (…)"),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    expect_file!["data/verify/gt3.txt"].assert_eq(&text);
}

#[test]
fn budget_exhaustion_is_inconclusive() {
    let (code, v) = json(&["--max-states", "5"], &examples().join("paper"));
    let s1 = find(&v, "assertions.rsa", "S1");
    assert_eq!(s1["verdict"], "inconclusive", "{s1:#}");
    assert!(s1["reason"].as_str().unwrap().contains("state"), "{s1:#}");
    assert_eq!(code, Some(3));
}

#[test]
fn usage_errors() {
    let out = robosim().args(["verify", "/nonexistent/robosim"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = robosim().args(["verify", "--timeout", "-1"]).arg(examples()).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// GT-3 in the paper's own semantics: the counterexample FDR printed in the
/// paper (§6.2), event for event (with lv = 1).
#[test]
fn paper_profile_prints_the_papers_counterexample() {
    let (code, v) = json(&["--semantics", "paper2019"], &data().join("gt3"));
    assert_eq!(code, Some(1));
    let s1 = find(&v, "checks.rsa", "S1");
    assert_eq!(s1["verdict"], "fail");
    let events: Vec<&str> = s1["counterexample"]["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["event"].as_str().unwrap())
        .filter(|e| *e != "τ")
        .collect();
    assert_eq!(
        events.join(", "),
        "registerRead.obstacleU.true, moveCall.1.0, moveRet, obstacle, stopCall, stopRet, \
         registerWrite.moveU.true.1.0, registerWrite.stopU.true"
    );
    // Period 2: not schedulable either, so `S2` (negated) passes.
    assert_eq!(find(&v, "checks.rsa", "S2")["verdict"], "pass");
}

/// `--diagrams DIR` draws the counterexample on the machine's diagram: the
/// states and transitions it passes through, with their cycles.
#[test]
fn counterexample_on_the_diagram() {
    let dir = std::env::temp_dir().join(format!("robosim-cex-diagrams-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = robosim().arg("verify").arg("--diagrams").arg(&dir).arg(data().join("gt3")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let svg = std::fs::read_to_string(dir.join("S1.paper_design.SMovement.svg")).expect("the diagram of S1");
    // Moving (its entry calls move), t1 (obstacle, stop) and Turning (stuck
    // on its entry's call) are marked in cycle 0.
    for id in ["Moving", "t1", "Turning"] {
        let at = svg.find(&format!(r#"data-id="{id}""#)).unwrap_or_else(|| panic!("{id} drawn"));
        let group_start = svg[..at].rfind("<g class=\"").expect("its group");
        assert!(svg[group_start..at].contains("highlight"), "{id} is highlighted");
        assert!(svg[at..].split("</g>").next().unwrap_or("").contains(">c0<"), "{id} has its cycle");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Asynchronous connections are checked under RoboTool's one-place
/// overwriting buffer (RT-12), or the buffer `--async-buffer` assumes
/// instead; every report states which.
#[test]
fn asynchronous_connections_under_an_assumed_buffer() {
    let dir = data().join("async");
    for flag in [&[][..], &["--async-buffer", "1:overwrite"][..]] {
        let (code, v) = json(flag, &dir);
        assert_eq!(code, Some(0), "{v:#}");
        let lost = find(&v, "checks.assertions", "Lost");
        assert_eq!(lost["verdict"], "pass", "{lost:#}");
        let note = lost["notes"][0].as_str().unwrap();
        assert!(note.contains(
            "buffer 1 value; when full, a new value replaces the oldest (RoboTool's buffer between controllers"
        ));
        let out = robosim().arg("verify").args(flag).arg(&dir).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.ends_with(
                "verified 2 assertions (robotool3): 2 pass, 0 fail, 0 inconclusive, 0 unsupported\n\
                 assumed: asynchronous connections buffer 1 value; when full, a new value replaces the oldest \
                 (RoboTool's buffer between controllers, RT-12)\n"
            ),
            "{text}"
        );
    }
    // When the sender waits instead, 1 is received too.
    let (code, v) = json(&["--async-buffer", "1:block"], &dir);
    assert_eq!(code, Some(1));
    assert_eq!(find(&v, "checks.assertions", "Lost")["verdict"], "fail");
    assert_eq!(find(&v, "checks.assertions", "Kept")["verdict"], "pass");
    for bad in ["0", "1:drop", "x"] {
        let out = robosim().args(["verify", "--async-buffer", bad]).arg(&dir).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("--async-buffer"), "{bad}");
    }
}

/// RT-8: a plain assertion about a RoboChart element is reported in each
/// semantics, side by side (JSON `semantics`, `[timed]` and `[untimed]` in
/// the table); a `timed assertion` in the timed one only. RT-9: untimed,
/// `wait(2)` is SKIP, so `Fast` has `Slow`'s traces.
#[test]
fn plain_assertions_in_both_semantics() {
    let dir = data().join("untimed");
    let (code, v) = json(&[], &dir);
    assert_eq!(code, Some(1), "{v:#}");
    let got: Vec<(&str, &str, &str)> = v["assertions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| (a["name"].as_str().unwrap(), a["semantics"].as_str().unwrap(), a["verdict"].as_str().unwrap()))
        .collect();
    assert_eq!(got, [("W", "timed", "fail"), ("W", "untimed", "pass"), ("T", "timed", "pass")]);
    let out = robosim().arg("verify").arg(&dir).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("  pass") || l.starts_with("  fail")).collect();
    assert_eq!(lines.len(), 3, "{text}");
    assert!(lines[0].starts_with("  fail          W [timed]: Fast refines SlowAsFast in the traces model"), "{text}");
    assert!(lines[1].starts_with("  pass          W [untimed]: Fast refines SlowAsFast in the traces model"), "{text}");
    assert!(lines[2].starts_with("  pass          T: Slow terminates"), "{text}");
    assert!(
        text.ends_with(
            "verified 2 assertions (robotool3; 3 analyses, timed and untimed): 2 pass, 1 fail, 0 inconclusive, \
             0 unsupported\n"
        ),
        "{text}"
    );
}

/// RoboTool resolves names per Eclipse project (robotool-facts, issue 17
/// item 6): two projects declare the same `robot::Controller`, each
/// assertion file checks its own project's machine, and neither is a
/// duplicate of the other.
#[test]
fn each_project_checks_its_own_machine() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/projects");
    let out = robosim().arg("check").arg(&dir).output().unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("checked 4 files: 0 errors, 0 warnings"), "{stdout}");
    let (_, v) = json(&[], &dir);
    let a1 = find(&v, "ProjectA/robot.assertions", "A1");
    assert_eq!(a1["verdict"], "fail", "{a1:#}");
    let steps = a1["counterexample"]["steps"].as_array().unwrap();
    assert!(steps.iter().any(|s| s.to_string().contains("ProjectA/robot.rct")), "{a1:#}");
    let b1 = find(&v, "ProjectB/robot.assertions", "B1");
    assert_eq!(b1["verdict"], "pass", "{b1:#}");
}
