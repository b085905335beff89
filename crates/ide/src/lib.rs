//! Editor features for RoboChart and RoboSim, independent of any editor
//! protocol: the language server (`robosim-lsp`) and the command line both
//! call these functions, and only translate their results.
//!
//! The shape follows rust-analyzer's: an [`AnalysisHost`] owns the mutable
//! salsa database and the workspace input; [`AnalysisHost::analysis`] hands
//! out an [`Analysis`], a cheap snapshot that other threads query while the
//! host moves on. Every query returns [`Cancellable`]: when the host changes
//! an input, queries still running on older snapshots unwind with
//! [`Cancelled`] instead of finishing work nobody wants.
//!
//! Results use byte ranges ([`TextRange`]); converting them to lines and
//! UTF-16 columns is the caller's business ([`LineIndex`] does it).

pub mod batch;
mod completion;
mod csp_block;
mod csp_hover;
mod diagnostics;
pub mod diagram;
mod edit;
pub mod export;
mod fixes;
mod folding;
mod formatting;
mod highlight;
mod hover;
mod navigation;
mod rename;
mod selection;
mod symbols;
pub mod verify;
pub mod workspace_files;

use std::collections::HashMap;
use std::panic::AssertUnwindSafe;
use std::sync::Arc;

use robosim_hir::{parse, Db, File, RootDatabase, Workspace};
use salsa::Setter;

pub use completion::{CompletionItem, CompletionKind};
pub use diagnostics::{carry_over, map_range, Diagnostic, Edit, RelatedInfo};
pub use diagram::{DiagramError, DiagramLens, RenderedDiagram};
pub use edit::{apply_edits, FileEdit, SourceChange, TextEdit};
pub use fixes::Assist;
pub use folding::{Fold, FoldKind};
pub use highlight::{HlRange, HlTag};
pub use hover::HoverResult;
pub use navigation::{NavigationTarget, ReferenceLoc};
pub use rename::RenameError;
pub use robosim_hir::{RuleSet, Severity};
pub use robosim_syntax::line_index::{LineCol, LineIndex};
pub use robosim_syntax::{FileKind, TextRange, TextSize};
pub use salsa::{Cancelled, Durability};
pub use symbols::{DocumentSymbol, SymbolKind, WorkspaceSymbol};
pub use verify::{Verified, VerifyLens, VerifyTarget};

/// The result of a query on a snapshot: `Err(Cancelled)` when an input
/// changed while it ran, so the answer would describe text that is gone.
pub type Cancellable<T> = Result<T, Cancelled>;

/// A file of the workspace. Stable for as long as the file is in the
/// workspace: edits keep the id, removing and re-adding a path gives a new one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FileId(File);

/// Owns the database and the workspace; the only place inputs change.
pub struct AnalysisHost {
    db: RootDatabase,
    workspace: Workspace,
    files: HashMap<String, File>,
}

impl std::fmt::Debug for AnalysisHost {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AnalysisHost").field("files", &self.files.len()).finish_non_exhaustive()
    }
}

impl Default for AnalysisHost {
    fn default() -> Self {
        AnalysisHost::new(RuleSet::default())
    }
}

impl AnalysisHost {
    /// A workspace with only the bundled library, checked with `rules`.
    pub fn new(rules: RuleSet) -> AnalysisHost {
        AnalysisHost::with_db(RootDatabase::default(), rules)
    }

    /// Like [`AnalysisHost::new`] over a given database (tests pass one that
    /// logs salsa events).
    pub fn with_db(mut db: RootDatabase, rules: RuleSet) -> AnalysisHost {
        // The same library files, paths and kinds as `robosim check`.
        // The library's inputs are of HIGH durability: queries that read
        // only the library are not even re-validated after an edit.
        let workspace = robosim_hir::load_workspace(&mut db, std::iter::empty(), rules);
        let library: Vec<File> = workspace.files(&db).clone();
        let mut files = HashMap::new();
        for file in library {
            files.insert(file.path(&db).clone(), file);
        }
        AnalysisHost { db, workspace, files }
    }

    /// A snapshot for queries, possibly on another thread. Changing an
    /// input through the host waits until every snapshot is dropped (after
    /// cancelling their queries), so snapshots must not outlive their work.
    pub fn analysis(&self) -> Analysis {
        Analysis { db: self.db.clone(), workspace: self.workspace }
    }

    /// The file at `path`, if it is in the workspace.
    pub fn file_id(&self, path: &str) -> Option<FileId> {
        self.files.get(path).copied().map(FileId)
    }

