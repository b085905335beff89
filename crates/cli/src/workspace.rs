//! Collecting the model files named on the command line, and checking them.

use std::fmt;
use std::path::{Path, PathBuf};

use robosim_syntax::line_index::LineIndex;
use robosim_syntax::{parse, FileKind, Parse, TextRange, TextSize};

use crate::diagnostics::{Diagnostic, Severity};

/// One loaded model file.
pub struct SourceFile {
    /// The path as given or as found under a given folder.
    pub path: String,
    pub text: String,
    pub line_index: LineIndex,
    pub parse: Parse,
    /// Byte offset of the first invalid UTF-8 sequence, if any.
    pub invalid_utf8: Option<usize>,
}

/// Every file of one `check` run.
pub struct Workspace {
    pub files: Vec<SourceFile>,
}

/// A usage or I/O problem: exit status 2.
pub struct LoadError(String);

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Directories never searched.
fn skipped_dir(name: &str) -> bool {
    name.starts_with('.') || matches!(name, "target" | "node_modules")
}

/// A `.rst` file is RoboSim unless it looks like reStructuredText.
fn looks_like_restructured_text(text: &str) -> bool {
    text.lines().any(|l| {
        let t = l.trim_end();
        t.starts_with(".. ")
            || (t.len() >= 3
                && t.chars().all(|c| matches!(c, '=' | '-' | '~' | '^' | '*' | '#' | '+'))
                && t.chars().all(|c| c == t.chars().next().unwrap_or(' ')))
    })
}

impl Workspace {
    pub fn load(paths: &[PathBuf]) -> Result<Workspace, LoadError> {
        let mut found = Vec::new();
        for p in paths {
            let meta = std::fs::metadata(p)
                .map_err(|e| LoadError(format!("cannot read `{}`: {}", p.display(), io_msg(&e))))?;
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
        let mut files = Vec::new();
        for (p, explicit) in found {
            let bytes =
                std::fs::read(&p).map_err(|e| LoadError(format!("cannot read `{}`: {}", p.display(), io_msg(&e))))?;
            let kind = FileKind::from_path(&p).unwrap_or(FileKind::RoboChart);
            let (text, invalid_utf8) = match String::from_utf8(bytes) {
                Ok(t) => (t, None),
                Err(e) => {
                    let at = e.utf8_error().valid_up_to();
                    (String::from_utf8_lossy(e.as_bytes()).into_owned(), Some(at))
                }
            };
            if kind == FileKind::RoboSim && !explicit && looks_like_restructured_text(&text) {
                continue;
            }
            let parse = parse(&text, kind);
            files.push(SourceFile {
                path: p.to_string_lossy().into_owned(),
                line_index: LineIndex::new(&text),
                text,
                parse,
                invalid_utf8,
            });
        }
        Ok(Workspace { files })
    }

    /// Every diagnostic, ordered by file and position.
    pub fn diagnostics(&self) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for (id, f) in self.files.iter().enumerate() {
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
            for e in f.parse.errors() {
                out.push(Diagnostic {
                    file: id,
                    range: e.range,
                    severity: match e.severity {
                        robosim_syntax::Severity::Error => Severity::Error,
                        robosim_syntax::Severity::Warning => Severity::Warning,
                    },
                    code: e.code().into(),
                    message: e.message.clone(),
                    related: Vec::new(),
                });
            }
        }
        out.sort_by_key(|d| (d.file, d.range.start(), d.range.end()));
        out
    }
}

fn walk(dir: &Path, out: &mut Vec<(PathBuf, bool)>) -> Result<(), LoadError> {
    let rd =
        std::fs::read_dir(dir).map_err(|e| LoadError(format!("cannot read `{}`: {}", dir.display(), io_msg(&e))))?;
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        // Symlinked folders are not followed, so cycles cannot hang the walk.
        let Ok(meta) = std::fs::symlink_metadata(&p) else { continue };
        if meta.is_dir() {
            if !skipped_dir(&name) {
                walk(&p, out)?;
            }
        } else if FileKind::from_path(&p).is_some() && std::fs::metadata(&p).is_ok_and(|m| m.is_file()) {
            out.push((p, false));
        }
    }
    Ok(())
}

fn io_msg(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}
