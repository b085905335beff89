//! The one list of every token and node kind, and the keyword tables of the
//! four languages. Everything else (lexer, parser, AST, later crates) refers
//! to these kinds; nothing else defines spellings.

use crate::FileKind;

/// Membership of a keyword in the four languages, as a bit set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Langs(u8);

impl Langs {
    const RCT: u8 = 1;
    const RST: u8 = 2;
    const ASSERTIONS: u8 = 4;
    const RSA: u8 = 8;
    /// Every file kind.
    pub(crate) const ALL: Langs = Langs(15);
    /// RoboChart models and their assertion files.
    pub(crate) const RC: Langs = Langs(Self::RCT | Self::ASSERTIONS);
    /// RoboSim models and their assertion files.
    pub(crate) const RS: Langs = Langs(Self::RST | Self::RSA);
    /// Both assertion languages.
    pub(crate) const ASSERT: Langs = Langs(Self::ASSERTIONS | Self::RSA);
    /// RoboChart assertions only.
    pub(crate) const RC_ASSERT: Langs = Langs(Self::ASSERTIONS);
    /// RoboSim assertions only.
    pub(crate) const RS_ASSERT: Langs = Langs(Self::RSA);

    pub(crate) fn contains(self, file: FileKind) -> bool {
        let bit = match file {
            FileKind::RoboChart => Self::RCT,
            FileKind::RoboSim => Self::RST,
            FileKind::Assertions => Self::ASSERTIONS,
            FileKind::SimAssertions => Self::RSA,
        };
        self.0 & bit != 0
    }
}

macro_rules! syntax_kinds {
    (
        tokens { $($tok:ident,)* }
        punct { $($p:ident = $ptext:literal,)* }
        keywords { $($kw:ident = $kwtext:literal in $langs:ident,)* }
        nodes { $($node:ident,)* }
    ) => {
        /// Every kind of token and node in the syntax tree.
        #[allow(non_camel_case_types, missing_docs)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u16)]
        pub enum SyntaxKind {
            $($tok,)*
            $($p,)*
            $($kw,)*
            $($node,)*
        }

        pub(crate) const ALL_KINDS: &[SyntaxKind] = &[
            $(SyntaxKind::$tok,)* $(SyntaxKind::$p,)* $(SyntaxKind::$kw,)* $(SyntaxKind::$node,)*
        ];

        /// Every keyword with its spelling and languages.
        const KEYWORDS: &[(SyntaxKind, &str, Langs)] = &[$((SyntaxKind::$kw, $kwtext, Langs::$langs),)*];

        impl SyntaxKind {
            /// The fixed spelling of a punctuation or keyword token.
            pub fn text(self) -> Option<&'static str> {
                match self {
                    $(SyntaxKind::$p => Some($ptext),)*
                    $(SyntaxKind::$kw => Some($kwtext),)*
                    _ => None,
                }
            }

            /// Whether this kind is a reserved word (in some language).
            pub const fn is_keyword(self) -> bool {
                matches!(self, $(SyntaxKind::$kw)|*)
            }

            /// Whether this kind is a punctuation or operator token.
            pub const fn is_punct(self) -> bool {
                matches!(self, $(SyntaxKind::$p)|*)
            }

            /// Whether this kind is a node (as opposed to a token).
            pub fn is_node(self) -> bool {
                matches!(self, $(SyntaxKind::$node)|*)
            }

            pub(crate) fn keyword_langs(self) -> Option<Langs> {
                match self {
                    $(SyntaxKind::$kw => Some(Langs::$langs),)*
                    _ => None,
                }
            }

            /// The keyword spelled `text` if it is reserved in files of kind `file`.
            pub fn keyword(text: &str, file: FileKind) -> Option<SyntaxKind> {
                let kind = match text {
                    $($kwtext => SyntaxKind::$kw,)*
                    _ => return None,
                };
                kind.keyword_langs().filter(|l| l.contains(file)).map(|_| kind)
            }

            /// Converts a raw rowan kind back; `None` for out-of-range values.
            pub fn from_raw(raw: u16) -> Option<SyntaxKind> {
                ALL_KINDS.get(raw as usize).copied()
            }
        }
    };
}

