//! Quick fixes for diagnostics. Each fix is a [`SourceChange`], computed
//! for the diagnostics of the current text that touch the requested range:
//!
//! - `SYN-01`, legacy empty `trigger`: delete the keyword;
//! - `RS:SM6`: add or remove the `$` (the message says which);
//! - `RS:SM5`: move a machine-level `requires I` into the machine's output
//!   context (creating it when there is none), possibly in another file;
//! - `REQ-01`: add `cycleDef cycle == 1`, or an empty `input context { }` or
//!   `output context { }`;
//! - `LNK-01`, unresolved event of a RoboChart trigger or communication:
//!   declare `event e` in the machine (typed after the variable of `e?x`);
//! - `CSP-N04`: name a block's function as RoboTool 3's CSPm calls the
//!   model's (`floor` → `Mathematics_floor`), in every clause and use of
//!   the block.

use robosim_hir::defs::{file_defs, Def, DefKind, Io, UseKind};
use robosim_hir::nav::type_ref_text;
use robosim_hir::resolve::{ctx_members, enclosing, Ctx};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{FileKind, SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange, TextSize};

use crate::diagnostics::Diagnostic;
use crate::edit::{SourceChange, TextEdit};
use crate::hover::prev_significant;
use crate::FileId;

/// A fix for a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Assist {
    /// What it does, for a menu.
    pub title: String,
    /// The diagnostic it fixes.
    pub diagnostic: Diagnostic,
    /// The edits.
    pub change: SourceChange,
}

pub(crate) fn code_actions(db: &dyn Db, ws: Workspace, file: File, range: TextRange) -> Vec<Assist> {
    if file.is_library(db) {
        return Vec::new();
    }
    let mut out = Vec::new();
    for d in crate::diagnostics::diagnostics(db, ws, file) {
        if d.range.intersect(range).is_none() {
            continue;
        }
        let fix = match d.code.as_str() {
            "SYN-01" if d.message.contains("empty `trigger`") => empty_trigger(db, file, &d),
            "RS:SM6" => dollar(db, file, &d),
            "RS:SM5" => move_requires(db, file, &d),
            "REQ-01" => required_part(db, file, &d),
            "LNK-01" if d.message.starts_with("cannot resolve event `") => declare_event(db, ws, file, &d),
            "CSP-N04" => robotool_function_name(db, ws, file, &d),
            _ => None,
        };
        if let Some((title, change)) = fix {
            let change = change.finish();
            if !change.is_empty() {
                out.push(Assist { title, diagnostic: d, change });
            }
        }
    }
    out
}

type Fix = Option<(String, SourceChange)>;

fn single(db: &dyn Db, file: File, title: String, edits: Vec<TextEdit>) -> Fix {
    let mut change = SourceChange::default();
    for e in edits {
        change.push(FileId(file), file.path(db), e);
    }
    Some((title, change))
}

fn slice(text: &str, range: TextRange) -> &str {
    text.get(usize::from(range.start())..usize::from(range.end())).unwrap_or("")
}

/// Deletes `range`, and the whole line when nothing else is on it; else
/// the blanks after it (or before it, at the end of a line).
fn delete_with_blanks(text: &str, range: TextRange) -> TextEdit {
    let (s, e) = (usize::from(range.start()), usize::from(range.end()).min(text.len()));
    let line_start = text[..s].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[e..].find('\n').map_or(text.len(), |i| e + i);
    let before = &text[line_start..s];
    let after = &text[e..line_end];
    if before.trim().is_empty() && after.trim().is_empty() {
        let end = if line_end < text.len() { line_end + 1 } else { line_end };
        return TextEdit::delete(TextRange::new((line_start as u32).into(), (end as u32).into()));
    }
    let blanks_after = after.len() - after.trim_start_matches([' ', '\t']).len();
    if blanks_after > 0 && !after.trim().is_empty() {
        return TextEdit::delete(TextRange::new(range.start(), ((e + blanks_after) as u32).into()));
    }
    let blanks_before = before.len() - before.trim_end_matches([' ', '\t']).len();
    TextEdit::delete(TextRange::new(((s - blanks_before) as u32).into(), range.end()))
}

fn empty_trigger(db: &dyn Db, file: File, d: &Diagnostic) -> Fix {
    let text = file.text(db);
    if slice(text, d.range) != "trigger" {
        return None;
    }
    single(db, file, "Remove the empty `trigger`".into(), vec![delete_with_blanks(text, d.range)])
}

fn dollar(db: &dyn Db, file: File, d: &Diagnostic) -> Fix {
    let text = file.text(db);
    let name = slice(text, d.range).trim();
    if name.is_empty() {
        return None;
    }
    if d.message.contains("without `$`") {
        let root = robosim_hir::parse(db, file).syntax_node();
        let token = root.token_at_offset(d.range.start()).right_biased()?;
        let dollar = prev_significant(&token).filter(|t| t.kind() == DOLLAR)?;
        let range = TextRange::new(dollar.text_range().start(), d.range.start());
        single(db, file, format!("Write `{name}` without `$`"), vec![TextEdit::delete(range)])
    } else {
        single(db, file, format!("Write `${name}`"), vec![TextEdit::insert(d.range.start(), "$")])
    }
}

