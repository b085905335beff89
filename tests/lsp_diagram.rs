//! Diagrams in the editor, end to end over stdio: the "◇ Show diagram"
//! code lenses (for clients that run `robosim.showDiagram` themselves, and
//! merged with the verification lenses), and the `robosim/diagram` request:
//! the model and the SVG of the paper's SMovement, all the diagrams of a
//! file, a model that follows the edits, and the errors for an unknown
//! element, an unknown file and missing parameters.

mod lsp_support;

use std::path::{Path, PathBuf};

use lsp_support::Server;
use serde_json::{json, Value};

/// A workspace folder with a copy of `examples/paper`.
fn paper_workspace(name: &str) -> PathBuf {
    let root = lsp_support::temp_dir(name);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/paper");
    for entry in std::fs::read_dir(&data).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, root.join(path.file_name().unwrap())).unwrap();
        }
    }
    root
}

/// The client capabilities of an editor that runs `robosim.showDiagram`
/// itself (as the VS Code extension declares).
fn diagram_caps() -> Value {
    json!({"experimental": {"commands": {"commands": ["robosim.showDiagram"]}}})
}

/// Starts a server on `root` with `caps` and waits until its model files
/// are loaded.
fn start(root: &Path, caps: Value) -> Server {
    let mut server = Server::start();
    let init = server.initialize(caps, json!([{"uri": lsp_support::uri(root), "name": "root"}]));
    // The command runs in the client: the server does not claim it.
    assert_eq!(init["result"]["capabilities"]["executeCommandProvider"]["commands"], json!(["robosim.verify"]));
    assert_eq!(init["result"]["capabilities"]["codeLensProvider"], json!({"resolveProvider": false}));
    server.expect(&json!({"method": "window/logMessage", "params": {"message": "loaded 5 model files"}}));
    server
}

fn file_uri(root: &Path, name: &str) -> String {
    lsp_support::uri(&root.join(name))
}

/// The line and UTF-16 column of the first `needle` in `text`, `skip`
/// bytes into it.
fn position(text: &str, needle: &str, skip: usize) -> (u64, u64) {
    let at = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in the text")) + skip;
    let before = &text[..at];
    let line = before.matches('\n').count() as u64;
    let col = before.rsplit('\n').next().unwrap().encode_utf16().count() as u64;
    (line, col)
}

/// The LSP range of `len` characters at `needle` (`skip` bytes into it).
fn range_of(text: &str, needle: &str, skip: usize, len: u64) -> Value {
    let (line, col) = position(text, needle, skip);
    json!({"start": {"line": line, "character": col}, "end": {"line": line, "character": col + len}})
}

/// The code lenses of `uri`: (range, title, command, arguments).
fn lenses(server: &mut Server, uri: &str) -> Vec<(Value, String, String, Value)> {
    let res = server.call("textDocument/codeLens", json!({"textDocument": {"uri": uri}}));
    res["result"]
        .as_array()
        .unwrap_or_else(|| panic!("{res}"))
        .iter()
        .map(|l| {
            let c = &l["command"];
            (
                l["range"].clone(),
                c["title"].as_str().unwrap().to_string(),
                c["command"].as_str().unwrap().to_string(),
                c["arguments"].clone(),
            )
        })
        .collect()
}

fn diagram(server: &mut Server, params: Value) -> Value {
    server.call("robosim/diagram", params)
}

const SHOW: &str = "robosim.showDiagram";
const TITLE: &str = "◇ Show diagram";

