//! SVG rendering of a laid-out diagram.
//!
//! The document is self-contained (inline style, no scripts). Each node,
//! transition, block and connection is a `<g>` with `data-*` attributes: what
//! it is, its id, its parent state (`data-parent`) and its source range
//! (`data-start`/`data-end` in bytes, `data-line`/`data-character` 0-based in
//! UTF-16 units), so that a viewer can move the cursor to the source. The
//! groups of a composite state's inside are nested in the state's group.
//! Every text has a `textLength`, so that its width is the one the layout
//! reserved whatever font the viewer has.

use std::fmt::Write as _;

use crate::layout::{layout, Cubic, Edge, Laid, Rect, Shape, Subject, TextLine, CHAR_W, FONT, LINE_H};
use crate::model::{Diagram, NodeKind, Span};

/// Colour of RoboSim inputs (and of connections from the platform).
pub const INPUT_COLOUR: &str = "#1565c0";
/// Colour of RoboSim outputs (and of connections to the platform).
pub const OUTPUT_COLOUR: &str = "#c05600";

const STYLE: &str = r#"
  .robosim-diagram text { font-family: "DejaVu Sans Mono", "Liberation Mono", Menlo, Consolas, monospace; font-size: 12px; fill: #1b1b1b; }
  .robosim-diagram .title { font-weight: bold; }
  .robosim-diagram .state-name, .robosim-diagram .block-name { font-weight: bold; }
  .robosim-diagram .stereotype { fill: #555; }
  .robosim-diagram .action { fill: #333; }
  .robosim-diagram .unresolved { fill: #b00020; }
  .robosim-diagram .node-box { fill: #fffbe6; stroke: #8a6d00; stroke-width: 1.5; }
  .robosim-diagram .composite > .node-box { fill: #fff3c4; }
  .robosim-diagram .block .node-box { fill: #eef4fb; stroke: #36597a; }
  .robosim-diagram .block.boundary .node-box { fill: #f7f7f7; stroke-dasharray: 6 3; }
  .robosim-diagram .separator { stroke: #8a6d00; stroke-width: 1; }
  .robosim-diagram .initial-dot { fill: #1b1b1b; }
  .robosim-diagram .junction-dot { fill: #fff; stroke: #1b1b1b; stroke-width: 1.5; }
  .robosim-diagram .final-ring { fill: #fff; stroke: #1b1b1b; stroke-width: 1.5; }
  .robosim-diagram .final-dot { fill: #1b1b1b; }
  .robosim-diagram .edge { fill: none; stroke: #37474f; stroke-width: 1.4; }
  .robosim-diagram .edge.dashed { stroke-dasharray: 6 4; }
  .robosim-diagram .edge.input { stroke: INPUT; }
  .robosim-diagram .edge.output { stroke: OUTPUT; }
  .robosim-diagram .label-bg { fill: #ffffff; fill-opacity: 0.85; }
  .robosim-diagram .io-input { fill: INPUT; font-weight: bold; }
  .robosim-diagram .io-output { fill: OUTPUT; font-weight: bold; }
  .robosim-diagram .exec { font-weight: bold; }
  .robosim-diagram g[data-start] { cursor: pointer; }
  .robosim-diagram .highlight > .node-box, .robosim-diagram .highlight > .edge { stroke: #d81b60; stroke-width: 3; }
  .robosim-diagram .cex-badge { fill: #d81b60; font-weight: bold; font-size: 11px; }
"#;

/// Renders a diagram as a standalone SVG document.
pub fn render_svg(d: &Diagram) -> String {
    let laid = layout(d);
    render_laid(d, &laid)
}

/// Steps of a counterexample to draw on a diagram: each is a byte offset in
/// the diagram's file (where the step's transition or statement is) and the
/// cycle it happened in. The innermost state or transition containing the
/// offset is highlighted and labelled with its cycles (`c0`, `c1 c2` …).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Marks {
    /// (byte offset, cycle), in the order of the counterexample.
    pub steps: Vec<(u32, u32)>,
}

/// Renders a diagram with the steps of a counterexample marked on it.
pub fn render_svg_marked(d: &Diagram, marks: &Marks) -> String {
    let laid = layout(d);
    let mut cycles: Vec<((u32, u32), Vec<u32>)> = Vec::new();
    for &(at, cycle) in &marks.steps {
        // The innermost (shortest) element whose declaration contains the step.
        let best = element_spans(&laid).into_iter().filter(|(a, b)| *a <= at && at < *b).min_by_key(|(a, b)| b - a);
        if let Some(span) = best {
            match cycles.iter_mut().find(|(s, _)| *s == span) {
                Some((_, cs)) if cs.last() != Some(&cycle) => cs.push(cycle),
                Some(_) => {}
                None => cycles.push((span, vec![cycle])),
            }
        }
    }
    render(d, &laid, &cycles)
}

/// Declaration span → the cycles marked on it.
type Marked = [((u32, u32), Vec<u32>)];

/// The declaration spans of every shape and edge.
fn element_spans(laid: &Laid) -> Vec<(u32, u32)> {
    fn walk(s: &Shape, out: &mut Vec<(u32, u32)>) {
        if let Some(r) = subject_span(&s.subject) {
            out.push(r);
        }
        for c in &s.children {
            walk(c, out);
        }
        for e in &s.edges {
            out.extend(subject_span(&e.subject));
        }
    }
    let mut out = Vec::new();
    for s in &laid.shapes {
        walk(s, &mut out);
    }
    out.extend(laid.edges.iter().filter_map(|e| subject_span(&e.subject)));
    out
}

fn subject_span(s: &Subject) -> Option<(u32, u32)> {
    match s {
        Subject::Node { range, .. } | Subject::Transition { range, .. } => Some((range.start, range.end)),
        _ => None,
    }
}

/// The cycles marked on `s`, if any.
fn marked<'m>(s: &Subject, marks: &'m Marked) -> Option<&'m [u32]> {
    let span = subject_span(s)?;
    marks.iter().find(|(sp, _)| *sp == span).map(|(_, c)| c.as_slice())
}

/// A badge `c0 c1` at (x, y) for a marked element.
fn badge(out: &mut String, cycles: &[u32], x: f64, y: f64) {
    let text: Vec<String> = cycles.iter().map(|c| format!("c{c}")).collect();
    let _ = writeln!(out, r#"<text class="cex-badge" x="{}" y="{}">{}</text>"#, n(x), n(y), text.join(" "));
}

/// Renders an already laid-out diagram.
pub fn render_laid(d: &Diagram, laid: &Laid) -> String {
    render(d, laid, &[])
}

fn render(d: &Diagram, laid: &Laid, marks: &Marked) -> String {
    let title = format!("{} {}", d.kind.word(), d.qualified_name);
    let legend = d.robosim && (!d.inputs.is_empty() || !d.outputs.is_empty());
    let title_h = LINE_H + 12.0;
    let legend_h = if legend { LINE_H + 8.0 } else { 0.0 };
    let title_w = title.chars().count() as f64 * CHAR_W + 16.0;
    let w = laid.w.max(title_w).max(if legend { 260.0 } else { 0.0 }).ceil() + 16.0;
    let h = (laid.h + title_h + legend_h).ceil() + 16.0;
    let mut out = String::new();
    let _ = write!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" class="robosim-diagram" width="{w}" height="{h}" viewBox="0 0 {w} {h}" data-kind="{}" data-name="{}" data-file="{}">"#,
        d.kind.word(),
        esc(&d.qualified_name),
        esc(&d.file)
    );
    out.push('\n');
    let _ = writeln!(out, "<style>{}</style>", STYLE.replace("INPUT", INPUT_COLOUR).replace("OUTPUT", OUTPUT_COLOUR));
    out.push_str(concat!(
        r#"<defs><marker id="rs-arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse">"#,
        r##"<path d="M0,0 L10,5 L0,10 z" fill="#37474f"/></marker></defs>"##,
        "\n"
    ));
    let _ = writeln!(out, r##"<rect class="background" x="0" y="0" width="{w}" height="{h}" fill="#ffffff"/>"##);
    let title_line =
        TextLine { text: title.clone(), rect: Rect { x: 8.0, y: 8.0, w: title_w - 16.0, h: LINE_H }, class: "title" };
    text(&mut out, &title_line, d, "");
    let _ = writeln!(out, r#"<g class="diagram" transform="translate(8 {})">"#, 8.0 + title_h);
    for s in &laid.shapes {
        shape(&mut out, s, d, "", marks);
    }
    for e in &laid.edges {
        edge(&mut out, e, d, "", marks);
    }
    out.push_str("</g>\n");
    if legend {
        let y = 8.0 + title_h + laid.h + 8.0;
        let legend_input = TextLine {
            text: "$input".into(),
            rect: Rect { x: 8.0, y, w: 6.0 * CHAR_W, h: LINE_H },
            class: "legend io-input",
        };
        let legend_output = TextLine {
            text: "$output".into(),
            rect: Rect { x: 8.0 + 10.0 * CHAR_W, y, w: 7.0 * CHAR_W, h: LINE_H },
            class: "legend io-output",
        };
        text(&mut out, &legend_input, d, "");
        text(&mut out, &legend_output, d, "");
    }
    out.push_str("</svg>\n");
    out
}

fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            _ => o.push(c),
        }
    }
    o
}

fn n(x: f64) -> String {
    let r = (x * 10.0).round() / 10.0;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        format!("{r:.1}")
    }
}

fn range_attrs(r: &Span) -> String {
    format!(
        r#" data-start="{}" data-end="{}" data-line="{}" data-character="{}" data-end-line="{}" data-end-character="{}""#,
        r.start, r.end, r.line, r.character, r.end_line, r.end_character
    )
}

/// One line of text, with RoboSim `$inputs` and `$outputs` coloured and
/// `exec` in bold.
fn text(out: &mut String, t: &TextLine, d: &Diagram, pad: &str) {
    let baseline = t.rect.y + LINE_H / 2.0 + FONT * 0.35;
    let _ = write!(
        out,
        r#"{pad}<text class="label {}" x="{}" y="{}" textLength="{}" lengthAdjust="spacingAndGlyphs" xml:space="preserve">"#,
        t.class,
        n(t.rect.x),
        n(baseline),
        n(t.rect.w.max(0.1)),
    );
    let chars: Vec<char> = t.text.chars().collect();
    let mut i = 0;
    let mut plain = String::new();
    let flush = |out: &mut String, plain: &mut String| {
        if !plain.is_empty() {
            out.push_str(&esc(plain));
            plain.clear();
        }
    };
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    while i < chars.len() {
        let c = chars[i];
        let word_start = i == 0 || !is_ident(chars[i - 1]);
        if c == '$' && d.robosim {
            let mut j = i + 1;
            while j < chars.len() && is_ident(chars[j]) {
                j += 1;
            }
            let name: String = chars[i + 1..j].iter().collect();
            let class = if d.outputs.contains(&name) {
                Some("io-output")
            } else if d.inputs.contains(&name) {
                Some("io-input")
            } else {
                None
            };
            if let Some(class) = class {
                flush(out, &mut plain);
                let _ = write!(out, r#"<tspan class="{class}">${}</tspan>"#, esc(&name));
                i = j;
                continue;
            }
        }
        if word_start
            && chars[i..].starts_with(&['e', 'x', 'e', 'c'])
            && !chars.get(i + 4).is_some_and(|c| is_ident(*c))
        {
            flush(out, &mut plain);
            out.push_str(r#"<tspan class="exec">exec</tspan>"#);
            i += 4;
            continue;
        }
        plain.push(c);
        i += 1;
    }
    flush(out, &mut plain);
    out.push_str("</text>\n");
}

fn subject_attrs(s: &Subject, parent: &str) -> (String, String) {
    match s {
        Subject::Node { id, kind, composite, range } => {
            let k = match kind {
                NodeKind::State => "state",
                NodeKind::Initial => "initial",
                NodeKind::Junction => "junction",
                NodeKind::Final => "final",
                NodeKind::ProbabilisticJunction => "probabilistic-junction",
            };
            let class = format!("node {k}{}", if *composite { " composite" } else { "" });
            (
                class,
                format!(
                    r#" data-kind="{k}" data-id="{}" data-parent="{}"{}"#,
                    esc(id),
                    esc(parent),
                    range_attrs(range)
                ),
            )
        }
        Subject::Transition { id, source, target, range } => (
            "transition".into(),
            format!(
                r#" data-kind="transition" data-id="{}" data-parent="{}" data-source="{}" data-target="{}"{}"#,
                esc(id),
                esc(parent),
                esc(source.as_deref().unwrap_or("")),
                esc(target.as_deref().unwrap_or("")),
                range_attrs(range)
            ),
        ),
        Subject::Block { id, kind, range } => (
            format!("block {kind}"),
            format!(r#" data-kind="{}" data-id="{}"{}"#, esc(kind), esc(id), range_attrs(range)),
        ),
        Subject::Connection { from, to, direction, is_async, range } => (
            format!("connection {direction}{}", if *is_async { " async" } else { "" }),
            format!(
                r#" data-kind="connection" data-source="{}" data-target="{}" data-direction="{direction}"{}"#,
                esc(from),
                esc(to),
                range_attrs(range)
            ),
        ),
    }
}

/// A circle of class `class` centred on (`cx`, `cy`).
fn circle(out: &mut String, class: &str, cx: f64, cy: f64, radius: f64) {
    let _ = writeln!(out, r#"<circle class="{class}" cx="{}" cy="{}" r="{}"/>"#, n(cx), n(cy), n(radius));
}

fn shape(out: &mut String, s: &Shape, d: &Diagram, parent: &str, marks: &Marked) {
    let (class, attrs) = subject_attrs(&s.subject, parent);
    let mark = marked(&s.subject, marks);
    let class = if mark.is_some() { format!("{class} highlight") } else { class };
    let _ = writeln!(out, r#"<g class="{class}"{attrs}>"#);
    if let Some(t) = &s.title {
        let _ = writeln!(out, "<title>{}</title>", esc(t));
    }
    let r = &s.rect;
    if let Some(cycles) = mark {
        badge(out, cycles, r.x + r.w + 2.0, r.y + 10.0);
    }
    let (cx, cy) = (r.x + r.w / 2.0, r.y + r.h / 2.0);
    match &s.subject {
        Subject::Node { kind: NodeKind::Initial, .. } => circle(out, "initial-dot", cx, cy, r.w / 2.0),
        Subject::Node { kind: NodeKind::Junction, .. } if s.texts.is_empty() => {
            circle(out, "junction-dot", cx, cy, r.w / 2.0 - 1.0);
        }
        Subject::Node { kind: NodeKind::ProbabilisticJunction, .. } => {
            circle(out, "junction-dot", cx, cy, r.w / 2.0 - 1.0);
            let _ = writeln!(
                out,
                r#"<text class="prob" x="{}" y="{}" text-anchor="middle" font-size="10">P</text>"#,
                n(cx),
                n(cy + 3.5)
            );
        }
        Subject::Node { kind: NodeKind::Final, .. } if s.texts.is_empty() => {
            circle(out, "final-ring", cx, cy, r.w / 2.0 - 1.0);
            circle(out, "final-dot", cx, cy, r.w / 2.0 - 5.0);
        }
        _ => {
            let rx = if matches!(s.subject, Subject::Block { .. }) { 3 } else { 10 };
            let _ = writeln!(
                out,
                r#"<rect class="node-box" x="{}" y="{}" width="{}" height="{}" rx="{rx}"/>"#,
                n(r.x),
                n(r.y),
                n(r.w),
                n(r.h)
            );
        }
    }
    if let Some(y) = s.separator {
        let _ = writeln!(
            out,
            r#"<line class="separator" x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
            n(r.x),
            n(y),
            n(r.x + r.w),
            n(y)
        );
    }
    for t in &s.texts {
        text(out, t, d, "");
    }
    let id = match &s.subject {
        Subject::Node { id, .. } => id.as_str(),
        _ => "",
    };
    for c in &s.children {
        shape(out, c, d, id, marks);
    }
    for e in &s.edges {
        edge(out, e, d, id, marks);
    }
    out.push_str("</g>\n");
}

fn path_d(path: &[Cubic]) -> String {
    let mut s = String::new();
    if let Some(first) = path.first() {
        let _ = write!(s, "M{} {}", n(first.p0.0), n(first.p0.1));
    }
    for c in path {
        let _ = write!(s, " C{} {} {} {} {} {}", n(c.c1.0), n(c.c1.1), n(c.c2.0), n(c.c2.1), n(c.p3.0), n(c.p3.1));
    }
    s
}

fn edge(out: &mut String, e: &Edge, d: &Diagram, parent: &str, marks: &Marked) {
    let (class, attrs) = subject_attrs(&e.subject, parent);
    let mark = marked(&e.subject, marks);
    let class = if mark.is_some() { format!("{class} highlight") } else { class };
    let _ = writeln!(out, r#"<g class="{class}"{attrs}>"#);
    if let Some(t) = &e.title {
        let _ = writeln!(out, "<title>{}</title>", esc(t));
    }
    if let (Some(cycles), Some(t)) = (mark, e.texts.first()) {
        badge(out, cycles, t.rect.x, t.rect.y - 2.0);
    }
    let mut edge_class = String::from("edge");
    if e.dashed {
        edge_class.push_str(" dashed");
    }
    if let Subject::Connection { direction, .. } = &e.subject {
        if direction != "internal" {
            edge_class.push(' ');
            edge_class.push_str(direction);
        }
    }
    let start = if e.both_heads { r#" marker-start="url(#rs-arrow)""# } else { "" };
    let _ = writeln!(out, r#"<path class="{edge_class}" d="{}"{start} marker-end="url(#rs-arrow)"/>"#, path_d(&e.path));
    for t in &e.texts {
        let _ = writeln!(
            out,
            r#"<rect class="label-bg" x="{}" y="{}" width="{}" height="{}"/>"#,
            n(t.rect.x - 1.0),
            n(t.rect.y),
            n(t.rect.w + 2.0),
            n(t.rect.h)
        );
    }
    for t in &e.texts {
        text(out, t, d, "");
    }
    out.push_str("</g>\n");
}
