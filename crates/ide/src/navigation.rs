//! Go to definition (and declaration, the same target) and find
//! references, over the semantic model's name resolution.

use robosim_hir::defs::DefKind;
use robosim_hir::element::defs_holding;
use robosim_hir::nav::{self, DeclLoc, Symbol};
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{TextRange, TextSize};

use crate::symbols::SymbolKind;
use crate::FileId;

/// A declaration to jump to.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NavigationTarget {
    /// The declaring file.
    pub file: FileId,
    /// Its path, as given when it was added (`<stdlib>/…` for the library).
    pub path: String,
    /// Whether the file is part of the bundled library (no editor can open
    /// it from disk).
    pub is_library: bool,
    /// The declared name.
    pub name: String,
    /// What it declares.
    pub kind: SymbolKind,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The name in the declaration.
    pub focus_range: TextRange,
}

/// One occurrence of a name found by [`crate::Analysis::find_references`].
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ReferenceLoc {
    /// The file.
    pub file: FileId,
    /// Its path, as given when it was added.
    pub path: String,
    /// The name's range (the last segment of a qualified name).
    pub range: TextRange,
    /// Whether this is the declaration itself rather than a use.
    pub is_declaration: bool,
}

/// The kind of symbol a definition kind shows as.
pub(crate) fn symbol_kind(k: DefKind) -> SymbolKind {
    match k {
        DefKind::Interface => SymbolKind::Interface,
        DefKind::Platform | DefKind::PlatformRef => SymbolKind::Platform,
        DefKind::Controller | DefKind::ControllerRef => SymbolKind::Controller,
        DefKind::StateMachine | DefKind::MachineRef => SymbolKind::StateMachine,
        DefKind::Operation | DefKind::OperationSig | DefKind::OperationRef => SymbolKind::Operation,
        DefKind::Function => SymbolKind::Function,
        DefKind::Module => SymbolKind::Module,
        DefKind::PrimitiveType => SymbolKind::PrimitiveType,
        DefKind::Record => SymbolKind::Record,
        DefKind::Enumeration => SymbolKind::Enum,
        DefKind::Field => SymbolKind::Field,
        DefKind::EnumLiteral => SymbolKind::EnumLiteral,
        DefKind::Event => SymbolKind::Event,
        DefKind::Variable => SymbolKind::Variable,
        DefKind::Constant => SymbolKind::Constant,
        DefKind::Clock => SymbolKind::Clock,
        DefKind::Parameter => SymbolKind::Parameter,
        DefKind::State => SymbolKind::State,
        DefKind::Initial => SymbolKind::Initial,
        DefKind::Junction => SymbolKind::Junction,
        DefKind::Final => SymbolKind::Final,
        DefKind::ProbabilisticJunction => SymbolKind::ProbabilisticJunction,
        DefKind::Transition | DefKind::Connection => SymbolKind::Transition,
        DefKind::Assertion => SymbolKind::Assertion,
        DefKind::CspProcess => SymbolKind::CspProcess,
        DefKind::Simulation => SymbolKind::Simulation,
    }
}

/// `range` without surrounding whitespace (names never contain any).
pub(crate) fn trimmed(text: &str, range: TextRange) -> TextRange {
    let Some(s) = text.get(usize::from(range.start())..usize::from(range.end())) else { return range };
    let lead = s.len() - s.trim_start().len();
    let trail = s.len() - s.trim_end().len();
    if lead + trail >= s.len() {
        return range;
    }
    TextRange::new(range.start() + TextSize::from(lead as u32), range.end() - TextSize::from(trail as u32))
}

/// The range of the last `::` segment of a (qualified) name.
pub(crate) fn last_segment(text: &str, range: TextRange) -> TextRange {
    let range = trimmed(text, range);
    let Some(s) = text.get(usize::from(range.start())..usize::from(range.end())) else { return range };
    match s.rfind("::") {
        Some(i) => {
            let rest = &s[i + 2..];
            let skip = rest.len() - rest.trim_start().len();
            TextRange::new(range.start() + TextSize::from((i + 2 + skip) as u32), range.end())
        }
        None => range,
    }
}

/// The reference or declaration at `offset`, and the declaration it denotes.
pub(crate) fn decl_at(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<(Symbol, Option<DeclLoc>)> {
    let sym = nav::symbol_at(db, ws, file, offset)?;
    let decl = nav::symbol_declaration(db, &sym);
    Some((sym, decl))
}

/// The range of the symbol under the cursor, as written.
pub(crate) fn symbol_range(sym: &Symbol) -> TextRange {
    match sym {
        Symbol::Reference(r) => r.range,
        Symbol::Declaration(d) => d.name_range,
    }
}

pub(crate) fn target(db: &dyn Db, decl: DeclLoc) -> NavigationTarget {
    let d = defs_holding(db, decl.file, decl.def).def(decl.def);
    NavigationTarget {
        file: FileId(decl.file),
        path: decl.file.path(db).clone(),
        is_library: decl.file.is_library(db),
        name: d.name.clone(),
        kind: symbol_kind(d.kind),
        full_range: decl.full_range,
        focus_range: trimmed(decl.file.text(db), decl.name_range),
    }
}

/// The declaration of the name at `offset`: the range of the name under
/// the cursor and the targets (none when it does not resolve).
pub(crate) fn goto_definition(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<(TextRange, Vec<NavigationTarget>)> {
    if let Some(found) = crate::csp_block::goto_definition(db, ws, file, offset) {
        return Some(found);
    }
    let (sym, decl) = decl_at(db, ws, file, offset)?;
    let origin = trimmed(file.text(db), symbol_range(&sym));
    Some((origin, decl.map(|d| target(db, d)).into_iter().collect()))
}

/// Every use of the declaration `decl` across the workspace, and the
/// declaration itself first when asked.
pub(crate) fn references_of(db: &dyn Db, ws: Workspace, decl: DeclLoc, include_declaration: bool) -> Vec<ReferenceLoc> {
    let mut out = Vec::new();
    if include_declaration {
        out.push(ReferenceLoc {
            file: FileId(decl.file),
            path: decl.file.path(db).clone(),
            range: trimmed(decl.file.text(db), decl.name_range),
            is_declaration: true,
        });
    }
    let mut uses: Vec<ReferenceLoc> = nav::find_references(db, ws, decl)
        .into_iter()
        .map(|(f, r)| ReferenceLoc {
            file: FileId(f),
            path: f.path(db).clone(),
            range: last_segment(f.text(db), r),
            is_declaration: false,
        })
        .collect();
    uses.sort_by(|a, b| (&a.path, a.range.start()).cmp(&(&b.path, b.range.start())));
    uses.dedup();
    out.extend(uses);
    out
}

/// The references of the name at `offset`; `None` when there is no name
/// there or it does not resolve.
pub(crate) fn find_references(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    offset: TextSize,
    include_declaration: bool,
) -> Option<Vec<ReferenceLoc>> {
    if let Some(found) = crate::csp_block::find_references(db, ws, file, offset, include_declaration) {
        return found;
    }
    let (_, decl) = decl_at(db, ws, file, offset)?;
    Some(references_of(db, ws, decl?, include_declaration))
}