    /// Adds the file at `path` or replaces its text. The language comes from
    /// `kind`, or else the extension (RoboChart when neither says).
    /// `durability` says how often the text is expected to change: LOW for
    /// a buffer being edited, MEDIUM for a file on disk.
    /// Setting the same text and language again changes nothing: no new
    /// revision, so queries running on snapshots are not cancelled.
    pub fn set_file(&mut self, path: &str, text: String, kind: Option<FileKind>, durability: Durability) -> FileId {
        let kind = kind.or_else(|| FileKind::from_path(std::path::Path::new(path))).unwrap_or(FileKind::RoboChart);
        if let Some(&file) = self.files.get(path) {
            if file.kind(&self.db) == kind && *file.text(&self.db) == text {
                return FileId(file);
            }
            // Either way, only the elements the edit touched are set
            // (`hir::element`).
            if file.kind(&self.db) != kind {
                file.set_kind(&mut self.db).with_durability(durability.max(Durability::MEDIUM)).to(kind);
                robosim_hir::set_text(&mut self.db, file, text, None, durability);
            } else if durability == Durability::LOW {
                // A buffer being edited: its last parse (normally computed
                // for the previous version already) lets the next parse
                // redo only the member the edit is in.
                robosim_hir::edit_text(&mut self.db, file, text, durability);
            } else {
                robosim_hir::set_text(&mut self.db, file, text, None, durability);
            }
            return FileId(file);
        }
        let file = robosim_hir::new_file(&mut self.db, path.to_string(), text, kind, false, durability);
        self.files.insert(path.to_string(), file);
        let mut all = self.workspace.files(&self.db).clone();
        all.push(file);
        self.workspace.set_files(&mut self.db).with_durability(Durability::MEDIUM).to(all);
        FileId(file)
    }

    /// Whether [`AnalysisHost::set_file`] with these arguments would change
    /// anything: the file is new, or its text or language differs.
    pub fn would_change(&self, path: &str, text: &str, kind: Option<FileKind>) -> bool {
        let kind = kind.or_else(|| FileKind::from_path(std::path::Path::new(path))).unwrap_or(FileKind::RoboChart);
        match self.files.get(path) {
            Some(&file) => file.kind(&self.db) != kind || file.text(&self.db) != text,
            None => true,
        }
    }

    /// Removes the file at `path`; false when there was none. Library files
    /// cannot be removed.
    pub fn remove_file(&mut self, path: &str) -> bool {
        match self.files.get(path) {
            Some(&file) if !file.is_library(&self.db) => {
                self.files.remove(path);
                let mut all = self.workspace.files(&self.db).clone();
                all.retain(|f| *f != file);
                self.workspace.set_files(&mut self.db).with_durability(Durability::MEDIUM).to(all);
                true
            }
            _ => false,
        }
    }

    /// Sets the rule set; a no-op (no new revision) when it is unchanged.
    pub fn set_rules(&mut self, rules: RuleSet) {
        if self.workspace.rules(&self.db) != rules {
            self.workspace.set_rules(&mut self.db).with_durability(Durability::MEDIUM).to(rules);
        }
    }

    /// Sets the RoboTool project roots (folders holding a `.project`,
    /// written as the files' paths are): names resolve within a project.
    /// A no-op when they are unchanged.
    pub fn set_projects(&mut self, mut roots: Vec<String>) {
        roots.sort();
        roots.dedup();
        if *self.workspace.projects(&self.db) != roots {
            self.workspace.set_projects(&mut self.db).with_durability(Durability::MEDIUM).to(roots);
        }
    }

    /// The project roots in force (see [`AnalysisHost::set_projects`]).
    pub fn projects(&self) -> Vec<String> {
        self.workspace.projects(&self.db).clone()
    }

    /// The rule set in force.
    pub fn rules(&self) -> RuleSet {
        self.workspace.rules(&self.db)
    }

    /// The bundled library's files, by path.
    pub fn library_files(&self) -> Vec<(String, FileId)> {
        let mut out: Vec<(String, FileId)> =
            self.files.iter().filter(|(_, f)| f.is_library(&self.db)).map(|(p, f)| (p.clone(), FileId(*f))).collect();
        out.sort();
        out
    }

    /// The user's files (not the library), by path.
    pub fn user_files(&self) -> Vec<(String, FileId)> {
        let mut out: Vec<(String, FileId)> =
            self.files.iter().filter(|(_, f)| !f.is_library(&self.db)).map(|(p, f)| (p.clone(), FileId(*f))).collect();
        out.sort();
        out
    }
}

