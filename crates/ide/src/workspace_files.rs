//! Which files on disk belong to a workspace: the one definition that
//! `robosim check` and the language server share.

use std::path::{Path, PathBuf};

use robosim_syntax::FileKind;

/// Folders never searched: hidden ones, build output and npm packages.
pub fn skipped_dir(name: &str) -> bool {
    name.starts_with('.') || matches!(name, "target" | "node_modules")
}

/// Whether `path` has a model extension (`.rct`, `.rst`, `.assertions`,
/// `.rsa`).
pub fn is_model_path(path: &Path) -> bool {
    FileKind::from_path(path).is_some()
}

/// A `.rst` file found in a folder is RoboSim unless it looks like
/// reStructuredText (`.. directive::`, section underlines), which shares
/// the extension.
pub fn looks_like_restructured_text(text: &str) -> bool {
    text.lines().any(|l| {
        let t = l.trim_end();
        t.starts_with(".. ")
            || (t.len() >= 3
                && t.chars().all(|c| matches!(c, '=' | '-' | '~' | '^' | '*' | '#' | '+'))
                && t.chars().all(|c| c == t.chars().next().unwrap_or(' ')))
    })
}

/// The model files under `dir`, recursively and sorted, skipping
/// [`skipped_dir`]s. Symlinked folders are not followed, so cycles cannot
/// hang the walk; symlinked files are. Folders that cannot be read are
/// returned with their error, and the walk goes on without them.
pub fn find_model_files(dir: &Path) -> (Vec<PathBuf>, Vec<(PathBuf, std::io::Error)>) {
    let mut files = Vec::new();
    let mut errors = Vec::new();
    walk(dir, &mut files, &mut errors);
    (files, errors)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>, errors: &mut Vec<(PathBuf, std::io::Error)>) {
    let rd = match std::fs::read_dir(dir) {
        Ok(rd) => rd,
        Err(e) => {
            errors.push((dir.to_path_buf(), e));
            return;
        }
    };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let Ok(meta) = std::fs::symlink_metadata(&p) else { continue };
        if meta.is_dir() {
            if !skipped_dir(&name) {
                walk(&p, out, errors);
            }
        } else if is_model_path(&p) && std::fs::metadata(&p).is_ok_and(|m| m.is_file()) {
            out.push(p);
        }
    }
}

/// The RoboTool (Eclipse) project a model file belongs to: the nearest
/// folder above it that holds a `.project` file. RoboTool resolves names
/// per project.
pub fn project_root(path: &Path) -> Option<PathBuf> {
    path.ancestors().skip(1).find(|dir| dir.join(".project").is_file()).map(Path::to_path_buf)
}

/// The distinct project roots of `paths` (see [`project_root`]), as
/// strings in the form the paths are written, sorted.
pub fn project_roots<'a>(paths: impl IntoIterator<Item = &'a Path>) -> Vec<String> {
    let mut roots: Vec<String> =
        paths.into_iter().filter_map(project_root).map(|r| r.to_string_lossy().into_owned()).collect();
    roots.sort();
    roots.dedup();
    roots
}

/// Reads a model file as text. Invalid UTF-8 is replaced (U+FFFD); the
/// offset of the first invalid byte is returned so that it can be reported.
pub fn read_model_file(path: &Path) -> std::io::Result<(String, Option<usize>)> {
    let bytes = std::fs::read(path)?;
    Ok(match String::from_utf8(bytes) {
        Ok(t) => (t, None),
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            (String::from_utf8_lossy(e.as_bytes()).into_owned(), Some(at))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restructured_text_is_recognised() {
        assert!(looks_like_restructured_text("Title\n=====\n"));
        assert!(looks_like_restructured_text(".. note:: hi\n"));
        assert!(!looks_like_restructured_text("stm M { initial i }\n"));
    }

    #[test]
    fn walk_skips_hidden_and_build_folders() {
        let dir = std::env::temp_dir().join(format!("robosim-ide-walk-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for sub in ["a", ".git", "target", "a/b"] {
            std::fs::create_dir_all(dir.join(sub)).unwrap();
        }
        for f in ["a/m.rct", "a/b/s.rst", ".git/x.rct", "target/y.rct", "a/notes.txt", "z.rsa"] {
            std::fs::write(dir.join(f), "").unwrap();
        }
        let (files, errors) = find_model_files(&dir);
        let rel: Vec<String> =
            files.iter().map(|p| p.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/")).collect();
        assert_eq!(rel, ["a/b/s.rst", "a/m.rct", "z.rsa"]);
        assert!(errors.is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
