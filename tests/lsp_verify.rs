//! Verification in the editor, end to end over stdio: code lenses on
//! assertions, simulations and modules; `workspace/executeCommand`
//! `robosim.verify` with `$/progress`; the results as `RS-VERIFY`
//! diagnostics, lens titles and hovers; stale results cleared by edits;
//! cancellation (by `window/workDoneProgress/cancel`, by an edit and by a
//! new request for the same assertion) of a check whose state space is
//! huge; and the `robosim.verify.*` settings.

mod lsp_support;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use lsp_support::{Server, TIMEOUT};
use serde_json::{json, Value};

/// A workspace folder with the paper's GT-3 design (`design.rct`) and its
/// assertions (`checks.rsa`), plus `extra` files.
fn gt3_workspace(name: &str, extra: &[(&str, &str)]) -> PathBuf {
    let root = lsp_support::temp_dir(name);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/verify/gt3");
    for f in ["design.rct", "checks.rsa"] {
        std::fs::copy(data.join(f), root.join(f)).unwrap();
    }
    for (path, text) in extra {
        std::fs::write(root.join(path), text).unwrap();
    }
    root
}

fn big_workspace(name: &str) -> PathBuf {
    let root = lsp_support::temp_dir(name);
    std::fs::write(root.join("design.rct"), robosim_engine::generate::design(8, 6)).unwrap();
    std::fs::write(
        root.join("checks.rsa"),
        "simulation S of Mod { cycleDef cycle == 1 }\nassertion A : S is schedulable\n",
    )
    .unwrap();
    root
}

/// Capabilities of a client with work-done progress, code lens refresh
/// and Markdown hovers.
fn full_caps() -> Value {
    json!({
        "window": {"workDoneProgress": true},
        "workspace": {"codeLens": {"refreshSupport": true}},
        "textDocument": {"hover": {"contentFormat": ["markdown", "plaintext"]}},
    })
}

/// Starts a server on `root` and waits until its files are loaded.
fn start(root: &Path, caps: Value, options: Value, files: usize) -> Server {
    let mut server = Server::start();
    let init = server.call(
        "initialize",
        json!({
            "capabilities": caps,
            "initializationOptions": options,
            "workspaceFolders": [{"uri": lsp_support::uri(root), "name": "root"}],
        }),
    );
    let caps = &init["result"]["capabilities"];
    assert_eq!(caps["executeCommandProvider"]["commands"], json!(["robosim.verify"]), "{init}");
    assert_eq!(caps["codeLensProvider"], json!({"resolveProvider": false}), "{init}");
    server.notify("initialized", json!({}));
    server
        .expect(&json!({"method": "window/logMessage", "params": {"message": format!("loaded {files} model files")}}));
    server
}

fn file_uri(root: &Path, name: &str) -> String {
    lsp_support::uri(&root.join(name))
}

/// The line and UTF-16 column of the first `needle` in `text`.
fn position(text: &str, needle: &str) -> (u64, u64) {
    let at = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in the text"));
    let before = &text[..at];
    let line = before.matches('\n').count() as u64;
    let col = before.rsplit('\n').next().unwrap().encode_utf16().count() as u64;
    (line, col)
}

/// A range from `needle`'s first occurrence (`skip` bytes into it) of
/// `len` characters, as LSP JSON.
fn range_of(text: &str, needle: &str, skip: usize, len: u64) -> Value {
    let (line, col) = position(text, needle);
    let col = col + skip as u64;
    json!({"start": {"line": line, "character": col}, "end": {"line": line, "character": col + len}})
}

/// The code lenses of `uri`: (range, title, arguments).
fn lenses(server: &mut Server, uri: &str) -> Vec<(Value, String, Value)> {
    let res = server.call("textDocument/codeLens", json!({"textDocument": {"uri": uri}}));
    res["result"]
        .as_array()
        .unwrap_or_else(|| panic!("{res}"))
        .iter()
        .map(|l| {
            assert_eq!(l["command"]["command"], "robosim.verify", "{l}");
            (l["range"].clone(), l["command"]["title"].as_str().unwrap().to_string(), l["command"]["arguments"].clone())
        })
        .collect()
}

