//! Typed views over the syntax tree. Each wrapper is a `SyntaxNode` of one
//! kind; accessors return `None` when the (possibly broken) source lacks
//! the part.

use crate::{RoboLang, SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken};
use rowan::Language;

/// A typed view of a node of one kind.
pub trait AstNode: Sized {
    /// Whether a node of kind `kind` can be viewed as `Self`.
    fn can_cast(kind: SyntaxKind) -> bool;
    /// The view, if the node has the right kind.
    fn cast(node: SyntaxNode) -> Option<Self>;
    /// The underlying node.
    fn syntax(&self) -> &SyntaxNode;
}

fn child<N: AstNode>(parent: &SyntaxNode) -> Option<N> {
    parent.children().find_map(N::cast)
}

fn children<N: AstNode>(parent: &SyntaxNode) -> impl Iterator<Item = N> {
    parent.children().filter_map(N::cast)
}

fn token(parent: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxToken> {
    parent.children_with_tokens().filter_map(|e| e.into_token()).find(|t| t.kind() == kind)
}

fn first_token(parent: &SyntaxNode) -> Option<SyntaxToken> {
    parent.children_with_tokens().filter_map(|e| e.into_token()).find(|t| !t.kind().is_trivia())
}

macro_rules! ast_nodes {
    ($($(#[$doc:meta])* $name:ident = $kind:ident;)*) => {$(
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Eq, Hash)]
        pub struct $name {
            pub(crate) syntax: SyntaxNode,
        }
        impl AstNode for $name {
            fn can_cast(kind: SyntaxKind) -> bool {
                kind == $kind
            }
            fn cast(node: SyntaxNode) -> Option<Self> {
                (node.kind() == $kind).then(|| $name { syntax: node })
            }
            fn syntax(&self) -> &SyntaxNode {
                &self.syntax
            }
        }
    )*};
}

