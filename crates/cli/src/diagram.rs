//! `robosim diagram`: one SVG (or DOT) per state machine, operation,
//! controller and module of the files given, or the diagram model as JSON.

use std::collections::HashSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use robosim_ide::diagram::{render_dot, render_svg, Diagram};

use crate::fail;
use crate::workspace::{done, Workspace};

/// What to write.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Output {
    Svg,
    Dot,
    Json,
}

/// The command's arguments.
pub struct Args {
    pub output: Output,
    pub dir: Option<PathBuf>,
    pub element: Option<String>,
    pub paths: Vec<PathBuf>,
}

pub fn run(args: Args) -> ExitCode {
    let ws = match Workspace::load(&args.paths, robosim_ide::RuleSet::Paper) {
        Ok(ws) => ws,
        Err(e) => return fail(e),
    };
    let mut diagrams: Vec<Diagram> = Vec::new();
    for f in ws.files.iter().take(ws.user_files) {
        diagrams.extend(done(ws.analysis.diagram_models(f.id)));
    }
    if let Some(name) = &args.element {
        diagrams.retain(|d| &d.name == name || &d.qualified_name == name);
        if diagrams.is_empty() {
            return fail(format!("no state machine, operation, controller or module named `{name}`"));
        }
    }
    if diagrams.is_empty() {
        eprintln!("robosim: no state machine, operation, controller or module in the files given");
        return ExitCode::from(1);
    }
    if args.output == Output::Json {
        let json = serde_json::to_string_pretty(&diagrams).unwrap_or_default();
        let _ = writeln!(std::io::stdout().lock(), "{json}");
        return ExitCode::SUCCESS;
    }
    let render = |d: &Diagram| if args.output == Output::Dot { render_dot(d) } else { render_svg(d) };
    let Some(dir) = &args.dir else {
        if diagrams.len() > 1 {
            let names: Vec<&str> = diagrams.iter().map(|d| d.qualified_name.as_str()).collect();
            return fail(format!(
                "{} diagrams ({}): write them to a folder with `-o DIR`, or choose one with `--element NAME`",
                diagrams.len(),
                names.join(", ")
            ));
        }
        let _ = std::io::stdout().lock().write_all(render(&diagrams[0]).as_bytes());
        return ExitCode::SUCCESS;
    };
    if let Err(e) = std::fs::create_dir_all(dir) {
        return fail(format!("cannot create `{}`: {e}", dir.display()));
    }
    let ext = if args.output == Output::Dot { "dot" } else { "svg" };
    let mut used = HashSet::new();
    for d in &diagrams {
        let path = file_name(dir, d, ext, &mut used);
        if let Err(e) = std::fs::write(&path, render(d)) {
            return fail(format!("cannot write `{}`: {e}", path.display()));
        }
        println!("{}", path.display());
    }
    ExitCode::SUCCESS
}

/// `DIR/package.Name.svg`, with `-2`, `-3`… when two elements share a name.
fn file_name(dir: &Path, d: &Diagram, ext: &str, used: &mut HashSet<String>) -> PathBuf {
    let base: String = d
        .qualified_name
        .replace("::", ".")
        .chars()
        .map(|c| if c.is_alphanumeric() || c == '.' || c == '_' || c == '-' { c } else { '_' })
        .collect();
    let mut name = format!("{base}.{ext}");
    let mut k = 2;
    while !used.insert(name.clone()) {
        name = format!("{base}-{k}.{ext}");
        k += 1;
    }
    dir.join(name)
}
