//! A workspace loaded once from paths on disk, for one-shot runs (the
//! command line): the files named, and the model files found under the
//! folders named, in one [`AnalysisHost`].

use std::fmt;
use std::path::{Path, PathBuf};

use robosim_syntax::FileKind;

use crate::workspace_files::{self, looks_like_restructured_text, read_model_file};
use crate::{AnalysisHost, Durability, FileId, RuleSet};

/// One file of a loaded workspace.
#[derive(Debug, Clone)]
pub struct LoadedFile {
    /// The path as given, or as found under a given folder.
    pub path: String,
    /// The file in the host.
    pub id: FileId,
    /// Byte offset of the first invalid UTF-8 sequence (replaced by U+FFFD
    /// in the text), if any.
    pub invalid_utf8: Option<usize>,
}

/// The files of a one-shot run and the host that analyses them.
#[derive(Debug)]
pub struct LoadedWorkspace {
    /// The analysis host over the files (and the bundled library).
    pub host: AnalysisHost,
    /// The user's files, in the order they were found.
    pub files: Vec<LoadedFile>,
}

/// A path that cannot be read, or is not a model file: a usage or I/O
/// problem, as opposed to a problem in a model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoadError(pub String);

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LoadError {}

/// Loads the files named in `paths` and the model files under the folders
/// named there (see [`workspace_files::find_model_files`]). A `.rst` file
/// found in a folder that looks like reStructuredText is skipped; one
/// named explicitly is always read as RoboSim.
pub fn load_paths(paths: &[PathBuf], rules: RuleSet) -> Result<LoadedWorkspace, LoadError> {
    let mut host = AnalysisHost::new(rules);
    let mut files = Vec::new();
    for (p, explicit) in model_files(paths)? {
        let (text, invalid_utf8) =
            read_model_file(&p).map_err(|e| LoadError(format!("cannot read `{}`: {}", p.display(), io_msg(&e))))?;
        let kind = FileKind::from_path(&p).unwrap_or(FileKind::RoboChart);
        if kind == FileKind::RoboSim && !explicit && looks_like_restructured_text(&text) {
            continue;
        }
        let path = p.to_string_lossy().into_owned();
        let id = host.set_file(&path, text, Some(kind), Durability::MEDIUM);
        files.push(LoadedFile { path, id, invalid_utf8 });
    }
    host.set_projects(workspace_files::project_roots(files.iter().map(|f| Path::new(&f.path))));
    Ok(LoadedWorkspace { host, files })
}

/// The model files named in `paths` and those found under the folders
/// named there, each with whether it was named explicitly.
pub fn model_files(paths: &[PathBuf]) -> Result<Vec<(PathBuf, bool)>, LoadError> {
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
/// run rather than being skipped silently.
fn walk(dir: &Path, out: &mut Vec<(PathBuf, bool)>) -> Result<(), LoadError> {
    let (files, errors) = workspace_files::find_model_files(dir);
    if let Some((d, e)) = errors.first() {
        return Err(LoadError(format!("cannot read `{}`: {}", d.display(), io_msg(e))));
    }
    out.extend(files.into_iter().map(|p| (p, false)));
    Ok(())
}

/// An I/O error in the words of the command line's messages.
pub fn io_msg(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}