ast_nodes! {
    /// The root of every file.
    SourceFile = SOURCE_FILE;
    /// A declaring identifier.
    Name = NAME;
    /// A simple reference.
    NameRef = NAME_REF;
    /// `a::b::c`.
    QualifiedName = QUALIFIED_NAME;
    /// `package a::b`.
    PackageDecl = PACKAGE_DECL;
    /// `import a::b` or `import a::*`.
    Import = IMPORT;
    /// `type T`.
    PrimitiveTypeDecl = PRIMITIVE_TYPE_DECL;
    /// `record R { … }` / `datatype R { … }`.
    RecordDecl = RECORD_DECL;
    /// A record field.
    Field = FIELD;
    /// `enumeration E { … }`.
    EnumDecl = ENUM_DECL;
    /// An enumeration literal.
    EnumLiteral = ENUM_LITERAL;
    /// `interface I { … }`.
    Interface = INTERFACE;
    /// `event e : T`.
    Event = EVENT;
    /// `var …` / `const …`.
    VariableList = VARIABLE_LIST;
    /// One variable of a list.
    Variable = VARIABLE;
    /// `clock C`.
    Clock = CLOCK;
    /// `op(x : T) [terminates]` in interfaces and platforms.
    OperationSig = OPERATION_SIG;
    /// `( p : T, … )`.
    ParamList = PARAM_LIST;
    /// One parameter.
    Param = PARAM;
    /// `uses I`, `provides I`, `requires I`.
    InterfaceUse = INTERFACE_USE;
    /// `robotic platform P { … }`.
    RoboticPlatform = ROBOTIC_PLATFORM;
    /// `rref p = P`.
    PlatformRef = PLATFORM_REF;
    /// `controller C { … }`.
    Controller = CONTROLLER;
    /// `cref c = C`.
    ControllerRef = CONTROLLER_REF;
    /// `stm M { … }`.
    StateMachine = STATE_MACHINE;
    /// `sref m = M`.
    StateMachineRef = STATE_MACHINE_REF;
    /// `operation op(…) { … }`.
    OperationDef = OPERATION_DEF;
    /// `opref o = Op`.
    OperationRef = OPERATION_REF;
    /// `function f(…) : T { … }`.
    Function = FUNCTION;
    /// `precondition e`.
    Precondition = PRECONDITION;
    /// `postcondition e`.
    Postcondition = POSTCONDITION;
    /// `module M { … }`.
    Module = MODULE;
    /// `connection a on e to b on f …`.
    Connection = CONNECTION;
    /// `cycleDef e` (RoboSim).
    CycleDef = CYCLE_DEF;
    /// `input context { … }` (RoboSim).
    InputContext = INPUT_CONTEXT;
    /// `output context { … }` (RoboSim).
    OutputContext = OUTPUT_CONTEXT;
    /// `state S { … }`.
    State = STATE;
    /// `initial i`.
    Initial = INITIAL;
    /// `junction j`.
    Junction = JUNCTION;
    /// `final f`.
    Final = FINAL;
    /// `probabilistic p`.
    ProbabilisticJunction = PROBABILISTIC_JUNCTION;
    /// `entry s`.
    EntryAction = ENTRY_ACTION;
    /// `during s`.
    DuringAction = DURING_ACTION;
    /// `exit s`.
    ExitAction = EXIT_ACTION;
    /// `transition t { … }`.
    Transition = TRANSITION;
    /// `trigger e…` (RoboChart).
    Trigger = TRIGGER;
    /// `exec` as a trigger (RoboSim).
    ExecTrigger = EXEC_TRIGGER;
    /// `#C`.
    ClockReset = CLOCK_RESET;
    /// `<{ e }`.
    Deadline = DEADLINE;
    /// `condition e` or `condition else`.
    Condition = CONDITION;
    /// `action s`.
    TransitionAction = TRANSITION_ACTION;
    /// `e[|g|]?x`, `e!v`, `e.v`, `e`.
    Communication = COMMUNICATION;
    /// `x = e`, `$x.f = e`.
    AssignStmt = ASSIGN_STMT;
    /// `op(args)` as a statement.
    CallStmt = CALL_STMT;
    /// `$op(args)` (RoboSim).
    SimCallStmt = SIM_CALL_STMT;
    /// `$e`, `$e!v`, `$e.v` (RoboSim).
    OutputCommStmt = OUTPUT_COMM_STMT;
    /// `$e`, `$e.v`, `$e?x : p` in expressions (RoboSim).
    SimRefExpr = SIM_REF_EXPR;
    /// A `name` used in an expression.
    RefExpr = REF_EXPR;
    /// `a op b`.
    BinExpr = BIN_EXPR;
    /// An assertion.
    Assertion = ASSERTION;
    /// `csp P csp-begin … csp-end`.
    CspBlock = CSP_BLOCK;
    /// `simulation S of M { … }` (RoboSim assertions).
    Simulation = SIMULATION;
    /// An ERROR node made by recovery.
    ErrorNode = ERROR;
}

/// Declarations that carry a `Name` child.
pub trait HasName: AstNode {
    /// The declaring name.
    fn name(&self) -> Option<Name> {
        child(self.syntax())
    }
}

macro_rules! has_name {
    ($($t:ty),*) => {$(impl HasName for $t {})*};
}

has_name!(
    PrimitiveTypeDecl,
    RecordDecl,
    Field,
    EnumDecl,
    EnumLiteral,
    Interface,
    Event,
    Variable,
    Clock,
    OperationSig,
    Param,
    RoboticPlatform,
    PlatformRef,
    Controller,
    ControllerRef,
    StateMachine,
    StateMachineRef,
    OperationDef,
    OperationRef,
    Function,
    Module,
    State,
    Initial,
    Junction,
    Final,
    ProbabilisticJunction,
    Transition,
    Assertion,
    CspBlock,
    Simulation
);

impl Name {
    /// The name's text without the `^` escape.
    pub fn text(&self) -> String {
        self.syntax.text().to_string().trim().trim_start_matches('^').to_string()
    }

