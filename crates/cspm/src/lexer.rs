//! The CSPm lexer: the whole text as a sequence of tokens, trivia included,
//! so that the tree built from them is lossless. Lexical errors become
//! `ERROR_TOKEN`s and diagnostics; the lexer never fails.

use crate::kinds::{SyntaxKind, KEYWORDS, PUNCT};
use crate::{Code, Diagnostic, TextRange};
use SyntaxKind::*;

/// One token: its kind and byte range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Token {
    pub kind: SyntaxKind,
    pub start: u32,
    pub len: u32,
}

impl Token {
    pub fn range(&self) -> TextRange {
        TextRange::new(self.start.into(), (self.start + self.len).into())
    }
}

/// Splits `text` into tokens, reporting lexical errors into `errors`.
pub(crate) fn lex(text: &str, errors: &mut Vec<Diagnostic>) -> Vec<Token> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0usize;
    // Whether only whitespace precedes `i` on its line (for `include`/`print`).
    while i < b.len() {
        let start = i;
        let c = b[i];
        let kind = if c.is_ascii_whitespace() {
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            WHITESPACE
        } else if b[i..].starts_with(b"--") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            LINE_COMMENT
        } else if b[i..].starts_with(b"{-") {
            let mut depth = 0u32;
            loop {
                if i >= b.len() {
                    errors.push(Diagnostic::error(
                        Code::Lex,
                        TextRange::new((start as u32).into(), (start as u32 + 2).into()),
                        "unterminated block comment: expected `-}`",
                    ));
                    break;
                }
                if b[i..].starts_with(b"{-") {
                    depth += 1;
                    i += 2;
                } else if b[i..].starts_with(b"-}") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            BLOCK_COMMENT
        } else if c.is_ascii_alphabetic() {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            while i < b.len() && b[i] == b'\'' {
                i += 1;
            }
            let word = &text[start..i];
            if (word == "include" || word == "print") && i < b.len() && (b[i] == b' ' || b[i] == b'\t') {
                while i < b.len() && b[i] != b'\n' && b[i] != b'\r' {
                    i += 1;
                }
                if word == "include" {
                    INCLUDE_LINE
                } else {
                    PRINT_LINE
                }
            } else {
                KEYWORDS.iter().find(|(k, _)| *k == word).map_or(IDENT, |(_, kind)| *kind)
            }
        } else if c.is_ascii_digit() {
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            INT
        } else if c == b'"' || c == b'\'' {
            i += 1;
            let mut closed = false;
            while i < b.len() && b[i] != b'\n' {
                if b[i] == b'\\' {
                    i = (i + 2).min(b.len());
                    continue;
                }
                if b[i] == c {
                    i += 1;
                    closed = true;
                    break;
                }
                i += 1;
                if c == b'\'' && i - start > 2 {
                    break;
                }
            }
            if !closed {
                i = char_boundary(text, i);
                errors.push(Diagnostic::error(
                    Code::Lex,
                    range(start, i),
                    if c == b'"' { "unterminated string literal" } else { "malformed character literal" },
                ));
                ERROR_TOKEN
            } else if c == b'"' {
                STRING
            } else {
                CHAR
            }
        } else if let Some(kind) = punct(&b[i..]) {
            i += kind.text().map_or(1, str::len);
            kind
        } else {
            i = char_boundary(text, i + 1);
            errors.push(Diagnostic::error(
                Code::Lex,
                range(start, i),
                format!("unexpected character {:?}", &text[start..i]),
            ));
            ERROR_TOKEN
        };
        out.push(Token { kind, start: start as u32, len: (i - start) as u32 });
    }
    out
}

fn range(a: usize, b: usize) -> TextRange {
    TextRange::new((a as u32).into(), (b as u32).into())
}

fn char_boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i += 1;
    }
    i
}

fn punct(rest: &[u8]) -> Option<SyntaxKind> {
    for &(text, kind) in PUNCT {
        if rest.starts_with(text.as_bytes()) {
            // `(|` opens a map only before a space (as in libcspm), so that
            // `(|~| …)` and `(||| …)` lex as a parenthesis.
            if kind == L_MAP && !rest.get(2).is_some_and(u8::is_ascii_whitespace) {
                continue;
            }
            // `-->` cannot happen (comment); `->` is the arrow.
            return Some(kind);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(SyntaxKind, &str)> {
        let mut errors = Vec::new();
        lex(text, &mut errors)
            .into_iter()
            .filter(|t| t.kind != WHITESPACE)
            .map(|t| (t.kind, &text[t.start as usize..(t.start + t.len) as usize]))
            .collect()
    }

    #[test]
    fn operators_take_the_longest_spelling() {
        assert_eq!(
            kinds("[] [[ [| |] |~| ||| || |> [FD= <-> <- (|~| a)"),
            vec![
                (EXT_CHOICE, "[]"),
                (L_RENAME, "[["),
                (L_PAR, "[|"),
                (R_PAR, "|]"),
                (INT_CHOICE, "|~|"),
                (INTERLEAVE, "|||"),
                (PARALLEL, "||"),
                (EXC_CLOSE, "|>"),
                (REFINES_FD, "[FD="),
                (TIE, "<->"),
                (DRAWN, "<-"),
                (L_PAREN, "("),
                (INT_CHOICE, "|~|"),
                (IDENT, "a"),
                (R_PAREN, ")"),
            ]
        );
    }

    #[test]
    fn comments_names_and_bad_input() {
        assert_eq!(
            kinds("P' -- c\n{- a {- b -} -} x_1 'c' \"s\" é"),
            vec![
                (IDENT, "P'"),
                (LINE_COMMENT, "-- c"),
                (BLOCK_COMMENT, "{- a {- b -} -}"),
                (IDENT, "x_1"),
                (CHAR, "'c'"),
                (STRING, "\"s\""),
                (ERROR_TOKEN, "é"),
            ]
        );
        for text in ["\"abc", "{- x", "'", "'ab", "é", "\u{1}"] {
            let mut errors = Vec::new();
            let toks = lex(text, &mut errors);
            assert!(!errors.is_empty(), "{text:?}");
            assert_eq!(toks.iter().map(|t| t.len).sum::<u32>() as usize, text.len());
        }
    }
}
