//! The one place where byte offsets meet LSP positions (0-based lines,
//! UTF-16 columns), and where `robosim-ide` results become LSP types.

use robosim_ide::{
    CompletionItem as IdeCompletion, CompletionKind, DocumentSymbol as IdeSymbol, Fold, FoldKind, HlRange, HlTag,
    LineCol, LineIndex, Severity, SymbolKind as IdeKind, TextRange, TextSize,
};
use tower_lsp_server::ls_types::{
    self as lsp, CompletionItemKind, DiagnosticSeverity, FoldingRangeKind, NumberOrString, Position, Range,
    SemanticToken, SemanticTokenModifier, SemanticTokenType, SemanticTokensLegend, SymbolKind,
};

/// A text with its line index: what every conversion needs.
#[derive(Clone, Copy)]
pub(crate) struct Text<'a> {
    pub(crate) text: &'a str,
    pub(crate) index: &'a LineIndex,
}

impl Text<'_> {
    pub(crate) fn position(&self, offset: TextSize) -> Position {
        let LineCol { line, col } = self.index.line_col(self.text, offset);
        Position::new(line, col)
    }

    pub(crate) fn range(&self, range: TextRange) -> Range {
        Range::new(self.position(range.start()), self.position(range.end()))
    }

    /// The byte offset of `pos`. Positions past the end of their line are
    /// moved to its end and positions past the last line to the end of the
    /// text (LSP asks for the first; the second is a client bug we survive);
    /// a column inside a surrogate pair moves to the character's start. The
    /// flag says whether the position had to be moved.
    pub(crate) fn offset(&self, pos: Position) -> (TextSize, bool) {
        let len = TextSize::of(self.text);
        if pos.line as usize >= self.index.line_count() {
            return (len, true);
        }
        let start = self.index.offset(self.text, LineCol { line: pos.line, col: 0 }).unwrap_or(len);
        let next = self.index.offset(self.text, LineCol { line: pos.line + 1, col: 0 }).unwrap_or(len);
        let line = &self.text[usize::from(start)..usize::from(next)];
        let line = line.strip_suffix('\n').map(|l| l.strip_suffix('\r').unwrap_or(l)).unwrap_or(line);
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            if units == pos.character {
                return (start + TextSize::from(i as u32), false);
            }
            units += c.len_utf16() as u32;
            if units > pos.character {
                return (start + TextSize::from(i as u32), true);
            }
        }
        let end = start + TextSize::of(line);
        (end, units != pos.character)
    }
}

pub(crate) fn severity(s: Severity) -> DiagnosticSeverity {
    match s {
        Severity::Error => DiagnosticSeverity::ERROR,
        Severity::Warning => DiagnosticSeverity::WARNING,
        Severity::Info => DiagnosticSeverity::INFORMATION,
        Severity::Hint => DiagnosticSeverity::HINT,
    }
}

pub(crate) fn diagnostic(
    text: Text<'_>,
    d: &robosim_ide::Diagnostic,
    related: Vec<lsp::DiagnosticRelatedInformation>,
) -> lsp::Diagnostic {
    lsp::Diagnostic {
        range: text.range(d.range),
        severity: Some(severity(d.severity)),
        code: Some(NumberOrString::String(d.code.clone())),
        code_description: None,
        source: Some("robosim".to_string()),
        message: d.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        tags: None,
        data: None,
    }
}

pub(crate) fn symbol_kind(k: IdeKind) -> SymbolKind {
    match k {
        IdeKind::Package => SymbolKind::PACKAGE,
        IdeKind::Interface => SymbolKind::INTERFACE,
        IdeKind::Platform => SymbolKind::OBJECT,
        IdeKind::Controller | IdeKind::StateMachine | IdeKind::Simulation => SymbolKind::CLASS,
        IdeKind::Module => SymbolKind::MODULE,
        IdeKind::Operation => SymbolKind::METHOD,
        IdeKind::Function | IdeKind::CspProcess => SymbolKind::FUNCTION,
        IdeKind::PrimitiveType => SymbolKind::TYPE_PARAMETER,
        IdeKind::Record => SymbolKind::STRUCT,
        IdeKind::Field => SymbolKind::FIELD,
        IdeKind::Enum => SymbolKind::ENUM,
        IdeKind::EnumLiteral => SymbolKind::ENUM_MEMBER,
        IdeKind::Event => SymbolKind::EVENT,
        IdeKind::Variable => SymbolKind::VARIABLE,
        IdeKind::Constant => SymbolKind::CONSTANT,
        IdeKind::Clock => SymbolKind::PROPERTY,
        IdeKind::Parameter => SymbolKind::VARIABLE,
        // States contain states and transitions, like namespaces; the
        // pseudo-states are points of the diagram.
        IdeKind::State => SymbolKind::NAMESPACE,
        IdeKind::Initial | IdeKind::Junction | IdeKind::Final | IdeKind::ProbabilisticJunction => SymbolKind::KEY,
        IdeKind::Transition => SymbolKind::OPERATOR,
        IdeKind::Assertion => SymbolKind::BOOLEAN,
    }
}

