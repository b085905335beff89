//! Parser infrastructure (rust-analyzer style): the grammar functions see
//! only non-trivia tokens and open, complete, abandon or wrap nodes through
//! markers. The tree is built as they go: every consumed token is added to
//! the green tree together with the trivia before it, so the tree is
//! lossless by construction.

use std::cell::Cell;

use rowan::GreenNode;

use crate::lexer::Token;
use crate::tree_builder::{Saved, TreeBuilder};
use crate::{FileKind, SyntaxError, SyntaxKind, TextRange, TextSize};
use SyntaxKind::*;

/// Deepest nesting of guarded constructs (expressions, statements, types,
/// blocks). Deeper input gets one error and is skipped flat, so that neither
/// the parser nor anything walking the tree recursively can overflow.
pub(crate) const MAX_DEPTH: u32 = 384;

/// Safety valve against a grammar bug looping without progress: after this
/// many look-aheads without consuming a token the parser sees end of file.
const FUEL: u32 = 1_000_000;

/// The kinds of the non-trivia tokens the grammar works on. Their ranges,
/// rarely needed, come from the builder, which is at or before the current
/// token (see `TreeBuilder::range_ahead`).
pub(crate) struct Input {
    kinds: Vec<SyntaxKind>,
    text_len: TextSize,
}

impl Input {
    /// The kinds of the non-trivia tokens (see `lexer::lex_for_parser`).
    pub(crate) fn from_parts(kinds: Vec<SyntaxKind>, text_len: TextSize) -> Input {
        Input { kinds, text_len }
    }
}

/// A set of token kinds (all token kinds are below 256).
#[derive(Clone, Copy)]
pub(crate) struct TokenSet([u64; 4]);

impl TokenSet {
    pub(crate) const fn new(kinds: &[SyntaxKind]) -> TokenSet {
        let mut bits = [0u64; 4];
        let mut i = 0;
        while i < kinds.len() {
            let k = kinds[i] as usize;
            bits[k / 64] |= 1 << (k % 64);
            i += 1;
        }
        TokenSet(bits)
    }

    pub(crate) fn contains(&self, kind: SyntaxKind) -> bool {
        let k = kind as usize;
        k < 256 && self.0[k / 64] & (1 << (k % 64)) != 0
    }
}

/// The parser state handed to every grammar function.
pub(crate) struct Parser<'a> {
    /// `input.kinds`, held directly: one load less per look-ahead.
    kinds: &'a [SyntaxKind],
    input: &'a Input,
    text: &'a str,
    pos: usize,
    /// The kind at `pos` (`EOF` past the end).
    cur: SyntaxKind,
    fuel: Cell<u32>,
    builder: TreeBuilder<'a>,
    errors: Vec<SyntaxError>,
    pub(crate) file: FileKind,
    depth: u32,
    /// The blocks currently open, innermost last (for recovery decisions
    /// and messages).
    pub(crate) blocks: Vec<crate::grammar::Block<'a>>,
}

impl<'a> Parser<'a> {
    pub(crate) fn new(input: &'a Input, tokens: &'a [Token], text: &'a str, file: FileKind) -> Parser<'a> {
        Parser {
            kinds: &input.kinds,
            input,
            text,
            pos: 0,
            cur: input.kinds.first().copied().unwrap_or(EOF),
            fuel: Cell::new(FUEL),
            builder: TreeBuilder::new(text, tokens),
            errors: Vec::new(),
            file,
            depth: 0,
            blocks: Vec::new(),
        }
    }

    /// The tree and the errors.
    pub(crate) fn finish(self) -> (GreenNode, Vec<SyntaxError>) {
        (self.builder.finish(SOURCE_FILE), self.errors)
    }

    pub(crate) fn is_robosim(&self) -> bool {
        matches!(self.file, FileKind::RoboSim | FileKind::SimAssertions)
    }

    /// The kind of the `n`-th token ahead (`EOF` past the end).
    pub(crate) fn nth(&self, n: usize) -> SyntaxKind {
        let fuel = self.fuel.get();
        if fuel == 0 {
            return EOF;
        }
        self.fuel.set(fuel - 1);
        self.kinds.get(self.pos + n).copied().unwrap_or(EOF)
    }

    /// `nth(0)`, the most common look-ahead, from `cur`.
    pub(crate) fn current(&self) -> SyntaxKind {
        let fuel = self.fuel.get();
        if fuel == 0 {
            return EOF;
        }
        self.fuel.set(fuel - 1);
        self.cur
    }

    pub(crate) fn at(&self, kind: SyntaxKind) -> bool {
        self.current() == kind
    }

    pub(crate) fn nth_at(&self, n: usize, kind: SyntaxKind) -> bool {
        self.nth(n) == kind
    }

    pub(crate) fn at_ts(&self, set: TokenSet) -> bool {
        set.contains(self.current())
    }

    pub(crate) fn at_eof(&self) -> bool {
        self.at(EOF)
    }

    /// Text of the `n`-th token ahead ("" past the end).
    pub(crate) fn nth_text(&self, n: usize) -> &'a str {
        match self.builder.range_ahead(n) {
            Some(r) => &self.text[r],
            None => "",
        }
    }

