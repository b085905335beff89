//! The lowered, typed model of a workspace: what the back ends (the
//! verification engine, the CSPm export) translate from, without reading
//! syntax.
//!
//! In the style of rust-analyzer's `hir-def`: a salsa query per file
//! ([`file_model`]) lowers every top-level element once into plain data —
//! machines and operations with their declarations, nodes in nested
//! regions, transitions with their trigger, guard and action; controllers
//! and modules with their instances and connections; platforms,
//! interfaces, enumerations and records. Expressions and statements are
//! trees ([`Expr`], [`Stmt`]) whose names carry what they resolve to and
//! whose types come from [`crate::types`]. Each element keeps its source
//! range (and [`ItemLoc`]s point at files), so that counterexamples and
//! diagrams still point into the text.
//!
//! The model records what the text says, in order; what it *means* for a
//! semantics (defaults, domains, the composition rules) is the back end's.

mod expr;
mod lower;
mod print;
mod shift;

pub use expr::{BinOp, Comm, CommPart, Expr, ExprKind, Selector, Stmt, StmtKind, UnOp};
pub use lower::{
    assertion_file, element_items, element_model, enum_literals, file_model, item, item_of, lower_file_model, resolve,
};
pub use print::render;
// The definition handles and kinds the model's data carries, so that a
// back end names them through the model.
pub use crate::defs::{ActionKind, DefId, DefKind, Io, UseKind};

use crate::cycle::CycleInfo;
use crate::index::ItemLoc;
use crate::types::Ty;
use crate::TextRange;

/// A type as written (its text and range, for messages) and what it
/// denotes (from [`crate::types::lower`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TyRef {
    /// The type.
    pub ty: Ty,
    /// The type as written, its names unresolved (a back end that resolves
    /// them from the declaring file, rather than to the canonical copy of
    /// a type declared in several files, reads this).
    pub written: crate::defs::TypeRef,
    /// Its text as written (whitespace as in the source).
    pub text: String,
    /// Its range.
    pub range: TextRange,
}

/// One variable of a `var`/`const` list.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct VarDecl {
    /// Its name.
    pub name: String,
    /// Its declared type (none when omitted).
    pub ty: Option<TyRef>,
    /// Its initial value.
    pub init: Option<Expr>,
    /// The declaration's range.
    pub range: TextRange,
}

/// A parameter of an operation (signature or definition).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Param {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: Option<TyRef>,
    /// The parameter's range.
    pub range: TextRange,
}

/// A declaration of a machine, operation, controller, interface or
/// platform, in the order written.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Decl {
    /// `var …` or `const …`.
    Vars {
        /// Whether the list is of constants.
        is_const: bool,
        /// Its variables.
        vars: Vec<VarDecl>,
        /// The list's range.
        range: TextRange,
    },
    /// `clock C`.
    Clock {
        /// Its name.
        name: String,
        /// The declaration's range.
        range: TextRange,
    },
    /// `event e : T`.
    Event {
        /// Its name.
        name: String,
        /// The type of its values, if it carries any.
        ty: Option<TyRef>,
        /// Whether it is a broadcast event.
        broadcast: bool,
        /// The declaration's range.
        range: TextRange,
    },
    /// An operation signature `op(x : T)`.
    OperationSig {
        /// Its name.
        name: String,
        /// Its parameters.
        params: Vec<Param>,
        /// The declaration's range.
        range: TextRange,
    },
    /// An operation defined, or referenced, inside a machine or
    /// interface, or a function: elements a declaration block may hold
    /// that the block itself does not describe further here.
    Nested {
        /// What it is.
        kind: NestedKind,
        /// Its name.
        name: String,
        /// Its range.
        range: TextRange,
    },
}

/// What a [`Decl::Nested`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NestedKind {
    /// `operation O(…) { … }`.
    OperationDef,
    /// `opref o = O`.
    OperationRef,
    /// `function f(…) : T { … }`.
    Function,
}

/// `uses`, `provides` or `requires I`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct InterfaceUse {
    /// Which keyword.
    pub kind: UseKind,
    /// The interface's name as written.
    pub path: Vec<String>,
    /// The interface it resolves to.
    pub target: Option<ItemLoc>,
    /// The whole clause's range.
    pub range: TextRange,
}

/// Declarations and the interfaces used, provided or required, in the
/// order written.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct Decls {
    /// The declarations.
    pub decls: Vec<Decl>,
    /// The interface clauses.
    pub uses: Vec<InterfaceUse>,
}