    /// The identifier token.
    pub fn ident(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
}

impl NameRef {
    /// The referenced name without the `^` escape.
    pub fn text(&self) -> String {
        self.syntax.text().to_string().trim().trim_start_matches('^').to_string()
    }
}

impl QualifiedName {
    /// The segments, without `^` escapes.
    pub fn segments(&self) -> Vec<String> {
        self.syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .filter(|t| t.kind() == IDENT || t.kind().is_keyword())
            .map(|t| t.text().trim_start_matches('^').to_string())
            .collect()
    }

    /// The segments joined by `::`.
    pub fn text(&self) -> String {
        self.segments().join("::")
    }
}

/// A top-level item of a model file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Item {
    /// `import …`.
    Import(Import),
    /// `type`, `record`, `datatype`.
    PrimitiveType(PrimitiveTypeDecl),
    /// A record type.
    Record(RecordDecl),
    /// An enumeration.
    Enum(EnumDecl),
    /// An interface.
    Interface(Interface),
    /// A robotic platform.
    Platform(RoboticPlatform),
    /// A controller.
    Controller(Controller),
    /// A state machine.
    StateMachine(StateMachine),
    /// An operation definition.
    Operation(OperationDef),
    /// A function.
    Function(Function),
    /// A module.
    Module(Module),
}

impl Item {
    fn cast(node: SyntaxNode) -> Option<Item> {
        Some(match node.kind() {
            IMPORT => Item::Import(Import { syntax: node }),
            PRIMITIVE_TYPE_DECL => Item::PrimitiveType(PrimitiveTypeDecl { syntax: node }),
            RECORD_DECL => Item::Record(RecordDecl { syntax: node }),
            ENUM_DECL => Item::Enum(EnumDecl { syntax: node }),
            INTERFACE => Item::Interface(Interface { syntax: node }),
            ROBOTIC_PLATFORM => Item::Platform(RoboticPlatform { syntax: node }),
            CONTROLLER => Item::Controller(Controller { syntax: node }),
            STATE_MACHINE => Item::StateMachine(StateMachine { syntax: node }),
            OPERATION_DEF => Item::Operation(OperationDef { syntax: node }),
            FUNCTION => Item::Function(Function { syntax: node }),
            MODULE => Item::Module(Module { syntax: node }),
            _ => return None,
        })
    }

    /// The underlying node.
    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Item::Import(n) => n.syntax(),
            Item::PrimitiveType(n) => n.syntax(),
            Item::Record(n) => n.syntax(),
            Item::Enum(n) => n.syntax(),
            Item::Interface(n) => n.syntax(),
            Item::Platform(n) => n.syntax(),
            Item::Controller(n) => n.syntax(),
            Item::StateMachine(n) => n.syntax(),
            Item::Operation(n) => n.syntax(),
            Item::Function(n) => n.syntax(),
            Item::Module(n) => n.syntax(),
        }
    }
}

impl SourceFile {
    /// `package …`, if declared.
    pub fn package(&self) -> Option<PackageDecl> {
        child(&self.syntax)
    }
    /// The top-level items in order.
    pub fn items(&self) -> impl Iterator<Item = Item> {
        self.syntax.children().filter_map(Item::cast)
    }
    /// Assertions (assertion files).
    pub fn assertions(&self) -> impl Iterator<Item = Assertion> {
        children(&self.syntax)
    }
    /// CSP blocks (assertion files).
    pub fn csp_blocks(&self) -> impl Iterator<Item = CspBlock> {
        children(&self.syntax)
    }
    /// Simulation declarations (`.rsa`).
    pub fn simulations(&self) -> impl Iterator<Item = Simulation> {
        children(&self.syntax)
    }
}

impl PackageDecl {
    /// The package name.
    pub fn qualified_name(&self) -> Option<QualifiedName> {
        child(&self.syntax)
    }
}

impl Import {
    /// The imported name.
    pub fn qualified_name(&self) -> Option<QualifiedName> {
        child(&self.syntax)
    }
    /// Whether it ends in `::*`.
    pub fn is_wildcard(&self) -> bool {
        token(&self.syntax, COLON2_STAR).is_some()
    }
}

