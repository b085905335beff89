//! End-to-end protocol tests of `robosim lsp` that sessions cannot
//! express: the ordering of published diagnostics under a burst of edits,
//! the end of input, and a flood of malformed frames.

mod lsp_support;

use robosim_test_support::generated;

use std::time::Duration;

use lsp_support::{Server, TIMEOUT};
use serde_json::{json, Value};

fn open(server: &mut Server, uri: &str, text: &str) {
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "robochart", "version": 1, "text": text}}),
    );
}

/// Diagnostics as comparable values (range, code, message).
fn essentials(params: &Value) -> Vec<Value> {
    params["diagnostics"].as_array().unwrap().iter().map(|d| json!([d["range"], d["code"], d["message"]])).collect()
}

/// 500 edits sent back to back: the published versions of the document
/// never go backwards, the last one published is the last one sent, and
/// its diagnostics are those of the final text.
#[test]
fn rapid_edits_never_publish_an_older_version_after_a_newer_one() {
    let mut server = Server::start();
    server.initialize(json!({}), Value::Null);
    let uri = "file:///robosim-test/rapid.rct";
    // Big enough (1,000 lines) that checks take a while and get cancelled.
    let mut text = generated::generated_model(1_000);
    open(&mut server, uri, &text);
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": 1}}));

    // Line 0 is `package bench`: odd edits append `;` (a syntax error),
    // even edits remove it; a few edits in between retype other lines.
    let line0_len = text.lines().next().unwrap().len() as u32;
    let mut burst = String::new();
    for version in 2..=501u32 {
        let change = if version.is_multiple_of(2) {
            json!({"range": {"start": {"line": 0, "character": line0_len}, "end": {"line": 0, "character": line0_len}}, "text": ";"})
        } else {
            json!({"range": {"start": {"line": 0, "character": line0_len}, "end": {"line": 0, "character": line0_len + 1}}, "text": ""})
        };
        if version.is_multiple_of(2) {
            text.insert(line0_len as usize, ';');
        } else {
            text.remove(line0_len as usize);
        }
        let msg = json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}});
        let body = msg.to_string();
        burst.push_str(&format!("Content-Length: {}\r\n\r\n{body}", body.len()));
    }
    // All 500 in one write: they arrive faster than any check finishes.
    server.send_raw(burst.as_bytes());
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": 501}}));
    // Anything still in flight would arrive now.
    server.drain(Duration::from_millis(500));

    let publishes: Vec<&Value> = server
        .log
        .iter()
        .filter(|m| m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri)
        .collect();
    let versions: Vec<i64> = publishes.iter().map(|m| m["params"]["version"].as_i64().unwrap()).collect();
    for pair in versions.windows(2) {
        assert!(pair[0] <= pair[1], "a publish for an older version followed a newer one: {versions:?}");
    }
    assert_eq!(versions.last(), Some(&501), "{versions:?}");
    eprintln!("published {} of 501 versions", versions.len());
    let final_publish = (*publishes.last().unwrap()).clone();

    server.shutdown();

    // The final diagnostics are those of the final text, as a fresh server
    // opening that text computes them.
    let mut fresh = Server::start();
    fresh.initialize(json!({}), Value::Null);
    open(&mut fresh, uri, &text);
    fresh.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": 1}}));
    // The first publish may come from a parse alone: take the last one.
    fresh.drain(Duration::from_millis(1000));
    let reference = fresh
        .log
        .iter()
        .rfind(|m| m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri)
        .unwrap()
        .clone();
    assert_eq!(essentials(&final_publish["params"]), essentials(&reference["params"]));
    fresh.shutdown();
}

/// The end of input without `exit` ends the server with status 1.
#[test]
fn end_of_input_ends_the_server() {
    let mut server = Server::start();
    server.initialize(json!({}), Value::Null);
    server.close_stdin();
    let status = server.wait_exit(TIMEOUT).expect("the server did not exit at the end of its input");
    assert_eq!(status.code(), Some(1));
}

