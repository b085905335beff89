//! `prob property NAME : formula …` of probabilistic RoboChart, read as an
//! assertion that the native checker does not check (RoboTool checks it
//! with PRISM), so that reports list it instead of staying silent.

use robosim_syntax::{SyntaxKind::*, SyntaxNode, TextRange};

use super::{collapsed, gap_after, required_name, AssertionDecl, AssertionKind, SemanticModelName};

pub(super) fn read_prob_property(node: &SyntaxNode) -> AssertionDecl {
    let mut problems = Vec::new();
    let (name, name_range) = required_name(node, gap_after(node, &[IDENT]), "the property's name", &mut problems);
    let formula = node
        .children()
        .find(|c| !matches!(c.kind(), NAME | PROB_WITH_CONSTANTS))
        .map(|f| collapsed(&f))
        .unwrap_or_default();
    AssertionDecl {
        name,
        name_range,
        range: node.text_range(),
        text: collapsed(node),
        subject: Vec::new(),
        subject_range: TextRange::empty(node.text_range().start()),
        negated: false,
        kind: AssertionKind::Probabilistic { formula },
        timed: None,
        model: SemanticModelName::Default,
        model_range: None,
        overrides: Vec::new(),
        problems,
    }
}