syntax_kinds! {
    tokens {
        EOF,
        WHITESPACE,
        LINE_COMMENT,
        BLOCK_COMMENT,
        IDENT,
        INT_NUMBER,
        FLOAT_NUMBER,
        STRING,
        CSP_TEXT,
        ERROR_TOKEN,
    }
    punct {
        L_CURLY = "{",
        R_CURLY = "}",
        L_PAREN = "(",
        R_PAREN = ")",
        L_BRACK = "[",
        R_BRACK = "]",
        L_PAREN_PIPE = "(|",
        R_PAREN_PIPE = "|)",
        L_BRACK_PIPE = "[|",
        R_BRACK_PIPE = "|]",
        DEADLINE_OPEN = "<{",
        SET_OPEN = "Set(",
        SEQ_OPEN = "Seq(",
        COLON2_STAR = "::*",
        COLON2 = "::",
        COLON = ":",
        COMMA = ",",
        SEMI = ";",
        AT = "@",
        PIPE = "|",
        HASH = "#",
        QUESTION = "?",
        BANG = "!",
        DOT = ".",
        EQ = "=",
        EQ2 = "==",
        NEQ = "!=",
        LT = "<",
        LTEQ = "<=",
        GT = ">",
        GTEQ = ">=",
        PLUS = "+",
        MINUS = "-",
        STAR = "*",
        SLASH = "/",
        PERCENT = "%",
        CARET = "^",
        AND = "/\\",
        OR = "\\/",
        IMPLIES = "=>",
        ARROW = "->",
        REL_ARROW = "<->",
        DOLLAR = "$",
    }
    keywords {
        TRUE_KW = "true" in ALL,
        FALSE_KW = "false" in ALL,
        ASYNC_KW = "_async" in ALL,
        BROADCAST_KW = "_broadcast" in RC,
        ACTION_KW = "action" in ALL,
        AS_KW = "as" in ALL,
        CAT_KW = "cat" in ALL,
        CLOCK_KW = "clock" in ALL,
        CONDITION_KW = "condition" in ALL,
        CONNECTION_KW = "connection" in ALL,
        CONST_KW = "const" in ALL,
        CONTROLLER_KW = "controller" in ALL,
        CREF_KW = "cref" in ALL,
        DATATYPE_KW = "datatype" in ALL,
        DIAGRAM_KW = "diagram" in ALL,
        DURING_KW = "during" in ALL,
        ELSE_KW = "else" in ALL,
        END_KW = "end" in ALL,
        ENTRY_KW = "entry" in ALL,
        ENUMERATION_KW = "enumeration" in ALL,
        EVENT_KW = "event" in ALL,
        EXISTS_KW = "exists" in ALL,
        EXISTS1_KW = "exists1" in ALL,
        EXIT_KW = "exit" in ALL,
        FINAL_KW = "final" in ALL,
        FORALL_KW = "forall" in ALL,
        FROM_KW = "from" in ALL,
        FUNCTION_KW = "function" in ALL,
        IF_KW = "if" in ALL,
        IFF_KW = "iff" in ALL,
        IMPORT_KW = "import" in ALL,
        IN_KW = "in" in ALL,
        INITIAL_KW = "initial" in ALL,
        INTERFACE_KW = "interface" in ALL,
        INVERSE_KW = "inverse" in ALL,
        IS_KW = "is" in ALL,
        JUNCTION_KW = "junction" in ALL,
        LAMBDA_KW = "lambda" in ALL,
        LET_KW = "let" in ALL,
        MATRIX_KW = "matrix" in ALL,
        MODULE_KW = "module" in ALL,
        MULT_KW = "mult" in ALL,
        NOT_KW = "not" in ALL,
        ON_KW = "on" in ALL,
        OPERATION_KW = "operation" in ALL,
        OPREF_KW = "opref" in ALL,
        PACKAGE_KW = "package" in ALL,
        PLATFORM_KW = "platform" in ALL,
        POSTCONDITION_KW = "postcondition" in ALL,
        PRECONDITION_KW = "precondition" in ALL,
        PROBABILISTIC_KW = "probabilistic" in ALL,
        PROBABILITY_KW = "probability" in ALL,
        PROVIDES_KW = "provides" in ALL,
        RECORD_KW = "record" in ALL,
        REQUIRES_KW = "requires" in ALL,
        RESULT_KW = "result" in ALL,
        ROBOTIC_KW = "robotic" in ALL,
        RREF_KW = "rref" in ALL,
        SEND_KW = "send" in ALL,
        SINCE_KW = "since" in ALL,
        SINCE_ENTRY_KW = "sinceEntry" in ALL,
        SKIP_KW = "skip" in ALL,
        SREF_KW = "sref" in ALL,
        STATE_KW = "state" in ALL,
        STM_KW = "stm" in ALL,
        TERMINATES_KW = "terminates" in ALL,
        THE_KW = "the" in ALL,
        THEN_KW = "then" in ALL,
        TO_KW = "to" in ALL,
        TRANSITION_KW = "transition" in ALL,
        TRANSPOSE_KW = "transpose" in ALL,
        TRIGGER_KW = "trigger" in RC,
        TYPE_KW = "type" in ALL,
        USES_KW = "uses" in ALL,
        VAR_KW = "var" in ALL,
        VECTOR_KW = "vector" in ALL,
        WAIT_KW = "wait" in ALL,
        CYCLE_KW = "cycle" in RS,
        CYCLE_DEF_KW = "cycleDef" in RS,
        CONTEXT_KW = "context" in RS,
        EXEC_KW = "exec" in RS,
        INPUT_KW = "input" in RS,
        OUTPUT_KW = "output" in RS,
        AND_KW = "and" in ASSERT,
        ASSERTION_KW = "assertion" in ASSERT,
        ASSIGNED_KW = "assigned" in ASSERT,
        ASSOCIATED_KW = "associated" in ASSERT,
        CONSTANT_KW = "constant" in ASSERT,
        CSP_KW = "csp" in ASSERT,
        DEADLOCK_FREE_KW = "deadlock-free" in ASSERT,
        DETERMINISTIC_KW = "deterministic" in ASSERT,
        DIVERGENCE_FREE_KW = "divergence-free" in ASSERT,
        DOES_KW = "does" in ASSERT,
        EQUAL_KW = "equal" in ASSERT,
        EQUALS_KW = "equals" in ASSERT,
        INITIALISED_KW = "initialised" in ASSERT,
        OF_KW = "of" in ASSERT,
        PARAMETER_KW = "parameter" in ASSERT,
        REACHABLE_KW = "reachable" in ASSERT,
        REFINE_KW = "refine" in ASSERT,
        REFINES_KW = "refines" in ASSERT,
        SET_KW = "set" in ASSERT,
        TERMINATE_KW = "terminate" in ASSERT,
        TIMED_KW = "timed" in ASSERT,
        TIMELOCK_FREE_KW = "timelock-free" in ASSERT,
        UNTIMED_KW = "untimed" in ASSERT,
        VALUE_KW = "value" in ASSERT,
        WITH_KW = "with" in ASSERT,
        FAILURES_DIVERGENCES_MODEL_KW = "failures divergences model" in ASSERT,
        FAILURES_MODEL_KW = "failures model" in ASSERT,
        TRACES_MODEL_KW = "traces model" in ASSERT,
        TICK_TOCK_MODEL_KW = "tick-tock model" in ASSERT,
        INSTANTIATE_KW = "instantiate" in RC_ASSERT,
        DEFAULT_KW = "DEFAULT" in RC_ASSERT,
        SCHEDULABLE_KW = "schedulable" in RS_ASSERT,
        SIMULATION_KW = "simulation" in RS_ASSERT,
    }
    nodes {
        SOURCE_FILE,
        ERROR,
        NAME,
        NAME_REF,
        QUALIFIED_NAME,
        PACKAGE_DECL,
        DIAGRAM_DECL,
        IMPORT,
        // types
        NAMED_TYPE,
        SET_TYPE,
        SEQ_TYPE,
        TYPE_VAR,
        PAREN_TYPE,
        PRODUCT_TYPE,
        FUNCTION_TYPE,
        RELATION_TYPE,
        VECTOR_TYPE,
        MATRIX_TYPE,
        // declarations
        PRIMITIVE_TYPE_DECL,
        RECORD_DECL,
        FIELD,
        ENUM_DECL,
        ENUM_LITERAL,
        INTERFACE,
        EVENT,
        VARIABLE_LIST,
        VARIABLE,
        CLOCK,
        OPERATION_SIG,
        PARAM_LIST,
        PARAM,
        TERMINATES_FLAG,
        INTERFACE_USE,
        ROBOTIC_PLATFORM,
        PLATFORM_REF,
        CONTROLLER,
        CONTROLLER_REF,
        STATE_MACHINE,
        STATE_MACHINE_REF,
        OPERATION_DEF,
        OPERATION_REF,
        TERMINATES_CLAUSE,
        PRECONDITION,
        POSTCONDITION,
        FUNCTION,
        MODULE,
        CONNECTION,
        ASYNC_FLAG,
        MULT_FLAG,
        CYCLE_DEF,
        INPUT_CONTEXT,
        OUTPUT_CONTEXT,
        // nodes of state machines
        STATE,
        INITIAL,
        JUNCTION,
        FINAL,
        PROBABILISTIC_JUNCTION,
        ENTRY_ACTION,
        DURING_ACTION,
        EXIT_ACTION,
        TRANSITION,
        TRANSITION_SOURCE,
        TRANSITION_TARGET,
        TRIGGER,
        EXEC_TRIGGER,
        PROBABILITY,
        CLOCK_RESET,
        DEADLINE,
        CONDITION,
        ELSE_CONDITION,
        TRANSITION_ACTION,
        // communications
        COMMUNICATION,
        COMM_GUARD,
        COMM_INPUT,
        COMM_OUTPUT,
        COMM_SYNC,
        // statements
        SEQ_STMT,
        TIMED_STMT,
        IF_STMT,
        COMM_STMT,
        SKIP_STMT,
        CALL_STMT,
        ASSIGN_STMT,
        ASSIGNABLE,
        FIELD_ACCESS,
        INDEX_ACCESS,
        PAR_STMT,
        WAIT_STMT,
        CLOCK_RESET_STMT,
        EXEC_STMT,
        OUTPUT_COMM_STMT,
        SIM_CALL_STMT,
        ARG_LIST,
        // expressions
        FORALL_EXPR,
        EXISTS_EXPR,
        LAMBDA_EXPR,
        BINDERS,
        BINDER,
        SUCH_THAT,
        BIN_EXPR,
        PREFIX_EXPR,
        THE_EXPR,
        LET_EXPR,
        LET_DECL,
        IF_EXPR,
        TYPE_TEST_EXPR,
        SELECT_EXPR,
        INDEX_EXPR,
        CALL_EXPR,
        LITERAL,
        REF_EXPR,
        RECORD_LITERAL,
        FIELD_VALUE,
        ENUM_LITERAL_EXPR,
        INTERVAL_EXPR,
        PAREN_EXPR,
        SINCE_EXPR,
        SINCE_ENTRY_EXPR,
        SEQ_EXPR,
        SET_EXPR,
        SET_RANGE_EXPR,
        SET_COMP_EXPR,
        MATRIX_EXPR,
        MATRIX_ROW,
        INVERSE_EXPR,
        TRANSPOSE_EXPR,
        TUPLE_EXPR,
        RESULT_EXPR,
        FROM_EXPR,
        TO_EXPR,
        CYCLE_EXPR,
        SIM_REF_EXPR,
        SIM_SYNC_SUFFIX,
        SIM_INPUT_SUFFIX,
        // assertion files
        ASSERTION,
        TIMING,
        ASSERTION_SUBJECT,
        ASSERTION_BODY,
        SEMANTIC_MODEL,
        PARAM_ASSIGNMENTS,
        CONSTANT_PARAM,
        PARAMETER_PARAM,
        CYCLE_DEF_PARAM,
        SETTER,
        CSP_BLOCK,
        ASSOCIATED_TO,
        TYPE_INSTANTIATION,
        SIMULATION,
        UNSUPPORTED_ITEM,
        // probabilistic assertions (syntax.md §5.3)
        PROB_CONST,
        PROB_CONSTANTS,
        PROB_CONFIG,
        PROB_PROPERTY,
        PROB_WITH_CONSTANTS,
        PROB_QUERY,
        PROB_BOUND,
        PROB_PATH_QUANT,
        PROB_TEMPORAL,
        PROB_UNTIL,
        PROB_PATH,
        PROB_DEADLOCK,
    }
}