impl PartialOrd for FileId {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for FileId {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        use salsa::plumbing::AsId;
        self.0.as_id().cmp(&other.0.as_id())
    }
}

/// A read-only snapshot of the workspace. `Send`, cheap to clone; every
/// query on it either finishes or returns `Err(Cancelled)`.
#[derive(Clone)]
pub struct Analysis {
    db: RootDatabase,
    workspace: Workspace,
}

impl std::fmt::Debug for Analysis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Analysis").finish_non_exhaustive()
    }
}

impl Analysis {
    /// Runs `f` on the database, turning salsa's cancellation unwinding into
    /// `Err(Cancelled)`. Other panics propagate: they are bugs.
    fn with_db<T>(&self, f: impl FnOnce(&dyn Db) -> T) -> Cancellable<T> {
        Cancelled::catch(AssertUnwindSafe(|| f(&self.db)))
    }

    /// The text of `file`.
    pub fn file_text(&self, file: FileId) -> Cancellable<Arc<str>> {
        self.with_db(|db| Arc::from(file.0.text(db).as_str()))
    }

    /// The line index of `file`, for position conversions (computed once
    /// per version of the text).
    pub fn line_index(&self, file: FileId) -> Cancellable<Arc<LineIndex>> {
        self.with_db(|db| line_index(db, file.0).clone())
    }

    /// The path of `file` as given when it was added.
    pub fn file_path(&self, file: FileId) -> Cancellable<String> {
        self.with_db(|db| file.0.path(db).clone())
    }

    /// The language of `file`.
    pub fn file_kind(&self, file: FileId) -> Cancellable<FileKind> {
        self.with_db(|db| file.0.kind(db))
    }

    /// Whether `file` is part of the bundled library.
    pub fn is_library(&self, file: FileId) -> Cancellable<bool> {
        self.with_db(|db| file.0.is_library(db))
    }

    /// Computes part of what [`Analysis::diagnostics`] needs, to be called
    /// on another thread at the same time (on a clone of this snapshot).
    pub fn prefetch_diagnostics(&self, file: FileId) -> Cancellable<()> {
        self.with_db(|db| robosim_hir::prefetch_rules(db, self.workspace, file.0))
    }

    /// Every diagnostic of `file`, sorted by position (none for library
    /// files).
    pub fn diagnostics(&self, file: FileId) -> Cancellable<Vec<Diagnostic>> {
        self.with_db(|db| diagnostics::diagnostics(db, self.workspace, file.0))
    }

    /// The syntax diagnostics of `file` alone: a parse, no semantic rules.
    /// Fast enough for every keystroke of a large file.
    pub fn syntax_diagnostics(&self, file: FileId) -> Cancellable<Vec<Diagnostic>> {
        self.with_db(|db| diagnostics::syntax_diagnostics(db, file.0))
    }

    /// The syntax tree of `file` as text: one line per node or token, with
    /// byte ranges and token texts, then the syntax errors (the format of
    /// the parser's snapshot tests).
    pub fn syntax_tree(&self, file: FileId) -> Cancellable<String> {
        self.with_db(|db| parse(db, file.0).debug_dump())
    }

    /// The text of `file` printed back from its syntax tree (the tree is
    /// lossless, so this is the text).
    pub fn reprint(&self, file: FileId) -> Cancellable<String> {
        self.with_db(|db| parse(db, file.0).syntax_node().text().to_string())
    }

    /// The declarations of `file` as a tree, in source order.
    pub fn document_symbols(&self, file: FileId) -> Cancellable<Vec<DocumentSymbol>> {
        self.with_db(|db| symbols::document_symbols(db, file.0).clone())
    }

    /// Declarations of the whole workspace (library included) whose name
    /// matches `query`, best matches first, at most `limit`.
    pub fn workspace_symbols(&self, query: &str, limit: usize) -> Cancellable<Vec<WorkspaceSymbol>> {
        self.with_db(|db| symbols::workspace_symbols(db, self.workspace, query, limit))
    }

    /// The highlighting of `file`: sorted, non-overlapping ranges.
    pub fn highlight(&self, file: FileId) -> Cancellable<Vec<HlRange>> {
        self.with_db(|db| highlight::highlight(db, file.0))
    }

    /// The foldable regions of `file`, sorted by start.
    pub fn folding_ranges(&self, file: FileId) -> Cancellable<Vec<Fold>> {
        self.with_db(|db| folding::folding_ranges(db, file.0))
    }

