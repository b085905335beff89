//! The `robosim` command, as a library: `src/main.rs` is the binary's
//! entry point, and the end-to-end suites (`tests/`) build the same entry
//! point into their own copy of the program.

mod csp;
mod diagnostics;
mod diagram;
mod fmt;
mod verify;
mod workspace;

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use diagnostics::{Diagnostic, Severity};
use workspace::{done, Workspace};

#[derive(Parser)]
#[command(
    name = "robosim",
    version,
    about = "Checks RoboChart (.rct) and RoboSim (.rst) models and their assertion files (.assertions, .rsa)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check files and folders (searched recursively) as one workspace.
    Check {
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Human)]
        format: Format,
        /// Rule set: the paper's rules as errors (`paper`), or RoboTool's
        /// choices, where the paper rules it does not check are warnings.
        #[arg(long, value_enum, default_value_t = Rules::Paper)]
        rules: Rules,
        /// When to colour human output.
        #[arg(long, value_enum, default_value_t = Color::Auto)]
        color: Color,
        /// Model files or folders.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Print the syntax tree of a file.
    Parse {
        /// Print the full tree with ranges and token texts.
        #[arg(long)]
        tree: bool,
        /// The model file.
        file: PathBuf,
    },
    /// Rewrite files and folders (searched recursively) in the canonical style.
    Fmt {
        /// Change nothing: list the files that would change, and exit 1 if any.
        #[arg(long)]
        check: bool,
        /// Model files or folders.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Run the assertions of the workspace's .rsa and .assertions files
    /// (schedulability, …) with the native checker.
    Verify {
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Human)]
        format: Format,
        /// The semantics: what RoboTool 3 generates, or the 2019 paper's.
        #[arg(long, value_enum, default_value_t = Semantics::Robotool3)]
        semantics: Semantics,
        /// Stop a check after exploring this many states (inconclusive).
        #[arg(long)]
        max_states: Option<u64>,
        /// Stop a check after this many seconds (inconclusive).
        #[arg(long)]
        timeout: Option<f64>,
        /// Worker threads for the search (default: the number of cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Check asynchronous connections between machines or controllers
        /// with this buffer, `SIZE[:overwrite|:block]` (for example
        /// `2:block`) instead of RoboTool's, `1:overwrite` (one place; a new
        /// value replaces an unread one).
        #[arg(long, value_name = "SIZE:POLICY", value_parser = parse_async_buffer)]
        async_buffer: Option<robosim_ide::verify::AsyncBuffer>,
        /// Also draw each counterexample on the diagrams it passes through,
        /// as SVG files in this folder (steps numbered by cycle).
        #[arg(long, value_name = "DIR")]
        diagrams: Option<PathBuf>,
        /// Model files or folders: the whole workspace the assertions refer to.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Draw state machines, operations, controllers and modules: one SVG
    /// (or DOT) file each in `-o DIR`, or one on stdout.
    Diagram {
        /// SVG output (the default).
        #[arg(long, conflicts_with_all = ["dot", "json"])]
        svg: bool,
        /// Graphviz DOT output, composite states as clusters.
        #[arg(long, conflicts_with = "json")]
        dot: bool,
        /// The diagram model as JSON on stdout, for other tools.
        #[arg(long)]
        json: bool,
        /// Write one file per diagram into this folder.
        #[arg(short = 'o', long = "out")]
        out: Option<PathBuf>,
        /// Only the element with this name (or qualified name).
        #[arg(long)]
        element: Option<String>,
        /// Model files or folders.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Export the workspace's tock-CSP semantics as CSPm files for FDR, with
    /// the assertions of its .rsa and .assertions files: one file each in
    /// `-o DIR`, or all on stdout.
    Csp {
        /// The semantics: what RoboTool 3 generates, or the 2019 paper's.
        #[arg(long, value_enum, default_value_t = Semantics::Robotool3)]
        semantics: Semantics,
        /// Write the files into this folder (created if needed).
        #[arg(short = 'o', long = "out")]
        out: Option<PathBuf>,
        /// Model files or folders: the whole workspace.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Run the language server (LSP over stdin/stdout).
    Lsp {
        /// Accepted for clients that announce the transport (VS Code's
        /// `TransportKind.stdio` appends it); stdio is the only transport.
        #[arg(long)]
        stdio: bool,
        /// Accepted and ignored, as most language servers do: the server
        /// ends when the client closes its input.
        #[arg(long = "clientProcessId", value_name = "PID")]
        client_process_id: Option<u64>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum Semantics {
    Robotool3,
    Paper2019,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Format {
    Human,
    Json,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum Rules {
    Paper,
    Robotool,
}

#[derive(Clone, Copy, ValueEnum)]
enum Color {
    Auto,
    Always,
    Never,
}

/// Runs the `robosim` command on the process's arguments and returns its
/// exit status: 0 success, 1 findings (errors, failed assertions), 2 usage
/// or input errors.
pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match cli.command {
        Command::Check { format, rules, color, paths } => check(format, rules, color, &paths),
        Command::Parse { tree, file } => parse(tree, &file),
        Command::Fmt { check, paths } => fmt::run(check, &paths),
        Command::Verify { format, semantics, max_states, timeout, threads, async_buffer, diagrams, paths } => {
            verify::run(verify::Args {
                format,
                profile: match semantics {
                    Semantics::Robotool3 => robosim_ide::verify::Profile::RoboTool3,
                    Semantics::Paper2019 => robosim_ide::verify::Profile::Paper2019,
                },
                max_states,
                timeout,
                threads,
                async_buffer,
                diagrams,
                paths,
            })
        }
        Command::Diagram { svg: _, dot, json, out, element, paths } => diagram::run(diagram::Args {
            output: if json {
                diagram::Output::Json
            } else if dot {
                diagram::Output::Dot
            } else {
                diagram::Output::Svg
            },
            dir: out,
            element,
            paths,
        }),
        Command::Csp { semantics, out, paths } => csp::run(csp::Args {
            profile: match semantics {
                Semantics::Robotool3 => robosim_ide::export::Profile::RoboTool3,
                Semantics::Paper2019 => robosim_ide::export::Profile::Paper2019,
            },
            out,
            paths,
        }),
        Command::Lsp { stdio: _, client_process_id: _ } => robosim_lsp::run_stdio(),
    }
}

pub(crate) fn fail(msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("robosim: {msg}");
    ExitCode::from(2)
}

fn check(format: Format, rules: Rules, color: Color, paths: &[PathBuf]) -> ExitCode {
    let rules = match rules {
        Rules::Paper => robosim_ide::RuleSet::Paper,
        Rules::Robotool => robosim_ide::RuleSet::RoboTool,
    };
    let ws = match Workspace::load(paths, rules) {
        Ok(ws) => ws,
        Err(e) => return fail(e),
    };
    let diags = ws.diagnostics();
    let has_error = diags.iter().any(|d| d.severity == Severity::Error);
    let out = std::io::stdout();
    let result = match format {
        Format::Json => {
            let json = diagnostics::to_json(&ws, &diags);
            writeln!(out.lock(), "{json}")
        }
        Format::Human => {
            let color = match color {
                Color::Always => true,
                Color::Never => false,
                Color::Auto => out.is_terminal() && std::env::var_os("NO_COLOR").is_none(),
            };
            diagnostics::render_human(&ws, &diags, color)
        }
    };
    if let Err(e) = result {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            return fail(format!("cannot write the report: {e}"));
        }
    }
    ExitCode::from(u8::from(has_error))
}

fn parse(tree: bool, file: &std::path::Path) -> ExitCode {
    let ws = match Workspace::load(&[file.to_path_buf()], robosim_ide::RuleSet::Paper) {
        Ok(ws) => ws,
        Err(e) => return fail(e),
    };
    if ws.user_files == 0 {
        return fail(format!("`{}` is not a model file (.rct, .rst, .assertions, .rsa)", file.display()));
    }
    let id = ws.files[0].id;
    let mut out = std::io::stdout().lock();
    let text = if tree { done(ws.analysis.syntax_tree(id)) } else { done(ws.analysis.reprint(id)) };
    let _ = out.write_all(text.as_bytes());
    let has_error = done(ws.analysis.syntax_diagnostics(id)).iter().any(|d| d.severity == Severity::Error);
    if !tree {
        let diags: Vec<Diagnostic> = ws.diagnostics();
        let _ = diagnostics::render_human(&ws, &diags, false);
    }
    ExitCode::from(u8::from(has_error))
}

/// `--async-buffer SIZE[:overwrite|:block]`.
fn parse_async_buffer(text: &str) -> Result<robosim_ide::verify::AsyncBuffer, String> {
    robosim_ide::verify::AsyncBuffer::parse(text)
}
