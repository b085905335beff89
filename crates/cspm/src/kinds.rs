//! The one list of every token and node kind of CSPm, with the spellings of
//! punctuation and keywords. Lexer, parser and lowering refer only to these.

macro_rules! syntax_kinds {
    (
        tokens { $($tok:ident,)* }
        punct { $($p:ident = $ptext:literal,)* }
        keywords { $($kw:ident = $kwtext:literal,)* }
        nodes { $($node:ident,)* }
    ) => {
        /// Every kind of token and node in a CSPm syntax tree.
        #[allow(non_camel_case_types, missing_docs)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u16)]
        pub enum SyntaxKind {
            $($tok,)*
            $($p,)*
            $($kw,)*
            $($node,)*
        }

        const ALL_KINDS: &[SyntaxKind] = &[
            $(SyntaxKind::$tok,)* $(SyntaxKind::$p,)* $(SyntaxKind::$kw,)* $(SyntaxKind::$node,)*
        ];

        /// Punctuation, longest spellings first (the lexer tries them in order).
        pub(crate) const PUNCT: &[(&str, SyntaxKind)] = &[$(($ptext, SyntaxKind::$p),)*];
        /// Keywords and their kinds.
        pub(crate) const KEYWORDS: &[(&str, SyntaxKind)] = &[$(($kwtext, SyntaxKind::$kw),)*];

        impl SyntaxKind {
            /// The spelling of a punctuation or keyword kind, for messages.
            pub fn text(self) -> Option<&'static str> {
                match self {
                    $(SyntaxKind::$p => Some($ptext),)*
                    $(SyntaxKind::$kw => Some($kwtext),)*
                    _ => None,
                }
            }
        }
    };
}

syntax_kinds! {
    tokens {
        WHITESPACE, LINE_COMMENT, BLOCK_COMMENT, ERROR_TOKEN, EOF,
        IDENT, INT, STRING, CHAR,
        // `include "file"` up to the end of its line.
        INCLUDE_LINE,
        // `print …` up to the end of its line.
        PRINT_LINE,
    }
    punct {
        // Three or more characters first: the lexer takes the first match.
        REFINES_FD = "[FD=", REFINES_VD = "[VD=", REFINES_RD = "[RD=",
        REFINES_T = "[T=", REFINES_F = "[F=", REFINES_V = "[V=", REFINES_R = "[R=",
        INT_CHOICE = "|~|", INTERLEAVE = "|||", TIE = "<->", YIELD_STAR = "=>*",
        EXT_CHOICE = "[]", INTERRUPT = "/\\", ARROW = "->", SLIDE = "[>", EXC_CLOSE = "|>",
        PARALLEL = "||", PROJECT = "|\\", LSYNC_INT = "/+", RSYNC_INT = "+\\",
        LSYNC_EXT = "[+", RSYNC_EXT = "+]", EQ2 = "==", NEQ = "!=", LTEQ = "<=", GTEQ = ">=",
        L_PIPE_BRACE = "{|", R_PIPE_BRACE = "|}", L_MAP = "(|", R_MAP = "|)",
        L_RENAME = "[[", R_RENAME = "]]", L_PAR = "[|", R_PAR = "|]", DOT2 = "..",
        DRAWN = "<-", COLON2 = "::", YIELD = "=>", AT2 = "@@", PROP_OPEN = ":[",
        L_PAREN = "(", R_PAREN = ")", L_BRACE = "{", R_BRACE = "}", L_BRACK = "[", R_BRACK = "]",
        LT = "<", GT = ">", PIPE = "|", COMMA = ",", DOT = ".", QUESTION = "?", BANG = "!",
        DOLLAR = "$", COLON = ":", EQ = "=", BACKSLASH = "\\", AT = "@", PLUS = "+", MINUS = "-",
        STAR = "*", SLASH = "/", PERCENT = "%", CARET = "^", HASH = "#", SEMI = ";", AMP = "&",
        UNDERSCORE = "_",
    }
    keywords {
        CHANNEL_KW = "channel", DATATYPE_KW = "datatype", SUBTYPE_KW = "subtype",
        NAMETYPE_KW = "nametype", MODULE_KW = "module", EXPORTS_KW = "exports",
        ENDMODULE_KW = "endmodule", INSTANCE_KW = "instance", EXTERNAL_KW = "external",
        TRANSPARENT_KW = "transparent", ASSERT_KW = "assert", LET_KW = "let", WITHIN_KW = "within",
        IF_KW = "if", THEN_KW = "then", ELSE_KW = "else", AND_KW = "and", OR_KW = "or",
        NOT_KW = "not", TRUE_KW = "true", FALSE_KW = "false", TIMED_KW = "Timed",
    }
    nodes {
        SOURCE_FILE, ERROR,
        // Declarations.
        DEFINITION, TYPE_ANNOTATION, CHANNEL_DECL, DATATYPE_DECL, SUBTYPE_DECL, DATATYPE_CLAUSE,
        NAMETYPE_DECL, EXTERNAL_DECL, TRANSPARENT_DECL, ASSERT_DECL, ASSERT_PROPERTY, MODULE_DECL,
        MODULE_EXPORTS, INSTANCE_DECL, TIMED_SECTION, INCLUDE_DECL, PRINT_DECL, NAME_LIST,
        // Expressions.
        LITERAL, NAME_REF, PAREN_EXPR, TUPLE_EXPR, CALL_EXPR, ARG_LIST, BIN_EXPR, UNARY_EXPR,
        SET_EXPR, SET_RANGE, SET_COMPREHENSION, SEQ_EXPR, SEQ_RANGE, SEQ_COMPREHENSION,
        CLOSURE_EXPR, CLOSURE_COMPREHENSION, MAP_EXPR, LET_EXPR, IF_EXPR, LAMBDA_EXPR,
        PREFIX_EXPR, INPUT_FIELD, NONDET_FIELD, OUTPUT_FIELD, GUARD_EXPR, REPLICATED_EXPR,
        GEN_PARALLEL, ALPHA_PARALLEL, LINK_PARALLEL, LINK, EXCEPTION, SYNC_EXT_CHOICE,
        SYNC_INTERRUPT, RENAME_EXPR, RENAME_PAIR, WILDCARD, DOUBLE_PATTERN,
        // Statements of comprehensions and replicated operators.
        STMT_LIST, GENERATOR, PREDICATE,
    }
}