    /// For each offset, the ranges that successively larger selections
    /// would cover, innermost first.
    pub fn selection_ranges(&self, file: FileId, offsets: &[TextSize]) -> Cancellable<Vec<Vec<TextRange>>> {
        self.with_db(|db| offsets.iter().map(|&o| selection::selection_ranges(db, file.0, o)).collect())
    }

    /// The hover at `offset`: the declaration of the name there, the
    /// periods of a `cycleDef`, the rules of the diagnostics there. `None`
    /// when there is nothing to say.
    pub fn hover(&self, file: FileId, offset: TextSize) -> Cancellable<Option<HoverResult>> {
        self.with_db(|db| hover::hover(db, self.workspace, file.0, offset, None))
    }

    /// Like [`Analysis::hover`], explaining the given diagnostics of `file`
    /// (those the editor shows) instead of computing them: the hover then
    /// does not wait for the complete check of a text just edited.
    pub fn hover_with_diagnostics(
        &self,
        file: FileId,
        offset: TextSize,
        diagnostics: &[Diagnostic],
    ) -> Cancellable<Option<HoverResult>> {
        self.with_db(|db| hover::hover(db, self.workspace, file.0, offset, Some(diagnostics)))
    }

    /// The declaration of the name at `offset`: the range of that name and
    /// its targets (empty when it does not resolve). `None` when there is
    /// no name at `offset`. Declaration and definition are the same thing
    /// in these languages.
    pub fn goto_definition(
        &self,
        file: FileId,
        offset: TextSize,
    ) -> Cancellable<Option<(TextRange, Vec<NavigationTarget>)>> {
        self.with_db(|db| navigation::goto_definition(db, self.workspace, file.0, offset))
    }

    /// Every reference to the declaration of the name at `offset`, across
    /// the workspace, the declaration first when `include_declaration`.
    /// `None` when there is no resolved name at `offset`.
    pub fn find_references(
        &self,
        file: FileId,
        offset: TextSize,
        include_declaration: bool,
    ) -> Cancellable<Option<Vec<ReferenceLoc>>> {
        self.with_db(|db| navigation::find_references(db, self.workspace, file.0, offset, include_declaration))
    }

    /// Whether the name at `offset` can be renamed: its range and current
    /// name, or why not.
    pub fn prepare_rename(
        &self,
        file: FileId,
        offset: TextSize,
    ) -> Cancellable<Result<(TextRange, String), RenameError>> {
        self.with_db(|db| rename::prepare_rename(db, self.workspace, file.0, offset))
    }

    /// Renames the declaration of the name at `offset` and every reference
    /// to it, or says why not (an invalid or reserved name, a clash in the
    /// same scope, a use in the bundled library).
    pub fn rename(
        &self,
        file: FileId,
        offset: TextSize,
        new_name: &str,
    ) -> Cancellable<Result<SourceChange, RenameError>> {
        self.with_db(|db| rename::rename(db, self.workspace, file.0, offset, new_name))
    }

    /// Completions at `offset`, sorted (keywords, then names by kind).
    pub fn completions(&self, file: FileId, offset: TextSize) -> Cancellable<Vec<CompletionItem>> {
        self.with_db(|db| completion::completions(db, self.workspace, file.0, offset))
    }

    /// The edits that format `file` in the canonical style of `robosim
    /// fmt`, or a message when it cannot be formatted (a syntax error).
    pub fn format(&self, file: FileId) -> Cancellable<Result<Vec<TextEdit>, String>> {
        self.with_db(|db| formatting::format(db, file.0))
    }

    /// The code lenses that start a verification from `file`: on each
    /// assertion and simulation of an assertion file, and on each RoboChart
    /// module that a simulation of the workspace simulates.
    pub fn verify_lenses(&self, file: FileId) -> Cancellable<Vec<VerifyLens>> {
        self.with_db(|db| verify::lenses(db, self.workspace, file.0))
    }

    /// The code lenses that open a diagram: on the name of each state
    /// machine, operation, controller and module of `file`.
    pub fn diagram_lenses(&self, file: FileId) -> Cancellable<Vec<DiagramLens>> {
        self.with_db(|db| diagram::lenses(db, file.0))
    }

    /// The diagrams of `file` (only those named `element`, a name or a
    /// qualified name, when it is given), in source order, each with its
    /// SVG; an error when `element` names nothing the file declares.
    pub fn diagrams(
        &self,
        file: FileId,
        element: Option<&str>,
    ) -> Cancellable<Result<Vec<RenderedDiagram>, DiagramError>> {
        let models = self.with_db(|db| diagram::diagrams(db, self.workspace, file.0, element))?;
        // The layout reads no database: it runs outside the query.
        Ok(models.map(|all| all.into_iter().map(diagram::render).collect()))
    }

