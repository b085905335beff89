//! Small helpers over the syntax tree and names.

use robosim_hir::defs::{file_defs, DefId, DefKind};
use robosim_hir::index::{resolve_item, ItemLoc};
use robosim_hir::{model, parse, Db, File, Workspace};
use robosim_syntax::ast;
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

/// The text of the first `NAME` child, without `^`.
pub(crate) fn name_of(n: &SyntaxNode) -> String {
    n.children().find(|c| c.kind() == NAME).map(|c| ident_text(&c)).unwrap_or_default()
}

/// The range of the first `NAME` child (or of the node).
pub(crate) fn name_range(n: &SyntaxNode) -> TextRange {
    n.children().find(|c| c.kind() == NAME).map(|c| c.text_range()).unwrap_or_else(|| n.text_range())
}

/// An identifier's text without `^` and whitespace; the segments of the
/// node's qualified name (itself or its first child).
pub(crate) use robosim_syntax::ast::{name_text as ident_text, qualified_path as path_of};

/// The first child of `kind`.
pub(crate) fn child(n: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxNode> {
    n.children().find(|c| c.kind() == kind)
}

/// The children of `kind`.
pub(crate) fn children(n: &SyntaxNode, kind: SyntaxKind) -> impl Iterator<Item = SyntaxNode> {
    n.children().filter(move |c| c.kind() == kind)
}

/// The first type child.
pub(crate) fn type_child(n: &SyntaxNode) -> Option<SyntaxNode> {
    n.children().find(|c| ast::is_type_kind(c.kind()))
}

/// The syntax node of a top-level item.
pub(crate) fn node_of(db: &dyn Db, loc: ItemLoc) -> Option<SyntaxNode> {
    let id = loc.def(db)?;
    let def = file_defs(db, loc.file).def(id);
    let root = parse(db, loc.file).syntax_node();
    let node = match root.covering_element(def.range) {
        robosim_syntax::SyntaxElement::Node(n) => n,
        robosim_syntax::SyntaxElement::Token(t) => t.parent()?,
    };
    node.ancestors().find(|n| n.kind() == def.syntax && n.text_range() == def.range)
}

/// The top-level element `id` of the model of `file`.
pub(crate) fn model_item_of(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> Option<&model::Item> {
    model::file_model(db, ws, file).items.iter().find(|(d, _)| *d == id).map(|(_, i)| i)
}

/// The top-level definition of `file` declared at `range`.
pub(crate) fn def_at(db: &dyn Db, file: File, range: TextRange) -> Option<DefId> {
    file_defs(db, file).iter().find(|(_, d)| d.range == range && d.parent.is_none()).map(|(id, _)| id)
}

/// The top-level element of the model of `file` at `range`.
pub(crate) fn model_item(db: &dyn Db, ws: Workspace, file: File, range: TextRange) -> Option<&model::Item> {
    model::file_model(db, ws, file).items.iter().map(|(_, i)| i).find(|i| item_range(i) == Some(range))
}

fn item_range(i: &model::Item) -> Option<TextRange> {
    match i {
        model::Item::Machine(b) | model::Item::Operation(b) => Some(b.range),
        model::Item::Controller(c) => Some(c.range),
        model::Item::Module(m) => Some(m.range),
        model::Item::Platform(p) | model::Item::Interface(p) => Some(p.range),
        model::Item::Function(f) => Some(f.range),
        _ => None,
    }
}

/// The machine or operation of the model of `file` at `range`: a
/// top-level one or one declared inside a controller or module.
pub(crate) fn model_behaviour(db: &dyn Db, ws: Workspace, file: File, range: TextRange) -> Option<model::Behaviour> {
    fn in_controller(c: &model::Controller, range: TextRange) -> Option<&model::Behaviour> {
        c.machines.iter().chain(&c.operations).find_map(|i| match &i.def {
            model::Definition::Inline(b) if b.range == range => Some(&**b),
            _ => None,
        })
    }
    model::file_model(db, ws, file).items.iter().find_map(|(_, i)| match i {
        model::Item::Machine(b) | model::Item::Operation(b) if b.range == range => Some(b.clone()),
        model::Item::Controller(c) => in_controller(c, range).cloned(),
        model::Item::Module(m) => m.controllers.iter().find_map(|c| match &c.def {
            model::Definition::Inline(c) => in_controller(c, range).cloned(),
            model::Definition::Ref { .. } => None,
        }),
        _ => None,
    })
}

/// Resolves `path`, written in `from`, to an item of one of the kinds.
pub(crate) fn resolve(
    db: &dyn Db,
    ws: Workspace,
    from: File,
    path: &[String],
    accept: fn(DefKind) -> bool,
) -> Option<(File, SyntaxNode)> {
    let loc = resolve_item(db, ws, from, path, accept).into_iter().next()?;
    Some((loc.file, node_of(db, loc)?))
}

/// CSPm reserved words and the names of its built-in functions and
/// processes, which generated names must avoid.
pub(crate) const RESERVED: &[&str] = &[
    "if",
    "then",
    "else",
    "let",
    "within",
    "channel",
    "datatype",
    "subtype",
    "nametype",
    "assert",
    "include",
    "transparent",
    "external",
    "module",
    "exports",
    "endmodule",
    "instance",
    "print",
    "true",
    "false",
    "not",
    "and",
    "or",
    "STOP",
    "SKIP",
    "CHAOS",
    "RUN",
    "WAIT",
    "Events",
    "Int",
    "Bool",
    "Proc",
    "Char",
    "Seq",
    "Set",
    "Timed",
    "union",
    "inter",
    "diff",
    "member",
    "card",
    "empty",
    "set",
    "seq",
    "length",
    "null",
    "head",
    "tail",
    "concat",
    "elem",
    "prioritise",
    "in",
    "out",
    "tock",
    "terminate",
    "timelock",
    "error",
    "show",
];

/// A CSPm identifier made of `s`: letters, digits and `_` only, not
/// starting with a digit, not reserved.
pub(crate) fn ident(s: &str) -> String {
    let mut out: String = s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert(0, 'x');
    }
    if RESERVED.contains(&out.as_str()) {
        out.push('_');
    }
    out
}

/// `a::b::c` as one identifier `a_b_c`.
pub(crate) fn qualified(path: &[String]) -> String {
    ident(&path.join("_"))
}

/// The CSPm module of a RoboChart element as RoboTool names it
/// (`robosim_hir::csp_names`): the element `M` of package `A::B` is the
/// module `M` inside the package's module `A_B`, written `A_B::M` (just `M`
/// in the default package). `path` is the element's model path, starting
/// with `package`; a nested element keeps its container's name (`C_S`).
pub(crate) fn element_module(package: &[String], path: &[String]) -> String {
    match path.strip_prefix(package) {
        Some(rest) if !package.is_empty() && !rest.is_empty() => format!("{}::{}", qualified(package), qualified(rest)),
        _ => qualified(path),
    }
}

/// The 1-based line and column of `offset` in `text`.
pub(crate) fn line_col(text: &str, offset: u32) -> (u32, u32) {
    let mut offset = (offset as usize).min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() as u32 + 1;
    let col = before.rsplit('\n').next().map(|l| l.chars().count()).unwrap_or(0) as u32 + 1;
    (line, col)
}