/// A lens on each machine, controller and module, with `[uri, qualified
/// name]`, after the module's schedulability lens; in RoboSim files too;
/// none in assertion files, and none for a client that does not run the
/// command.
#[test]
fn lenses_open_the_diagram_of_each_machine_controller_and_module() {
    let root = paper_workspace("diagram-lenses");
    let design = file_uri(&root, "design.rct");
    let text = std::fs::read_to_string(root.join("design.rct")).unwrap();
    let mut server = start(&root, diagram_caps());

    let all = lenses(&mut server, &design);
    let diagram = |needle: &str, skip: usize, name: &str, qualified: &str| {
        (
            range_of(&text, needle, skip, name.len() as u64),
            TITLE.to_string(),
            SHOW.to_string(),
            json!([design, qualified]),
        )
    };
    assert_eq!(all.len(), 6, "{all:#?}");
    assert_eq!(all[0], diagram("stm SMovement", 4, "SMovement", "paper_design::SMovement"));
    assert_eq!(all[1], diagram("controller Movement", 11, "Movement", "paper_design::Movement"));
    // The module's schedulability lenses (one per simulation of it) come
    // first, at the same place.
    for l in &all[2..5] {
        assert_eq!(l.0, range_of(&text, "module CFootBot", 7, 8));
        assert_eq!(l.2, "robosim.verify");
    }
    assert_eq!(all[5], diagram("module CFootBot", 7, "CFootBot", "paper_design::CFootBot"));

    // RoboSim machines get theirs.
    let sim = file_uri(&root, "simulation.rst");
    let sim_text = std::fs::read_to_string(root.join("simulation.rst")).unwrap();
    let sim_lenses = lenses(&mut server, &sim);
    let machine =
        sim_lenses.iter().find(|l| l.3[1] == "paper_sim::SimSMovement").unwrap_or_else(|| panic!("{sim_lenses:#?}"));
    assert_eq!(machine.0, range_of(&sim_text, "stm SimSMovement", 4, 12));
    assert_eq!((machine.1.as_str(), machine.2.as_str()), (TITLE, SHOW));
    assert!(sim_lenses.iter().all(|l| l.2 == SHOW), "{sim_lenses:#?}");

    // Assertion files have no diagrams.
    let checks = file_uri(&root, "assertions.rsa");
    assert!(lenses(&mut server, &checks).iter().all(|l| l.2 == "robosim.verify"));
    server.shutdown();

    // A client that does not declare the command gets only the verification
    // lens: a lens it could not run would fail when clicked.
    let mut server = start(&root, json!({}));
    let all = lenses(&mut server, &design);
    assert_eq!(all.len(), 3, "{all:#?}");
    assert!(all.iter().all(|l| l.2 == "robosim.verify"), "{all:#?}");
    server.shutdown();
}

/// `robosim/diagram` for SMovement: its states, transitions and ranges, and
/// the SVG with the source ranges of its groups; the qualified name selects
/// the same diagram; no element gives every diagram of the file.
#[test]
fn the_diagram_of_smovement() {
    let root = paper_workspace("diagram-request");
    let design = file_uri(&root, "design.rct");
    let text = std::fs::read_to_string(root.join("design.rct")).unwrap();
    let mut server = start(&root, json!({}));

    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "SMovement"}));
    let result = &res["result"];
    assert_eq!(result["uri"], json!(design), "{res}");
    let diagrams = result["diagrams"].as_array().unwrap_or_else(|| panic!("{res}"));
    assert_eq!(diagrams.len(), 1);
    let model = &diagrams[0]["model"];
    assert_eq!(model["kind"], "stateMachine");
    assert_eq!(model["name"], "SMovement");
    assert_eq!(model["qualifiedName"], "paper_design::SMovement");
    assert_eq!(model["file"], json!(root.join("design.rct").to_string_lossy()));
    assert_eq!(model["robosim"], false);
    let (line, character) = position(&text, "stm SMovement", 4);
    assert_eq!(model["nameRange"]["line"], line);
    assert_eq!(model["nameRange"]["character"], character);

    let nodes = model["region"]["nodes"].as_array().unwrap();
    let summary: Vec<(&str, &str)> =
        nodes.iter().map(|n| (n["id"].as_str().unwrap(), n["kind"].as_str().unwrap())).collect();
    assert_eq!(summary, [("i0", "initial"), ("Moving", "state"), ("Turning", "state")]);
    let moving = &nodes[1];
    let (line, character) = position(&text, "state Moving", 6);
    assert_eq!(
        (moving["nameRange"]["line"].as_u64(), moving["nameRange"]["character"].as_u64()),
        (Some(line), Some(character))
    );
    assert_eq!(
        moving["actions"],
        json!([{"kind": "entry", "text": "move(lv, 0); wait(1)", "range": moving["actions"][0]["range"]}])
    );
    let transitions: Vec<(&str, &str, &str, &str)> = model["region"]["transitions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            (
                t["id"].as_str().unwrap(),
                t["source"].as_str().unwrap(),
                t["target"].as_str().unwrap(),
                t["label"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        transitions,
        [
            ("t0", "i0", "Moving", ""),
            ("t1", "Moving", "Turning", "obstacle #MBC / stop(); wait([0, 1])"),
            ("t2", "Turning", "Moving", "[since(MBC) >= PI / av]"),
        ]
    );

    // The SVG: a standalone document whose groups lead back to the source.
    let svg = diagrams[0]["svg"].as_str().unwrap();
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""), "{svg}");
    assert!(svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains(r#"data-name="paper_design::SMovement""#));
    let (line, character) = position(&text, "state Moving", 0);
    let moving_group = svg
        .lines()
        .find(|l| l.contains(r#"data-id="Moving""#))
        .unwrap_or_else(|| panic!("no group for Moving in\n{svg}"));
    assert!(moving_group.contains(&format!(r#"data-line="{line}" data-character="{character}""#)), "{moving_group}");
    assert!(svg.contains(r#"data-kind="transition" data-id="t1""#));
    assert!(svg.contains(">Turning</text>"));

    // The qualified name selects the same diagram.
    let by_qualified =
        diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "paper_design::SMovement"}));
    assert_eq!(by_qualified["result"], res["result"]);

    // No element: every diagram of the file, in source order.
    let every = diagram(&mut server, json!({"textDocument": {"uri": design}}));
    let names: Vec<(&str, &str)> = every["result"]["diagrams"]
        .as_array()
        .unwrap_or_else(|| panic!("{every}"))
        .iter()
        .map(|d| (d["model"]["kind"].as_str().unwrap(), d["model"]["name"].as_str().unwrap()))
        .collect();
    assert_eq!(names, [("stateMachine", "SMovement"), ("controller", "Movement"), ("module", "CFootBot")]);
    let module = &every["result"]["diagrams"][2];
    assert!(module["svg"].as_str().unwrap().contains(r#"data-kind="connection""#));
    server.shutdown();
}

/// The diagram follows the open buffer: a state renamed in an edit is
/// renamed in the next answer, before anything is saved.
#[test]
fn the_diagram_follows_the_edits() {
    let root = paper_workspace("diagram-edits");
    let design = file_uri(&root, "design.rct");
    let text = std::fs::read_to_string(root.join("design.rct")).unwrap();
    let mut server = start(&root, json!({}));
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": design, "languageId": "robochart", "version": 1, "text": text}}),
    );
    let edited = text.replace("Turning", "Spinning");
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": design, "version": 2}, "contentChanges": [{"text": edited}]}),
    );
    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "SMovement"}));
    let model = &res["result"]["diagrams"][0]["model"];
    let ids: Vec<&str> = model["region"]["nodes"]
        .as_array()
        .unwrap_or_else(|| panic!("{res}"))
        .iter()
        .map(|n| n["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["i0", "Moving", "Spinning"]);
    assert!(res["result"]["diagrams"][0]["svg"].as_str().unwrap().contains(">Spinning</text>"));

    // A machine renamed away: the old name is an unknown element now.
    let edited = edited.replace("stm SMovement", "stm SMove").replace("sref sm = SMovement", "sref sm = SMove");
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": design, "version": 3}, "contentChanges": [{"text": edited}]}),
    );
    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "paper_design::SMovement"}));
    assert_eq!(res["error"]["code"], -32602, "{res}");
    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "paper_design::SMove"}));
    assert_eq!(res["result"]["diagrams"][0]["model"]["name"], "SMove", "{res}");
    server.shutdown();
}

