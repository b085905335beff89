//! The semantic model of a RoboChart/RoboSim workspace, computed
//! incrementally with salsa: file text → parse → per-file declarations →
//! workspace-wide names → references → types → well-formedness diagnostics.
//!
//! Inputs are [`File`]s (path, text, language) and one [`Workspace`] (the set
//! of files and the rule set). Everything else is a tracked query whose
//! results are plain values, so the CLI, the language server and tests read
//! them the same way.

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
    /// The current text.
    #[returns(ref)]
    pub text: String,
    /// The language, from the extension.
    #[returns(copy)]
    pub kind: FileKind,
    /// Whether this is a bundled library file (never reported on).
    #[returns(copy)]
    pub is_library: bool,
    /// An earlier text of the file and its parse, set by editors along with
    /// a new text so that [`parse`] reparses only what the edit touched.
    #[default]
    #[returns(ref)]
    pub prior: Option<Prior>,
}

/// An earlier text of a file and its syntax tree, from which the tree of
/// the current text is derived incrementally (the result is the same as
/// parsing the current text from scratch; only the cost differs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Prior {
    /// The earlier text.
    pub text: std::sync::Arc<str>,
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
    let (text, kind) = (file.text(db), file.kind(db));
    match file.prior(db) {
        Some(prior) if prior.parse.file_kind() == kind => robosim_syntax::reparse(&prior.parse, &prior.text, text),
        _ => robosim_syntax::parse(text, kind),
    }
}

/// Creates the workspace inputs for `files` (path, text) plus the bundled
/// library.
pub fn load_workspace(
    db: &RootDatabase,
    files: impl IntoIterator<Item = (String, String)>,
    rules: RuleSet,
) -> Workspace {
    let mut all = Vec::new();
    for lib in robosim_stdlib::FILES {
        let kind = kind_of(lib.path).unwrap_or(FileKind::RoboChart);
        all.push(File::new(db, lib.path.to_string(), lib.text.to_string(), kind, true));
    }
    for (path, text) in files {
        let kind = kind_of(&path).unwrap_or(FileKind::RoboChart);
        all.push(File::new(db, path, text, kind, false));
    }
    Workspace::new(db, all, rules)
}

fn kind_of(path: &str) -> Option<FileKind> {
    FileKind::from_path(std::path::Path::new(path))
}
