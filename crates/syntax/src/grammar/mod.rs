//! The grammar of syntax.md as recursive-descent functions. Declarations
//! and blocks are here; types, expressions, statements and the assertion
//! languages have their own modules.

mod assertions;
mod exprs;
mod prob;
mod stmts;
mod types;

use crate::parser::{CompletedMarker, Parser, TokenSet};
use crate::SyntaxKind::{self, *};

pub(crate) use exprs::expr;
pub(crate) use stmts::stmt;
pub(crate) use types::type_;

/// The kinds of block whose members the parser dispatches on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BlockKind {
    File,
    Interface,
    Platform,
    Controller,
    StateMachine,
    Operation,
    State,
    Module,
    InputContext,
    OutputContext,
    Simulation,
    Record,
    Enumeration,
    Function,
}

/// An open block: its kind and a description for messages.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Block<'a> {
    kind: BlockKind,
    what: Named<'a>,
}

/// "state machine `M`", or "the state machine" when the name is missing;
/// formatted only when a message needs it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Named<'a> {
    pub(crate) desc: &'static str,
    pub(crate) name: Option<&'a str>,
}

impl std::fmt::Display for Named<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.name {
            Some(n) => write!(f, "{} `{}`", self.desc, n.trim_start_matches('^')),
            None => write!(f, "the {}", self.desc),
        }
    }
}

/// The member forms a block can contain, recognised by their first token.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Member {
    Package,
    Diagram,
    Import,
    Interface,
    Platform,
    TypeDecl,
    Controller,
    StateMachine,
    OperationDef,
    Function,
    Module,
    InterfaceUse,
    Variables,
    Event,
    Clock,
    OperationSig,
    OperationRef,
    MachineRef,
    ControllerRef,
    PlatformRef,
    Connection,
    Node,
    Transition,
    Action,
    Contract,
    CycleDef,
    IoContext,
}

fn member_at(p: &Parser<'_>) -> Option<Member> {
    Some(match p.current() {
        PACKAGE_KW => Member::Package,
        DIAGRAM_KW => Member::Diagram,
        IMPORT_KW => Member::Import,
        INTERFACE_KW => Member::Interface,
        ROBOTIC_KW => Member::Platform,
        TYPE_KW | DATATYPE_KW | RECORD_KW | ENUMERATION_KW => Member::TypeDecl,
        CONTROLLER_KW => Member::Controller,
        STM_KW => Member::StateMachine,
        OPERATION_KW => Member::OperationDef,
        FUNCTION_KW => Member::Function,
        MODULE_KW => Member::Module,
        USES_KW | PROVIDES_KW | REQUIRES_KW => Member::InterfaceUse,
        VAR_KW | CONST_KW => Member::Variables,
        EVENT_KW | BROADCAST_KW => Member::Event,
        CLOCK_KW => Member::Clock,
        IDENT if p.nth_at(1, L_PAREN) => Member::OperationSig,
        OPREF_KW => Member::OperationRef,
        SREF_KW => Member::MachineRef,
        CREF_KW => Member::ControllerRef,
        RREF_KW => Member::PlatformRef,
        CONNECTION_KW => Member::Connection,
        STATE_KW | INITIAL_KW | JUNCTION_KW | FINAL_KW | PROBABILISTIC_KW => Member::Node,
        TRANSITION_KW => Member::Transition,
        ENTRY_KW | DURING_KW | EXIT_KW => Member::Action,
        TERMINATES_KW | PRECONDITION_KW | POSTCONDITION_KW => Member::Contract,
        CYCLE_DEF_KW => Member::CycleDef,
        INPUT_KW | OUTPUT_KW => Member::IoContext,
        _ => return None,
    })
}

