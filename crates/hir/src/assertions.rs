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

mod csp;
mod prob;
mod read;

use robosim_syntax::{ast, ast::AstNode, SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange};

use csp::read_csp_block;
pub use read::eval_value;
use read::{read_assertion, read_simulation};

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
