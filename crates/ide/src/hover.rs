//! Hovers, in Markdown. Up to three sections, in this order:
//!
//! - on a name (a reference or a declaration): the declaration's signature
//!   in a code block, where it is declared and its doc comment; on a RoboSim
//!   `$` reference, also whether it is an input or an output and when in the
//!   cycle it is read or written (Cavalcanti et al., *Verified simulation
//!   for robotics*, SCP 2019, §3 and §5);
//! - in a `cycleDef`: the least admissible periods of the container's own
//!   specification and of the joint one with its components;
//! - inside the range of a diagnostic: its rule code, the rule's summary
//!   and where the catalogue is.

use std::fmt::Write;

use robosim_hir::cycle::Feasibility;
use robosim_hir::defs::{DefId, DefKind, Io};
use robosim_hir::element::{defs_around, defs_holding};
use robosim_hir::nav::{self, DeclLoc, Symbol};
use robosim_hir::resolve::{ctx_members, enclosing, Ctx, ResolvedRef};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{FileKind, SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange, TextSize};

use crate::navigation::{decl_at, symbol_range, trimmed};

/// A hover: Markdown text about the range under the cursor.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct HoverResult {
    /// The range the hover is about (the name, the `cycleDef`, or the
    /// diagnostic).
    pub range: TextRange,
    /// The text, in Markdown.
    pub markdown: String,
}

/// Where the rule catalogue lives, for links in diagnostic hovers.
const RULES_DOC: &str = concat!(env!("CARGO_PKG_REPOSITORY"), "/blob/main/docs/rules.md");

/// `shown`: the diagnostics to explain, when the caller has them (those an
/// editor shows); otherwise the file's are computed, which waits for the
/// complete check of its text.
pub(crate) fn hover(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
    shown: Option<&[crate::Diagnostic]>,
) -> Option<HoverResult> {
    let text = file.text(db);
    let offset = offset.min(TextSize::of(text.as_str()));
    let mut sections: Vec<String> = Vec::new();
    let mut range: Option<TextRange> = None;

    if let Some((sym, Some(decl))) = decl_at(db, ws, file, offset) {
        let mut s = declaration_section(db, file, decl);
        if let Symbol::Reference(r) = &sym {
            if let Some(io) = sim_io_section(db, ws, file, r, decl) {
                s.push_str("\n\n---\n\n");
                s.push_str(&io);
            }
        }
        sections.push(s);
        range = Some(trimmed(text, symbol_range(&sym)));
    }

    if let Some((cycle_range, s)) = cycle_section(db, ws, file, offset) {
        sections.push(s);
        range.get_or_insert(cycle_range);
    }

    if let Some((block_range, s)) = crate::csp_block::hover(db, ws, file, offset) {
        sections.push(s);
        range.get_or_insert(block_range);
    }

    if let Some((csp_range, s)) = crate::csp_hover::csp_section(db, ws, file, offset) {
        sections.push(s);
        range.get_or_insert(csp_range);
    }

    let mut explain = |code: &str, severity, r: TextRange| {
        if r.contains_inclusive(offset) {
            sections.push(diagnostic_section(code, severity));
            range.get_or_insert(r);
        }
    };
    match shown {
        Some(diags) => diags.iter().for_each(|d| explain(&d.code, d.severity, d.range)),
        None if !file.is_library(db) => {
            robosim_hir::file_diagnostics(db, ws, file).iter().for_each(|d| explain(&d.code, d.severity, d.range))
        }
        None => {}
    }

    let range = range?;
    Some(HoverResult { range, markdown: sections.join("\n\n---\n\n") })
}

fn language(kind: FileKind) -> &'static str {
    match kind {
        FileKind::RoboChart | FileKind::Assertions => "robochart",
        FileKind::RoboSim | FileKind::SimAssertions => "robosim",
    }
}

