//! The lexer: text → tokens (kind + length), lossless. Never fails: stray
//! characters become `ERROR_TOKEN`s and problems are reported as errors next
//! to the token stream.

use crate::parser::Input;
use crate::tree_builder::word as word_at;
use crate::{FileKind, SyntaxError, SyntaxKind, TextRange, TextSize};
use SyntaxKind::*;

/// One lexed token: its kind and its length in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    /// The kind of the token.
    pub kind: SyntaxKind,
    /// Its length in bytes (never zero).
    pub len: TextSize,
}

/// Splits `text` into tokens for a file of kind `file`. The lengths add up to
/// `text.len()`.
pub fn lex(text: &str, file: FileKind) -> (Vec<Token>, Vec<SyntaxError>) {
    let mut lx = Lexer::<false>::new(text, file);
    lx.run();
    (lx.tokens, lx.errors)
}

/// The tokens and errors, plus the parser's view of the non-trivia tokens,
/// collected in the same pass (a second pass over the tokens costs more).
pub(crate) fn lex_for_parser(text: &str, file: FileKind) -> (Vec<Token>, Vec<SyntaxError>, Input) {
    let mut lx = Lexer::<true>::new(text, file);
    lx.run();
    let input = Input::from_parts(lx.kinds, TextSize::of(text));
    (lx.tokens, lx.errors, input)
}

/// `INPUT`: whether to also collect the kinds of non-trivia
/// tokens for the parser.
struct Lexer<'a, const INPUT: bool> {
    src: &'a [u8],
    text: &'a str,
    pos: usize,
    file: FileKind,
    tokens: Vec<Token>,
    errors: Vec<SyntaxError>,
    kinds: Vec<SyntaxKind>,
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_ident_continue(b: u8) -> bool {
    IDENT_CONTINUE[usize::from(b)]
}

/// `is_ident_continue` as a table: the lexer's hottest test.
const IDENT_CONTINUE: [bool; 256] = {
    let mut t = [false; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = (b as u8).is_ascii_alphanumeric() || b as u8 == b'_';
        b += 1;
    }
    t
};

const fn is_whitespace(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n')
}

/// What a token's first byte says about it, for the lexer's dispatch.
#[derive(Clone, Copy)]
enum First {
    Space,
    /// A word (`is_ident_start`).
    Letter,
    /// An operator that cannot start a comment (all but `/` and `^`).
    Punct,
    Other,
}

const FIRST_BYTE: [First; 256] = {
    let mut t = [First::Other; 256];
    let mut b = 0;
    while b < 256 {
        let c = b as u8;
        t[b] = if is_whitespace(c) {
            First::Space
        } else if c.is_ascii_alphabetic() || c == b'_' {
            First::Letter
        } else if c.is_ascii_punctuation() && !matches!(c, b'/' | b'^' | b'"' | b'\'' | b'_') {
            First::Punct
        } else {
            First::Other
        };
        b += 1;
    }
    t
};

impl<'a, const INPUT: bool> Lexer<'a, INPUT> {
    fn new(text: &'a str, file: FileKind) -> Self {
        // Real models have two and a half to four bytes per token
        // (whitespace included), and four or more per non-trivia token;
        // sizing once avoids regrowing (copying) large vectors.
        let n = text.len() / 2 + 16;
        let m = if INPUT { text.len() / 3 + 16 } else { 0 };
        Lexer {
            src: text.as_bytes(),
            text,
            pos: 0,
            file,
            tokens: Vec::with_capacity(n),
            errors: Vec::new(),
            kinds: Vec::with_capacity(m),
        }
    }

    fn at(&self, off: usize) -> u8 {
        self.src.get(self.pos + off).copied().unwrap_or(0)
    }

    fn rest(&self) -> &[u8] {
        &self.src[self.pos..]
    }