/// Errors: an element the file does not declare, a file the server does
/// not know, and missing parameters are `InvalidParams`, and the server
/// keeps serving.
#[test]
fn unknown_elements_and_files_are_errors() {
    let root = paper_workspace("diagram-errors");
    let design = file_uri(&root, "design.rct");
    let mut server = start(&root, json!({}));

    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "Nowhere"}));
    assert_eq!(res["error"]["code"], -32602, "{res}");
    let message = res["error"]["message"].as_str().unwrap();
    assert!(message.contains("`Nowhere`"), "{message}");
    assert!(message.contains("`paper_design::SMovement`"), "the message lists what there is: {message}");
    assert!(res.get("result").is_none());

    // Assertion files declare no diagrams.
    let checks = file_uri(&root, "assertions.rsa");
    let res = diagram(&mut server, json!({"textDocument": {"uri": checks}, "element": "SMovement"}));
    assert_eq!(res["error"]["code"], -32602, "{res}");
    let res = diagram(&mut server, json!({"textDocument": {"uri": checks}}));
    assert_eq!(res["result"]["diagrams"], json!([]), "{res}");

    let missing = file_uri(&root, "missing.rct");
    let res = diagram(&mut server, json!({"textDocument": {"uri": missing}, "element": "SMovement"}));
    assert_eq!(res["error"]["code"], -32602, "{res}");
    assert!(res["error"]["message"].as_str().unwrap().contains("missing.rct"), "{res}");

    let res = diagram(&mut server, json!({"element": "SMovement"}));
    assert_eq!(res["error"]["code"], -32602, "{res}");

    // Still serving.
    let res = diagram(&mut server, json!({"textDocument": {"uri": design}, "element": "CFootBot"}));
    assert_eq!(res["result"]["diagrams"][0]["model"]["kind"], "module", "{res}");
    server.shutdown();
}