    /// The range of the current token, or an empty range at the end of the
    /// text.
    pub(crate) fn current_range(&self) -> TextRange {
        match self.builder.range_ahead(0) {
            Some(r) if self.fuel.get() > 0 => r,
            _ => TextRange::empty(self.input.text_len),
        }
    }

    /// The range just after the previous token (for "missing X" errors).
    pub(crate) fn prev_end(&self) -> TextRange {
        match self.prev_range() {
            Some(r) => TextRange::empty(r.end()),
            None => TextRange::empty(0.into()),
        }
    }

    pub(crate) fn prev_range(&self) -> Option<TextRange> {
        // The builder has added the tokens up to `pos` and at most the
        // trivia after them.
        self.builder.range_behind()
    }

    pub(crate) fn bump_any(&mut self) {
        if self.at_eof() {
            return;
        }
        self.fuel.set(FUEL);
        self.pos += 1;
        self.cur = self.kinds.get(self.pos).copied().unwrap_or(EOF);
        self.builder.token();
    }

    pub(crate) fn bump(&mut self, kind: SyntaxKind) {
        debug_assert!(self.at(kind));
        self.bump_any();
    }

    pub(crate) fn eat(&mut self, kind: SyntaxKind) -> bool {
        if self.at(kind) {
            self.bump_any();
            true
        } else {
            false
        }
    }

    /// Consumes `kind` or reports "expected `what` …, found …".
    pub(crate) fn expect(&mut self, kind: SyntaxKind) -> bool {
        if self.eat(kind) {
            return true;
        }
        self.error_expected(kind.describe());
        false
    }

    /// Consumes `kind` or reports `message` (which should say where).
    pub(crate) fn expect_msg(&mut self, kind: SyntaxKind, message: impl std::fmt::Display) -> bool {
        if self.eat(kind) {
            return true;
        }
        self.error(format!("{message}, found {}", self.found()));
        false
    }

    pub(crate) fn found(&self) -> String {
        let k = self.current();
        match k {
            IDENT => format!("`{}`", self.nth_text(0)),
            EOF => "end of file".into(),
            _ if k.is_keyword() => format!("keyword `{}`", self.nth_text(0)),
            _ => k.describe(),
        }
    }

    pub(crate) fn error_expected(&mut self, what: impl std::fmt::Display) {
        let msg = format!("expected {what}, found {}", self.found());
        self.error(msg);
    }

    /// An error on the current token (or at the end of the file).
    pub(crate) fn error(&mut self, message: impl Into<String>) {
        let range = self.error_range();
        self.push_error(SyntaxError::error(message, range));
    }

    fn error_range(&self) -> TextRange {
        // At the end of the file, point just after the last token rather
        // than at trailing whitespace.
        if self.at_eof() {
            return match self.prev_range() {
                Some(r) => TextRange::empty(r.end()),
                None => TextRange::empty(self.input.text_len),
            };
        }
        self.current_range()
    }

    pub(crate) fn error_at(&mut self, range: TextRange, message: impl Into<String>) {
        self.push_error(SyntaxError::error(message, range));
    }

    fn push_error(&mut self, e: SyntaxError) {
        // Never report two errors at the same place: the first is the cause.
        if self.errors.last().is_some_and(|l| l.range.start() == e.range.start()) {
            return;
        }
        self.errors.push(e);
    }

    /// Reports `message` and wraps the current token in an ERROR node.
    pub(crate) fn err_and_bump(&mut self, message: impl Into<String>) {
        let m = self.start();
        self.error(message);
        self.bump_balanced();
        m.complete(self, ERROR);
    }

