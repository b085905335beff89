//! The model files named on the command line, loaded into an `ide`
//! analysis host, and their diagnostics.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use robosim_ide::batch::{load_paths, LoadError};
use robosim_ide::{Analysis, AnalysisHost, Cancellable, FileId, LineIndex, RuleSet, TextRange, TextSize};

use crate::diagnostics::{Diagnostic, Related, Severity};

pub use robosim_ide::batch::io_msg;

/// One loaded model file.
pub struct SourceFile {
    /// The path as given or as found under a given folder.
    pub path: String,
    pub text: Arc<str>,
    pub line_index: Arc<LineIndex>,
    /// Byte offset of the first invalid UTF-8 sequence, if any.
    pub invalid_utf8: Option<usize>,
    /// The file in the analysis host.
    pub id: FileId,
}

/// Every file of one run and the analysis over them. The bundled library
/// files come after the user's files.
pub struct Workspace {
    pub files: Vec<SourceFile>,
    /// How many of `files` the user gave (the rest is the library).
    pub user_files: usize,
    /// Keeps the database alive; nothing changes it after loading.
    _host: AnalysisHost,
    pub analysis: Analysis,
}

/// The answer of a query. Queries are cancelled only when an input
/// changes, and a command-line run changes none after loading.
pub fn done<T>(result: Cancellable<T>) -> T {
    match result {
        Ok(v) => v,
        Err(_) => unreachable!("the command line changes no input while it queries"),
    }
}

impl Workspace {
    pub fn load(paths: &[PathBuf], rules: RuleSet) -> Result<Workspace, LoadError> {
        let loaded = load_paths(paths, rules)?;
        let analysis = loaded.host.analysis();
        let user_files = loaded.files.len();
        let mut files = Vec::new();
        let mut add = |path: String, id: FileId, invalid_utf8: Option<usize>| {
            files.push(SourceFile {
                path,
                text: done(analysis.file_text(id)),
                line_index: done(analysis.line_index(id)),
                invalid_utf8,
                id,
            })
        };
        for f in loaded.files {
            add(f.path, f.id, f.invalid_utf8);
        }
        for (path, id) in loaded.host.library_files() {
            add(path, id, None);
        }
        Ok(Workspace { files, user_files, _host: loaded.host, analysis })
    }

    /// The position of `offset` in file `i`: 0-based line, UTF-16 column.
    pub fn line_col(&self, i: usize, offset: TextSize) -> (u32, u32) {
        let f = &self.files[i];
        let lc = f.line_index.line_col(&f.text, offset);
        (lc.line, lc.col)
    }

    /// Every diagnostic of the user's files, ordered by file and position.
    pub fn diagnostics(&self) -> Vec<Diagnostic> {
        let index: HashMap<FileId, usize> = self.files.iter().enumerate().map(|(i, f)| (f.id, i)).collect();
        let mut out = Vec::new();
        for (file, f) in self.files.iter().enumerate().take(self.user_files) {
            if let Some(at) = f.invalid_utf8 {
                let at = TextSize::from(at as u32);
                out.push(Diagnostic {
                    file,
                    range: TextRange::new(at, at),
                    severity: Severity::Error,
                    code: "SYN-01".into(),
                    message: "the file is not valid UTF-8 text; invalid bytes are shown as \u{FFFD}".into(),
                    related: Vec::new(),
                });
            }
            for d in done(self.analysis.diagnostics(f.id)) {
                out.push(Diagnostic {
                    file,
                    range: d.range,
                    severity: d.severity,
                    code: d.code,
                    message: d.message,
                    related: d
                        .related
                        .into_iter()
                        .filter_map(|r| {
                            Some(Related { file: *index.get(&r.file)?, range: r.range, message: r.message })
                        })
                        .collect(),
                });
            }
        }
        out.sort_by_key(|d| (d.file, d.range.start(), d.range.end()));
        out
    }
}
