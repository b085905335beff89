//! Incremental reparsing: after an edit inside one top-level member of a
//! model file (a machine, controller, module, interface, …), only that
//! member is lexed and parsed again and its node is swapped into the old
//! tree. The result is always exactly what [`parse`] gives for the new text
//! (the tests compare the two over the corpus under random edits); whenever
//! that cannot be guaranteed cheaply the whole file is parsed instead.
//!
//! Why it is exact. The edit must leave the member's first token and its
//! closing `}` untouched, so the text before the member and after it is the
//! same: the lexer reaches the member in the same state and, since the new
//! member lexes on its own without any error and still ends with its `}`
//! (which nothing can extend), it produces the same tokens there and after.
//! The parser reaches a top-level member with nothing but the file's block
//! open, which is the context [`crate::grammar::top_level_member`] recreates;
//! what came before only ever looked at the member's first token (a keyword:
//! the grammar peeks a second token only after a name or a punctuation mark),
//! and the member must end exactly at its `}`, so the rest of the file sees
//! the same tokens in the same state. Errors inside the member are replaced
//! and errors after it shifted; an error sitting exactly on the member's
//! boundary could belong to either side, so it makes us parse everything.
//! So does an unterminated comment, string or CSP block before the member,
//! since the lexer searched the rest of the file for its end.

use crate::kinds::SyntaxKind::R_CURLY;
use crate::{grammar, lexer, parse, parser, Parse, Severity, SyntaxError, SyntaxNode, TextRange, TextSize};

/// Parses `new_text`, reusing `old`, the parse of `old_text`, when the two
/// differ inside one top-level member. Same result as
/// `parse(new_text, old.file_kind())`.
pub fn reparse(old: &Parse, old_text: &str, new_text: &str) -> Parse {
    try_reparse(old, old_text, new_text).unwrap_or_else(|| parse(new_text, old.file_kind()))
}

/// The incremental path of [`reparse`] alone: `None` when the edit is not
/// confined to one top-level member (or the text does not match `old`).
pub fn try_reparse(old: &Parse, old_text: &str, new_text: &str) -> Option<Parse> {
    if old_text == new_text {
        return Some(old.clone());
    }
    let kind = old.file_kind();
    if kind.is_assertions() || u32::from(old.green().text_len()) as usize != old_text.len() {
        return None;
    }
    let (old_edit, delta) = changed_range(old_text, new_text);
    let root = old.syntax_node();
    let member = enclosing_member(&root, old_edit)?;
    let old_range = member.text_range();
    let new_end = usize::from(old_range.end()).checked_add_signed(delta)?;
    let member_text = new_text.get(usize::from(old_range.start())..new_end)?;

    let (before, after) = split_errors(old.errors(), old_range)?;
    if before.iter().any(|e| opens_to_end_of_file(&root, e)) {
        return None;
    }
    let (green, member_errors) = parse_member(member_text, kind)?;

    // Inside the member, ranges were relative to its start; after it, they
    // move with its end.
    let new_member_end = TextSize::from(new_end as u32);
    let mut errors = before;
    errors.extend(member_errors.into_iter().map(|mut e| {
        e.range += old_range.start();
        e
    }));
    errors.extend(after.into_iter().map(|mut e| {
        e.range = e.range - old_range.end() + new_member_end;
        e
    }));
    Some(Parse { green: member.replace_with(green), errors: errors.into(), file: kind })
}

/// The range of `old` that was replaced, and how much longer the new text
/// is: the longest common prefix and suffix are kept.
fn changed_range(old: &str, new: &str) -> (TextRange, isize) {
    let (o, n) = (old.as_bytes(), new.as_bytes());
    let mut prefix = common_prefix(o, n);
    let room = o.len().min(n.len()) - prefix;
    let mut suffix = common_suffix(&o[o.len() - room..], &n[n.len() - room..]);
    // Keep both ends on character boundaries (the bytes around them are the
    // same in both texts, so one check serves both).
    while !old.is_char_boundary(prefix) {
        prefix -= 1;
    }
    while !old.is_char_boundary(o.len() - suffix) {
        suffix -= 1;
    }
    let range = TextRange::new(TextSize::from(prefix as u32), TextSize::from((o.len() - suffix) as u32));
    (range, n.len() as isize - o.len() as isize)
}

/// Bytes compared at once by [`common_prefix`] and [`common_suffix`]:
/// slices compare with `memcmp`, where a byte at a time cost a tenth of a
/// keystroke's whole check on a 10,000-line file.
const CHUNK: usize = 64;

/// How many bytes `a` and `b` have in common from the start.
fn common_prefix(a: &[u8], b: &[u8]) -> usize {
    let n = a.len().min(b.len());
    let mut i = 0;
    while i + CHUNK <= n && a[i..i + CHUNK] == b[i..i + CHUNK] {
        i += CHUNK;
    }
    i + a[i..n].iter().zip(&b[i..n]).take_while(|(x, y)| x == y).count()
}