/// The arguments clients add to a server's command line: VS Code's
/// `TransportKind.stdio` appends `--stdio`, and some clients pass
/// `--clientProcessId`. The server accepts both and serves as usual.
#[test]
fn client_transport_arguments_are_accepted() {
    for args in [&["--stdio"][..], &["--clientProcessId=4242"], &["--stdio", "--clientProcessId", "7"]] {
        let mut server = Server::start_with_args(args);
        let init = server.initialize(json!({}), Value::Null);
        assert!(!init["result"]["capabilities"]["hoverProvider"].is_null(), "{args:?}: {init}");
        server.shutdown();
    }
}

/// `exit` before `initialize`: status 1, at once.
#[test]
fn exit_before_initialize() {
    let mut server = Server::start();
    server.notify("exit", Value::Null);
    let status = server.wait_exit(TIMEOUT).expect("the server did not exit");
    assert_eq!(status.code(), Some(1));
}

/// A flood of malformed frames of every kind, interleaved with valid
/// requests: every valid request is answered, and the server lives on.
#[test]
fn malformed_flood_is_survived() {
    let mut server = Server::start();
    server.initialize(json!({}), Value::Null);
    let uri = "file:///robosim-test/flood.rct";
    open(&mut server, uri, "stm M { initial i }");
    // Bodies that are not valid messages, correctly framed…
    let bodies: [&[u8]; 7] = [
        b"{{{{{",
        b"\xff\xfe",
        b"null",
        b"{\"jsonrpc\":\"2.0\",\"method\":5,\"id\":true}",
        b"{\"jsonrpc\":\"2.0\",\"method\":\"textDocument/didChange\"}",
        b"{\"jsonrpc\":\"2.0\",\"id\":1,\"method\":\"initialize\",\"params\":\"x\"}",
        b"{\"jsonrpc\":\"2.0\",\"id\":2,\"method\":\"textDocument/foldingRange\",\"params\":[1,2]}",
    ];
    let mut garbage: Vec<Vec<u8>> = bodies
        .iter()
        .map(|b| {
            let mut f = format!("Content-Length: {}\r\n\r\n", b.len()).into_bytes();
            f.extend_from_slice(b);
            f
        })
        .collect();
    // …and headers that are not valid (the reader resynchronises at the
    // next `Content-Length`).
    garbage.push(b"Content-Length: -1\r\n\r\n".to_vec());
    garbage.push(b"Content-Length: abc\r\n\r\n{}".to_vec());
    garbage.push(b"Content-Type: text/plain\r\n\r\n".to_vec());
    garbage.push(b"\r\n\r\n".to_vec());
    let mut ids = Vec::new();
    for round in 0..50 {
        server.send_raw(&garbage[round % garbage.len()]);
        ids.push(server.request("textDocument/foldingRange", json!({"textDocument": {"uri": uri}})));
    }
    for id in ids {
        let res = server.expect(&json!({"id": id}));
        assert!(res.get("result").is_some(), "{res}");
    }
    assert!(server.alive());
    server.shutdown();
}

/// A file nested as deep as the parser allows, and deeper: diagnostics,
/// symbols and tokens are served, and the server lives on.
#[test]
fn deep_nesting_does_not_crash_the_server() {
    let mut server = Server::start();
    server.initialize(json!({}), Value::Null);
    let uri = "file:///robosim-test/deep.rct";
    let mut text = String::from("stm M { initial i ");
    for _ in 0..2000 {
        text.push_str("state S { ");
    }
    open(&mut server, uri, &text);
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": 1}}));
    for method in ["textDocument/documentSymbol", "textDocument/semanticTokens/full", "textDocument/foldingRange"] {
        let res = server.call(method, json!({"textDocument": {"uri": uri}}));
        assert!(res.get("result").is_some(), "{method}: {res}");
    }
    // The complete check, too.
    server.drain(Duration::from_millis(500));
    assert!(server.alive());
    server.shutdown();
}

/// Whether a publish has RS:SM6 (the rule the toggle below breaks).
fn has_sm6(msg: &Value) -> bool {
    msg["params"]["diagnostics"].as_array().is_some_and(|a| a.iter().any(|d| d["code"] == "RS:SM6"))
}

