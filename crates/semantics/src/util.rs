//! Small helpers over names and the model.

use robosim_hir::model::DefId;
use robosim_hir::{model, Db, File, Workspace};

/// The top-level element `id` of the model of `file` (read from its
/// element's model alone).
pub(crate) fn model_item_of(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> Option<&model::Item> {
    model::item_of(db, ws, file, id)
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
    "endexec",
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

/// The call event of the operation `op` (`suffix` `Call`, or `Ret` in
/// paper2019) as RoboTool names it: `setCall` for an operation `set`. The
/// whole name is escaped, not the operation's alone (`set_Call`), since
/// only the whole needs to avoid CSPm's reserved names.
pub(crate) fn op_event(op: &str, suffix: &str) -> String {
    ident(&format!("{op}{suffix}"))
}

/// The channel of a RoboChart event `e` of a controller or module:
/// RoboTool's name, the event's own, even `in` or `out` (InOut's
/// constructors, which the container then writes as `in'`/`out'`).
pub(crate) fn event_ident(e: &str) -> String {
    if matches!(e, "in" | "out") {
        e.to_string()
    } else {
        ident(e)
    }
}

/// `a::b::c` as one identifier `a_b_c`.
pub(crate) fn qualified(path: &[String]) -> String {
    ident(&path.join("_"))
}

/// The CSPm module of an element `robosim_hir::csp_names` does not name:
/// as it would, the element `M` of package `A::B` is the module `M` inside
/// the package's module `A_B`, written `A_B::M` (just `M` in the default
/// package), and a nested element is inside its container's (`A_B::C::S`).
/// `path` is the element's model path, starting with `package`.
pub(crate) fn element_module(package: &[String], path: &[String]) -> String {
    let rest = match path.strip_prefix(package) {
        Some(rest) if !rest.is_empty() => rest,
        _ => return qualified(path),
    };
    let mut parts: Vec<String> = rest.iter().map(|s| ident(s)).collect();
    if !package.is_empty() {
        parts.insert(0, qualified(package));
    }
    parts.join("::")
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
