//! Foldable regions: bodies in braces, block comments, runs of line
//! comments, runs of imports, CSP blocks (and inside them `Timed` sections,
//! definitions and `{- -}` comments) and multi-line assertions. Only
//! regions that span more than one line are reported.

use robosim_hir::{Db, File};
use robosim_syntax::{SyntaxElement, SyntaxKind::*, SyntaxNode, TextRange, TextSize};

/// What a fold hides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FoldKind {
    /// A body in braces, or another multi-line construct.
    Region,
    /// A block comment or consecutive line comments.
    Comment,
    /// Consecutive imports.
    Imports,
    /// The text of a CSP block.
    Csp,
}

/// One foldable region.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fold {
    /// From the first to the last byte of the region (the braces included).
    pub range: TextRange,
    /// What it is.
    pub kind: FoldKind,
}

pub(crate) fn folding_ranges(db: &dyn Db, file: File) -> Vec<Fold> {
    let text = file.text(db);
    let root = robosim_hir::parse(db, file).syntax_node();
    let mut folds = Vec::new();
    let mut comments: Option<TextRange> = None;
    let mut imports: Option<TextRange> = None;
    let push = |folds: &mut Vec<Fold>, range: TextRange, kind: FoldKind| {
        let slice = text.get(usize::from(range.start())..usize::from(range.end())).unwrap_or("");
        if slice.contains('\n') {
            folds.push(Fold { range, kind });
        }
    };
    for (i, el) in root.descendants_with_tokens().enumerate() {
        if i % 4096 == 4095 {
            crate::check_cancelled(db);
        }
        match el {
            SyntaxElement::Node(node) => {
                if let Some(range) = brace_block(&node) {
                    push(&mut folds, range, FoldKind::Region);
                }
                match node.kind() {
                    ASSERTION => push(&mut folds, node.text_range(), FoldKind::Region),
                    IMPORT => {
                        let r = node.text_range();
                        // Imports are top-level siblings: a run continues
                        // when only trivia lies between two of them.
                        imports = Some(match imports {
                            Some(run) if only_trivia_between(&root, run.end(), r.start()) => run.cover(r),
                            Some(run) => {
                                push(&mut folds, run, FoldKind::Imports);
                                r
                            }
                            None => r,
                        });
                    }
                    _ => {}
                }
            }
            SyntaxElement::Token(token) => match token.kind() {
                LINE_COMMENT => {
                    // The token ends with its newline, which the fold
                    // must not include.
                    let r = token.text_range();
                    let trimmed = TextSize::of(token.text().trim_end());
                    let r = TextRange::at(r.start(), trimmed);
                    comments = Some(comments.map_or(r, |run| run.cover(r)));
                }
                WHITESPACE if !token.text().contains('\n') => {}
                _ => {
                    if let Some(run) = comments.take() {
                        push(&mut folds, run, FoldKind::Comment);
                    }
                    match token.kind() {
                        BLOCK_COMMENT => push(&mut folds, token.text_range(), FoldKind::Comment),
                        CSP_TEXT => push(&mut folds, token.text_range(), FoldKind::Csp),
                        _ => {}
                    }
                }
            },
        }
    }
    if let Some(run) = comments {
        push(&mut folds, run, FoldKind::Comment);
    }
    if let Some(run) = imports {
        push(&mut folds, run, FoldKind::Imports);
    }
    crate::csp_block::folds(db, file, &mut folds);
    folds.sort_by_key(|f| (f.range.start(), std::cmp::Reverse(f.range.end())));
    folds
}

/// `{` … `}` of a node, when the braces are its own tokens (declaration
/// bodies, deadlines, set literals). Without a `}` (broken source) the body
/// runs to the end of the node.
fn brace_block(node: &SyntaxNode) -> Option<TextRange> {
    let mut open = None;
    for el in node.children_with_tokens() {
        match el.kind() {
            L_CURLY if open.is_none() => open = Some(el.text_range().start()),
            R_CURLY => {
                if let Some(start) = open {
                    return Some(TextRange::new(start, el.text_range().end()));
                }
            }
            _ => {}
        }
    }
    open.map(|start| TextRange::new(start, node.text_range().end()))
}

fn only_trivia_between(root: &SyntaxNode, start: TextSize, end: TextSize) -> bool {
    if start >= end {
        return true;
    }
    let mut offset = start;
    while offset < end {
        let Some(token) = root.token_at_offset(offset).right_biased() else { return false };
        if !token.kind().is_trivia() {
            return false;
        }
        offset = token.text_range().end();
    }
    true
}