#[allow(deprecated)] // `deprecated` is a required field of the LSP type.
pub(crate) fn document_symbol(text: Text<'_>, s: &IdeSymbol) -> lsp::DocumentSymbol {
    lsp::DocumentSymbol {
        name: s.name.clone(),
        detail: s.detail.clone(),
        kind: symbol_kind(s.kind),
        tags: None,
        deprecated: None,
        range: text.range(s.full_range),
        selection_range: text.range(s.selection_range),
        children: (!s.children.is_empty()).then(|| s.children.iter().map(|c| document_symbol(text, c)).collect()),
    }
}

/// The flat form, for clients without hierarchical symbol support.
#[allow(deprecated)]
pub(crate) fn flat_symbols(
    text: Text<'_>,
    uri: &lsp::Uri,
    symbols: &[IdeSymbol],
    container: Option<&str>,
    out: &mut Vec<lsp::SymbolInformation>,
) {
    for s in symbols {
        out.push(lsp::SymbolInformation {
            name: s.name.clone(),
            kind: symbol_kind(s.kind),
            tags: None,
            deprecated: None,
            location: lsp::Location::new(uri.clone(), text.range(s.full_range)),
            container_name: container.map(str::to_string),
        });
        flat_symbols(text, uri, &s.children, Some(&s.name), out);
    }
}

fn completion_kind(k: CompletionKind) -> CompletionItemKind {
    match k {
        CompletionKind::Keyword => CompletionItemKind::KEYWORD,
        CompletionKind::Symbol(k) => match k {
            IdeKind::Package | IdeKind::Module => CompletionItemKind::MODULE,
            IdeKind::Interface => CompletionItemKind::INTERFACE,
            IdeKind::Platform | IdeKind::Controller | IdeKind::StateMachine | IdeKind::Simulation => {
                CompletionItemKind::CLASS
            }
            IdeKind::Operation => CompletionItemKind::METHOD,
            IdeKind::Function | IdeKind::CspProcess => CompletionItemKind::FUNCTION,
            IdeKind::PrimitiveType => CompletionItemKind::TYPE_PARAMETER,
            IdeKind::Record => CompletionItemKind::STRUCT,
            IdeKind::Field => CompletionItemKind::FIELD,
            IdeKind::Enum => CompletionItemKind::ENUM,
            IdeKind::EnumLiteral => CompletionItemKind::ENUM_MEMBER,
            IdeKind::Event => CompletionItemKind::EVENT,
            IdeKind::Variable | IdeKind::Parameter => CompletionItemKind::VARIABLE,
            IdeKind::Constant => CompletionItemKind::CONSTANT,
            IdeKind::Clock => CompletionItemKind::PROPERTY,
            IdeKind::State | IdeKind::Initial | IdeKind::Junction | IdeKind::Final | IdeKind::ProbabilisticJunction => {
                CompletionItemKind::VALUE
            }
            IdeKind::Transition | IdeKind::Assertion => CompletionItemKind::REFERENCE,
        },
    }
}

/// A completion: it replaces the part of the name typed so far. Names sort
/// before keywords.
pub(crate) fn completion_item(text: Text<'_>, c: &IdeCompletion) -> lsp::CompletionItem {
    let group = if c.kind == CompletionKind::Keyword { '1' } else { '0' };
    lsp::CompletionItem {
        label: c.label.clone(),
        kind: Some(completion_kind(c.kind)),
        detail: c.detail.clone(),
        sort_text: Some(format!("{group}{}", c.label)),
        text_edit: Some(lsp::CompletionTextEdit::Edit(lsp::TextEdit::new(text.range(c.range), c.label.clone()))),
        ..lsp::CompletionItem::default()
    }
}

