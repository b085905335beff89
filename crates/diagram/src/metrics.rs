//! How readable a laid-out diagram is, measured the same way for our layout
//! and for Graphviz `dot`'s layout of the same graph (issue 21): the
//! drawing's size, its edge crossings and how far each edge label is from
//! its own edge.
//!
//! [`reference_dot`] writes a diagram as DOT with every node, composite
//! header and edge label at the size our layout gives it, so that `dot
//! -Tplain` lays out the same boxes; [`measure_plain`] measures its answer.
//! `dot` is a benchmark for the tests only, never run by the tool.

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::layout::{header_size, label_lines, leaf_size, structure_sizes, Edge, Laid, Rect, Shape};
use crate::model::{Diagram, NodeKind, Region};

/// What is measured of one drawing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Nodes and blocks, nested ones included.
    pub nodes: usize,
    /// Width of the drawing.
    pub w: f64,
    /// Height of the drawing.
    pub h: f64,
    /// Points where two edges cross, outside every node.
    pub crossings: usize,
    /// The largest distance from an edge label to its own edge.
    pub label_distance: f64,
}

impl Metrics {
    /// Width over height.
    pub fn aspect(&self) -> f64 {
        self.w / self.h.max(1.0)
    }

    /// Width times height.
    pub fn area(&self) -> f64 {
        self.w * self.h
    }
}

/// An edge as a polyline, with its label's box.
struct Line {
    points: Vec<(f64, f64)>,
    label: Option<Rect>,
}

/// Our layout's edges, its leaf nodes' boxes and its number of nodes.
fn flatten(laid: &Laid) -> (Vec<Line>, Vec<Rect>, usize) {
    fn walk(s: &Shape, lines: &mut Vec<Line>, leaves: &mut Vec<Rect>, nodes: &mut usize) {
        *nodes += 1;
        if s.children.is_empty() {
            leaves.push(s.rect);
        }
        for c in &s.children {
            walk(c, lines, leaves, nodes);
        }
        lines.extend(s.edges.iter().map(line_of));
    }
    let (mut lines, mut leaves, mut nodes) = (Vec::new(), Vec::new(), 0);
    for s in &laid.shapes {
        walk(s, &mut lines, &mut leaves, &mut nodes);
    }
    lines.extend(laid.edges.iter().map(line_of));
    (lines, leaves, nodes)
}

/// Measures our layout of a diagram.
pub fn measure(laid: &Laid) -> Metrics {
    let (lines, leaves, nodes) = flatten(laid);
    Metrics {
        nodes,
        w: laid.w,
        h: laid.h,
        crossings: crossings(&lines, &leaves),
        label_distance: label_distance(&lines),
    }
}

fn line_of(e: &Edge) -> Line {
    let mut points = Vec::new();
    for c in &e.path {
        for t in 0..=24 {
            if t > 0 || points.is_empty() {
                points.push(c.at(t as f64 / 24.0));
            }
        }
    }
    let label = e.texts.iter().map(|t| t.rect).reduce(|a, b| {
        let (x, y) = (a.x.min(b.x), a.y.min(b.y));
        Rect { x, y, w: (a.x + a.w).max(b.x + b.w) - x, h: (a.y + a.h).max(b.y + b.h) - y }
    });
    Line { points, label }
}

/// Proper crossings of two segments: the point, if any.
fn cross(a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)) -> Option<(f64, f64)> {
    let r = (b.0 - a.0, b.1 - a.1);
    let s = (d.0 - c.0, d.1 - c.1);
    let den = r.0 * s.1 - r.1 * s.0;
    if den.abs() < 1e-9 {
        return None;
    }
    let t = ((c.0 - a.0) * s.1 - (c.1 - a.1) * s.0) / den;
    let u = ((c.0 - a.0) * r.1 - (c.1 - a.1) * r.0) / den;
    ((0.0..1.0).contains(&t) && (0.0..1.0).contains(&u)).then_some((a.0 + t * r.0, a.1 + t * r.1))
}

/// The points where two different edges of our layout cross (outside
/// every node), to see where [`measure`]'s crossings are.
pub fn crossing_points(laid: &Laid) -> Vec<(f64, f64)> {
    let (lines, leaves, _) = flatten(laid);
    let mut out = Vec::new();
    crossings_at(&lines, &leaves, &mut out);
    out
}

/// The points where two different edges cross, outside the (slightly
/// grown) leaf nodes: edges that meet at a node's border are not crossing.
fn crossings(lines: &[Line], leaves: &[Rect]) -> usize {
    let mut out = Vec::new();
    crossings_at(lines, leaves, &mut out);
    out.len()
}

