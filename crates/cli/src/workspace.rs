//! Collecting the model files named on the command line, and checking them.

use std::fmt;
use std::path::{Path, PathBuf};

use std::collections::HashMap;

use robosim_hir::{RootDatabase, RuleSet};
use robosim_syntax::line_index::LineIndex;
use robosim_syntax::{FileKind, Parse, TextRange, TextSize};

use robosim_ide::workspace_files::{self, looks_like_restructured_text, read_model_file};

use crate::diagnostics::{Diagnostic, Related, Severity};

/// One loaded model file.
pub struct SourceFile {
    /// The path as given or as found under a given folder.
    pub path: String,
    pub text: String,
    pub line_index: LineIndex,
    /// Byte offset of the first invalid UTF-8 sequence, if any.
    pub invalid_utf8: Option<usize>,
    /// The file's input in the semantic database.
    pub input: robosim_hir::File,
}

/// Every file of one `check` run, and the semantic database over them. The
/// bundled library files come after the user's files.
pub struct Workspace {
    pub files: Vec<SourceFile>,
    /// How many of `files` the user gave (the rest is the library).
    pub user_files: usize,
    pub db: RootDatabase,
    pub input: robosim_hir::Workspace,
}

/// A usage or I/O problem: exit status 2.
pub struct LoadError(String);

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl Workspace {
    pub fn load(paths: &[PathBuf], rules: RuleSet) -> Result<Workspace, LoadError> {
        let found = find_model_files(paths)?;
        let mut loaded = Vec::new();
        for (p, explicit) in found {
            let (text, invalid_utf8) =
                read_model_file(&p).map_err(|e| LoadError(format!("cannot read `{}`: {}", p.display(), io_msg(&e))))?;
            let kind = FileKind::from_path(&p).unwrap_or(FileKind::RoboChart);
            if kind == FileKind::RoboSim && !explicit && looks_like_restructured_text(&text) {
                continue;
            }
            loaded.push((p.to_string_lossy().into_owned(), text, invalid_utf8));
        }
        Ok(Workspace::new(loaded, rules))
    }

    fn new(loaded: Vec<(String, String, Option<usize>)>, rules: RuleSet) -> Workspace {
        let db = RootDatabase::default();
        let input = robosim_hir::load_workspace(&db, loaded.iter().map(|(p, t, _)| (p.clone(), t.clone())), rules);
        let inputs = input.files(&db).clone();
        // The library comes first in the database, last here.
        let (lib, user): (Vec<_>, Vec<_>) = inputs.into_iter().partition(|f| f.is_library(&db));
        let mut files: Vec<SourceFile> = user
            .into_iter()
            .zip(loaded)
            .map(|(input, (path, text, invalid_utf8))| SourceFile {
                path,
                line_index: LineIndex::new(&text),
                text,
                invalid_utf8,
                input,
            })
            .collect();
        let user_files = files.len();
        for input in lib {
            let text = input.text(&db).clone();
            files.push(SourceFile {
                path: input.path(&db).clone(),
                line_index: LineIndex::new(&text),
                text,
                invalid_utf8: None,
                input,
            });
        }
        Workspace { files, user_files, db, input }
    }

    /// The syntax tree of file `i`.
    pub fn parse(&self, i: usize) -> &Parse {
        robosim_hir::parse(&self.db, self.files[i].input)
    }

    /// Every diagnostic of the user's files, ordered by file and position.
    pub fn diagnostics(&self) -> Vec<Diagnostic> {
        let index: HashMap<robosim_hir::File, usize> =
            self.files.iter().enumerate().map(|(i, f)| (f.input, i)).collect();
        let mut out = Vec::new();
        for (id, f) in self.files.iter().enumerate().take(self.user_files) {
            if let Some(at) = f.invalid_utf8 {
                let at = TextSize::from(at as u32);
                out.push(Diagnostic {
                    file: id,
                    range: TextRange::new(at, at),
                    severity: Severity::Error,
                    code: "SYN-01".into(),
                    message: "the file is not valid UTF-8 text; invalid bytes are shown as \u{FFFD}".into(),
                    related: Vec::new(),
                });
            }
            for d in robosim_hir::file_diagnostics(&self.db, self.input, f.input) {
                out.push(Diagnostic {
                    file: id,
                    range: d.range,
                    severity: d.severity,
                    code: d.code.clone(),
                    message: d.message.clone(),
                    related: d
                        .related
                        .iter()
                        .filter_map(|r| {
                            Some(Related { file: *index.get(&r.file)?, range: r.range, message: r.message.clone() })
                        })
                        .collect(),
                });
            }
        }
        out.sort_by_key(|d| (d.file, d.range.start(), d.range.end()));
        out
    }
}

/// The model files named on the command line, and those found under the
/// folders named there, each with whether it was named explicitly.
pub(crate) fn find_model_files(paths: &[PathBuf]) -> Result<Vec<(PathBuf, bool)>, LoadError> {
    let mut found = Vec::new();
    for p in paths {
        let meta =
            std::fs::metadata(p).map_err(|e| LoadError(format!("cannot read `{}`: {}", p.display(), io_msg(&e))))?;
        if meta.is_dir() {
            walk(p, &mut found)?;
        } else if FileKind::from_path(p).is_some() {
            found.push((p.clone(), true));
        } else {
            return Err(LoadError(format!(
                "`{}` is not a model file: expected .rct, .rst, .assertions or .rsa",
                p.display()
            )));
        }
    }
    Ok(found)
}

/// The model files under `dir`; a folder that cannot be read stops the
/// run (exit status 2) rather than being skipped silently.
fn walk(dir: &Path, out: &mut Vec<(PathBuf, bool)>) -> Result<(), LoadError> {
    let (files, errors) = workspace_files::find_model_files(dir);
    if let Some((d, e)) = errors.first() {
        return Err(LoadError(format!("cannot read `{}`: {}", d.display(), io_msg(e))));
    }
    out.extend(files.into_iter().map(|p| (p, false)));
    Ok(())
}

pub(crate) fn io_msg(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}
