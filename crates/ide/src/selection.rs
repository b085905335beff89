//! Expanding selections: the token under the cursor, then each enclosing
//! node of the syntax tree.

use robosim_hir::{Db, File};
use robosim_syntax::{SyntaxKind, SyntaxToken, TextRange, TextSize};
use rowan::TokenAtOffset;

pub(crate) fn selection_ranges(db: &dyn Db, file: File, offset: TextSize) -> Vec<TextRange> {
    let root = robosim_hir::parse(db, file).syntax_node();
    let offset = offset.min(root.text_range().end());
    let token = match root.token_at_offset(offset) {
        TokenAtOffset::None => return vec![TextRange::empty(offset)],
        TokenAtOffset::Single(t) => t,
        TokenAtOffset::Between(left, right) => better(left, right),
    };
    let mut out = Vec::new();
    if token.kind() != SyntaxKind::WHITESPACE {
        out.push(token.text_range());
    } else {
        // Between words, start with the caret itself, as editors do.
        out.push(TextRange::empty(offset));
    }
    for node in token.parent_ancestors() {
        let r = node.text_range();
        if out.last() != Some(&r) {
            out.push(r);
        }
    }
    out
}

/// At a boundary between two tokens, the one that means something: a name
/// or keyword over punctuation, anything over whitespace.
fn better(left: SyntaxToken, right: SyntaxToken) -> SyntaxToken {
    let rank = |t: &SyntaxToken| match t.kind() {
        k if k.is_trivia() => 0,
        k if k.is_punct() => 1,
        _ => 2,
    };
    if rank(&right) >= rank(&left) {
        right
    } else {
        left
    }
}
