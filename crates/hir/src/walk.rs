//! Finding the few nodes of some kinds in a large tree.
//!
//! `SyntaxNode::descendants` allocates a cursor for every node it visits.
//! Rules that look for rare kinds (vector types, statement deadlines, clock
//! resets) scan the green tree instead, which allocates nothing, and build
//! cursors only along the paths to what they found.

use robosim_syntax::{RoboLang, SyntaxKind, SyntaxNode, TextRange, TextSize};
use rowan::{Language, NodeOrToken};

/// The descendants of `root` (itself included) whose kind satisfies
/// `wanted`, in preorder: the same nodes as
/// `root.descendants().filter(|n| wanted(n.kind()))`.
pub(crate) fn find_nodes(root: &SyntaxNode, wanted: impl Fn(SyntaxKind) -> bool) -> Vec<SyntaxNode> {
    find_nodes_pruned(root, wanted, |_| true)
}

/// Like [`find_nodes`], but does not look inside the nodes whose kind fails
/// `descend` (they are still returned when wanted): the same nodes as a
/// preorder walk that skips those subtrees.
pub(crate) fn find_nodes_pruned(
    root: &SyntaxNode,
    wanted: impl Fn(SyntaxKind) -> bool,
    descend: impl Fn(SyntaxKind) -> bool,
) -> Vec<SyntaxNode> {
    let mut out = Vec::new();
    if wanted(root.kind()) {
        out.push(root.clone());
    }
    if !descend(root.kind()) {
        return out;
    }
    let mut scan =
        Scan { wanted, descend, path: Vec::new(), emitted: 0, steps: Vec::new(), hits: Vec::new() };
    scan.collect(root.green(), root.text_range().start());
    out.reserve(scan.hits.len());
    // Paths come in preorder, so each one shares a prefix with the last:
    // keep the cursors of the last path and build only the rest.
    // `stack[d]` is the node at depth `d + 1` of the last path.
    let mut stack: Vec<SyntaxNode> = Vec::new();
    let mut start = 0;
    for hit in &scan.hits {
        stack.truncate(hit.keep as usize);
        let steps = &scan.steps[start..hit.end];
        start = hit.end;
        if stack.len() < hit.keep as usize {
            // An earlier step failed (it cannot: the paths were read off
            // this very tree); the deeper paths are lost with it.
            continue;
        }
        for step in steps {
            let parent = stack.last().unwrap_or(root);
            let Some(node) = child_at(parent, step) else { break };
            stack.push(node);
        }
        if stack.len() == hit.keep as usize + steps.len() {
            if let Some(n) = stack.last() {
                out.push(n.clone());
            }
        }
    }
    out
}

/// One step of a path: a child's index among all children (tokens
/// included) and its range.
#[derive(Clone, Copy)]
struct Step {
    index: u32,
    range: TextRange,
}

/// A wanted node: its path is the first `keep` steps of the previous hit's
/// path, then the steps recorded up to `end`.
struct Hit {
    keep: u32,
    end: usize,
}

struct Scan<W, D> {
    wanted: W,
    descend: D,
    /// The path to the node being scanned.
    path: Vec<Step>,
    /// How much of `path` the last hit's path shares.
    emitted: usize,
    /// The new steps of every hit, one after the other: one buffer, and
    /// only what differs from the previous hit's path.
    steps: Vec<Step>,
    hits: Vec<Hit>,
}

impl<W: Fn(SyntaxKind) -> bool, D: Fn(SyntaxKind) -> bool> Scan<W, D> {
    /// Records the path of every wanted node below `green` (at `offset`).
    fn collect(&mut self, green: &rowan::GreenNodeData, mut offset: TextSize) {
        for (i, child) in green.children().enumerate() {
            let len = child.text_len();
            if let NodeOrToken::Node(node) = child {
                let kind = RoboLang::kind_from_raw(node.kind());
                self.path.push(Step { index: i as u32, range: TextRange::at(offset, len) });
                if (self.wanted)(kind) {
                    self.steps.extend_from_slice(&self.path[self.emitted..]);
                    self.hits.push(Hit { keep: self.emitted as u32, end: self.steps.len() });
                    self.emitted = self.path.len();
                }
                if (self.descend)(kind) {
                    self.collect(node, offset);
                }
                self.path.pop();
                self.emitted = self.emitted.min(self.path.len());
            }
            offset += len;
        }
    }
}

/// The child node of `parent` at `step`: found by its range with a binary
/// search (one cursor), or by counting when empty nodes make the range
/// ambiguous.
fn child_at(parent: &SyntaxNode, step: &Step) -> Option<SyntaxNode> {
    if let Some(NodeOrToken::Node(n)) = parent.child_or_token_at_range(step.range) {
        if n.index() == step.index as usize {
            return Some(n);
        }
    }
    parent.children_with_tokens().nth(step.index as usize)?.into_node()
}

#[cfg(test)]
mod tests {
    use super::*;
    use robosim_syntax::{FileKind, SyntaxKind::*};

    #[test]
    fn finds_the_same_nodes_as_descendants() {
        let text = "stm M { var x : vector(real, 2) clock C initial i state S { entry #C; x = x }\n\
                    transition t { from i to S trigger e #C condition since(C) > 1 } }";
        let root = robosim_syntax::parse(text, FileKind::RoboChart).syntax_node();
        for kinds in [&[VECTOR_TYPE][..], &[CLOCK_RESET, CLOCK_RESET_STMT, SINCE_EXPR], &[SOURCE_FILE], &[REF_EXPR]] {
            let fast = find_nodes(&root, |k| kinds.contains(&k));
            let slow: Vec<SyntaxNode> = root.descendants().filter(|n| kinds.contains(&n.kind())).collect();
            assert!(!slow.is_empty(), "{kinds:?}");
            assert_eq!(fast, slow, "{kinds:?}");
        }
    }

    #[test]
    fn pruned_finds_the_same_nodes_as_a_skipping_preorder() {
        let text = "stm M { var x : nat = 1 + 2 state S { entry x = (x + 1) * 2; e?x } transition t { from S to S condition x > 1 /\\ x < 2 } }\n\
                    stm N { state ( }";
        let root = robosim_syntax::parse(text, FileKind::RoboChart).syntax_node();
        let descend = |k: SyntaxKind| k != BIN_EXPR;
        let wanted = |k: SyntaxKind| matches!(k, BIN_EXPR | REF_EXPR | ASSIGN_STMT | STATE | ERROR);
        let mut slow = Vec::new();
        let mut events = root.preorder();
        while let Some(event) = events.next() {
            let rowan::WalkEvent::Enter(n) = event else { continue };
            if wanted(n.kind()) {
                slow.push(n.clone());
            }
            if !descend(n.kind()) {
                events.skip_subtree();
            }
        }
        assert!(!slow.is_empty());
        assert_eq!(find_nodes_pruned(&root, wanted, descend), slow);
    }
}
