//! Inputs shared by the tests of several crates (the parser's, the
//! formatter's, the engine's and the exporter's): the model files under a
//! folder, a soup of tokens and keywords of all four languages, and a small
//! model that uses most constructs.

use std::path::{Path, PathBuf};

/// Appends the model files under `dir` (recursively, sorted, skipping `.git`)
/// to `out`; nothing for a folder that cannot be read.
pub fn model_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n == ".git") {
                continue;
            }
            model_files(&p, out);
        } else if is_model_file(&p) {
            out.push(p);
        }
    }
}

/// The model and assertion files under `dir` ([`model_files`]), each as
/// (its path as text, its contents), to load as one workspace.
pub fn read_model_files(dir: &Path) -> Vec<(String, String)> {
    let mut paths = Vec::new();
    model_files(dir, &mut paths);
    paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).expect("a model file"))).collect()
}

/// The RoboTool projects of the corpus repository `repo` (a folder of
/// `../shared/corpus`), as the corpus's `MANIFEST.md` records them: the
/// `.project` files were not copied, so the manifest's "Files:" entry names
/// the project folders of a repository that holds several (`in two projects
/// (`A/`, `B/`)`). RoboTool resolves names within a project, so each is
/// checked on its own; a repository with one project is `[repo]`.
pub fn corpus_projects(repo: &Path) -> Vec<PathBuf> {
    let manifest = repo.parent().map(|c| c.join("MANIFEST.md"));
    let text = manifest.and_then(|m| std::fs::read_to_string(m).ok()).unwrap_or_default();
    let name = repo.file_name().map(|n| n.to_string_lossy().replacen("__", "/", 1)).unwrap_or_default();
    let section = text.split("\n### ").find(|s| s.lines().next().is_some_and(|l| l.trim() == name));
    // The "- Files:" bullet, up to the next bullet.
    let files = section
        .and_then(|s| s.split("\n- ").find(|b| b.starts_with("Files:")))
        .filter(|b| b.contains("projects"))
        .unwrap_or_default();
    let roots: Vec<PathBuf> = files
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|q| q.ends_with('/'))
        .map(|q| repo.join(q.trim_end_matches('/')))
        .filter(|p| p.is_dir())
        .collect();
    if roots.is_empty() {
        vec![repo.to_path_buf()]
    } else {
        roots
    }
}

/// Words proptest strings together into arbitrary, mostly broken, input.
pub const SOUP: &[&str] = &[
    "stm",
    "state",
    "transition",
    "from",
    "to",
    "trigger",
    "exec",
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    "[|",
    "|]",
    "(|",
    "|)",
    "<{",
    "x",
    "e",
    "1",
    "2.5",
    "\"s\"",
    "=",
    "==",
    ";",
    ",",
    ":",
    "::",
    "::*",
    "?",
    "!",
    ".",
    "$",
    "#",
    "if",
    "then",
    "else",
    "end",
    "forall",
    "@",
    "|",
    "Set(",
    "Seq(",
    "int",
    "->",
    "<->",
    "*",
    "+",
    "-",
    "not",
    "/\\",
    "\\/",
    "=>",
    "interface",
    "event",
    "var",
    "const",
    "controller",
    "module",
    "connection",
    "on",
    "_async",
    "cycleDef",
    "input",
    "context",
    "assertion",
    "is",
    "deadlock-free",
    "csp",
    "csp-begin",
    "csp-end",
    "with",
    "constant",
    "of",
    "set",
    "and",
    "/*",
    "*/",
    "//",
    "\n",
    "the",
    "let",
    "lambda",
    "since",
    "sinceEntry",
    "wait",
    "send",
    "entry",
    "^",
    "<",
    ">",
    "\n\n",
    "\t",
];

/// A small well-formed model touching most constructs.
pub const MODEL: &str = "package p\ninterface I { event e : int move(x : real) }\nstm M {\n  requires I uses I\n  var x : int = 0\n  clock C\n  initial i\n  state S { entry move(1.0); x = x + 1 during skip exit #C }\n  transition t { from i to S }\n  transition u { from S to S trigger e?x #C <{ 1 } condition x > 0 /\\ since(C) < 2 action if x == 1 then move(0) else skip end }\n}\nmodule Mod { robotic platform P { provides I } controller C { requires I sref m = M connection C on e to m on e } connection P on e to C on e (_async) [mult] }\n";

/// Whether `path` has the extension of one of the four languages (`.rct`,
/// `.rst`, `.assertions`, `.rsa`). Written out rather than taken from
/// `robosim-syntax` so that the syntax crate's own tests can use this crate.
pub fn is_model_file(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| matches!(e, "rct" | "rst" | "assertions" | "rsa"))
}
