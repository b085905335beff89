//! Replays the LSP sessions in `tests/lsp/*.json` against the real
//! `robosim lsp` binary over stdio.
//!
//! A session is a JSON object:
//!
//! - `files`: model files to create under a fresh workspace folder
//!   (`$ROOT`, or `$ROOT_URI` as a URI, in any string or object key of the
//!   session);
//! - `replies`: results for the server's requests to the client, by method
//!   (default `null`);
//! - `steps`, in order:
//!   - `{"send": message}` sends a client message;
//!   - `{"raw": "text"}` sends bytes as they are (malformed input);
//!   - `{"expect": pattern}` waits for a server message matching the
//!     pattern (see `lsp_support::matches`; `"$contains:…"` matches a
//!     string containing the rest). Server messages that arrive meanwhile
//!     wait for later expectations, so notifications may come in any order;
//!     with `"snapshot": "title"`, the message's `result` (or `params`) is
//!     added to the session's snapshot `tests/lsp/NAME.snap`;
//!   - `{"expect_none": pattern, "within_ms": N}`: no such message arrives
//!     from now on within N ms;
//!   - `{"write": {"path": p, "text": t}}` and `{"delete": p}` change the
//!     workspace on disk;
//! - `exit_code`: the status the server must end with after the steps
//!   (default: the harness sends `shutdown` and `exit` and expects 0).
//!
//! Refresh the snapshots with `UPDATE_EXPECT=1 cargo test -p robosim-cli
//! --test lsp_sessions` and review the diff.

mod lsp_support;

use std::path::{Path, PathBuf};
use std::time::Duration;

use lsp_support::{Server, TIMEOUT};
use serde_json::Value;

fn substitute(v: &Value, root: &Path) -> Value {
    let text = |s: &str| s.replace("$ROOT_URI", &lsp_support::uri(root)).replace("$ROOT", &root.to_string_lossy());
    match v {
        Value::String(s) => Value::String(text(s)),
        Value::Array(a) => Value::Array(a.iter().map(|x| substitute(x, root)).collect()),
        // Keys too: workspace edits are maps from URIs.
        Value::Object(o) => Value::Object(o.iter().map(|(k, x)| (text(k), substitute(x, root))).collect()),
        other => other.clone(),
    }
}

/// `"$contains:…"` patterns become `"$any"` when they hold, so the shared
/// matcher can compare the rest.
fn resolve_contains(pattern: &Value, actual: &Value) -> Value {
    match (pattern, actual) {
        (Value::String(p), Value::String(a)) if p.starts_with("$contains:") => {
            if a.contains(&p["$contains:".len()..]) {
                Value::String("$any".into())
            } else {
                pattern.clone()
            }
        }
        (Value::Object(p), Value::Object(a)) => Value::Object(
            p.iter()
                .map(|(k, pv)| (k.clone(), a.get(k).map(|av| resolve_contains(pv, av)).unwrap_or_else(|| pv.clone())))
                .collect(),
        ),
        (Value::Array(p), Value::Array(a)) if p.len() == a.len() => {
            Value::Array(p.iter().zip(a).map(|(p, a)| resolve_contains(p, a)).collect())
        }
        _ => pattern.clone(),
    }
}

fn has_contains(p: &Value) -> bool {
    match p {
        Value::String(s) => s.starts_with("$contains:"),
        Value::Array(a) => a.iter().any(has_contains),
        Value::Object(o) => o.values().any(has_contains),
        _ => false,
    }
}

fn expect(server: &mut Server, pattern: &Value, timeout: Duration) -> Option<Value> {
    if !has_contains(pattern) {
        return server.try_expect(pattern, timeout);
    }
    // Re-check every message with the pattern resolved against it.
    let deadline = std::time::Instant::now() + timeout;
    loop {
        if let Some(i) = server.pending.iter().position(|m| lsp_support::matches(&resolve_contains(pattern, m), m)) {
            return Some(server.pending.remove(i));
        }
        let left = deadline.checked_duration_since(std::time::Instant::now())?;
        server.drain(left.min(Duration::from_millis(20)));
    }
}

