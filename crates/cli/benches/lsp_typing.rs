//! Typing in a generated 10,000-line model, replayed against `robosim lsp`
//! over stdio: keystroke → `publishDiagnostics` for that version, plus
//! document symbols, semantic tokens, folding ranges, hover and go to
//! definition on the same file.
//!
//! `cargo bench -p robosim-cli --bench lsp_typing` builds the binary with
//! the bench profile (the release profile's optimisations) and runs it as
//! an editor would. `ROBOSIM_BIN=path` benchmarks another binary.
//!
//! Keystrokes come every 80 ms, as from a fast typist, and the latency is
//! measured from sending a keystroke to reading the first
//! `publishDiagnostics` for its version: the whole path (JSON, applying the
//! edit, parsing, converting, publishing), with nothing hidden by a
//! debounce, which the server does not have. That first publish has the
//! syntax diagnostics of the new text and the last complete check's
//! semantic diagnostics moved along with the edits, unless the complete
//! check was ready within the server's short wait for it (then the first
//! publish is the complete one, and the only one). The complete check for
//! the version is always the last publish for it, measured in a second
//! pass with pauses long enough for it to finish.
//!
//! Then the RoboSim case of issue 22: a generated 11,641-line RoboSim model
//! (120 copies of a small module) in which one guard is toggled between
//! `not $obstacle` and `not obstacle` (an RS:SM6 violation); the latency
//! that counts is that of the complete publish, the one with RS:SM6 after
//! the bad edit and without it after the fix. The same toggles, replayed
//! in-process on a database with salsa's event log, give the number of
//! queries each keystroke re-executes. `LSP_TYPING=robosim` runs the
//! RoboSim parts only (this and the hovers below), `LSP_TYPING=hover` the
//! hovers only.
//!
//! Last, hover after a keystroke on the same RoboSim model: a space typed
//! in (or removed from) the middle copy's guard, the complete publish
//! awaited (the editor idle), then one hover on a
//! transition of the edited machine, on a transition of another machine,
//! or on another machine's name (its whole process as a tock-CSP term);
//! and the same in-process, on an `AnalysisHost`, without the server
//! around it. Each hover is the first request after its edit, so nothing
//! it reads is memoised for the new text.

use framing::{frame, read_message};
use robosim_test_support::generated;
use robosim_test_support::lsp_framing as framing;

