//! What the layout of each token depends on, read off the syntax tree: which
//! nodes are blocks, where members start, which tokens open and close
//! bracket groups, and the spacing between two adjacent tokens of one item.
//!
//! Everything here looks only at kinds and at the tree around a token, never
//! at the whitespace of the input, so that formatting a formatted file makes
//! the same decisions again (idempotence).

use robosim_syntax::SyntaxKind::{self, *};
use robosim_syntax::{SyntaxNode, SyntaxToken, TextRange};

/// Node kinds whose body is a `{ … }` of members, one per line when the
/// block is expanded.
pub(crate) fn is_block(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        INTERFACE
            | RECORD_DECL
            | ENUM_DECL
            | ROBOTIC_PLATFORM
            | CONTROLLER
            | STATE_MACHINE
            | OPERATION_DEF
            | FUNCTION
            | MODULE
            | STATE
            | TRANSITION
            | INPUT_CONTEXT
            | OUTPUT_CONTEXT
            | SIMULATION
    )
}

/// Blocks that may stay on one line with several members: the clauses of a
/// transition and the literals of an enumeration read well side by side;
/// other members (declarations, nodes, fields) do not.
fn any_member_count_inline(kind: SyntaxKind) -> bool {
    matches!(kind, TRANSITION | ENUM_DECL)
}

fn parent_kind(t: &SyntaxToken) -> Option<SyntaxKind> {
    t.parent().map(|p| p.kind())
}

/// The `{` of a block node: its first direct `{` child.
pub(crate) fn open_brace(block: &SyntaxNode) -> Option<SyntaxToken> {
    block.children_with_tokens().filter_map(|e| e.into_token()).find(|t| t.kind() == L_CURLY)
}

/// The `}` of a block node: its last direct `}` child.
pub(crate) fn close_brace(block: &SyntaxNode) -> Option<SyntaxToken> {
    block.children_with_tokens().filter_map(|e| e.into_token()).filter(|t| t.kind() == R_CURLY).last()
}

/// Whether `t` is the `{` of a block.
pub(crate) fn is_block_open(t: &SyntaxToken) -> bool {
    t.kind() == L_CURLY && parent_kind(t).is_some_and(is_block)
}

/// The member nodes of a block: its child nodes after the `{`.
pub(crate) fn members(block: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> {
    let after = open_brace(block).map(|t| t.text_range().end());
    block.children().filter(move |n| after.is_some_and(|a| n.text_range().start() >= a))
}

/// Whether the number of members allows `block` on one line.
pub(crate) fn member_count_allows_inline(block: &SyntaxNode) -> bool {
    any_member_count_inline(block.kind()) || members(block).nth(1).is_none()
}

/// The role of a token in the layout of its block.
#[derive(Debug, Clone)]
pub(crate) enum Role {
    /// The first token of a member of a block, or of an item of the file.
    Member {
        /// The block (or the `SOURCE_FILE`).
        parent: SyntaxNode,
        /// Whether this is the block's first member.
        first: bool,
        /// Kept on the line of the previous member even in an expanded
        /// block: the `to` of a transition after its `from`, and a clock
        /// reset after another one.
        join: bool,
    },
    /// The `}` of a block.
    Close,
    /// Any other token: spaced within its item.
    Inner(Spacing),
}

/// Spacing between two tokens of one item. The soft forms keep a line break
/// that the author wrote there (and only there).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Spacing {
    /// Glued: `f(`, `a::b`, `x,`.
    None,
    /// One space.
    Space,
    /// Glued, or a line break if the input had one.
    SoftNone,
    /// One space, or a line break if the input had one.
    SoftSpace,
}

impl Spacing {
    pub(crate) fn is_soft(self) -> bool {
        matches!(self, Spacing::SoftNone | Spacing::SoftSpace)
    }

    pub(crate) fn is_space(self) -> bool {
        matches!(self, Spacing::Space | Spacing::SoftSpace)
    }
}

