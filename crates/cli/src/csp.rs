//! `robosim csp`: the workspace's tock-CSP semantics as CSPm files for FDR
//! (RoboTool's naming and layout), with the assertions of its `.rsa` and
//! `.assertions` files as FDR `assert`s, and RoboChart's untimed semantics
//! with the untimed and plain assertions (RT-8, RT-9).
//!
//! The layout is RoboTool's: the untimed script in the output folder, the
//! timed one in its `timed/` subfolder (each folder's assertion files
//! include the files beside them).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use robosim_ide::export::Profile;

use crate::fail;
use crate::workspace::{done, io_msg, Workspace};

/// The command's arguments.
pub struct Args {
    pub profile: Profile,
    pub out: Option<PathBuf>,
    pub paths: Vec<PathBuf>,
}

pub fn run(args: Args) -> ExitCode {
    let ws = match Workspace::load(&args.paths, robosim_ide::RuleSet::Paper) {
        Ok(ws) => ws,
        Err(e) => return fail(e),
    };
    if ws.user_files == 0 {
        return fail("no model files (.rct, .rst, .assertions, .rsa) were found");
    }
    let export = done(ws.analysis.export_csp(args.profile));
    for w in &export.warnings {
        eprintln!("robosim: warning: {w}");
    }
    // (path in the output folder, file): the untimed script, then the timed.
    let files: Vec<(PathBuf, &robosim_ide::export::OutFile)> = export
        .untimed
        .iter()
        .map(|f| (PathBuf::from(&f.name), f))
        .chain(export.files.iter().map(|f| (PathBuf::from("timed").join(&f.name), f)))
        .collect();
    match &args.out {
        Some(dir) => {
            for sub in [dir.clone(), dir.join("timed")] {
                if let Err(e) = std::fs::create_dir_all(&sub) {
                    return fail(format!("cannot create `{}`: {}", sub.display(), io_msg(&e)));
                }
            }
            for (rel, f) in &files {
                let path = dir.join(rel);
                if let Err(e) = std::fs::write(&path, f.text()) {
                    return fail(format!("cannot write `{}`: {}", path.display(), io_msg(&e)));
                }
            }
            eprintln!(
                "robosim: wrote {} files to {} ({} untimed, {} timed in timed/)",
                files.len(),
                dir.display(),
                export.untimed.len(),
                export.files.len()
            );
        }
        None => {
            let mut out = std::io::stdout().lock();
            for (i, (rel, f)) in files.iter().enumerate() {
                let sep = if i == 0 { "" } else { "\n" };
                let r = write!(out, "{sep}-- ==== {} ====\n{}", rel.display(), f.text());
                if let Err(e) = r {
                    if e.kind() == std::io::ErrorKind::BrokenPipe {
                        break;
                    }
                    return fail(format!("cannot write the output: {e}"));
                }
            }
        }
    }
    if export.warnings.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "robosim: {} construct{} not exported (see the warnings and the NOT EXPORTED comments)",
            export.warnings.len(),
            if export.warnings.len() == 1 { " was" } else { "s were" }
        );
        ExitCode::from(1)
    }
}
