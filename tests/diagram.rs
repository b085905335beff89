//! `robosim diagram` end to end: one SVG per machine, controller and module
//! in `-o DIR`, DOT with clusters, the model as JSON, `--element`, and the
//! usage errors.

use std::path::{Path, PathBuf};
use std::process::Command;

fn robosim() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_robosim-e2e"));
    c.current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."));
    c
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("robosim-diagram-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn one_svg_per_element_of_the_running_example() {
    let dir = temp_dir("paper");
    let out = robosim().args(["diagram", "-o"]).arg(&dir).arg("examples/paper/design.rct").output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let listed = String::from_utf8(out.stdout).unwrap();
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["paper_design.CFootBot.svg", "paper_design.Movement.svg", "paper_design.SMovement.svg"]);
    assert_eq!(listed.lines().count(), 3);
    let svg = std::fs::read_to_string(dir.join("paper_design.SMovement.svg")).unwrap();
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    for needle in [
        r#"data-kind="state" data-id="Moving""#,
        r#"data-kind="state" data-id="Turning""#,
        r#"data-kind="initial" data-id="i0""#,
        r#"data-kind="transition" data-id="t0""#,
        r#"data-kind="transition" data-id="t1""#,
        r#"data-kind="transition" data-id="t2""#,
        ">entry move(lv, 0); wait(1)</text>",
    ] {
        assert!(svg.contains(needle), "missing {needle}");
    }
    // Labels may be wrapped: their lines, joined, are the whole label.
    assert_eq!(label_of(&svg, "t1"), "obstacle #MBC / stop(); wait([0, 1])");
    assert_eq!(label_of(&svg, "t2"), "[since(MBC) &gt;= PI / av]");
    // The source range of t1 (line 41, 0-based 40), for click-to-source.
    assert!(svg.contains(r#"data-id="t1" data-parent="" data-source="Moving" data-target="Turning" data-start="#));
    let module = std::fs::read_to_string(dir.join("paper_design.CFootBot.svg")).unwrap();
    assert!(module.contains(r#"class="connection input async""#), "{module}");
    assert!(module.contains(">mv: Movement</text>"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The text lines of transition `id`'s group, joined with spaces.
fn label_of(svg: &str, id: &str) -> String {
    let start = svg.find(&format!(r#"data-kind="transition" data-id="{id}""#)).expect("the transition");
    let group = &svg[start..start + svg[start..].find("</g>").unwrap()];
    group
        .split("</text>")
        .filter_map(|t| t.rfind('>').map(|i| &t[i + 1..]))
        .filter(|t| !t.trim().is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn robosim_inputs_and_outputs_are_coloured() {
    let out =
        robosim().args(["diagram", "--element", "SimSMovement", "examples/paper/simulation.rst"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let svg = String::from_utf8(out.stdout).unwrap();
    assert!(svg.contains(r#"<tspan class="io-input">$obstacle</tspan>"#));
    assert!(svg.contains(r#"<tspan class="io-output">$move</tspan>"#));
    assert!(svg.contains(r#"<tspan class="exec">exec</tspan>"#));
}

#[test]
fn dot_draws_composite_states_as_clusters() {
    let out =
        robosim().args(["diagram", "--dot", "--element", "Robot", "tests/data/diagram/nested.rct"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let dot = String::from_utf8(out.stdout).unwrap();
    assert!(dot.starts_with("digraph \"nested::Robot\" {"));
    assert!(dot.contains("subgraph \"cluster_Working\" {"));
    assert!(dot.contains("subgraph \"cluster_Working::Searching\" {"));
    assert!(dot.contains("\"Working::Searching::j\" -> \"Working::Searching::Turning\" [label=\"[level > 3]\"];"));
}

#[test]
fn json_is_the_diagram_model() {
    let out = robosim().args(["diagram", "--json", "tests/data/diagram/nested.rct"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let all = v.as_array().unwrap();
    assert_eq!(all.len(), 3);
    assert_eq!(all[0]["kind"], "stateMachine");
    let working = &all[0]["region"]["nodes"][1];
    assert_eq!(working["id"], "Working");
    assert_eq!(working["actions"][0]["kind"], "entry");
    assert_eq!(working["region"]["nodes"][1]["id"], "Working::Searching");
    let w2 = &working["region"]["transitions"][1];
    assert_eq!(w2["label"], "battery?level [level < 10] / level = 0");
    assert_eq!(w2["trigger"], "battery?level");
    assert_eq!(w2["range"]["line"], 37);
    let module = &all[2];
    assert_eq!(module["kind"], "module");
    assert_eq!(module["connections"][0]["isAsync"], true);
    assert_eq!(module["connections"][0]["direction"], "input");
    assert_eq!(module["connections"][3]["direction"], "output");
}

#[test]
fn usage_errors() {
    let out = robosim().args(["diagram", "examples/paper/design.rct"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("3 diagrams") && err.contains("-o DIR"), "{err}");
    let out = robosim().args(["diagram", "--element", "Nope", "examples/paper/design.rct"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("named `Nope`"));
}

#[test]
fn the_readme_diagrams_are_up_to_date() {
    let dir = temp_dir("docs");
    let out = robosim()
        .args(["diagram", "-o"])
        .arg(&dir)
        .args(["examples/paper/design.rct", "examples/paper/simulation.rst"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/diagrams");
    for name in ["paper_design.SMovement.svg", "paper_sim.SimSMovement.svg", "paper_design.CFootBot.svg"] {
        let fresh = std::fs::read_to_string(dir.join(name)).unwrap();
        let committed = std::fs::read_to_string(docs.join(name)).unwrap();
        assert!(
            fresh == committed,
            "docs/diagrams/{name} is stale: run `robosim diagram -o docs/diagrams examples/paper/design.rct examples/paper/simulation.rst`"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