macro_rules! children_accessors {
    ($owner:ty { $($method:ident -> $t:ty;)* }) => {
        impl $owner {
            $(
                #[doc = concat!("The `", stringify!($t), "` children.")]
                pub fn $method(&self) -> impl Iterator<Item = $t> {
                    children(&self.syntax)
                }
            )*
        }
    };
}

children_accessors!(Interface { events -> Event; variable_lists -> VariableList; clocks -> Clock; operations -> OperationSig; });
children_accessors!(RoboticPlatform { uses -> InterfaceUse; events -> Event; variable_lists -> VariableList; operations -> OperationSig; });
children_accessors!(Controller {
    uses -> InterfaceUse; events -> Event; variable_lists -> VariableList; operations -> OperationDef;
    operation_refs -> OperationRef; machines -> StateMachine; machine_refs -> StateMachineRef;
    connections -> Connection; cycle_defs -> CycleDef;
});
children_accessors!(StateMachine {
    uses -> InterfaceUse; events -> Event; variable_lists -> VariableList; clocks -> Clock;
    states -> State; initials -> Initial; junctions -> Junction; finals -> Final;
    transitions -> Transition; input_contexts -> InputContext; output_contexts -> OutputContext; cycle_defs -> CycleDef;
});
children_accessors!(OperationDef {
    uses -> InterfaceUse; events -> Event; variable_lists -> VariableList; clocks -> Clock;
    states -> State; initials -> Initial; transitions -> Transition;
});
children_accessors!(State { states -> State; initials -> Initial; junctions -> Junction; finals -> Final; transitions -> Transition; });
children_accessors!(Module {
    controllers -> Controller; controller_refs -> ControllerRef; machines -> StateMachine;
    machine_refs -> StateMachineRef; platforms -> RoboticPlatform; platform_refs -> PlatformRef;
    connections -> Connection; cycle_defs -> CycleDef;
});
children_accessors!(RecordDecl { fields -> Field; });
children_accessors!(EnumDecl { literals -> EnumLiteral; });
children_accessors!(VariableList { variables -> Variable; });
children_accessors!(ParamList { params -> Param; });
children_accessors!(InputContext { uses -> InterfaceUse; events -> Event; });
children_accessors!(OutputContext { uses -> InterfaceUse; events -> Event; });

impl VariableList {
    /// Whether this is a `const` list.
    pub fn is_const(&self) -> bool {
        token(&self.syntax, CONST_KW).is_some()
    }
}

impl Event {
    /// Whether declared `_broadcast`.
    pub fn is_broadcast(&self) -> bool {
        token(&self.syntax, BROADCAST_KW).is_some()
    }
    /// The node of its type, if typed.
    pub fn type_node(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_type_kind(n.kind()))
    }
}

impl Variable {
    /// The node of its declared type.
    pub fn type_node(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_type_kind(n.kind()))
    }
    /// The initialiser expression, if any.
    pub fn initialiser(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_expr_kind(n.kind()))
    }
}

impl InterfaceUse {
    /// `uses`, `provides` or `requires`.
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    /// The interface named.
    pub fn qualified_name(&self) -> Option<QualifiedName> {
        child(&self.syntax)
    }
}

macro_rules! ref_target {
    ($($t:ty),*) => {$(
        impl $t {
            /// The referenced definition's name.
            pub fn target(&self) -> Option<QualifiedName> {
                child(&self.syntax)
            }
        }
    )*};
}
ref_target!(PlatformRef, ControllerRef, StateMachineRef, OperationRef);

impl OperationSig {
    /// The parameters.
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
    /// Whether marked `[terminates]`.
    pub fn terminates(&self) -> bool {
        self.syntax.children().any(|n| n.kind() == TERMINATES_FLAG)
    }
}

impl OperationDef {
    /// The parameters.
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
}

impl Function {
    /// The parameters.
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
    /// The node of the result type.
    pub fn return_type(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_type_kind(n.kind()))
    }
}

