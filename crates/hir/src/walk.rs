//! Finding the nodes of some kinds in a large tree.
//!
//! `SyntaxNode::descendants` allocates a cursor for every node it visits.
//! Instead, one scan of the green tree per parse, which allocates nothing,
//! records where the nodes that resolution, typing and the rules look for
//! are ([`file_nodes`]); each query then builds cursors only along the
//! paths to the nodes it asks for, or none at all for nodes it can read
//! from their green tree.

use robosim_syntax::{ast, RoboLang, SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange, TextSize};
use rowan::{Language, NodeOrToken};

use crate::{parse, Db, File};

/// One step of a path: a child's index among all children (tokens
/// included) and its range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Step {
    index: u32,
    range: TextRange,
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

/// The kinds [`file_nodes`] records: those the per-keystroke queries look
/// for (typed positions, names in behaviour, type names, clocks, sizes).
pub(crate) fn recorded(k: SyntaxKind) -> bool {
    matches!(
        k,
        // Typed positions.
        CONDITION
            | PRECONDITION
            | POSTCONDITION
            | VARIABLE
            | ASSIGN_STMT
            | IF_STMT
            | WAIT_STMT
            | CALL_STMT
            | SIM_CALL_STMT
            | COMMUNICATION
            | OUTPUT_COMM_STMT
            | PROBABILITY
            | ENTRY_ACTION
            | DURING_ACTION
            | EXIT_ACTION
            | TRANSITION_ACTION
            // Names in behaviour.
            | REF_EXPR
            | SIM_REF_EXPR
            | ENUM_LITERAL_EXPR
            | COMM_STMT
            | SINCE_ENTRY_EXPR
            | COMM_INPUT
            // Declaration-level names and clocks.
            | NAMED_TYPE
            | CLOCK_RESET
            | CLOCK_RESET_STMT
            | SINCE_EXPR
            // Sizes and deadlines.
            | VECTOR_TYPE
            | MATRIX_TYPE
            | TIMED_STMT
    )
}

/// Where the nodes of the [`recorded`] kinds are in a file's tree: several
/// queries look for them after every keystroke, and one scan of the tree
/// serves them all.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct NodeTable {
    /// The recorded nodes and their ancestors, each once, parents first.
    places: Vec<Place>,
    /// The recorded nodes, in preorder.
    hits: Vec<TableHit>,
}

/// A node on the path to a recorded one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Place {
    /// Index in `places` of the parent (`NONE` for a child of the root).
    parent: u32,
    /// Depth below the root (its children: 1).
    depth: u32,
    step: Step,
}

const NONE: u32 = u32::MAX;

#[derive(Debug, Clone, PartialEq, Eq)]
struct TableHit {
    kind: SyntaxKind,
    /// Whether an expression or a type encloses the node.
    nested: bool,
    /// Whether an expression that [`binds`] names encloses the node.
    bound: bool,
    /// Index in `places`.
    place: u32,
}

/// The [`NodeTable`] of `file`.
#[salsa::tracked(returns(ref), no_eq)]
pub(crate) fn file_nodes(db: &dyn Db, file: File) -> NodeTable {
    node_table(&parse(db, file).syntax_node())
}

/// Scans the tree below `root` for the [`recorded`] kinds.
pub(crate) fn node_table(root: &SyntaxNode) -> NodeTable {
    let mut scan = TableScan { path: Vec::new(), placed: Vec::new(), nested: 0, bound: 0, out: NodeTable::default() };
    scan.collect(root.green(), root.text_range().start());
    scan.out
}

struct TableScan {
    /// The path to the node being scanned.
    path: Vec<Step>,
    /// The places of the first entries of `path` that have one.
    placed: Vec<u32>,
    /// How many expressions and types enclose the node being scanned.
    nested: u32,
    /// How many of those bind names.
    bound: u32,
    out: NodeTable,
}