fn declaration_section(db: &dyn Db, from: File, decl: DeclLoc) -> String {
    let d = nav::describe(db, decl);
    let mut s = format!("```{}\n{}\n```", language(decl.file.kind(db)), d.signature);
    let mut place = Vec::new();
    if let Some(c) = &d.container {
        place.push(c.clone());
    }
    if decl.file != from {
        let path = decl.file.path(db);
        let name = std::path::Path::new(path.as_str()).file_name().map(|n| n.to_string_lossy().into_owned());
        place.push(format!("declared in `{}`", name.unwrap_or_else(|| path.clone())));
    }
    if !place.is_empty() {
        let _ = write!(s, "\n\n{}", place.join(", "));
    }
    if let Some(doc) = &d.doc {
        let _ = write!(s, "\n\n{doc}");
    }
    s
}

/// How a `$` reference uses its register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Use {
    /// `$e`, `$x` or `$e?v` in an expression.
    Read,
    /// `$x = …`.
    Assign,
    /// `$op(…)`.
    Call,
    /// `$e` or `$e!v` as a statement.
    Emit,
}

/// The non-trivia token before `token`.
pub(crate) fn prev_significant(token: &SyntaxToken) -> Option<SyntaxToken> {
    let mut t = token.prev_token();
    while let Some(x) = t {
        if !x.kind().is_trivia() {
            return Some(x);
        }
        t = x.prev_token();
    }
    None
}

/// The `$` of a reference starting at `start`, if it is a RoboSim `$` name.
fn dollar_before(root: &SyntaxNode, start: TextSize) -> Option<SyntaxToken> {
    let token = root.token_at_offset(start).right_biased()?;
    let prev = prev_significant(&token)?;
    (prev.kind() == DOLLAR).then_some(prev)
}

/// The context (machine or operation) whose members a name at `range` sees.
pub(crate) fn machine_of(db: &dyn Db, file: File, range: TextRange) -> Option<DefId> {
    let defs = defs_around(db, file, range);
    let inner = defs.innermost(range)?;
    enclosing(defs, inner, &[DefKind::Operation, DefKind::StateMachine])
}

fn sim_io_section(db: &dyn Db, ws: Workspace, file: File, r: &ResolvedRef, decl: DeclLoc) -> Option<String> {
    if file.kind(db) != FileKind::RoboSim {
        return None;
    }
    let root = robosim_hir::parse(db, file).syntax_node();
    let dollar = dollar_before(&root, r.range.start())?;
    let usage = match dollar.parent()?.kind() {
        ASSIGNABLE => Use::Assign,
        SIM_CALL_STMT => Use::Call,
        OUTPUT_COMM_STMT => Use::Emit,
        _ => Use::Read,
    };
    let kind = defs_holding(db, decl.file, decl.def).def(decl.def).kind;
    // The context the name is used in decides whether it is an input or an
    // output: interface members get their I/O from the `uses`/`requires`
    // that brings them in.
    let mut input = false;
    let mut output = false;
    if let (Some(target), Some(ctx)) = (r.target, machine_of(db, file, r.range)) {
        for m in ctx_members(db, ws, Ctx::Local(file, ctx)).into_owned() {
            if m.target == target {
                input |= m.io == Some(Io::Input);
                output |= m.io == Some(Io::Output);
            }
        }
    }
    if !input && !output {
        match defs_holding(db, decl.file, decl.def).def(decl.def).io {
            Some(Io::Input) => input = true,
            Some(Io::Output) => output = true,
            None => return None,
        }
    }
    let what = match kind {
        DefKind::Event => "event",
        DefKind::Variable => "variable",
        DefKind::OperationSig | DefKind::Operation => "operation",
        _ => "element",
    };
    let name = r.text.as_str();
    let both = input && output;
    let as_input = match usage {
        Use::Read => input || !output,
        _ => !output,
    };
    let mut s = String::new();
    if as_input {
        let _ = write!(s, "**Input {what}**");
        if both {
            s.push_str(" (also an output of this machine)");
        }
        s.push_str(". ");
        match kind {
            DefKind::Event => {
                let _ = write!(
                    s,
                    "Its register is read at the start of every cycle, before the machine runs. `${name}` is true in the cycles in which the event occurred; a value it carries (`${name}?x`) is meaningful only then."
                );
            }
            _ => {
                let _ = write!(
                    s,
                    "Its register is read at the start of every cycle, before the machine runs: `${name}` is the value read for the current cycle."
                );
            }
        }
    } else {
        let _ = write!(s, "**Output {what}**");
        if both {
            s.push_str(" (also an input of this machine)");
        }
        s.push_str(". ");
        let when = "when the cycle's processing ends (when the machine reaches an `exec` trigger)";
        let order = "with the other outputs of the cycle, in the order they were recorded; outputs that did not occur are written as absent";
        let _ = match kind {
            DefKind::Event => write!(
                s,
                "`${name}` records the event when the statement runs. The register is written {when}, {order}. A simulation assumes each output occurs at most once per cycle."
            ),
            DefKind::Variable => write!(
                s,
                "`${name} = …` records the new value when the statement runs. The register is written {when}, {order}. A simulation assumes each output occurs at most once per cycle."
            ),
            _ => write!(
                s,
                "`${name}(…)` calls the platform operation `{name}`: the call is recorded when the statement runs, and the operation is executed as the registers are written, {when}, {order}. A simulation assumes each operation is called at most once per cycle."
            ),
        };
    }
    Some(s)
}