fn title_at(server: &mut Server, uri: &str, arg: &Value) -> String {
    let all = lenses(server, uri);
    all.iter().find(|(_, _, args)| args[1] == *arg).unwrap_or_else(|| panic!("no lens for {arg} in {all:?}")).1.clone()
}

/// Runs `robosim.verify` with `[uri, what]`: the request is answered at
/// once, with `null`.
fn verify(server: &mut Server, uri: &str, what: Value) {
    let res = server.call("workspace/executeCommand", json!({"command": "robosim.verify", "arguments": [uri, what]}));
    assert_eq!(res.get("result"), Some(&Value::Null), "{res}");
}

/// Waits for the server to create a progress token for a verification.
fn created_token(server: &mut Server) -> Value {
    loop {
        // The workspace's loading has a token of its own.
        let msg = server.expect(&json!({"method": "window/workDoneProgress/create"}));
        let token = msg["params"]["token"].clone();
        if token.as_str().is_some_and(|t| t.starts_with("robosim/verify/")) {
            return token;
        }
    }
}

fn progress(server: &mut Server, token: &Value, kind: &str) -> Value {
    server.expect(&json!({"method": "$/progress", "params": {"token": token, "value": {"kind": kind}}}))
}

/// The next publish for `uri` whose diagnostics satisfy `pred`.
fn publish_where(server: &mut Server, uri: &str, pred: impl Fn(&[Value]) -> bool) -> Vec<Value> {
    let deadline = Instant::now() + TIMEOUT;
    loop {
        let pattern = json!({"method": "textDocument/publishDiagnostics", "params": {"uri": uri}});
        let left = deadline.checked_duration_since(Instant::now()).expect("no such publish");
        let msg =
            server.try_expect(&pattern, left).unwrap_or_else(|| panic!("no such publish; log:\n{:#?}", server.log));
        let diags = msg["params"]["diagnostics"].as_array().unwrap().clone();
        if pred(&diags) {
            return diags;
        }
    }
}

fn verify_diags(diags: &[Value]) -> Vec<&Value> {
    diags.iter().filter(|d| d["code"] == "RS-VERIFY").collect()
}

fn hover(server: &mut Server, uri: &str, (line, character): (u64, u64)) -> String {
    let res = server.call(
        "textDocument/hover",
        json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
    );
    res["result"]["contents"]["value"].as_str().unwrap_or_else(|| panic!("{res}")).to_string()
}

/// The hover at `pos` once it contains `text` (a check's result arrives
/// in the background).
fn hover_when(server: &mut Server, uri: &str, pos: (u64, u64), text: &str) -> String {
    let deadline = Instant::now() + TIMEOUT;
    loop {
        server.drain(Duration::from_millis(100));
        let h = hover(server, uri, pos);
        if h.contains(text) {
            return h;
        }
        assert!(Instant::now() < deadline, "{h}");
    }
}