/// Toggles `$` in one guard of a generated RoboSim model (`not $obstacle`
/// ↔ `not obstacle`, an RS:SM6 violation) `edits` times, each waited for
/// until its complete publish, and returns every publish of the document
/// by version.
fn toggle(server: &mut Server, edits: i64) -> Vec<(i64, Vec<Value>)> {
    let uri = "file:///robosim-test/toggle.rst";
    let text = generated::generated_robosim(20);
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "robosim", "version": 1, "text": text}}),
    );
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": 1}}));
    server.drain(Duration::from_millis(300));
    let at = text.find("stm SimSMovement10 {").unwrap();
    let at = at + text[at..].find("not $obstacle").unwrap() + "not ".len();
    let line = text[..at].matches('\n').count();
    let col = at - text[..at].rfind('\n').unwrap() - 1;
    let pos = json!({"line": line, "character": col});
    for version in 2..2 + edits {
        let bad = version % 2 == 0;
        let change = if bad {
            json!({"range": {"start": pos, "end": {"line": line, "character": col + 1}}, "text": ""})
        } else {
            json!({"range": {"start": pos, "end": pos}, "text": "$"})
        };
        server.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}),
        );
        // The complete publish: RS:SM6 after the bad edit, none after the
        // fix (the syntax-only one carries the last check's over).
        let deadline = std::time::Instant::now() + TIMEOUT;
        loop {
            let msg = server.expect(
                &json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri, "version": version}}),
            );
            if has_sm6(&msg) == bad {
                break;
            }
            assert!(std::time::Instant::now() < deadline, "no complete publish for version {version}");
        }
    }
    server.drain(Duration::from_millis(300));
    let mut by_version: Vec<(i64, Vec<Value>)> = Vec::new();
    for m in server.log.iter().filter(|m| m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri)
    {
        let v = m["params"]["version"].as_i64().unwrap();
        match by_version.last_mut() {
            Some((last, list)) if *last == v => list.push(m.clone()),
            _ => by_version.push((v, vec![m.clone()])),
        }
    }
    by_version
}

/// After an edit the complete check's publish is the last for the version:
/// a syntax-only publish (the parse's, with the last check's diagnostics
/// carried over) may come first, when the check is not done within the
/// server's short wait, never after it.
#[test]
fn the_complete_publish_of_an_edit_comes_last() {
    let mut server = Server::start();
    server.initialize(json!({}), Value::Null);
    let by_version = toggle(&mut server, 20);
    assert_eq!(by_version.iter().map(|(v, _)| *v).collect::<Vec<_>>(), (1..22).collect::<Vec<_>>());
    for (version, publishes) in by_version.iter().skip(1) {
        let bad = version % 2 == 0;
        assert!(matches!(publishes.len(), 1 | 2), "version {version}: {} publishes", publishes.len());
        let complete: Vec<bool> = publishes.iter().map(|m| has_sm6(m) == bad).collect();
        assert_eq!(complete.last(), Some(&true), "version {version}: the last publish is not the complete one");
        assert_eq!(complete.iter().filter(|c| **c).count(), 1, "version {version}: {publishes:?}");
    }
    server.shutdown();
}

/// When the complete check is done within the server's wait for it, it is
/// the only publish of the version: the syntax-only one is not sent (here
/// with a wait long enough for any check of this small model).
#[test]
fn a_check_done_within_the_wait_is_published_alone() {
    let mut server = Server::start_with_env(&[], &[("ROBOSIM_SYNTAX_HOLD_MS", "5000")]);
    server.initialize(json!({}), Value::Null);
    let by_version = toggle(&mut server, 10);
    for (version, publishes) in &by_version {
        assert_eq!(publishes.len(), 1, "version {version}: {publishes:?}");
        if *version > 1 {
            assert_eq!(has_sm6(&publishes[0]), version % 2 == 0, "version {version}");
        }
    }
    server.shutdown();
}