/// Whether `m` may appear in a block of kind `b` in either language.
/// Language-specific restrictions are reported by the member parsers.
fn plausible(b: BlockKind, m: Member) -> bool {
    use BlockKind as B;
    use Member as M;
    match b {
        B::File => matches!(
            m,
            M::Package
                | M::Diagram
                | M::Import
                | M::Interface
                | M::Platform
                | M::TypeDecl
                | M::Controller
                | M::StateMachine
                | M::OperationDef
                | M::Function
                | M::Module
        ),
        B::Interface => matches!(m, M::OperationSig | M::Event | M::Variables | M::Clock),
        B::Platform => matches!(m, M::InterfaceUse | M::Variables | M::OperationSig | M::Event),
        B::Controller => matches!(
            m,
            M::InterfaceUse
                | M::Variables
                | M::Event
                | M::OperationDef
                | M::OperationRef
                | M::StateMachine
                | M::MachineRef
                | M::Connection
                | M::CycleDef
        ),
        B::StateMachine => matches!(
            m,
            M::InterfaceUse | M::Variables | M::Event | M::Node | M::Transition | M::Clock | M::IoContext | M::CycleDef
        ),
        B::Operation => matches!(
            m,
            M::Contract | M::InterfaceUse | M::Variables | M::Event | M::Node | M::Transition | M::Clock | M::IoContext
        ),
        B::State => matches!(m, M::Node | M::Transition | M::Action),
        B::Module => matches!(
            m,
            M::Connection
                | M::Controller
                | M::ControllerRef
                | M::StateMachine
                | M::MachineRef
                | M::Platform
                | M::PlatformRef
                | M::CycleDef
        ),
        B::InputContext | B::OutputContext => matches!(m, M::InterfaceUse | M::Event),
        B::Simulation => matches!(m, M::CycleDef | M::IoContext),
        B::Function => matches!(m, M::Contract),
        B::Record | B::Enumeration => false,
    }
}

fn describe_member(m: Member) -> &'static str {
    match m {
        Member::Package => "a `package` declaration",
        Member::Diagram => "a `diagram` header",
        Member::Import => "an `import`",
        Member::Interface => "an interface",
        Member::Platform => "a robotic platform",
        Member::TypeDecl => "a type declaration",
        Member::Controller => "a controller",
        Member::StateMachine => "a state machine",
        Member::OperationDef => "an operation definition",
        Member::Function => "a function",
        Member::Module => "a module",
        Member::InterfaceUse => "an interface use",
        Member::Variables => "a variable declaration",
        Member::Event => "an event",
        Member::Clock => "a clock",
        Member::OperationSig => "an operation signature",
        Member::OperationRef => "an `opref`",
        Member::MachineRef => "an `sref`",
        Member::ControllerRef => "a `cref`",
        Member::PlatformRef => "an `rref`",
        Member::Connection => "a connection",
        Member::Node => "a state or node",
        Member::Transition => "a transition",
        Member::Action => "an entry, during or exit action",
        Member::Contract => "a `terminates`, `precondition` or `postcondition` clause",
        Member::CycleDef => "a `cycleDef`",
        Member::IoContext => "an input or output context",
    }
}

fn block_desc(b: BlockKind) -> &'static str {
    match b {
        BlockKind::File => "at the top level of a file",
        BlockKind::Interface => "in an interface",
        BlockKind::Platform => "in a robotic platform",
        BlockKind::Controller => "in a controller",
        BlockKind::StateMachine => "in a state machine",
        BlockKind::Operation => "in an operation definition",
        BlockKind::State => "in a state",
        BlockKind::Module => "in a module",
        BlockKind::InputContext => "in an input context",
        BlockKind::OutputContext => "in an output context",
        BlockKind::Simulation => "in a simulation",
        BlockKind::Record => "in a record",
        BlockKind::Enumeration => "in an enumeration",
        BlockKind::Function => "in a function",
    }
}