/// The syntax node of a definition.
fn node_of(db: &dyn Db, file: File, def: &Def) -> Option<SyntaxNode> {
    let root = robosim_hir::parse(db, file).syntax_node();
    let start = match root.covering_element(def.range) {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    start.ancestors().find(|n| n.text_range() == def.range && n.kind() == def.syntax)
}

/// The leading blanks of the line containing `offset`.
fn line_indent(text: &str, offset: TextSize) -> &str {
    let at = usize::from(offset).min(text.len());
    let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line = &text[start..];
    &line[..line.len() - line.trim_start_matches([' ', '\t']).len()]
}

/// The line break the file uses.
fn eol(text: &str) -> &'static str {
    if text.contains("\r\n") {
        "\r\n"
    } else {
        "\n"
    }
}

/// Inserts `member` into the body of `block`: after the child `after`, or
/// at the start of the body. A one-line body gets it on the same line;
/// otherwise it goes on a line of its own, indented as the other members.
fn insert_member(text: &str, block: &SyntaxNode, after: Option<&SyntaxNode>, member: &str) -> Option<TextEdit> {
    let tokens: Vec<_> = block.children_with_tokens().filter_map(|e| e.into_token()).collect();
    let l = tokens.iter().find(|t| t.kind() == L_CURLY)?;
    let r = tokens.iter().rfind(|t| t.kind() == R_CURLY);
    let pos = after.map_or(l.text_range().end(), |a| a.text_range().end());
    let one_line =
        r.is_some_and(|r| !slice(text, TextRange::new(l.text_range().end(), r.text_range().start())).contains('\n'));
    if one_line {
        return Some(TextEdit::insert(pos, format!(" {member}")));
    }
    // The indentation of the members, or one level deeper than the block.
    let first_member = block
        .children_with_tokens()
        .skip_while(|e| e.kind() != L_CURLY)
        .skip(1)
        .find(|e| !e.kind().is_trivia() && e.kind() != R_CURLY);
    let on_own_line = |at: TextSize| text[..usize::from(at)].trim_end_matches([' ', '\t']).ends_with('\n');
    let indent = match first_member {
        Some(m) if on_own_line(m.text_range().start()) => line_indent(text, m.text_range().start()).to_string(),
        _ => {
            let unit = if text.lines().any(|l| l.starts_with('\t')) { "\t" } else { "    " };
            format!("{}{unit}", line_indent(text, block.text_range().start()))
        }
    };
    // At the end of the line of `pos`, unless that is inside a comment.
    let p = usize::from(pos);
    let line_end = text[p..].find('\n').map_or(text.len(), |i| p + i);
    let line_end = if text[..line_end].ends_with('\r') { line_end - 1 } else { line_end };
    let root = block.ancestors().last()?;
    let at = TextSize::from(line_end as u32);
    // A line comment ends at the line break inserted first: only block
    // comments, strings and CSP text would swallow the member.
    let inside_token = root.token_at_offset(at).any(|t| {
        let r = t.text_range();
        r.start() < at && at < r.end() && !matches!(t.kind(), WHITESPACE | LINE_COMMENT)
    });
    let at = if inside_token { pos } else { at };
    Some(TextEdit::insert(at, format!("{}{indent}{member}", eol(text))))
}

fn required_part(db: &dyn Db, file: File, d: &Diagnostic) -> Fix {
    let text = file.text(db);
    let defs = file_defs(db, file);
    let (_, def) = defs.iter().find(|(_, x)| {
        x.name_range == d.range
            && matches!(x.kind, DefKind::StateMachine | DefKind::Controller | DefKind::Module | DefKind::Operation)
    })?;
    let node = node_of(db, file, def)?;
    let child = |k: SyntaxKind| node.children().filter(|c| c.kind() == k).last();
    let (title, member, after) = if d.message.contains("needs a `cycleDef`") {
        ("Add `cycleDef cycle == 1`", "cycleDef cycle == 1", None)
    } else if d.message.contains("needs an `input context") {
        ("Add an empty `input context`", "input context { }", child(CYCLE_DEF))
    } else if d.message.contains("needs an `output context") {
        ("Add an empty `output context`", "output context { }", child(INPUT_CONTEXT).or_else(|| child(CYCLE_DEF)))
    } else {
        return None;
    };
    let edit = insert_member(text, &node, after.as_ref(), member)?;
    single(db, file, title.to_string(), vec![edit])
}