/// What kind of node of a state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeKind {
    /// A (simple or composite) state.
    State,
    /// A junction.
    Junction,
    /// The initial junction of a region.
    Initial,
    /// A final state.
    Final,
    /// A probabilistic junction.
    Probabilistic,
}

/// An entry, during, exit or transition action.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Action {
    /// Its statement (none when incomplete).
    pub stmt: Option<Stmt>,
    /// The whole clause's range.
    pub range: TextRange,
}

/// A node of a region.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Node {
    /// What it is.
    pub kind: NodeKind,
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// The whole node's range.
    pub range: TextRange,
    /// Every `entry`, `during` and `exit` clause, in the order written
    /// (a well-formed state has at most one of each, the first of each
    /// is lowered below; diagrams show them all).
    pub actions: Vec<(ActionKind, TextRange)>,
    /// `entry` action.
    pub entry: Option<Action>,
    /// `during` action.
    pub during: Option<Action>,
    /// `exit` action.
    pub exit: Option<Action>,
    /// The region inside a state (empty for a simple state).
    pub region: Region,
}

/// The nodes and transitions of a machine, an operation or a state.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct Region {
    /// The nodes, in order.
    pub nodes: Vec<Node>,
    /// The transitions, in order.
    pub transitions: Vec<Transition>,
}

impl Region {
    /// Whether the region has no nodes (a simple state's).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// A transition's condition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Condition {
    /// `condition else`.
    pub is_else: bool,
    /// The guard expression.
    pub expr: Option<Expr>,
    /// The clause's range.
    pub range: TextRange,
}

/// A transition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Transition {
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// The whole transition's range.
    pub range: TextRange,
    /// The source node's name (in the same region).
    pub source: Option<String>,
    /// The target node's name.
    pub target: Option<String>,
    /// The source node: its index in the region's nodes.
    pub source_node: Option<usize>,
    /// The target node: its index in the region's nodes.
    pub target_node: Option<usize>,
    /// The trigger's communication.
    pub trigger: Option<Comm>,
    /// The `trigger` clause's range.
    pub trigger_range: Option<TextRange>,
    /// `exec` (RoboSim).
    pub exec: bool,
    /// The `exec` trigger's range.
    pub exec_range: Option<TextRange>,
    /// `probability p`: its range.
    pub probability: Option<TextRange>,
    /// Clocks reset (`#C`): name and the clause's range.
    pub resets: Vec<(String, TextRange)>,
    /// `condition g`.
    pub condition: Option<Condition>,
    /// `<{d}`: the clause's range and the limit.
    pub deadline: Option<(TextRange, Option<Expr>)>,
    /// `action a`.
    pub action: Option<Action>,
}

/// A state machine or an operation definition: its behaviour.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Behaviour {
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// Its range.
    pub range: TextRange,
    /// Parameters (operations).
    pub params: Vec<Param>,
    /// Declarations and interfaces.
    pub decls: Decls,
    /// RoboSim input and output contexts, in the order written.
    pub contexts: Vec<(Io, Decls)>,
    /// Nodes and transitions.
    pub region: Region,
    /// Every integer literal written in it (RoboTool widens the numeric
    /// types with them).
    pub literals: Vec<i64>,
    /// Its definition in its file (for [`crate::cycle::simulation_period`]).
    pub def: Option<DefId>,
    /// RoboSim: what its `cycleDef`s allow (none without any).
    pub cycle: Option<CycleInfo>,
}

impl Behaviour {
    /// Every communication of its behaviour (triggers and communication
    /// statements, in nodes, actions and transitions), with whether it is
    /// a trigger.
    pub fn communications(&self) -> Vec<(&Comm, bool)> {
        let mut out = Vec::new();
        self.region.communications(&mut out);
        out
    }
}

impl Region {
    /// A transition of the region (or of a state inside it) with an `exec`
    /// trigger, if any (RoboSim).
    pub fn exec_transition(&self) -> Option<&Transition> {
        self.transitions.iter().find(|t| t.exec).or_else(|| self.nodes.iter().find_map(|n| n.region.exec_transition()))
    }

    /// The range of an `exec` statement inside a composite state of the
    /// region (in its substates' actions or its transitions'), if any.
    pub fn exec_in_composite(&self) -> Option<TextRange> {
        self.nodes.iter().filter(|n| !n.region.is_empty()).find_map(|n| n.region.exec_stmt())
    }