/// Tokens at which junk skipping stops: they start or end something.
const STOP: TokenSet = TokenSet::new(&[
    R_CURLY,
    PACKAGE_KW,
    DIAGRAM_KW,
    IMPORT_KW,
    INTERFACE_KW,
    ROBOTIC_KW,
    TYPE_KW,
    DATATYPE_KW,
    RECORD_KW,
    ENUMERATION_KW,
    CONTROLLER_KW,
    STM_KW,
    OPERATION_KW,
    FUNCTION_KW,
    MODULE_KW,
    USES_KW,
    PROVIDES_KW,
    REQUIRES_KW,
    VAR_KW,
    CONST_KW,
    EVENT_KW,
    BROADCAST_KW,
    CLOCK_KW,
    OPREF_KW,
    SREF_KW,
    CREF_KW,
    RREF_KW,
    CONNECTION_KW,
    STATE_KW,
    INITIAL_KW,
    JUNCTION_KW,
    FINAL_KW,
    PROBABILISTIC_KW,
    TRANSITION_KW,
    ENTRY_KW,
    DURING_KW,
    EXIT_KW,
    TERMINATES_KW,
    PRECONDITION_KW,
    POSTCONDITION_KW,
    CYCLE_DEF_KW,
    INPUT_KW,
    OUTPUT_KW,
    ASSERTION_KW,
    CSP_KW,
    TIMED_KW,
    UNTIMED_KW,
    SIMULATION_KW,
    INSTANTIATE_KW,
]);

/// The entry point: a whole file of any kind.
pub(crate) fn source_file(p: &mut Parser<'_>) {
    let m = p.start_root();
    if p.file.is_assertions() {
        assertions::assertion_file(p);
    } else {
        if p.at(PACKAGE_KW) {
            package_decl(p);
        }
        p.blocks.push(Block { kind: BlockKind::File, what: Named { desc: "file", name: None } });
        members(p, BlockKind::File, true);
        p.blocks.pop();
    }
    // Anything the grammar left (only possible after a recovery bail-out).
    if !p.at_eof() {
        let e = p.start();
        p.error(format!("unexpected {}", p.found()));
        while !p.at_eof() {
            p.bump_any();
        }
        e.complete(p, ERROR);
    }
    m.complete(p, SOURCE_FILE);
}

/// Entry point for incremental reparsing: one top-level member of a model
/// file that ends with its body's `}` (an interface, platform, type,
/// controller, machine, operation, function or module), parsed exactly as
/// the top-level loop of [`source_file`] parses it. Returns false when the
/// tokens are not exactly one such member, so that the caller parses the
/// whole file instead.
pub(crate) fn top_level_member(p: &mut Parser<'_>) -> bool {
    let m = p.start_root();
    let ok = match member_at(p) {
        Some(
            found @ (Member::Interface
            | Member::Platform
            | Member::TypeDecl
            | Member::Controller
            | Member::StateMachine
            | Member::OperationDef
            | Member::Function
            | Member::Module),
        ) if !p.file.is_assertions() => {
            p.blocks.push(Block { kind: BlockKind::File, what: Named { desc: "file", name: None } });
            member(p, found);
            p.blocks.pop();
            p.at_eof()
        }
        _ => false,
    };
    if !ok {
        // Whatever is left goes into the root so that the builder stays
        // balanced; the caller throws this tree away.
        while !p.at_eof() {
            p.bump_any();
        }
    }
    m.complete(p, SOURCE_FILE);
    ok
}

fn package_decl(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(PACKAGE_KW);
    qualified_name(p, "a package name after `package`");
    m.complete(p, PACKAGE_DECL);
}

/// A block body `{ … }`: the `{` is expected at the current token.
pub(crate) fn block<'a>(p: &mut Parser<'a>, kind: BlockKind, what: Named<'a>) {
    if !p.at(L_CURLY) {
        p.error(format!("expected `{{` to open the body of {what}, found {}", p.found()));
        // Without a `{` only go on if a member of this block follows.
        if !member_at(p).is_some_and(|m| plausible(kind, m)) {
            return;
        }
    } else {
        p.bump(L_CURLY);
    }
    p.blocks.push(Block { kind, what });
    members(p, kind, false);
    p.blocks.pop();
}

