//! The layout engine: one pass over the tokens and comments of a parsed
//! file, in order, deciding the whitespace before each of them.
//!
//! It never recurses: the block and bracket structure is tracked with
//! explicit stacks, and all tree walks are iterative, so the depth of the
//! input cannot overflow the stack.

use robosim_syntax::lexer;
use robosim_syntax::SyntaxKind::*;
use robosim_syntax::{FileKind, SyntaxNode, SyntaxToken, TextRange, TextSize};

use crate::rules::{self, Role, Spacing};
use crate::{Indent, Options};

/// Columns a tab counts for when checking the line width.
const TAB_WIDTH: usize = 4;

/// A token or comment of the input, with the line breaks before it.
struct Elem {
    tok: SyntaxToken,
    /// Line breaks in the input between the previous element and this one
    /// (the line break that ends a line comment counts).
    breaks: u32,
}

impl Elem {
    fn is_comment(&self) -> bool {
        matches!(self.tok.kind(), LINE_COMMENT | BLOCK_COMMENT)
    }
}

/// A block whose `{` has been printed and whose `}` has not.
struct OpenBlock {
    inline: bool,
}

/// An open bracket group (or `if … end`) of the current item.
struct Group {
    /// The node the group spans: its last token closes the group.
    range: TextRange,
    /// The indentation of the line the group was opened on.
    line_indent: usize,
}

/// Where the next token goes, relative to the previous output.
#[derive(Debug, Clone, Copy)]
enum Place {
    Glue,
    Space,
    Line { blank: bool, indent: usize },
}

pub(crate) struct Printer<'a> {
    opts: &'a Options,
    file: FileKind,
    nl: &'static str,
    elems: Vec<Elem>,
    /// `comments_before[i]`: how many of `elems[..i]` are comments.
    comments_before: Vec<u32>,
    /// Byte offsets just after each `\n` of the input.
    line_starts: Vec<TextSize>,

    out: String,
    /// Visual column at the end of `out`.
    col: usize,
    /// Line breaks at the end of `out` (0 in the middle of a line).
    trailing_breaks: u32,
    /// Indentation level of the current output line.
    line_indent: usize,
    /// Whether a token (not just comments) is on the current output line.
    code_on_line: bool,
    blocks: Vec<OpenBlock>,
    /// Indentation level of the members of the innermost expanded block.
    depth: usize,
    /// Indentation level of the first line of the current item.
    item_indent: usize,
    groups: Vec<Group>,
}