    /// The number of bytes from `from` on that satisfy `pred`.
    fn run_len(&self, from: usize, pred: impl Fn(u8) -> bool) -> usize {
        let mut i = from;
        while i < self.src.len() && pred(self.src[i]) {
            i += 1;
        }
        i - from
    }

    // Called for every token: not inlining it costs more than the copies.
    #[inline(always)]
    fn push(&mut self, kind: SyntaxKind, len: usize) {
        debug_assert!(len > 0);
        self.tokens.push(Token { kind, len: TextSize::from(len as u32) });
        if INPUT && !kind.is_trivia() {
            self.kinds.push(kind);
        }
        self.pos += len;
    }

    fn range(&self, start: usize, len: usize) -> TextRange {
        TextRange::at(TextSize::from(start as u32), TextSize::from(len as u32))
    }

    fn error(&mut self, start: usize, len: usize, message: impl Into<String>) {
        let range = self.range(start, len);
        self.errors.push(SyntaxError::error(message, range));
    }

    fn warning(&mut self, start: usize, len: usize, message: impl Into<String>) {
        let range = self.range(start, len);
        self.errors.push(SyntaxError::compat_warning(message, range));
    }

    fn is_assertion_file(&self) -> bool {
        matches!(self.file, FileKind::Assertions | FileKind::SimAssertions)
    }

    fn run(&mut self) {
        while let Some(&b) = self.src.get(self.pos) {
            let start = self.pos;
            // The common tokens by a table of the first byte; `token`
            // handles everything.
            match FIRST_BYTE[usize::from(b)] {
                First::Space => {
                    // The first byte is known: scanning starts after it.
                    let n = 1 + self.run_len(start + 1, is_whitespace);
                    self.push(WHITESPACE, n);
                }
                First::Letter => self.word(),
                First::Punct => self.punct(start),
                First::Other => self.token(),
            }
            debug_assert!(self.pos > start, "lexer made no progress");
        }
    }

    fn token(&mut self) {
        let b = self.at(0);
        let start = self.pos;
        match b {
            b' ' | b'\t' | b'\r' | b'\n' => {
                let n = self.run_len(self.pos, is_whitespace);
                self.push(WHITESPACE, n);
            }
            b'/' if self.at(1) == b'/' => {
                let n = self.rest().iter().take_while(|&&c| c != b'\n').count();
                let n = if self.at(n) == b'\n' { n + 1 } else { n };
                self.push(LINE_COMMENT, n);
            }
            b'/' if self.at(1) == b'*' => self.block_comment(),
            b'"' | b'\'' => self.string(b),
            b'0'..=b'9' => self.number(),
            b'^' if is_ident_start(self.at(1)) => {
                let n = 1 + self.run_len(self.pos + 1, is_ident_continue);
                self.push(IDENT, n);
            }
            _ if is_ident_start(b) => self.word(),
            _ if b.is_ascii_graphic() => self.punct(start),
            _ => self.stray(),
        }
    }

    fn block_comment(&mut self) {
        let start = self.pos;
        match find(&self.src[start + 2..], b"*/") {
            Some(i) => self.push(BLOCK_COMMENT, 2 + i + 2),
            None => {
                // Recovery: end the comment at the end of its first line, so
                // the rest of the file keeps its structure while the user
                // is still typing the closing `*/`.
                let line = self.rest().iter().take_while(|&&c| c != b'\n').count();
                self.error(start, 2, "unterminated block comment: expected `*/`");
                self.push(BLOCK_COMMENT, line);
            }
        }
    }