impl SyntaxKind {
    /// Whitespace and comments.
    pub fn is_trivia(self) -> bool {
        matches!(self, SyntaxKind::WHITESPACE | SyntaxKind::LINE_COMMENT | SyntaxKind::BLOCK_COMMENT)
    }

    /// Tokens FDR lets a line break follow without ending the definition
    /// (libcspm's lexer "soaks" the newline after them).
    pub(crate) fn soaks_after(self) -> bool {
        use SyntaxKind::*;
        !matches!(
            self,
            IDENT
                | INT
                | STRING
                | CHAR
                | R_PAREN
                | R_BRACE
                | R_PIPE_BRACE
                | R_MAP
                | R_RENAME
                | GT
                | TRUE_KW
                | FALSE_KW
                | EXPORTS_KW
                | ENDMODULE_KW
                | INCLUDE_LINE
                | PRINT_LINE
                | ERROR_TOKEN
                | EOF
        )
    }

    /// Tokens FDR lets a line break precede without ending the definition.
    pub(crate) fn soaks_before(self) -> bool {
        use SyntaxKind::*;
        !matches!(
            self,
            IDENT
                | L_PAREN
                | L_PIPE_BRACE
                | L_BRACE
                | L_MAP
                | LT
                | MINUS
                | HASH
                | CHANNEL_KW
                | DATATYPE_KW
                | SUBTYPE_KW
                | NAMETYPE_KW
                | MODULE_KW
                | EXPORTS_KW
                | ENDMODULE_KW
                | INSTANCE_KW
                | EXTERNAL_KW
                | TRANSPARENT_KW
                | ASSERT_KW
                | TIMED_KW
                | INCLUDE_LINE
                | PRINT_LINE
                | ERROR_TOKEN
                | EOF
                | COLON2
        )
    }
}

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(kind: SyntaxKind) -> Self {
        rowan::SyntaxKind(kind as u16)
    }
}

/// The rowan language of CSPm trees.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CspmLanguage {}

impl rowan::Language for CspmLanguage {
    type Kind = SyntaxKind;
    fn kind_from_raw(raw: rowan::SyntaxKind) -> SyntaxKind {
        ALL_KINDS.get(raw.0 as usize).copied().unwrap_or(SyntaxKind::ERROR)
    }
    fn kind_to_raw(kind: SyntaxKind) -> rowan::SyntaxKind {
        kind.into()
    }
}

/// A node of a CSPm syntax tree.
pub type SyntaxNode = rowan::SyntaxNode<CspmLanguage>;
/// A token of a CSPm syntax tree.
pub type SyntaxToken = rowan::SyntaxToken<CspmLanguage>;
