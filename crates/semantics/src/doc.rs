//! A small Wadler-style pretty-printing document: text, optional line
//! breaks grouped so that a group is printed on one line when it fits, and
//! nesting for the indentation of broken lines.

/// A document.
#[derive(Debug, Clone)]
pub(crate) enum Doc {
    /// Text without newlines.
    Text(String),
    /// A space when its group is flat, a newline (and the indentation) when broken.
    Line,
    /// Nothing when flat, a newline when broken.
    SoftLine,
    /// Always a newline: its groups are never flat.
    HardLine,
    /// In sequence.
    Cat(Vec<Doc>),
    /// Broken lines inside are indented by this much more.
    Nest(usize, Box<Doc>),
    /// Printed flat when it fits in the remaining width.
    Group(Box<Doc>),
}

pub(crate) fn text(s: impl Into<String>) -> Doc {
    Doc::Text(s.into())
}

pub(crate) fn cat(parts: Vec<Doc>) -> Doc {
    Doc::Cat(parts)
}

pub(crate) fn nest(n: usize, d: Doc) -> Doc {
    Doc::Nest(n, Box::new(d))
}

pub(crate) fn group(d: Doc) -> Doc {
    Doc::Group(Box::new(d))
}

/// Renders `doc` in `width` columns.
pub(crate) fn render(doc: &Doc, width: usize) -> String {
    let mut out = String::new();
    let mut col = 0usize;
    // (indent, flat, doc)
    let mut stack: Vec<(usize, bool, &Doc)> = vec![(0, false, doc)];
    while let Some((ind, flat, d)) = stack.pop() {
        match d {
            Doc::Text(s) => {
                out.push_str(s);
                col += s.chars().count();
            }
            Doc::Line | Doc::SoftLine if flat => {
                if matches!(d, Doc::Line) {
                    out.push(' ');
                    col += 1;
                }
            }
            Doc::Line | Doc::SoftLine | Doc::HardLine => {
                // No trailing spaces on broken lines.
                while out.ends_with(' ') {
                    out.pop();
                }
                out.push('\n');
                out.push_str(&" ".repeat(ind));
                col = ind;
            }
            Doc::Cat(parts) => {
                for p in parts.iter().rev() {
                    stack.push((ind, flat, p));
                }
            }
            Doc::Nest(n, inner) => stack.push((ind + n, flat, inner)),
            Doc::Group(inner) => {
                let flat_now = flat || fits(inner, width.saturating_sub(col), &stack);
                stack.push((ind, flat_now, inner));
            }
        }
    }
    out
}

/// Whether `d`, printed flat, fits in `room` columns, counting the text
/// that follows it up to the next possible line break.
fn fits(d: &Doc, room: usize, rest: &[(usize, bool, &Doc)]) -> bool {
    let mut room = room.min(isize::MAX as usize / 2) as isize;
    let mut todo: Vec<&Doc> = vec![d];
    // Measure the group itself flat.
    while let Some(d) = todo.pop() {
        match d {
            Doc::Text(s) => room -= s.chars().count() as isize,
            Doc::Line => room -= 1,
            Doc::SoftLine => {}
            Doc::HardLine => return false,
            Doc::Cat(parts) => todo.extend(parts.iter().rev()),
            Doc::Nest(_, inner) | Doc::Group(inner) => todo.push(inner),
        }
        if room < 0 {
            return false;
        }
    }
    // Then what follows on the same line.
    for (_, flat, d) in rest.iter().rev() {
        let mut todo: Vec<&Doc> = vec![d];
        while let Some(d) = todo.pop() {
            match d {
                Doc::Text(s) => room -= s.chars().count() as isize,
                Doc::Line | Doc::SoftLine if *flat => {
                    if matches!(d, Doc::Line) {
                        room -= 1
                    }
                }
                Doc::Line | Doc::SoftLine | Doc::HardLine => return room >= 0,
                Doc::Cat(parts) => todo.extend(parts.iter().rev()),
                Doc::Nest(_, inner) => todo.push(inner),
                // A following group may break where it needs to.
                Doc::Group(_) => return room >= 0,
            }
            if room < 0 {
                return false;
            }
        }
    }
    room >= 0
}
