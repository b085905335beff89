//! Layout of a diagram with `layout-rs` (a Sugiyama-style layered layout:
//! ranks, crossing minimisation, Brandes–Köpf placement, spline edges).
//!
//! `layout-rs` has no clusters, so hierarchy is laid out inside out: the
//! region of each composite state is laid out first, and the state becomes a
//! box of that size (plus its header) in its parent's layout; the inner
//! shapes are then moved into the box.
//!
//! Edge labels are sized nodes of the layout (layout-rs's label connectors),
//! so they never overlap nodes or each other. A connector's box is twice the
//! label's width: the edge passes through its middle, and the label goes on
//! the side of the edge the curve does not cross.

use std::collections::HashMap;

use layout::core::base::Orientation;
use layout::core::format::{ClipHandle, RenderBackend};
use layout::core::geometry::Point;
use layout::core::style::StyleAttr;
use layout::std_shapes::shapes::{Arrow, Element, ShapeKind};
use layout::topo::layout::VisualGraph;

use crate::model::{Block, Connection, Diagram, Node, NodeKind, Region, Span, Transition};

/// Font size of every text, in pixels.
pub const FONT: f64 = 12.0;
/// Advance of one character of the (monospace) font.
pub const CHAR_W: f64 = 7.2;
/// Height of one line of text.
pub const LINE_H: f64 = 16.0;
/// Padding inside boxes.
const PAD: f64 = 8.0;
/// Gap between an edge and its label.
const GAP: f64 = 6.0;
/// Longest line of a label before it wraps.
const WRAP: usize = 44;

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
    fn at(&self, t: f64) -> (f64, f64) {
        let u = 1.0 - t;
        let f =
            |a: f64, b: f64, c: f64, d: f64| u * u * u * a + 3.0 * u * u * t * b + 3.0 * u * t * t * c + t * t * t * d;
        (f(self.p0.0, self.c1.0, self.c2.0, self.p3.0), f(self.p0.1, self.c1.1, self.c2.1, self.p3.1))
    }

    fn reversed(&self) -> Cubic {
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
    /// How many regions the layout engine failed on (laid out in a column
    /// instead).
    pub fallbacks: usize,
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

/// Splits `text` into lines of at most `WRAP` characters, at spaces.
pub fn wrap(text: &str) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    for word in text.split(' ') {
        let len = cur.chars().count() + 1 + word.chars().count();
        if !cur.is_empty() && len > WRAP {
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

fn text_width(s: &str) -> f64 {
    s.chars().count() as f64 * CHAR_W
}

/// Lays out a diagram.
pub fn layout(d: &Diagram) -> Laid {
    FALLBACKS.with(|f| f.set(0));
    let (w, h, shapes, edges) = match &d.region {
        Some(r) => layout_region(r),
        None => layout_structure(&d.blocks, &d.connections),
    };
    Laid { w, h, shapes, edges, fallbacks: FALLBACKS.with(|f| f.get()) }
}

thread_local! {
    static FALLBACKS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
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
}

fn layout_region(r: &Region) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    let mut items = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for n in &r.nodes {
        index.insert(&n.id, items.len());
        items.push(node_item(n));
    }
    let mut reqs = Vec::new();
    for t in &r.transitions {
        let label = if t.label.is_empty() { Vec::new() } else { wrap(&t.label) };
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
                },
            });
            items.len() - 1
        };
        let from = end(&t.source, &t.source_name, &mut items);
        let to = end(&t.target, &t.target_name, &mut items);
        reqs.push(EdgeReq { from, to, label, subject: transition_subject(t), both_heads: false, dashed: false });
    }
    place(items, reqs)
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
    let mut texts = vec![TextLine {
        rect: Rect { x: PAD, y: PAD, w: text_width(&n.name), h: LINE_H },
        text: n.name.clone(),
        class: "state-name",
    }];
    let mut y = PAD + LINE_H + 4.0;
    for a in &n.actions {
        for (i, line) in wrap(&format!("{} {}", a.kind, a.text)).into_iter().enumerate() {
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
        let (iw, ih, inner_shapes, inner_edges) = layout_region(&n.region);
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
        },
    }
}