/// The keywords spelled with identifier characters only (the others are
/// never a word of the lexer), by a hash of their bytes packed into two
/// words (see `pack`). The lexer looks up every word: hashing two words
/// and comparing two more is cheaper than a `match` on the text.
const KEYWORD_SLOTS: usize = 512;
static KEYWORD_TABLE: [(u64, u64, SyntaxKind, Langs); KEYWORD_SLOTS] = {
    let mut t = [(0u64, 0u64, SyntaxKind::EOF, Langs(0)); KEYWORD_SLOTS];
    let mut i = 0;
    while i < KEYWORDS.len() {
        let (kind, text, langs) = KEYWORDS[i];
        let b = text.as_bytes();
        let mut ident = true;
        let mut j = 0;
        while j < b.len() {
            ident &= b[j].is_ascii_alphanumeric() || b[j] == b'_';
            j += 1;
        }
        // The lexer only looks up words of up to 16 bytes.
        assert!(!ident || b.len() <= 16, "a keyword longer than 16 bytes");
        if ident {
            let (w0, w1) = pack_const(b);
            let mut slot = keyword_slot(w0, w1);
            while t[slot].0 != 0 {
                slot = (slot + 1) % KEYWORD_SLOTS;
            }
            t[slot] = (w0, w1, kind, langs);
        }
        i += 1;
    }
    t
};

