//! Hover, go to definition, references, completion and folding inside the
//! `csp` blocks of assertion files. A name in a block denotes, from the
//! innermost: a name bound in its definition (a parameter, a `let`, a
//! generator, an input `?x`), a top-level definition of one of the file's
//! blocks (RT-7), a name of FDR's or RoboTool's library
//! ([`robosim_hir::csp_library`]), or one of the model's names as
//! RoboTool's CSPm spells them ([`robosim_hir::csp_names`]), whose
//! declaration is in a model file.

use robosim_cspm::{self as cspm, SyntaxKind as K};
use robosim_hir::csp_blocks::{csp_blocks, name_text, CspBlock, CspDef, CspDefKind};
use robosim_hir::csp_library::{self, CspLibKind, CspLibName, CspLibSource};
use robosim_hir::csp_names::{csp_names, CspKind, CspName, CspType, TypeDef};
use robosim_hir::defs::file_defs;
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{FileKind, TextRange, TextSize};

use crate::completion::{CompletionItem, CompletionKind};
use crate::folding::{Fold, FoldKind};
use crate::navigation::{symbol_kind, NavigationTarget, ReferenceLoc};
use crate::symbols::SymbolKind;
use crate::FileId;

/// What a name of a block denotes.
#[derive(Debug, Clone, PartialEq)]
enum Meaning<'a> {
    /// Bound inside a definition, at `binding` (in the file).
    Local { binding: TextRange, how: &'static str },
    /// A top-level definition of a block of the file.
    Block(&'a CspDef),
    /// A library name.
    Library(&'static CspLibName),
    /// A name of the model.
    Model(&'a CspName),
    /// Nothing known (the diagnostics say so).
    Unknown,
}

/// A block's CSPm tree and where its text starts in the file.
struct Tree<'a> {
    block: &'a CspBlock,
    root: cspm::SyntaxNode,
    start: TextSize,
}

impl Tree<'_> {
    fn to_file(&self, r: TextRange) -> TextRange {
        r + self.start
    }
}

fn block_trees<'a>(text: &str, blocks: &'a [CspBlock]) -> Vec<Tree<'a>> {
    blocks
        .iter()
        .filter_map(|b| {
            let body = b.body?;
            let root = cspm::parse(text.get(usize::from(body.start())..usize::from(body.end()))?).syntax_node();
            Some(Tree { block: b, root, start: body.start() })
        })
        .collect()
}

fn is_assertion_file(db: &dyn Db, file: File) -> bool {
    matches!(file.kind(db), FileKind::Assertions | FileKind::SimAssertions)
}

/// A name written in a block: a `NAME_REF`, or the name token of a
/// `channel`, `datatype`, `nametype` declaration or constructor.
struct Occurrence {
    name: String,
    /// In the tree.
    range: TextRange,
    node: cspm::SyntaxNode,
}

fn occurrence_at(root: &cspm::SyntaxNode, offset: TextSize) -> Option<Occurrence> {
    let tokens = root.token_at_offset(offset);
    let token =
        tokens.clone().find(|t| t.kind() == K::IDENT).or_else(|| tokens.into_iter().find(|t| t.kind() == K::IDENT))?;
    let parent = token.parent()?;
    if parent.kind() == K::NAME_REF {
        return Some(Occurrence { name: name_text(&parent), range: parent.text_range(), node: parent });
    }
    Some(Occurrence { name: token.text().to_owned(), range: token.text_range(), node: parent })
}

/// Every occurrence of a name in a tree.
fn occurrences(root: &cspm::SyntaxNode) -> Vec<Occurrence> {
    let mut out = Vec::new();
    for el in root.descendants_with_tokens() {
        match el {
            rowan::NodeOrToken::Node(n) if n.kind() == K::NAME_REF => {
                out.push(Occurrence { name: name_text(&n), range: n.text_range(), node: n });
            }
            rowan::NodeOrToken::Token(t) if t.kind() == K::IDENT => {
                if let Some(p) = t.parent().filter(|p| p.kind() != K::NAME_REF) {
                    out.push(Occurrence { name: t.text().to_owned(), range: t.text_range(), node: p });
                }
            }
            _ => {}
        }
    }
    out
}

