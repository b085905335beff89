//! Highlighting from the syntax tree alone: lexical classes (keywords,
//! numbers, strings, comments), names in type positions, RoboSim's `$`
//! references, declaration names by what they declare, and the references
//! whose kind the grammar fixes (`from`/`to` name states, `#C` clocks, a
//! trigger's first name an event, …). Other references wait for name
//! resolution; the editor's grammar colours them meanwhile.

use robosim_hir::{Db, File};
use robosim_syntax::{SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange, TextSize};

use crate::symbols::SymbolKind;

/// What a highlighted range is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HlTag {
    /// A reserved word.
    Keyword,
    /// A name in a type position, or a type constructor (`Set(`).
    Type,
    /// A numeric literal.
    Number,
    /// A string literal.
    String,
    /// A comment.
    Comment,
    /// A RoboSim `$` reference: the `$` and the name after it.
    SimRef,
    /// A name of a known kind, declared here or referenced.
    Symbol(SymbolKind),
}

/// One highlighted range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct HlRange {
    /// Where, in bytes.
    pub range: TextRange,
    /// What it is.
    pub tag: HlTag,
    /// Whether this is the declaring occurrence of a name.
    pub declaration: bool,
}

pub(crate) fn highlight(db: &dyn Db, file: File) -> Vec<HlRange> {
    let root = robosim_hir::parse(db, file).syntax_node();
    let mut out = Vec::new();
    for (i, token) in root.descendants_with_tokens().filter_map(|e| e.into_token()).enumerate() {
        // Walking a large file takes milliseconds: stay responsive to edits.
        if i % 4096 == 4095 {
            crate::check_cancelled(db);
        }
        if let Some((tag, declaration, range)) = classify(&token) {
            out.push(HlRange { range, tag, declaration });
        }
    }
    out
}

fn classify(token: &SyntaxToken) -> Option<(HlTag, bool, TextRange)> {
    let range = token.text_range();
    let kind = token.kind();
    let tag = match kind {
        WHITESPACE | CSP_TEXT | ERROR_TOKEN => return None,
        LINE_COMMENT | BLOCK_COMMENT => HlTag::Comment,
        INT_NUMBER | FLOAT_NUMBER => HlTag::Number,
        STRING => HlTag::String,
        DOLLAR => HlTag::SimRef,
        SET_OPEN | SEQ_OPEN => {
            // `Set(` is one token; only the word is the type.
            let word = TextRange::at(range.start(), TextSize::from(3));
            return Some((HlTag::Type, false, word));
        }
        IDENT => return classify_name(token).map(|(t, d)| (t, d, range)),
        k if k.is_keyword() => {
            // A reserved word written where a name belongs (reported as an
            // error) is still shown as the name it was meant to be.
            if let Some(named) = classify_name(token) {
                return Some((named.0, named.1, range));
            }
            HlTag::Keyword
        }
        _ => return None,
    };
    Some((tag, false, range))
}

/// Identifiers (and keywords in name positions): by their place in the tree.
fn classify_name(token: &SyntaxToken) -> Option<(HlTag, bool)> {
    let parent = token.parent()?;
    match parent.kind() {
        NAME => {
            let decl = parent.parent()?;
            let kind = SymbolKind::of_declaration(&decl)?;
            Some((HlTag::Symbol(kind), true))
        }
        NAME_REF => name_ref_tag(&parent).map(|t| (t, false)),
        QUALIFIED_NAME => qualified_name_tag(&parent).map(|t| (t, false)),
        _ => None,
    }
}

fn name_ref_tag(name_ref: &SyntaxNode) -> Option<HlTag> {
    let context = name_ref.parent()?;
    Some(match context.kind() {
        TRANSITION_SOURCE | TRANSITION_TARGET => HlTag::Symbol(SymbolKind::State),
        CLOCK_RESET | CLOCK_RESET_STMT | SINCE_EXPR => HlTag::Symbol(SymbolKind::Clock),
        // The event of a communication is its first name; later names are
        // payload variables or values.
        COMMUNICATION if is_first_node(name_ref) => HlTag::Symbol(SymbolKind::Event),
        FIELD_ACCESS => HlTag::Symbol(SymbolKind::Field),
        CONNECTION => {
            // `connection A on e to B on f`: nodes and events alternate.
            let index = context.children().filter(|n| n.kind() == NAME_REF).position(|n| &n == name_ref)?;
            if index.is_multiple_of(2) {
                HlTag::Symbol(SymbolKind::Controller)
            } else {
                HlTag::Symbol(SymbolKind::Event)
            }
        }
        REF_EXPR if context.parent().is_some_and(|p| p.kind() == CALL_EXPR) && is_first_node(&context) => {
            HlTag::Symbol(SymbolKind::Function)
        }
        _ => return None,
    })
}

fn qualified_name_tag(name: &SyntaxNode) -> Option<HlTag> {
    if prev_non_trivia_is_dollar(name) {
        return Some(HlTag::SimRef);
    }
    let context = name.parent()?;
    Some(match context.kind() {
        NAMED_TYPE => HlTag::Type,
        PACKAGE_DECL | IMPORT => HlTag::Symbol(SymbolKind::Package),
        INTERFACE_USE => HlTag::Symbol(SymbolKind::Interface),
        PLATFORM_REF => HlTag::Symbol(SymbolKind::Platform),
        CONTROLLER_REF => HlTag::Symbol(SymbolKind::Controller),
        STATE_MACHINE_REF => HlTag::Symbol(SymbolKind::StateMachine),
        OPERATION_REF | CALL_STMT => HlTag::Symbol(SymbolKind::Operation),
        TYPE_INSTANTIATION => HlTag::Type,
        _ => return None,
    })
}

fn is_first_node(node: &SyntaxNode) -> bool {
    node.parent().and_then(|p| p.first_child()).is_some_and(|first| &first == node)
}

fn prev_non_trivia_is_dollar(node: &SyntaxNode) -> bool {
    let mut prev = node.prev_sibling_or_token();
    while let Some(el) = prev {
        if !el.kind().is_trivia() {
            return el.kind() == DOLLAR;
        }
        prev = el.prev_sibling_or_token();
    }
    false
}