use std::io::{BufReader, Write};
use std::process::{ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const KEYSTROKES: usize = 200;
const REQUESTS: usize = 50;

struct Client {
    stdin: ChildStdin,
    rx: Receiver<(Instant, Value)>,
    next_id: i64,
}

impl Client {
    fn send(&mut self, msg: &Value) {
        self.stdin.write_all(frame(msg).as_bytes()).expect("the server's stdin closed");
        self.stdin.flush().expect("the server's stdin closed");
    }

    /// Waits for the first message satisfying `pred`; returns when it was
    /// read.
    fn wait(&mut self, pred: impl Fn(&Value) -> bool) -> (Instant, Value) {
        loop {
            let (at, msg) = self.rx.recv_timeout(Duration::from_secs(60)).expect("the server stopped answering");
            if msg.get("method").is_some() && msg.get("id").is_some() {
                // A request from the server: answer `null`.
                self.send(&json!({"jsonrpc": "2.0", "id": msg["id"], "result": null}));
                continue;
            }
            if pred(&msg) {
                return (at, msg);
            }
        }
    }

    /// Waits for the publishes of `version` that `pred` picks until none
    /// comes for `quiet`; returns when the last one was read, and it. The
    /// complete check's publish is the last for its version (the server
    /// never sends the syntax-only one after it), so with a `quiet` longer
    /// than any check this is the complete publish.
    fn settle(&mut self, pred: impl Fn(&Value) -> bool, quiet: Duration) -> (Instant, Value) {
        let mut last = self.wait(&pred);
        loop {
            let Ok((at, msg)) = self.rx.recv_timeout(quiet) else { return last };
            if msg.get("method").is_some() && msg.get("id").is_some() {
                self.send(&json!({"jsonrpc": "2.0", "id": msg["id"], "result": null}));
            } else if pred(&msg) {
                last = (at, msg);
            }
        }
    }

    fn request(&mut self, method: &str, params: Value) -> Duration {
        self.next_id += 1;
        let id = self.next_id;
        let start = Instant::now();
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        let (at, msg) = self.wait(|m| m["id"] == id);
        assert!(msg.get("result").is_some(), "{method} failed: {msg}");
        at - start
    }
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn report(name: &str, mut samples: Vec<Duration>) {
    samples.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "{name:<40} n={:<4} p50 {:>7.2} ms   p95 {:>7.2} ms   max {:>7.2} ms",
        samples.len(),
        ms(percentile(&samples, 0.50)),
        ms(percentile(&samples, 0.95)),
        ms(*samples.last().unwrap())
    );
}

fn main() {
    // `cargo bench` passes `--bench`; plain `cargo test` runs benches as
    // tests with no such flag: keep that quick.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let bin = std::env::var("ROBOSIM_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_robosim").to_string());
    let mut child = Command::new(&bin)
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {bin}: {e}"));
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        let mut reader = BufReader::new(stdout);
        while let Some(msg) = read_message(&mut reader) {
            if tx.send((Instant::now(), msg)).is_err() {
                return;
            }
        }
    });
    let mut c = Client { stdin: child.stdin.take().unwrap(), rx, next_id: 0 };

    c.request(
        "initialize",
        json!({"capabilities": {"textDocument": {"documentSymbol": {"hierarchicalDocumentSymbolSupport": true}}}}),
    );
    c.send(&json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
    let only = std::env::var("LSP_TYPING").unwrap_or_default();
    if only.is_empty() {
        robochart(&mut c, &bin);
    }
    if only != "hover" {
        robosim_toggle(&mut c);
        robosim_queries();
    }
    robosim_hover(&mut c);
    robosim_hover_in_process();

    c.request("shutdown", Value::Null);
    c.send(&json!({"jsonrpc": "2.0", "method": "exit"}));
    let _ = child.wait();
}

/// Whether a `publishDiagnostics` message has an RS:SM6 diagnostic.
fn has_sm6(msg: &Value) -> bool {
    msg["params"]["diagnostics"].as_array().is_some_and(|a| a.iter().any(|d| d["code"] == "RS:SM6"))
}