/// `b` (at most 16 bytes) as two little-endian words, zero-padded.
const fn pack_const(b: &[u8]) -> (u64, u64) {
    let mut w = [0u64; 2];
    let mut j = 0;
    while j < b.len() {
        w[j / 8] |= (b[j] as u64) << (8 * (j % 8));
        j += 1;
    }
    (w[0], w[1])
}

const fn keyword_slot(w0: u64, w1: u64) -> usize {
    ((w0 ^ w1.rotate_left(29)).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> (64 - KEYWORD_SLOTS.trailing_zeros())) as usize
}

impl SyntaxKind {
    /// `keyword` for a word of identifier characters, given as its bytes
    /// packed into two words (zero-padded; only words of up to 16 bytes).
    #[inline]
    pub(crate) fn keyword_packed(w0: u64, w1: u64, file: FileKind) -> Option<SyntaxKind> {
        let mut slot = keyword_slot(w0, w1);
        loop {
            let (k0, k1, kind, langs) = KEYWORD_TABLE[slot];
            if k0 == w0 && k1 == w1 {
                return langs.contains(file).then_some(kind);
            }
            if k0 == 0 {
                return None;
            }
            slot = (slot + 1) % KEYWORD_SLOTS;
        }
    }

    /// Whitespace and comments: kept in the tree, skipped by the parser.
    pub fn is_trivia(self) -> bool {
        matches!(self, SyntaxKind::WHITESPACE | SyntaxKind::LINE_COMMENT | SyntaxKind::BLOCK_COMMENT)
    }