impl Connection {
    /// Source node, source event, target node, target event, in order.
    pub fn endpoints(&self) -> Vec<NameRef> {
        children(&self.syntax).collect()
    }
    /// Whether `( _async )`.
    pub fn is_async(&self) -> bool {
        self.syntax.children().any(|n| n.kind() == ASYNC_FLAG)
    }
    /// Whether `[ mult ]`.
    pub fn is_mult(&self) -> bool {
        self.syntax.children().any(|n| n.kind() == MULT_FLAG)
    }
}

impl Transition {
    /// The source node's name.
    pub fn source(&self) -> Option<NameRef> {
        self.syntax.children().find(|n| n.kind() == TRANSITION_SOURCE).and_then(|n| child(&n))
    }
    /// The target node's name.
    pub fn target(&self) -> Option<NameRef> {
        self.syntax.children().find(|n| n.kind() == TRANSITION_TARGET).and_then(|n| child(&n))
    }
    /// The RoboChart trigger.
    pub fn trigger(&self) -> Option<Trigger> {
        child(&self.syntax)
    }
    /// The RoboSim `exec` trigger.
    pub fn exec(&self) -> Option<ExecTrigger> {
        child(&self.syntax)
    }
    /// Clock resets `#C`.
    pub fn resets(&self) -> impl Iterator<Item = ClockReset> {
        children(&self.syntax)
    }
    /// The deadline.
    pub fn deadline(&self) -> Option<Deadline> {
        child(&self.syntax)
    }
    /// The condition.
    pub fn condition(&self) -> Option<Condition> {
        child(&self.syntax)
    }
    /// The action.
    pub fn action(&self) -> Option<TransitionAction> {
        child(&self.syntax)
    }
}

impl Trigger {
    /// The communication, if any (empty in the legacy syntax).
    pub fn communication(&self) -> Option<Communication> {
        child(&self.syntax)
    }
}

impl Condition {
    /// Whether `condition else`.
    pub fn is_else(&self) -> bool {
        self.syntax.children().any(|n| n.kind() == ELSE_CONDITION)
    }
    /// The guard expression.
    pub fn expr(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_expr_kind(n.kind()))
    }
}

impl TransitionAction {
    /// The statement.
    pub fn stmt(&self) -> Option<SyntaxNode> {
        self.syntax.children().find(|n| is_stmt_kind(n.kind()))
    }
}