fn layout_structure(blocks: &[Block], connections: &[Connection]) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    let mut items = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for b in blocks {
        index.insert(&b.id, items.len());
        let title = match &b.reference {
            Some(r) => format!("{}: {r}", b.id),
            None => b.id.clone(),
        };
        let kind = format!("«{}»", b.kind);
        let texts = vec![
            TextLine {
                rect: Rect { x: PAD, y: PAD, w: text_width(&kind), h: LINE_H },
                text: kind,
                class: "stereotype",
            },
            TextLine {
                rect: Rect { x: PAD, y: PAD + LINE_H, w: text_width(&title), h: LINE_H },
                text: title,
                class: "block-name",
            },
        ];
        let w = texts.iter().map(|t| t.rect.w).fold(0.0, f64::max) + 2.0 * PAD;
        let h = 2.0 * LINE_H + 2.0 * PAD;
        items.push(Item {
            size: (w, h),
            circle: false,
            shape: Shape {
                subject: Subject::Block { id: b.id.clone(), kind: b.kind.clone(), range: b.range },
                rect: Rect { x: 0.0, y: 0.0, w, h },
                texts,
                separator: None,
                children: Vec::new(),
                edges: Vec::new(),
            },
        });
    }
    let mut reqs = Vec::new();
    for c in connections {
        let (Some(&from), Some(&to)) = (index.get(c.from.as_str()), index.get(c.to.as_str())) else { continue };
        let mut label = c.label.clone();
        if c.is_async {
            label.push_str(" (async)");
        }
        reqs.push(EdgeReq {
            from,
            to,
            label: wrap(&label),
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
    place(items, reqs)
}

/// What the layout engine reports while "rendering": the edges' curves.
#[derive(Default)]
struct Capture {
    arrows: Vec<Captured>,
}

/// An edge's index, its path as layout-rs draws it, and its arrowheads
/// (start, end).
type Captured = (usize, Vec<(Point, Point)>, (bool, bool));

impl RenderBackend for Capture {
    fn draw_rect(&mut self, _: Point, _: Point, _: &StyleAttr, _: Option<String>, _: Option<ClipHandle>) {}
    fn draw_line(&mut self, _: Point, _: Point, _: &StyleAttr, _: Option<String>) {}
    fn draw_circle(&mut self, _: Point, _: Point, _: &StyleAttr, _: Option<String>) {}
    fn draw_text(&mut self, _: Point, _: &str, _: &StyleAttr) {}
    fn draw_arrow(
        &mut self,
        path: &[(Point, Point)],
        _: bool,
        head: (bool, bool),
        _: &StyleAttr,
        properties: Option<String>,
        _: &str,
    ) {
        if let Some(i) = properties.and_then(|p| p.parse().ok()) {
            self.arrows.push((i, path.to_vec(), head));
        }
    }
    fn create_clip(&mut self, _: Point, _: Point, _: usize) -> ClipHandle {
        0
    }
}

/// The font size given to the layout's label connectors: their text is a
/// block of characters whose count sets the box size exactly.
const UNIT: usize = 2;
/// layout-rs pads connector boxes by this much.
const CONN_PAD: f64 = 10.0;
const MARK: char = '@';

/// The placeholder text of edge `i`'s label connector, for a box of `w`×`h`.
fn placeholder(i: usize, w: f64, h: f64) -> String {
    let cols = (((w - CONN_PAD) / UNIT as f64).ceil() as usize).max(8);
    let rows = (((h - CONN_PAD) / UNIT as f64).ceil() as usize).max(1);
    let head = format!("{MARK}{i}{MARK}");
    let first: String = head.chars().chain(std::iter::repeat('x')).take(cols.max(head.len())).collect();
    let other = "x".repeat(cols);
    let mut s = first;
    for _ in 1..rows {
        s.push('\n');
        s.push_str(&other);
    }
    s
}

fn placeholder_index(s: &str) -> Option<usize> {
    let rest = s.strip_prefix(MARK)?;
    rest[..rest.find(MARK)?].parse().ok()
}

/// Lays out items and edges with layout-rs; falls back to a column when the
/// engine fails (it asserts on some inputs).
fn place(items: Vec<Item>, reqs: Vec<EdgeReq>) -> (f64, f64, Vec<Shape>, Vec<Edge>) {
    if items.is_empty() {
        return (0.0, 0.0, Vec::new(), Vec::new());
    }
    let engine = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_engine(&items, &reqs)));
    let (node_rects, edges) = match engine {
        Ok(r) => r,
        Err(_) => {
            FALLBACKS.with(|f| f.set(f.get() + 1));
            fallback(&items, &reqs)
        }
    };
    let mut shapes = Vec::new();
    for (item, r) in items.into_iter().zip(node_rects) {
        let mut s = item.shape;
        s.translate(r.x - s.rect.x, r.y - s.rect.y);
        shapes.push(s);
    }
    let mut edges = edges;
    // Move everything to (0, 0).
    let mut min = (f64::MAX, f64::MAX);
    let mut max = (f64::MIN, f64::MIN);
    let mut grow = |x: f64, y: f64| {
        min = (min.0.min(x), min.1.min(y));
        max = (max.0.max(x), max.1.max(y));
    };
    for s in &shapes {
        grow(s.rect.x, s.rect.y);
        grow(s.rect.x + s.rect.w, s.rect.y + s.rect.h);
    }
    for e in &edges {
        for c in &e.path {
            for t in 0..=8 {
                let p = c.at(t as f64 / 8.0);
                grow(p.0, p.1);
            }
        }
        for t in &e.texts {
            grow(t.rect.x, t.rect.y);
            grow(t.rect.x + t.rect.w, t.rect.y + t.rect.h);
        }
    }
    let margin = 4.0;
    let (dx, dy) = (margin - min.0, margin - min.1);
    for s in &mut shapes {
        s.translate(dx, dy);
    }
    for e in &mut edges {
        e.translate(dx, dy);
    }
    (max.0 - min.0 + 2.0 * margin, max.1 - min.1 + 2.0 * margin, shapes, edges)
}