    /// The range of an `exec` statement anywhere in the region, if any.
    pub fn exec_stmt(&self) -> Option<TextRange> {
        let mut found = None;
        let actions = self
            .nodes
            .iter()
            .flat_map(|n| [&n.entry, &n.during, &n.exit])
            .chain(self.transitions.iter().map(|t| &t.action));
        for s in actions.filter_map(|a| a.as_ref().and_then(|a| a.stmt.as_ref())) {
            s.walk(&mut |s| {
                if matches!(s.kind, StmtKind::Exec) {
                    found = found.or(Some(s.range));
                }
            });
        }
        found.or_else(|| self.nodes.iter().find_map(|n| n.region.exec_stmt()))
    }

    fn communications<'a>(&'a self, out: &mut Vec<(&'a Comm, bool)>) {
        fn action<'a>(a: &'a Option<Action>, out: &mut Vec<(&'a Comm, bool)>) {
            if let Some(s) = a.as_ref().and_then(|a| a.stmt.as_ref()) {
                s.walk(&mut |s| {
                    if let StmtKind::Comm(c) = &s.kind {
                        out.push((c, false));
                    }
                });
            }
        }
        for n in &self.nodes {
            action(&n.entry, out);
            action(&n.during, out);
            action(&n.exit, out);
            n.region.communications(out);
        }
        for t in &self.transitions {
            if let Some(c) = &t.trigger {
                out.push((c, true));
            }
            action(&t.action, out);
        }
    }
}

/// An element declared inline or referenced by name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Definition<T> {
    /// Declared here.
    Inline(Box<T>),
    /// `sref`/`cref`/`rref`/`opref n = Path`: the path and what it
    /// resolves to.
    Ref {
        /// The path as written.
        path: Vec<String>,
        /// The element.
        target: Option<ItemLoc>,
    },
}

/// An instance of a machine, operation, controller or platform inside a
/// controller or module.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Instance<T> {
    /// The instance's name (the reference's, or the inline element's).
    pub name: String,
    /// Its range.
    pub range: TextRange,
    /// The element.
    pub def: Definition<T>,
}

/// A connection `connection N on e to M on f (_async) [mult]`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Connection {
    /// Source node (instance name, or the enclosing element's).
    pub from: String,
    /// Source event.
    pub efrom: String,
    /// Target node.
    pub to: String,
    /// Target event.
    pub eto: String,
    /// `(_async)`.
    pub is_async: bool,
    /// `[mult]`: both ways.
    pub is_mult: bool,
    /// What the source node is, in the enclosing controller or module.
    pub from_end: End,
    /// What the target node is.
    pub to_end: End,
    /// Its range.
    pub range: TextRange,
}

/// What a connection's node names, in its controller or module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum End {
    /// The enclosing controller (or module) itself.
    This,
    /// A platform of the module (index into its platforms).
    Platform(usize),
    /// A controller of the module (index into its controllers).
    Controller(usize),
    /// A machine of the controller (index into its machines).
    Machine(usize),
    /// Nothing of that name.
    Unknown,
}

/// A controller.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Controller {
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// Its range.
    pub range: TextRange,
    /// Its own declarations (events, interfaces).
    pub decls: Decls,
    /// Its machines, in order.
    pub machines: Vec<Instance<Behaviour>>,
    /// Its operations (defined or referenced), in order.
    pub operations: Vec<Instance<Behaviour>>,
    /// Its connections.
    pub connections: Vec<Connection>,
    /// Its definition in its file (for [`crate::cycle::simulation_period`]).
    pub def: Option<DefId>,
    /// RoboSim: what its and its machines' `cycleDef`s allow.
    pub cycle: Option<CycleInfo>,
}

/// A robotic platform.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Platform {
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// Its range.
    pub range: TextRange,
    /// What it declares, provides and uses.
    pub decls: Decls,
}

/// A module.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Module {
    /// Its name.
    pub name: String,
    /// The name's range (its keyword's when it has none).
    pub name_range: TextRange,
    /// Its range.
    pub range: TextRange,
    /// Its platforms (normally one).
    pub platforms: Vec<Instance<Platform>>,
    /// Its controllers, in order.
    pub controllers: Vec<Instance<Controller>>,
    /// State machines declared or referenced directly in it (which
    /// RoboChart's well-formedness rules reject; diagrams show them), in
    /// order.
    pub machines: Vec<Instance<Behaviour>>,
    /// Its connections.
    pub connections: Vec<Connection>,
    /// Its definition in its file (for [`crate::cycle::simulation_period`]).
    pub def: Option<DefId>,
    /// RoboSim: what its and its controllers' `cycleDef`s allow.
    pub cycle: Option<CycleInfo>,
}

/// A record type's field.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Field {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: Option<TyRef>,
    /// Its range.
    pub range: TextRange,
}

