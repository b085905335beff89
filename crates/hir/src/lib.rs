//! The semantic model of a RoboChart/RoboSim workspace, computed
//! incrementally with salsa: file text → parse → per-file declarations →
//! workspace-wide names → references → types → well-formedness diagnostics.
//!
//! Inputs are [`File`]s (path, text, language) and one [`Workspace`] (the set
//! of files and the rule set). Everything else is a tracked query whose
//! results are plain values, so the CLI, the language server and tests read
//! them the same way.

pub mod assertion_names;
pub mod assertions;
pub mod body;
mod checks;
pub mod codes;
pub mod csp_blocks;
pub mod csp_defs;
pub mod csp_fn;
pub mod csp_library;
pub mod csp_names;
pub mod cycle;
mod db;
pub mod defs;
mod defs_shift;
mod diagnostics;
pub mod domains;
pub mod element;
pub mod element_rules;
pub mod index;
pub mod model;
mod more_checks;
pub mod nav;
pub mod profile;
pub mod resolve;
mod robosim;
pub mod target;
pub mod types;
mod walk;

pub use db::{Db, RootDatabase};
pub use diagnostics::{file_diagnostics, prefetch_rules, Diagnostic, Related, Severity};
pub use robosim_syntax::{line_index, FileKind, Parse, TextRange, TextSize};

/// One model file: its path (as given by the user, or a `<stdlib>/…` path
/// for the bundled library), its text and its language.
#[salsa::input(debug)]
pub struct File {
    /// The path as given or found, used in messages and JSON.
    #[returns(ref)]
    pub path: String,
    /// The current text. Set it with [`set_text`], which also updates the
    /// file's [`element::Element`]s.
    #[get(text_field)]
    #[set(set_text_field)]
    #[returns(ref)]
    pub(crate) text: String,
    /// The language, from the extension.
    #[returns(copy)]
    pub kind: FileKind,
    /// Whether this is a bundled library file (never reported on).
    #[returns(copy)]
    pub is_library: bool,
    /// An earlier text of the file and its parse, set by editors along with
    /// a new text so that [`parse`] reparses only what the edit touched.
    #[default]
    #[get(prior_field)]
    #[set(set_prior_field)]
    #[returns(ref)]
    pub(crate) prior: Option<Prior>,
    /// The top-level elements of the text, kept by [`set_text`].
    #[default]
    #[returns(ref)]
    pub(crate) elements: Vec<element::Element>,
    /// The package and imports of the text (positions from the file's
    /// start), kept by [`set_text`].
    #[default]
    #[returns(ref)]
    pub(crate) header: defs::FileDefs,
    /// The element last edited at low durability, if any (read by no
    /// query; see [`element::Element`]).
    #[default]
    #[returns(copy)]
    pub(crate) hot: Option<element::Element>,
}

impl File {
    /// The current text.
    pub fn text(self, db: &dyn Db) -> &String {
        self.text_field(db)
    }

    /// The earlier text and parse given with the current text, if any.
    pub fn prior(self, db: &dyn Db) -> &Option<Prior> {
        self.prior_field(db)
    }
}

/// An earlier text of a file and its syntax tree, from which the tree of
/// the current text is derived incrementally (the result is the same as
/// parsing the current text from scratch; only the cost differs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Prior {
    /// The earlier text.
    pub text: String,
    /// Its parse.
    pub parse: Parse,
}

/// The set of files checked together, and the rule set in force.
#[salsa::input(debug)]
pub struct Workspace {
    /// Every file of the workspace, the bundled library included.
    #[returns(ref)]
    pub files: Vec<File>,
    /// Which rule set decides severities.
    #[returns(copy)]
    pub rules: RuleSet,
    /// The root folders of the RoboTool (Eclipse) projects in the
    /// workspace, written as the files' paths are: folders holding a
    /// `.project`. RoboTool resolves names within a project, so a file
    /// under a root sees only that project's files and the library; with
    /// no roots every file sees every other (see [`index::project_of`]).
    #[default]
    #[returns(ref)]
    pub projects: Vec<String>,
}