    fn string(&mut self, quote: u8) {
        let start = self.pos;
        let bytes = self.rest();
        let mut i = 1;
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 2,
                c if c == quote => {
                    let len = i + 1;
                    self.check_escapes(start, len);
                    self.push(STRING, len);
                    return;
                }
                _ => i += 1,
            }
        }
        // Unterminated: same recovery as block comments (end of first line).
        let line = bytes.iter().take_while(|&&c| c != b'\n').count();
        let q = quote as char;
        self.error(start, 1, format!("unterminated string: expected a closing {q}"));
        self.push(STRING, line.max(1));
    }

    fn check_escapes(&mut self, start: usize, len: usize) {
        let bytes = &self.src[start..start + len];
        let mut i = 1;
        let mut bad = Vec::new();
        while i + 1 < len {
            if bytes[i] == b'\\' {
                let ok = match bytes[i + 1] {
                    b'b' | b't' | b'n' | b'f' | b'r' | b'"' | b'\'' | b'\\' => true,
                    b'u' => bytes.get(i + 2..i + 6).is_some_and(|h| h.iter().all(u8::is_ascii_hexdigit)),
                    _ => false,
                };
                if !ok {
                    bad.push(start + i);
                }
                i += 2;
            } else {
                i += 1;
            }
        }
        for off in bad {
            let clen = self.text[off + 1..].chars().next().map_or(0, char::len_utf8);
            self.error(
                off,
                1 + clen,
                "invalid escape sequence in string: use \\b \\t \\n \\f \\r \\\" \\' \\\\ or \\uXXXX",
            );
        }
    }

    fn number(&mut self) {
        let start = self.pos;
        let digits = self.run_len(start, |b| b.is_ascii_digit());
        if self.at(digits) == b'.' && self.at(digits + 1).is_ascii_digit() {
            let frac = self.src[start + digits + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
            self.push(FLOAT_NUMBER, digits + 1 + frac);
            return;
        }
        if self.at(digits) == b'.' {
            self.warning(
                start,
                digits + 1,
                format!(
                    "RoboTool's lexer rejects a number directly followed by `.`: write `{} .` with a space",
                    &self.text[start..start + digits]
                ),
            );
        }
        if self.text[start..start + digits].trim_start_matches('0').len() > 10
            || self.text[start..start + digits].parse::<u64>().is_ok_and(|v| v > i32::MAX as u64)
        {
            self.error(
                start,
                digits,
                "integer literal is too large: RoboTool reads integers as 32-bit (at most 2147483647)",
            );
        }
        self.push(INT_NUMBER, digits);
    }

    fn word(&mut self) {
        let start = self.pos;
        // Called at a letter: scanning starts after it.
        let n = 1 + self.run_len(start + 1, is_ident_continue);
        let (w0, w1) = match n {
            1..=8 => (word_at(self.src, start, n), 0),
            9..=16 => (word_at(self.src, start, 8), word_at(self.src, start + 8, n - 8)),
            _ => (0, 0),
        };
        // `Set(` and `Seq(`, compared as packed words.
        const SET: u64 = u64::from_le_bytes(*b"Set\0\0\0\0\0");
        const SEQ: u64 = u64::from_le_bytes(*b"Seq\0\0\0\0\0");
        if (w0 == SET || w0 == SEQ) && self.at(n) == b'(' {
            self.push(if w0 == SET { SET_OPEN } else { SEQ_OPEN }, n + 1);
            return;
        }
        if self.is_assertion_file() && self.assertion_word(&self.text[start..start + n], n) {
            return;
        }
        let kind = match n {
            1..=16 => SyntaxKind::keyword_packed(w0, w1, self.file),
            _ => None,
        };
        self.push(kind.unwrap_or(IDENT), n);
    }

    /// Hyphenated words, multi-word model tokens and CSP blocks of the
    /// assertion languages. Returns whether a token was pushed.
    fn assertion_word(&mut self, word: &str, n: usize) -> bool {
        let after = &self.src[self.pos + n..];
        let hyphen = |suffix: &[u8]| {
            after.starts_with(suffix) && !after.get(suffix.len()).copied().is_some_and(is_ident_continue)
        };
        match word {
            "deadlock" if hyphen(b"-free") => {
                self.push(DEADLOCK_FREE_KW, n + 5);
                true
            }
            "divergence" if hyphen(b"-free") => {
                self.push(DIVERGENCE_FREE_KW, n + 5);
                true
            }
            "timelock" if hyphen(b"-free") => {
                self.push(TIMELOCK_FREE_KW, n + 5);
                true
            }
            "csp" if hyphen(b"-begin") => {
                self.csp_block();
                true
            }
            "failures" => {
                let start = self.pos;
                if let Some(len) = self.phrase(n, &["divergences", "model"]) {
                    self.push(FAILURES_DIVERGENCES_MODEL_KW, len);
                    self.check_phrase_spacing(start, len);
                    true
                } else if let Some(len) = self.phrase(n, &["model"]) {
                    self.push(FAILURES_MODEL_KW, len);
                    self.check_phrase_spacing(start, len);
                    true
                } else {
                    false
                }
            }
            "traces" => {
                let start = self.pos;
                match self.phrase(n, &["model"]) {
                    Some(len) => {
                        self.push(TRACES_MODEL_KW, len);
                        self.check_phrase_spacing(start, len);
                        true
                    }
                    None => false,
                }
            }
            "tick" if hyphen(b"-tock") => {
                let start = self.pos;
                match self.phrase(n + 5, &["model"]) {
                    Some(len) => {
                        self.push(TICK_TOCK_MODEL_KW, len);
                        self.check_phrase_spacing(start, len);
                        true
                    }
                    None => false,
                }
            }
            _ => false,
        }
    }

    /// Matches `([ \t]+ word)*` after `first` bytes; returns the total length.
    fn phrase(&self, first: usize, words: &[&str]) -> Option<usize> {
        let mut i = self.pos + first;
        for w in words {
            let ws = self.src[i..].iter().take_while(|&&c| c == b' ' || c == b'\t').count();
            if ws == 0 || !self.src[i + ws..].starts_with(w.as_bytes()) {
                return None;
            }
            i += ws + w.len();
            if self.src.get(i).copied().is_some_and(is_ident_continue) {
                return None;
            }
        }
        Some(i - self.pos)
    }

    fn check_phrase_spacing(&mut self, start: usize, len: usize) {
        let text = &self.text[start..start + len];
        let canonical: Vec<&str> = text.split([' ', '\t']).filter(|s| !s.is_empty()).collect();
        let canonical = canonical.join(" ");
        if canonical != text {
            self.warning(
                start,
                len,
                format!("RoboTool only accepts exactly one space between the words: write `{canonical}`"),
            );
        }
    }

    fn csp_block(&mut self) {
        let start = self.pos;
        let body = start + "csp-begin".len();
        match find(&self.src[body..], b"csp-end") {
            Some(i) => self.push(CSP_TEXT, body - start + i + "csp-end".len()),
            None => {
                self.error(start, "csp-begin".len(), "unterminated CSP block: expected `csp-end`");
                self.push(CSP_TEXT, self.src.len() - start);
            }
        }
    }

    fn punct(&mut self, start: usize) {
        let (b0, b1, b2) = (self.at(0), self.at(1), self.at(2));
        // Longest match first (§1.5).
        let (kind, len) = match (b0, b1) {
            (b':', b':') if b2 == b'*' => (COLON2_STAR, 3),
            (b':', b':') => (COLON2, 2),
            (b':', _) => (COLON, 1),
            (b'<', b'-') if b2 == b'>' => (REL_ARROW, 3),
            (b'<', b'-') => {
                // Hazard 5: RoboTool's lexer fails here; we read `<` `-` and say so.
                self.error(
                    start,
                    2,
                    "`<-` is not a token: write `< -` (with a space) for a comparison with a negative number",
                );
                (LT, 1)
            }
            (b'<', b'{') => (DEADLINE_OPEN, 2),
            (b'<', b'=') => (LTEQ, 2),
            (b'<', _) => (LT, 1),
            (b'(', b'|') => (L_PAREN_PIPE, 2),
            (b'(', _) => (L_PAREN, 1),
            (b'[', b'|') => (L_BRACK_PIPE, 2),
            (b'[', _) => (L_BRACK, 1),
            (b'|', b')') => (R_PAREN_PIPE, 2),
            (b'|', b']') => (R_BRACK_PIPE, 2),
            (b'|', _) => (PIPE, 1),
            (b'=', b'=') => (EQ2, 2),
            (b'=', b'>') => (IMPLIES, 2),
            (b'=', _) => (EQ, 1),
            (b'!', b'=') => (NEQ, 2),
            (b'!', _) => (BANG, 1),
            (b'>', b'=') => (GTEQ, 2),
            (b'>', _) => (GT, 1),
            (b'/', b'\\') => (AND, 2),
            (b'/', _) => (SLASH, 1),
            (b'\\', b'/') => (OR, 2),
            (b'-', b'>') => (ARROW, 2),
            (b'-', _) => (MINUS, 1),
            (b'{', _) => (L_CURLY, 1),
            (b'}', _) => (R_CURLY, 1),
            (b')', _) => (R_PAREN, 1),
            (b']', _) => (R_BRACK, 1),
            (b',', _) => (COMMA, 1),
            (b';', _) => (SEMI, 1),
            (b'@', _) => (AT, 1),
            (b'#', _) => (HASH, 1),
            (b'?', _) => (QUESTION, 1),
            (b'.', _) => (DOT, 1),
            (b'+', _) => (PLUS, 1),
            (b'*', _) => (STAR, 1),
            (b'%', _) => (PERCENT, 1),
            (b'^', _) => (CARET, 1),
            (b'$', _) if self.dollar_is_token() => (DOLLAR, 1),
            _ => return self.stray(),
        };
        self.push(kind, len);
    }

    /// A run of characters that mean nothing here becomes one error token.
    fn stray(&mut self) {
        let start = self.pos;
        let mut end = start;
        for (i, c) in self.text[start..].char_indices() {
            let stray = !c.is_ascii()
                || (c.is_ascii_control() && !is_whitespace(c as u8))
                || matches!(c, '\\' | '$' | '`' | '~' | '&');
            if !stray {
                break;
            }
            // `\/` and (in RoboSim) `$` are tokens: stop before them.
            if i > 0 && (self.text[start + i..].starts_with("\\/") || (c == '$' && self.dollar_is_token())) {
                break;
            }
            end = start + i + c.len_utf8();
            if i == 0 && c == '\\' {
                break;
            }
        }
        let len = (end - start).max(1);
        let shown: String = self.text[start..start + len].chars().take(8).flat_map(char::escape_default).collect();
        let msg = if self.text[start..].starts_with('$') {
            "`$` is only used in RoboSim files (.rst, .rsa)".to_string()
        } else {
            format!("unexpected character `{shown}`: only ASCII letters, digits and operators are allowed outside strings and comments")
        };
        self.error(start, len, msg);
        self.push(ERROR_TOKEN, len);
    }

    fn dollar_is_token(&self) -> bool {
        matches!(self.file, FileKind::RoboSim | FileKind::SimAssertions)
    }
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str, file: FileKind) -> Vec<(SyntaxKind, &str)> {
        let (toks, _) = lex(text, file);
        let mut off = 0usize;
        toks.iter()
            .map(|t| {
                let s = &text[off..off + u32::from(t.len) as usize];
                off += u32::from(t.len) as usize;
                (t.kind, s)
            })
            .filter(|(k, _)| *k != WHITESPACE)
            .collect()
    }

    #[test]
    fn lengths_cover_input() {
        for text in ["", "a", "/* x", "\"abc", "csp-begin x", "é", "\u{1}\u{2}", "1.", "s^t", "<-1"] {
            for file in [FileKind::RoboChart, FileKind::RoboSim, FileKind::Assertions, FileKind::SimAssertions] {
                let (toks, _) = lex(text, file);
                let total: u32 = toks.iter().map(|t| u32::from(t.len)).sum();
                assert_eq!(total as usize, text.len(), "{text:?}");
            }
        }
    }

    #[test]
    fn hazards() {
        use FileKind::*;
        assert_eq!(kinds("s^t", RoboChart), vec![(IDENT, "s"), (IDENT, "^t")]);
        assert_eq!(kinds("s ^ t", RoboChart), vec![(IDENT, "s"), (CARET, "^"), (IDENT, "t")]);
        assert_eq!(kinds("Set(int)", RoboChart)[0], (SET_OPEN, "Set("));
        assert_eq!(kinds("Set (int)", RoboChart)[0], (IDENT, "Set"));
        assert_eq!(kinds("a<{1}", RoboChart)[1], (DEADLINE_OPEN, "<{"));
        assert_eq!(kinds("import a::b::*", RoboChart).last(), Some(&(COLON2_STAR, "::*")));
        assert_eq!(kinds("1.5", RoboChart), vec![(FLOAT_NUMBER, "1.5")]);
        assert_eq!(kinds("1.x", RoboChart), vec![(INT_NUMBER, "1"), (DOT, "."), (IDENT, "x")]);
        assert_eq!(kinds("true", RoboChart), vec![(TRUE_KW, "true")]);
        assert_eq!(kinds("^true", RoboChart), vec![(IDENT, "^true")]);
        assert_eq!(
            kinds("in the failures divergences model", Assertions)[2],
            (FAILURES_DIVERGENCES_MODEL_KW, "failures divergences model")
        );
        assert_eq!(kinds("failures : x", Assertions)[0], (IDENT, "failures"));
        assert_eq!(kinds("tick-tock model", SimAssertions), vec![(TICK_TOCK_MODEL_KW, "tick-tock model")]);
        assert_eq!(kinds("x is deadlock-free", RoboChart)[2], (IDENT, "deadlock"));
        assert_eq!(kinds("x is deadlock-free", Assertions)[2], (DEADLOCK_FREE_KW, "deadlock-free"));
        assert_eq!(
            kinds("csp-begin A = STOP -- csp-end\ncsp-end x", Assertions),
            vec![
                (CSP_TEXT, "csp-begin A = STOP -- csp-end"),
                (WHITESPACE, "\n"),
                (CSP_KW, "csp"),
                (MINUS, "-"),
                (END_KW, "end"),
                (IDENT, "x")
            ]
            .into_iter()
            .filter(|(k, _)| *k != WHITESPACE)
            .collect::<Vec<_>>()
        );
        assert_eq!(kinds("// csp-begin\nx", Assertions)[0].0, LINE_COMMENT);
        assert_eq!(kinds("$ e", RoboSim)[0], (DOLLAR, "$"));
        assert_eq!(kinds("(|a|)", RoboChart)[0], (L_PAREN_PIPE, "(|"));
    }

    #[test]
    fn errors_and_warnings() {
        let (_, e) = lex("a<-1", FileKind::RoboChart);
        assert_eq!(e.len(), 1);
        assert!(e[0].message.contains("`<-`"));
        let (_, e) = lex("set to 3.\n", FileKind::Assertions);
        assert_eq!(e[0].severity, crate::Severity::Warning);
        let (_, e) = lex("failures  model", FileKind::Assertions);
        assert_eq!(e[0].severity, crate::Severity::Warning);
        let (t, e) = lex("/* x\ny", FileKind::RoboChart);
        assert_eq!(e[0].range, TextRange::new(0.into(), 2.into()));
        assert_eq!(t.last().unwrap().kind, IDENT);
        let (_, e) = lex("\"a\\qb\"", FileKind::RoboChart);
        assert_eq!(e.len(), 1);
        let (t, e) = lex("é€ x", FileKind::RoboChart);
        assert_eq!(e.len(), 1);
        assert_eq!(t[0].kind, ERROR_TOKEN);
        assert_eq!(u32::from(t[0].len), 5);
    }
}