/// Whether expressions of kind `k` bind names for their operands
/// (quantifiers, `lambda`, set comprehensions, `the`, `let`).
pub(crate) fn binds(k: SyntaxKind) -> bool {
    matches!(k, FORALL_EXPR | EXISTS_EXPR | LAMBDA_EXPR | THE_EXPR | SET_COMP_EXPR | LET_EXPR)
}

/// A node [`NodeTable::found`] gives: a cursor, or only its green node
/// and range when the caller can do without a cursor.
pub(crate) enum Found {
    /// The node.
    Node(SyntaxNode),
    /// The node's green tree and range.
    Green(rowan::GreenNode, TextRange),
}

impl TableScan {
    fn collect(&mut self, green: &rowan::GreenNodeData, mut offset: TextSize) {
        for (i, child) in green.children().enumerate() {
            let len = child.text_len();
            if let NodeOrToken::Node(node) = child {
                let kind = RoboLang::kind_from_raw(node.kind());
                self.path.push(Step { index: i as u32, range: TextRange::at(offset, len) });
                if recorded(kind) {
                    // Give this node and its ancestors places, once.
                    for d in self.placed.len()..self.path.len() {
                        let parent = d.checked_sub(1).map_or(NONE, |p| self.placed[p]);
                        self.placed.push(self.out.places.len() as u32);
                        self.out.places.push(Place { parent, depth: d as u32 + 1, step: self.path[d] });
                    }
                    let place = self.placed[self.path.len() - 1];
                    self.out.hits.push(TableHit { kind, nested: self.nested > 0, bound: self.bound > 0, place });
                }
                let wraps = ast::is_expr_kind(kind) || ast::is_type_kind(kind);
                let binding = binds(kind);
                self.nested += wraps as u32;
                self.bound += binding as u32;
                self.collect(node, offset);
                self.nested -= wraps as u32;
                self.bound -= binding as u32;
                self.path.pop();
                self.placed.truncate(self.path.len());
            }
            offset += len;
        }
    }
}

impl NodeTable {
    /// The nodes below `root` (the root of the tree the table was made
    /// from) whose kind is one of `kinds`, each of them [`recorded`], in
    /// preorder; with `outside_exprs`, only those no expression or type
    /// encloses.
    pub(crate) fn nodes(&self, root: &SyntaxNode, kinds: &[SyntaxKind], outside_exprs: bool) -> Vec<SyntaxNode> {
        let found = self.found(root, kinds, outside_exprs, |_, _| false);
        found.into_iter().filter_map(|f| if let Found::Node(n) = f { Some(n) } else { None }).collect()
    }

    /// Like [`NodeTable::nodes`], but gives the green node (no cursor) of
    /// the nodes for which `green_ok(kind, bound)` holds, `bound` saying
    /// whether an expression that [`binds`] names encloses the node.
    pub(crate) fn found(
        &self,
        root: &SyntaxNode,
        kinds: &[SyntaxKind],
        outside_exprs: bool,
        green_ok: impl Fn(SyntaxKind, bool) -> bool,
    ) -> Vec<Found> {
        debug_assert!(kinds.iter().all(|k| recorded(*k)), "{kinds:?}");
        // Every hit of the file is tested: a table by kind rather than a
        // search of `kinds`.
        let mut wanted = vec![false; kinds.iter().map(|k| *k as usize + 1).max().unwrap_or(0)];
        for &k in kinds {
            wanted[k as usize] = true;
        }
        let is_wanted = |k: SyntaxKind| wanted.get(k as usize).copied().unwrap_or(false);
        let mut out = Vec::new();
        // Cursors for the path to the last node built: `stack[d]` is at
        // depth `d + 1`, with its place. Each node shares a prefix of it.
        let mut stack: Vec<(u32, SyntaxNode)> = Vec::new();
        let mut chain: Vec<u32> = Vec::new();
        for hit in &self.hits {
            if !is_wanted(hit.kind) || (outside_exprs && hit.nested) {
                continue;
            }
            if green_ok(hit.kind, hit.bound) {
                if let Some(found) = self.green_at(root, hit.place, &mut chain) {
                    out.push(found);
                    continue;
                }
            }
            // Up from the node to the deepest place the stack has.
            chain.clear();
            let mut id = hit.place;
            let mut common = 0;
            while id != NONE {
                let place = &self.places[id as usize];
                let d = place.depth as usize;
                if stack.get(d - 1).is_some_and(|(p, _)| *p == id) {
                    common = d;
                    break;
                }
                chain.push(id);
                id = place.parent;
            }
            stack.truncate(common);
            for &id in chain.iter().rev() {
                let parent = stack.last().map_or(root, |(_, n)| n);
                // The path was read off this very tree, so the child is there.
                let Some(node) = child_at(parent, &self.places[id as usize].step) else { break };
                stack.push((id, node));
            }
            if stack.last().is_some_and(|(p, _)| *p == hit.place) {
                out.push(Found::Node(stack[stack.len() - 1].1.clone()));
            }
        }
        out
    }

