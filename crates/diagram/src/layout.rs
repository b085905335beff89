//! Layout of a diagram: each region (a machine's, a composite state's, or
//! a controller's or module's blocks) is a layered graph ([`crate::layered`]),
//! laid out downwards and rightwards with ranks of several widths, the most
//! compact of those that are neither too wide nor too tall being kept.
//!
//! Hierarchy is laid out inside out: the region of each composite state is
//! laid out first, and the state becomes a box of that size (plus its
//! header) in its parent's layout; the inner shapes are then moved into it.
//!
//! Edge labels are sized dummy nodes of the layered graph, so they never
//! overlap nodes or each other, and sit beside their own edge. Long texts
//! are wrapped, then elided after a few lines; the shape or edge then has
//! the full text as a tooltip (`title`).

use std::collections::HashMap;

use crate::layered::{layered, GEdge, GNode, GRect, Placed};
use crate::model::{Block, Connection, Diagram, Node, NodeKind, Region, Span, Transition};

/// Font size of every text, in pixels.
pub const FONT: f64 = 12.0;
/// Advance of one character of the (monospace) font.
pub const CHAR_W: f64 = 7.2;
/// Height of one line of text.
pub const LINE_H: f64 = 16.0;
/// Padding inside boxes.
const PAD: f64 = 8.0;
/// Longest line of a label before it wraps.
const WRAP: usize = 40;
/// Lines of a label, or of one action, before the rest is elided.
const MAX_LINES: usize = 3;
/// Line length and lines of labels wrapped narrower, for diagrams too wide.
const NARROW_WRAP: usize = 22;
const NARROW_LINES: usize = 5;
/// Longest name of a state or block before it is elided.
const MAX_NAME: usize = 32;

/// An axis-aligned rectangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    #[allow(missing_docs)]
    pub x: f64,
    #[allow(missing_docs)]
    pub y: f64,
    #[allow(missing_docs)]
    pub w: f64,
    #[allow(missing_docs)]
    pub h: f64,
}

impl Rect {
    fn translate(&mut self, dx: f64, dy: f64) {
        self.x += dx;
        self.y += dy;
    }

    /// Whether the interiors of two rectangles intersect.
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    /// Whether `o` lies inside this rectangle.
    pub fn contains(&self, o: &Rect) -> bool {
        o.x >= self.x - 0.01
            && o.y >= self.y - 0.01
            && o.x + o.w <= self.x + self.w + 0.01
            && o.y + o.h <= self.y + self.h + 0.01
    }
}

/// A line of text at a position (its box: `LINE_H` high, `CHAR_W` per char).
#[derive(Debug, Clone, PartialEq)]
pub struct TextLine {
    /// The text.
    pub text: String,
    /// Its box.
    pub rect: Rect,
    /// CSS class (`state-name`, `action`, `transition-label`, …).
    pub class: &'static str,
}

/// A cubic Bézier segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cubic {
    #[allow(missing_docs)]
    pub p0: (f64, f64),
    #[allow(missing_docs)]
    pub c1: (f64, f64),
    #[allow(missing_docs)]
    pub c2: (f64, f64),
    #[allow(missing_docs)]
    pub p3: (f64, f64),
}

impl Cubic {
    /// The point at `t` in [0, 1].
    pub fn at(&self, t: f64) -> (f64, f64) {
        let u = 1.0 - t;
        let f =
            |a: f64, b: f64, c: f64, d: f64| u * u * u * a + 3.0 * u * u * t * b + 3.0 * u * t * t * c + t * t * t * d;
        (f(self.p0.0, self.c1.0, self.c2.0, self.p3.0), f(self.p0.1, self.c1.1, self.c2.1, self.p3.1))
    }

    pub(crate) fn reversed(&self) -> Cubic {
        Cubic { p0: self.p3, c1: self.c2, c2: self.c1, p3: self.p0 }
    }

    fn translate(&mut self, dx: f64, dy: f64) {
        for p in [&mut self.p0, &mut self.c1, &mut self.c2, &mut self.p3] {
            p.0 += dx;
            p.1 += dy;
        }
    }
}