/// A function: its signature and its specification.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Function {
    /// Its name.
    pub name: String,
    /// Its range.
    pub range: TextRange,
    /// Its parameters.
    pub params: Vec<Param>,
    /// Its result type.
    pub result: Option<TyRef>,
    /// `precondition e`, in order.
    pub preconditions: Vec<Expr>,
    /// `postcondition e`, in order (`result == e` defines it).
    pub postconditions: Vec<Expr>,
}

impl Function {
    /// The `e` of each postcondition `result == e` (or `result iff e`),
    /// written that way round: one is the definition RoboTool's CSPm
    /// function is made of (`f(x) = e`, RT-2). Both back ends read it here.
    pub fn result_definitions(&self) -> Vec<&Expr> {
        self.postconditions
            .iter()
            .filter_map(|x| match &x.kind {
                ExprKind::Binary(BinOp::Eq | BinOp::Iff, l, r) if l.kind == ExprKind::Result => Some(&**r),
                _ => None,
            })
            .collect()
    }

    /// Whether a postcondition pins the result (`result == e` or
    /// `e == result`, `iff`, also inside a conjunction): a function that
    /// does has a body, in a form or another.
    pub fn pins_result(&self) -> bool {
        fn pins(e: &Expr) -> bool {
            match &e.kind {
                ExprKind::Binary(BinOp::Eq | BinOp::Iff, a, b) => {
                    a.kind == ExprKind::Result || b.kind == ExprKind::Result
                }
                ExprKind::Binary(BinOp::And, a, b) => pins(a) || pins(b),
                _ => false,
            }
        }
        self.postconditions.iter().any(pins)
    }

    /// Why a call of this function has no meaning the back ends can give,
    /// because of a generic type (`?X`) in its signature; `None` when its
    /// types do not stand in the way. A CSPm function is untyped, so one
    /// without a body over generic parameters is RoboTool's default all
    /// the same (`p_f(x, y) = true`, RT-2), whatever the arguments; but
    /// the default of a generic result depends on the type each call
    /// gives `?X`, which RoboTool's CSPm does not establish, and a body
    /// over generic types is evaluated at the types of each call, which
    /// neither back end does yet. Both refuse with this reason.
    pub fn generic_refusal(&self) -> Option<String> {
        fn var(t: &Option<TyRef>) -> Option<(&str, &str)> {
            t.as_ref().and_then(|t| Some((t.ty.type_variable()?, t.text.trim())))
        }
        let name = &self.name;
        if !self.result_definitions().is_empty() || self.pins_result() {
            let generic = self
                .params
                .iter()
                .find_map(|p| var(&p.ty).map(|(_, t)| format!("the parameter `{}` has the generic type `{t}`", p.name)))
                .or_else(|| var(&self.result).map(|(_, t)| format!("its result has the generic type `{t}`")));
            return Some(format!(
                "the function `{name}` is defined by its postconditions and {}: calls of a function defined \
                 over generic types are not supported yet",
                generic?
            ));
        }
        let (v, t) = var(&self.result)?;
        Some(format!(
            "the function `{name}` has no body and its result type `{t}` is generic: its default (RT-2) depends \
             on the type `?{v}` stands for in each call, which RoboTool's CSPm does not establish; calls of it are \
             not supported yet"
        ))
    }
}

/// A top-level element of a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Item {
    /// `stm`.
    Machine(Behaviour),
    /// `operation`.
    Operation(Behaviour),
    /// `controller`.
    Controller(Controller),
    /// `module`.
    Module(Module),
    /// `robotic platform`.
    Platform(Platform),
    /// `interface`.
    Interface(Platform),
    /// `enumeration`: its literals.
    Enumeration(String, Vec<String>),
    /// `datatype`: its fields.
    Record(String, Vec<Field>),
    /// `type T` (a primitive type).
    PrimitiveType(String),
    /// `function f(…) : T { … }`.
    Function(Function),
    /// Anything the model does not describe (functions, assertions, …).
    Other,
}

/// The model of one file: its top-level elements with their definitions.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct FileModel {
    /// The package path (empty for the default package).
    pub package: Vec<String>,
    /// The elements, in order, each with its definition in the file.
    pub items: Vec<(DefId, Item)>,
    /// Every integer literal written in the file, in order: the numeric
    /// types are bounded once per project, widened by every literal of its
    /// models (robotool-facts RT-5: one `instantiations.csp` for the whole
    /// project), not per element.
    pub literals: Vec<i64>,
    /// The file's syntax errors (not warnings), in order: range and
    /// message. A back end refuses a file that has any.
    pub syntax_errors: Vec<(TextRange, String)>,
}