/// The issue-22 measurement: toggling `$` in the middle copy's guard of
/// the generated RoboSim model, each edit waited for until its complete
/// publish (present after the bad edit, absent after the fix).
fn robosim_toggle(c: &mut Client) {
    let text = generated::generated_robosim(120);
    let lines: Vec<&str> = text.lines().collect();
    println!("RoboSim model: {} lines, {:.1} KB", lines.len(), text.len() as f64 / 1024.0);
    let uri = "file:///robosim-bench/generated.rst";
    c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "robosim", "version": 1, "text": text}}}));
    let published = |version: i64| {
        move |m: &Value| {
            m["method"] == "textDocument/publishDiagnostics"
                && m["params"]["uri"] == uri
                && m["params"]["version"] == version
        }
    };
    let (_, open) = c.settle(published(1), SETTLE);
    assert!(!has_sm6(&open), "the generated model has no RS:SM6");
    let middle = text.find("SimSMovement60 {").expect("copy 60");
    let at = middle + text[middle..].find("condition not $obstacle").unwrap() + "condition not ".len();
    let line = text[..at].matches('\n').count();
    let col = (at - text[..at].rfind('\n').map_or(0, |i| i + 1)) as u32;
    let pos = json!({"line": line, "character": col});
    let mut version = 1;
    let (mut first_pub, mut complete) = (Vec::new(), Vec::new());
    let mut singles = 0;
    const WARM: usize = 6;
    for k in 0..WARM + TOGGLES {
        version += 1;
        let bad = k % 2 == 0;
        let change = if bad {
            json!({"range": {"start": pos, "end": {"line": line, "character": col + 1}}, "text": ""})
        } else {
            json!({"range": {"start": pos, "end": pos}, "text": "$"})
        };
        let sent = Instant::now();
        c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}}));
        // The complete publish is the first with RS:SM6 after the bad edit,
        // the first without it after the fix: the syntax-only publish
        // carries the last check's diagnostics over (none after the good
        // text; RS:SM6, moved, after the bad one, as `$` goes in before
        // the name), so it never passes for the complete one.
        let (fast_at, msg) = c.wait(published(version));
        let (at, msg) = if has_sm6(&msg) == bad {
            singles += 1;
            (fast_at, msg)
        } else {
            c.wait(move |m| published(version)(m) && has_sm6(m) == bad)
        };
        assert_eq!(has_sm6(&msg), bad, "the complete publish after edit {k} (bad: {bad})");
        if k >= WARM {
            first_pub.push(fast_at - sent);
            complete.push(at - sent);
        }
        std::thread::sleep(Duration::from_millis(40));
        // Nothing for this version may follow the complete publish.
        while let Ok((_, m)) = c.rx.try_recv() {
            assert!(!published(version)(&m), "a publish for version {version} after its complete one");
            if m.get("method").is_some() && m.get("id").is_some() {
                c.send(&json!({"jsonrpc": "2.0", "id": m["id"], "result": null}));
            }
        }
    }
    report("RoboSim toggle → first publish", first_pub);
    report("RoboSim toggle → complete publish", complete);
    println!("  complete in the first publish (one publish only): {singles} of {}", WARM + TOGGLES);
}

/// How long no publish for a version must come before the last one is
/// taken for its complete check's: longer than any check after an edit.
const SETTLE: Duration = Duration::from_millis(250);

/// Edits of the toggle benchmark.
const TOGGLES: usize = 60;

