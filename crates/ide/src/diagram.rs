//! Diagrams in the editor, independent of any protocol: the code lenses
//! that open the diagram of a state machine, operation, controller or
//! module, and the diagram models of a file (`robosim-diagram`) with their
//! SVG, as `robosim diagram` draws them.

use robosim_hir::defs::{file_defs, DefKind};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::TextRange;

pub use robosim_diagram::{render_dot, render_svg};

pub use robosim_diagram::model::{
    Action, Block, Connection, Diagram, DiagramKind, Node, NodeKind, Region, Span, Transition,
};

/// A diagram and its drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedDiagram {
    /// The diagram model (ranges in bytes and in lines and UTF-16 columns).
    pub diagram: Diagram,
    /// The standalone SVG document, whose groups carry their source range
    /// (`data-line`, `data-character`, …).
    pub svg: String,
}

/// A place from which a diagram can be opened: the name of a state
/// machine, operation, controller or module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiagramLens {
    /// The element's name.
    pub range: TextRange,
    /// What it is.
    pub kind: DiagramKind,
    /// The element's name.
    pub name: String,
    /// Its qualified name (package and enclosing elements, joined with
    /// `::`), which selects it among the diagrams of its file.
    pub qualified_name: String,
}

/// Why no diagram could be given.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DiagramError {
    /// The file declares nothing of that name.
    UnknownElement {
        /// The name asked for.
        element: String,
        /// The qualified names of what the file does declare.
        available: Vec<String>,
    },
}

impl std::fmt::Display for DiagramError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DiagramError::UnknownElement { element, available } if available.is_empty() => {
                write!(f, "no state machine, operation, controller or module named `{element}`: the file declares none")
            }
            DiagramError::UnknownElement { element, available } => write!(
                f,
                "no state machine, operation, controller or module named `{element}` (the file declares {})",
                available.iter().map(|a| format!("`{a}`")).collect::<Vec<_>>().join(", ")
            ),
        }
    }
}

impl std::error::Error for DiagramError {}

/// The diagram lenses of `file`: one on the name of each state machine,
/// operation, controller and module it declares, in source order.
pub(crate) fn lenses(db: &dyn Db, file: File) -> Vec<DiagramLens> {
    if file.is_library(db) || file.kind(db).is_assertions() {
        return Vec::new();
    }
    let defs = file_defs(db, file);
    let mut out = Vec::new();
    for (id, d) in defs.iter() {
        let kind = match d.kind {
            DefKind::StateMachine => DiagramKind::StateMachine,
            DefKind::Operation => DiagramKind::Operation,
            DefKind::Controller => DiagramKind::Controller,
            DefKind::Module => DiagramKind::Module,
            _ => continue,
        };
        if d.name.is_empty() {
            continue;
        }
        let mut qualified = defs.package.clone();
        qualified.extend(defs.local_path(id));
        out.push(DiagramLens { range: d.name_range, kind, name: d.name.clone(), qualified_name: qualified.join("::") });
    }
    out.sort_by_key(|l| l.range.start());
    out
}

/// The diagram models of `file`, in source order; only those named
/// `element` (a name or a qualified name) when it is given.
pub(crate) fn diagrams(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    element: Option<&str>,
) -> Result<Vec<Diagram>, DiagramError> {
    let mut all = robosim_diagram::file_diagrams(db, ws, file);
    let Some(element) = element else { return Ok(all) };
    let available: Vec<String> = all.iter().map(|d| d.qualified_name.clone()).collect();
    // The qualified name first: it is unique where simple names may not be.
    if all.iter().any(|d| d.qualified_name == element) {
        all.retain(|d| d.qualified_name == element);
    } else {
        all.retain(|d| d.name == element);
    }
    if all.is_empty() {
        return Err(DiagramError::UnknownElement { element: element.to_string(), available });
    }
    Ok(all)
}

/// Lays out and draws `diagram` as SVG. It reads no database: callers run
/// it outside queries.
pub fn render(diagram: Diagram) -> RenderedDiagram {
    let svg = robosim_diagram::render_svg(&diagram);
    RenderedDiagram { diagram, svg }
}

/// Draws `diagram` with the steps of `counterexamples` that fall in it
/// marked (states and transitions highlighted, labelled with their
/// cycles); plainly when none does.
pub fn render_with(diagram: Diagram, counterexamples: &[robosim_engine::verify::Counterexample]) -> RenderedDiagram {
    match render_marked(diagram.clone(), counterexamples) {
        Some(marked) => marked,
        None => render(diagram),
    }
}

/// Draws `diagram` with the steps of `counterexamples` that fall in it
/// marked; `None` when none does.
pub fn render_marked(
    diagram: Diagram,
    counterexamples: &[robosim_engine::verify::Counterexample],
) -> Option<RenderedDiagram> {
    let mut steps = Vec::new();
    for c in counterexamples {
        let last = c.steps.last().map_or(0, |s| s.cycle);
        let located = c.steps.iter().chain(&c.specification).filter_map(|s| s.location.as_ref().map(|l| (l, s.cycle)));
        for (l, cycle) in located.chain(c.stuck_at.iter().map(|l| (l, last))) {
            let at = u32::from(l.range.start());
            if l.file == diagram.file && diagram.range.start <= at && at < diagram.range.end {
                steps.push((at, cycle));
            }
        }
    }
    if steps.is_empty() {
        return None;
    }
    let svg = robosim_diagram::render_svg_marked(&diagram, &robosim_diagram::Marks { steps });
    Some(RenderedDiagram { diagram, svg })
}
