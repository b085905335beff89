//! Reading an assertion file (`.rsa` or `.assertions`) into the structured,
//! source-located values the verifier runs: the simulations it declares,
//! its assertions with their parameter overrides, and the data-domain
//! instantiations of its `csp … csp-begin … csp-end` blocks (spec
//! `syntax.md` §5.1–5.2, `semantics.md` §3 and §7.1).
//!
//! [`read_assertions`] works on the (possibly broken) syntax tree of
//! `robosim_syntax::parse`. It never panics: a missing piece gives an empty
//! name or path, an empty range where the piece should have been, and a
//! [`Problem`] on the item it belongs to. Syntax errors themselves are the
//! parser's business; problems only say what the reader could not read.
//!
//! Every form of the assertion grammar is modelled by an [`AssertionKind`]
//! other than [`AssertionKind::Other`], which only broken (incomplete)
//! assertions produce.

mod prob;

use robosim_syntax::{ast, ast::AstNode, SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange, TextSize};

/// Everything the verifier needs from one assertion file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AssertionFile {
    /// `simulation S of M { … }` declarations (`.rsa`), in file order.
    pub simulations: Vec<SimulationDecl>,
    /// The assertions, in file order.
    pub assertions: Vec<AssertionDecl>,
    /// Data domains and constant values read from the `csp` blocks, and the
    /// `instantiate P as T` items of `.assertions` files.
    pub instantiations: Instantiations,
    /// The `csp … csp-begin … csp-end` blocks, in file order.
    pub csp_blocks: Vec<CspBlockDecl>,
    /// Items the parser recognised but skipped as unsupported (SLEEC and
    /// probabilistic assertions): what they are, so that a report can say
    /// that they were not checked rather than stay silent.
    pub skipped: Vec<Problem>,
}

/// `simulation S of M { cycleDef cycle == N … }`: the module (or
/// controller, machine) `M` constrained by the assumptions of a simulation
/// with cycle period `N`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimulationDecl {
    /// The declared name (`""` if missing).
    pub name: String,
    /// The name's range, or an empty range where it should be.
    pub name_range: TextRange,
    /// The whole declaration.
    pub range: TextRange,
    /// The simulated element, as qualified-name segments (empty if missing).
    pub of: Vec<String>,
    /// The range of `of`'s path, or an empty range where it should be.
    pub of_range: TextRange,
    /// The cycle period from `cycleDef cycle == N`, `cycleDef (cycle == N)`,
    /// `cycleDef { cycle == N }` or `cycleDef N == cycle`; `None` without a
    /// `cycleDef`. A `cycleDef` of any other shape gives `Value::Other` with
    /// the expression's text (and a problem).
    pub cycle: Option<Value>,
    /// The range of the (first) `cycleDef …` clause.
    pub cycle_range: Option<TextRange>,
    /// What could not be read.
    pub problems: Vec<Problem>,
}

/// One `assertion NAME : …` of the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssertionDecl {
    /// The assertion's name (`""` if missing).
    pub name: String,
    /// The name's range, or an empty range where it should be.
    pub name_range: TextRange,
    /// The whole assertion, from `timed`/`assertion` to the optional final `.`.
    pub range: TextRange,
    /// The assertion's source text, comments dropped and each run of
    /// whitespace (or of comments) collapsed to one space.
    pub text: String,
    /// The element the assertion is about (the left-hand side; the state of
    /// a reachability assertion; the clock of a clock-initialisation
    /// assertion), as qualified-name segments; empty if missing.
    pub subject: Vec<String>,
    /// The subject's range, or an empty range where it should be.
    pub subject_range: TextRange,
    /// `is not …`, `does not …`, `is not equal to …`, `… is not initialised`.
    pub negated: bool,
    /// What is asserted.
    pub kind: AssertionKind,
    /// `Some(true)` for `timed`, `Some(false)` for `untimed`, `None` without
    /// a prefix (or with `DEFAULT`, which means the same).
    pub timed: Option<bool>,
    /// The `in the … model` clause, for every kind (for `Refines`/`Equals`
    /// it is also in the kind). [`SemanticModelName::Default`] when absent.
    pub model: SemanticModelName,
    /// The range of `in the … model`, when present.
    pub model_range: Option<TextRange>,
    /// The `with …` parameter list, in order.
    pub overrides: Vec<Override>,
    /// What could not be read.
    pub problems: Vec<Problem>,
}

/// What an assertion asserts: one variant per form of the grammar.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AssertionKind {
    /// `X is [not] schedulable` (RoboSim).
    Schedulable,
    /// `X is [not] deadlock-free`.
    DeadlockFree,
    /// `X is [not] divergence-free`.
    DivergenceFree,
    /// `X is [not] deterministic`.
    Deterministic,
    /// `X is [not] timelock-free`.
    TimelockFree,
    /// `X terminates` / `X does not terminate`.
    Terminates,
    /// `X refines Y` / `X does not refine Y`: `Y ⊑ X` (X is the implementation).
    Refines {
        /// `Y`, the specification.
        other: Vec<String>,
        /// `Y`'s range, or an empty range where it should be.
        other_range: TextRange,
        /// The semantic model of the refinement.
        model: SemanticModelName,
    },
    /// `X equals Y` / `X is not equal to Y`.
    Equals {
        /// `Y`.
        other: Vec<String>,
        /// `Y`'s range, or an empty range where it should be.
        other_range: TextRange,
        /// The semantic model of the equivalence.
        model: SemanticModelName,
    },
    /// `S::s is [not] reachable in M`.
    Reachable {
        /// The state (the same path as the assertion's subject).
        state: Vec<String>,
        /// The state's range.
        state_range: TextRange,
        /// The machine `M` in which the state should be reachable.
        machine: Vec<String>,
        /// `M`'s range, or an empty range where it should be.
        machine_range: TextRange,
    },
    /// `clock C is [not] initialised`.
    ClockInitialised {
        /// The clock (the same path as the assertion's subject).
        clock: Vec<String>,
        /// The clock's range.
        clock_range: TextRange,
    },
    /// `prob property NAME : formula` of probabilistic RoboChart, checked by
    /// RoboTool with PRISM: the formula's text.
    Probabilistic {
        /// The formula, as collapsed text.
        formula: String,
    },
    /// An assertion whose body could not be read (the user is typing): the
    /// body's text. Every complete form of the grammar has its own variant.
    Other(String),
}