/// The same toggles in-process, on a database that logs salsa's events:
/// the queries each keystroke re-executes, and the complete check's time
/// without the server around it.
fn robosim_queries() {
    use robosim_hir::{file_diagnostics, load_workspace, RootDatabase, RuleSet};
    use std::sync::{Arc, Mutex};
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let validated: Arc<Mutex<Vec<String>>> = Arc::default();
    let (sink, vsink) = (log.clone(), validated.clone());
    let mut db = RootDatabase::with_event_log(move |e| {
        let (sink, key) = match e.kind {
            salsa::EventKind::WillExecute { database_key } => (&sink, format!("{database_key:?}")),
            salsa::EventKind::DidValidateMemoizedValue { database_key } => (&vsink, format!("{database_key:?}")),
            _ => return,
        };
        sink.lock().unwrap().push(key.split('(').next().unwrap_or("").to_string());
    });
    let good = generated::generated_robosim(120);
    let middle = good.find("SimSMovement60 {").unwrap();
    let at = middle + good[middle..].find("not $obstacle").unwrap();
    let bad = format!("{}not obstacle{}", &good[..at], &good[at + "not $obstacle".len()..]);
    let ws = load_workspace(&mut db, [("gen.rst".to_string(), good.clone())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| !f.is_library(&db)).unwrap();
    file_diagnostics(&db, ws, file);
    let (mut counts, mut times) = (Vec::new(), Vec::new());
    let mut last = Vec::new();
    for k in 0..TOGGLES {
        let text = if k % 2 == 0 { &bad } else { &good };
        log.lock().unwrap().clear();
        validated.lock().unwrap().clear();
        let start = Instant::now();
        robosim_hir::edit_text(&mut db, file, text.clone(), robosim_hir::Durability::LOW);
        let n = file_diagnostics(&db, ws, file).iter().filter(|d| d.code == "RS:SM6").count();
        times.push(start.elapsed());
        assert_eq!(n, usize::from(k % 2 == 0));
        last = std::mem::take(&mut *log.lock().unwrap());
        counts.push(last.len());
    }
    counts.sort();
    report("RoboSim toggle, in-process complete check", times);
    println!(
        "queries re-executed per keystroke: median {}, max {}",
        counts[counts.len() / 2],
        counts[counts.len() - 1]
    );
    let mut by_name: std::collections::BTreeMap<&str, usize> = Default::default();
    for q in &last {
        *by_name.entry(q.as_str()).or_default() += 1;
    }
    println!("  last keystroke: {by_name:?}");
    // What salsa verified without re-executing: the memos of the elements
    // the edit did not touch, each checked against its inputs.
    let valid = std::mem::take(&mut *validated.lock().unwrap());
    let mut by_name: std::collections::BTreeMap<&str, usize> = Default::default();
    for q in &valid {
        *by_name.entry(q.as_str()).or_default() += 1;
    }
    let mut top: Vec<_> = by_name.into_iter().collect();
    top.sort_by_key(|(_, n)| std::cmp::Reverse(*n));
    println!("memos re-validated by the last keystroke: {} ({:?} …)", valid.len(), &top[..top.len().min(12)]);
}

/// Offsets in the generated RoboSim model for the hover benchmark: where
/// a space is typed and removed (in copy 60's guard, which keeps the
/// model well-formed, so that every hover has its term), and the hovers: a transition of the edited
/// machine, a transition of copy 30's machine, copy 30's machine name.
struct HoverSites {
    guard: usize,
    targets: [(&'static str, usize); 3],
}

fn hover_sites(text: &str) -> HoverSites {
    let find = |copy: usize, what: &str| {
        let at = text.find(&format!("stm SimSMovement{copy} {{")).unwrap();
        at + text[at..].find(what).unwrap()
    };
    HoverSites {
        guard: find(60, "condition not $obstacle") + "condition not ".len(),
        targets: [
            ("transition of the edited machine", find(60, "transition t1") + "transition t".len()),
            ("transition of another machine", find(30, "transition t1") + "transition t".len()),
            ("another machine's name", find(30, "SimSMovement30") + 3),
        ],
    }
}

fn position(text: &str, at: usize) -> Value {
    let line = text[..at].matches('\n').count();
    let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1);
    json!({"line": line, "character": col})
}

/// Hover after a keystroke over LSP (see the module's comment).
fn robosim_hover(c: &mut Client) {
    let text = generated::generated_robosim(120);
    let sites = hover_sites(&text);
    let uri = "file:///robosim-bench/hover.rst";
    c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "robosim", "version": 1, "text": text}}}));
    let published = |version: i64| {
        move |m: &Value| {
            m["method"] == "textDocument/publishDiagnostics"
                && m["params"]["uri"] == uri
                && m["params"]["version"] == version
        }
    };
    c.settle(published(1), SETTLE);
    let pos = position(&text, sites.guard);
    let mut version = 1;
    for (name, at) in sites.targets {
        let hover = json!({"textDocument": {"uri": uri}, "position": position(&text, at)});
        let mut samples = Vec::new();
        for k in 0..HOVERS + 4 {
            version += 1;
            let change = if version % 2 == 0 {
                json!({"range": {"start": pos, "end": pos}, "text": " "})
            } else {
                let end = json!({"line": pos["line"], "character": pos["character"].as_u64().unwrap() + 1});
                json!({"range": {"start": pos, "end": end}, "text": ""})
            };
            c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
                "textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}}));
            c.settle(published(version), SETTLE);
            let took = c.request("textDocument/hover", hover.clone());
            if k >= 4 {
                samples.push(took);
            }
        }
        report(&format!("RoboSim hover after a keystroke: {name}"), samples);
    }
    c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didClose", "params": {"textDocument": {"uri": uri}}}));
}

/// Hovers after each edit.
const HOVERS: usize = 40;