/// What a shape stands for, with its source range (the fields are those of
/// the diagram model's element: its id, kind, ends and range).
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)]
pub enum Subject {
    /// A node of a machine.
    Node { id: String, kind: NodeKind, composite: bool, range: Span },
    /// A transition.
    Transition { id: String, source: Option<String>, target: Option<String>, range: Span },
    /// A block of a controller or module.
    Block { id: String, kind: String, range: Span },
    /// A connection.
    Connection { from: String, to: String, direction: String, is_async: bool, range: Span },
}

/// A laid-out node or block; composite states contain their inside.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// What it is.
    pub subject: Subject,
    /// Its box.
    pub rect: Rect,
    /// The texts drawn in it (name, actions).
    pub texts: Vec<TextLine>,
    /// The y of the line between the header and the inside, for composites.
    pub separator: Option<f64>,
    /// The shapes inside (composite states).
    pub children: Vec<Shape>,
    /// The edges inside (composite states).
    pub edges: Vec<Edge>,
    /// The full texts, when some were elided.
    pub title: Option<String>,
}

/// A laid-out transition or connection.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// What it is.
    pub subject: Subject,
    /// The curve, from source to target.
    pub path: Vec<Cubic>,
    /// An arrowhead at the start too (bidirectional connections).
    pub both_heads: bool,
    /// Dashed (asynchronous connections).
    pub dashed: bool,
    /// The label's lines.
    pub texts: Vec<TextLine>,
    /// The full label, when it was elided.
    pub title: Option<String>,
}

/// A laid-out diagram, in pixels from (0, 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Laid {
    /// Width.
    pub w: f64,
    /// Height.
    pub h: f64,
    /// The top-level shapes.
    pub shapes: Vec<Shape>,
    /// The top-level edges.
    pub edges: Vec<Edge>,
}

impl Shape {
    fn translate(&mut self, dx: f64, dy: f64) {
        self.rect.translate(dx, dy);
        for t in &mut self.texts {
            t.rect.translate(dx, dy);
        }
        if let Some(s) = &mut self.separator {
            *s += dy;
        }
        for c in &mut self.children {
            c.translate(dx, dy);
        }
        for e in &mut self.edges {
            e.translate(dx, dy);
        }
    }
}

impl Edge {
    fn translate(&mut self, dx: f64, dy: f64) {
        for c in &mut self.path {
            c.translate(dx, dy);
        }
        for t in &mut self.texts {
            t.rect.translate(dx, dy);
        }
    }
}

/// Splits `text` into lines of at most `WRAP` characters, at spaces (and
/// inside words longer than a line).
pub fn wrap(text: &str) -> Vec<String> {
    wrap_at(text, WRAP)
}

/// Splits `text` into lines of at most `width` characters.
fn wrap_at(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    let words = text.split(' ').flat_map(|w| {
        let chars: Vec<char> = w.chars().collect();
        let pieces: Vec<String> = if chars.is_empty() {
            vec![String::new()]
        } else {
            chars.chunks(width).map(|c| c.iter().collect()).collect()
        };
        pieces
    });
    for word in words {
        let word = word.as_str();
        let len = cur.chars().count() + 1 + word.chars().count();
        if !cur.is_empty() && len > width {
            lines.push(std::mem::take(&mut cur));
        }
        if !cur.is_empty() {
            cur.push(' ');
        }
        cur.push_str(word);
    }
    if !cur.is_empty() || lines.is_empty() {
        lines.push(cur);
    }
    lines
}

/// `text` wrapped, its lines beyond `MAX_LINES` elided; and whether some
/// were.
pub fn wrap_elided(text: &str) -> (Vec<String>, bool) {
    wrap_elided_at(text, WRAP, MAX_LINES)
}

fn wrap_elided_at(text: &str, width: usize, max_lines: usize) -> (Vec<String>, bool) {
    let mut lines = wrap_at(text, width);
    if lines.len() <= max_lines {
        return (lines, false);
    }
    lines.truncate(max_lines);
    let last = &mut lines[max_lines - 1];
    if last.chars().count() >= width {
        *last = last.chars().take(width - 1).collect();
    }
    last.push('…');
    (lines, true)
}

/// A name shortened in the middle to `MAX_NAME` characters (the start and
/// end of a long identifier say most); and whether it was.
pub fn elide_name(name: &str) -> (String, bool) {
    let chars: Vec<char> = name.chars().collect();
    if chars.len() <= MAX_NAME {
        return (name.to_string(), false);
    }
    let head = (MAX_NAME - 1) * 2 / 5;
    let tail = MAX_NAME - 1 - head;
    let mut s: String = chars[..head].iter().collect();
    s.push('…');
    s.extend(&chars[chars.len() - tail..]);
    (s, true)
}