impl AssertionKind {
    /// A short stable name of the kind (`"refines"`, `"deadlock-free"`, …),
    /// for reports and statistics.
    pub fn label(&self) -> &'static str {
        match self {
            AssertionKind::Schedulable => "schedulable",
            AssertionKind::DeadlockFree => "deadlock-free",
            AssertionKind::DivergenceFree => "divergence-free",
            AssertionKind::Deterministic => "deterministic",
            AssertionKind::TimelockFree => "timelock-free",
            AssertionKind::Terminates => "terminates",
            AssertionKind::Refines { .. } => "refines",
            AssertionKind::Equals { .. } => "equals",
            AssertionKind::Reachable { .. } => "reachable",
            AssertionKind::ClockInitialised { .. } => "clock-initialised",
            AssertionKind::Probabilistic { .. } => "probabilistic",
            AssertionKind::Other(_) => "other",
        }
    }
}

/// The semantic model named by `in the … model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SemanticModelName {
    /// `traces model`.
    Traces,
    /// `failures model`.
    Failures,
    /// `failures divergences model`.
    FailuresDivergences,
    /// `tick-tock model`.
    TickTock,
    /// No model given (or an unknown one, with a problem).
    Default,
}

/// A value given in the file: literals are evaluated, anything else keeps
/// its text.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Value {
    /// An integer literal, possibly negated or parenthesised; also a real
    /// literal with an integral value (`2.0`).
    Int(i64),
    /// `true` / `false`.
    Bool(bool),
    /// Anything else (an expression, an enumeration value, a real such as
    /// `1.5`, which the bounded semantics cannot represent), with its text
    /// (comments dropped, whitespace collapsed; `""` if missing).
    Other(String),
}

impl Value {
    /// The integer, if this is one.
    pub fn as_int(&self) -> Option<i64> {
        match self {
            Value::Int(n) => Some(*n),
            _ => None,
        }
    }
}

/// One item of an assertion's `with …` list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Override {
    /// `constant NAME of ELEMENT set to VALUE` (also `assigned`, `with value`).
    Constant {
        /// The constant's name (`""` if missing).
        name: String,
        /// The name's range.
        name_range: TextRange,
        /// The element declaring it.
        of: Vec<String>,
        /// The element's range.
        of_range: TextRange,
        /// The value.
        value: Value,
        /// The value's range.
        value_range: TextRange,
        /// The whole item.
        range: TextRange,
    },
    /// `parameter NAME of OPERATION set to VALUE`.
    Parameter {
        /// The parameter's name (`""` if missing).
        name: String,
        /// The name's range.
        name_range: TextRange,
        /// The operation declaring it.
        of: Vec<String>,
        /// The operation's range.
        of_range: TextRange,
        /// The value.
        value: Value,
        /// The value's range.
        value_range: TextRange,
        /// The whole item.
        range: TextRange,
    },
    /// `cycleDef of ELEMENT set to VALUE` (RoboSim): the cycle period of a
    /// simulation or RoboSim module.
    CycleDef {
        /// The element.
        of: Vec<String>,
        /// The element's range.
        of_range: TextRange,
        /// The period.
        value: Value,
        /// The value's range.
        value_range: TextRange,
        /// The whole item.
        range: TextRange,
    },
}

impl Override {
    /// The range of the whole item.
    pub fn range(&self) -> TextRange {
        match self {
            Override::Constant { range, .. } | Override::Parameter { range, .. } | Override::CycleDef { range, .. } => {
                *range
            }
        }
    }
}

/// Data domains and constant values (semantics §3).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Instantiations {
    /// `nametype NAME = {a..b}` (also `{ -2..2}`, and `{a, b, c}` when the
    /// set is a contiguous range) from `csp` blocks: the name as written
    /// (`core_nat`, `nat`, `TemperatureRange`), the bounds and the line.
    pub types: Vec<(String, i64, i64, TextRange)>,
    /// `NAME = VALUE` lines of `csp` blocks whose value is an integer or
    /// boolean literal, with the CSP name as written: RoboTool's generated
    /// names are `const_<Machine>_<constant>` and `<pkg>_<Machine>_<constant>`
    /// (e.g. `const_UAV_poll`, `aggregation_Movement_lv`), but any
    /// identifier is read.
    pub constants: Vec<(String, Value, TextRange)>,
    /// Function definitions `f(p1, …) = e` of `csp` blocks, one clause per
    /// line, in the subset [`crate::csp_fn`] reads.
    pub functions: Vec<crate::csp_fn::CspFunction>,
    /// `instantiate P as T` items (`.assertions`).
    pub type_instantiations: Vec<TypeInstantiation>,
}

impl Instantiations {
    /// The bounds of primitive type `primitive` (`"nat"`, `"int"`, `"real"`,
    /// `"clock_type"`, …), from `nametype core_<primitive>` or
    /// `nametype <primitive>`; the last definition in the file wins.
    pub fn type_bounds(&self, primitive: &str) -> Option<(i64, i64)> {
        let core = format!("core_{primitive}");
        self.types.iter().rev().find(|(n, ..)| *n == core || n == primitive).map(|(_, lo, hi, _)| (*lo, *hi))
    }

    /// The value of CSP constant `name`; the last definition wins.
    pub fn constant(&self, name: &str) -> Option<&Value> {
        self.constants.iter().rev().find(|(n, ..)| n == name).map(|(_, v, _)| v)
    }
}

/// `instantiate P as T` (`.assertions`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeInstantiation {
    /// The primitive type `P`, as qualified-name segments.
    pub primitive: Vec<String>,
    /// The type `T`, as text.
    pub ty: String,
    /// The whole item.
    pub range: TextRange,
}