/// Members of the innermost block until its `}` (or end of file at top
/// level).
fn members(p: &mut Parser<'_>, kind: BlockKind, top: bool) {
    // RoboSim machines: declarations before the first node or transition.
    let mut seen_node = false;
    loop {
        if p.at_eof() {
            if !top {
                let what = p.blocks.last().map(|b| b.what).unwrap_or(Named { desc: "file", name: None });
                p.error(format!("expected `}}` to close the body of {what}"));
            }
            return;
        }
        if p.at(R_CURLY) {
            if top {
                p.err_and_bump("unexpected `}`: there is no open block to close here");
                continue;
            }
            p.bump(R_CURLY);
            return;
        }
        if !top && p.file.is_assertions() && p.at_ts(assertions::ITEM_START) && !p.at(CSP_KW) {
            let what = p.blocks.last().map(|b| b.what).unwrap_or(Named { desc: "file", name: None });
            let range = p.prev_end();
            p.error_at(range, format!("expected `}}` to close the body of {what}"));
            return;
        }
        match member_at(p) {
            Some(m) if plausible(kind, m) => {
                check_language(p, kind, m, &mut seen_node);
                if kind == BlockKind::Function && p.at(TERMINATES_KW) {
                    p.error("a function has no `terminates` clause: only `precondition` and `postcondition`");
                }
                member(p, m);
            }
            Some(m) if !top && enclosing_accepts(p, m) => {
                let what = p.blocks.last().map(|b| b.what).unwrap_or(Named { desc: "file", name: None });
                let range = p.prev_end();
                p.error_at(range, format!("expected `}}` to close the body of {what} before {}", describe_member(m)));
                return;
            }
            Some(m) => {
                p.error(format!("{} is not allowed {}", describe_member(m), block_desc(kind)));
                member(p, m);
            }
            None => junk(p, kind),
        }
    }
}

fn enclosing_accepts(p: &Parser<'_>, m: Member) -> bool {
    let n = p.blocks.len();
    p.blocks[..n.saturating_sub(1)].iter().any(|b| plausible(b.kind, m))
}

/// Skips tokens that cannot start a member, as one ERROR node.
fn junk(p: &mut Parser<'_>, kind: BlockKind) {
    let msg = match (p.current(), kind) {
        (IDENT, _) if p.nth_text(0) == "_broadcast" && p.is_robosim() => {
            "`_broadcast` events do not exist in RoboSim".to_string()
        }
        (IDENT, BlockKind::StateMachine | BlockKind::Controller | BlockKind::Module) if p.nth_text(0) == "cycleDef" => {
            "`cycleDef` is RoboSim syntax: it is not allowed in a RoboChart (.rct) file".to_string()
        }
        (IDENT, _) if matches!(p.nth_text(0), "input" | "output") && p.nth_text(1) == "context" => {
            "input and output contexts are RoboSim syntax: they are not allowed in a RoboChart (.rct) file".to_string()
        }
        _ => format!("unexpected {} {}: expected {}", p.found(), block_desc(kind), expected_members(kind)),
    };
    let m = p.start();
    p.error(msg);
    loop {
        p.bump_balanced();
        if p.at_eof() || p.at_ts(STOP) || member_at(p).is_some() {
            break;
        }
    }
    m.complete(p, ERROR);
}

fn expected_members(kind: BlockKind) -> &'static str {
    match kind {
        BlockKind::File => {
            "a declaration (`interface`, `stm`, `controller`, `module`, `type`, `function`, `import`, …)"
        }
        BlockKind::Interface => "an event, variable, clock or operation signature",
        BlockKind::Platform => "an interface use, variable, event or operation signature",
        BlockKind::Controller => "a declaration, state machine, operation or connection",
        BlockKind::StateMachine => "a declaration, state, node or transition",
        BlockKind::Operation => "a declaration, node or transition",
        BlockKind::State => "a node, transition or entry/during/exit action",
        BlockKind::Module => "a controller, state machine, platform, reference or connection",
        BlockKind::InputContext | BlockKind::OutputContext => "`uses`, `requires` or an event",
        BlockKind::Simulation => "`cycleDef` or an input/output context",
        BlockKind::Function => "`precondition` or `postcondition`",
        BlockKind::Record => "a field `name : Type`",
        BlockKind::Enumeration => "an enumeration literal",
    }
}