fn text_width(s: &str) -> f64 {
    s.chars().count() as f64 * CHAR_W
}

/// Lays out a diagram.
pub fn layout(d: &Diagram) -> Laid {
    let (w, h, shapes, edges) = match &d.region {
        Some(r) => layout_region(r, true),
        None => layout_structure(&d.blocks, &d.connections),
    };
    Laid { w, h, shapes, edges }
}

/// One item to lay out: its size, and how to build its shape at a position.
struct Item {
    size: (f64, f64),
    circle: bool,
    shape: Shape,
}

/// One edge to lay out.
struct EdgeReq {
    from: usize,
    to: usize,
    label: Vec<String>,
    subject: Subject,
    both_heads: bool,
    dashed: bool,
    title: Option<String>,
    /// The whole label, to wrap narrower.
    full: String,
}

fn layout_region(r: &Region, top: bool) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    let mut items = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for n in &r.nodes {
        index.insert(&n.id, items.len());
        items.push(node_item(n));
    }
    let mut reqs = Vec::new();
    for t in &r.transitions {
        let (label, cut) = label_text(&t.label);
        // An end that does not resolve gets a small box of its own, so that
        // every transition is drawn.
        let end = |id: &Option<String>, name: &str, items: &mut Vec<Item>| -> usize {
            if let Some(i) = id.as_deref().and_then(|id| index.get(id)) {
                return *i;
            }
            let text = format!("?{name}");
            let w = text_width(&text) + 2.0 * PAD;
            items.push(Item {
                size: (w, LINE_H + 2.0 * PAD),
                circle: false,
                shape: Shape {
                    subject: Subject::Node {
                        id: text.clone(),
                        kind: NodeKind::Junction,
                        composite: false,
                        range: t.range,
                    },
                    rect: Rect { x: 0.0, y: 0.0, w, h: LINE_H + 2.0 * PAD },
                    texts: vec![TextLine {
                        rect: Rect { x: PAD, y: PAD, w: text_width(&text), h: LINE_H },
                        text,
                        class: "unresolved",
                    }],
                    separator: None,
                    children: Vec::new(),
                    edges: Vec::new(),
                    title: None,
                },
            });
            items.len() - 1
        };
        let from = end(&t.source, &t.source_name, &mut items);
        let to = end(&t.target, &t.target_name, &mut items);
        reqs.push(EdgeReq {
            from,
            to,
            label,
            subject: transition_subject(t),
            both_heads: false,
            dashed: false,
            title: cut.then(|| t.label.clone()),
            full: t.label.clone(),
        });
    }
    place(items, reqs, top)
}

fn transition_subject(t: &Transition) -> Subject {
    Subject::Transition { id: t.id.clone(), source: t.source.clone(), target: t.target.clone(), range: t.range }
}