    /// The diagram models of `file` (not laid out), in source order.
    pub fn diagram_models(&self, file: FileId) -> Cancellable<Vec<diagram::Diagram>> {
        self.with_db(|db| robosim_diagram::file_diagrams(db, self.workspace, file.0))
    }

    /// The workspace's tock-CSP semantics as CSPm files for FDR, with the
    /// assertions of its assertion files.
    pub fn export_csp(&self, profile: export::Profile) -> Cancellable<export::Export> {
        self.with_db(|db| robosim_semantics::export_workspace(db, self.workspace, &export::Options { profile }))
    }

    /// Runs every assertion of the workspace's assertion files with the
    /// native engine, in file order: one report each. Like
    /// [`Analysis::verify`], it may run for long.
    pub fn verify_workspace(
        &self,
        opts: &verify::Options,
        progress: Option<verify::ProgressFn>,
    ) -> Cancellable<Vec<verify::Report>> {
        self.with_db(|db| robosim_engine::verify::verify_workspace(db, self.workspace, opts, progress))
    }

    /// Whether `target` names an assertion or a simulation of an assertion
    /// file of the workspace, or what is wrong.
    pub fn check_verify_target(&self, target: &VerifyTarget) -> Cancellable<Result<(), String>> {
        self.with_db(|db| verify::check_target(db, self.workspace, target))
    }

    /// Runs the check of `target` with the native engine: one report per
    /// assertion checked, or what is wrong with the target. It may run for
    /// long: the snapshot is held meanwhile, so the caller must stop it
    /// (through `opts.budget.cancel`) before changing an input.
    pub fn verify(
        &self,
        target: &VerifyTarget,
        opts: &verify::Options,
        progress: Option<verify::ProgressFn>,
    ) -> Cancellable<Result<Vec<verify::Report>, String>> {
        self.with_db(|db| verify::run(db, self.workspace, target, opts, progress))
    }

    /// The diagnostics of the verification reports about assertions of
    /// `file` (code `RS-VERIFY`).
    pub fn verify_diagnostics(&self, file: FileId, verified: &[Verified]) -> Cancellable<Vec<Diagnostic>> {
        self.with_db(|db| verify::diagnostics(db, self.workspace, file.0, verified))
    }

    /// Like [`Analysis::hover_with_diagnostics`] (or [`Analysis::hover`]
    /// when `diagnostics` is `None`), with, on an assertion's name, the
    /// last verification report about it among `verified`.
    pub fn hover_with_verification(
        &self,
        file: FileId,
        offset: TextSize,
        diagnostics: Option<&[Diagnostic]>,
        verified: &[Verified],
    ) -> Cancellable<Option<HoverResult>> {
        self.with_db(|db| {
            let base = hover::hover(db, self.workspace, file.0, offset, diagnostics);
            let text = file.0.text(db);
            let offset = offset.min(TextSize::of(text.as_str()));
            let Some((range, section)) = verify::hover_section(db, self.workspace, file.0, offset, verified) else {
                return base;
            };
            Some(match base {
                Some(h) => HoverResult { range: h.range, markdown: format!("{section}\n\n---\n\n{}", h.markdown) },
                None => HoverResult { range, markdown: section },
            })
        })
    }

    /// Quick fixes for the diagnostics of `file` that touch `range`.
    pub fn code_actions(&self, file: FileId, range: TextRange) -> Cancellable<Vec<Assist>> {
        self.with_db(|db| fixes::code_actions(db, self.workspace, file.0, range))
    }
}

/// Line starts of a file's text, memoised per text version.
#[salsa::tracked(returns(ref))]
fn line_index(db: &dyn Db, file: File) -> Arc<LineIndex> {
    Arc::new(LineIndex::new(file.text(db)))
}

/// Unwinds with `Cancelled` if an input changed; called from long loops
/// that run no query (queries check on entry).
fn check_cancelled(db: &dyn Db) {
    db.unwind_if_revision_cancelled();
}

/// Formats a model text in the canonical style of `robosim fmt` (the same
/// as [`Analysis::format`]); an error, saying where, when the text has a
/// syntax error.
pub fn format_text(text: &str, kind: FileKind) -> Result<String, String> {
    robosim_fmt::format(text, kind, &robosim_fmt::Options::default()).map_err(|e| e.to_string())
}