fn crossings_at(lines: &[Line], leaves: &[Rect], out: &mut Vec<(f64, f64)>) {
    let near_node = |p: (f64, f64)| {
        leaves.iter().any(|r| p.0 >= r.x - 3.0 && p.0 <= r.x + r.w + 3.0 && p.1 >= r.y - 3.0 && p.1 <= r.y + r.h + 3.0)
    };
    for (i, a) in lines.iter().enumerate() {
        for b in &lines[i + 1..] {
            let mut found: Vec<(f64, f64)> = Vec::new();
            for sa in a.points.windows(2) {
                for sb in b.points.windows(2) {
                    if let Some(p) = cross(sa[0], sa[1], sb[0], sb[1]) {
                        // One crossing sampled twice at a segment joint.
                        if !near_node(p) && !found.iter().any(|q| (q.0 - p.0).abs() < 2.0 && (q.1 - p.1).abs() < 2.0) {
                            found.push(p);
                        }
                    }
                }
            }
            out.extend(found);
        }
    }
}

fn point_rect_distance(p: (f64, f64), r: &Rect) -> f64 {
    let dx = (r.x - p.0).max(0.0).max(p.0 - (r.x + r.w));
    let dy = (r.y - p.1).max(0.0).max(p.1 - (r.y + r.h));
    (dx * dx + dy * dy).sqrt()
}

/// The largest distance from a label's box to the nearest point of its edge.
fn label_distance(lines: &[Line]) -> f64 {
    lines
        .iter()
        .filter_map(|l| {
            let r = l.label?;
            // Points between samples too: a long straight segment has few.
            let d = l
                .points
                .windows(2)
                .flat_map(|s| {
                    (0..8).map(move |k| {
                        let t = k as f64 / 8.0;
                        (s[0].0 + t * (s[1].0 - s[0].0), s[0].1 + t * (s[1].1 - s[0].1))
                    })
                })
                .chain(l.points.last().copied())
                .map(|p| point_rect_distance(p, &r))
                .fold(f64::MAX, f64::min);
            Some(d)
        })
        .fold(0.0, f64::max)
}

/// Points to inches, as DOT sizes nodes.
fn inch(px: f64) -> String {
    format!("{:.4}", px / 72.0)
}

/// An HTML-like DOT label that is an empty box of exactly `w`×`h` points.
fn sized_label(w: f64, h: f64) -> String {
    format!(
        r#"<<TABLE BORDER="0" CELLBORDER="0" CELLPADDING="0" CELLSPACING="0" FIXEDSIZE="TRUE" WIDTH="{}" HEIGHT="{}"><TR><TD></TD></TR></TABLE>>"#,
        w.ceil().max(1.0) as i64,
        h.ceil().max(1.0) as i64
    )
}

/// The diagram as DOT, with every box at the size our layout gives it:
/// nodes and blocks fixed-size, composite states clusters with a header of
/// their header's size, edge labels empty boxes of the label's size. Nodes
/// are `n0`, `n1`… and a composite's anchor `a0`, `a1`…. With `compound`,
/// transitions of a composite state end at its cluster's border
/// (`lhead`/`ltail`); without (dot asserts on some such graphs), at the
/// anchor inside it.
pub fn reference_dot(d: &Diagram, compound: bool) -> String {
    let mut out = String::from("digraph G {\n  compound=true; margin=0; pad=0;\n  node [label=\"\", margin=0];\n");
    match &d.region {
        Some(r) => {
            let mut k = 0;
            dot_region(r, &mut k, "  ", compound, &mut out);
        }
        None => {
            let (sizes, edges) = structure_sizes(&d.blocks, &d.connections);
            for (i, (w, h)) in sizes.iter().enumerate() {
                let _ = writeln!(out, "  n{i} [shape=box, fixedsize=true, width={}, height={}];", inch(*w), inch(*h));
            }
            for (from, to, (w, h)) in edges {
                let _ = writeln!(out, "  n{from} -> n{to} [label={}];", sized_label(w, h));
            }
        }
    }
    out.push_str("}\n");
    out
}