/// The two rule sets of the well-formedness catalogue (§4.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RuleSet {
    /// Every rule at the severity of the catalogue (default).
    #[default]
    Paper,
    /// RoboTool compatibility: the paper rules RoboTool does not check, and
    /// every new rule, are warnings.
    RoboTool,
}

/// The syntax tree of a file (re-parsed only when its text changes; from
/// its [`Prior`] when it has one, which reparses only the edited member).
#[salsa::tracked(returns(ref))]
pub fn parse(db: &dyn Db, file: File) -> Parse {
    let (text, kind) = (file.text_field(db), file.kind(db));
    match file.prior_field(db) {
        Some(prior) if prior.parse.file_kind() == kind => robosim_syntax::reparse(&prior.parse, &prior.text, text),
        _ => robosim_syntax::parse(text, kind),
    }
}

/// Creates the workspace inputs for `files` (path, text) plus the bundled
/// library. The library's inputs are of high durability (it never
/// changes), the rest of low durability but for the files' paths and
/// languages.
pub fn load_workspace(
    db: &mut RootDatabase,
    files: impl IntoIterator<Item = (String, String)>,
    rules: RuleSet,
) -> Workspace {
    let mut all = Vec::new();
    for lib in robosim_stdlib::FILES {
        let kind = kind_of(lib.path).unwrap_or(FileKind::RoboChart);
        all.push(new_file(db, lib.path.to_string(), lib.text.to_string(), kind, true, Durability::HIGH));
    }
    for (path, text) in files {
        let kind = kind_of(&path).unwrap_or(FileKind::RoboChart);
        all.push(new_file(db, path, text, kind, false, Durability::LOW));
    }
    Workspace::builder(all, rules).durability(Durability::MEDIUM).new(db)
}

/// A new file of the workspace (not yet in its [`Workspace::files`]):
/// `durability` is that of its text, its path and language are of medium
/// durability at least. Creates its elements.
pub fn new_file(
    db: &mut RootDatabase,
    path: String,
    text: String,
    kind: FileKind,
    is_library: bool,
    durability: Durability,
) -> File {
    let file = File::builder(path, text, kind, is_library)
        .durability(durability.max(Durability::MEDIUM))
        .text_durability(durability)
        .prior_durability(durability)
        .new(db);
    element::sync_elements(db, file, durability);
    file
}

/// Sets the text of `file` (with `prior`, an earlier text and its parse
/// from which the new parse is derived incrementally, if any), and keeps
/// its elements: only those whose syntax changed are set. `durability`
/// is that of the text: LOW for a buffer being edited (its edited element
/// is then the only input of low durability, so that salsa re-validates
/// the other elements' results without looking at them), MEDIUM or HIGH
/// for files that rarely change.
pub fn set_text(db: &mut RootDatabase, file: File, text: String, prior: Option<Prior>, durability: Durability) {
    use salsa::Setter;
    file.set_prior_field(db).with_durability(durability).to(prior);
    file.set_text_field(db).with_durability(durability).to(text);
    element::sync_elements(db, file, durability);
}

/// Sets the text of `file` after an edit, as [`set_text`] with the
/// current text and parse as the prior (the current text is moved there,
/// not copied): what an editor's host does after each keystroke.
pub fn edit_text(db: &mut RootDatabase, file: File, text: String, durability: Durability) {
    use salsa::Setter;
    let parse = parse(db, file).clone();
    let old = file.set_text_field(db).with_durability(durability).to(text);
    file.set_prior_field(db).with_durability(durability).to(Some(Prior { text: old, parse }));
    element::sync_elements(db, file, durability);
}

pub use salsa::Durability;

fn kind_of(path: &str) -> Option<FileKind> {
    FileKind::from_path(std::path::Path::new(path))
}
