//! What the diagram tests share: where the repository is, and the model
//! files of a folder read as one workspace.

use std::path::{Path, PathBuf};

use robosim_hir::FileKind;

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The model files directly in `dir`, as (path relative to `base`, text).
pub fn files_in(dir: &Path, base: &Path) -> Vec<(String, String)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_file() && matches!(FileKind::from_path(p), Some(FileKind::RoboChart | FileKind::RoboSim)))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let rel = p.strip_prefix(base).unwrap().to_string_lossy().replace('\\', "/");
            (rel, String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned())
        })
        .collect()
}