/// Reports members that are plausible here in one language but not in the
/// language of this file (RoboSim's overrides, §3).
fn check_language(p: &mut Parser<'_>, kind: BlockKind, m: Member, seen_node: &mut bool) {
    let rs = p.is_robosim();
    match (kind, m) {
        (BlockKind::StateMachine, Member::Node | Member::Transition) => *seen_node = true,
        (BlockKind::StateMachine, _) if rs && *seen_node => {
            p.error("in a RoboSim state machine, declarations must come before the first node or transition");
        }
        _ => {}
    }
    if !rs {
        return;
    }
    match (kind, m, p.current()) {
        (BlockKind::StateMachine, Member::Event, _) => p.error(
            "events of a RoboSim state machine are declared in its `input context { … }` or `output context { … }`",
        ),
        (BlockKind::Operation, Member::Event, _) => {
            p.error("events of a RoboSim operation are declared in its `input context { … }` or `output context { … }`")
        }
        (BlockKind::StateMachine, Member::InterfaceUse, PROVIDES_KW) => {
            p.error("a RoboSim state machine cannot `provides` an interface: use `uses` or `requires`")
        }
        (BlockKind::Platform, Member::InterfaceUse, REQUIRES_KW) => {
            p.error("a RoboSim robotic platform cannot `requires` an interface: use `provides` or `uses`")
        }
        (BlockKind::InputContext | BlockKind::OutputContext, Member::InterfaceUse, PROVIDES_KW) => {
            p.error("an input or output context only takes `uses` and `requires`")
        }
        _ => {}
    }
}

fn member(p: &mut Parser<'_>, m: Member) {
    match m {
        Member::Package => {
            p.error("`package` must be the first declaration of the file");
            package_decl(p);
        }
        Member::Diagram => {
            let mk = p.start();
            p.bump(DIAGRAM_KW);
            name(p, "diagram");
            mk.complete(p, DIAGRAM_DECL);
        }
        Member::Import => import(p),
        Member::Interface => named_block(p, INTERFACE_KW, INTERFACE, BlockKind::Interface, "interface"),
        Member::Platform => platform(p),
        Member::TypeDecl => type_decl(p),
        Member::Controller => named_block(p, CONTROLLER_KW, CONTROLLER, BlockKind::Controller, "controller"),
        Member::StateMachine => named_block(p, STM_KW, STATE_MACHINE, BlockKind::StateMachine, "state machine"),
        Member::OperationDef => operation_def(p),
        Member::Function => function(p),
        Member::Module => named_block(p, MODULE_KW, MODULE, BlockKind::Module, "module"),
        Member::InterfaceUse => {
            let mk = p.start();
            let kw = p.nth_text(0);
            p.bump_any();
            qualified_name(p, format_args!("an interface name after `{kw}`"));
            mk.complete(p, INTERFACE_USE);
        }
        Member::Variables => variable_list(p),
        Member::Event => event(p),
        Member::Clock => {
            let mk = p.start();
            p.bump(CLOCK_KW);
            name(p, "clock");
            mk.complete(p, CLOCK);
        }
        Member::OperationSig => operation_sig(p),
        Member::OperationRef => reference(p, OPERATION_REF, "operation"),
        Member::MachineRef => reference(p, STATE_MACHINE_REF, "state machine"),
        Member::ControllerRef => reference(p, CONTROLLER_REF, "controller"),
        Member::PlatformRef => reference(p, PLATFORM_REF, "robotic platform"),
        Member::Connection => connection(p),
        Member::Node => node(p),
        Member::Transition => stmts::transition(p),
        Member::Action => {
            let mk = p.start();
            let kind = match p.current() {
                ENTRY_KW => ENTRY_ACTION,
                DURING_KW => DURING_ACTION,
                _ => EXIT_ACTION,
            };
            let kw = p.nth_text(0);
            p.bump_any();
            if stmts::at_stmt_start(p) {
                stmt(p);
            } else {
                p.error_expected(format_args!("a statement after `{kw}`"));
            }
            mk.complete(p, kind);
        }
        Member::Contract => {
            let mk = p.start();
            let kind = match p.current() {
                TERMINATES_KW => TERMINATES_CLAUSE,
                PRECONDITION_KW => PRECONDITION,
                _ => POSTCONDITION,
            };
            p.bump_any();
            if kind != TERMINATES_CLAUSE {
                expr(p);
            }
            mk.complete(p, kind);
        }
        Member::CycleDef => cycle_def(p),
        Member::IoContext => io_context(p),
    }
}

