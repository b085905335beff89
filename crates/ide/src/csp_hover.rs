//! The **tock-CSP** section of hovers: on a state machine, controller or
//! module name, a transition, an `exec`, a RoboSim output or a platform
//! call, the CSP term `robosim csp` generates for it (RoboTool 3
//! semantics) and a one-line reading in English.

use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{TextRange, TextSize};

/// The section's range and Markdown, when the construct at `offset` has a term.
pub(crate) fn csp_section(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<(TextRange, String)> {
    let t = robosim_semantics::hover::hover_term(db, ws, file, offset)?;
    Some((t.range, format!("**tock-CSP**\n\n```csp\n{}\n```\n\n{}", t.term, t.reading)))
}