/// The label's size.
fn label_size(label: &[String]) -> (f64, f64) {
    let w = label.iter().map(|l| text_width(l)).fold(0.0, f64::max);
    (w, label.len() as f64 * LINE_H)
}

fn run_engine(items: &[Item], reqs: &[EdgeReq]) -> (Vec<Rect>, Vec<Edge>) {
    let dir = Orientation::TopToBottom;
    let mut vg = VisualGraph::new(dir);
    let handles: Vec<_> = items
        .iter()
        .map(|it| {
            let shape = if it.circle { ShapeKind::new_circle("") } else { ShapeKind::new_box("") };
            vg.add_node(Element::create(shape, StyleAttr::simple(), dir, Point::new(it.size.0, it.size.1)))
        })
        .collect();
    for (i, r) in reqs.iter().enumerate() {
        let mut arrow = Arrow::simple_with_properties("", i.to_string());
        arrow.look.font_size = UNIT;
        if !r.label.is_empty() {
            let (w, h) = label_size(&r.label);
            arrow.text = placeholder(i, 2.0 * (w + GAP), h);
        }
        vg.add_edge(arrow, handles[r.from], handles[r.to]);
    }
    let mut capture = Capture::default();
    vg.do_it(false, false, false, &mut capture);
    let rects: Vec<Rect> = handles
        .iter()
        .map(|h| {
            let (a, b) = vg.pos(*h).bbox(false);
            Rect { x: a.x, y: a.y, w: b.x - a.x, h: b.y - a.y }
        })
        .collect();
    // The label connectors: edge index → (box, pass point).
    let mut boxes: HashMap<usize, (Rect, Point)> = HashMap::new();
    for n in vg.iter_nodes() {
        let e = vg.element(n);
        if let ShapeKind::Connector(Some(text)) = &e.shape {
            if let Some(i) = placeholder_index(text) {
                let (a, b) = e.pos.bbox(false);
                boxes.insert(i, (Rect { x: a.x, y: a.y, w: b.x - a.x, h: b.y - a.y }, e.pos.center()));
            }
        }
    }
    // Labels go beside their edge, where they overlap no node and no
    // other label (layout-rs's placement can leave label boxes touching).
    let mut taken: Vec<Rect> = rects.clone();
    let mut edges = Vec::new();
    let mut arrows = capture.arrows;
    arrows.sort_by_key(|a| a.0);
    for (i, path, head) in arrows {
        let r = &reqs[i];
        let mut curve = to_cubics(&path);
        // layout-rs reverses back edges; draw them from source to target.
        if head.0 && !head.1 {
            curve = curve.iter().rev().map(Cubic::reversed).collect();
        }
        let texts = match boxes.get(&i) {
            Some((b, pass)) => place_label(&r.label, b, pass, &curve, &mut taken),
            None => Vec::new(),
        };
        edges.push(Edge { subject: r.subject.clone(), path: curve, both_heads: r.both_heads, dashed: r.dashed, texts });
    }
    (rects, edges)
}

