//! `robosim csp`: the workspace's tock-CSP semantics as CSPm files for FDR
//! (RoboTool's naming and layout), with the assertions of its `.rsa` and
//! `.assertions` files as FDR `assert`s.

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
    match &args.out {
        Some(dir) => {
            if let Err(e) = std::fs::create_dir_all(dir) {
                return fail(format!("cannot create `{}`: {}", dir.display(), io_msg(&e)));
            }
            for f in &export.files {
                let path = dir.join(&f.name);
                if let Err(e) = std::fs::write(&path, f.text()) {
                    return fail(format!("cannot write `{}`: {}", path.display(), io_msg(&e)));
                }
            }
            eprintln!("robosim: wrote {} files to {}", export.files.len(), dir.display());
        }
        None => {
            let mut out = std::io::stdout().lock();
            for (i, f) in export.files.iter().enumerate() {
                let sep = if i == 0 { "" } else { "\n" };
                let r = write!(out, "{sep}-- ==== {} ====\n{}", f.name, f.text());
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
