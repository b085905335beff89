//! Navigation over resolved names, for editors: the reference or
//! declaration at an offset, where a target is declared, every reference
//! to a target across the workspace, and a description of a declaration
//! (its signature and the `//` comment above it) for hovers.

use robosim_syntax::{SyntaxKind::*, SyntaxNode, TextRange, TextSize};

use crate::body::{body_refs_at, body_resolution};
use crate::defs::{file_defs, Def, DefData, DefId, DefKind, Io, TypeRef};
use crate::element::defs_holding;
use crate::index::ItemLoc;
use crate::resolve::{file_resolution, ResolvedRef, Target};
use crate::{parse, Db, File, Workspace};

/// A declaration's location.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DeclLoc {
    /// The declaring file.
    pub file: File,
    /// The definition.
    pub def: DefId,
    /// The name's range.
    pub name_range: TextRange,
    /// The whole declaration's range.
    pub full_range: TextRange,
}

/// Where `target` is declared.
pub fn declaration(db: &dyn Db, target: Target) -> Option<DeclLoc> {
    let (file, def) = match target {
        Target::Def(f, d) => (f, d),
        Target::Item(loc) => (loc.file, loc.def(db)?),
        Target::Member(loc, i) => {
            let item = loc.def(db)?;
            let name = &loc.summary(db).members[i as usize].name;
            let kind = loc.summary(db).members[i as usize].kind;
            let defs = defs_holding(db, loc.file, item);
            let (id, _) = defs.children(Some(item)).find(|(_, d)| &d.name == name && d.kind == kind)?;
            (loc.file, id)
        }
    };
    let d = defs_holding(db, file, def).def(def);
    Some(DeclLoc { file, def, name_range: d.name_range, full_range: d.range })
}

/// Every reference of `file` (declaration-level and in behaviour), sorted.
pub fn references_in(db: &dyn Db, ws: Workspace, file: File) -> Vec<ResolvedRef> {
    let mut v: Vec<ResolvedRef> =
        file_resolution(db, ws, file).refs.iter().chain(&body_resolution(db, ws, file).refs).cloned().collect();
    v.sort_by_key(|r| r.range.start());
    v
}

/// What is at an offset of a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Symbol {
    /// A reference (resolved or not).
    Reference(ResolvedRef),
    /// The name of a declaration.
    Declaration(DeclLoc),
}

/// The reference or declaration name covering `offset`.
pub fn symbol_at(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<Symbol> {
    let hit = |r: TextRange| r.contains_inclusive(offset);
    // Behaviour is resolved around `offset` only (see `body_refs_at`), and
    // first: names in behaviour and declaration-level references never
    // cover the same offset (a test checks it on every example and corpus
    // file), so a name in an action needs no resolution of the rest.
    let innermost = |refs: &[ResolvedRef]| refs.iter().filter(|r| hit(r.range)).min_by_key(|r| r.range.len()).cloned();
    if let Some(r) = innermost(&body_refs_at(db, ws, file, offset)) {
        return Some(Symbol::Reference(r));
    }
    // Within the element at `offset`: after a keystroke elsewhere, its
    // names resolve again on their own (and the declarations are its).
    let (refs, defs) = match crate::element::element_at(db, file, offset) {
        Some((e, at)) => {
            let mut refs = crate::element::element_refs(db, ws, e).clone();
            refs.iter_mut().for_each(|r| r.range += TextSize::from(at));
            (std::borrow::Cow::Owned(refs), crate::element::placed_defs(db, e))
        }
        None => (std::borrow::Cow::Borrowed(&file_resolution(db, ws, file).refs[..]), file_defs(db, file)),
    };
    if let Some(r) = innermost(&refs) {
        return Some(Symbol::Reference(r));
    }
    defs.iter()
        .filter(|(_, d)| !d.name.is_empty() && hit(d.name_range))
        .min_by_key(|(_, d)| d.name_range.len())
        .map(|(id, d)| Symbol::Declaration(DeclLoc { file, def: id, name_range: d.name_range, full_range: d.range }))
}

/// The declaration a symbol denotes.
pub fn symbol_declaration(db: &dyn Db, sym: &Symbol) -> Option<DeclLoc> {
    match sym {
        Symbol::Reference(r) => declaration(db, r.target?),
        Symbol::Declaration(d) => Some(*d),
    }
}

/// Every reference to the declaration `decl` in the workspace (not the
/// declaration itself).
pub fn find_references(db: &dyn Db, ws: Workspace, decl: DeclLoc) -> Vec<(File, TextRange)> {
    let mut out = Vec::new();
    for &f in ws.files(db) {
        if f.is_library(db) && f != decl.file {
            continue;
        }
        for r in references_in(db, ws, f) {
            if let Some(t) = r.target {
                if declaration(db, t).is_some_and(|d| d.file == decl.file && d.def == decl.def) {
                    // Qualified references point at their last segment.
                    out.push((f, last_segment(db, f, r.range)));
                }
            }
        }
    }
    out
}

/// The range of the last `::` segment of a (qualified) name.
fn last_segment(db: &dyn Db, file: File, range: TextRange) -> TextRange {
    let text = &file.text(db)[range];
    match text.rfind("::") {
        Some(i) => {
            let start = range.start() + TextSize::from((i + 2) as u32);
            let rest = &text[i + 2..];
            let skip = rest.len() - rest.trim_start().len();
            TextRange::new(start + TextSize::from(skip as u32), range.end())
        }
        None => range,
    }
}

/// A declaration described for a hover.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Description {
    /// One line in the language's syntax (`event obstacle : nat`).
    pub signature: String,
    /// Where it sits (`in state machine SMovement`).
    pub container: Option<String>,
    /// The `//` or `/* */` comment directly above the declaration.
    pub doc: Option<String>,
}

