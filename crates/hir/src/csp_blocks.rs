//! The CSPm of the `csp NAME csp-begin … csp-end` blocks of an assertion
//! file, read by the CSPm engine (`robosim-cspm`): each block's top-level
//! definitions, and its syntax, name and type errors at their ranges in the
//! file.
//!
//! What a block sees (RT-7): its own definitions, those of the other blocks
//! of its file (RoboTool includes a file's blocks in one script), FDR's
//! built-ins and RoboTool's library ([`crate::csp_library`]), and the names
//! RoboTool's generated CSPm gives the model. The model's names are not
//! known here one by one, so any name that may be one of them (module paths
//! `M::e`, `const_…`, `cycle_…`, `core_…`, and the generated names of the
//! workspace's types, enumeration literals and functions) is taken as known
//! with an unknown type: a block is never wrong because of a model name.

use std::rc::Rc;

use robosim_cspm::{self as cspm, ExternalName, NameLookup};
use robosim_syntax::{SyntaxKind, TextRange, TextSize};
use rustc_hash::FxHashMap;

use crate::csp_library::{self, CspLibKind};
use crate::csp_names::{CspKind, CspName, CspNames};
use crate::{parse, Db, File, FileKind, Workspace};

/// The csp blocks of one file.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CspBlocks {
    /// The blocks, in text order.
    pub blocks: Vec<CspBlock>,
}

/// One `csp` block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CspBlock {
    /// Its name (`""` if missing).
    pub name: String,
    /// The whole block, `csp` to `csp-end`.
    pub range: TextRange,
    /// The CSPm text between `csp-begin` and `csp-end`, in the file.
    pub body: Option<TextRange>,
    /// Its top-level definitions, in text order.
    pub defs: Vec<CspDef>,
    /// Its syntax, name and type errors, at file ranges.
    pub problems: Vec<CspProblem>,
}

/// What a block definition defines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CspDefKind {
    /// `P = …` (a process or a value).
    Value,
    /// `f(x) = …`.
    Function,
    /// `channel c`.
    Channel,
    /// `datatype T = …` or `subtype T = …`.
    Datatype,
    /// A constructor of a datatype.
    Constructor,
    /// `nametype T = …`.
    Nametype,
}

impl CspDefKind {
    /// A human name ("channel", "function", …).
    pub fn describe(self) -> &'static str {
        match self {
            CspDefKind::Value => "definition",
            CspDefKind::Function => "function",
            CspDefKind::Channel => "channel",
            CspDefKind::Datatype => "datatype",
            CspDefKind::Constructor => "constructor",
            CspDefKind::Nametype => "nametype",
        }
    }

    /// Whether patterns match the name rather than bind it.
    fn is_constructor(self) -> bool {
        matches!(self, CspDefKind::Channel | CspDefKind::Constructor)
    }
}

/// A top-level name a block defines.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CspDef {
    /// The name.
    pub name: String,
    /// What it is.
    pub kind: CspDefKind,
    /// The name where it is defined, in the file.
    pub name_range: TextRange,
    /// The whole declaration (of a multi-clause function, its first clause).
    pub range: TextRange,
}

/// An error of a block, from the CSPm engine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CspProblem {
    /// The stable code (`CSP-P01`, `CSP-N01`, `CSP-T01`, … in [`crate::codes`]).
    pub code: &'static str,
    /// Where, in the file.
    pub range: TextRange,
    /// What is wrong.
    pub message: String,
}

/// A block as written: its name and the range of its CSPm text.
struct Raw {
    name: String,
    range: TextRange,
    body: Option<TextRange>,
}

fn raw_blocks(db: &dyn Db, file: File) -> Vec<Raw> {
    let root = parse(db, file).syntax_node();
    let mut out = Vec::new();
    for node in root.descendants().filter(|n| n.kind() == SyntaxKind::CSP_BLOCK) {
        let name = node
            .children()
            .find(|c| c.kind() == SyntaxKind::NAME)
            .map(|n| n.text().to_string().trim().to_owned())
            .unwrap_or_default();
        let body = node
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .find(|t| t.kind() == SyntaxKind::CSP_TEXT)
            .and_then(|tok| {
                let text = tok.text();
                let inner = text.strip_prefix("csp-begin")?;
                let inner = inner.strip_suffix("csp-end").unwrap_or(inner);
                let start = tok.text_range().start() + TextSize::of("csp-begin");
                Some(TextRange::at(start, TextSize::of(inner)))
            });
        out.push(Raw { name, range: node.text_range(), body });
    }
    out
}