/// Writes a region; `k` numbers the nodes across the whole diagram.
fn dot_region(
    r: &Region,
    k: &mut usize,
    pad: &str,
    compound: bool,
    out: &mut String,
) -> HashMap<String, (String, bool)> {
    // Node id → (DOT node, whether it is a cluster's anchor).
    let mut names: HashMap<String, (String, bool)> = HashMap::new();
    for n in &r.nodes {
        let i = *k;
        *k += 1;
        if n.kind == NodeKind::State && !n.region.is_empty() {
            let (w, h) = header_size(n);
            let _ = writeln!(out, "{pad}subgraph cluster_{i} {{ label={}; labeljust=l;", sized_label(w, h));
            let _ = writeln!(out, "{pad}  a{i} [shape=point, style=invis, width=0.01];");
            dot_region(&n.region, k, &format!("{pad}  "), compound, out);
            let _ = writeln!(out, "{pad}}}");
            names.insert(n.id.clone(), (format!("a{i}"), true));
        } else {
            let (w, h, circle) = leaf_size(n);
            let shape = if circle { "circle" } else { "box" };
            let _ = writeln!(out, "{pad}n{i} [shape={shape}, fixedsize=true, width={}, height={}];", inch(w), inch(h));
            names.insert(n.id.clone(), (format!("n{i}"), false));
        }
    }
    for t in &r.transitions {
        let mut end = |id: &Option<String>, name: &str| -> (String, bool) {
            if let Some(e) = id.as_ref().and_then(|id| names.get(id)) {
                return e.clone();
            }
            // An unresolved end gets a box of its own, as in our layout.
            let i = *k;
            *k += 1;
            let (w, h) = crate::layout::unresolved_size(name);
            let _ = writeln!(out, "{pad}n{i} [shape=box, fixedsize=true, width={}, height={}];", inch(w), inch(h));
            (format!("n{i}"), false)
        };
        let (s, s_cluster) = end(&t.source, &t.source_name);
        let (g, g_cluster) = end(&t.target, &t.target_name);
        let mut attrs = Vec::new();
        let lines = label_lines(&t.label);
        if !lines.is_empty() {
            let (w, h) = crate::layout::label_size(&lines);
            attrs.push(format!("label={}", sized_label(w, h)));
        }
        if s_cluster && compound {
            attrs.push(format!("ltail=cluster_{}", &s[1..]));
        }
        if g_cluster && compound {
            attrs.push(format!("lhead=cluster_{}", &g[1..]));
        }
        let _ = writeln!(out, "{pad}{s} -> {g} [{}];", attrs.join(", "));
    }
    names
}

/// Measures `dot -Tplain`'s layout of [`reference_dot`]'s graph: its size
/// and crossings (its clusters are not in the plain output: only leaf nodes
/// are obstacles; its labels' distances are not measured). `None` if the
/// text is not plain output.
pub fn measure_plain(plain: &str) -> Option<Metrics> {
    let mut size = None;
    let mut leaves = Vec::new();
    let mut lines = Vec::new();
    let mut nodes = 0;
    let mut clusters = std::collections::HashSet::new();
    for l in plain.lines() {
        let f = split_plain(l);
        match f.first().map(String::as_str) {
            Some("graph") => {
                let w: f64 = f.get(2)?.parse().ok()?;
                let h: f64 = f.get(3)?.parse().ok()?;
                size = Some((w * 72.0, h * 72.0));
            }
            Some("node") => {
                let (x, y, w, h): (f64, f64, f64, f64) = (
                    f.get(2)?.parse().ok()?,
                    f.get(3)?.parse().ok()?,
                    f.get(4)?.parse().ok()?,
                    f.get(5)?.parse().ok()?,
                );
                if f[1].starts_with('a') {
                    clusters.insert(f[1].clone());
                    continue;
                }
                nodes += 1;
                leaves.push(Rect { x: (x - w / 2.0) * 72.0, y: (y - h / 2.0) * 72.0, w: w * 72.0, h: h * 72.0 });
            }
            Some("edge") => {
                let n: usize = f.get(3)?.parse().ok()?;
                let pts: Vec<(f64, f64)> = (0..n)
                    .map(|i| {
                        Some((
                            f.get(4 + 2 * i)?.parse::<f64>().ok()? * 72.0,
                            f.get(5 + 2 * i)?.parse::<f64>().ok()? * 72.0,
                        ))
                    })
                    .collect::<Option<_>>()?;
                // A B-spline of cubic pieces: p0 c1 c2 p1 c1 c2 p2 …
                let mut points = vec![*pts.first()?];
                for seg in pts[1..].chunks(3) {
                    if let [c1, c2, p3] = seg {
                        let p0 = *points.last()?;
                        let cubic = crate::layout::Cubic { p0, c1: *c1, c2: *c2, p3: *p3 };
                        points.extend((1..=24).map(|t| cubic.at(t as f64 / 24.0)));
                    }
                }
                // dot's labels are not measured (`label_distance` is 0).
                lines.push(Line { points, label: None });
            }
            _ => {}
        }
    }
    let (w, h) = size?;
    Some(Metrics { nodes: nodes + clusters.len(), w, h, crossings: crossings(&lines, &leaves), label_distance: 0.0 })
}

/// A line of plain output split at spaces, with quoted fields unquoted.
fn split_plain(l: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for c in l.chars() {
        match c {
            '"' => quoted = !quoted,
            ' ' if !quoted => {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
            }
            _ => cur.push(c),
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}