fn node_item(n: &Node) -> Item {
    let subject = |composite| Subject::Node { id: n.id.clone(), kind: n.kind, composite, range: n.range };
    let empty = |size: f64, composite| Shape {
        subject: subject(composite),
        rect: Rect { x: 0.0, y: 0.0, w: size, h: size },
        texts: Vec::new(),
        separator: None,
        children: Vec::new(),
        edges: Vec::new(),
        title: None,
    };
    match n.kind {
        NodeKind::Initial => return Item { size: (16.0, 16.0), circle: true, shape: empty(16.0, false) },
        NodeKind::Junction | NodeKind::ProbabilisticJunction => {
            return Item { size: (18.0, 18.0), circle: true, shape: empty(18.0, false) }
        }
        NodeKind::Final if n.region.is_empty() && n.actions.is_empty() => {
            return Item { size: (22.0, 22.0), circle: true, shape: empty(22.0, false) }
        }
        _ => {}
    }
    // A state: its name, its actions, then its inside.
    let (name, mut cut) = elide_name(&n.name);
    let mut texts = vec![TextLine {
        rect: Rect { x: PAD, y: PAD, w: text_width(&name), h: LINE_H },
        text: name,
        class: "state-name",
    }];
    let mut y = PAD + LINE_H + 4.0;
    for a in &n.actions {
        let (lines, elided) = wrap_elided(&format!("{} {}", a.kind, a.text));
        cut |= elided;
        for (i, line) in lines.into_iter().enumerate() {
            let indent = if i == 0 { 0.0 } else { 2.0 * CHAR_W };
            texts.push(TextLine {
                rect: Rect { x: PAD + indent, y, w: text_width(&line), h: LINE_H },
                text: line,
                class: "action",
            });
            y += LINE_H;
        }
    }
    let composite = !n.region.is_empty();
    let header = y + if composite { 4.0 } else { PAD - 4.0 };
    let text_w = texts.iter().map(|t| t.rect.x + t.rect.w).fold(0.0, f64::max) + PAD;
    let (mut w, mut h) = (text_w.max(80.0), header.max(36.0));
    let mut children = Vec::new();
    let mut edges = Vec::new();
    let mut separator = None;
    if composite {
        let (iw, ih, inner_shapes, inner_edges) = layout_region(&n.region, false);
        separator = Some(header);
        w = w.max(iw + 2.0 * PAD);
        h = header + PAD + ih + PAD;
        // Centre the inside horizontally.
        let dx = (w - iw) / 2.0;
        for mut s in inner_shapes {
            s.translate(dx, header + PAD);
            children.push(s);
        }
        for mut e in inner_edges {
            e.translate(dx, header + PAD);
            edges.push(e);
        }
    }
    Item {
        size: (w, h),
        circle: false,
        shape: Shape {
            subject: subject(composite),
            rect: Rect { x: 0.0, y: 0.0, w, h },
            texts,
            separator,
            children,
            edges,
            title: cut.then(|| {
                let mut full = n.name.clone();
                for a in &n.actions {
                    full.push_str(&format!("\n{} {}", a.kind, a.text));
                }
                full
            }),
        },
    }
}

/// A block: its stereotype and its (elided) name.
fn block_item(b: &Block) -> Item {
    let full = match &b.reference {
        Some(r) => format!("{}: {r}", b.id),
        None => b.id.clone(),
    };
    let (title, cut) = elide_name(&full);
    let kind = format!("«{}»", b.kind);
    let texts = vec![
        TextLine { rect: Rect { x: PAD, y: PAD, w: text_width(&kind), h: LINE_H }, text: kind, class: "stereotype" },
        TextLine {
            rect: Rect { x: PAD, y: PAD + LINE_H, w: text_width(&title), h: LINE_H },
            text: title,
            class: "block-name",
        },
    ];
    let w = texts.iter().map(|t| t.rect.w).fold(0.0, f64::max) + 2.0 * PAD;
    let h = 2.0 * LINE_H + 2.0 * PAD;
    Item {
        size: (w, h),
        circle: false,
        shape: Shape {
            subject: Subject::Block { id: b.id.clone(), kind: b.kind.clone(), range: b.range },
            rect: Rect { x: 0.0, y: 0.0, w, h },
            texts,
            separator: None,
            children: Vec::new(),
            edges: Vec::new(),
            title: cut.then_some(full),
        },
    }
}

fn layout_structure(blocks: &[Block], connections: &[Connection]) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    let mut items = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for b in blocks {
        index.insert(&b.id, items.len());
        items.push(block_item(b));
    }
    let mut reqs = Vec::new();
    for c in connections {
        let (Some(&from), Some(&to)) = (index.get(c.from.as_str()), index.get(c.to.as_str())) else { continue };
        let mut label = c.label.clone();
        if c.is_async {
            label.push_str(" (async)");
        }
        let (lines, cut) = wrap_elided(&label);
        reqs.push(EdgeReq {
            from,
            to,
            label: lines,
            title: cut.then(|| label.clone()),
            full: label,
            subject: Subject::Connection {
                from: c.from.clone(),
                to: c.to.clone(),
                direction: c.direction.clone(),
                is_async: c.is_async,
                range: c.range,
            },
            both_heads: c.bidirectional,
            dashed: c.is_async,
        });
    }
    place(items, reqs, true)
}

/// The two orientations tried: ranks downwards or rightwards.
#[derive(Clone, Copy, PartialEq)]
enum Flow {
    Down,
    Right,
}

impl Flow {
    /// (cross, along) of an (x, y) size.
    fn size(self, (w, h): (f64, f64)) -> (f64, f64) {
        match self {
            Flow::Down => (w, h),
            Flow::Right => (h, w),
        }
    }