fn move_requires(db: &dyn Db, file: File, d: &Diagnostic) -> Fix {
    // The machine-level `requires` is at the diagnostic, or (for a machine
    // declared elsewhere) at one of its related locations.
    let places = std::iter::once((file, d.range)).chain(d.related.iter().map(|r| (r.file.0, r.range)));
    for (f, range) in places {
        let defs = file_defs(db, f);
        let Some(u) = defs.uses.iter().find(|u| u.range == range && u.kind == UseKind::Requires && u.io.is_none())
        else {
            continue;
        };
        let text = f.text(db);
        let machine = defs.def(u.owner);
        let node = node_of(db, f, machine)?;
        let root = node.ancestors().last()?;
        let use_node = match root.covering_element(u.range) {
            rowan::NodeOrToken::Node(n) => n,
            rowan::NodeOrToken::Token(t) => t.parent()?,
        }
        .ancestors()
        .find(|n| n.kind() == INTERFACE_USE)?;
        let iface = slice(text, u.range).trim().to_string();
        let mut edits = vec![delete_with_blanks(text, use_node.text_range())];
        let already = defs.uses_of(u.owner).any(|o| o.io == Some(Io::Output) && o.path == u.path);
        if !already {
            let insert = match node.children().find(|c| c.kind() == OUTPUT_CONTEXT) {
                Some(out) => insert_member(text, &out, None, &format!("requires {iface}"))?,
                None => {
                    let after = node.children().filter(|c| matches!(c.kind(), INPUT_CONTEXT | CYCLE_DEF)).last();
                    insert_member(text, &node, after.as_ref(), &format!("output context {{ requires {iface} }}"))?
                }
            };
            edits.push(insert);
        }
        let mut change = SourceChange::default();
        for e in edits {
            change.push(FileId(f), f.path(db), e);
        }
        return Some((format!("Move `requires {iface}` into the output context of `{}`", machine.name), change));
    }
    None
}

fn declare_event(db: &dyn Db, ws: Workspace, file: File, d: &Diagnostic) -> Fix {
    if file.kind(db) != FileKind::RoboChart {
        return None;
    }
    let text = file.text(db);
    let name = slice(text, d.range).trim().to_string();
    if name.is_empty() || name.contains("::") {
        return None;
    }
    let root = robosim_hir::parse(db, file).syntax_node();
    let token = root.token_at_offset(d.range.start()).right_biased()?;
    let comm = token.parent_ancestors().find(|n| n.kind() == COMMUNICATION)?;
    let defs = file_defs(db, file);
    let inner = defs.innermost(d.range)?;
    let owner = enclosing(defs, inner, &[DefKind::StateMachine, DefKind::Operation, DefKind::Controller])?;
    // `e?x`: the type of `x`; `e!v`, `e.v`: unknown, so no fix.
    let mut ty = String::new();
    if let Some(input) = comm.children().find(|c| c.kind() == COMM_INPUT) {
        let var = input.descendants_with_tokens().filter_map(|e| e.into_token()).find(|t| t.kind() == IDENT)?;
        let var = var.text().trim_start_matches('^').to_string();
        let m = ctx_members(db, ws, Ctx::Local(file, owner))
            .into_owned()
            .into_iter()
            .find(|m| m.name == var && matches!(m.kind, DefKind::Variable | DefKind::Parameter))?;
        ty = format!(" : {}", type_ref_text(m.ty.as_ref()?));
    } else if comm.children().any(|c| matches!(c.kind(), COMM_OUTPUT | COMM_SYNC)) {
        return None;
    }
    let od = defs.def(owner);
    let node = node_of(db, file, od)?;
    let after = node.children().filter(|c| c.kind() == EVENT).last();
    let member = format!("event {name}{ty}");
    let edit = insert_member(text, &node, after.as_ref(), &member)?;
    single(db, file, format!("Declare `{member}` in {} `{}`", od.kind.describe(), od.name), vec![edit])
}

/// CSP-N04: renames the block's function (at the diagnostic) to the name
/// the message gives (`its calls use `X``), wherever the block writes it:
/// a name a block defines is that definition throughout the block.
fn robotool_function_name(db: &dyn Db, ws: Workspace, file: File, d: &Diagnostic) -> Fix {
    let text = file.text(db);
    let old = slice(text, d.range);
    let new = d.message.split("its calls use `").nth(1)?.split('`').next()?;
    let block = robosim_hir::csp_blocks::csp_blocks(db, ws, file).at(d.range.start())?;
    let body = block.body?;
    let bytes = text.as_bytes();
    let ident = |i: usize| bytes.get(i).is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_' || *c == b'\'');
    let (start, end) = (usize::from(body.start()), usize::from(body.end()).min(text.len()));
    let edits = text[start..end]
        .match_indices(old)
        .map(|(i, _)| start + i)
        .filter(|&i| !ident(i.wrapping_sub(1)) && !ident(i + old.len()))
        .map(|i| TextEdit::replace(TextRange::at((i as u32).into(), TextSize::of(old)), new.to_string()))
        .collect();
    single(db, file, format!("Rename `{old}` to `{new}`, RoboTool 3's name of the model's function"), edits)
}