pub(crate) fn folding_range(text: Text<'_>, line_folding_only: bool, fold: &Fold) -> Option<lsp::FoldingRange> {
    let range = text.range(fold.range);
    let kind = match fold.kind {
        FoldKind::Comment => Some(FoldingRangeKind::Comment),
        FoldKind::Imports => Some(FoldingRangeKind::Imports),
        FoldKind::Region | FoldKind::Csp => Some(FoldingRangeKind::Region),
    };
    // Clients that fold whole lines would hide text after the region's
    // end on its last line: end one line earlier then (as rust-analyzer).
    let end_line = if line_folding_only {
        let rest = text.text.get(usize::from(fold.range.end())..).unwrap_or("");
        let more = rest.chars().take_while(|c| *c != '\n').any(|c| !c.is_whitespace());
        if more {
            range.end.line.saturating_sub(1)
        } else {
            range.end.line
        }
    } else {
        range.end.line
    };
    if end_line <= range.start.line {
        return None;
    }
    Some(lsp::FoldingRange {
        start_line: range.start.line,
        start_character: (!line_folding_only).then_some(range.start.character),
        end_line,
        end_character: (!line_folding_only && end_line == range.end.line).then_some(range.end.character),
        kind,
        collapsed_text: None,
    })
}

pub(crate) fn selection_range(text: Text<'_>, ranges: &[TextRange]) -> lsp::SelectionRange {
    // `ranges` runs from the innermost out; LSP nests the other way.
    let mut outer: Option<Box<lsp::SelectionRange>> = None;
    for r in ranges.iter().rev() {
        outer = Some(Box::new(lsp::SelectionRange { range: text.range(*r), parent: outer }));
    }
    outer.map(|b| *b).unwrap_or(lsp::SelectionRange { range: Range::default(), parent: None })
}

// Semantic tokens.

/// Custom token types, after the standard ones. Editors without a colour
/// for them keep their grammar's colouring.
const STATE: SemanticTokenType = SemanticTokenType::new("state");
const CLOCK: SemanticTokenType = SemanticTokenType::new("clock");
const TRANSITION: SemanticTokenType = SemanticTokenType::new("transition");
const SIM_REFERENCE: SemanticTokenType = SemanticTokenType::new("simReference");

/// Token types in legend order: the index is the wire encoding.
const TOKEN_TYPES: &[SemanticTokenType] = &[
    SemanticTokenType::NAMESPACE,
    SemanticTokenType::TYPE,
    SemanticTokenType::CLASS,
    SemanticTokenType::ENUM,
    SemanticTokenType::INTERFACE,
    SemanticTokenType::STRUCT,
    SemanticTokenType::TYPE_PARAMETER,
    SemanticTokenType::PARAMETER,
    SemanticTokenType::VARIABLE,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::ENUM_MEMBER,
    SemanticTokenType::EVENT,
    SemanticTokenType::FUNCTION,
    SemanticTokenType::METHOD,
    SemanticTokenType::KEYWORD,
    SemanticTokenType::COMMENT,
    SemanticTokenType::STRING,
    SemanticTokenType::NUMBER,
    STATE,
    CLOCK,
    TRANSITION,
    SIM_REFERENCE,
];

const TOKEN_MODIFIERS: &[SemanticTokenModifier] =
    &[SemanticTokenModifier::DECLARATION, SemanticTokenModifier::READONLY];
const DECLARATION: u32 = 1;
const READONLY: u32 = 2;

pub(crate) fn semantic_tokens_legend() -> SemanticTokensLegend {
    SemanticTokensLegend { token_types: TOKEN_TYPES.to_vec(), token_modifiers: TOKEN_MODIFIERS.to_vec() }
}

fn type_index(t: &SemanticTokenType) -> u32 {
    TOKEN_TYPES.iter().position(|x| x == t).unwrap_or(0) as u32
}

fn token_type(tag: HlTag) -> SemanticTokenType {
    match tag {
        HlTag::Keyword => SemanticTokenType::KEYWORD,
        HlTag::Type => SemanticTokenType::TYPE,
        HlTag::Number => SemanticTokenType::NUMBER,
        HlTag::String => SemanticTokenType::STRING,
        HlTag::Comment => SemanticTokenType::COMMENT,
        HlTag::SimRef => SIM_REFERENCE,
        HlTag::Symbol(k) => match k {
            IdeKind::Package | IdeKind::Module => SemanticTokenType::NAMESPACE,
            IdeKind::Interface => SemanticTokenType::INTERFACE,
            IdeKind::Platform | IdeKind::Controller | IdeKind::StateMachine | IdeKind::Simulation => {
                SemanticTokenType::CLASS
            }
            IdeKind::Operation => SemanticTokenType::METHOD,
            IdeKind::Function | IdeKind::CspProcess => SemanticTokenType::FUNCTION,
            IdeKind::PrimitiveType => SemanticTokenType::TYPE,
            IdeKind::Record => SemanticTokenType::STRUCT,
            IdeKind::Field | IdeKind::Assertion => SemanticTokenType::PROPERTY,
            IdeKind::Enum => SemanticTokenType::ENUM,
            IdeKind::EnumLiteral => SemanticTokenType::ENUM_MEMBER,
            IdeKind::Event => SemanticTokenType::EVENT,
            IdeKind::Variable | IdeKind::Constant => SemanticTokenType::VARIABLE,
            IdeKind::Clock => CLOCK,
            IdeKind::Parameter => SemanticTokenType::PARAMETER,
            IdeKind::State | IdeKind::Initial | IdeKind::Junction | IdeKind::Final | IdeKind::ProbabilisticJunction => {
                STATE
            }
            IdeKind::Transition => TRANSITION,
        },
    }
}