pub(crate) fn cycle_def(p: &mut Parser<'_>) {
    let mk = p.start();
    p.bump(CYCLE_DEF_KW);
    expr(p);
    mk.complete(p, CYCLE_DEF);
}

pub(crate) fn io_context(p: &mut Parser<'_>) {
    let mk = p.start();
    let (kind, block_kind, what) = if p.at(INPUT_KW) {
        (INPUT_CONTEXT, BlockKind::InputContext, "input context")
    } else {
        (OUTPUT_CONTEXT, BlockKind::OutputContext, "output context")
    };
    p.bump_any();
    p.expect_msg(
        CONTEXT_KW,
        format_args!("expected `context` after `{}`", if kind == INPUT_CONTEXT { "input" } else { "output" }),
    );
    block(p, block_kind, Named { desc: what, name: None });
    mk.complete(p, kind);
}

/// `kw Name { members }` for interfaces, controllers, machines and modules.
fn named_block(p: &mut Parser<'_>, kw: SyntaxKind, node: SyntaxKind, kind: BlockKind, what: &'static str) {
    let mk = p.start();
    p.bump(kw);
    let n = name(p, what);
    block(p, kind, describe_named(what, n));
    mk.complete(p, node);
}

fn describe_named<'a>(desc: &'static str, name: Option<&'a str>) -> Named<'a> {
    Named { desc, name }
}

fn platform(p: &mut Parser<'_>) {
    let mk = p.start();
    p.bump(ROBOTIC_KW);
    p.expect_msg(PLATFORM_KW, "expected `platform` after `robotic`");
    let n = name(p, "robotic platform");
    block(p, BlockKind::Platform, describe_named("robotic platform", n));
    mk.complete(p, ROBOTIC_PLATFORM);
}

/// A declaring name. Returns its text when present.
pub(crate) fn name<'a>(p: &mut Parser<'a>, what: impl std::fmt::Display) -> Option<&'a str> {
    if p.at(IDENT) {
        let text = p.nth_text(0).trim_start_matches('^');
        let m = p.start();
        p.bump(IDENT);
        m.complete(p, NAME);
        return Some(text);
    }
    if p.current().is_keyword() && !matches!(p.current(), TRUE_KW | FALSE_KW) && !p.at(L_CURLY) {
        let kw = p.nth_text(0);
        // Take the keyword as the name so the rest keeps its structure.
        let m = p.start();
        p.error(format!(
            "`{kw}` is a reserved word and cannot be the name of the {what}: write `^{kw}` to use it as a name"
        ));
        p.bump_any();
        m.complete(p, NAME);
        return Some(kw);
    }
    p.error_expected(format_args!("a name for the {what}"));
    None
}

/// A simple reference.
pub(crate) fn name_ref(p: &mut Parser<'_>, what: impl std::fmt::Display) -> bool {
    if p.at(IDENT) {
        let m = p.start();
        p.bump(IDENT);
        m.complete(p, NAME_REF);
        return true;
    }
    p.error_expected(what);
    false
}

/// A simple reference where the grammar allows no `::`; a qualified name
/// is reported and kept inside the reference.
pub(crate) fn simple_name_ref(p: &mut Parser<'_>, what: impl std::fmt::Display) -> bool {
    if !p.at(IDENT) {
        p.error_expected(what);
        return false;
    }
    let m = p.start();
    p.bump(IDENT);
    if p.at(COLON2) {
        p.error(format!("{what} is a simple name here: `::` is not allowed"));
        while p.at(COLON2) && p.nth_at(1, IDENT) {
            p.bump(COLON2);
            p.bump(IDENT);
        }
    }
    m.complete(p, NAME_REF);
    true
}

/// `ID ( "::" ID )*`.
pub(crate) fn qualified_name(p: &mut Parser<'_>, what: impl std::fmt::Display) -> bool {
    if !p.at(IDENT) {
        p.error_expected(what);
        return false;
    }
    let m = p.start();
    p.bump(IDENT);
    while p.at(COLON2) {
        if p.nth_at(1, STAR) {
            p.error("write `::*` without spaces");
            p.bump(COLON2);
            break;
        }
        p.bump(COLON2);
        if !p.eat(IDENT) {
            p.error_expected("a name after `::`");
            break;
        }
    }
    m.complete(p, QUALIFIED_NAME);
    true
}