    /// Consumes one token, or a whole bracketed group if it opens one.
    pub(crate) fn bump_balanced(&mut self) {
        let mut depth = 0i32;
        loop {
            let k = self.current();
            if k == EOF {
                return;
            }
            if is_open(k) {
                depth += 1;
            } else if is_close(k) {
                depth -= 1;
            }
            self.bump_any();
            if depth <= 0 {
                return;
            }
        }
    }

    /// Starts the root, which takes leading trivia and, when completed,
    /// everything that is left.
    pub(crate) fn start_root(&mut self) -> RootMarker {
        debug_assert_eq!(self.builder.checkpoint(), 0);
        RootMarker(())
    }

    /// Starts a node inside the root.
    pub(crate) fn start(&mut self) -> Marker {
        let before = self.builder.save();
        // Trivia in front of a node belongs to its parent.
        self.builder.trivia();
        Marker { first_child: self.builder.checkpoint(), before, done: false }
    }

    /// Whether `extra` more levels of tree nesting still fit in the budget.
    pub(crate) fn depth_allows(&self, extra: u32) -> bool {
        self.depth + extra < MAX_DEPTH
    }

    /// Adds (or gives back) levels of tree nesting made by left-nested
    /// chains such as `a + b + c`, which the grammar builds in a loop.
    pub(crate) fn add_depth(&mut self, n: i32) {
        self.depth = self.depth.saturating_add_signed(n);
    }

    /// Runs `f` one level deeper; past `MAX_DEPTH` reports an error and
    /// skips the construct flat instead.
    pub(crate) fn nested<T>(&mut self, f: impl FnOnce(&mut Parser<'a>) -> Option<T>) -> Option<T> {
        if self.depth >= MAX_DEPTH {
            let m = self.start();
            self.error(format!(
                "nesting is too deep (more than {MAX_DEPTH} levels); the rest of this construct is not parsed"
            ));
            self.bump_balanced();
            m.complete(self, ERROR);
            return None;
        }
        self.depth += 1;
        let r = f(self);
        self.depth -= 1;
        r
    }
}

fn is_open(k: SyntaxKind) -> bool {
    matches!(k, L_CURLY | L_PAREN | L_BRACK | L_PAREN_PIPE | L_BRACK_PIPE | DEADLINE_OPEN | SET_OPEN | SEQ_OPEN)
}

fn is_close(k: SyntaxKind) -> bool {
    matches!(k, R_CURLY | R_PAREN | R_BRACK | R_PAREN_PIPE | R_BRACK_PIPE)
}

/// An open node; must be completed or abandoned.
pub(crate) struct Marker {
    /// Where the node's children start in the builder.
    first_child: usize,
    /// The builder before `start` moved trivia into the parent, for
    /// `abandon`.
    before: Saved,
    done: bool,
}

impl Marker {
    pub(crate) fn complete(mut self, p: &mut Parser<'_>, kind: SyntaxKind) -> CompletedMarker {
        self.done = true;
        p.builder.finish_node(kind, self.first_child);
        CompletedMarker { first_child: self.first_child }
    }

    pub(crate) fn abandon(mut self, p: &mut Parser<'_>) {
        self.done = true;
        // Nothing was added since `start`: undo its moving trivia into the
        // parent, so that the trivia goes wherever the next token or node
        // puts it, as if the marker had never been started.
        if p.builder.checkpoint() == self.first_child {
            p.builder.restore(self.before);
        }
    }
}

impl Drop for Marker {
    fn drop(&mut self) {
        // A forgotten marker is a grammar bug; its children stay in the
        // parent and the tree is still lossless, so only debug builds
        // complain.
        debug_assert!(self.done || std::thread::panicking(), "marker dropped without completion");
    }
}

/// The open root (see `Parser::start_root`).
pub(crate) struct RootMarker(());

impl RootMarker {
    pub(crate) fn complete(self, p: &mut Parser<'_>, kind: SyntaxKind) {
        // The root takes everything that is left.
        p.builder.rest();
        p.builder.finish_node(kind, 0);
    }
}

/// A finished node, which can still be wrapped by a new parent.
#[derive(Clone, Copy)]
pub(crate) struct CompletedMarker {
    first_child: usize,
}

impl CompletedMarker {
    /// Starts a new node that will contain this one (for postfix and infix
    /// forms).
    pub(crate) fn precede(self, p: &mut Parser<'_>) -> Marker {
        Marker { first_child: self.first_child, before: p.builder.save(), done: false }
    }
}