/// A `[timed|untimed] csp NAME [associated to …] csp-begin … csp-end` block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CspBlockDecl {
    /// The process (or block) name (`""` if missing).
    pub name: String,
    /// The name's range.
    pub name_range: TextRange,
    /// The whole block.
    pub range: TextRange,
    /// Declared `timed`.
    pub timed: bool,
    /// Whether every non-blank, non-comment line of the block was read: a
    /// `nametype` or constant instantiation (into
    /// [`AssertionFile::instantiations`]) or one of RoboTool's standard
    /// definitions ([`CspLineKind::Standard`]), and the block is
    /// terminated by `csp-end`. A block that is not understood needs a CSPm
    /// interpreter ("export to FDR").
    pub understood: bool,
    /// The elements of `associated to A, B`.
    pub associated: Vec<Vec<String>>,
    /// The CSPm text between `csp-begin` and `csp-end`.
    pub text_range: Option<TextRange>,
    /// The block's non-blank, non-comment lines and how they were read.
    pub lines: Vec<CspLine>,
    /// What could not be read.
    pub problems: Vec<Problem>,
}

/// One line of a CSP block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CspLine {
    /// The line, without surrounding blanks and comments.
    pub range: TextRange,
    /// How it was read.
    pub kind: CspLineKind,
}

/// How a CSP block line was read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CspLineKind {
    /// `nametype NAME = {a..b}`, in [`Instantiations::types`].
    Type,
    /// `NAME = literal`, in [`Instantiations::constants`].
    Constant,
    /// `f(p1, …) = e`, in [`Instantiations::functions`].
    Function,
    /// A definition RoboTool generates that restates what the native
    /// semantics does anyway: the saturating arithmetic `Plus`, `Minus`,
    /// `Mult`, `Div`, `Modulus`, `Neg` (semantics §3), `nametype
    /// core_boolean = Bool` and `nametype core_string = LSeq(Char,2)`.
    Standard,
    /// Anything else: CSPm the native checker does not interpret.
    Other,
}

/// Something the reader could not read, on a byte range of the file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Problem {
    /// Where.
    pub range: TextRange,
    /// What.
    pub message: String,
}

impl Problem {
    fn new(range: TextRange, message: impl Into<String>) -> Problem {
        Problem { range, message: message.into() }
    }
}

impl AssertionFile {
    /// The assertion called `name`, if any.
    pub fn assertion(&self, name: &str) -> Option<&AssertionDecl> {
        self.assertions.iter().find(|a| a.name == name)
    }

    /// The simulation called `name`, if any.
    pub fn simulation(&self, name: &str) -> Option<&SimulationDecl> {
        self.simulations.iter().find(|s| s.name == name)
    }

    /// The CSP block called `name`, if any.
    pub fn csp_block(&self, name: &str) -> Option<&CspBlockDecl> {
        self.csp_blocks.iter().find(|b| b.name == name)
    }

    /// The CSP block that contains `range` (e.g. of an instantiation, to
    /// know whether it is `timed`).
    pub fn csp_block_containing(&self, range: TextRange) -> Option<&CspBlockDecl> {
        self.csp_blocks.iter().find(|b| b.range.contains_range(range))
    }

    /// Every problem of the file, in no particular order.
    pub fn problems(&self) -> impl Iterator<Item = &Problem> {
        self.simulations
            .iter()
            .flat_map(|s| &s.problems)
            .chain(self.assertions.iter().flat_map(|a| &a.problems))
            .chain(self.csp_blocks.iter().flat_map(|b| &b.problems))
    }
}

/// Reads the assertion file whose syntax tree is `root` (the root of
/// `robosim_syntax::parse(text, FileKind::SimAssertions | FileKind::Assertions)`).
pub fn read_assertions(root: &SyntaxNode) -> AssertionFile {
    let mut file = AssertionFile::default();
    for node in root.descendants() {
        match node.kind() {
            ASSERTION => file.assertions.push(read_assertion(&node)),
            PROB_PROPERTY => file.assertions.push(prob::read_prob_property(&node)),
            SIMULATION => file.simulations.push(read_simulation(&node)),
            CSP_BLOCK => {
                let block = read_csp_block(&node, &mut file.instantiations);
                file.csp_blocks.push(block);
            }
            TYPE_INSTANTIATION => {
                let primitive = child(&node, QUALIFIED_NAME)
                    .and_then(ast::QualifiedName::cast)
                    .map(|q| q.segments())
                    .unwrap_or_default();
                let ty =
                    node.children().find(|c| ast::is_type_kind(c.kind())).map(|t| collapsed(&t)).unwrap_or_default();
                // A broken item (the parser reports it) instantiates nothing.
                if !primitive.is_empty() && !ty.is_empty() {
                    file.instantiations.type_instantiations.push(TypeInstantiation {
                        primitive,
                        ty,
                        range: node.text_range(),
                    });
                }
            }
            UNSUPPORTED_ITEM => {
                let first = tokens(&node).next().map(|t| t.text().to_string()).unwrap_or_default();
                let what = if first == "sleec" || first == "timed" || first == "untimed" {
                    "SLEEC assertions are not supported: not checked"
                } else {
                    "probabilistic assertions (PRISM) are not supported: not checked"
                };
                file.skipped.push(Problem::new(node.text_range(), what));
            }
            _ => {}
        }
    }
    file
}

// ---------------------------------------------------------------------------
// Tree helpers

