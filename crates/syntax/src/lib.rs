//! Lossless, error-tolerant front end for RoboChart (`.rct`), RoboSim
//! (`.rst`) and their assertion languages (`.assertions`, `.rsa`).
//!
//! [`parse`] always returns a full rowan tree whose text is byte-identical to
//! the input, plus the syntax errors found on the way. Typed views over the
//! tree live in [`ast`].

pub mod ast;
mod grammar;
mod kinds;
pub mod lexer;
pub mod line_index;
mod parser;
mod reparse;
mod tree_builder;

use std::path::Path;
use std::sync::Arc;

pub use kinds::{RoboLang, SyntaxKind};
pub use reparse::{reparse, try_reparse};
pub use rowan::{GreenNode, TextRange, TextSize};

/// A node of the syntax tree (cheap to clone; owns its root).
pub type SyntaxNode = rowan::SyntaxNode<RoboLang>;
/// A token of the syntax tree.
pub type SyntaxToken = rowan::SyntaxToken<RoboLang>;
/// A node or a token.
pub type SyntaxElement = rowan::SyntaxElement<RoboLang>;

/// The four languages, told apart by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FileKind {
    /// RoboChart models, `.rct`.
    RoboChart,
    /// RoboSim models, `.rst`.
    RoboSim,
    /// RoboChart assertions, `.assertions`.
    Assertions,
    /// RoboSim assertions, `.rsa`.
    SimAssertions,
}

impl FileKind {
    /// All file kinds.
    pub const ALL: [FileKind; 4] =
        [FileKind::RoboChart, FileKind::RoboSim, FileKind::Assertions, FileKind::SimAssertions];

    /// The kind for a file extension (without the dot).
    pub fn from_extension(ext: &str) -> Option<FileKind> {
        match ext {
            "rct" => Some(FileKind::RoboChart),
            "rst" => Some(FileKind::RoboSim),
            "assertions" => Some(FileKind::Assertions),
            "rsa" => Some(FileKind::SimAssertions),
            _ => None,
        }
    }

    /// The kind for a path, by its extension.
    pub fn from_path(path: &Path) -> Option<FileKind> {
        path.extension().and_then(|e| e.to_str()).and_then(FileKind::from_extension)
    }

    /// The usual extension (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            FileKind::RoboChart => "rct",
            FileKind::RoboSim => "rst",
            FileKind::Assertions => "assertions",
            FileKind::SimAssertions => "rsa",
        }
    }

    /// Whether this is one of the two assertion languages.
    pub fn is_assertions(self) -> bool {
        matches!(self, FileKind::Assertions | FileKind::SimAssertions)
    }
}

/// How serious a syntax diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Severity {
    /// The file does not parse as RoboTool would parse it.
    Error,
    /// Accepted here, but RoboTool's parser rejects it.
    Warning,
}

/// A syntax error or compatibility warning, on a byte range of the file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SyntaxError {
    /// What is wrong, and what was expected where.
    pub message: String,
    /// Where, in bytes.
    pub range: TextRange,
    /// Error or compatibility warning.
    pub severity: Severity,
}

impl SyntaxError {
    pub(crate) fn error(message: impl Into<String>, range: TextRange) -> SyntaxError {
        SyntaxError { message: message.into(), range, severity: Severity::Error }
    }

    pub(crate) fn compat_warning(message: impl Into<String>, range: TextRange) -> SyntaxError {
        SyntaxError { message: message.into(), range, severity: Severity::Warning }
    }

    /// The stable diagnostic code: `SYN-01` for syntax errors, `SYN-02` for
    /// input we accept but RoboTool's lexer rejects.
    pub fn code(&self) -> &'static str {
        match self.severity {
            Severity::Error => "SYN-01",
            Severity::Warning => "SYN-02",
        }
    }
}

/// The result of parsing one file: a green tree and its errors. Cheap to
/// clone and shareable between threads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Parse {
    green: GreenNode,
    errors: Arc<[SyntaxError]>,
    file: FileKind,
}

impl Parse {
    /// The root of the tree.
    pub fn syntax_node(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.green.clone())
    }

    /// The typed root.
    pub fn tree(&self) -> ast::SourceFile {
        ast::SourceFile { syntax: self.syntax_node() }
    }

    /// The green tree (for storage in incremental databases).
    pub fn green(&self) -> &GreenNode {
        &self.green
    }

    /// Syntax errors and compatibility warnings, sorted by position.
    pub fn errors(&self) -> &[SyntaxError] {
        &self.errors
    }

    /// The language the file was parsed as.
    pub fn file_kind(&self) -> FileKind {
        self.file
    }

    /// An indented dump of the tree with token texts, followed by the
    /// errors; the format of the snapshot tests and of `robosim parse --tree`.
    pub fn debug_dump(&self) -> String {
        let mut out = debug_tree(&self.syntax_node());
        for e in self.errors.iter() {
            let sev = match e.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
            };
            out.push_str(&format!(
                "{sev} {}..{}: {}\n",
                u32::from(e.range.start()),
                u32::from(e.range.end()),
                e.message
            ));
        }
        out
    }
}

/// Parses `text` as a file of kind `file`. Never fails and never panics.
pub fn parse(text: &str, file: FileKind) -> Parse {
    let (tokens, mut errors, input) = lexer::lex_for_parser(text, file);
    let mut p = parser::Parser::new(&input, &tokens, text, file);
    grammar::source_file(&mut p);
    let (green, parse_errors) = p.finish();
    errors.extend(parse_errors);
    errors.sort_by_key(|e| (e.range.start(), e.range.end()));
    // A stray character gets one error from the lexer; the parser's
    // complaint about the same token adds nothing.
    errors.dedup_by(|later, first| first.severity == Severity::Error && later.range.start() == first.range.start());
    Parse { green, errors: errors.into(), file }
}

/// An indented dump of a tree: one line per node or token, with ranges.
pub fn debug_tree(node: &SyntaxNode) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let mut indent = 0usize;
    for event in node.preorder_with_tokens() {
        match event {
            rowan::WalkEvent::Enter(el) => {
                let r = el.text_range();
                let _ = write!(out, "{:indent$}{:?}@{}..{}", "", el.kind(), u32::from(r.start()), u32::from(r.end()));
                if let rowan::NodeOrToken::Token(t) = &el {
                    let _ = write!(out, " {:?}", t.text());
                }
                out.push('\n');
                if el.as_node().is_some() {
                    indent += 2;
                }
            }
            rowan::WalkEvent::Leave(el) => {
                if el.as_node().is_some() {
                    indent -= 2;
                }
            }
        }
    }
    out
}