/// The names a binder node binds for what is inside it, with how.
fn bound_by(node: &cspm::SyntaxNode) -> Vec<(String, TextRange, &'static str)> {
    let mut out = Vec::new();
    let pattern_names = |p: &cspm::SyntaxNode, how, out: &mut Vec<_>| {
        let refs = std::iter::once(p.clone()).chain(p.descendants()).filter(|n| n.kind() == K::NAME_REF);
        for n in refs {
            out.push((name_text(&n), n.text_range(), how));
        }
    };
    match node.kind() {
        K::DEFINITION => {
            if let Some(lhs) = node.children().next().filter(|l| l.kind() == K::CALL_EXPR) {
                for args in lhs.descendants().filter(|n| n.kind() == K::ARG_LIST) {
                    for p in args.children() {
                        pattern_names(&p, "a parameter", &mut out);
                    }
                }
            }
        }
        K::LET_EXPR => {
            for d in node.children().filter(|c| c.kind() == K::DEFINITION) {
                let Some(lhs) = d.children().next() else { continue };
                let callee = match lhs.kind() {
                    K::CALL_EXPR => lhs.children().next(),
                    _ => Some(lhs),
                };
                match callee {
                    Some(c) if c.kind() == K::NAME_REF => {
                        out.push((name_text(&c), c.text_range(), "a local definition (`let`)"));
                    }
                    Some(c) => pattern_names(&c, "a local definition (`let`)", &mut out),
                    None => {}
                }
            }
        }
        K::LAMBDA_EXPR => {
            // `\ p, q @ e`: the patterns before `@`.
            for el in node.children_with_tokens() {
                match el {
                    rowan::NodeOrToken::Token(t) if t.kind() == K::AT => break,
                    rowan::NodeOrToken::Node(p) => pattern_names(&p, "a lambda parameter", &mut out),
                    _ => {}
                }
            }
        }
        K::PREFIX_EXPR => {
            for f in node.children().filter(|c| matches!(c.kind(), K::INPUT_FIELD | K::NONDET_FIELD)) {
                if let Some(p) = f.children().next() {
                    pattern_names(&p, "an input of a prefix", &mut out);
                }
            }
        }
        _ => {
            for list in node.children().filter(|c| c.kind() == K::STMT_LIST) {
                for g in list.children().filter(|c| c.kind() == K::GENERATOR) {
                    if let Some(p) = g.children().next() {
                        pattern_names(&p, "a generator", &mut out);
                    }
                }
            }
        }
    }
    out
}

/// The lookup context of a file: its blocks and the model's names.
struct Scope<'a> {
    blocks: &'a [CspBlock],
    model: &'a robosim_hir::csp_names::CspNames,
}

impl<'a> Scope<'a> {
    fn new(db: &'a dyn Db, ws: Workspace, file: File) -> Scope<'a> {
        Scope { blocks: &csp_blocks(db, ws, file).blocks, model: csp_names(db, ws) }
    }

    /// Whether patterns match `name` rather than bind it.
    fn is_constructor(&self, name: &str) -> bool {
        self.blocks
            .iter()
            .flat_map(|b| &b.defs)
            .any(|d| d.name == name && matches!(d.kind, CspDefKind::Channel | CspDefKind::Constructor))
            || csp_library::lookup(name)
                .is_some_and(|l| matches!(l.kind, CspLibKind::Channel | CspLibKind::Constructor))
            || self.model.get(name).is_some_and(|n| matches!(n.kind, CspKind::Channel { .. } | CspKind::Literal { .. }))
    }

    fn global(&self, name: &str, own: &CspBlock) -> Meaning<'a> {
        // The block's own definition first, then the other blocks'.
        let all = || self.blocks.iter().flat_map(|b| b.defs.iter().map(move |d| (b, d)));
        let found =
            all().find(|(b, d)| b.range == own.range && d.name == name).or_else(|| all().find(|(_, d)| d.name == name));
        if let Some((_, d)) = found {
            return Meaning::Block(d);
        }
        if let Some(l) = csp_library::lookup(name) {
            return Meaning::Library(l);
        }
        match self.model.get(name) {
            Some(n) => Meaning::Model(n),
            None => Meaning::Unknown,
        }
    }