fn import(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(IMPORT_KW);
    qualified_name(p, "a package or element name after `import`");
    if p.at(COLON2) && p.nth_at(1, STAR) {
        p.error("write `::*` without spaces");
        p.bump(COLON2);
        p.bump(STAR);
    } else {
        p.eat(COLON2_STAR);
    }
    m.complete(p, IMPORT);
}

fn type_decl(p: &mut Parser<'_>) {
    let m = p.start();
    match p.current() {
        TYPE_KW => {
            p.bump(TYPE_KW);
            name(p, "type");
            m.complete(p, PRIMITIVE_TYPE_DECL);
        }
        ENUMERATION_KW => {
            p.bump(ENUMERATION_KW);
            let n = name(p, "enumeration");
            list_body(p, BlockKind::Enumeration, describe_named("enumeration", n), enum_literal);
            m.complete(p, ENUM_DECL);
        }
        _ => {
            p.bump_any();
            let n = name(p, "record");
            list_body(p, BlockKind::Record, describe_named("record", n), field);
            m.complete(p, RECORD_DECL);
        }
    }
}

/// `{ item* }` where every item starts with an identifier.
fn list_body<'a>(p: &mut Parser<'a>, kind: BlockKind, what: Named<'a>, item: fn(&mut Parser<'a>)) {
    if !p.expect_msg(L_CURLY, format_args!("expected `{{` to open the body of {what}")) {
        return;
    }
    loop {
        match p.current() {
            R_CURLY => {
                p.bump(R_CURLY);
                return;
            }
            EOF => {
                p.error(format!("expected `}}` to close the body of {what}"));
                return;
            }
            IDENT => item(p),
            _ if member_at(p).is_some() => {
                let range = p.prev_end();
                p.error_at(range, format!("expected `}}` to close the body of {what}"));
                return;
            }
            k if k.is_keyword() && !matches!(k, TRUE_KW | FALSE_KW) => item(p),
            _ => junk(p, kind),
        }
    }
}

fn field(p: &mut Parser<'_>) {
    let m = p.start();
    let n = name(p, "field");
    p.expect_msg(COLON, format_args!("expected `:` and a type after field `{}`", n.unwrap_or_default()));
    type_(p);
    m.complete(p, FIELD);
}

fn enum_literal(p: &mut Parser<'_>) {
    let m = p.start();
    name(p, "enumeration literal");
    if p.eat(L_PAREN) {
        type_list(p);
        p.expect(R_PAREN);
    }
    m.complete(p, ENUM_LITERAL);
}

fn type_list(p: &mut Parser<'_>) {
    type_(p);
    while p.eat(COMMA) {
        type_(p);
    }
}

fn variable_list(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump_any();
    variable(p);
    while p.eat(COMMA) {
        variable(p);
    }
    m.complete(p, VARIABLE_LIST);
}

fn variable(p: &mut Parser<'_>) {
    let m = p.start();
    let n = name(p, "variable");
    p.expect_msg(COLON, format_args!("expected `:` and a type after variable `{}`", n.unwrap_or_default()));
    type_(p);
    if p.eat(EQ) {
        expr(p);
    }
    m.complete(p, VARIABLE);
}

fn event(p: &mut Parser<'_>) {
    let m = p.start();
    p.eat(BROADCAST_KW);
    p.expect(EVENT_KW);
    name(p, "event");
    if p.eat(COLON) {
        type_(p);
    }
    m.complete(p, EVENT);
}

fn operation_sig(p: &mut Parser<'_>) {
    let m = p.start();
    name(p, "operation");
    param_list(p);
    if p.at(L_BRACK) && p.nth_at(1, TERMINATES_KW) {
        let f = p.start();
        p.bump(L_BRACK);
        p.bump(TERMINATES_KW);
        p.expect(R_BRACK);
        f.complete(p, TERMINATES_FLAG);
    }
    m.complete(p, OPERATION_SIG);
}

