//! Parser infrastructure: the grammar functions see only non-trivia tokens
//! and open, wrap and close nodes of a rowan green tree as they go. Every
//! token, trivia included, is added to the tree, so it is lossless.
//!
//! FDR's layout rule lives here (`at_line_break`): a line break ends a
//! definition unless the token before it or the token after it "soaks" it
//! (operators, opening brackets, `let`, …), exactly as libcspm's lexer does.

use rowan::{Checkpoint, GreenNode, GreenNodeBuilder};

use crate::kinds::SyntaxKind::{self, *};
use crate::lexer::Token;
use crate::{Code, Diagnostic, TextRange};

/// Deepest nesting of expressions; deeper input is one error, skipped flat,
/// so that nothing walking the tree recursively can overflow the stack.
pub(crate) const MAX_DEPTH: u32 = 300;

/// Look-aheads without progress after which the parser sees end of file
/// (a guard against a grammar bug looping).
const FUEL: u32 = 100_000;

pub(crate) struct Parser<'t> {
    text: &'t str,
    tokens: &'t [Token],
    /// Indices into `tokens` of the non-trivia tokens.
    significant: Vec<usize>,
    pos: usize,
    /// Next index into `tokens` not yet added to the tree.
    emitted: usize,
    builder: GreenNodeBuilder<'static>,
    pub(crate) errors: Vec<Diagnostic>,
    fuel: std::cell::Cell<u32>,
    pub(crate) depth: u32,
    /// Inside a sequence literal `<…>`, where `>` closes it rather than
    /// compares (reset inside brackets, as libcspm's sequence stack does).
    pub(crate) gt_closes: bool,
    pub(crate) stack: crate::stack::StackGuard,
    /// A token after which a line break is hard whatever its kind (the `]`
    /// closing an assertion's property, which libcspm lexes apart).
    hard_after: Option<usize>,
}