    fn point(self, (c, a): (f64, f64)) -> (f64, f64) {
        match self {
            Flow::Down => (c, a),
            Flow::Right => (a, c),
        }
    }

    fn rect(self, r: &GRect) -> Rect {
        match self {
            Flow::Down => Rect { x: r.cross, y: r.along, w: r.w, h: r.h },
            Flow::Right => Rect { x: r.along, y: r.cross, w: r.h, h: r.w },
        }
    }
}

/// The size of a layout: the box of its nodes, labels and curves.
fn extent(p: &Placed, flow: Flow) -> (f64, f64, f64, f64) {
    let mut min = (f64::MAX, f64::MAX);
    let mut max = (f64::MIN, f64::MIN);
    let mut grow = |x: f64, y: f64| {
        min = (min.0.min(x), min.1.min(y));
        max = (max.0.max(x), max.1.max(y));
    };
    for r in p.nodes.iter().chain(p.labels.iter().flatten()) {
        let r = flow.rect(r);
        grow(r.x, r.y);
        grow(r.x + r.w, r.y + r.h);
    }
    for c in p.paths.iter().flatten() {
        for t in 0..=8 {
            let q = flow.point(c.at(t as f64 / 8.0));
            grow(q.0, q.1);
        }
    }
    (min.0, min.1, max.0 - min.0, max.1 - min.1)
}

/// How good a candidate layout is (lower is better): its area, raised for
/// each crossing, and, for a whole diagram (`top`; the inside of a
/// composite state may be of any shape), much raised when it is wider or
/// taller than about 3:1.
fn score(w: f64, h: f64, crossings: usize, top: bool) -> f64 {
    let skew = (w / h.max(1.0)).max(h / w.max(1.0));
    let aspect = if top && skew > 2.8 { 20.0 * (skew / 2.8).powi(2) } else { 1.0 };
    w * h * (1.0 + 0.35 * crossings as f64) * aspect
}

/// Lays out items and edges: layered downwards and rightwards, with ranks
/// unbounded or wrapped at several widths; keeps the best (see [`score`]).
fn place(items: Vec<Item>, reqs: Vec<EdgeReq>, top: bool) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    if items.is_empty() {
        return (0.0, 0.0, Vec::new(), Vec::new());
    }
    let mut area: f64 = items.iter().map(|it| (it.size.0 + 18.0) * (it.size.1 + 22.0)).sum();
    area += reqs.iter().map(|r| label_size(&r.label)).map(|(w, h)| (w + 14.0) * (h + 22.0)).sum::<f64>();
    let side = area.sqrt();
    // Labels as wrapped, and wrapped narrower when that fits better.
    let narrow: Vec<(Vec<String>, bool)> =
        reqs.iter()
            .map(|r| {
                if r.full.is_empty() {
                    (Vec::new(), false)
                } else {
                    wrap_elided_at(&r.full, NARROW_WRAP, NARROW_LINES)
                }
            })
            .collect();
    let changed = reqs.iter().zip(&narrow).any(|(r, n)| r.label != n.0);
    let mut best: Option<(f64, Flow, bool, Placed)> = None;
    for (flow, thin) in [(Flow::Down, false), (Flow::Right, false), (Flow::Down, true), (Flow::Right, true)] {
        if thin && !changed {
            continue;
        }
        let label_of = |i: usize| if thin { &narrow[i].0 } else { &reqs[i].label };
        let nodes: Vec<GNode> = items
            .iter()
            .map(|it| {
                let (cross, along) = flow.size(it.size);
                GNode { cross, along, round: it.circle, stretch: !it.circle && it.shape.children.is_empty() }
            })
            .collect();
        let edges: Vec<GEdge> = reqs
            .iter()
            .enumerate()
            .map(|(i, r)| GEdge {
                from: r.from,
                to: r.to,
                label: (!label_of(i).is_empty()).then(|| flow.size(label_size(label_of(i)))),
            })
            .collect();
        let widest = nodes.iter().map(|g| g.cross).fold(0.0, f64::max);
        let mut limits = vec![None];
        limits.extend([2.5, 1.6, 1.1, 0.75, 0.5].iter().map(|k| Some((side * k).max(widest))));
        limits.dedup();
        for limit in limits {
            let p = layered(&nodes, &edges, limit, flow == Flow::Right);
            let (_, _, w, h) = extent(&p, flow);
            // Narrower labels only when clearly better: wide lines read best.
            let s = score(w, h, p.crossings, top) * if thin { 1.25 } else { 1.0 };
            if best.as_ref().is_none_or(|b| s < b.0) {
                best = Some((s, flow, thin, p));
            }
        }
    }
    let Some((_, flow, thin, placed)) = best else { return (0.0, 0.0, Vec::new(), Vec::new()) };
    let (x0, y0, w, h) = extent(&placed, flow);
    let margin = 4.0;
    let (dx, dy) = (margin - x0, margin - y0);
    let mut shapes = Vec::new();
    for (item, r) in items.into_iter().zip(&placed.nodes) {
        let r = flow.rect(r);
        let mut s = item.shape;
        s.translate(r.x - s.rect.x + dx, r.y - s.rect.y + dy);
        // Stretched for its edges' ends or its self-loops.
        if s.children.is_empty() && !item.circle {
            s.rect.w = r.w;
            s.rect.h = r.h;
        }
        shapes.push(s);
    }
    let mut edges = Vec::new();
    for (i, (mut r, n)) in reqs.into_iter().zip(narrow).enumerate() {
        if thin {
            r.label = n.0;
            r.title = n.1.then(|| r.full.clone());
        }
        let path: Vec<Cubic> = placed.paths[i]
            .iter()
            .map(|c| {
                let m = |p: (f64, f64)| {
                    let q = flow.point(p);
                    (q.0 + dx, q.1 + dy)
                };
                Cubic { p0: m(c.p0), c1: m(c.c1), c2: m(c.c2), p3: m(c.p3) }
            })
            .collect();
        let texts = match &placed.labels[i] {
            Some(g) => {
                let at = flow.rect(g);
                r.label
                    .iter()
                    .enumerate()
                    .map(|(k, l)| TextLine {
                        text: l.clone(),
                        rect: Rect { x: at.x + dx, y: at.y + dy + k as f64 * LINE_H, w: text_width(l), h: LINE_H },
                        class: "edge-label",
                    })
                    .collect()
            }
            None => Vec::new(),
        };
        edges.push(Edge {
            subject: r.subject,
            path,
            both_heads: r.both_heads,
            dashed: r.dashed,
            texts,
            title: r.title,
        });
    }
    (w + 2.0 * margin, h + 2.0 * margin, shapes, edges)
}

