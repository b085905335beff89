//! Graphviz DOT output: composite states as nested clusters, so that
//! `dot -Tsvg` draws the same hierarchy.

use std::fmt::Write as _;

use crate::model::{Diagram, NodeKind, Region};

fn q(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The diagram as a DOT digraph.
pub fn render_dot(d: &Diagram) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "digraph {} {{", q(&d.qualified_name));
    let _ =
        writeln!(out, "  label={}; labelloc=t; compound=true;", q(&format!("{} {}", d.kind.word(), d.qualified_name)));
    out.push_str("  node [fontname=\"monospace\", fontsize=12]; edge [fontname=\"monospace\", fontsize=11];\n");
    if let Some(r) = &d.region {
        region(&mut out, r, 1);
    }
    for b in &d.blocks {
        let label = match &b.reference {
            Some(r) => format!("«{}»\\n{}: {r}", b.kind, b.id),
            None => format!("«{}»\\n{}", b.kind, b.id),
        };
        let style = if b.kind == "boundary" { ", style=dashed" } else { "" };
        let _ = writeln!(out, "  {} [shape=box, label=\"{}\"{style}];", q(&b.id), label.replace('"', "\\\""));
    }
    for c in &d.connections {
        let mut attrs = vec![format!("label={}", q(&c.label))];
        if c.is_async {
            attrs.push("style=dashed".into());
        }
        if c.bidirectional {
            attrs.push("dir=both".into());
        }
        match c.direction.as_str() {
            "input" => attrs.push("color=\"#1565c0\"".into()),
            "output" => attrs.push("color=\"#c05600\"".into()),
            _ => {}
        }
        let _ = writeln!(out, "  {} -> {} [{}];", q(&c.from), q(&c.to), attrs.join(", "));
    }
    out.push_str("}\n");
    out
}

fn region(out: &mut String, r: &Region, depth: usize) {
    let pad = "  ".repeat(depth);
    for n in &r.nodes {
        let id = q(&n.id);
        match n.kind {
            NodeKind::Initial => {
                let _ = writeln!(out, "{pad}{id} [shape=point, width=0.15, label=\"\"];");
            }
            NodeKind::Junction => {
                let _ = writeln!(out, "{pad}{id} [shape=circle, width=0.2, label=\"\"];");
            }
            NodeKind::ProbabilisticJunction => {
                let _ = writeln!(out, "{pad}{id} [shape=circle, width=0.25, label=\"P\"];");
            }
            NodeKind::Final => {
                let _ = writeln!(out, "{pad}{id} [shape=doublecircle, width=0.2, label=\"\"];");
            }
            NodeKind::State if n.region.is_empty() => {
                let mut label = n.name.clone();
                for a in &n.actions {
                    label.push_str(&format!("\\n{} {}", a.kind, a.text));
                }
                let _ =
                    writeln!(out, "{pad}{id} [shape=box, style=rounded, label={}];", q(&label).replace("\\\\n", "\\n"));
            }
            NodeKind::State => {
                let mut label = n.name.clone();
                for a in &n.actions {
                    label.push_str(&format!("\\n{} {}", a.kind, a.text));
                }
                let _ = writeln!(out, "{pad}subgraph {} {{", q(&format!("cluster_{}", n.id)));
                let _ = writeln!(out, "{pad}  label={}; style=rounded;", q(&label).replace("\\\\n", "\\n"));
                // An invisible anchor for transitions to and from the state.
                let _ = writeln!(out, "{pad}  {id} [shape=point, style=invis, width=0];");
                region(out, &n.region, depth + 1);
                let _ = writeln!(out, "{pad}}}");
            }
        }
    }
    for t in &r.transitions {
        let (Some(s), Some(tg)) = (&t.source, &t.target) else { continue };
        let _ = writeln!(out, "{pad}{} -> {} [label={}];", q(s), q(tg), q(&t.label));
    }
}