/// The role of `b`, the token after `a` (`None` at the start of the file).
pub(crate) fn role(a: Option<&SyntaxToken>, b: &SyntaxToken) -> Role {
    if b.kind() == R_CURLY && b.parent().is_some_and(|p| is_block(p.kind())) {
        return Role::Close;
    }
    if let Some((member, parent)) = member_of(b) {
        let first = parent.kind() != SOURCE_FILE && members(&parent).next().is_some_and(|m| m == member);
        let join = match member.kind() {
            TRANSITION_TARGET => true,
            CLOCK_RESET => member.prev_sibling().is_some_and(|s| s.kind() == CLOCK_RESET),
            _ => false,
        };
        return Role::Member { parent, first, join };
    }
    match a {
        Some(a) => Role::Inner(spacing(a, b)),
        None => Role::Inner(Spacing::None),
    }
}

/// The member (and its block or file) that `t` is the first token of.
fn member_of(t: &SyntaxToken) -> Option<(SyntaxNode, SyntaxNode)> {
    let start = t.text_range().start();
    let mut node = t.parent()?;
    // Iterative: nodes never start with trivia, so the walk stops at the
    // first ancestor that starts earlier (bounded by the nesting depth).
    loop {
        if node.text_range().start() != start {
            return None;
        }
        let parent = node.parent()?;
        if parent.kind() == SOURCE_FILE {
            return Some((node, parent));
        }
        if is_block(parent.kind()) && open_brace(&parent).is_some_and(|o| o.text_range().end() <= start) {
            return Some((node, parent));
        }
        node = parent;
    }
}

/// Connection flags keep the spaced spelling RoboTool writes: `( _async )`,
/// `[ mult ]`.
fn spaced_flag(kind: Option<SyntaxKind>) -> bool {
    matches!(kind, Some(ASYNC_FLAG | MULT_FLAG))
}

/// `(`, `[`, a set `{` and a sequence `<`: nothing after them.
fn is_tight_open(t: &SyntaxToken) -> bool {
    match t.kind() {
        L_PAREN | L_BRACK | SET_OPEN | SEQ_OPEN => true,
        L_CURLY => !parent_kind(t).is_some_and(is_block),
        LT => parent_kind(t) == Some(SEQ_EXPR),
        _ => false,
    }
}

/// `)`, `]`, a set `}` and a sequence `>`: nothing before them.
fn is_tight_close(t: &SyntaxToken) -> bool {
    match t.kind() {
        R_PAREN | R_BRACK => true,
        R_CURLY => !parent_kind(t).is_some_and(|k| is_block(k) || k == DEADLINE),
        GT => parent_kind(t) == Some(SEQ_EXPR),
        _ => false,
    }
}

/// Whether `t` opens a bracket group (for continuation indentation): any
/// bracket, and the `if` of an `if … end`.
pub(crate) fn opens_group(t: &SyntaxToken) -> bool {
    match t.kind() {
        L_PAREN | L_BRACK | SET_OPEN | SEQ_OPEN | L_PAREN_PIPE | L_BRACK_PIPE | DEADLINE_OPEN => true,
        L_CURLY => !parent_kind(t).is_some_and(is_block),
        LT => parent_kind(t) == Some(SEQ_EXPR),
        IF_KW => matches!(parent_kind(t), Some(IF_EXPR | IF_STMT)),
        _ => false,
    }
}

/// Whether `t` is the `then` or `else` of the `if` whose node spans `group`.
pub(crate) fn is_group_middle(t: &SyntaxToken, group: TextRange) -> bool {
    matches!(t.kind(), THEN_KW | ELSE_KW) && t.parent().is_some_and(|p| p.text_range() == group)
}

/// Binary operators of expressions and types: a line may break before or
/// after them.
fn is_operator(t: &SyntaxToken) -> bool {
    match parent_kind(t) {
        // The only direct token child of a binary expression is its operator.
        Some(BIN_EXPR) => true,
        Some(FUNCTION_TYPE) => t.kind() == ARROW,
        Some(RELATION_TYPE) => t.kind() == REL_ARROW,
        Some(PRODUCT_TYPE) => t.kind() == STAR,
        _ => false,
    }
}

/// Whether `t` is the first token of a node of kind `kind`.
fn starts(t: &SyntaxToken, kind: SyntaxKind) -> bool {
    t.parent().is_some_and(|p| p.kind() == kind && p.text_range().start() == t.text_range().start())
}

