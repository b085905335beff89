//! The canonical formatter for RoboChart (`.rct`), RoboSim (`.rst`) and
//! their assertion files (`.assertions`, `.rsa`).
//!
//! [`format()`] changes only whitespace: spaces, tabs and line breaks between
//! tokens. Every other token and every comment keeps its text and its place
//! in the token order; a final check re-lexes the output and refuses to
//! return anything else. Formatting is idempotent: formatting the output
//! again gives the same text. A file with a syntax error is not formatted
//! at all ([`FormatError::Syntax`]), so an editor never rewrites a file
//! while it is being typed. Compatibility warnings (`SYN-02`) do not block
//! formatting.
//!
//! # The canonical style
//!
//! It is the layout of RoboTool's own models, made regular:
//!
//! - **Blocks.** `{` ends the header line. Members come one per line,
//!   indented one level (four spaces by default, see [`Options`]), and `}`
//!   goes on a line of its own. A block stays on one line — `state S { entry
//!   x = 1 }`, `transition t { from a to b condition c }`, `enumeration E {
//!   A B C }` — only if the author wrote it on one line, it has at most one
//!   member (transitions and enumerations may have any number of clauses or
//!   literals), it contains no comment and it fits in
//!   [`Options::max_width`]. An empty body is always `{ }`.
//! - **Transitions**, when expanded, put `from a to b` on the first line and
//!   then each clause on its own line: the trigger (or `exec` or
//!   `probability`), the clock resets (together), the deadline, the
//!   condition and the action.
//! - **Blank lines** between members and between top-level items are kept,
//!   at most one in a row; blank lines anywhere else (after `{`, before `}`,
//!   inside a declaration or statement) are removed.
//! - **Spacing** within a line follows the examples of the language
//!   reference: `x : T`, `a = b`, `a + b`, `f(a, b)`, `s[i]`, `r.f`,
//!   `a::b`, `e?x`, `e!v`, `e.v`, `$e`, `#C`, `-x`, `{1, 2}`, `<1, 2>`,
//!   `(| a, b |)`, `[| 1, 2 |]`, `<{ 1 }`, `( _async )`, `[ mult ]`,
//!   `op() [terminates]`, `s1; s2`. Where gluing two tokens would change how
//!   they lex, a space is kept (`s ^ t`, `set to 1 .`, `Set (x)`, `< -1`).
//! - **Long lines** are not re-wrapped. Inside a declaration, statement,
//!   expression or assertion, a line break the author wrote is kept only
//!   at these places: after `,` `;` `=` `@` an opening bracket, a binary
//!   operator, `then` or `else`; before a closing bracket, a binary operator,
//!   `@` `<{` `then` `else` `end`; around the `|` of binders; and, in
//!   assertion files, before `with`, `and`, `in the …`, `associated to` and
//!   the CSP text. Other line breaks are removed. A continuation line is
//!   indented one level deeper than the line that opened the innermost
//!   bracket (or `if`) still open, or than the first line of the item. A
//!   closing bracket, `then`, `else` or `end` that starts a line lines up
//!   with the line that opened it. The CSP text and a block's `{` line up
//!   with their item.
//! - **Comments** stay where they are: a comment at the end of a line stays
//!   at the end of that line, a comment on a line of its own stays on a line
//!   of its own, indented like the code around it. Trailing spaces after a
//!   line comment are removed; the text of block comments, strings and
//!   `csp-begin … csp-end` blocks is never touched.
//! - **Files** end with exactly one line break, and use the line ending most
//!   of their lines use (LF or CRLF).

mod printer;
mod rules;

use std::fmt;

use robosim_syntax::{FileKind, Severity, SyntaxKind, TextRange};

/// Indentation unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Indent {
    /// One tab per level (RoboTool's Eclipse editor writes tabs).
    Tab,
    /// This many spaces per level (at most 16).
    Spaces(u8),
}

/// Formatting options.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// Indentation unit; four spaces by default, as in the examples of the
    /// language reference and this repository.
    pub indent: Indent,
    /// The widest line a one-line block may make (in characters, a tab
    /// counting as four). Wider blocks are expanded. Lines are never
    /// re-wrapped otherwise. 120 by default.
    pub max_width: usize,
}

impl Default for Options {
    fn default() -> Options {
        Options { indent: Indent::Spaces(4), max_width: 120 }
    }
}

/// Why a file was not formatted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FormatError {
    /// The file has a syntax error: the first one (by position).
    Syntax {
        /// 1-based line.
        line: u32,
        /// 1-based column, in characters.
        column: u32,
        /// The byte range of the error.
        range: TextRange,
        /// The parser's message.
        message: String,
    },
    /// The formatter would have changed more than whitespace. This is a bug;
    /// the file is left as it was.
    Internal(String),
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormatError::Syntax { line, column, message, .. } => write!(f, "{line}:{column}: {message}"),
            FormatError::Internal(msg) => write!(f, "internal formatter error, file left unchanged: {msg}"),
        }
    }
}