/// Describes a declaration.
pub fn describe(db: &dyn Db, decl: DeclLoc) -> Description {
    let defs = defs_holding(db, decl.file, decl.def);
    let d = defs.def(decl.def);
    let signature = match d.kind {
        // The whole behaviour, which a diagram shortens (issue 21).
        DefKind::State | DefKind::Transition => behaviour_text(db, decl.file, d).unwrap_or_else(|| signature(d)),
        _ => signature(d),
    };
    let container = d.parent.map(|p| {
        let pd = defs.def(p);
        format!("in {} `{}`", pd.kind.describe(), pd.name)
    });
    Description { signature, container, doc: doc_comment(db, decl.file, d) }
}

fn type_text(t: &Option<TypeRef>) -> String {
    match t {
        Some(t) => format!(" : {}", type_ref_text(t)),
        None => String::new(),
    }
}

/// A type as written.
pub fn type_ref_text(t: &TypeRef) -> String {
    match t {
        TypeRef::Named(p, _) => p.join("::"),
        TypeRef::Set(a) => format!("Set({})", type_ref_text(a)),
        TypeRef::Seq(a) => format!("Seq({})", type_ref_text(a)),
        TypeRef::Var(n) => format!("?{n}"),
        TypeRef::Product(v) => v.iter().map(type_ref_text).collect::<Vec<_>>().join(" * "),
        TypeRef::Function(a, b) => format!("{} -> {}", type_ref_text(a), type_ref_text(b)),
        TypeRef::Relation(a, b) => format!("{} <-> {}", type_ref_text(a), type_ref_text(b)),
        TypeRef::Vector(a, _) => format!("vector({}, …)", type_ref_text(a)),
        TypeRef::Matrix(a, _, _) => format!("matrix({}, …, …)", type_ref_text(a)),
        TypeRef::Missing => "?".into(),
    }
}

fn signature(d: &Def) -> String {
    let io = match d.io {
        Some(Io::Input) => " (input)",
        Some(Io::Output) => " (output)",
        None => "",
    };
    match (&d.kind, &d.data) {
        (DefKind::Event, DefData::Typed { ty, broadcast, .. }) => {
            format!("{}event {}{}{io}", if *broadcast { "_broadcast " } else { "" }, d.name, type_text(ty))
        }
        (DefKind::Variable, DefData::Typed { ty, .. }) => format!("var {}{}{io}", d.name, type_text(ty)),
        (DefKind::Constant, DefData::Typed { ty, .. }) => format!("const {}{}{io}", d.name, type_text(ty)),
        (DefKind::Parameter | DefKind::Field, DefData::Typed { ty, .. }) => format!("{}{}", d.name, type_text(ty)),
        (
            DefKind::OperationSig | DefKind::Operation | DefKind::Function,
            DefData::Signature { params, result, terminates },
        ) => {
            let ps = params.iter().map(|(n, t)| format!("{n}{}", type_text(t))).collect::<Vec<_>>().join(", ");
            let kw = match d.kind {
                DefKind::Operation => "operation ",
                DefKind::Function => "function ",
                _ => "",
            };
            let r = result.as_ref().map(|t| format!(" : {}", type_ref_text(t))).unwrap_or_default();
            let term = if *terminates && d.kind == DefKind::OperationSig { " [terminates]" } else { "" };
            format!("{kw}{}({ps}){r}{term}{io}", d.name)
        }
        (
            DefKind::PlatformRef | DefKind::ControllerRef | DefKind::MachineRef | DefKind::OperationRef,
            DefData::Reference { path, .. },
        ) => {
            let kw = match d.kind {
                DefKind::PlatformRef => "rref",
                DefKind::ControllerRef => "cref",
                DefKind::MachineRef => "sref",
                _ => "opref",
            };
            format!("{kw} {} = {}", d.name, path.join("::"))
        }
        (DefKind::Transition, DefData::Transition(t)) => {
            let from = t.source.as_ref().map(|s| s.0.as_str()).unwrap_or("?");
            let to = t.target.as_ref().map(|s| s.0.as_str()).unwrap_or("?");
            format!("transition {} {{ from {from} to {to} … }}", d.name)
        }
        (kind, _) => {
            let kw = match kind {
                DefKind::Interface => "interface",
                DefKind::Platform => "robotic platform",
                DefKind::Controller => "controller",
                DefKind::StateMachine => "stm",
                DefKind::Module => "module",
                DefKind::PrimitiveType => "type",
                DefKind::Record => "record",
                DefKind::Enumeration => "enumeration",
                DefKind::EnumLiteral => "literal",
                DefKind::Clock => "clock",
                DefKind::State => "state",
                DefKind::Initial => "initial",
                DefKind::Junction => "junction",
                DefKind::Final => "final",
                DefKind::ProbabilisticJunction => "probabilistic",
                DefKind::Assertion if d.syntax == PROB_PROPERTY => "prob property",
                DefKind::Assertion if d.syntax == PROB_CONSTANTS => "constants",
                DefKind::Assertion => "assertion",
                DefKind::CspProcess => "csp",
                DefKind::Simulation => "simulation",
                other => other.describe(),
            };
            format!("{kw} {}", d.name)
        }
    }
}