/// The blocks of `file` (none unless it is an assertion file), read and
/// checked.
#[salsa::tracked(returns(ref))]
pub fn csp_blocks(db: &dyn Db, ws: Workspace, file: File) -> CspBlocks {
    if !matches!(file.kind(db), FileKind::Assertions | FileKind::SimAssertions) {
        return CspBlocks::default();
    }
    let text = file.text(db);
    let raws = raw_blocks(db, file);
    let parsed: Vec<Option<(TextRange, cspm::Parse)>> =
        raws.iter().map(|r| r.body.map(|b| (b, cspm::parse(&text[b])))).collect();
    let defs: Vec<Vec<CspDef>> = parsed
        .iter()
        .map(|p| p.as_ref().map(|(b, p)| top_level_defs(&p.syntax_node(), b.start())).unwrap_or_default())
        .collect();
    let model = crate::csp_names::csp_names(db, ws);
    let mut blocks = Vec::new();
    for (i, raw) in raws.into_iter().enumerate() {
        let mut problems = Vec::new();
        if let Some(body) = raw.body {
            let mut others = FxHashMap::default();
            for (j, ds) in defs.iter().enumerate() {
                if j != i {
                    for d in ds {
                        *others.entry(d.name.clone()).or_insert(false) |= d.kind.is_constructor();
                    }
                }
            }
            let names = BlockNames { others, model };
            let m = cspm::Module::check(&text[body], &names);
            for d in m.diagnostics() {
                problems.push(CspProblem {
                    code: d.code.as_str(),
                    range: d.range + body.start(),
                    message: d.message.clone(),
                });
            }
        }
        problems.extend(misnamed_functions(db, ws, file, &defs[i], &defs));
        blocks.push(CspBlock { name: raw.name, range: raw.range, body: raw.body, defs: defs[i].clone(), problems });
    }
    CspBlocks { blocks }
}

/// CSP-N04: a block's function named as the model's function of a package
/// (`floor` for `Mathematics::floor`) defines another name than the one
/// RoboTool 3's CSPm calls (`Mathematics_floor`, RT-2), unless the file's
/// blocks define that one too.
fn misnamed_functions(db: &dyn Db, ws: Workspace, file: File, own: &[CspDef], all: &[Vec<CspDef>]) -> Vec<CspProblem> {
    let index = crate::index::index_for(db, ws, file);
    let defined = |n: &str| all.iter().flatten().any(|d| d.name == n);
    let mut out = Vec::new();
    for d in own.iter().filter(|d| d.kind == CspDefKind::Function) {
        let mut functions: Vec<&Vec<String>> = index
            .items
            .iter()
            .filter(|(path, locs)| {
                path.len() > 1
                    && path.last() == Some(&d.name)
                    && locs.iter().any(|l| l.summary(db).kind == crate::defs::DefKind::Function)
            })
            .map(|(path, _)| path)
            .collect();
        functions.sort();
        let Some(path) = functions.first() else { continue };
        let robotool = crate::csp_fn::robotool_function_name(&path[..path.len() - 1], &d.name);
        if defined(&robotool) {
            continue;
        }
        out.push(CspProblem {
            code: "CSP-N04",
            range: d.name_range,
            message: format!(
                "`{}` is not the name RoboTool 3's CSPm gives the model's function `{}`: its calls use `{robotool}`, \
                 so they do not read this definition (RoboTool's default holds, RT-2, or FDR stops if an \
                 `Instantiations` block leaves `{robotool}` undefined); write `{robotool}(…) = …`",
                d.name,
                path.join("::")
            ),
        });
    }
    out
}

impl CspBlocks {
    /// The block whose CSPm text contains `offset` (its ends included).
    pub fn at(&self, offset: TextSize) -> Option<&CspBlock> {
        self.blocks.iter().find(|b| b.body.is_some_and(|r| r.contains_inclusive(offset)))
    }

    /// The definitions of `name` in the file's blocks.
    pub fn defs_of<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a CspDef> + 'a {
        self.blocks.iter().flat_map(|b| &b.defs).filter(move |d| d.name == name)
    }
}