fn child(node: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxNode> {
    node.children().find(|c| c.kind() == kind)
}

/// The non-trivia tokens directly under `node`.
fn direct_tokens(node: &SyntaxNode) -> impl Iterator<Item = SyntaxToken> {
    node.children_with_tokens().filter_map(|e| e.into_token()).filter(|t| !t.kind().is_trivia())
}

/// All non-trivia tokens of `node`, in order.
fn tokens(node: &SyntaxNode) -> impl Iterator<Item = SyntaxToken> {
    node.descendants_with_tokens().filter_map(|e| e.into_token()).filter(|t| !t.kind().is_trivia())
}

fn has_token(node: &SyntaxNode, kind: SyntaxKind) -> bool {
    direct_tokens(node).any(|t| t.kind() == kind)
}

/// The text of `node` without comments, each run of trivia one space.
fn collapsed(node: &SyntaxNode) -> String {
    let mut out = String::new();
    let mut gap = false;
    for el in node.descendants_with_tokens() {
        let Some(t) = el.into_token() else { continue };
        if t.kind().is_trivia() {
            gap = true;
            continue;
        }
        if gap && !out.is_empty() {
            out.push(' ');
        }
        gap = false;
        out.push_str(t.text());
    }
    out
}

/// An empty range just after the last direct child of `node` whose kind is
/// one of `after`, or at the end of `node` if there is none: where a
/// missing piece should have been.
fn gap_after(node: &SyntaxNode, after: &[SyntaxKind]) -> TextRange {
    let end = node
        .children_with_tokens()
        .filter(|e| after.contains(&e.kind()))
        .last()
        .map(|e| e.text_range().end())
        .unwrap_or_else(|| node.text_range().end());
    TextRange::empty(end)
}

/// A qualified name's segments and range; when missing, an empty path at
/// `gap` and a problem.
fn required_path(
    q: Option<SyntaxNode>,
    gap: TextRange,
    what: &str,
    problems: &mut Vec<Problem>,
) -> (Vec<String>, TextRange) {
    match q.and_then(ast::QualifiedName::cast) {
        Some(q) if !q.segments().is_empty() => (q.segments(), q.syntax().text_range()),
        Some(q) => {
            problems.push(Problem::new(q.syntax().text_range(), format!("missing {what}")));
            (Vec::new(), q.syntax().text_range())
        }
        None => {
            problems.push(Problem::new(gap, format!("missing {what}")));
            (Vec::new(), gap)
        }
    }
}

/// A declaring `NAME` child's text and range; `""` and a problem if missing.
fn required_name(node: &SyntaxNode, gap: TextRange, what: &str, problems: &mut Vec<Problem>) -> (String, TextRange) {
    match child(node, NAME).and_then(ast::Name::cast) {
        Some(n) if !n.text().is_empty() => (n.text(), n.syntax().text_range()),
        other => {
            let range = other.map(|n| n.syntax().text_range()).unwrap_or(gap);
            problems.push(Problem::new(range, format!("missing {what}")));
            (String::new(), range)
        }
    }
}

// ---------------------------------------------------------------------------
// Values

/// Evaluates a value expression: literals, `-e`, `(e)`; else its text.
pub fn eval_value(expr: &SyntaxNode) -> Value {
    match expr.kind() {
        PAREN_EXPR => match expr.children().find(|c| ast::is_expr_kind(c.kind())) {
            Some(inner) if direct_tokens(expr).all(|t| matches!(t.kind(), L_PAREN | R_PAREN)) => {
                match eval_value(&inner) {
                    Value::Other(_) => Value::Other(collapsed(expr)),
                    v => v,
                }
            }
            _ => Value::Other(collapsed(expr)),
        },
        PREFIX_EXPR => {
            let ops: Vec<_> = direct_tokens(expr).collect();
            let operand = expr.children().find(|c| ast::is_expr_kind(c.kind()));
            match (ops.as_slice(), operand) {
                ([op], Some(e)) if op.kind() == MINUS => match eval_value(&e) {
                    Value::Int(n) => n.checked_neg().map(Value::Int).unwrap_or_else(|| Value::Other(collapsed(expr))),
                    _ => Value::Other(collapsed(expr)),
                },
                _ => Value::Other(collapsed(expr)),
            }
        }
        LITERAL => {
            let toks: Vec<_> = direct_tokens(expr).collect();
            match toks.as_slice() {
                [t] => match t.kind() {
                    TRUE_KW => Value::Bool(true),
                    FALSE_KW => Value::Bool(false),
                    INT_NUMBER => t.text().parse().map(Value::Int).unwrap_or_else(|_| Value::Other(t.text().into())),
                    FLOAT_NUMBER => {
                        integral_real(t.text()).map(Value::Int).unwrap_or_else(|| Value::Other(t.text().into()))
                    }
                    _ => Value::Other(t.text().into()),
                },
                _ => Value::Other(collapsed(expr)),
            }
        }
        _ => Value::Other(collapsed(expr)),
    }
}

/// `2.0` → 2, `2.50` → none.
fn integral_real(text: &str) -> Option<i64> {
    let (int, frac) = text.split_once('.')?;
    if !frac.bytes().all(|b| b == b'0') {
        return None;
    }
    int.parse().ok()
}

/// The value expression of a `with` item, its range, and a problem if missing.
fn read_value(node: &SyntaxNode, problems: &mut Vec<Problem>) -> (Value, TextRange) {
    match node.children().find(|c| ast::is_expr_kind(c.kind())) {
        Some(e) => (eval_value(&e), e.text_range()),
        None => {
            let gap =
                gap_after(node, &[SETTER, QUALIFIED_NAME, OF_KW, NAME_REF, CONSTANT_KW, PARAMETER_KW, CYCLE_DEF_KW]);
            problems.push(Problem::new(gap, "missing the value"));
            (Value::Other(String::new()), gap)
        }
    }
}

fn check_period(value: &Value, range: TextRange, problems: &mut Vec<Problem>) {
    match value {
        Value::Int(n) if *n >= 1 => {}
        Value::Other(text) if text.is_empty() => {}
        Value::Int(n) => problems.push(Problem::new(range, format!("the cycle period must be at least 1, not {n}"))),
        Value::Bool(_) | Value::Other(_) => {
            problems.push(Problem::new(range, "the cycle period must be an integer literal"))
        }
    }
}

// ---------------------------------------------------------------------------
// Assertions

fn read_assertion(node: &SyntaxNode) -> AssertionDecl {
    let mut problems = Vec::new();
    let timed = child(node, TIMING).and_then(|t| direct_tokens(&t).next()).and_then(|t| match t.kind() {
        TIMED_KW => Some(true),
        UNTIMED_KW => Some(false),
        _ => None,
    });
    let (name, name_range) =
        required_name(node, gap_after(node, &[TIMING, ASSERTION_KW]), "the assertion's name", &mut problems);

    let (model, model_range) = match child(node, SEMANTIC_MODEL) {
        None => (SemanticModelName::Default, None),
        Some(sm) => {
            let model = direct_tokens(&sm).find_map(|t| match t.kind() {
                TRACES_MODEL_KW => Some(SemanticModelName::Traces),
                FAILURES_MODEL_KW => Some(SemanticModelName::Failures),
                FAILURES_DIVERGENCES_MODEL_KW => Some(SemanticModelName::FailuresDivergences),
                TICK_TOCK_MODEL_KW => Some(SemanticModelName::TickTock),
                _ => None,
            });
            if model.is_none() {
                problems.push(Problem::new(
                    sm.text_range(),
                    format!("unknown semantic model `{}`: the default model is used", collapsed(&sm)),
                ));
            }
            (model.unwrap_or(SemanticModelName::Default), Some(sm.text_range()))
        }
    };

    let body = child(node, ASSERTION_BODY);
    let is_clock = body.as_ref().is_some_and(|b| has_token(b, CLOCK_KW));
    let subject_gap = gap_after(node, &[TIMING, ASSERTION_KW, NAME, COLON]);
    let (subject, subject_range) = if is_clock {
        let b = body.as_ref().expect("is_clock implies a body");
        required_path(child(b, QUALIFIED_NAME), gap_after(b, &[CLOCK_KW]), "the clock", &mut problems)
    } else {
        let q = child(node, ASSERTION_SUBJECT).and_then(|s| child(&s, QUALIFIED_NAME));
        let gap =
            child(node, ASSERTION_SUBJECT).map(|s| TextRange::empty(s.text_range().start())).unwrap_or(subject_gap);
        required_path(q, gap, "the assertion's subject", &mut problems)
    };

    let (kind, negated) = match &body {
        Some(b) => read_body(b, model, &subject, subject_range, &mut problems),
        None => {
            problems
                .push(Problem::new(gap_after(node, &[ASSERTION_SUBJECT, COLON, NAME]), "missing the assertion's body"));
            (AssertionKind::Other(String::new()), false)
        }
    };

    let mut overrides = Vec::new();
    if let Some(list) = child(node, PARAM_ASSIGNMENTS) {
        for p in list.children() {
            if let Some(o) = read_override(&p, &mut problems) {
                overrides.push(o);
            }
        }
        if overrides.is_empty() {
            problems.push(Problem::new(list.text_range(), "missing the parameters after `with`"));
        }
    }

    AssertionDecl {
        name,
        name_range,
        range: node.text_range(),
        text: collapsed(node),
        subject,
        subject_range,
        negated,
        kind,
        timed,
        model,
        model_range,
        overrides,
        problems,
    }
}

fn read_body(
    body: &SyntaxNode,
    model: SemanticModelName,
    subject: &[String],
    subject_range: TextRange,
    problems: &mut Vec<Problem>,
) -> (AssertionKind, bool) {
    let toks: Vec<SyntaxKind> = direct_tokens(body).map(|t| t.kind()).collect();
    let negated = toks.contains(&NOT_KW);
    let incomplete = |problems: &mut Vec<Problem>, what: &str| {
        problems.push(Problem::new(body.text_range(), format!("incomplete assertion: {what}")));
        (AssertionKind::Other(collapsed(body)), negated)
    };
    let other = |kw: &[SyntaxKind], what: &str, problems: &mut Vec<Problem>| {
        required_path(child(body, QUALIFIED_NAME), gap_after(body, kw), what, problems)
    };
    match toks.first() {
        Some(CLOCK_KW) => {
            if !toks.contains(&INITIALISED_KW) {
                return incomplete(problems, "expected `is [not] initialised` after the clock");
            }
            let kind = AssertionKind::ClockInitialised { clock: subject.to_vec(), clock_range: subject_range };
            (kind, negated)
        }
        Some(IS_KW) => {
            let property = toks.iter().find_map(|k| match k {
                SCHEDULABLE_KW => Some(AssertionKind::Schedulable),
                DEADLOCK_FREE_KW => Some(AssertionKind::DeadlockFree),
                DIVERGENCE_FREE_KW => Some(AssertionKind::DivergenceFree),
                DETERMINISTIC_KW => Some(AssertionKind::Deterministic),
                TIMELOCK_FREE_KW => Some(AssertionKind::TimelockFree),
                _ => None,
            });
            if let Some(kind) = property {
                (kind, negated)
            } else if toks.contains(&REACHABLE_KW) {
                let (machine, machine_range) =
                    other(&[REACHABLE_KW, IN_KW], "the machine after `reachable in`", problems);
                let kind = AssertionKind::Reachable {
                    state: subject.to_vec(),
                    state_range: subject_range,
                    machine,
                    machine_range,
                };
                (kind, negated)
            } else if toks.contains(&EQUAL_KW) {
                let (other, other_range) = other(&[EQUAL_KW, TO_KW], "the element after `equal to`", problems);
                (AssertionKind::Equals { other, other_range, model }, negated)
            } else {
                incomplete(problems, "expected a property after `is`")
            }
        }
        Some(TERMINATES_KW) => (AssertionKind::Terminates, false),
        Some(DOES_KW) => {
            if toks.contains(&REFINE_KW) {
                let (other, other_range) = other(&[REFINE_KW], "the element after `does not refine`", problems);
                (AssertionKind::Refines { other, other_range, model }, true)
            } else if toks.contains(&TERMINATE_KW) {
                (AssertionKind::Terminates, true)
            } else {
                incomplete(problems, "expected `refine` or `terminate` after `does not`")
            }
        }
        Some(REFINES_KW) => {
            let (other, other_range) = other(&[REFINES_KW], "the element after `refines`", problems);
            (AssertionKind::Refines { other, other_range, model }, false)
        }
        Some(EQUALS_KW) => {
            let (other, other_range) = other(&[EQUALS_KW], "the element after `equals`", problems);
            (AssertionKind::Equals { other, other_range, model }, false)
        }
        _ => incomplete(problems, "expected `is …`, `refines`, `equals`, `does not …` or `terminates`"),
    }
}

fn read_override(p: &SyntaxNode, problems: &mut Vec<Problem>) -> Option<Override> {
    let kind = p.kind();
    if !matches!(kind, CONSTANT_PARAM | PARAMETER_PARAM | CYCLE_DEF_PARAM) {
        return None;
    }
    let (name, name_range) = match child(p, NAME_REF).and_then(ast::NameRef::cast) {
        Some(n) if !n.text().is_empty() => (n.text(), n.syntax().text_range()),
        _ if kind == CYCLE_DEF_PARAM => (String::new(), TextRange::empty(p.text_range().start())),
        _ => {
            let gap = gap_after(p, &[CONSTANT_KW, PARAMETER_KW]);
            let what = if kind == CONSTANT_PARAM { "the constant's name" } else { "the parameter's name" };
            problems.push(Problem::new(gap, format!("missing {what}")));
            (String::new(), gap)
        }
    };
    let (of, of_range) = required_path(
        child(p, QUALIFIED_NAME),
        gap_after(p, &[OF_KW, NAME_REF, CONSTANT_KW, PARAMETER_KW, CYCLE_DEF_KW]),
        "the element after `of`",
        problems,
    );
    let (value, value_range) = read_value(p, problems);
    let range = p.text_range();
    if kind == CYCLE_DEF_PARAM {
        check_period(&value, value_range, problems);
        return Some(Override::CycleDef { of, of_range, value, value_range, range });
    }
    Some(if kind == CONSTANT_PARAM {
        Override::Constant { name, name_range, of, of_range, value, value_range, range }
    } else {
        Override::Parameter { name, name_range, of, of_range, value, value_range, range }
    })
}

// ---------------------------------------------------------------------------
// Simulations

fn read_simulation(node: &SyntaxNode) -> SimulationDecl {
    let mut problems = Vec::new();
    let (name, name_range) =
        required_name(node, gap_after(node, &[SIMULATION_KW]), "the simulation's name", &mut problems);
    let (of, of_range) = required_path(
        child(node, QUALIFIED_NAME),
        gap_after(node, &[OF_KW, NAME, SIMULATION_KW]),
        "the simulated element after `of`",
        &mut problems,
    );
    let mut cycle = None;
    let mut cycle_range = None;
    for def in node.children().filter(|c| c.kind() == CYCLE_DEF) {
        if cycle.is_some() {
            problems.push(Problem::new(def.text_range(), "a simulation has one `cycleDef`: this one is ignored"));
            continue;
        }
        cycle_range = Some(def.text_range());
        let Some(expr) = def.children().find(|c| ast::is_expr_kind(c.kind())) else {
            problems.push(Problem::new(gap_after(&def, &[CYCLE_DEF_KW]), "missing `cycle == N` after `cycleDef`"));
            cycle = Some(Value::Other(String::new()));
            continue;
        };
        let value = match cycle_equation(&expr) {
            Some(v) => {
                let value = eval_value(&v);
                check_period(&value, v.text_range(), &mut problems);
                value
            }
            None => {
                problems.push(Problem::new(expr.text_range(), "expected `cycleDef cycle == N` with an integer `N`"));
                Value::Other(collapsed(&expr))
            }
        };
        cycle = Some(value);
    }
    SimulationDecl { name, name_range, range: node.text_range(), of, of_range, cycle, cycle_range, problems }
}

/// `cycle == e`, `e == cycle`, `(…)`, `{ … }` (one element): `e`.
fn cycle_equation(expr: &SyntaxNode) -> Option<SyntaxNode> {
    let inner = |e: &SyntaxNode| -> Option<SyntaxNode> {
        let mut exprs = e.children().filter(|c| ast::is_expr_kind(c.kind()));
        let first = exprs.next()?;
        exprs.next().is_none().then_some(first)
    };
    match expr.kind() {
        PAREN_EXPR => cycle_equation(&inner(expr)?),
        SET_EXPR if !has_token(expr, COMMA) => cycle_equation(&inner(expr)?),
        BIN_EXPR if ast::binary_operator(expr) == Some(EQ2) => {
            let ops = ast::operand_exprs(expr);
            let [a, b] = ops.as_slice() else { return None };
            let is_cycle = |e: &SyntaxNode| {
                let mut e = e.clone();
                while e.kind() == PAREN_EXPR {
                    match inner(&e) {
                        Some(i) => e = i,
                        None => return false,
                    }
                }
                e.kind() == CYCLE_EXPR
            };
            if is_cycle(a) {
                Some(b.clone())
            } else if is_cycle(b) {
                Some(a.clone())
            } else {
                None
            }
        }
        _ => None,
    }
}

// ---------------------------------------------------------------------------
// CSP blocks

fn read_csp_block(node: &SyntaxNode, inst: &mut Instantiations) -> CspBlockDecl {
    let mut problems = Vec::new();
    let timed = child(node, TIMING).and_then(|t| direct_tokens(&t).next()).is_some_and(|t| t.kind() == TIMED_KW);
    let (name, name_range) =
        required_name(node, gap_after(node, &[TIMING, CSP_KW]), "the CSP block's name", &mut problems);
    let associated = child(node, ASSOCIATED_TO)
        .map(|a| a.children().filter_map(ast::QualifiedName::cast).map(|q| q.segments()).collect())
        .unwrap_or_default();
    let mut lines = Vec::new();
    let mut text_range = None;
    let understood = match direct_tokens(node).find(|t| t.kind() == CSP_TEXT) {
        None => {
            problems.push(Problem::new(
                gap_after(node, &[NAME, ASSOCIATED_TO, CSP_KW]),
                "missing the CSP text `csp-begin … csp-end`",
            ));
            false
        }
        Some(tok) => {
            let text = tok.text();
            let start = tok.text_range().start();
            let body_start = if text.starts_with("csp-begin") { "csp-begin".len() } else { 0 };
            let terminated = text.len() >= body_start + "csp-end".len() && text.ends_with("csp-end");
            let body_end = if terminated {
                text.len() - "csp-end".len()
            } else {
                problems.push(Problem::new(tok.text_range(), "unterminated CSP block: expected `csp-end`"));
                text.len()
            };
            let body = &text[body_start..body_end];
            let offset = start + TextSize::from(body_start as u32);
            text_range = Some(TextRange::at(offset, TextSize::from(body.len() as u32)));
            csp::read(body, offset, inst, &mut lines, &mut problems);
            terminated && lines.iter().all(|l: &CspLine| l.kind != CspLineKind::Other)
        }
    };
    CspBlockDecl {
        name,
        name_range,
        range: node.text_range(),
        timed,
        understood,
        associated,
        text_range,
        lines,
        problems,
    }
}

/// A line-based reader for the instantiation subset of CSPm. Comments
/// (`--`, `{- -}`) are dropped; each remaining non-blank line is one
/// [`CspLine`]. A line is read as an instantiation only if it starts a
/// top-level definition: a line inside open brackets or inside a
/// `let … within` (a local definition), and a line followed by one that
/// starts with an operator (the definition goes on), is [`CspLineKind::Other`].
mod csp {
    use super::{CspLine, CspLineKind, Instantiations, Problem, Value};
    use robosim_syntax::{TextRange, TextSize};

    /// RoboTool's saturating arithmetic, without whitespace.
    const STANDARD: &[&str] = &[
        "Plus(e1,e2,T)=ifmember(e1+e2,T)thene1+e2elsee1",
        "Minus(e1,e2,T)=ifmember(e1-e2,T)thene1-e2elsee1",
        "Mult(e1,e2,T)=ifmember(e1*e2,T)thene1*e2elsee1",
        "Div(e1,e2,T)=ifmember(e1/e2,T)thene1/e2elsee1",
        "Modulus(e1,e2,T)=ifmember(e1%e2,T)thene1%e2elsee1",
        "Neg(e1,T)=ifmember(-e1,T)then-e1elsee1",
    ];

    /// A non-blank line of the block, comments blanked out.
    struct Line<'a> {
        text: &'a str,
        /// Offset of `text` in the block.
        at: usize,
        /// Whether it continues a definition of the lines before (inside
        /// brackets or a `let … within`).
        continuation: bool,
    }

    /// Reads `body` (the text between `csp-begin` and `csp-end`, which
    /// starts at `offset` in the file): fills `inst`, `lines` and `problems`.
    pub(super) fn read(
        body: &str,
        offset: TextSize,
        inst: &mut Instantiations,
        lines: &mut Vec<CspLine>,
        problems: &mut Vec<Problem>,
    ) {
        let range =
            |at: usize, len: usize| TextRange::at(offset + TextSize::from(at as u32), TextSize::from(len as u32));
        let masked = mask_comments(body, &mut |at, len, msg| problems.push(Problem::new(range(at, len), msg)));
        let all = split_lines(&masked);
        for (i, line) in all.iter().enumerate() {
            let r = range(line.at, line.text.len());
            let next_continues = all.get(i + 1).is_some_and(|n| starts_with_operator(n.text));
            let kind = if line.continuation || next_continues {
                CspLineKind::Other
            } else {
                classify(line.text, r, inst, problems)
            };
            lines.push(CspLine { range: r, kind });
        }
    }

    /// `body` with `--` and `{- … -}` comments replaced by spaces (newlines
    /// kept, so offsets stay). `{-` followed by a digit is kept as the
    /// negative bound the user meant, with a problem, since FDR would read
    /// a comment there.
    fn mask_comments(body: &str, problem: &mut dyn FnMut(usize, usize, String)) -> String {
        let b = body.as_bytes();
        let mut out = b.to_vec();
        let mut i = 0;
        while i < b.len() {
            if b[i] == b'-' && b.get(i + 1) == Some(&b'-') {
                while i < b.len() && b[i] != b'\n' {
                    out[i] = b' ';
                    i += 1;
                }
            } else if b[i] == b'{' && b.get(i + 1) == Some(&b'-') {
                if b.get(i + 2).is_some_and(|c| c.is_ascii_digit()) {
                    problem(i, 2, "`{-` starts a comment in CSPm: write `{ -…}` with a space for FDR".to_string());
                    i += 2;
                    continue;
                }
                let end = body[i + 2..].find("-}").map(|j| i + 2 + j + 2).unwrap_or(b.len());
                for (k, c) in out.iter_mut().enumerate().take(end).skip(i) {
                    if b[k] != b'\n' {
                        *c = b' ';
                    }
                }
                i = end;
            } else {
                i += 1;
            }
        }
        // Only whole runs of ASCII-delimited comments were blanked, so the
        // text stays valid UTF-8; be total anyway.
        String::from_utf8(out).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
    }

    fn split_lines(masked: &str) -> Vec<Line<'_>> {
        let mut out = Vec::new();
        let mut at = 0;
        let mut brackets = 0usize;
        let mut lets = 0usize;
        for raw in masked.split('\n') {
            let start = at;
            at += raw.len() + 1;
            let text = raw.trim();
            if text.is_empty() {
                continue;
            }
            let lead = raw.len() - raw.trim_start().len();
            out.push(Line { text, at: start + lead, continuation: brackets > 0 || lets > 0 });
            for c in text.chars() {
                match c {
                    '(' | '[' | '{' => brackets += 1,
                    ')' | ']' | '}' => brackets = brackets.saturating_sub(1),
                    _ => {}
                }
            }
            for w in text.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '\'')) {
                match w {
                    "let" => lets += 1,
                    "within" => lets = lets.saturating_sub(1),
                    _ => {}
                }
            }
        }
        out
    }

    /// Whether a line continues the expression of the line before.
    fn starts_with_operator(text: &str) -> bool {
        text.starts_with(|c: char| "+-*/%^.,)]}|&=<>@:;\\[?!~".contains(c))
            || ["then", "else", "within", "and", "or"].iter().any(|k| {
                text.strip_prefix(k).is_some_and(|rest| rest.is_empty() || rest.starts_with(|c: char| !is_ident(c)))
            })
    }

    fn is_ident(c: char) -> bool {
        c.is_ascii_alphanumeric() || c == '_' || c == '\''
    }

    fn is_identifier(s: &str) -> bool {
        s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && s.chars().all(is_ident)
    }

    fn classify(text: &str, range: TextRange, inst: &mut Instantiations, problems: &mut Vec<Problem>) -> CspLineKind {
        let squashed: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        if STANDARD.contains(&squashed.as_str()) {
            return CspLineKind::Standard;
        }
        if let Some(rest) = text.strip_prefix("nametype").filter(|r| r.starts_with(char::is_whitespace)) {
            let Some((name, rhs)) = rest.split_once('=') else { return CspLineKind::Other };
            let (name, rhs) = (name.trim(), rhs.trim());
            if !is_identifier(name) || rhs.starts_with('=') {
                return CspLineKind::Other;
            }
            let rhs_squashed: String = rhs.chars().filter(|c| !c.is_whitespace()).collect();
            let base = name.strip_prefix("core_").unwrap_or(name);
            if (base == "boolean" && rhs_squashed == "Bool") || (base == "string" && rhs_squashed == "LSeq(Char,2)") {
                return CspLineKind::Standard;
            }
            return match int_range(rhs) {
                Some(Ok((lo, hi))) => {
                    inst.types.push((name.to_string(), lo, hi, range));
                    CspLineKind::Type
                }
                Some(Err(msg)) => {
                    problems.push(Problem::new(range, format!("`nametype {name}`: {msg}")));
                    CspLineKind::Other
                }
                None => CspLineKind::Other,
            };
        }
        if let Some((name, params, body)) = crate::csp_fn::parse_definition(text) {
            inst.functions.push(crate::csp_fn::CspFunction { name, params, body, range });
            return CspLineKind::Function;
        }
        if let Some((name, rhs)) = text.split_once('=') {
            let name = name.trim();
            if is_identifier(name) && !rhs.starts_with('=') {
                if let Some(v) = literal(rhs.trim()) {
                    inst.constants.push((name.to_string(), v, range));
                    return CspLineKind::Constant;
                }
            }
        }
        CspLineKind::Other
    }

    /// A CSPm integer or boolean literal, possibly negated or parenthesised.
    fn literal(text: &str) -> Option<Value> {
        let text = text.trim();
        if let Some(inner) = text.strip_prefix('(').and_then(|t| t.strip_suffix(')')) {
            return literal(inner);
        }
        match text {
            "true" => return Some(Value::Bool(true)),
            "false" => return Some(Value::Bool(false)),
            _ => {}
        }
        int(text).map(Value::Int)
    }

    fn int(text: &str) -> Option<i64> {
        let text = text.trim();
        if let Some(rest) = text.strip_prefix('-') {
            return int(rest)?.checked_neg();
        }
        if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        text.parse().ok()
    }

    /// `{a..b}` or a set of integers `{a, b, c}`: `Some(Ok(bounds))` when it
    /// is a non-empty contiguous range, `Some(Err(why))` when it is a set of
    /// integers that is not, `None` when it is something else.
    fn int_range(rhs: &str) -> Option<Result<(i64, i64), String>> {
        let inner = rhs.strip_prefix('{')?.strip_suffix('}')?.trim();
        if let Some((lo, hi)) = inner.split_once("..") {
            let (lo, hi) = (int(lo)?, int(hi)?);
            return Some(if lo <= hi { Ok((lo, hi)) } else { Err(format!("the range {lo}..{hi} is empty")) });
        }
        if inner.is_empty() {
            return Some(Err("the set is empty".to_string()));
        }
        let mut values = inner.split(',').map(int).collect::<Option<Vec<_>>>()?;
        values.sort_unstable();
        values.dedup();
        let (lo, hi) = (values[0], values[values.len() - 1]);
        let contiguous = i128::from(hi) - i128::from(lo) + 1 == values.len() as i128;
        Some(if contiguous {
            Ok((lo, hi))
        } else {
            Err(format!(
                "{{{}}} is not a contiguous range of integers, which is all the native checker supports",
                values.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
            ))
        })
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn integer_sets() {
            assert_eq!(int_range("{0..3}"), Some(Ok((0, 3))));
            assert_eq!(int_range("{ -2 .. 2 }"), Some(Ok((-2, 2))));
            assert_eq!(int_range("{1, 0, 2, 2}"), Some(Ok((0, 2))));
            assert_eq!(int_range("{5}"), Some(Ok((5, 5))));
            assert!(matches!(int_range("{0, 2}"), Some(Err(_))));
            assert!(matches!(int_range("{2..1}"), Some(Err(_))));
            assert!(matches!(int_range("{}"), Some(Err(_))));
            assert_eq!(int_range("{a..b}"), None);
            assert_eq!(int_range("Bool"), None);
            assert_eq!(int_range("{0..99999999999999999999}"), None);
        }

        #[test]
        fn literals() {
            assert_eq!(literal("12"), Some(Value::Int(12)));
            assert_eq!(literal("-(3)"), None);
            assert_eq!(literal("(-3)"), Some(Value::Int(-3)));
            assert_eq!(literal("- 3"), Some(Value::Int(-3)));
            assert_eq!(literal("true"), Some(Value::Bool(true)));
            assert_eq!(literal("1.5"), None);
            assert_eq!(literal("x"), None);
            assert_eq!(literal(""), None);
        }

        #[test]
        fn comments_are_blanked_in_place() {
            let mut problems = Vec::new();
            let text = "a -- b\n{- c\nd -} e\n{-2..2}";
            let masked = mask_comments(text, &mut |at, len, msg| problems.push((at, len, msg)));
            assert_eq!(masked, "a     \n    \n     e\n{-2..2}");
            assert_eq!(problems.len(), 1);
            assert_eq!(mask_comments("{- open", &mut |_, _, _| {}), "       ");
            assert_eq!(mask_comments("é -- é\nx", &mut |_, _, _| {}), "é      \nx");
        }
    }
}