    /// A short human description used in messages ("`state`", "identifier", …).
    pub fn describe(self) -> String {
        match self {
            SyntaxKind::EOF => "end of file".to_string(),
            SyntaxKind::IDENT => "identifier".to_string(),
            SyntaxKind::INT_NUMBER => "integer".to_string(),
            SyntaxKind::FLOAT_NUMBER => "number".to_string(),
            SyntaxKind::STRING => "string".to_string(),
            SyntaxKind::CSP_TEXT => "CSP block".to_string(),
            SyntaxKind::ERROR_TOKEN => "invalid character".to_string(),
            k => match k.text() {
                Some(t) => format!("`{t}`"),
                None => format!("{k:?}"),
            },
        }
    }
}

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(k: SyntaxKind) -> Self {
        rowan::SyntaxKind(k as u16)
    }
}

/// The rowan language tag of our trees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RoboLang {}

impl rowan::Language for RoboLang {
    type Kind = SyntaxKind;
    fn kind_from_raw(raw: rowan::SyntaxKind) -> SyntaxKind {
        // Raw kinds only ever come from trees we built, so this cannot fail;
        // ERROR keeps it total anyway.
        SyntaxKind::from_raw(raw.0).unwrap_or(SyntaxKind::ERROR)
    }
    fn kind_to_raw(kind: SyntaxKind) -> rowan::SyntaxKind {
        kind.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_round_trip() {
        for (i, k) in ALL_KINDS.iter().enumerate() {
            assert_eq!(*k as usize, i);
            assert_eq!(SyntaxKind::from_raw(i as u16), Some(*k));
        }
    }

    #[test]
    fn packed_keyword_lookup_agrees_with_the_match() {
        let mut words: Vec<&str> = KEYWORDS.iter().map(|k| k.1).filter(|t| !t.contains([' ', '-'])).collect();
        words.extend(["x", "stat", "states", "transitions", "a_very_long_name", "operation1", "Set", "abcdefgh"]);
        for w in words {
            let (w0, w1) = pack_const(w.as_bytes());
            for file in FileKind::ALL {
                assert_eq!(SyntaxKind::keyword_packed(w0, w1, file), SyntaxKind::keyword(w, file), "{w}");
            }
        }
    }

    #[test]
    fn keyword_sets_differ_by_language() {
        assert_eq!(SyntaxKind::keyword("trigger", FileKind::RoboChart), Some(SyntaxKind::TRIGGER_KW));
        assert_eq!(SyntaxKind::keyword("trigger", FileKind::RoboSim), None);
        assert_eq!(SyntaxKind::keyword("exec", FileKind::RoboChart), None);
        assert_eq!(SyntaxKind::keyword("exec", FileKind::SimAssertions), Some(SyntaxKind::EXEC_KW));
        assert_eq!(SyntaxKind::keyword("assertion", FileKind::RoboSim), None);
        assert_eq!(SyntaxKind::keyword("instantiate", FileKind::SimAssertions), None);
        assert_eq!(SyntaxKind::keyword("schedulable", FileKind::Assertions), None);
        // send and wait stay reserved in RoboSim (§1.4).
        assert!(SyntaxKind::keyword("wait", FileKind::RoboSim).is_some());
    }

    #[test]
    fn robochart_has_75_reserved_words() {
        let n = ALL_KINDS
            .iter()
            .filter(|k| {
                k.keyword_langs().is_some_and(|l| l.contains(FileKind::RoboChart))
                    && !matches!(k, SyntaxKind::TRUE_KW | SyntaxKind::FALSE_KW)
            })
            .count();
        assert_eq!(n, 75);
    }
}