    /// The green node at `place`, read down from the root (no cursor).
    fn green_at(&self, root: &SyntaxNode, place: u32, chain: &mut Vec<u32>) -> Option<Found> {
        chain.clear();
        let mut id = place;
        while id != NONE {
            chain.push(id);
            id = self.places[id as usize].parent;
        }
        let mut green = root.green();
        for &id in chain.iter().rev() {
            let step = &self.places[id as usize].step;
            green = green.children().nth(step.index as usize)?.into_node()?;
        }
        Some(Found::Green(green.to_owned(), self.places[place as usize].step.range))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_finds_the_same_nodes_as_a_walk() {
        let text = "stm M { var x : vector(real, 2) = 1 + 2 clock C initial i state S { entry x = (x + 1) * 2; e?x; #C }\n\
                    transition t { from i to S trigger e #C condition since(C) > 1 /\\ x < (x as nat) action wait(1) } }\n\
                    function f(a : Set(nat)) : boolean { precondition forall y : nat | y in a @ y > 0 }\n\
                    stm N { state ( }";
        let root = robosim_syntax::parse(text, robosim_syntax::FileKind::RoboChart).syntax_node();
        let table = node_table(&root);
        let all: Vec<SyntaxKind> = (0..=u16::MAX).map_while(SyntaxKind::from_raw).filter(|k| recorded(*k)).collect();
        let sets = [&all[..], &[REF_EXPR], &[NAMED_TYPE, CLOCK_RESET, SINCE_EXPR], &[VARIABLE, ASSIGN_STMT, CONDITION]];
        let outside = |n: &SyntaxNode| {
            n.ancestors().skip(1).all(|a| !ast::is_expr_kind(a.kind()) && !ast::is_type_kind(a.kind()))
        };
        for set in sets {
            let slow: Vec<SyntaxNode> = root.descendants().filter(|n| set.contains(&n.kind())).collect();
            assert!(!slow.is_empty(), "{set:?}");
            assert_eq!(table.nodes(&root, set, false), slow, "{set:?}");
            let slow: Vec<SyntaxNode> = slow.into_iter().filter(outside).collect();
            assert_eq!(table.nodes(&root, set, true), slow, "{set:?}");
        }
        // Green nodes stand for the same nodes, and `bound` says whether a
        // binding expression encloses them.
        let slow: Vec<SyntaxNode> = root.descendants().filter(|n| n.kind() == REF_EXPR).collect();
        let found = table.found(&root, &[REF_EXPR], false, |_, bound| !bound);
        assert_eq!(found.len(), slow.len());
        let mut greens = 0;
        for (f, n) in found.iter().zip(&slow) {
            let bound = n.ancestors().skip(1).any(|a| binds(a.kind()));
            match f {
                Found::Green(g, range) => {
                    assert!(!bound);
                    assert_eq!((&**g, *range), (n.green(), n.text_range()));
                    greens += 1;
                }
                Found::Node(m) => assert!(bound && m == n),
            }
        }
        assert!(greens > 0 && greens < slow.len());
    }
}