/// Hover after a keystroke in-process (see the module's comment): the
/// edit applied to an `AnalysisHost`, its diagnostics computed, then the
/// hover timed.
fn robosim_hover_in_process() {
    use robosim_ide::{AnalysisHost, Durability, RuleSet, TextSize};
    let good = generated::generated_robosim(120);
    let sites = hover_sites(&good);
    let spaced = format!("{} {}", &good[..sites.guard], &good[sites.guard..]);
    let mut host = AnalysisHost::new(RuleSet::Paper);
    let file = host.set_file("/w/gen.rst", good.clone(), None, Durability::LOW);
    host.analysis().diagnostics(file).unwrap();
    for (name, at) in sites.targets {
        let mut samples = Vec::new();
        for k in 0..HOVERS + 4 {
            let (text, at) = if k % 2 == 0 { (&spaced, at + usize::from(at > sites.guard)) } else { (&good, at) };
            host.set_file("/w/gen.rst", text.clone(), None, Durability::LOW);
            let a = host.analysis();
            a.diagnostics(file).unwrap();
            let start = Instant::now();
            let h = a.hover_with_diagnostics(file, TextSize::from(at as u32), &[]).unwrap();
            let took = start.elapsed();
            assert!(h.is_some_and(|h| h.markdown.contains("tock-CSP")), "{name}: no term");
            if k >= 4 {
                samples.push(took);
            }
        }
        report(&format!("in-process hover after a keystroke: {name}"), samples);
    }
}

/// Reads whatever the server still sends until it is quiet for `quiet`.
fn settle_all(c: &mut Client, quiet: Duration) {
    while let Ok((_, msg)) = c.rx.recv_timeout(quiet) {
        if msg.get("method").is_some() && msg.get("id").is_some() {
            c.send(&json!({"jsonrpc": "2.0", "id": msg["id"], "result": null}));
        }
    }
}