impl<'a> Printer<'a> {
    pub(crate) fn new(root: &SyntaxNode, text: &str, file: FileKind, opts: &'a Options) -> Printer<'a> {
        let mut elems = Vec::new();
        let mut breaks = 0u32;
        let mut crlf = 0usize;
        let mut lf = 0usize;
        let mut count_breaks = |s: &str| {
            let n = s.matches('\n').count();
            let c = s.matches("\r\n").count();
            crlf += c;
            lf += n - c;
            n as u32
        };
        for tok in root.descendants_with_tokens().filter_map(|e| e.into_token()) {
            match tok.kind() {
                WHITESPACE => breaks += count_breaks(tok.text()),
                _ => {
                    let ends_line = tok.kind() == LINE_COMMENT && tok.text().ends_with('\n');
                    if ends_line {
                        count_breaks(tok.text());
                    }
                    elems.push(Elem { tok, breaks });
                    breaks = u32::from(ends_line);
                }
            }
        }
        let mut comments_before = Vec::with_capacity(elems.len() + 1);
        let mut n = 0;
        for e in &elems {
            comments_before.push(n);
            n += u32::from(e.is_comment());
        }
        comments_before.push(n);
        let line_starts =
            text.bytes().enumerate().filter(|(_, b)| *b == b'\n').map(|(i, _)| TextSize::from(i as u32 + 1)).collect();
        Printer {
            opts,
            file,
            // The line breaks the formatter writes (and those that end line
            // comments) follow the majority of the input's, so a CRLF file
            // stays CRLF; the output is then uniform, so it keeps its style.
            nl: if crlf > lf { "\r\n" } else { "\n" },
            elems,
            comments_before,
            line_starts,
            out: String::with_capacity(text.len() + text.len() / 8),
            col: 0,
            trailing_breaks: 0,
            line_indent: 0,
            code_on_line: false,
            blocks: Vec::new(),
            depth: 0,
            item_indent: 0,
            groups: Vec::new(),
        }
    }

    pub(crate) fn run(mut self) -> String {
        let mut prev: Option<usize> = None;
        let mut next = 0;
        for i in 0..self.elems.len() {
            if self.elems[i].is_comment() {
                continue;
            }
            self.token(prev, next, i);
            prev = Some(i);
            next = i + 1;
        }
        // Comments after the last token, at the top level.
        let mut last = prev;
        for c in next..self.elems.len() {
            self.comment(c, last, true, 0);
            last = Some(c);
        }
        if !self.out.is_empty() && self.trailing_breaks == 0 {
            self.out.push_str(self.nl);
        }
        self.out
    }

    /// Prints the comments `elems[first..i]`, then the token `elems[i]`;
    /// `prev` is the previous token.
    fn token(&mut self, prev: Option<usize>, first: usize, i: usize) {
        let b = self.elems[i].tok.clone();
        let a = prev.map(|p| self.elems[p].tok.clone());
        let role = rules::role(a.as_ref(), &b);
        let inline_block = self.blocks.last().is_some_and(|o| o.inline);

        // The nominal place of `b`, where comments before it go, and whether
        // blank lines are kept there (only between members).
        let (place, comment_indent, zone, starts_item) = match &role {
            Role::Member { parent, .. } if parent.kind() == SOURCE_FILE => {
                (Nominal::Line { first: false, indent: 0 }, 0, true, true)
            }
            Role::Member { .. } if inline_block => (Nominal::Fixed(Spacing::Space), self.depth, false, true),
            Role::Member { join: true, .. } => (Nominal::Fixed(Spacing::Space), self.depth, false, true),
            Role::Member { first, .. } => (Nominal::Line { first: *first, indent: self.depth }, self.depth, true, true),
            Role::Close if inline_block => (Nominal::Fixed(Spacing::Space), self.depth, false, false),
            Role::Close => (Nominal::Close { indent: self.depth.saturating_sub(1) }, self.depth, true, false),
            Role::Inner(sp) => (Nominal::Fixed(*sp), self.continuation_indent(None), false, false),
        };

        let mut last = prev;
        for c in first..i {
            self.comment(c, last, zone, comment_indent);
            last = Some(c);
        }
        if starts_item {
            self.groups.clear();
            self.item_indent = self.depth;
        }

        let breaks = self.elems[i].breaks;
        let after_comment = first < i;
        let line_indent = match place {
            Nominal::Line { indent, .. } | Nominal::Close { indent } => indent,
            Nominal::Fixed(_) if matches!(role, Role::Member { .. }) => self.depth,
            // A block's `{` pushed to a line of its own (by a comment) lines
            // up with its header, as its `}` will; so does the CSP text.
            Nominal::Fixed(_) if b.kind() == CSP_TEXT || rules::is_block_open(&b) => self.item_indent,
            Nominal::Fixed(_) => self.continuation_indent(Some(&b)),
        };
        let member_zone = matches!(place, Nominal::Line { .. });
        let placed = if after_comment && (breaks > 0 || self.trailing_breaks > 0) {
            let blank = breaks >= 2 && member_zone && self.blank_allowed(last);
            Place::Line { blank, indent: line_indent }
        } else if after_comment {
            match place {
                // A member may follow a comment that starts its line:
                // `/* note */ event e`.
                Nominal::Line { .. } if !self.code_on_line => Place::Space,
                Nominal::Line { .. } | Nominal::Close { .. } => Place::Line { blank: false, indent: line_indent },
                Nominal::Fixed(_) => Place::Space,
            }
        } else {
            match place {
                Nominal::Line { first, .. } => {
                    Place::Line { blank: breaks >= 2 && !first && self.blank_allowed(last), indent: line_indent }
                }
                Nominal::Close { .. } => Place::Line { blank: false, indent: line_indent },
                Nominal::Fixed(sp) if sp.is_soft() && breaks > 0 => Place::Line { blank: false, indent: line_indent },
                Nominal::Fixed(sp) if sp.is_space() => Place::Space,
                Nominal::Fixed(_) => match &a {
                    Some(a) if !self.glue_is_safe(a, &b) => Place::Space,
                    _ => Place::Glue,
                },
            }
        };
        self.place(placed);
        self.write(b.text());
        self.code_on_line = true;

        // Structure after the token.
        if let Role::Close = role {
            if let Some(o) = self.blocks.pop() {
                if !o.inline {
                    self.depth = self.depth.saturating_sub(1);
                }
            }
        }
        let end = b.text_range().end();
        while self.groups.last().is_some_and(|g| g.range.end() == end) {
            self.groups.pop();
        }
        if rules::is_block_open(&b) {
            let inline = match b.parent() {
                Some(block) => self.decide_inline(&block, i),
                None => false,
            };
            self.blocks.push(OpenBlock { inline });
            if !inline {
                self.depth += 1;
            }
        } else if rules::opens_group(&b) {
            if let Some(p) = b.parent() {
                self.groups.push(Group { range: p.text_range(), line_indent: self.line_indent });
            }
        }
    }

    /// Prints comment `elems[c]`. `prev` is the element before it; `zone`
    /// says whether blank lines are kept here (between members); `indent`
    /// is used when the comment starts a line.
    fn comment(&mut self, c: usize, prev: Option<usize>, zone: bool, indent: usize) {
        let breaks = self.elems[c].breaks;
        if self.out.is_empty() {
            // First thing in the file: no separator.
        } else if breaks > 0 || self.trailing_breaks > 0 {
            let blank = breaks >= 2 && zone && self.blank_allowed(prev);
            self.place(Place::Line { blank, indent });
        } else {
            self.place(Place::Space);
        }
        let tok = self.elems[c].tok.clone();
        if tok.kind() == LINE_COMMENT {
            // The comment's own line break (and any trailing blanks before
            // it) is whitespace: it is rewritten in the file's style.
            self.write(line_comment_text(tok.text()));
            self.out.push_str(self.nl);
            self.trailing_breaks = 1;
            self.col = 0;
        } else {
            self.write(tok.text());
        }
    }

    /// A blank line may follow element `prev`: not at the start of the file
    /// and not right after a block's `{`, even with comments after the `{`
    /// on its line.
    fn blank_allowed(&self, prev: Option<usize>) -> bool {
        let Some(mut p) = prev else { return false };
        while self.elems[p].is_comment() && self.elems[p].breaks == 0 && p > 0 {
            p -= 1;
        }
        !rules::is_block_open(&self.elems[p].tok)
    }

    /// The indentation of a line that starts with `b` inside the current
    /// item: one level deeper than the line that opened the innermost open
    /// group, or than the item's first line; a group's closer (and the
    /// `then`/`else` of an `if`) goes back to the opening line's level.
    fn continuation_indent(&self, b: Option<&SyntaxToken>) -> usize {
        match self.groups.last() {
            Some(g) => {
                if let Some(b) = b {
                    if g.range.end() == b.text_range().end() || rules::is_group_middle(b, g.range) {
                        return g.line_indent;
                    }
                }
                g.line_indent + 1
            }
            None => self.item_indent + 1,
        }
    }

    /// Whether the block whose `{` is `elems[open]` stays on one line.
    fn decide_inline(&self, block: &SyntaxNode, open: usize) -> bool {
        // Inside a one-line block everything is on that line.
        if self.blocks.last().is_some_and(|o| o.inline) {
            return true;
        }
        let Some(close) = rules::close_brace(block) else { return false };
        let Some(close_idx) = self.index_of(&close) else { return false };
        if close_idx <= open || self.comments_before[close_idx] != self.comments_before[open + 1] {
            return false;
        }
        // An empty body is always `{ }`.
        if rules::members(block).next().is_none() {
            return true;
        }
        // Otherwise only a body the author wrote on one line stays there.
        let open_end = self.elems[open].tok.text_range().end();
        if self.line_of(open_end) != self.line_of(close.text_range().start()) {
            return false;
        }
        if block.descendants().any(|n| rules::is_block(n.kind()) && !rules::member_count_allows_inline(&n)) {
            return false;
        }
        let budget = self.opts.max_width.saturating_sub(self.col);
        self.flat_width(open, close_idx, budget) <= budget
    }

    /// The width of `elems[open + 1..=close]` printed on one line, or some
    /// value above `budget` once it exceeds it.
    fn flat_width(&self, open: usize, close: usize, budget: usize) -> usize {
        let mut width = 0;
        for k in open + 1..=close {
            let (a, b) = (&self.elems[k - 1].tok, &self.elems[k].tok);
            width += match rules::role(Some(a), b) {
                Role::Member { .. } | Role::Close => 1,
                Role::Inner(sp) if sp.is_space() => 1,
                Role::Inner(_) => usize::from(!self.glue_is_safe(a, b)),
            };
            width += text_width(b.text());
            if width > budget {
                break;
            }
        }
        width
    }

    /// Whether `a` and `b` written without a space still lex as the same
    /// two tokens, with no new warning. This is what keeps `s ^ t`, `1 .`,
    /// `Set (`, `< -1` and `< {` apart: `^t` is an escaped name, `1.` a
    /// RoboTool lexer error, `Set(` a keyword, `<-` a lexer error and `<{` a
    /// deadline.
    fn glue_is_safe(&self, a: &SyntaxToken, b: &SyntaxToken) -> bool {
        let (at, bt) = (a.text(), b.text());
        let mut joined = String::with_capacity(at.len() + bt.len());
        joined.push_str(at);
        joined.push_str(bt);
        let (tokens, errors) = lexer::lex(&joined, self.file);
        errors.is_empty()
            && tokens.len() == 2
            && tokens[0].kind == a.kind()
            && tokens[1].kind == b.kind()
            && tokens[0].len == TextSize::of(at)
    }

    fn index_of(&self, t: &SyntaxToken) -> Option<usize> {
        let start = t.text_range().start();
        self.elems.binary_search_by_key(&start, |e| e.tok.text_range().start()).ok()
    }

    fn line_of(&self, offset: TextSize) -> usize {
        self.line_starts.partition_point(|&s| s <= offset)
    }

    fn place(&mut self, place: Place) {
        if self.out.is_empty() {
            return;
        }
        match place {
            Place::Glue if self.trailing_breaks == 0 => {}
            Place::Space if self.trailing_breaks == 0 => {
                self.out.push(' ');
                self.col += 1;
            }
            // After a line comment the next token starts a line, whatever
            // was asked: indent it like the line it continues.
            Place::Glue | Place::Space => {
                let indent = self.line_indent;
                self.indent(indent);
            }
            Place::Line { blank, indent } => {
                let want = if blank { 2 } else { 1 };
                while self.trailing_breaks < want {
                    self.out.push_str(self.nl);
                    self.trailing_breaks += 1;
                }
                self.indent(indent);
            }
        }
    }

    fn indent(&mut self, level: usize) {
        let (unit, width) = match self.opts.indent {
            Indent::Tab => ("\t", TAB_WIDTH),
            Indent::Spaces(n) => (&"                "[..usize::from(n.min(16))], usize::from(n.min(16))),
        };
        for _ in 0..level {
            self.out.push_str(unit);
        }
        self.col = level * width;
        self.line_indent = level;
        self.code_on_line = false;
    }

    fn write(&mut self, text: &str) {
        self.out.push_str(text);
        match text.rfind('\n') {
            Some(i) => {
                self.col = text_width(&text[i + 1..]);
                self.trailing_breaks = u32::from(i + 1 == text.len());
            }
            None => {
                self.col += text_width(text);
                if !text.is_empty() {
                    self.trailing_breaks = 0;
                }
            }
        }
    }
}

/// Where a token goes before comments and the input's line breaks are
/// taken into account.
#[derive(Debug, Clone, Copy)]
enum Nominal {
    /// Starts a line: a member of an expanded block, or an item of the file.
    Line { first: bool, indent: usize },
    /// The `}` of an expanded block.
    Close { indent: usize },
    /// Within a line.
    Fixed(Spacing),
}

/// A line comment without its line break and trailing blanks, which are
/// whitespace (only spaces, tabs, CR and LF: other characters are content).
pub(crate) fn line_comment_text(text: &str) -> &str {
    text.trim_end_matches([' ', '\t', '\r', '\n'])
}

fn text_width(s: &str) -> usize {
    s.chars().map(|c| if c == '\t' { TAB_WIDTH } else { 1 }).sum()
}