/// The spacing between two adjacent tokens `a` and `b` of one item.
pub(crate) fn spacing(a: &SyntaxToken, b: &SyntaxToken) -> Spacing {
    use Spacing::*;
    let (ak, bk) = (a.kind(), b.kind());
    let (ap, bp) = (parent_kind(a), parent_kind(b));

    // A probability query keeps RoboTool's spelling: `Prob=? of`,
    // `Prob max=? [`.
    if bp == Some(PROB_BOUND) && bk == EQ {
        return None;
    }
    if ap == Some(PROB_BOUND) && ak == QUESTION {
        return Space;
    }
    // Prefixes that attach to what follows: `$e`, `#C`, `a::b`, `r.f`,
    // `Set(T`, `?X`, `e?x`, `e!v`, `-x`.
    match ak {
        DOLLAR | HASH | COLON2 | DOT | SET_OPEN | SEQ_OPEN | QUESTION | BANG => return None,
        MINUS if ap == Some(PREFIX_EXPR) => return None,
        _ => {}
    }
    // Suffixes that attach to what precedes: `a::b`, `p::*`, `r.f`, `x,`,
    // `s;`, `e?x`, `e!v`. A type variable `?X` is an operand instead.
    match bk {
        COLON2 | COLON2_STAR | DOT | COMMA | SEMI | BANG => return None,
        QUESTION if bp != Some(TYPE_VAR) => return None,
        _ => {}
    }
    if is_tight_open(a) {
        return if spaced_flag(ap) { Space } else { SoftNone };
    }
    if is_tight_close(b) {
        return if spaced_flag(bp) { Space } else { SoftNone };
    }
    // The two-character brackets are spaced inside: `(| a, b |)`,
    // `[| 1, 2 |]`, `<{ 1 }`.
    if matches!(ak, L_PAREN_PIPE | L_BRACK_PIPE | DEADLINE_OPEN) {
        return SoftSpace;
    }
    if matches!(bk, R_PAREN_PIPE | R_BRACK_PIPE) || (bk == R_CURLY && bp == Some(DEADLINE)) {
        return SoftSpace;
    }
    // Brackets glued to the name or keyword before them: calls, parameter
    // lists, `wait(`, `since(`, `vector(`, indexing, record literals and
    // trigger guards.
    match bk {
        L_PAREN
            if matches!(
                bp,
                Some(
                    ARG_LIST
                        | PARAM_LIST
                        | ENUM_LITERAL
                        | WAIT_STMT
                        | SINCE_EXPR
                        | SINCE_ENTRY_EXPR
                        | INVERSE_EXPR
                        | TRANSPOSE_EXPR
                        | VECTOR_TYPE
                        | MATRIX_TYPE
                )
            ) =>
        {
            return None
        }
        L_BRACK if matches!(bp, Some(INDEX_EXPR | INDEX_ACCESS)) => return None,
        L_PAREN_PIPE if bp == Some(RECORD_LITERAL) => return None,
        L_BRACK_PIPE if bp == Some(COMM_GUARD) => return None,
        _ => {}
    }
    // Everything else is spaced. These are the places where an author's
    // line break is kept: after separators, around operators, around the
    // parts of `if … then … else … end`, around binder `@` and `|`, and
    // before the clauses of an assertion.
    let soft = matches!(ak, COMMA | SEMI | AT | EQ)
        || (ak == PIPE && ap == Some(SUCH_THAT))
        || matches!(bk, AT | DEADLINE_OPEN | CSP_TEXT)
        || (bk == PIPE && bp == Some(SUCH_THAT))
        || is_operator(a)
        || is_operator(b)
        || (matches!(ak, THEN_KW | ELSE_KW) && matches!(ap, Some(IF_EXPR | IF_STMT)))
        || (matches!(bk, THEN_KW | ELSE_KW | END_KW) && matches!(bp, Some(IF_EXPR | IF_STMT)))
        || (bk == AND_KW && bp == Some(PARAM_ASSIGNMENTS))
        || starts(b, PARAM_ASSIGNMENTS)
        || starts(b, SEMANTIC_MODEL)
        || starts(b, ASSOCIATED_TO);
    if soft {
        SoftSpace
    } else {
        Space
    }
}