/// The RoboChart part: typing in the generated 10,000-line model.
fn robochart(c: &mut Client, bin: &str) {
    let text = generated::generated_model(10_000);
    let lines: Vec<&str> = text.lines().collect();
    println!("model: {} lines, {:.1} KB; server: {bin}", lines.len(), text.len() as f64 / 1024.0);
    let uri = "file:///robosim-bench/generated.rct";
    let start = Instant::now();
    c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "robochart", "version": 1, "text": text}}}));
    let published = |version: i64| {
        move |m: &Value| {
            m["method"] == "textDocument/publishDiagnostics"
                && m["params"]["uri"] == uri
                && m["params"]["version"] == version
        }
    };
    let (at, _) = c.wait(published(1));
    report("didOpen → publishDiagnostics", vec![at - start]);
    c.settle(published(1), SETTLE);

    // Type in the middle of the file, at the end of an entry action:
    // ` + count0` keystroke by keystroke, then backspace it, over and over.
    let line = lines.len() / 2 + lines[lines.len() / 2..].iter().position(|l| l.contains("entry move(")).unwrap();
    let end = lines[line].encode_utf16().count() as u32;
    let word: Vec<char> = " + count0".chars().collect();
    let mut typed = 0u32;
    let mut version = 1;
    let mut keystroke = |c: &mut Client, k: usize, version: i64| {
        let typing = (k / word.len()).is_multiple_of(2);
        let change = if typing {
            let ch = word[typed as usize % word.len()];
            let pos = json!({"line": line, "character": end + typed});
            typed += 1;
            json!({"range": {"start": pos, "end": pos}, "text": ch.to_string()})
        } else {
            typed -= 1;
            json!({"range": {"start": {"line": line, "character": end + typed}, "end": {"line": line, "character": end + typed + 1}}, "text": ""})
        };
        c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}}));
    };

    // A typist: a keystroke every 80 ms, whatever the server is doing. The
    // first publish for each version is the parse's (syntax diagnostics,
    // and the last check's semantic ones moved along).
    let mut first = Vec::with_capacity(KEYSTROKES);
    for k in 0..KEYSTROKES + 10 {
        version += 1;
        let sent = Instant::now();
        keystroke(c, k, version);
        let (at, _) = c.wait(published(version));
        // The first keystrokes warm caches up; they are not counted.
        if k >= 10 {
            first.push(at - sent);
        }
        std::thread::sleep(Duration::from_millis(80).saturating_sub(sent.elapsed()));
    }
    report("keystroke → publishDiagnostics (first)", first);

    // With a pause after each keystroke, the complete check (semantic
    // rules included) finishes and is published: the last message for
    // the version.
    settle_all(c, SETTLE);
    let mut complete = Vec::with_capacity(REQUESTS);
    for k in 0..REQUESTS {
        version += 1;
        let sent = Instant::now();
        keystroke(c, KEYSTROKES + 10 + k, version);
        let (at, _) = c.settle(published(version), SETTLE);
        complete.push(at - sent);
    }
    report("keystroke → publishDiagnostics (complete)", complete);

    let doc = json!({"textDocument": {"uri": uri}});
    for (name, method) in [
        ("textDocument/documentSymbol", "textDocument/documentSymbol"),
        ("textDocument/semanticTokens/full", "textDocument/semanticTokens/full"),
        ("textDocument/foldingRange", "textDocument/foldingRange"),
    ] {
        let mut samples = Vec::new();
        for i in 0..REQUESTS {
            // An edit first, so that nothing is memoised from the previous
            // request: each answer is computed for a new version.
            version += 1;
            let pos = json!({"line": line, "character": end});
            let text = if i.is_multiple_of(2) { " " } else { "" };
            let range = if i.is_multiple_of(2) {
                json!({"start": pos, "end": pos})
            } else {
                json!({"start": pos, "end": {"line": line, "character": end + 1}})
            };
            c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
                "textDocument": {"uri": uri, "version": version}, "contentChanges": [{"range": range, "text": text}]}}));
            // Every publish: the request then competes with nothing.
            c.settle(published(version), SETTLE);
            samples.push(c.request(method, doc.clone()));
        }
        report(&format!("{name} (after an edit)"), samples);
    }
    // Hover and definition on a variable in the middle of the file (the
    // target of `count = …` in the edited entry action, declared at the top
    // of its machine), after an edit.
    let name_col = lines[line].find("count").unwrap();
    let at_name = json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": name_col + 2}});
    let edit = |c: &mut Client, i: usize, version: i64| {
        let pos = json!({"line": line, "character": end});
        let (range, text) = if i.is_multiple_of(2) {
            (json!({"start": pos, "end": pos}), " ")
        } else {
            (json!({"start": pos, "end": {"line": line, "character": end + 1}}), "")
        };
        c.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": uri, "version": version}, "contentChanges": [{"range": range, "text": text}]}}));
    };
    for method in ["textDocument/hover", "textDocument/definition"] {
        // Once the check of the new text is published (the editor is idle).
        let mut samples = Vec::new();
        for i in 0..REQUESTS {
            version += 1;
            edit(c, i, version);
            c.settle(published(version), SETTLE);
            samples.push(c.request(method, at_name.clone()));
        }
        report(&format!("{method} (after an edit)"), samples);
        // Right after the keystroke, racing the check of the new text.
        let mut samples = Vec::new();
        for i in 0..REQUESTS {
            version += 1;
            edit(c, i, version);
            samples.push(c.request(method, at_name.clone()));
            std::thread::sleep(Duration::from_millis(300));
        }
        report(&format!("{method} (right after a keystroke)"), samples);
    }

    let mut samples = Vec::new();
    for i in 0..REQUESTS {
        let p = json!({"line": (i * 97) % lines.len(), "character": 3});
        samples.push(c.request("textDocument/selectionRange", json!({"textDocument": {"uri": uri}, "positions": [p]})));
    }
    report("textDocument/selectionRange", samples);
}