/// The top-level names `root` (a CSPm tree whose text starts at `offset`
/// in the file) defines, with their ranges in the file.
pub fn top_level_defs(root: &cspm::SyntaxNode, offset: TextSize) -> Vec<CspDef> {
    use cspm::SyntaxKind as K;
    let mut out: Vec<CspDef> = Vec::new();
    let push = |out: &mut Vec<CspDef>, name: String, kind, name_range: TextRange, range: TextRange| {
        if !name.is_empty() {
            out.push(CspDef { name, kind, name_range: name_range + offset, range: range + offset });
        }
    };
    let mut stack: Vec<cspm::SyntaxNode> = root.children().collect();
    stack.reverse();
    while let Some(node) = stack.pop() {
        let range = node.text_range();
        match node.kind() {
            K::TIMED_SECTION => {
                let mut inner: Vec<_> = node.children().collect();
                inner.reverse();
                stack.extend(inner);
            }
            K::DEFINITION => {
                let Some(lhs) = node.children().next() else { continue };
                match lhs.kind() {
                    K::NAME_REF => push(&mut out, name_text(&lhs), CspDefKind::Value, lhs.text_range(), range),
                    K::CALL_EXPR => {
                        // `f(x)(y)`: the name is the innermost callee.
                        let mut callee = lhs;
                        while let Some(c) = callee.children().next().filter(|c| c.kind() != K::ARG_LIST) {
                            callee = c;
                            if callee.kind() == K::NAME_REF {
                                break;
                            }
                        }
                        if callee.kind() == K::NAME_REF {
                            // A function of several clauses is defined once.
                            let name = name_text(&callee);
                            if !out.iter().any(|d| d.name == name && d.kind == CspDefKind::Function) {
                                push(&mut out, name, CspDefKind::Function, callee.text_range(), range);
                            }
                        }
                    }
                    // A pattern: every name it binds.
                    _ => {
                        for n in lhs.descendants().filter(|n| n.kind() == K::NAME_REF) {
                            push(&mut out, name_text(&n), CspDefKind::Value, n.text_range(), range);
                        }
                    }
                }
            }
            K::CHANNEL_DECL => {
                for list in node.children().filter(|c| c.kind() == K::NAME_LIST) {
                    for t in idents(&list) {
                        push(&mut out, t.text().to_owned(), CspDefKind::Channel, t.text_range(), range);
                    }
                }
            }
            K::DATATYPE_DECL | K::SUBTYPE_DECL | K::NAMETYPE_DECL => {
                let kind = if node.kind() == K::NAMETYPE_DECL { CspDefKind::Nametype } else { CspDefKind::Datatype };
                if let Some(t) = idents(&node).next() {
                    push(&mut out, t.text().to_owned(), kind, t.text_range(), range);
                }
                if node.kind() == K::DATATYPE_DECL {
                    for clause in node.children().filter(|c| c.kind() == K::DATATYPE_CLAUSE) {
                        if let Some(t) = idents(&clause).next() {
                            push(
                                &mut out,
                                t.text().to_owned(),
                                CspDefKind::Constructor,
                                t.text_range(),
                                clause.text_range(),
                            );
                        }
                    }
                }
            }
            _ => {}
        }
    }
    out
}

fn idents(node: &cspm::SyntaxNode) -> impl Iterator<Item = cspm::SyntaxToken> {
    node.children_with_tokens().filter_map(|e| e.into_token()).filter(|t| t.kind() == cspm::SyntaxKind::IDENT)
}

/// The name a `NAME_REF` node spells (`M::e`), without blanks.
pub fn name_text(node: &cspm::SyntaxNode) -> String {
    node.children_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| t.text().to_owned())
        .collect()
}

/// Whether `name`, absent from the table of the model's names, may still
/// be one RoboTool generates: the cycle constants of RoboSim (`cycle_…`),
/// which the table does not list. Returns whether patterns match it.
fn untabled_model_name(name: &str) -> Option<bool> {
    name.starts_with("cycle_").then_some(false)
}

/// Whether patterns match the model's name `n` rather than bind it.
fn model_constructor(n: &CspName) -> bool {
    matches!(n.kind, CspKind::Channel { .. } | CspKind::Literal { .. } | CspKind::Register { .. })
}

/// The names a block sees beyond its own. Used only to resolve names:
/// the checker asks whether a name exists and whether patterns match it,
/// so the values given are placeholders, never evaluated.
struct BlockNames<'a> {
    /// The other blocks' top-level names (`true`: a channel or constructor).
    others: FxHashMap<String, bool>,
    model: &'a CspNames,
}

impl NameLookup for BlockNames<'_> {
    fn lookup(&self, name: &str) -> Option<ExternalName> {
        let ctor = if let Some(&c) = self.others.get(name) {
            c
        } else if let Some(l) = csp_library::lookup(name) {
            matches!(l.kind, CspLibKind::Channel | CspLibKind::Constructor)
        } else if let Some(n) = self.model.get(name) {
            model_constructor(n)
        } else {
            untabled_model_name(name)?
        };
        Some(if ctor {
            ExternalName::Channel(Vec::new())
        } else {
            ExternalName::Value(cspm::Value::Tuple(Rc::from([])))
        })
    }
}
