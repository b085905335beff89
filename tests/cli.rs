//! End-to-end tests of the `robosim` binary: exit codes, the JSON contract
//! and the human rendering.

use std::path::{Path, PathBuf};
use std::process::Command;

fn robosim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robosim-e2e"))
}

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data").join(p)
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

#[test]
fn examples_check_clean() {
    let out = robosim().arg("check").arg(examples()).output().unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("0 errors, 0 warnings"), "{stdout}");
}

#[test]
fn json_contract() {
    let dir = data("broken");
    let out = robosim().args(["check", "--format", "json"]).arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // README.txt is not a model file: two files found.
    assert_eq!(v["files"], 2);
    let diags = v["diagnostics"].as_array().unwrap();
    let machine = dir.join("machine.rct").to_string_lossy().into_owned();
    let first = &diags[0];
    assert_eq!(first["file"], machine.as_str());
    assert_eq!(first["code"], "SYN-01");
    assert_eq!(first["severity"], "error");
    assert_eq!(first["message"], "`;` separates statements and cannot end them: remove this `;`");
    assert_eq!(
        first["range"],
        serde_json::json!({"start": {"line": 2, "character": 23}, "end": {"line": 2, "character": 24}})
    );
    assert_eq!(first["related"], serde_json::json!([]));
    let second = &diags[1];
    assert_eq!(second["message"], "expected `to` after the source of transition `t`, found `S`");
    assert_eq!(second["range"]["start"], serde_json::json!({"line": 3, "character": 24}));
    // UTF-16 columns: line 1 of unicode.rct is `stm N { state é }`; the
    // stray `é` is at character 14 and one UTF-16 unit wide.
    let uni =
        diags.iter().find(|d| d["file"].as_str().unwrap().ends_with("unicode.rct") && d["code"] == "SYN-01").unwrap();
    assert_eq!(
        uni["range"],
        serde_json::json!({"start": {"line": 1, "character": 14}, "end": {"line": 1, "character": 15}})
    );
}

#[test]
fn human_output_renders_excerpts() {
    let out = robosim().args(["check", "--color", "never"]).arg(data("broken/machine.rct")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("error[SYN-01]: expected `to` after the source of transition `t`, found `S`"), "{s}");
    assert!(s.contains("machine.rct:4:25"), "{s}");
    assert!(s.contains("transition t { from i S }"), "{s}");
    assert!(s.contains("checked 1 file: 2 errors, 0 warnings"), "{s}");
    assert!(!s.contains('\u{1b}'), "no colour when not asked");
}

#[test]
fn usage_and_io_errors_exit_2() {
    let out = robosim().args(["check", "no/such/path.rct"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.trim(), "robosim: cannot read `no/such/path.rct`: no such file or directory");
    let out = robosim().args(["check", "--format", "xml", "."]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = robosim().arg("check").arg(data("broken/README.txt")).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = robosim().arg("check").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn parse_tree() {
    let out = robosim().args(["parse", "--tree"]).arg(data("broken/machine.rct")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.starts_with("SOURCE_FILE@0..89\n  STATE_MACHINE@0..88\n    STM_KW@0..3 \"stm\"\n"), "{s}");
    assert!(s.contains("error 55..56: `;` separates statements"), "{s}");
}

#[test]
fn invalid_utf8_is_reported_not_fatal() {
    let dir = std::env::temp_dir().join(format!("robosim-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bin.rct");
    std::fs::write(&f, b"interface I { event e }\n\xff\xfe\x00junk").unwrap();
    let out = robosim().args(["check", "--format", "json"]).arg(&f).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let msgs: Vec<&str> = v["diagnostics"].as_array().unwrap().iter().map(|d| d["message"].as_str().unwrap()).collect();
    assert!(msgs[0].starts_with("the file is not valid UTF-8"), "{msgs:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An assertion file's names that denote nothing are LNK-01 errors of
/// `check`, on the name that fails; `verify` refuses the same assertions
/// (the two read names through the same resolution), and decides the one
/// whose names resolve.
#[test]
fn assertion_names_check_and_verify_agree() {
    let dir = data("assertion_names");
    let out = robosim().args(["check", "--format", "json"]).arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let found: Vec<(String, serde_json::Value, String)> = v["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (d["code"].as_str().unwrap().to_string(), d["range"].clone(), d["message"].as_str().unwrap().to_string())
        })
        .collect();
    let at = |line: u32, start: u32, end: u32| serde_json::json!({"start": {"line": line, "character": start}, "end": {"line": line, "character": end}});
    let expected = [
        (at(0, 14, 21), "cannot resolve `Nothing`: no simulation, module, controller, state machine, operation or `csp` block of that name is in scope"),
        (at(1, 17, 18), "cannot resolve state `Q` in `M`"),
        (at(2, 47, 54), "cannot resolve constant `nothere` of the state machine `M`: neither it, its interfaces nor its parts declare one"),
    ];
    assert_eq!(found.len(), expected.len(), "{found:#?}");
    for ((code, range, message), (want_range, want)) in found.iter().zip(&expected) {
        assert_eq!((code.as_str(), range, message.as_str()), ("LNK-01", want_range, *want));
    }
    let out = robosim().args(["verify", "--format", "json"]).arg(&dir).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for a in v["assertions"].as_array().unwrap() {
        let want = if a["name"] == "G" { "pass" } else { "unsupported" };
        assert_eq!(a["verdict"], want, "{a:#}");
    }
}
