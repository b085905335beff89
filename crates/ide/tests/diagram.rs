//! Diagrams from a snapshot: the lenses (qualified names of nested
//! elements), the diagrams selected by name or qualified name, their SVG,
//! and the error for a name the file does not declare.

use robosim_ide::diagram::DiagramKind;
use robosim_ide::{AnalysisHost, DiagramError, Durability, TextRange, TextSize};

const MODEL: &str = "package p
stm Top { initial i state S { } transition t { from i to S } }
controller C {
    stm Inner { initial i state A { state B { } initial j transition u { from j to B } } transition t { from i to A } }
    operation Op() { initial i final f transition t { from i to f } }
}
module M { robotic platform P { } cref c = C }
";

/// The range of `name`, `skip` bytes into the first `needle` of the model.
fn name_at(needle: &str, skip: u32, name: &str) -> TextRange {
    let at = MODEL.find(needle).unwrap() as u32 + skip;
    TextRange::at(TextSize::new(at), TextSize::of(name))
}

#[test]
fn lenses_name_every_machine_operation_controller_and_module() {
    let mut host = AnalysisHost::default();
    let file = host.set_file("/w/a.rct", MODEL.into(), None, Durability::LOW);
    let lenses = host.analysis().diagram_lenses(file).unwrap();
    let got: Vec<(DiagramKind, &str, TextRange)> =
        lenses.iter().map(|l| (l.kind, l.qualified_name.as_str(), l.range)).collect();
    assert_eq!(
        got,
        [
            (DiagramKind::StateMachine, "p::Top", name_at("stm Top", 4, "Top")),
            (DiagramKind::Controller, "p::C", name_at("controller C", 11, "C")),
            (DiagramKind::StateMachine, "p::C::Inner", name_at("stm Inner", 4, "Inner")),
            (DiagramKind::Operation, "p::C::Op", name_at("operation Op", 10, "Op")),
            (DiagramKind::Module, "p::M", name_at("module M", 7, "M")),
        ]
    );

    // Assertion files and the library have none.
    let checks =
        host.set_file("/w/a.rsa", "simulation S of p::M { cycleDef cycle == 1 }\n".into(), None, Durability::LOW);
    assert_eq!(host.analysis().diagram_lenses(checks).unwrap(), []);
}

#[test]
fn diagrams_by_name_with_their_svg() {
    let mut host = AnalysisHost::default();
    let file = host.set_file("/w/a.rct", MODEL.into(), None, Durability::LOW);
    let a = host.analysis();

    let all = a.diagrams(file, None).unwrap().unwrap();
    let names: Vec<&str> = all.iter().map(|d| d.diagram.qualified_name.as_str()).collect();
    assert_eq!(names, ["p::Top", "p::C", "p::C::Inner", "p::C::Op", "p::M"]);

    let inner = a.diagrams(file, Some("Inner")).unwrap().unwrap();
    assert_eq!(inner.len(), 1);
    assert_eq!(a.diagrams(file, Some("p::C::Inner")).unwrap().unwrap(), inner);
    let d = &inner[0];
    let region = d.diagram.region.as_ref().unwrap();
    let composite = region.nodes.iter().find(|n| n.name == "A").unwrap();
    assert_eq!(composite.region.nodes.iter().map(|n| n.id.as_str()).collect::<Vec<_>>(), ["A::B", "A::j"]);
    assert!(d.svg.starts_with("<svg"));
    // The SVG leads back to the source: the nested state B, line 3 (0-based).
    let b_line = d.svg.lines().find(|l| l.contains(r#"data-id="A::B""#)).unwrap();
    let col = MODEL.lines().nth(3).unwrap().find("state B").unwrap();
    assert!(b_line.contains(&format!(r#"data-line="3" data-character="{col}""#)), "{b_line}");

    let err = a.diagrams(file, Some("Missing")).unwrap().unwrap_err();
    let DiagramError::UnknownElement { element, available } = &err;
    assert_eq!(element, "Missing");
    assert_eq!(available.len(), 5);
    assert!(err.to_string().contains("`p::C::Inner`"), "{err}");
}