fn param_list(p: &mut Parser<'_>) {
    let m = p.start();
    if p.expect_msg(L_PAREN, "expected `(` and the parameters") {
        if !p.at(R_PAREN) {
            param(p);
            while p.eat(COMMA) {
                param(p);
            }
        }
        p.expect(R_PAREN);
    }
    m.complete(p, PARAM_LIST);
}

fn param(p: &mut Parser<'_>) {
    let m = p.start();
    let n = name(p, "parameter");
    p.expect_msg(COLON, format_args!("expected `:` and a type after parameter `{}`", n.unwrap_or_default()));
    type_(p);
    m.complete(p, PARAM);
}

fn reference(p: &mut Parser<'_>, kind: SyntaxKind, what: &str) {
    let m = p.start();
    let kw = p.nth_text(0);
    p.bump_any();
    name(p, format_args!("{what} reference"));
    p.expect_msg(EQ, format_args!("expected `=` and the {what} definition after `{kw}` and its name"));
    qualified_name(p, format_args!("the name of a {what} definition"));
    m.complete(p, kind);
}

fn operation_def(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(OPERATION_KW);
    let n = name(p, "operation");
    param_list(p);
    block(p, BlockKind::Operation, describe_named("operation", n));
    m.complete(p, OPERATION_DEF);
}

fn function(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(FUNCTION_KW);
    let n = name(p, "function");
    param_list(p);
    if p.expect_msg(COLON, format_args!("expected `:` and the result type of function `{}`", n.unwrap_or_default())) {
        type_(p);
    }
    block(p, BlockKind::Function, describe_named("function", n));
    m.complete(p, FUNCTION);
}

fn connection(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(CONNECTION_KW);
    simple_name_ref(p, "the source of the connection (a controller, machine or platform)");
    p.expect_msg(ON_KW, "expected `on` and an event after the source of the connection");
    simple_name_ref(p, "the event of the connection's source");
    p.expect_msg(TO_KW, "expected `to` and the target of the connection");
    simple_name_ref(p, "the target of the connection (a controller, machine or platform)");
    p.expect_msg(ON_KW, "expected `on` and an event after the target of the connection");
    simple_name_ref(p, "the event of the connection's target");
    if p.at(L_PAREN) {
        let f = p.start();
        p.bump(L_PAREN);
        p.expect_msg(ASYNC_KW, "expected `_async` in the connection's `( _async )`");
        p.expect(R_PAREN);
        f.complete(p, ASYNC_FLAG);
    }
    if p.at(L_BRACK) {
        let f = p.start();
        p.bump(L_BRACK);
        p.expect_msg(MULT_KW, "expected `mult` in the connection's `[ mult ]`");
        p.expect(R_BRACK);
        f.complete(p, MULT_FLAG);
    }
    m.complete(p, CONNECTION);
}

fn node(p: &mut Parser<'_>) {
    let m = p.start();
    let (kind, what) = match p.current() {
        STATE_KW => (STATE, "state"),
        INITIAL_KW => (INITIAL, "initial junction"),
        JUNCTION_KW => (JUNCTION, "junction"),
        FINAL_KW => (FINAL, "final state"),
        _ => (PROBABILISTIC_JUNCTION, "probabilistic junction"),
    };
    let kw = p.nth_text(0);
    p.bump_any();
    let n = name(p, what);
    if kind == STATE {
        p.nested(|p| {
            block(p, BlockKind::State, describe_named("state", n));
            Some(())
        });
    } else if p.at(L_CURLY) {
        let e = p.start();
        p.error(format!("`{kw}` nodes have no body"));
        p.bump_balanced();
        e.complete(p, ERROR);
    }
    m.complete(p, kind);
}

/// `( args )` as an ARG_LIST node.
pub(crate) fn arg_list(p: &mut Parser<'_>) -> CompletedMarker {
    let m = p.start();
    p.bump(L_PAREN);
    if !p.at(R_PAREN) {
        expr(p);
        while p.eat(COMMA) {
            expr(p);
        }
    }
    p.expect_msg(R_PAREN, "expected `)` to close the argument list");
    m.complete(p, ARG_LIST)
}