/// A state with its entry, during and exit actions (not its substates),
/// or a whole transition, each clause on a line of its own with its
/// whitespace collapsed.
fn behaviour_text(db: &dyn Db, file: File, d: &Def) -> Option<String> {
    let root = parse(db, file).syntax_node();
    let node = match root.covering_element(d.range) {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    let node = node.ancestors().find(|n| n.text_range() == d.range)?;
    let one_line = |n: &SyntaxNode| n.text().to_string().split_whitespace().collect::<Vec<_>>().join(" ");
    if d.kind == DefKind::State {
        let actions: Vec<String> = node
            .children()
            .filter(|c| matches!(c.kind(), ENTRY_ACTION | DURING_ACTION | EXIT_ACTION))
            .map(|c| format!("    {}", one_line(&c)))
            .collect();
        return Some(if actions.is_empty() {
            format!("state {}", d.name)
        } else {
            format!("state {} {{\n{}\n}}", d.name, actions.join("\n"))
        });
    }
    let text = one_line(&node);
    Some(text)
}

/// The comment block directly above a declaration (no blank line between).
fn doc_comment(db: &dyn Db, file: File, d: &Def) -> Option<String> {
    let root = parse(db, file).syntax_node();
    let node = root.covering_element(d.range);
    let node = match node {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    let node = node.ancestors().find(|n| n.text_range() == d.range)?;
    // Variables live in a `var`/`const` list: its comment documents them.
    let anchor = if node.kind() == VARIABLE { node.parent()? } else { node };
    let mut lines = Vec::new();
    let mut tok = anchor.first_token()?.prev_token();
    while let Some(t) = tok {
        match t.kind() {
            WHITESPACE => {
                if t.text().matches('\n').count() > 1 {
                    break;
                }
            }
            LINE_COMMENT => lines.push(t.text().trim_start_matches("//").trim().to_string()),
            BLOCK_COMMENT => {
                let body = t.text().trim_start_matches("/*").trim_end_matches("*/");
                for l in body.lines().rev() {
                    lines.push(l.trim().trim_start_matches('*').trim().to_string());
                }
            }
            _ => break,
        }
        tok = t.prev_token();
    }
    lines.reverse();
    while lines.first().is_some_and(|l| l.is_empty()) {
        lines.remove(0);
    }
    while lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// The item of the index a declaration is, when it is a top-level item.
pub fn item_of(db: &dyn Db, decl: DeclLoc) -> Option<ItemLoc> {
    let s = crate::index::file_summary(db, decl.file);
    let defs = file_defs(db, decl.file);
    let pos = defs.children(None).filter(|(_, d)| !d.name.is_empty()).position(|(id, _)| id == decl.def)?;
    (pos < s.items.len()).then_some(ItemLoc { file: decl.file, index: pos as u32 })
}

/// The cycle information of a RoboSim container, for hovers on `cycleDef`.
pub fn cycle_info(db: &dyn Db, ws: Workspace, file: File, def: DefId) -> Option<crate::cycle::CycleInfo> {
    crate::cycle::cycle_infos(db, ws, file).iter().find(|(d, _)| *d == def).map(|(_, i)| *i)
}