impl<'t> Parser<'t> {
    pub(crate) fn new(text: &'t str, tokens: &'t [Token]) -> Parser<'t> {
        let significant = (0..tokens.len()).filter(|&i| !tokens[i].kind.is_trivia()).collect();
        Parser {
            text,
            tokens,
            significant,
            pos: 0,
            emitted: 0,
            builder: GreenNodeBuilder::new(),
            errors: Vec::new(),
            fuel: std::cell::Cell::new(FUEL),
            depth: 0,
            gt_closes: false,
            stack: crate::stack::StackGuard::new(crate::stack::STATIC_PASS_STACK),
            hard_after: None,
        }
    }

    /// Opens the root node (before any trivia, which belongs inside it).
    pub(crate) fn start_root(&mut self, kind: SyntaxKind) {
        self.builder.start_node(kind.into());
    }

    pub(crate) fn finish(mut self) -> (GreenNode, Vec<Diagnostic>) {
        while self.emitted < self.tokens.len() {
            self.emit_one();
        }
        self.builder.finish_node();
        (self.builder.finish(), self.errors)
    }

    pub(crate) fn nth(&self, n: usize) -> SyntaxKind {
        let fuel = self.fuel.get();
        if fuel == 0 {
            return EOF;
        }
        self.fuel.set(fuel - 1);
        self.significant.get(self.pos + n).map_or(EOF, |&i| self.tokens[i].kind)
    }

    pub(crate) fn current(&self) -> SyntaxKind {
        self.nth(0)
    }

    pub(crate) fn at(&self, kind: SyntaxKind) -> bool {
        self.current() == kind
    }

    /// The range of the current token (empty at the end of the text).
    pub(crate) fn current_range(&self) -> TextRange {
        match self.significant.get(self.pos) {
            Some(&i) => self.tokens[i].range(),
            None => {
                let end = (self.text.len() as u32).into();
                TextRange::empty(end)
            }
        }
    }

    /// Makes a line break after the previous token end the definition.
    pub(crate) fn hard_break_after_previous(&mut self) {
        self.hard_after = self.pos.checked_sub(1).and_then(|p| self.significant.get(p)).copied();
    }

    /// The text of the current token.
    pub(crate) fn token_text(&self) -> &'t str {
        &self.text[self.current_range()]
    }

    /// Whether the previous and the current token touch (no trivia between).
    pub(crate) fn adjacent(&self) -> bool {
        match (self.pos.checked_sub(1).and_then(|p| self.significant.get(p)), self.significant.get(self.pos)) {
            (Some(&a), Some(&b)) => b == a + 1,
            _ => false,
        }
    }

    /// Whether a line break FDR counts as the end of a definition comes
    /// before the current token.
    pub(crate) fn at_line_break(&self) -> bool {
        let (Some(&prev), Some(&cur)) =
            (self.pos.checked_sub(1).and_then(|p| self.significant.get(p)), self.significant.get(self.pos))
        else {
            return false;
        };
        let newline =
            self.tokens[prev + 1..cur].iter().any(|t| t.kind == WHITESPACE && self.text[t.range()].contains('\n'));
        // Keywords that only start declarations end the previous one on a
        // new line even after a soaking token (`]` of `:[deadlock free]`).
        let starts_decl = matches!(
            self.tokens[cur].kind,
            ASSERT_KW | CHANNEL_KW | DATATYPE_KW | NAMETYPE_KW | SUBTYPE_KW | MODULE_KW | TIMED_KW
        );
        let hard = self.hard_after == Some(prev);
        newline
            && (starts_decl || hard || (!self.tokens[prev].kind.soaks_after() && !self.tokens[cur].kind.soaks_before()))
    }

    fn emit_one(&mut self) {
        let t = self.tokens[self.emitted];
        self.builder.token(t.kind.into(), &self.text[t.range()]);
        self.emitted += 1;
    }

    fn flush_trivia(&mut self) {
        while self.emitted < self.tokens.len() && self.tokens[self.emitted].kind.is_trivia() {
            self.emit_one();
        }
    }

    pub(crate) fn bump(&mut self) {
        if let Some(&i) = self.significant.get(self.pos) {
            while self.emitted <= i {
                self.emit_one();
            }
            self.pos += 1;
            self.fuel.set(FUEL);
        }
    }

    pub(crate) fn eat(&mut self, kind: SyntaxKind) -> bool {
        if self.at(kind) {
            self.bump();
            true
        } else {
            false
        }
    }

    pub(crate) fn expect(&mut self, kind: SyntaxKind) -> bool {
        if self.eat(kind) {
            return true;
        }
        self.error(format!("expected `{}`", kind.text().unwrap_or("?")));
        false
    }

    pub(crate) fn error(&mut self, message: impl Into<String>) {
        let range = self.current_range();
        // One message per place: cascades after the first say nothing new.
        if self.errors.last().is_some_and(|e| e.range == range) {
            return;
        }
        let found = match self.current() {
            EOF => "the end of the text".to_owned(),
            _ => format!("`{}`", &self.text[range]),
        };
        self.errors.push(Diagnostic::error(Code::Syntax, range, format!("{}, found {found}", message.into())));
    }

    pub(crate) fn start(&mut self, kind: SyntaxKind) {
        self.flush_trivia();
        self.builder.start_node(kind.into());
    }

    pub(crate) fn checkpoint(&mut self) -> Checkpoint {
        self.flush_trivia();
        self.builder.checkpoint()
    }

    pub(crate) fn start_at(&mut self, cp: Checkpoint, kind: SyntaxKind) {
        self.builder.start_node_at(cp, kind.into());
    }

    pub(crate) fn finish_node(&mut self) {
        self.builder.finish_node();
    }

    /// Wraps tokens into an `ERROR` node until `stop` holds, a line break
    /// ends the definition, or the text ends.
    pub(crate) fn skip_until(&mut self, stop: impl Fn(SyntaxKind) -> bool) {
        if self.at(EOF) || stop(self.current()) {
            return;
        }
        self.start(ERROR);
        loop {
            self.bump();
            if self.at(EOF) || stop(self.current()) || self.at_line_break() {
                break;
            }
        }
        self.finish_node();
    }
}