impl std::error::Error for FormatError {}

/// Formats `text`, a file of kind `kind`, in the canonical style (see the
/// crate documentation). Fails on a file with a syntax error; never panics.
pub fn format(text: &str, kind: FileKind, options: &Options) -> Result<String, FormatError> {
    let parse = robosim_syntax::parse(text, kind);
    if let Some(e) = parse.errors().iter().find(|e| e.severity == Severity::Error) {
        let (line, column) = line_col(text, usize::from(e.range.start()));
        return Err(FormatError::Syntax { line, column, range: e.range, message: e.message.clone() });
    }
    let root = parse.syntax_node();
    let out = printer::Printer::new(&root, text, kind, options).run();
    verify(text, &out, kind)?;
    Ok(out)
}

/// The 1-based line and character column of byte `offset`.
fn line_col(text: &str, offset: usize) -> (u32, u32) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[start..].chars().count() + 1;
    (line as u32, column as u32)
}

/// The tokens of `text` that formatting must keep: everything but
/// whitespace, with line comments compared without their line break and
/// trailing blanks.
fn kept_tokens(text: &str, kind: FileKind) -> Vec<(SyntaxKind, &str)> {
    let (tokens, _) = robosim_syntax::lexer::lex(text, kind);
    let mut out = Vec::with_capacity(tokens.len());
    let mut at = 0usize;
    for t in tokens {
        let len = usize::from(t.len);
        let s = text.get(at..at + len).unwrap_or("");
        at += len;
        match t.kind {
            SyntaxKind::WHITESPACE => {}
            SyntaxKind::LINE_COMMENT => out.push((t.kind, printer::line_comment_text(s))),
            k => out.push((k, s)),
        }
    }
    out
}

/// The safety net: the output must consist of the same tokens as the input
/// and parse without errors.
fn verify(input: &str, output: &str, kind: FileKind) -> Result<(), FormatError> {
    let before = kept_tokens(input, kind);
    let after = kept_tokens(output, kind);
    if before != after {
        let at = before.iter().zip(&after).position(|(a, b)| a != b).unwrap_or(before.len().min(after.len()));
        return Err(FormatError::Internal(format!(
            "the token sequence would change at token {at}: {:?} became {:?}",
            before.get(at),
            after.get(at)
        )));
    }
    let reparsed = robosim_syntax::parse(output, kind);
    if let Some(e) = reparsed.errors().iter().find(|e| e.severity == Severity::Error) {
        return Err(FormatError::Internal(format!("the output would not parse: {}", e.message)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(text: &str, kind: FileKind) -> String {
        format(text, kind, &Options::default()).unwrap()
    }

    #[test]
    fn syntax_errors_are_refused_with_position() {
        let err = format("stm M {\n  state S { entry x = 1; }\n}\n", FileKind::RoboChart, &Options::default());
        let Err(FormatError::Syntax { line, column, message, .. }) = err else { panic!("{err:?}") };
        assert_eq!((line, column), (2, 24));
        assert!(message.contains("`;` separates statements"), "{message}");
    }

    #[test]
    fn compatibility_warnings_do_not_block() {
        let out = fmt("assertion A : M is deadlock-free with constant k of M set to 3.", FileKind::Assertions);
        // The space that RoboTool's lexer needs is inserted.
        assert_eq!(out, "assertion A : M is deadlock-free with constant k of M set to 3 .\n");
    }

    #[test]
    fn empty_and_comment_only_files() {
        assert_eq!(fmt("", FileKind::RoboChart), "");
        assert_eq!(fmt(" \n\n\t", FileKind::RoboChart), "");
        assert_eq!(fmt("\n\n// c   \n\n\n/* d */", FileKind::RoboSim), "// c\n\n/* d */\n");
    }

    #[test]
    fn crlf_is_kept() {
        let out = fmt("interface I {\r\n  event e // x\r\n\r\n\r\n  event f }", FileKind::RoboChart);
        assert_eq!(out, "interface I {\r\n    event e // x\r\n\r\n    event f\r\n}\r\n");
    }

    #[test]
    fn tabs_and_width_options() {
        let opts = Options { indent: Indent::Tab, max_width: 20 };
        let out = format("stm M { state S { entry x = 1 } }", FileKind::RoboChart, &opts).unwrap();
        assert_eq!(out, "stm M {\n\tstate S {\n\t\tentry x = 1\n\t}\n}\n");
        let out = format("stm M {\n state S { entry x = 1 } }", FileKind::RoboChart, &Options::default()).unwrap();
        assert_eq!(out, "stm M {\n    state S { entry x = 1 }\n}\n");
    }

    #[test]
    fn line_col_counts_characters() {
        assert_eq!(line_col("é\nab", 4), (2, 2));
        assert_eq!(line_col("éa", 2), (1, 2));
        assert_eq!(line_col("ab", 99), (1, 3));
    }
}