impl Communication {
    /// The event's name.
    pub fn event(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl Assertion {
    /// `timed`/`untimed`, if given.
    pub fn timing(&self) -> Option<SyntaxToken> {
        self.syntax.children().find(|n| n.kind() == TIMING).and_then(|n| first_token(&n))
    }
    /// The subject element.
    pub fn subject(&self) -> Option<QualifiedName> {
        self.syntax.children().find(|n| n.kind() == ASSERTION_SUBJECT).and_then(|n| child(&n))
    }
}

impl CspBlock {
    /// The raw `csp-begin … csp-end` token.
    pub fn csp_text(&self) -> Option<SyntaxToken> {
        token(&self.syntax, CSP_TEXT)
    }
}

impl Simulation {
    /// The simulated element.
    pub fn of(&self) -> Option<QualifiedName> {
        child(&self.syntax)
    }
}

/// Whether `kind` is a type node.
pub fn is_type_kind(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        NAMED_TYPE
            | SET_TYPE
            | SEQ_TYPE
            | TYPE_VAR
            | PAREN_TYPE
            | PRODUCT_TYPE
            | FUNCTION_TYPE
            | RELATION_TYPE
            | VECTOR_TYPE
            | MATRIX_TYPE
    )
}

/// The operator token of a `BIN_EXPR` (`==`, `<`, `/\\`, `+`, `cat`, `^`, …),
/// or `None` when recovery left it out. Read from the green tree: typing
/// asks for the operator of every binary expression, and a cursor per token
/// would cost more than the rest.
pub fn binary_operator(node: &SyntaxNode) -> Option<SyntaxKind> {
    node.green().children().filter_map(|c| c.into_token()).map(|t| RoboLang::kind_from_raw(t.kind())).find(|k| {
        matches!(
            k,
            EQ2 | NEQ
                | LT
                | LTEQ
                | GT
                | GTEQ
                | IN_KW
                | AND
                | OR
                | IMPLIES
                | IFF_KW
                | PLUS
                | MINUS
                | STAR
                | SLASH
                | PERCENT
                | CAT_KW
                | CARET
        )
    })
}

/// The text of a name or name-reference node, without surrounding space or
/// the `^` that escapes keywords. Names are almost always one token, read
/// directly: formatting a node's text is far slower.
pub fn name_text(n: &SyntaxNode) -> String {
    let mut parts = n.children_with_tokens();
    if let (Some(rowan::NodeOrToken::Token(t)), None) = (parts.next(), parts.next()) {
        return t.text().trim().trim_start_matches('^').to_string();
    }
    n.text().to_string().trim().trim_start_matches('^').to_string()
}

/// The segments of the qualified name `n` is, or of its first
/// `QUALIFIED_NAME` child; empty when there is none.
pub fn qualified_path(n: &SyntaxNode) -> Vec<String> {
    let q =
        if n.kind() == QUALIFIED_NAME { Some(n.clone()) } else { n.children().find(|c| c.kind() == QUALIFIED_NAME) };
    q.and_then(QualifiedName::cast).map(|q| q.segments()).unwrap_or_default()
}

/// The expression children of `node`, in order (the operands of an operator).
pub fn operand_exprs(node: &SyntaxNode) -> Vec<SyntaxNode> {
    node.children().filter(|c| is_expr_kind(c.kind())).collect()
}

/// Whether `kind` is an expression node.
pub fn is_expr_kind(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        FORALL_EXPR
            | EXISTS_EXPR
            | LAMBDA_EXPR
            | BIN_EXPR
            | PREFIX_EXPR
            | THE_EXPR
            | LET_EXPR
            | IF_EXPR
            | TYPE_TEST_EXPR
            | SELECT_EXPR
            | INDEX_EXPR
            | CALL_EXPR
            | LITERAL
            | REF_EXPR
            | RECORD_LITERAL
            | ENUM_LITERAL_EXPR
            | INTERVAL_EXPR
            | PAREN_EXPR
            | SINCE_EXPR
            | SINCE_ENTRY_EXPR
            | SEQ_EXPR
            | SET_EXPR
            | SET_RANGE_EXPR
            | SET_COMP_EXPR
            | MATRIX_EXPR
            | INVERSE_EXPR
            | TRANSPOSE_EXPR
            | TUPLE_EXPR
            | RESULT_EXPR
            | FROM_EXPR
            | TO_EXPR
            | CYCLE_EXPR
            | SIM_REF_EXPR
    )
}

/// Whether `kind` is a statement node.
pub fn is_stmt_kind(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        SEQ_STMT
            | TIMED_STMT
            | IF_STMT
            | COMM_STMT
            | SKIP_STMT
            | CALL_STMT
            | ASSIGN_STMT
            | PAR_STMT
            | WAIT_STMT
            | CLOCK_RESET_STMT
            | EXEC_STMT
            | OUTPUT_COMM_STMT
            | SIM_CALL_STMT
    )
}

#[cfg(test)]
mod tests {
    use crate::{parse, FileKind, SyntaxKind::BIN_EXPR};

    #[test]
    fn binary_operator_finds_every_operator() {
        let ops =
            ["==", "!=", "<", "<=", ">", ">=", "in", "/\\", "\\/", "=>", "iff", "+", "-", "*", "/", "%", "cat", "^"];
        let text: String = ops.iter().map(|op| format!("stm M{} {{ var x : nat = a {op} b }}\n", op.len())).collect();
        let root = parse(&text, FileKind::RoboChart).syntax_node();
        let found: Vec<_> = root
            .descendants()
            .filter(|n| n.kind() == BIN_EXPR)
            .map(|n| super::binary_operator(&n).and_then(|k| k.text()))
            .collect();
        assert_eq!(found, ops.iter().map(|op| Some(*op)).collect::<Vec<_>>());
    }
}
