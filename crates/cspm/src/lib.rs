//! CSPm, the machine-readable CSP of FDR, as found in the `csp … csp-begin
//! … csp-end` blocks of RoboChart/RoboSim assertion files and in whole
//! `.csp` files.
//!
//! - [`parse`]: a lossless, error-recovering parser (rowan tree) following
//!   FDR's layout rule and libcspm's precedences.
//! - [`Module::check`]: lowering, name resolution and checks, with
//!   diagnostics that carry byte ranges and stable [`Code`]s.
//! - [`Evaluator`]: values (integers, booleans, sets, sequences, tuples,
//!   datatypes, channels with dotted values, functions, lambdas, `let`) and
//!   processes, compiled by CSP's operational semantics into an explicit
//!   [`Lts`] with named events, including FDR's `Timed(f) { … }` sections.
//!
//! Every evaluation is bounded ([`Limits`]) and cancellable; no input makes
//! it panic. Names the text does not define (a model's channels and
//! constants) can be supplied through [`NameLookup`].

mod ast;
mod builtins;
mod dotted;
mod eval;
mod grammar;
mod kinds;
mod lexer;
mod lts;
mod parser;
mod proc;
mod proc_eval;
mod resolve;
mod stack;
mod typeck;
mod value;

pub use ast::Module;
pub use eval::{Evaluator, Limits};
pub use kinds::{CspmLanguage, SyntaxKind, SyntaxNode, SyntaxToken};
pub use lts::{Label, Lts};
pub use resolve::{BuildLts, ExternalName, NameLookup, NoNames};
pub use rowan::{TextRange, TextSize};
pub use value::Value;

/// Stable codes of diagnostics (shown as `CSP-…`; tests and clients may
/// rely on them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Code {
    /// A lexical error: an unknown character, an unterminated comment or literal.
    Lex,
    /// A syntax error.
    Syntax,
    /// A construct this engine parses but does not support (yet).
    Unsupported,
    /// A name that is not defined.
    Unresolved,
    /// A name defined twice in the same scope.
    Duplicate,
    /// An expression where a pattern is required, or a malformed definition.
    BadPattern,
    /// A type error: a value of the wrong kind for an operation.
    Type,
    /// A run-time error: division by zero, no matching clause, `head(<>)`, `error(…)`.
    Runtime,
    /// A bound of [`Limits`] was reached (depth, set size, states, time).
    Limit,
    /// The evaluation was cancelled.
    Cancelled,
}

impl Code {
    /// The stable spelling, e.g. `CSP-P01`.
    pub fn as_str(self) -> &'static str {
        match self {
            Code::Lex => "CSP-L01",
            Code::Syntax => "CSP-P01",
            Code::Unsupported => "CSP-U01",
            Code::Unresolved => "CSP-N01",
            Code::Duplicate => "CSP-N02",
            Code::BadPattern => "CSP-N03",
            Code::Type => "CSP-T01",
            Code::Runtime => "CSP-E01",
            Code::Limit => "CSP-E02",
            Code::Cancelled => "CSP-E03",
        }
    }
}

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Severity {
    /// The text is not valid CSPm (or cannot be evaluated).
    Error,
    /// Valid, but suspicious.
    Warning,
}

/// A message about a byte range of the text.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// Its stable code.
    pub code: Code,
    /// How serious it is.
    pub severity: Severity,
    /// The bytes it is about.
    pub range: TextRange,
    /// The message, one sentence.
    pub message: String,
}

impl Diagnostic {
    pub(crate) fn error(code: Code, range: TextRange, message: impl Into<String>) -> Diagnostic {
        Diagnostic { code, severity: Severity::Error, range, message: message.into() }
    }
}

impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {:?}: {}", self.code.as_str(), self.range, self.message)
    }
}

/// The result of [`parse`]: a lossless tree and the syntax errors.
#[derive(Clone, Debug)]
pub struct Parse {
    green: rowan::GreenNode,
    errors: Vec<Diagnostic>,
}

impl Parse {
    /// The root of the tree (a `SOURCE_FILE`).
    pub fn syntax_node(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.green.clone())
    }

    /// Lexical and syntax errors, in text order.
    pub fn errors(&self) -> &[Diagnostic] {
        &self.errors
    }

    /// The tree and the errors as text, for snapshot tests.
    pub fn debug_dump(&self) -> String {
        let mut out = format!("{:#?}", self.syntax_node());
        for e in &self.errors {
            out.push_str(&format!("{e}\n"));
        }
        out
    }
}

/// Parses a CSPm text (a whole `.csp` file or the inside of a `csp` block).
pub fn parse(text: &str) -> Parse {
    let mut errors = Vec::new();
    // Offsets are `u32`: a longer text is cut (never happens in practice).
    let text = if text.len() > u32::MAX as usize / 2 { &text[..0] } else { text };
    let tokens = lexer::lex(text, &mut errors);
    let mut p = parser::Parser::new(text, &tokens);
    grammar::source_file(&mut p);
    let (green, mut syntax) = p.finish();
    errors.append(&mut syntax);
    errors.sort_by_key(|e| e.range.start());
    Parse { green, errors }
}