/// The label's size.
pub(crate) fn label_size(label: &[String]) -> (f64, f64) {
    let w = label.iter().map(|l| text_width(l)).fold(0.0, f64::max);
    (w, label.len() as f64 * LINE_H)
}

/// A transition label's lines, as drawn.
pub(crate) fn label_lines(label: &str) -> Vec<String> {
    label_text(label).0
}

/// A transition label's lines (none when empty), and whether it was elided.
fn label_text(label: &str) -> (Vec<String>, bool) {
    if label.is_empty() {
        (Vec::new(), false)
    } else {
        wrap_elided(label)
    }
}

/// The size of a node that is not composite, and whether it is a circle.
pub(crate) fn leaf_size(n: &Node) -> (f64, f64, bool) {
    let it = node_item(n);
    (it.size.0, it.size.1, it.circle)
}

/// The size of a composite state's header (name and actions).
pub(crate) fn header_size(n: &Node) -> (f64, f64) {
    let flat = Node { region: Region::default(), ..n.clone() };
    let it = node_item(&flat);
    it.size
}

/// The box of an unresolved end.
pub(crate) fn unresolved_size(name: &str) -> (f64, f64) {
    (text_width(&format!("?{name}")) + 2.0 * PAD, LINE_H + 2.0 * PAD)
}

/// A connection between two blocks (by index) with its label's size.
pub(crate) type SizedLink = (usize, usize, (f64, f64));

/// The blocks' sizes and the connections.
pub(crate) fn structure_sizes(blocks: &[Block], connections: &[Connection]) -> (Vec<(f64, f64)>, Vec<SizedLink>) {
    let sizes = blocks.iter().map(|b| block_item(b).size).collect();
    let index = |id: &str| blocks.iter().position(|b| b.id == id);
    let edges = connections
        .iter()
        .filter_map(|c| {
            let mut label = c.label.clone();
            if c.is_async {
                label.push_str(" (async)");
            }
            Some((index(&c.from)?, index(&c.to)?, label_size(&wrap_elided(&label).0)))
        })
        .collect();
    (sizes, edges)
}