fn run_session(path: &Path) -> String {
    let name = path.file_stem().unwrap().to_string_lossy().into_owned();
    let session: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let root = lsp_support::temp_dir(&name);
    let session = substitute(&session, &root);
    if let Some(files) = session.get("files").and_then(Value::as_object) {
        for (rel, text) in files {
            let p = root.join(rel);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(&p, text.as_str().unwrap()).unwrap();
        }
    }
    let mut server = Server::start();
    if let Some(replies) = session.get("replies").and_then(Value::as_object) {
        server.replies = replies.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    }
    let mut snapshot = String::new();
    for (i, step) in session["steps"].as_array().unwrap().iter().enumerate() {
        let at = format!("{name}: step {i}: {step}");
        if let Some(msg) = step.get("send") {
            server.send(msg);
        } else if let Some(raw) = step.get("raw") {
            server.send_raw(raw.as_str().unwrap().as_bytes());
        } else if let Some(pattern) = step.get("expect") {
            let msg = expect(&mut server, pattern, TIMEOUT).unwrap_or_else(|| {
                panic!(
                    "{at}\nnot received within {TIMEOUT:?}; pending:\n{}",
                    server.pending.iter().map(|m| m.to_string()).collect::<Vec<_>>().join("\n")
                )
            });
            if let Some(title) = step.get("snapshot").and_then(Value::as_str) {
                let body = msg.get("result").or_else(|| msg.get("params")).cloned().unwrap_or(Value::Null);
                let body = compact(&body, 0).replace(&lsp_support::uri(&root), "$ROOT_URI");
                snapshot.push_str(&format!("== {title}\n{body}\n"));
            }
        } else if let Some(pattern) = step.get("expect_none") {
            // Only what arrives from now on counts.
            let ms = step.get("within_ms").and_then(Value::as_u64).unwrap_or(500);
            let seen = server.log.len();
            server.drain(Duration::from_millis(ms));
            if let Some(msg) =
                server.log[seen..].iter().find(|m| lsp_support::matches(&resolve_contains(pattern, m), m))
            {
                panic!("{at}\nunexpected message: {msg}");
            }
        } else if let Some(w) = step.get("write") {
            std::fs::write(root.join(w["path"].as_str().unwrap()), w["text"].as_str().unwrap()).unwrap();
        } else if let Some(p) = step.get("delete") {
            std::fs::remove_file(root.join(p.as_str().unwrap())).unwrap();
        } else if step.get("comment").is_none() {
            panic!("{at}: unknown step");
        }
    }
    match session.get("exit_code").and_then(Value::as_i64) {
        Some(code) => {
            let status = server.wait_exit(TIMEOUT).unwrap_or_else(|| panic!("{name}: the server did not exit"));
            assert_eq!(status.code(), Some(code as i32), "{name}: exit status");
        }
        None => server.shutdown(),
    }
    let _ = std::fs::remove_dir_all(&root);
    snapshot
}

/// JSON for snapshots: values that fit on a line stay on one, arrays of
/// numbers (semantic tokens) go five to a line.
fn compact(v: &Value, indent: usize) -> String {
    let flat = v.to_string();
    if flat.len() + indent <= 100 {
        return flat;
    }
    let pad = " ".repeat(indent + 2);
    match v {
        Value::Array(a) if a.iter().all(Value::is_number) => {
            let rows: Vec<String> = a
                .chunks(5)
                .map(|c| format!("{pad}{}", c.iter().map(Value::to_string).collect::<Vec<_>>().join(", ")))
                .collect();
            format!("[\n{}\n{}]", rows.join(",\n"), " ".repeat(indent))
        }
        Value::Array(a) => {
            let rows: Vec<String> = a.iter().map(|x| format!("{pad}{}", compact(x, indent + 2))).collect();
            format!("[\n{}\n{}]", rows.join(",\n"), " ".repeat(indent))
        }
        Value::Object(o) => {
            let rows: Vec<String> = o
                .iter()
                .map(|(k, x)| format!("{pad}{}: {}", Value::from(k.as_str()), compact(x, indent + 2)))
                .collect();
            format!("{{\n{}\n{}}}", rows.join(",\n"), " ".repeat(indent))
        }
        _ => flat,
    }
}

fn sessions() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("lsp");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn sessions_replay() {
    let files = sessions();
    assert!(!files.is_empty(), "no sessions in tests/lsp");
    for path in files {
        let snapshot = run_session(&path);
        let snap = path.with_extension("snap");
        if !snapshot.is_empty() || snap.exists() {
            expect_test::expect_file![snap].assert_eq(&snapshot);
        }
    }
}