/// The GT-3 design from the lenses to the verdict: lenses on the
/// simulation, the assertions and the module; a run with progress; the
/// failure as a diagnostic with the counterexample in the design; the lens
/// titles and the hover; a pass; and an edit of the design that clears it
/// all (while opening it does not).
#[test]
fn verify_an_assertion_from_its_lens() {
    let root = gt3_workspace("verify-gt3", &[]);
    let checks = file_uri(&root, "checks.rsa");
    let design = file_uri(&root, "design.rct");
    let checks_text = std::fs::read_to_string(root.join("checks.rsa")).unwrap();
    let design_text = std::fs::read_to_string(root.join("design.rct")).unwrap();
    let mut server = start(&root, full_caps(), Value::Null, 2);

    // Lenses, before any run.
    let sim = json!({"simulation": "P1"});
    assert_eq!(
        lenses(&mut server, &checks),
        vec![
            (
                range_of(&checks_text, "P1 of", 0, 2),
                "▶ Check schedulability (cycle 1)".to_string(),
                json!([checks, sim])
            ),
            (range_of(&checks_text, "S1 :", 0, 2), "▶ Verify".to_string(), json!([checks, "S1"])),
            (range_of(&checks_text, "S2 :", 0, 2), "▶ Verify".to_string(), json!([checks, "S2"])),
        ]
    );
    // The module the simulation is of gets its lens, which runs the
    // simulation's check in the assertion file.
    assert_eq!(
        lenses(&mut server, &design),
        vec![(
            range_of(&design_text, "module CFootBot", 7, 8),
            "▶ Check schedulability (cycle 1)".to_string(),
            json!([checks, sim])
        )]
    );

    // S1 fails: progress, then the diagnostic.
    verify(&mut server, &checks, json!("S1"));
    let token = created_token(&mut server);
    let begin = progress(&mut server, &token, "begin");
    assert_eq!(begin["params"]["value"]["title"], "Verifying assertion S1", "{begin}");
    assert_eq!(begin["params"]["value"]["cancellable"], true, "{begin}");
    let end = progress(&mut server, &token, "end");
    assert!(end["params"]["value"]["message"].as_str().unwrap().starts_with("fail · 23 states"), "{end}");
    let diags = publish_where(&mut server, &checks, |d| !verify_diags(d).is_empty());
    let failed = verify_diags(&diags);
    assert_eq!(failed.len(), 1, "{diags:?}");
    let d = failed[0];
    assert_eq!(d["range"], range_of(&checks_text, "S1 :", 0, 2));
    assert_eq!(d["severity"], 1);
    assert_eq!(d["message"], "CFootBot cannot be scheduled in cycles of period 1");
    let related = d["relatedInformation"].as_array().unwrap();
    assert!(related.iter().all(|r| r["location"]["uri"] == design), "{related:?}");
    let first = &related[0];
    assert_eq!(
        first["message"], "cycle 0, t = 0: (moveCall.1.0) — mv::sm: calls the platform operation in Moving",
        "{related:?}"
    );
    // `move(lv, 0)` in Moving's entry action.
    assert_eq!(first["location"]["range"], range_of(&design_text, "move(lv, 0)", 0, 11));
    let stuck = related.last().unwrap();
    assert!(stuck["message"].as_str().unwrap().contains("must call move(0, 15) now"), "{stuck}");
    assert_eq!(stuck["location"]["range"], range_of(&design_text, "move(0, av)", 0, 11));
    // The lenses are refreshed and show the verdict.
    server.expect(&json!({"method": "workspace/codeLens/refresh"}));
    assert_eq!(title_at(&mut server, &checks, &json!("S1")), "✘ fail — re-run");
    assert_eq!(title_at(&mut server, &checks, &json!("S2")), "▶ Verify");

    // The hover on the name: verdict, statistics, semantics, reason,
    // domains and the counterexample by cycle.
    let h = hover(&mut server, &checks, position(&checks_text, "S1 :"));
    assert!(h.contains("fail · 23 states, 25 transitions, "), "{h}");
    assert!(h.contains(" · robotool3"), "{h}");
    assert!(h.contains("CFootBot cannot be scheduled in cycles of period 1"), "{h}");
    assert!(h.contains("domains: core_nat = "), "{h}");
    assert!(h.contains("```text\ncycle 0  t = 0\n  read   i_obstacle.true\n"), "{h}");
    assert!(
        h.contains("  design (moveCall.1.0)  mv::sm: calls the platform operation in Moving  --> design.rct:33:15\n"),
        "{h}"
    );
    assert!(h.contains("stuck: mv::sm (in Turning) must call move(0, 15) now"), "{h}");

    // S2 (`is not schedulable` with period 2) passes: no diagnostic.
    verify(&mut server, &checks, json!("S2"));
    let token = created_token(&mut server);
    let end = progress(&mut server, &token, "end");
    assert!(end["params"]["value"]["message"].as_str().unwrap().starts_with("pass · "), "{end}");
    server.drain(Duration::from_millis(300));
    let title = title_at(&mut server, &checks, &json!("S2"));
    assert!(title.starts_with("✔ pass · 21 states · ") && title.ends_with(" ms"), "{title}");
    assert!(hover(&mut server, &checks, position(&checks_text, "S2 :")).contains("pass · 21 states"));

    // The simulation's lens runs both; one fails, so it shows a failure,
    // and so does the module's.
    verify(&mut server, &checks, sim.clone());
    let token = created_token(&mut server);
    let begin = progress(&mut server, &token, "begin");
    assert_eq!(begin["params"]["value"]["title"], "Verifying schedulability of P1", "{begin}");
    let end = progress(&mut server, &token, "end");
    assert!(end["params"]["value"]["message"].as_str().unwrap().contains("(2 assertions)"), "{end}");
    server.drain(Duration::from_millis(300));
    assert_eq!(title_at(&mut server, &checks, &sim), "✘ fail — re-run");
    assert_eq!(title_at(&mut server, &design, &sim), "✘ fail — re-run");

    // Opening the design changes nothing…
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": design, "languageId": "robochart", "version": 1, "text": design_text}}),
    );
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": design, "version": 1}}));
    assert_eq!(title_at(&mut server, &checks, &json!("S1")), "✘ fail — re-run");
    // …but editing it makes the results stale: the diagnostic is cleared
    // and the lenses start over.
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": design, "version": 2}, "contentChanges": [
            {"range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}}, "text": "// edited\n"}]}),
    );
    publish_where(&mut server, &checks, |d| verify_diags(d).is_empty());
    assert_eq!(title_at(&mut server, &checks, &json!("S1")), "▶ Verify");
    assert_eq!(title_at(&mut server, &checks, &sim), "▶ Check schedulability (cycle 1)");
    assert!(!hover(&mut server, &checks, position(&checks_text, "S1 :")).contains("Last verification"));
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// A simulation that no assertion is about is checked as `S is
/// schedulable`, with the diagnostic on the simulation's name; an
/// assertion the engine cannot check (here, about an unknown element) gets
/// an information diagnostic; and a
/// client without work-done progress gets no progress, but the results.
#[test]
fn ad_hoc_schedulability_and_unsupported_assertions() {
    let extra = "simulation P2 of paper_design::CFootBot { cycleDef cycle == 1 }\n\
                 assertion D1 : Nope is deadlock-free\n";
    let root = gt3_workspace("verify-adhoc", &[("extra.rsa", extra)]);
    // The constants get their values in the design: the simulation needs
    // no assertion to give them.
    let design_text = std::fs::read_to_string(root.join("design.rct"))
        .unwrap()
        .replace("const PI : real, lv : real, av : real", "const PI : real = 45, lv : real = 1, av : real = 15");
    std::fs::write(root.join("design.rct"), design_text).unwrap();
    let uri = file_uri(&root, "extra.rsa");
    let mut server = start(&root, json!({}), Value::Null, 3);
    let design = file_uri(&root, "design.rct");
    let args: Vec<Value> = lenses(&mut server, &design).into_iter().map(|l| l.2).collect();
    assert_eq!(
        args,
        [json!([file_uri(&root, "checks.rsa"), {"simulation": "P1"}]), json!([uri, {"simulation": "P2"}])]
    );

    verify(&mut server, &uri, json!({"simulation": "P2"}));
    let diags = publish_where(&mut server, &uri, |d| !verify_diags(d).is_empty());
    let d = verify_diags(&diags);
    assert_eq!(d.len(), 1, "{diags:?}");
    assert_eq!(d[0]["range"], range_of(extra, "P2 of", 0, 2));
    assert_eq!(d[0]["message"], "CFootBot cannot be scheduled in cycles of period 1");
    assert_eq!(d[0]["severity"], 1);
    assert_eq!(title_at(&mut server, &uri, &json!({"simulation": "P2"})), "✘ fail — re-run");

    verify(&mut server, &uri, json!("D1"));
    let diags = publish_where(&mut server, &uri, |d| verify_diags(d).len() == 2);
    let info = verify_diags(&diags).into_iter().find(|d| d["severity"] == 3).expect("an information diagnostic");
    assert_eq!(info["range"], range_of(extra, "D1 :", 0, 2));
    assert_eq!(info["message"], "`Nope` is not a simulation, module, controller or machine");
    assert_eq!(
        title_at(&mut server, &uri, &json!("D1")),
        "unsupported: `Nope` is not a simulation, module, controller or machine"
    );
    assert!(!server.log.iter().any(|m| m["method"] == "window/workDoneProgress/create" || m["method"] == "$/progress"));

    // Wrong arguments are refused.
    for args in [json!([uri]), json!([uri, "Nope"]), json!([uri, {"simulation": "Nope"}]), json!([design, "S1"])] {
        let res = server.call("workspace/executeCommand", json!({"command": "robosim.verify", "arguments": args}));
        assert_eq!(res["error"]["code"], -32602, "{args}: {res}");
    }
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// Starts the check of the huge design and waits until it reports
/// progress: returns its token.
fn start_big_check(server: &mut Server, checks: &str) -> Value {
    verify(server, checks, json!("A"));
    let token = created_token(server);
    progress(server, &token, "begin");
    let report = progress(server, &token, "report");
    assert!(report["params"]["value"]["message"].as_str().unwrap().contains(" states, "), "{report}");
    token
}

/// Waits for the end of `token`'s progress; it must say `cancelled` and
/// arrive within 2 s of `since`.
fn expect_cancelled_end(server: &mut Server, token: &Value, since: Instant) {
    let pattern = json!({"method": "$/progress", "params": {"token": token, "value": {"kind": "end"}}});
    let end = server.try_expect(&pattern, Duration::from_secs(2)).expect("no progress end within 2 s of the cancel");
    assert!(since.elapsed() < Duration::from_secs(2), "{:?}", since.elapsed());
    eprintln!("progress end {:?} after the cancel", since.elapsed());
    assert_eq!(end["params"]["value"]["message"], "cancelled", "{end}");
}

/// Nothing is published for a cancelled check, and its lens starts over.
fn expect_no_verdict(server: &mut Server, checks: &str) {
    server.drain(Duration::from_millis(500));
    let verdicts: Vec<&Value> = server
        .log
        .iter()
        .filter(|m| m["method"] == "textDocument/publishDiagnostics")
        .filter(|m| m["params"]["diagnostics"].as_array().unwrap().iter().any(|d| d["code"] == "RS-VERIFY"))
        .collect();
    assert!(verdicts.is_empty(), "{verdicts:?}");
    assert_eq!(title_at(server, checks, &json!("A")), "▶ Verify");
}

/// `window/workDoneProgress/cancel` stops a check that would run for
/// minutes; a new request for the same assertion stops the one running.
#[test]
fn cancel_a_long_check_from_its_progress() {
    let root = big_workspace("verify-cancel");
    let checks = file_uri(&root, "checks.rsa");
    let mut server = start(&root, full_caps(), Value::Null, 2);

    let first = start_big_check(&mut server, &checks);
    assert!(title_at(&mut server, &checks, &json!("A")).starts_with("⏳ verifying"));
    // Again: the first run stops, the second goes on.
    let cancelled_at = Instant::now();
    let second = start_big_check(&mut server, &checks);
    assert_ne!(first, second);
    expect_cancelled_end(&mut server, &first, cancelled_at);
    progress(&mut server, &second, "report");

    let cancelled_at = Instant::now();
    server.notify("window/workDoneProgress/cancel", json!({"token": second}));
    expect_cancelled_end(&mut server, &second, cancelled_at);
    expect_no_verdict(&mut server, &checks);
    // The server still answers, at once.
    let t = Instant::now();
    lenses(&mut server, &checks);
    assert!(t.elapsed() < Duration::from_secs(2));
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// An edit of any file of the workspace stops a running check: requests
/// are answered meanwhile, and the edit's diagnostics are not held up.
#[test]
fn an_edit_cancels_a_long_check() {
    let root = big_workspace("verify-edit");
    let checks = file_uri(&root, "checks.rsa");
    let design = file_uri(&root, "design.rct");
    let text = std::fs::read_to_string(root.join("design.rct")).unwrap();
    let mut server = start(&root, full_caps(), Value::Null, 2);
    let token = start_big_check(&mut server, &checks);

    // Other requests are answered while the check runs.
    let t = Instant::now();
    let res = server.call("textDocument/documentSymbol", json!({"textDocument": {"uri": design}}));
    assert!(res["result"].is_array(), "{res}");
    assert!(t.elapsed() < Duration::from_secs(2), "{:?}", t.elapsed());
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": design, "languageId": "robochart", "version": 1, "text": text}}),
    );
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": design, "version": 1}}));
    // Opening it changed nothing: the check goes on.
    progress(&mut server, &token, "report");

    let edited_at = Instant::now();
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": design, "version": 2}, "contentChanges": [
            {"range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}}, "text": "// edited\n"}]}),
    );
    server.expect(&json!({"method": "textDocument/publishDiagnostics", "params": {"uri": design, "version": 2}}));
    assert!(edited_at.elapsed() < Duration::from_secs(2), "{:?}", edited_at.elapsed());
    expect_cancelled_end(&mut server, &token, edited_at);
    expect_no_verdict(&mut server, &checks);
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// `robosim.verify.timeoutSeconds` ends a check as inconclusive (a warning
/// with the reason), from the initialization options.
#[test]
fn timeout_setting_gives_an_inconclusive_warning() {
    let root = big_workspace("verify-timeout");
    let checks = file_uri(&root, "checks.rsa");
    let mut server = start(&root, json!({}), json!({"verify": {"timeoutSeconds": 1}}), 2);
    verify(&mut server, &checks, json!("A"));
    let diags = publish_where(&mut server, &checks, |d| !verify_diags(d).is_empty());
    let d = verify_diags(&diags)[0];
    assert_eq!(d["severity"], 2, "{d}");
    assert_eq!(d["message"], "time budget of 1.000 s ran out before a verdict");
    assert_eq!(
        title_at(&mut server, &checks, &json!("A")),
        "⚠ inconclusive: time budget of 1.000 s ran out before a verdict"
    );
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// `robosim.verify.semantics` from `workspace/configuration`: the paper's
/// semantics, named in the hover, with its own counterexample.
#[test]
fn semantics_setting_from_the_configuration() {
    let root = gt3_workspace("verify-paper", &[]);
    let checks = file_uri(&root, "checks.rsa");
    let checks_text = std::fs::read_to_string(root.join("checks.rsa")).unwrap();
    let mut server = Server::start();
    server.replies = vec![("workspace/configuration".into(), json!([{"verify": {"semantics": "paper2019"}}]))];
    server.initialize(
        json!({"workspace": {"configuration": true}}),
        json!([{"uri": lsp_support::uri(&root), "name": "root"}]),
    );
    server.expect(&json!({"method": "workspace/configuration"}));
    server.expect(&json!({"method": "window/logMessage", "params": {"message": "loaded 2 model files"}}));
    verify(&mut server, &checks, json!("S1"));
    publish_where(&mut server, &checks, |d| !verify_diags(d).is_empty());
    let h = hover(&mut server, &checks, position(&checks_text, "S1 :"));
    assert!(h.contains("fail · 30 states, 30 transitions, ") && h.contains(" · paper2019"), "{h}");
    assert!(h.contains("  read   obstacleU.true\n") && h.contains("  write  moveU.true.1.0\n"), "{h}");

    // Back to RoboTool 3's through `workspace/didChangeConfiguration`.
    server.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"robosim": {"verify": {"semantics": "robotool3"}}}}),
    );
    verify(&mut server, &checks, json!("S1"));
    let h = hover_when(&mut server, &checks, position(&checks_text, "S1 :"), " · robotool3");
    assert!(h.contains("fail · 23 states"), "{h}");
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// After a failed check, `robosim/diagram` draws its counterexample on the
/// machine's diagram: the states and transitions it passes through are
/// highlighted with their cycles.
#[test]
fn a_failed_check_is_drawn_on_the_diagram() {
    let root = gt3_workspace("verify-diagram", &[]);
    let checks = file_uri(&root, "checks.rsa");
    let design = file_uri(&root, "design.rct");
    let mut server = start(&root, full_caps(), Value::Null, 2);
    let diagram = |server: &mut Server| {
        let res = server.call("robosim/diagram", json!({"textDocument": {"uri": design}, "element": "SMovement"}));
        res["result"]["diagrams"][0]["svg"].as_str().unwrap_or_else(|| panic!("{res}")).to_string()
    };
    assert!(!diagram(&mut server).contains(" highlight\""), "no marks before a check");
    verify(&mut server, &checks, json!("S1"));
    let token = created_token(&mut server);
    progress(&mut server, &token, "end");
    let svg = diagram(&mut server);
    for id in ["Moving", "t1", "Turning"] {
        let at = svg.find(&format!(r#"data-id="{id}""#)).unwrap_or_else(|| panic!("{id} drawn"));
        let group = svg[..at].rfind("<g class=\"").expect("its group");
        assert!(svg[group..at].contains("highlight"), "{id} is highlighted");
    }
    assert!(svg.contains(">c0<"), "the cycle is written");
    server.shutdown();
}

/// `robosim.verify.asyncBuffer`: controllers connected asynchronously are
/// checked under the buffer it names, and without it under RoboTool's
/// (RT-12); the hover states which.
#[test]
fn async_buffer_setting() {
    let root = lsp_support::temp_dir("verify-async");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/verify/async");
    for f in ["model.rct", "checks.assertions"] {
        std::fs::copy(data.join(f), root.join(f)).unwrap();
    }
    let checks = file_uri(&root, "checks.assertions");
    let checks_text = std::fs::read_to_string(root.join("checks.assertions")).unwrap();
    let mut server = start(&root, json!({}), json!({"verify": {"asyncBuffer": "1:block"}}), 2);
    verify(&mut server, &checks, json!("Lost"));
    // The sender waits: 1 is received too.
    let h = hover_when(&mut server, &checks, position(&checks_text, "Lost :"), "fail");
    assert!(h.contains("buffer 1 value; when full, the sender waits (assumed with `--async-buffer`"), "{h}");
    // No buffer set: RoboTool's.
    server
        .notify("workspace/didChangeConfiguration", json!({"settings": {"robosim": {"verify": {"asyncBuffer": ""}}}}));
    verify(&mut server, &checks, json!("Lost"));
    let h = hover_when(&mut server, &checks, position(&checks_text, "Lost :"), "pass");
    assert!(
        h.contains("when full, a new value replaces the oldest (RoboTool's buffer between controllers, RT-12)"),
        "{h}"
    );
    assert!(title_at(&mut server, &checks, &json!("Lost")).starts_with("✔ pass · 6 states"));
    server.shutdown();
    let _ = std::fs::remove_dir_all(&root);
}

/// The server reads a workspace folder holding two RoboTool projects (a
/// `.project` each) as RoboTool does: names resolve within a project, so
/// `Controller` in project B's assertions means project B's machine, and
/// verifying it gives project B's verdict.
#[test]
fn names_resolve_within_each_project() {
    let root = lsp_support::temp_dir("projects");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/projects");
    for p in ["ProjectA", "ProjectB"] {
        std::fs::create_dir_all(root.join(p)).unwrap();
        for f in [".project", "robot.rct", "robot.assertions"] {
            std::fs::copy(data.join(p).join(f), root.join(p).join(f)).unwrap();
        }
    }
    let mut server = start(&root, full_caps(), json!({}), 4);
    let uri = file_uri(&root, "ProjectB/robot.assertions");
    let text = std::fs::read_to_string(root.join("ProjectB/robot.assertions")).unwrap();
    let (line, character) = position(&text, "Controller is");
    let res = server.call(
        "textDocument/definition",
        json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character + 1}}),
    );
    let target = res["result"].to_string();
    assert!(target.contains("ProjectB/robot.rct"), "{res}");
    assert!(!target.contains("ProjectA"), "{res}");
    let lens = lenses(&mut server, &uri);
    let (_, _, arg) = lens.iter().find(|(_, title, _)| title.contains("Verify")).expect("a verify lens").clone();
    verify(&mut server, &uri, arg[1].clone());
    let token = created_token(&mut server);
    progress(&mut server, &token, "end");
    let title = title_at(&mut server, &uri, &arg[1]);
    assert!(title.contains("pass"), "{title}");
}
