//! Finding the few nodes of some kinds in a large tree.
//!
//! `SyntaxNode::descendants` allocates a cursor for every node it visits.
//! Rules that look for rare kinds (vector types, statement deadlines, clock
//! resets) scan the green tree instead, which allocates nothing, and build
//! cursors only along the paths to what they found.

use robosim_syntax::{RoboLang, SyntaxKind, SyntaxNode};
use rowan::{Language, NodeOrToken};

/// The descendants of `root` (itself included) whose kind satisfies
/// `wanted`, in preorder: the same nodes as
/// `root.descendants().filter(|n| wanted(n.kind()))`.
pub(crate) fn find_nodes(root: &SyntaxNode, wanted: impl Fn(SyntaxKind) -> bool) -> Vec<SyntaxNode> {
    let mut paths = Vec::new();
    let mut path = Vec::new();
    collect(root.green(), &wanted, &mut path, &mut paths);
    let mut out = Vec::with_capacity(paths.len() + 1);
    if wanted(root.kind()) {
        out.push(root.clone());
    }
    // Paths come in preorder, so each one shares a prefix with the last and
    // then moves right: keep the cursors of the last path and step from
    // them, visiting each child of an ancestor at most once overall.
    // `stack[d]` is the child index and node at depth `d + 1`.
    let mut stack: Vec<(usize, SyntaxNode)> = Vec::new();
    let mut prev: &[usize] = &[];
    for p in &paths {
        let common = p.iter().zip(prev).take_while(|(a, b)| a == b).count();
        // Reuse the node at depth `common` as the starting sibling.
        stack.truncate(common + 1);
        for level in common..p.len() {
            let start = if stack.len() > level {
                stack.pop().map(|(i, n)| (i, rowan::NodeOrToken::Node(n)))
            } else {
                let parent = if level == 0 { root } else { &stack[level - 1].1 };
                parent.first_child_or_token().map(|e| (0, e))
            };
            let Some((mut idx, mut elem)) = start else { break };
            while idx < p[level] {
                let Some(next) = elem.next_sibling_or_token() else { break };
                elem = next;
                idx += 1;
            }
            // The path was read off this very tree, so this is its node.
            let Some(node) = elem.into_node() else { break };
            stack.push((idx, node));
        }
        if stack.len() == p.len() {
            if let Some((_, n)) = stack.last() {
                out.push(n.clone());
            }
        }
        prev = p;
    }
    out
}

/// Pushes the child-index path of every wanted node below `green`.
fn collect(
    green: &rowan::GreenNodeData,
    wanted: &impl Fn(SyntaxKind) -> bool,
    path: &mut Vec<usize>,
    paths: &mut Vec<Vec<usize>>,
) {
    for (i, child) in green.children().enumerate() {
        if let NodeOrToken::Node(node) = child {
            path.push(i);
            if wanted(RoboLang::kind_from_raw(node.kind())) {
                paths.push(path.clone());
            }
            collect(node, wanted, path, paths);
            path.pop();
        }
    }
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
}