/// layout-rs's path (`M p0 C c1 c2 p1 S c p …`) as explicit cubics.
fn to_cubics(path: &[(Point, Point)]) -> Vec<Cubic> {
    let pt = |p: Point| (p.x, p.y);
    let mut out = Vec::new();
    if path.len() < 2 {
        return out;
    }
    let mut start = pt(path[0].0);
    let mut c1 = pt(path[0].1);
    for seg in &path[1..] {
        let (c2, end) = (pt(seg.0), pt(seg.1));
        out.push(Cubic { p0: start, c1, c2, p3: end });
        // The next segment's first control point mirrors this one's second.
        c1 = (2.0 * end.0 - c2.0, 2.0 * end.1 - c2.1);
        start = end;
    }
    out
}

/// Puts a label's lines beside the edge, in its connector box on the side
/// the curve crosses least, or else as near as possible where it overlaps
/// nothing in `taken`; the chosen box is added to `taken`.
fn place_label(label: &[String], b: &Rect, pass: &Point, curve: &[Cubic], taken: &mut Vec<Rect>) -> Vec<TextLine> {
    let (w, h) = label_size(label);
    let top = b.y + (b.h - h).max(0.0) / 2.0;
    let hits = |r: &Rect| {
        curve
            .iter()
            .flat_map(|c| (0..=32).map(move |t| c.at(t as f64 / 32.0)))
            .filter(|p| p.0 >= r.x && p.0 <= r.x + r.w && p.1 >= r.y && p.1 <= r.y + r.h)
            .count()
    };
    let free = |r: &Rect, taken: &[Rect]| !taken.iter().any(|t| t.overlaps(r));
    let right = Rect { x: pass.x + GAP, y: top, w, h };
    let left = Rect { x: pass.x - GAP - w, y: top, w, h };
    let mut candidates = if hits(&left) < hits(&right) { vec![left, right] } else { vec![right, left] };
    // Then further and further away, up and down.
    for k in 1..=12 {
        let dy = k as f64 * (LINE_H / 2.0);
        for base in [candidates[0], candidates[1]] {
            candidates.push(Rect { y: base.y + dy, ..base });
            candidates.push(Rect { y: base.y - dy, ..base });
        }
    }
    let at = candidates.into_iter().find(|r| free(r, taken)).unwrap_or_else(|| {
        // Beyond everything on the right, which is always free.
        let x = taken.iter().map(|t| t.x + t.w).fold(pass.x, f64::max) + GAP;
        Rect { x, y: top, w, h }
    });
    taken.push(at);
    label
        .iter()
        .enumerate()
        .map(|(k, l)| TextLine {
            text: l.clone(),
            rect: Rect { x: at.x, y: at.y + k as f64 * LINE_H, w: text_width(l), h: LINE_H },
            class: "edge-label",
        })
        .collect()
}

/// A plain layout when the engine fails: nodes in a column, edges on the
/// right, labels stacked in a column beyond them.
fn fallback(items: &[Item], reqs: &[EdgeReq]) -> (Vec<Rect>, Vec<Edge>) {
    let mut y = 0.0;
    let mut rects = Vec::new();
    let mut width: f64 = 0.0;
    for it in items {
        rects.push(Rect { x: 0.0, y, w: it.size.0, h: it.size.1 });
        width = width.max(it.size.0);
        y += it.size.1 + 30.0;
    }
    let mut label_y = 0.0;
    let mut edges = Vec::new();
    for (k, r) in reqs.iter().enumerate() {
        let (a, b) = (&rects[r.from], &rects[r.to]);
        let bend = width + 20.0 + 12.0 * k as f64;
        let p0 = (a.x + a.w, a.y + a.h / 2.0);
        let p3 = (b.x + b.w, b.y + b.h / 2.0);
        let path = vec![Cubic { p0, c1: (bend, p0.1), c2: (bend, p3.1), p3 }];
        let label_x = width + 40.0 + 12.0 * reqs.len() as f64;
        let texts = r
            .label
            .iter()
            .map(|l| {
                let t = TextLine {
                    text: l.clone(),
                    rect: Rect { x: label_x, y: label_y, w: text_width(l), h: LINE_H },
                    class: "edge-label",
                };
                label_y += LINE_H;
                t
            })
            .collect();
        label_y += 4.0;
        edges.push(Edge { subject: r.subject.clone(), path, both_heads: r.both_heads, dashed: r.dashed, texts });
    }
    (rects, edges)
}