    /// What the occurrence `o` of tree `t` denotes.
    fn meaning(&self, t: &Tree<'_>, o: &Occurrence) -> Meaning<'a> {
        let at = t.to_file(o.range);
        // A definition's own name.
        if let Some(d) = self.blocks.iter().flat_map(|b| &b.defs).find(|d| d.name_range == at) {
            return Meaning::Block(d);
        }
        if o.node.kind() == K::NAME_REF && !self.is_constructor(&o.name) {
            for anc in o.node.ancestors() {
                if let Some((_, r, how)) = bound_by(&anc).into_iter().find(|(n, _, _)| *n == o.name) {
                    return Meaning::Local { binding: t.to_file(r), how };
                }
            }
        }
        self.global(&o.name, t.block)
    }
}

/// The block tree containing `offset`, and the name there.
fn at<'a>(trees: &'a [Tree<'a>], offset: TextSize) -> Option<(&'a Tree<'a>, Occurrence)> {
    let t = trees.iter().find(|t| t.block.body.is_some_and(|b| b.contains_inclusive(offset)))?;
    let o = occurrence_at(&t.root, offset - t.start)?;
    Some((t, o))
}

/// The hover section of the name at `offset` in a block.
pub(crate) fn hover(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<(TextRange, String)> {
    if !is_assertion_file(db, file) {
        return None;
    }
    let text = file.text(db);
    let scope = Scope::new(db, ws, file);
    let trees = block_trees(text, scope.blocks);
    let (t, o) = at(&trees, offset)?;
    let md = match scope.meaning(t, &o) {
        Meaning::Local { how, .. } => format!("```csp\n{}\n```\n\nBound as {how}.", o.name),
        Meaning::Block(d) => {
            let block = scope.blocks.iter().find(|b| b.defs.contains(d)).map(|b| b.name.as_str()).unwrap_or("");
            let line = first_line(text, d.range);
            format!("```csp\n{line}\n```\n\nA {} of the csp block `{block}`.", d.kind.describe())
        }
        Meaning::Library(l) => {
            let from = match l.source {
                CspLibSource::Fdr => "FDR's built-in",
                CspLibSource::RoboTool => "RoboTool's tock-CSP library",
            };
            format!("```csp\n{}\n```\n\n{}\n\n*{from}*", l.signature, l.summary)
        }
        Meaning::Model(n) => model_hover(db, n),
        Meaning::Unknown => return None,
    };
    Some((t.to_file(o.range), md))
}

fn first_line(text: &str, r: TextRange) -> String {
    let s = text.get(usize::from(r.start())..usize::from(r.end())).unwrap_or("");
    let line = s.lines().next().unwrap_or("").trim_end();
    if s.trim_end().len() > line.len() {
        format!("{line} …")
    } else {
        line.to_owned()
    }
}

/// A CSPm type as RoboTool writes it.
fn show_type(t: &CspType) -> String {
    match t {
        CspType::Nat => "core_nat".into(),
        CspType::Int => "core_int".into(),
        CspType::Real => "core_real".into(),
        CspType::Bool => "core_boolean".into(),
        CspType::Str => "core_string".into(),
        CspType::Clock => "core_clock_type".into(),
        CspType::InOut => "InOut".into(),
        CspType::Named(n) | CspType::Other(n) => n.clone(),
        CspType::Tuple(ts) => format!("({})", ts.iter().map(show_type).collect::<Vec<_>>().join(", ")),
        CspType::Set(t) => format!("Set({})", show_type(t)),
        CspType::Seq(t) => format!("Seq({})", show_type(t)),
    }
}

/// The signature of a model name in CSPm, and what it is.
fn model_signature(n: &CspName) -> (String, &'static str) {
    match &n.kind {
        CspKind::Module => (format!("module {}", n.name), "The CSPm module of a package or an element of the model."),
        CspKind::Channel { fields } if fields.is_empty() => (format!("channel {}", n.name), "A channel of the model."),
        CspKind::Channel { fields } => (
            format!("channel {} : {}", n.name, fields.iter().map(show_type).collect::<Vec<_>>().join(".")),
            "A channel of the model (`in`: received by the element, `out`: sent).",
        ),
        CspKind::Register { input, ty } => (
            format!(
                "{} {}{}",
                if *input { "input" } else { "output" },
                n.name,
                ty.as_ref().map(|t| format!(" : {}", show_type(t))).unwrap_or_default()
            ),
            "A RoboSim register (`registerRead`/`registerWrite`).",
        ),
        CspKind::Constant { ty, init } => (
            format!("{} : {}{}", n.name, show_type(ty), init.as_ref().map(|i| format!(" = {i}")).unwrap_or_default()),
            "A constant of the model (its value comes from the instantiations).",
        ),
        CspKind::Type(TypeDef::Enumeration(lits)) => {
            (format!("datatype {} = {}", n.name, lits.join(" | ")), "An enumeration of the model.")
        }
        CspKind::Type(TypeDef::Record(fs)) => (
            format!("nametype {} = ({})", n.name, fs.iter().map(show_type).collect::<Vec<_>>().join(", ")),
            "A record of the model, as a tuple.",
        ),
        CspKind::Type(TypeDef::Core) => {
            (format!("nametype {}", n.name), "A number type: its values come from the instantiations.")
        }
        CspKind::Type(TypeDef::Primitive) => {
            (format!("nametype {}", n.name), "A primitive type of the model (`{0, 1}` unless instantiated).")
        }
        CspKind::Literal { ty, .. } => (format!("{} : {ty}", n.name), "An enumeration literal of the model."),
        CspKind::Process { params } if params.is_empty() => {
            (n.name.clone(), "A process RoboTool generates for an element.")
        }
        CspKind::Process { params } => {
            (format!("{}({})", n.name, params.join(", ")), "A process RoboTool generates for an element.")
        }
        CspKind::EventSet => (n.name.clone(), "The set of the element's visible events."),
    }
}

fn model_hover(db: &dyn Db, n: &CspName) -> String {
    let (sig, what) = model_signature(n);
    let mut md = format!("```csp\n{sig}\n```\n\n{what}");
    if let Some(d) = n.decl {
        if let Some((_, def)) = file_defs(db, d.file).iter().find(|(_, x)| x.name_range == d.range) {
            md.push_str(&format!(
                "\n\nDeclared as the {} `{}` in `{}`.",
                def.kind.describe(),
                def.name,
                d.file.path(db)
            ));
        } else {
            md.push_str(&format!("\n\nDeclared in `{}`.", d.file.path(db)));
        }
    }
    md
}

/// The origin range and targets of the name at `offset` in a block.
pub(crate) fn goto_definition(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<(TextRange, Vec<NavigationTarget>)> {
    if !is_assertion_file(db, file) {
        return None;
    }
    let text = file.text(db);
    let scope = Scope::new(db, ws, file);
    let trees = block_trees(text, scope.blocks);
    let (t, o) = at(&trees, offset)?;
    let origin = t.to_file(o.range);
    let here = |name: &str, kind, full: TextRange, focus: TextRange| NavigationTarget {
        file: FileId(file),
        path: file.path(db).clone(),
        is_library: file.is_library(db),
        name: name.to_owned(),
        kind,
        full_range: full,
        focus_range: focus,
    };
    let targets = match scope.meaning(t, &o) {
        Meaning::Local { binding, how } => {
            let kind = if how.contains("let") { SymbolKind::CspProcess } else { SymbolKind::Parameter };
            vec![here(&o.name, kind, binding, binding)]
        }
        Meaning::Block(d) => vec![here(&d.name, SymbolKind::CspProcess, d.range, d.name_range)],
        Meaning::Model(n) => n.decl.map(|d| model_target(db, n, d)).into_iter().collect(),
        Meaning::Library(_) | Meaning::Unknown => Vec::new(),
    };
    Some((origin, targets))
}

fn model_target(db: &dyn Db, n: &CspName, d: robosim_hir::csp_names::Decl) -> NavigationTarget {
    let def = file_defs(db, d.file).iter().find(|(_, x)| x.name_range == d.range).map(|(_, x)| x.clone());
    NavigationTarget {
        file: FileId(d.file),
        path: d.file.path(db).clone(),
        is_library: d.file.is_library(db),
        name: def.as_ref().map(|x| x.name.clone()).unwrap_or_else(|| n.name.clone()),
        kind: def.as_ref().map(|x| symbol_kind(x.kind)).unwrap_or(SymbolKind::Package),
        full_range: def.as_ref().map(|x| x.range).unwrap_or(d.range),
        focus_range: d.range,
    }
}

/// The references of the name at `offset` in a block: in the file's
/// blocks, or for a model name in the blocks of every assertion file
/// (`Some(None)`: a name nothing declares, such as a library name).
pub(crate) fn find_references(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
    include_declaration: bool,
) -> Option<Option<Vec<ReferenceLoc>>> {
    if !is_assertion_file(db, file) {
        return None;
    }
    let text = file.text(db);
    let scope = Scope::new(db, ws, file);
    let trees = block_trees(text, scope.blocks);
    let (t, o) = at(&trees, offset)?;
    let meaning = scope.meaning(t, &o);
    let decl = match &meaning {
        Meaning::Local { binding, .. } => Some((file, *binding)),
        Meaning::Block(d) => Some((file, d.name_range)),
        Meaning::Model(n) => n.decl.map(|d| (d.file, d.range)),
        // Nothing declares them (as for an unresolved name).
        Meaning::Library(_) | Meaning::Unknown => return Some(None),
    };
    let files: Vec<File> = match meaning {
        Meaning::Model(_) => {
            ws.files(db).iter().copied().filter(|f| !f.is_library(db) && is_assertion_file(db, *f)).collect()
        }
        _ => vec![file],
    };
    let mut out = Vec::new();
    for f in files {
        let ftext = f.text(db);
        let fscope = Scope::new(db, ws, f);
        for ft in block_trees(ftext, fscope.blocks) {
            for occ in occurrences(&ft.root) {
                let r = ft.to_file(occ.range);
                if occ.name != o.name || Some((f, r)) == decl {
                    continue;
                }
                if same(&fscope.meaning(&ft, &occ), &meaning) {
                    out.push(ReferenceLoc {
                        file: FileId(f),
                        path: f.path(db).clone(),
                        range: r,
                        is_declaration: false,
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| (&a.path, a.range.start()).cmp(&(&b.path, b.range.start())));
    if let (true, Some((f, r))) = (include_declaration, decl) {
        out.insert(0, ReferenceLoc { file: FileId(f), path: f.path(db).clone(), range: r, is_declaration: true });
    }
    Some(Some(out))
}

fn same(a: &Meaning<'_>, b: &Meaning<'_>) -> bool {
    match (a, b) {
        (Meaning::Local { binding: x, .. }, Meaning::Local { binding: y, .. }) => x == y,
        (Meaning::Block(x), Meaning::Block(y)) => x.name_range == y.name_range,
        (Meaning::Library(x), Meaning::Library(y)) => x.name == y.name,
        (Meaning::Model(x), Meaning::Model(y)) => x.name == y.name,
        _ => false,
    }
}

/// Completions inside a block: the names in scope, the file's block
/// definitions, the library and the model's names. `None` outside blocks.
pub(crate) fn completions(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<Vec<CompletionItem>> {
    if !is_assertion_file(db, file) {
        return None;
    }
    let text = file.text(db);
    let scope = Scope::new(db, ws, file);
    let trees = block_trees(text, scope.blocks);
    let t = trees.iter().find(|t| t.block.body.is_some_and(|b| b.start() < offset && offset <= b.end()))?;
    let bytes = text.as_bytes();
    let end = usize::from(offset).min(text.len());
    let mut start = end;
    // A qualified name being typed (`M::e`) is replaced as a whole.
    while start > 0
        && (bytes[start - 1].is_ascii_alphanumeric() || bytes[start - 1] == b'_' || bytes[start - 1] == b':')
    {
        start -= 1;
    }
    let start = start.max(usize::from(t.start));
    let typed = &text[start..end];
    let range = TextRange::new(TextSize::from(start as u32), TextSize::from(end as u32));
    let rel = offset - t.start;
    let token = t.root.token_at_offset(rel).left_biased();
    if token.as_ref().is_some_and(|tk| matches!(tk.kind(), K::LINE_COMMENT | K::BLOCK_COMMENT | K::STRING)) {
        return Some(Vec::new());
    }
    let mut items = Vec::new();
    let mut add = |label: &str, kind: SymbolKind, detail: String| {
        if label.starts_with(typed) {
            items.push(CompletionItem {
                label: label.to_owned(),
                kind: CompletionKind::Symbol(kind),
                detail: Some(detail),
                range,
            });
        }
    };
    if let Some(node) = token.and_then(|tk| tk.parent()) {
        for anc in node.ancestors() {
            for (n, _, how) in bound_by(&anc) {
                add(&n, SymbolKind::Parameter, format!("bound as {how}"));
            }
        }
    }
    for b in scope.blocks {
        for d in &b.defs {
            add(&d.name, SymbolKind::CspProcess, format!("{} of csp block {}", d.kind.describe(), b.name));
        }
    }
    for l in csp_library::LIBRARY {
        let kind = match l.kind {
            CspLibKind::Channel => SymbolKind::Event,
            CspLibKind::Constructor => SymbolKind::EnumLiteral,
            CspLibKind::Process => SymbolKind::CspProcess,
            CspLibKind::Function => SymbolKind::Function,
            CspLibKind::Type => SymbolKind::PrimitiveType,
        };
        add(l.name, kind, format!("{} — {}", l.signature, l.summary));
    }
    for n in scope.model.iter() {
        let kind = match n.kind {
            CspKind::Module => SymbolKind::Module,
            CspKind::Channel { .. } | CspKind::Register { .. } | CspKind::EventSet => SymbolKind::Event,
            CspKind::Constant { .. } => SymbolKind::Constant,
            CspKind::Type(_) => SymbolKind::PrimitiveType,
            CspKind::Literal { .. } => SymbolKind::EnumLiteral,
            CspKind::Process { .. } => SymbolKind::StateMachine,
        };
        add(&n.name, kind, model_signature(n).0);
    }
    items.sort_by(|a, b| (a.kind, &a.label).cmp(&(b.kind, &b.label)));
    items.dedup_by(|a, b| a.label == b.label && a.kind == b.kind);
    Some(items)
}

/// Folds inside blocks: `Timed` sections, multi-line definitions and
/// `{- -}` comments (the block itself folds as a whole elsewhere).
pub(crate) fn folds(db: &dyn Db, file: File, out: &mut Vec<Fold>) {
    if !is_assertion_file(db, file) {
        return;
    }
    let text = file.text(db);
    let root = robosim_hir::parse(db, file).syntax_node();
    for tok in root.descendants_with_tokens().filter_map(|e| e.into_token()) {
        if tok.kind() != robosim_syntax::SyntaxKind::CSP_TEXT {
            continue;
        }
        let Some(inner) = tok.text().strip_prefix("csp-begin") else { continue };
        let inner = inner.strip_suffix("csp-end").unwrap_or(inner);
        let start = tok.text_range().start() + TextSize::of("csp-begin");
        let tree = cspm::parse(inner).syntax_node();
        for el in tree.descendants_with_tokens() {
            let (r, kind) = match &el {
                rowan::NodeOrToken::Node(n)
                    if matches!(n.kind(), K::TIMED_SECTION | K::DEFINITION | K::LET_EXPR | K::MODULE_DECL) =>
                {
                    (n.text_range(), FoldKind::Region)
                }
                rowan::NodeOrToken::Token(t) if t.kind() == K::BLOCK_COMMENT => (t.text_range(), FoldKind::Comment),
                _ => continue,
            };
            let r = r + start;
            let slice = text.get(usize::from(r.start())..usize::from(r.end())).unwrap_or("");
            if slice.trim_end().contains('\n') {
                out.push(Fold { range: r, kind });
            }
        }
    }
}
