//! The diagram model and its layout on the paper's running example
//! (`examples/paper`), the lawn mower and every machine, operation,
//! controller and module of `../shared/corpus`:
//!
//! - the model is snapshotted (one line per node, transition, block and
//!   connection);
//! - every node and transition the file declares is in the model, at the
//!   right level, and every transition is drawn;
//! - in the layout, every shape lies inside its parent state's box (below
//!   its header), and no two texts (state names, actions, labels) overlap.

use std::collections::BTreeSet;

use expect_test::expect_file;
use robosim_diagram::layout::{layout, Edge, Laid, Rect, Shape};
use robosim_diagram::model::{Diagram, Region};
use robosim_diagram::{dump, file_diagrams};
use robosim_hir::defs::{file_defs, DefKind};
use robosim_hir::FileKind;
use robosim_hir::{load_workspace, RootDatabase, RuleSet};

mod support;
use support::{files_in, root};

fn count_region(r: &Region) -> (usize, usize) {
    let mut nodes = r.nodes.len();
    let mut transitions = r.transitions.len();
    for n in &r.nodes {
        let (a, b) = count_region(&n.region);
        nodes += a;
        transitions += b;
    }
    (nodes, transitions)
}

fn texts_of_shape(s: &Shape, out: &mut Vec<(String, Rect)>) {
    for t in &s.texts {
        out.push((t.text.clone(), t.rect));
    }
    for c in &s.children {
        texts_of_shape(c, out);
    }
    for e in &s.edges {
        texts_of_edge(e, out);
    }
}

fn texts_of_edge(e: &Edge, out: &mut Vec<(String, Rect)>) {
    for t in &e.texts {
        out.push((t.text.clone(), t.rect));
    }
}

fn count_edges(edges: &[Edge], shapes: &[Shape]) -> usize {
    edges.len() + shapes.iter().map(|s| count_edges(&s.edges, &s.children)).sum::<usize>()
}

/// Every child inside its parent's box, below the header; returns problems.
fn check_nesting(s: &Shape, what: &str, problems: &mut Vec<String>) {
    let inner_top = s.separator.unwrap_or(s.rect.y);
    for c in &s.children {
        let inside = Rect { x: s.rect.x, y: inner_top, w: s.rect.w, h: s.rect.y + s.rect.h - inner_top };
        if !inside.contains(&c.rect) {
            problems.push(format!("{what}: {:?} is not inside {:?}", c.subject, s.subject));
        }
        check_nesting(c, what, problems);
    }
    for t in &s.texts {
        if !s.rect.contains(&t.rect) {
            problems.push(format!("{what}: text `{}` sticks out of {:?}", t.text, s.subject));
        }
    }
    for e in &s.edges {
        for t in &e.texts {
            if !s.rect.contains(&t.rect) {
                problems.push(format!("{what}: label `{}` sticks out of {:?}", t.text, s.subject));
            }
        }
    }
}

fn check_layout(d: &Diagram, laid: &Laid, problems: &mut Vec<String>) {
    let what = format!("{} {}", d.file, d.qualified_name);
    let mut texts = Vec::new();
    for s in &laid.shapes {
        texts_of_shape(s, &mut texts);
        check_nesting(s, &what, problems);
    }
    for e in &laid.edges {
        texts_of_edge(e, &mut texts);
    }
    for (i, (a, ra)) in texts.iter().enumerate() {
        for (b, rb) in &texts[i + 1..] {
            if ra.overlaps(rb) {
                problems.push(format!("{what}: `{a}` {ra:?} overlaps `{b}` {rb:?}"));
            }
        }
    }
    let expected = match &d.region {
        Some(r) => count_region(r).1,
        None => d.connections.len(),
    };
    let drawn = count_edges(&laid.edges, &laid.shapes);
    if drawn != expected {
        problems.push(format!("{what}: {drawn} edges drawn for {expected} transitions or connections"));
    }
    // Top-level shapes do not overlap one another.
    for (i, a) in laid.shapes.iter().enumerate() {
        for b in &laid.shapes[i + 1..] {
            if a.rect.overlaps(&b.rect) {
                problems.push(format!("{what}: {:?} overlaps {:?}", a.subject, b.subject));
            }
        }
    }
}

/// Dumps every diagram of one workspace and checks it; returns the dump.
fn run_workspace(files: Vec<(String, String)>, problems: &mut Vec<String>) -> String {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, files, RuleSet::Paper);
    let mut out = String::new();
    for &f in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
        let defs = file_defs(&db, f);
        let diagrams = file_diagrams(&db, ws, f);
        // Every machine, operation, controller and module has a diagram.
        let elements = defs
            .iter()
            .filter(|(_, d)| {
                matches!(d.kind, DefKind::StateMachine | DefKind::Operation | DefKind::Controller | DefKind::Module)
            })
            .count();
        assert_eq!(elements, diagrams.len(), "{}", f.path(&db));
        for d in &diagrams {
            out.push_str(&dump(d));
            // Every node and transition declared inside the element.
            if let Some(r) = &d.region {
                let (id, _) = defs
                    .iter()
                    .find(|(_, x)| {
                        u32::from(x.range.start()) == d.range.start
                            && matches!(x.kind, DefKind::StateMachine | DefKind::Operation)
                    })
                    .expect("the element's definition");
                let mut nodes = 0;
                let mut transitions = 0;
                let mut stack = vec![id];
                while let Some(p) = stack.pop() {
                    for (c, cd) in defs.children(Some(p)) {
                        if cd.kind.is_node() {
                            nodes += 1;
                            stack.push(c);
                        } else if cd.kind == DefKind::Transition {
                            transitions += 1;
                        }
                    }
                }
                assert_eq!(count_region(r), (nodes, transitions), "{} {}", d.file, d.qualified_name);
            }
            let laid = layout(d);
            check_layout(d, &laid, problems);
            // The SVG names every node and transition.
            let svg = robosim_diagram::render_svg(d);
            assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        }
    }
    out
}

#[test]
fn paper_example() {
    let root = root();
    let mut problems = Vec::new();
    let mut out = run_workspace(files_in(&root.join("examples/paper"), &root), &mut problems);
    out.push_str(&run_workspace(files_in(&root.join("examples/lawnmower"), &root), &mut problems));
    out.push_str(&run_workspace(files_in(&root.join("tests/data/diagram"), &root), &mut problems));
    expect_file!["../test_data/examples.txt"].assert_eq(&out);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn corpus() {
    let base = root().join("../shared/corpus");
    let mut dirs = BTreeSet::new();
    let mut stack = vec![base.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if FileKind::from_path(&p).is_some() {
                dirs.insert(d.clone());
            }
        }
    }
    let mut problems = Vec::new();
    let mut out = String::new();
    for dir in dirs {
        out.push_str(&run_workspace(files_in(&dir, &base), &mut problems));
    }
    expect_file!["../test_data/corpus.txt"].assert_eq(&out);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