/// How many bytes `a` and `b` have in common at the end.
fn common_suffix(a: &[u8], b: &[u8]) -> usize {
    let n = a.len().min(b.len());
    let (a, b) = (&a[a.len() - n..], &b[b.len() - n..]);
    let mut k = 0;
    while k + CHUNK <= n && a[n - k - CHUNK..n - k] == b[n - k - CHUNK..n - k] {
        k += CHUNK;
    }
    k + a[..n - k].iter().rev().zip(b[..n - k].iter().rev()).take_while(|(x, y)| x == y).count()
}

/// The top-level member whose inside (after its first token and before its
/// closing `}`) contains `edit`.
fn enclosing_member(root: &SyntaxNode, edit: TextRange) -> Option<SyntaxNode> {
    let member = root.children().find(|n| n.text_range().contains_range(edit))?;
    let first = member.first_token()?;
    let last = member.last_token()?;
    let inside = first.text_range().end() <= edit.start() && edit.end() <= last.text_range().start();
    (inside && !first.kind().is_trivia() && last.kind() == R_CURLY).then_some(member)
}

/// Whether `error` is an unterminated comment, string or CSP block: the
/// lexer looked for its end through the rest of the file, so text inserted
/// anywhere after it may end it and change every token in between.
fn opens_to_end_of_file(root: &SyntaxNode, error: &SyntaxError) -> bool {
    use crate::SyntaxKind::{BLOCK_COMMENT, CSP_TEXT, STRING};
    let at = error.range.start();
    root.token_at_offset(at)
        .any(|t| t.text_range().start() == at && matches!(t.kind(), BLOCK_COMMENT | STRING | CSP_TEXT))
}

/// The errors before and after `member`; `None` when one starts at its
/// first token, sits on its end or straddles it.
fn split_errors(errors: &[SyntaxError], member: TextRange) -> Option<(Vec<SyntaxError>, Vec<SyntaxError>)> {
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for e in errors {
        let r = e.range;
        // The previous member's parse looks at this member's first token and
        // may complain there; an empty range at either end may belong to
        // either side.
        let on_boundary = r.start() == member.start() || (r.is_empty() && r.start() == member.end());
        if on_boundary {
            return None;
        } else if r.end() <= member.start() {
            before.push(e.clone());
        } else if r.start() >= member.end() {
            after.push(e.clone());
        } else if !member.contains_range(r) {
            return None;
        }
    }
    Some((before, after))
}

/// The green node of one top-level member and its errors (relative to
/// its start), when `text` lexes cleanly and parses as exactly one member
/// ending at its last `}`.
fn parse_member(text: &str, kind: crate::FileKind) -> Option<(rowan::GreenNode, Vec<SyntaxError>)> {
    let (tokens, lex_errors, input) = lexer::lex_for_parser(text, kind);
    let (first, last) = (tokens.first()?, tokens.last()?);
    if !lex_errors.is_empty() || first.kind.is_trivia() || last.kind != R_CURLY {
        return None;
    }
    let mut p = parser::Parser::new(&input, &tokens, text, kind);
    if !grammar::top_level_member(&mut p) {
        return None;
    }
    let (root, mut errors) = p.finish();
    let len = TextSize::of(text);
    if errors.iter().any(|e| e.range.start() == 0.into() || (e.range.is_empty() && e.range.start() == len)) {
        return None;
    }
    // As `parse` does for the whole file.
    errors.sort_by_key(|e| (e.range.start(), e.range.end()));
    errors.dedup_by(|later, first| first.severity == Severity::Error && later.range.start() == first.range.start());
    let mut children = root.children();
    let node = children.next()?.into_node()?.to_owned();
    children.next().is_none().then_some((node, errors))
}

#[cfg(test)]
mod tests {
    use super::{common_prefix, common_suffix, CHUNK};

    /// The chunked comparisons agree with a byte at a time, for every
    /// place of the difference around chunk boundaries.
    #[test]
    fn common_prefix_and_suffix_agree_with_bytewise() {
        for len in [0, 1, CHUNK - 1, CHUNK, CHUNK + 1, 3 * CHUNK + 5] {
            let a: Vec<u8> = (0..len).map(|i| (i % 251) as u8).collect();
            for at in 0..len {
                for extra in [0usize, 1, CHUNK + 2] {
                    let mut b = a.clone();
                    b[at] ^= 0xff;
                    b.extend(std::iter::repeat_n(7u8, extra));
                    let prefix = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
                    assert_eq!(common_prefix(&a, &b), prefix, "len {len}, at {at}, extra {extra}");
                    let suffix = a.iter().rev().zip(b.iter().rev()).take_while(|(x, y)| x == y).count();
                    assert_eq!(common_suffix(&a, &b), suffix, "len {len}, at {at}, extra {extra}");
                    let mut c = vec![9u8; extra];
                    c.extend(&b[..len]);
                    let suffix = a.iter().rev().zip(c.iter().rev()).take_while(|(x, y)| x == y).count();
                    assert_eq!(common_suffix(&a, &c), suffix, "len {len}, at {at}, extra {extra} (front)");
                }
            }
        }
    }
}