/// Delta-encoded tokens. Multi-line ranges (block comments) are cut at
/// line ends, since clients need not support tokens across lines.
pub(crate) fn semantic_tokens(text: Text<'_>, ranges: &[HlRange]) -> Vec<SemanticToken> {
    let mut out = Vec::with_capacity(ranges.len());
    let (mut prev_line, mut prev_col) = (0u32, 0u32);
    for h in ranges {
        let ty = type_index(&token_type(h.tag));
        let mut mods = 0;
        if h.declaration {
            mods |= DECLARATION;
        }
        if h.tag == HlTag::Symbol(IdeKind::Constant) {
            mods |= READONLY;
        }
        let Some(slice) = text.text.get(usize::from(h.range.start())..usize::from(h.range.end())) else { continue };
        let start = text.position(h.range.start());
        let (mut line, mut col) = (start.line, start.character);
        for (i, piece) in slice.split('\n').enumerate() {
            if i > 0 {
                line += 1;
                col = 0;
            }
            let piece = piece.strip_suffix('\r').unwrap_or(piece);
            let len: u32 = piece.chars().map(|c| c.len_utf16() as u32).sum();
            if len == 0 {
                continue;
            }
            let delta_line = line - prev_line;
            let delta_start = if delta_line == 0 { col - prev_col } else { col };
            out.push(SemanticToken {
                delta_line,
                delta_start,
                length: len,
                token_type: ty,
                token_modifiers_bitset: mods,
            });
            prev_line = line;
            prev_col = col;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(s: &str) -> (String, LineIndex) {
        (s.to_string(), LineIndex::new(s))
    }

    #[test]
    fn offsets_clamp_instead_of_failing() {
        let (s, index) = text("ab\r\n\u{e9}\u{1F600}x\nlast");
        let t = Text { text: &s, index: &index };
        let at = |line, character| t.offset(Position::new(line, character));
        assert_eq!(at(0, 2), (2.into(), false));
        // Past the end of the line: its end, before `\r\n`.
        assert_eq!(at(0, 9), (2.into(), true));
        // é is 1 unit, 😀 2: column 2 is inside the pair.
        assert_eq!(at(1, 1), (6.into(), false));
        assert_eq!(at(1, 2), (6.into(), true));
        assert_eq!(at(1, 3), (10.into(), false));
        assert_eq!(at(1, 4), (11.into(), false));
        assert_eq!(at(2, 4), (16.into(), false));
        // Past the last line: the end of the text.
        assert_eq!(at(7, 0), (16.into(), true));
        for off in [0u32, 1, 2, 4, 6, 10, 11, 12, 16] {
            let p = t.position(off.into());
            assert_eq!(t.offset(p), (off.into(), false), "{off}");
        }
    }

    #[test]
    fn multi_line_tokens_are_split_and_delta_encoded() {
        let (s, index) = text("/* a\n b */ x");
        let t = Text { text: &s, index: &index };
        let ranges = [
            HlRange { range: TextRange::new(0.into(), 10.into()), tag: HlTag::Comment, declaration: false },
            HlRange {
                range: TextRange::new(11.into(), 12.into()),
                tag: HlTag::Symbol(IdeKind::Constant),
                declaration: true,
            },
        ];
        let tokens = semantic_tokens(t, &ranges);
        let comment = type_index(&SemanticTokenType::COMMENT);
        let variable = type_index(&SemanticTokenType::VARIABLE);
        let flat: Vec<_> = tokens
            .iter()
            .map(|t| (t.delta_line, t.delta_start, t.length, t.token_type, t.token_modifiers_bitset))
            .collect();
        assert_eq!(flat, [(0, 0, 4, comment, 0), (1, 0, 5, comment, 0), (0, 6, 1, variable, DECLARATION | READONLY)]);
    }
}
