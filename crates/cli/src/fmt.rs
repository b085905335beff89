//! `robosim fmt [--check] PATH...`: rewrites model files in the canonical
//! style (see the `robosim-fmt` crate), or lists those that are not in it.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use robosim_ide::batch::{io_msg, model_files};
use robosim_ide::workspace_files::looks_like_restructured_text;
use robosim_ide::{format_text, FileKind};

/// What happened to the files of one run, for the exit status.
#[derive(Default)]
struct Tally {
    changed: usize,
    unchanged: usize,
    /// Files not formatted because they do not parse (exit status 1).
    refused: bool,
    /// Files that could not be read or written (exit status 2).
    io_failed: bool,
}

pub(crate) fn run(check: bool, paths: &[PathBuf]) -> ExitCode {
    let found = match model_files(paths) {
        Ok(found) => found,
        Err(e) => return crate::fail(e),
    };
    let mut tally = Tally::default();
    let mut out = io::stdout().lock();
    for (path, explicit) in found {
        format_file(&path, explicit, check, &mut tally, &mut out);
    }
    if !check {
        let files = if tally.changed == 1 { "file" } else { "files" };
        let _ = writeln!(out, "formatted {} {files}, {} unchanged", tally.changed, tally.unchanged);
    }
    let status = if tally.io_failed {
        2
    } else if tally.refused || (check && tally.changed > 0) {
        1
    } else {
        0
    };
    ExitCode::from(status)
}

fn format_file(path: &Path, explicit: bool, check: bool, tally: &mut Tally, out: &mut impl Write) {
    let shown = path.display();
    let bytes = match fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("robosim: cannot read `{shown}`: {}", io_msg(&e));
            tally.io_failed = true;
            return;
        }
    };
    // Rewriting a lossy decoding would destroy the invalid bytes.
    let Ok(text) = String::from_utf8(bytes) else {
        eprintln!("robosim: {shown}: not formatted: the file is not valid UTF-8 text");
        tally.refused = true;
        return;
    };
    let kind = FileKind::from_path(path).unwrap_or(FileKind::RoboChart);
    // Same rule as `check`: documentation found in a folder is not a model.
    if kind == FileKind::RoboSim && !explicit && looks_like_restructured_text(&text) {
        return;
    }
    let formatted = match format_text(&text, kind) {
        Ok(formatted) => formatted,
        Err(e) => {
            eprintln!("robosim: {shown}: not formatted: {e}");
            tally.refused = true;
            return;
        }
    };
    if formatted == text {
        tally.unchanged += 1;
    } else if check {
        let _ = writeln!(out, "would reformat: {shown}");
        tally.changed += 1;
    } else if let Err(e) = write_atomically(path, &formatted) {
        eprintln!("robosim: cannot write `{shown}`: {}", io_msg(&e));
        tally.io_failed = true;
    } else {
        tally.changed += 1;
    }
}

/// Replaces the file at `path` with `text` so that an interruption leaves
/// either the old file or the new one, never a truncated one: the text goes
/// to a temporary file in the same folder, which is then renamed over the
/// original (atomic within one file system).
fn write_atomically(path: &Path, text: &str) -> io::Result<()> {
    // Through a symbolic link, replace the file it points to, not the link.
    let target =
        if fs::symlink_metadata(path)?.file_type().is_symlink() { fs::canonicalize(path)? } else { path.into() };
    let meta = fs::metadata(&target)?;
    // A rename would replace a read-only file; refuse as writing would.
    if meta.permissions().readonly() {
        return Err(io::Error::from(io::ErrorKind::PermissionDenied));
    }
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let (tmp, mut file) = create_temp(&dir, &name)?;
    let written = (|| {
        file.write_all(text.as_bytes())?;
        file.sync_all()?;
        drop(file);
        fs::set_permissions(&tmp, meta.permissions())?;
        fs::rename(&tmp, &target)
    })();
    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    written
}

/// A new hidden file beside `name` in `dir`, never an existing one.
fn create_temp(dir: &Path, name: &str) -> io::Result<(PathBuf, fs::File)> {
    let mut last = None;
    for n in 0..100 {
        let tmp = dir.join(format!(".{name}.robosim-fmt-{}-{n}.tmp", std::process::id()));
        match fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| io::Error::from(io::ErrorKind::AlreadyExists)))
}