fn feasibility(f: Feasibility) -> String {
    match f {
        Feasibility::Feasible(p) => format!("least admissible period **{p}**"),
        Feasibility::Infeasible => "no positive period".to_string(),
        Feasibility::Unknown => "could not be decided".to_string(),
    }
}

fn cycle_section(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<(TextRange, String)> {
    if file.kind(db) != FileKind::RoboSim {
        return None;
    }
    let root = robosim_hir::parse(db, file).syntax_node();
    let token = root.token_at_offset(offset).left_biased()?;
    let node = token.parent_ancestors().find(|n| n.kind() == CYCLE_DEF)?;
    let defs = defs_around(db, file, node.text_range());
    let owner = defs.innermost(node.text_range())?;
    let d = defs.def(owner);
    if !matches!(d.kind, DefKind::Module | DefKind::Controller | DefKind::StateMachine) {
        return None;
    }
    let mut s = format!("**Cycle of {} `{}`**\n\n", d.kind.describe(), d.name);
    let parts = match d.kind {
        DefKind::Module => Some(("its controllers", [DefKind::Controller, DefKind::ControllerRef])),
        DefKind::Controller => Some(("its machines", [DefKind::StateMachine, DefKind::MachineRef])),
        _ => None,
    };
    match nav::cycle_info(db, ws, file, owner) {
        Some(info) => {
            let _ = write!(s, "- on its own: {}", feasibility(info.own));
            if let Some((what, kinds)) = parts {
                match info.joint {
                    Some(j) => {
                        let _ = write!(s, "\n- with {what}: {}", feasibility(j));
                    }
                    None if info.own == Feasibility::Infeasible => {}
                    None if defs.children(Some(owner)).any(|(_, c)| kinds.contains(&c.kind)) => {
                        let _ = write!(
                            s,
                            "\n- with {what}: not decided, because one of them has no cycleDef, or one that is not a condition or admits no period on its own"
                        );
                    }
                    None => {}
                }
            }
        }
        None => s.push_str("No period is computed: the cycleDef is not a boolean condition on `cycle`."),
    }
    Some((trimmed(file.text(db), node.text_range()), s))
}

fn diagnostic_section(code: &str, severity: robosim_hir::Severity) -> String {
    let mut s = format!("**{code}** ({})", severity.as_str());
    if let Some(rule) = robosim_hir::codes::rule(code) {
        let _ = write!(s, ": {}", rule.summary);
    }
    let _ = write!(s, "\n\nSee [`{code}` in the rule catalogue]({RULES_DOC}) (`docs/rules.md`).");
    s
}
