//! Per-file declarations: the syntax tree lowered to a flat arena of named
//! elements (interfaces, machines, states, events, …) with their parents,
//! the interface uses of each context, the references to resolve and the
//! facts the well-formedness rules need. Ranges point into the file.

use robosim_syntax::ast::AstNode as _;
use robosim_syntax::{ast, SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use crate::{parse, Db, File};

/// Index of a definition in its file's [`FileDefs`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DefId(pub u32);

/// What a definition is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum DefKind {
    Interface,
    Platform,
    Controller,
    StateMachine,
    Operation,
    Function,
    Module,
    PrimitiveType,
    Record,
    Enumeration,
    Field,
    EnumLiteral,
    Event,
    Variable,
    Constant,
    Clock,
    OperationSig,
    Parameter,
    State,
    Initial,
    Junction,
    Final,
    ProbabilisticJunction,
    Transition,
    Connection,
    PlatformRef,
    ControllerRef,
    MachineRef,
    OperationRef,
    Assertion,
    CspProcess,
    Simulation,
}

impl DefKind {
    /// A human name for messages ("state machine", "event", …).
    pub fn describe(self) -> &'static str {
        match self {
            DefKind::Interface => "interface",
            DefKind::Platform => "robotic platform",
            DefKind::Controller => "controller",
            DefKind::StateMachine => "state machine",
            DefKind::Operation => "operation",
            DefKind::Function => "function",
            DefKind::Module => "module",
            DefKind::PrimitiveType => "type",
            DefKind::Record => "record",
            DefKind::Enumeration => "enumeration",
            DefKind::Field => "field",
            DefKind::EnumLiteral => "enumeration literal",
            DefKind::Event => "event",
            DefKind::Variable => "variable",
            DefKind::Constant => "constant",
            DefKind::Clock => "clock",
            DefKind::OperationSig => "operation",
            DefKind::Parameter => "parameter",
            DefKind::State => "state",
            DefKind::Initial => "initial junction",
            DefKind::Junction => "junction",
            DefKind::Final => "final state",
            DefKind::ProbabilisticJunction => "probabilistic junction",
            DefKind::Transition => "transition",
            DefKind::Connection => "connection",
            DefKind::PlatformRef => "platform reference",
            DefKind::ControllerRef => "controller reference",
            DefKind::MachineRef => "state machine reference",
            DefKind::OperationRef => "operation reference",
            DefKind::Assertion => "assertion",
            DefKind::CspProcess => "CSP process",
            DefKind::Simulation => "simulation",
        }
    }

    /// Whether this is a node of a state machine (a transition end).
    pub fn is_node(self) -> bool {
        matches!(
            self,
            DefKind::State | DefKind::Initial | DefKind::Junction | DefKind::Final | DefKind::ProbabilisticJunction
        )
    }

    /// Whether this is a type declaration.
    pub fn is_type(self) -> bool {
        matches!(self, DefKind::PrimitiveType | DefKind::Record | DefKind::Enumeration)
    }

    /// Whether definitions of this kind are top-level items that other files
    /// can name.
    pub fn is_item(self) -> bool {
        matches!(
            self,
            DefKind::Interface
                | DefKind::Platform
                | DefKind::Controller
                | DefKind::StateMachine
                | DefKind::Operation
                | DefKind::Function
                | DefKind::Module
                | DefKind::PrimitiveType
                | DefKind::Record
                | DefKind::Enumeration
                | DefKind::CspProcess
                | DefKind::Simulation
        )
    }
}

/// Whether a declaration sits in a RoboSim input or output context.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Io {
    /// `input context { … }`.
    Input,
    /// `output context { … }`.
    Output,
}

/// `uses`, `provides` or `requires`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UseKind {
    /// `uses I`.
    Uses,
    /// `provides I`.
    Provides,
    /// `requires I`.
    Requires,
}

impl UseKind {
    /// The keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            UseKind::Uses => "uses",
            UseKind::Provides => "provides",
            UseKind::Requires => "requires",
        }
    }
}

/// One `uses/provides/requires I` of a context.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Use {
    /// Which keyword.
    pub kind: UseKind,
    /// The interface's (qualified) name.
    pub path: Vec<String>,
    /// The range of the name.
    pub range: TextRange,
    /// The context that uses it.
    pub owner: DefId,
    /// Inside an input/output context, which one.
    pub io: Option<Io>,
}

/// A syntactic type.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum TypeRef {
    Named(Vec<String>, TextRange),
    Set(Box<TypeRef>),
    Seq(Box<TypeRef>),
    Var(String),
    Product(Vec<TypeRef>),
    Function(Box<TypeRef>, Box<TypeRef>),
    Relation(Box<TypeRef>, Box<TypeRef>),
    Vector(Box<TypeRef>, TextRange),
    Matrix(Box<TypeRef>, TextRange, TextRange),
    Missing,
}

/// Kind-specific facts.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
#[allow(missing_docs)]
pub enum DefData {
    #[default]
    None,
    /// Events, variables, constants, parameters, fields.
    Typed {
        ty: Option<TypeRef>,
        init: Option<TextRange>,
        broadcast: bool,
    },
    /// Operation signatures, operation definitions, functions.
    Signature {
        params: Vec<(String, Option<TypeRef>)>,
        result: Option<TypeRef>,
        terminates: bool,
    },
    Transition(TransitionData),
    Connection(ConnectionData),
    /// `rref`/`cref`/`sref`/`opref`: the target's path and its range.
    Reference {
        path: Vec<String>,
        range: TextRange,
    },
    /// Enumeration literal argument types.
    Literal {
        args: Vec<TypeRef>,
    },
}

/// A transition's clauses.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
#[allow(missing_docs)]
pub struct TransitionData {
    pub source: Option<(String, TextRange)>,
    pub target: Option<(String, TextRange)>,
    /// The trigger clause's range and its event (name, range).
    pub trigger: Option<(TextRange, Option<(String, TextRange)>)>,
    pub exec: Option<TextRange>,
    pub probability: Option<TextRange>,
    pub resets: Vec<(String, TextRange)>,
    pub deadline: Option<TextRange>,
    pub condition: Option<TextRange>,
    pub is_else: bool,
    pub action: Option<TextRange>,
}

/// A connection's ends.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
#[allow(missing_docs)]
pub struct ConnectionData {
    pub from: Option<(String, TextRange)>,
    pub efrom: Option<(String, TextRange)>,
    pub to: Option<(String, TextRange)>,
    pub eto: Option<(String, TextRange)>,
    pub is_async: bool,
    /// The `( _async )` flag's range.
    pub async_range: Option<TextRange>,
    pub is_mult: bool,
}

/// One declaration.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Def {
    /// What it is.
    pub kind: DefKind,
    /// Its name without `^` ("" when missing).
    pub name: String,
    /// The name's range (or the keyword's, when the name is missing).
    pub name_range: TextRange,
    /// The whole declaration's range.
    pub range: TextRange,
    /// The enclosing definition.
    pub parent: Option<DefId>,
    /// The I/O context it is declared in (RoboSim).
    pub io: Option<Io>,
    /// Kind-specific facts.
    pub data: DefData,
    /// The node kind, to find the node again.
    pub syntax: SyntaxKind,
}

/// Which action of a state an action clause is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActionKind {
    /// `entry`.
    Entry,
    /// `during`.
    During,
    /// `exit`.
    Exit,
}

impl ActionKind {
    /// Its keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            ActionKind::Entry => "entry",
            ActionKind::During => "during",
            ActionKind::Exit => "exit",
        }
    }
}

/// Facts about a context block (machine, controller, module, operation,
/// state) that are not definitions.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct ContainerFacts {
    /// `cycleDef` expressions (ranges), in order.
    pub cycle_defs: Vec<TextRange>,
    /// `input context` keyword ranges.
    pub input_contexts: Vec<TextRange>,
    /// `output context` keyword ranges.
    pub output_contexts: Vec<TextRange>,
    /// Entry/during/exit actions: which and range.
    pub actions: Vec<(ActionKind, TextRange)>,
}

/// An `import`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ImportDecl {
    /// The imported path.
    pub path: Vec<String>,
    /// Whether it ends in `::*`.
    pub wildcard: bool,
    /// The range of the path.
    pub range: TextRange,
}

/// Everything a file declares.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct FileDefs {
    /// The package path (empty for the default package).
    pub package: Vec<String>,
    /// The package name's range.
    pub package_range: Option<TextRange>,
    /// The imports.
    pub imports: Vec<ImportDecl>,
    /// All definitions, parents before children.
    pub defs: Vec<Def>,
    /// Interface uses of every context.
    pub uses: Vec<Use>,
    /// Per-definition container facts (same indices as `defs`).
    pub facts: Vec<ContainerFacts>,
    /// Children of each definition, and (last) the top-level items: lookups
    /// are by index instead of scanning every definition.
    child_index: Vec<Vec<DefId>>,
    /// Definitions sorted by start offset, for `innermost`.
    by_start: Vec<DefId>,
    /// The id of `defs[0]`: 0 for a file; for one element's definitions
    /// (`crate::element`), the number of definitions before it in the file,
    /// so that ids are the file's.
    base: u32,
}

impl FileDefs {
    /// The definition `id`.
    pub fn def(&self, id: DefId) -> &Def {
        &self.defs[(id.0 - self.base) as usize]
    }

    /// Whether `id` is one of these definitions.
    pub(crate) fn holds(&self, id: DefId) -> bool {
        id.0 >= self.base && ((id.0 - self.base) as usize) < self.defs.len()
    }

    /// The container facts of `id`.
    pub fn facts(&self, id: DefId) -> &ContainerFacts {
        &self.facts[(id.0 - self.base) as usize]
    }

    /// All definitions with their ids.
    pub fn iter(&self) -> impl Iterator<Item = (DefId, &Def)> {
        self.defs.iter().enumerate().map(|(i, d)| (DefId(self.base + i as u32), d))
    }

    /// The direct children of `parent` (`None`: top-level items).
    pub fn children(&self, parent: Option<DefId>) -> impl Iterator<Item = (DefId, &Def)> {
        let slot = match parent {
            Some(p) => (p.0 - self.base) as usize,
            None => self.defs.len(),
        };
        self.child_index.get(slot).into_iter().flatten().map(move |id| (*id, self.def(*id)))
    }

    /// The uses of context `owner`.
    pub fn uses_of(&self, owner: DefId) -> impl Iterator<Item = &Use> {
        self.uses.iter().filter(move |u| u.owner == owner)
    }

    /// The qualified path of a definition inside the file (ancestors' names
    /// then its own), without the package.
    pub fn local_path(&self, id: DefId) -> Vec<String> {
        let mut out = Vec::new();
        let mut cur = Some(id);
        while let Some(c) = cur {
            let d = self.def(c);
            out.push(d.name.clone());
            cur = d.parent;
        }
        out.reverse();
        out
    }

    /// The innermost definition whose range contains `range`.
    pub fn innermost(&self, range: TextRange) -> Option<DefId> {
        // Ranges nest, so the innermost container of `range` is an ancestor
        // (or self) of the last definition starting at or before it.
        let i = self.by_start.partition_point(|id| self.def(*id).range.start() <= range.start());
        let mut cur = self.by_start.get(i.checked_sub(1)?).copied();
        while let Some(c) = cur {
            let d = self.def(c);
            if d.range.contains_range(range) {
                return Some(c);
            }
            cur = d.parent;
        }
        None
    }

    fn build_indexes(&mut self) {
        self.child_index = vec![Vec::new(); self.defs.len() + 1];
        let base = self.base;
        for (i, d) in self.defs.iter().enumerate() {
            let slot = d.parent.map_or(self.defs.len(), |p| (p.0 - base) as usize);
            self.child_index[slot].push(DefId(base + i as u32));
        }
        self.by_start = (0..self.defs.len() as u32).map(|i| DefId(base + i)).collect();
        // Stable: among equal starts, parents (pushed first) stay first.
        self.by_start.sort_by_key(|id| self.defs[(id.0 - base) as usize].range.start());
    }

    /// These definitions with ids from `base` on (they are lowered from
    /// 0), under the package and imports of `header`.
    pub(crate) fn rebased(&self, base: u32, header: &FileDefs) -> FileDefs {
        let mut out = FileDefs {
            package: header.package.clone(),
            package_range: header.package_range,
            imports: header.imports.clone(),
            defs: self.defs.clone(),
            uses: self.uses.clone(),
            facts: self.facts.clone(),
            child_index: Vec::new(),
            by_start: Vec::new(),
            base,
        };
        for d in &mut out.defs {
            if let Some(p) = &mut d.parent {
                p.0 += base;
            }
        }
        for u in &mut out.uses {
            u.owner.0 += base;
        }
        out.build_indexes();
        out
    }
}

/// Lowers a file's tree to its declarations.
#[salsa::tracked(returns(ref))]
pub fn file_defs(db: &dyn Db, file: File) -> FileDefs {
    // Put together from the elements' (`crate::element`): a keystroke
    // lowers the edited element only.
    let mut out = lower_header(&parse(db, file).syntax_node());
    for (e, at) in crate::element::file_elements(db, file) {
        crate::defs_shift::append(&mut out, crate::element::element_lowered(db, *e), (*at).into());
    }
    out.build_indexes();
    out
}

/// The definitions of a whole tree, lowered in one pass: what
/// [`file_defs`] puts together from the elements (tests compare the two).
pub fn lower_file(root: &SyntaxNode) -> FileDefs {
    let mut l = Lower { out: FileDefs::default() };
    for child in root.children() {
        match child.kind() {
            PACKAGE_DECL | IMPORT => header(&mut l.out, &child),
            _ => l.item(&child, None, None),
        }
    }
    l.out.build_indexes();
    l.out
}

/// Records the package or import `child` (a child of the root) in `out`.
fn header(out: &mut FileDefs, child: &SyntaxNode) {
    let Some(q) = child.children().find_map(ast_qualified) else { return };
    if child.kind() == PACKAGE_DECL {
        out.package = q.segments();
        out.package_range = Some(q.syntax().text_range());
    } else {
        let wildcard = child.children_with_tokens().any(|t| t.kind() == COLON2_STAR);
        out.imports.push(ImportDecl { path: q.segments(), wildcard, range: q.syntax().text_range() });
    }
}

/// The package and imports of a file's tree, alone.
pub(crate) fn lower_header(root: &SyntaxNode) -> FileDefs {
    let mut out = FileDefs::default();
    // Found on the green tree, a cursor built for these nodes only: this
    // runs after every keystroke, and a file has hundreds of elements.
    let (raw_package, raw_import) = (rowan::SyntaxKind(PACKAGE_DECL as u16), rowan::SyntaxKind(IMPORT as u16));
    let mut at = root.text_range().start();
    for child in root.green().children() {
        let len = child.text_len();
        if let rowan::NodeOrToken::Node(n) = child {
            if n.kind() == raw_package || n.kind() == raw_import {
                let range = TextRange::at(at, len);
                match root.child_or_token_at_range(range).and_then(|c| c.into_node()) {
                    Some(c) if c.text_range() == range && matches!(c.kind(), PACKAGE_DECL | IMPORT) => {
                        header(&mut out, &c)
                    }
                    // Not found alone (cannot happen with non-empty
                    // nodes): the plain walk.
                    _ => return lower_header_walk(root),
                }
            }
        }
        at += len;
    }
    out
}

fn lower_header_walk(root: &SyntaxNode) -> FileDefs {
    let mut out = FileDefs::default();
    for child in root.children().filter(|c| matches!(c.kind(), PACKAGE_DECL | IMPORT)) {
        header(&mut out, &child);
    }
    out
}

/// The definitions of one top-level element (`node`: a child of the root
/// that is not a package or an import), with ids from 0: what
/// [`file_defs`] lowers from it.
pub(crate) fn lower_element(node: &SyntaxNode) -> FileDefs {
    let mut l = Lower { out: FileDefs::default() };
    l.item(node, None, None);
    l.out.build_indexes();
    l.out
}

fn ast_qualified(n: SyntaxNode) -> Option<ast::QualifiedName> {
    use ast::AstNode;
    ast::QualifiedName::cast(n)
}

struct Lower {
    out: FileDefs,
}

/// The text of a name or name-reference node, as
/// [`robosim_syntax::ast::name_text`] gives it, read from the green tree
/// without a cursor per token (names are read for every declaration and
/// reference of the file).
pub(crate) fn name_text(n: &SyntaxNode) -> String {
    green_name_text(n.green())
}

/// The text of the first `NAME` child (without `^`) and its range.
fn name_of(node: &SyntaxNode) -> Option<(String, TextRange)> {
    child_name(node, NAME)
}

fn ref_of(node: &SyntaxNode) -> Option<(String, TextRange)> {
    child_name(node, NAME_REF)
}

/// The text and range of the first child of `node` of kind `kind` (a name
/// or name reference), read from the green tree: every declaration has
/// a name, and a cursor per child cost more than the rest of lowering.
fn child_name(node: &SyntaxNode, kind: SyntaxKind) -> Option<(String, TextRange)> {
    let mut offset = node.text_range().start();
    for child in node.green().children() {
        let len = child.text_len();
        if let rowan::NodeOrToken::Node(c) = child {
            if <robosim_syntax::RoboLang as rowan::Language>::kind_from_raw(c.kind()) == kind {
                return Some((green_name_text(c), TextRange::at(offset, len)));
            }
        }
        offset += len;
    }
    None
}

/// [`name_text`] of a green name node.
pub(crate) fn green_name_text(n: &rowan::GreenNodeData) -> String {
    let mut parts = n.children();
    if let (Some(rowan::NodeOrToken::Token(t)), None) = (parts.next(), parts.next()) {
        return t.text().trim().trim_start_matches('^').to_string();
    }
    n.to_string().trim().trim_start_matches('^').to_string()
}

fn path_of(node: &SyntaxNode) -> Option<(Vec<String>, TextRange)> {
    let q = node.children().find_map(ast_qualified)?;
    Some((q.segments(), q.syntax().text_range()))
}

fn first_token_range(node: &SyntaxNode) -> TextRange {
    node.children_with_tokens()
        .find(|t| !t.kind().is_trivia())
        .map(|t| t.text_range())
        .unwrap_or_else(|| node.text_range())
}

/// Lowers a type node.
pub fn lower_type(node: &SyntaxNode) -> TypeRef {
    let types: Vec<SyntaxNode> = node.children().filter(|c| ast::is_type_kind(c.kind())).collect();
    let first = || types.first().map(lower_type).unwrap_or(TypeRef::Missing);
    match node.kind() {
        NAMED_TYPE => match path_of(node) {
            Some((p, r)) => TypeRef::Named(p, r),
            None => TypeRef::Missing,
        },
        SET_TYPE => TypeRef::Set(Box::new(first())),
        SEQ_TYPE => TypeRef::Seq(Box::new(first())),
        TYPE_VAR => TypeRef::Var(
            node.children_with_tokens()
                .filter_map(|t| t.into_token())
                .find(|t| t.kind() == IDENT)
                .map(|t| t.text().trim_start_matches('^').to_string())
                .unwrap_or_default(),
        ),
        PAREN_TYPE => first(),
        PRODUCT_TYPE => TypeRef::Product(types.iter().map(lower_type).collect()),
        FUNCTION_TYPE | RELATION_TYPE => {
            let a = types.first().map(lower_type).unwrap_or(TypeRef::Missing);
            let b = types.get(1).map(lower_type).unwrap_or(TypeRef::Missing);
            if node.kind() == FUNCTION_TYPE {
                TypeRef::Function(Box::new(a), Box::new(b))
            } else {
                TypeRef::Relation(Box::new(a), Box::new(b))
            }
        }
        VECTOR_TYPE | MATRIX_TYPE => {
            let sizes: Vec<TextRange> =
                node.children().filter(|c| ast::is_expr_kind(c.kind())).map(|c| c.text_range()).collect();
            let empty = TextRange::empty(node.text_range().end());
            if node.kind() == VECTOR_TYPE {
                TypeRef::Vector(Box::new(first()), sizes.first().copied().unwrap_or(empty))
            } else {
                TypeRef::Matrix(
                    Box::new(first()),
                    sizes.first().copied().unwrap_or(empty),
                    sizes.get(1).copied().unwrap_or(empty),
                )
            }
        }
        _ => TypeRef::Missing,
    }
}

fn type_child(node: &SyntaxNode) -> Option<TypeRef> {
    node.children().find(|c| ast::is_type_kind(c.kind())).map(|t| lower_type(&t))
}

impl Lower {
    fn push(
        &mut self,
        kind: DefKind,
        node: &SyntaxNode,
        parent: Option<DefId>,
        io: Option<Io>,
        data: DefData,
    ) -> DefId {
        let (name, name_range) = name_of(node).unwrap_or_else(|| (String::new(), first_token_range(node)));
        self.push_named(kind, name, name_range, node, parent, io, data)
    }

    #[allow(clippy::too_many_arguments)]
    fn push_named(
        &mut self,
        kind: DefKind,
        name: String,
        name_range: TextRange,
        node: &SyntaxNode,
        parent: Option<DefId>,
        io: Option<Io>,
        data: DefData,
    ) -> DefId {
        let id = DefId(self.out.defs.len() as u32);
        self.out.defs.push(Def {
            kind,
            name,
            name_range,
            range: node.text_range(),
            parent,
            io,
            data,
            syntax: node.kind(),
        });
        self.out.facts.push(ContainerFacts::default());
        id
    }

    /// A declaration or member at any level.
    fn item(&mut self, node: &SyntaxNode, parent: Option<DefId>, io: Option<Io>) {
        let kind = match node.kind() {
            INTERFACE => DefKind::Interface,
            ROBOTIC_PLATFORM => DefKind::Platform,
            CONTROLLER => DefKind::Controller,
            STATE_MACHINE => DefKind::StateMachine,
            OPERATION_DEF => DefKind::Operation,
            MODULE => DefKind::Module,
            STATE => DefKind::State,
            SIMULATION => DefKind::Simulation,
            FUNCTION => {
                let data = self.signature(node);
                let id = self.push(DefKind::Function, node, parent, io, data);
                self.params(node, id);
                return;
            }
            PRIMITIVE_TYPE_DECL => {
                self.push(DefKind::PrimitiveType, node, parent, io, DefData::None);
                return;
            }
            RECORD_DECL => {
                let id = self.push(DefKind::Record, node, parent, io, DefData::None);
                for f in node.children().filter(|c| c.kind() == FIELD) {
                    let data = DefData::Typed { ty: type_child(&f), init: None, broadcast: false };
                    self.push(DefKind::Field, &f, Some(id), None, data);
                }
                return;
            }
            ENUM_DECL => {
                let id = self.push(DefKind::Enumeration, node, parent, io, DefData::None);
                for lit in node.children().filter(|c| c.kind() == ENUM_LITERAL) {
                    let args = lit.children().filter(|c| ast::is_type_kind(c.kind())).map(|t| lower_type(&t)).collect();
                    self.push(DefKind::EnumLiteral, &lit, Some(id), None, DefData::Literal { args });
                }
                return;
            }
            EVENT => {
                let data = DefData::Typed {
                    ty: type_child(node),
                    init: None,
                    broadcast: node.children_with_tokens().any(|t| t.kind() == BROADCAST_KW),
                };
                self.push(DefKind::Event, node, parent, io, data);
                return;
            }
            VARIABLE_LIST => {
                let is_const = node.children_with_tokens().any(|t| t.kind() == CONST_KW);
                for v in node.children().filter(|c| c.kind() == VARIABLE) {
                    let init = v.children().find(|c| ast::is_expr_kind(c.kind())).map(|e| e.text_range());
                    let data = DefData::Typed { ty: type_child(&v), init, broadcast: false };
                    let kind = if is_const { DefKind::Constant } else { DefKind::Variable };
                    self.push(kind, &v, parent, io, data);
                }
                return;
            }
            CLOCK => {
                self.push(DefKind::Clock, node, parent, io, DefData::None);
                return;
            }
            OPERATION_SIG => {
                let data = self.signature(node);
                let id = self.push(DefKind::OperationSig, node, parent, io, data);
                self.params(node, id);
                return;
            }
            INITIAL | JUNCTION | FINAL | PROBABILISTIC_JUNCTION => {
                let kind = match node.kind() {
                    INITIAL => DefKind::Initial,
                    JUNCTION => DefKind::Junction,
                    FINAL => DefKind::Final,
                    _ => DefKind::ProbabilisticJunction,
                };
                self.push(kind, node, parent, io, DefData::None);
                return;
            }
            TRANSITION => {
                let data = DefData::Transition(transition_data(node));
                self.push(DefKind::Transition, node, parent, io, data);
                return;
            }
            CONNECTION => {
                let refs: Vec<(String, TextRange)> = node
                    .children()
                    .filter(|c| c.kind() == NAME_REF)
                    .map(|n| (crate::defs::name_text(&n), n.text_range()))
                    .collect();
                let data = ConnectionData {
                    from: refs.first().cloned(),
                    efrom: refs.get(1).cloned(),
                    to: refs.get(2).cloned(),
                    eto: refs.get(3).cloned(),
                    is_async: node.children().any(|c| c.kind() == ASYNC_FLAG),
                    async_range: node.children().find(|c| c.kind() == ASYNC_FLAG).map(|c| c.text_range()),
                    is_mult: node.children().any(|c| c.kind() == MULT_FLAG),
                };
                let r = first_token_range(node);
                self.push_named(DefKind::Connection, String::new(), r, node, parent, io, DefData::Connection(data));
                return;
            }
            PLATFORM_REF | CONTROLLER_REF | STATE_MACHINE_REF | OPERATION_REF => {
                let kind = match node.kind() {
                    PLATFORM_REF => DefKind::PlatformRef,
                    CONTROLLER_REF => DefKind::ControllerRef,
                    STATE_MACHINE_REF => DefKind::MachineRef,
                    _ => DefKind::OperationRef,
                };
                let data = match path_of(node) {
                    Some((path, range)) => DefData::Reference { path, range },
                    None => DefData::None,
                };
                self.push(kind, node, parent, io, data);
                return;
            }
            INTERFACE_USE => {
                if let Some(owner) = parent {
                    self.interface_use(node, owner, io);
                }
                return;
            }
            INPUT_CONTEXT | OUTPUT_CONTEXT => {
                let which = if node.kind() == INPUT_CONTEXT { Io::Input } else { Io::Output };
                if let Some(owner) = parent {
                    let r = first_token_range(node);
                    let f = &mut self.out.facts[owner.0 as usize];
                    if which == Io::Input {
                        f.input_contexts.push(r);
                    } else {
                        f.output_contexts.push(r);
                    }
                }
                for c in node.children() {
                    self.item(&c, parent, Some(which));
                }
                return;
            }
            CYCLE_DEF => {
                if let Some(owner) = parent {
                    let r = node
                        .children()
                        .find(|c| ast::is_expr_kind(c.kind()))
                        .map(|e| e.text_range())
                        .unwrap_or_else(|| first_token_range(node));
                    self.out.facts[owner.0 as usize].cycle_defs.push(r);
                }
                return;
            }
            ENTRY_ACTION | DURING_ACTION | EXIT_ACTION => {
                if let Some(owner) = parent {
                    let kind = match node.kind() {
                        ENTRY_ACTION => ActionKind::Entry,
                        DURING_ACTION => ActionKind::During,
                        _ => ActionKind::Exit,
                    };
                    self.out.facts[owner.0 as usize].actions.push((kind, node.text_range()));
                }
                return;
            }
            ASSERTION | PROB_PROPERTY | PROB_CONSTANTS => {
                self.push(DefKind::Assertion, node, parent, io, DefData::None);
                return;
            }
            PROB_CONST => {
                let data = DefData::Typed { ty: type_child(node), init: None, broadcast: false };
                self.push(DefKind::Constant, node, parent, io, data);
                return;
            }
            CSP_BLOCK => {
                self.push(DefKind::CspProcess, node, parent, io, DefData::None);
                return;
            }
            _ => return,
        };
        let data = if kind == DefKind::Operation { self.signature(node) } else { DefData::None };
        let id = self.push(kind, node, parent, io, data);
        if kind == DefKind::Operation {
            self.params(node, id);
        }
        for c in node.children() {
            if c.kind() != PARAM_LIST {
                self.item(&c, Some(id), None);
            }
        }
    }

    fn interface_use(&mut self, node: &SyntaxNode, owner: DefId, io: Option<Io>) {
        let kind = match node.children_with_tokens().find(|t| !t.kind().is_trivia()).map(|t| t.kind()) {
            Some(PROVIDES_KW) => UseKind::Provides,
            Some(REQUIRES_KW) => UseKind::Requires,
            _ => UseKind::Uses,
        };
        if let Some((path, range)) = path_of(node) {
            self.out.uses.push(Use { kind, path, range, owner, io });
        }
    }

    fn signature(&mut self, node: &SyntaxNode) -> DefData {
        let params = node
            .children()
            .find(|c| c.kind() == PARAM_LIST)
            .map(|pl| {
                pl.children()
                    .filter(|c| c.kind() == PARAM)
                    .map(|p| (name_of(&p).map(|n| n.0).unwrap_or_default(), type_child(&p)))
                    .collect()
            })
            .unwrap_or_default();
        DefData::Signature {
            params,
            result: if node.kind() == FUNCTION { type_child(node) } else { None },
            terminates: node.children().any(|c| c.kind() == TERMINATES_FLAG || c.kind() == TERMINATES_CLAUSE),
        }
    }

    fn params(&mut self, node: &SyntaxNode, owner: DefId) {
        if let Some(pl) = node.children().find(|c| c.kind() == PARAM_LIST) {
            for p in pl.children().filter(|c| c.kind() == PARAM) {
                let data = DefData::Typed { ty: type_child(&p), init: None, broadcast: false };
                self.push(DefKind::Parameter, &p, Some(owner), None, data);
            }
        }
    }
}

fn transition_data(node: &SyntaxNode) -> TransitionData {
    let mut t = TransitionData::default();
    for c in node.children() {
        match c.kind() {
            TRANSITION_SOURCE => t.source = ref_of(&c),
            TRANSITION_TARGET => t.target = ref_of(&c),
            TRIGGER => {
                let event = c.children().find(|n| n.kind() == COMMUNICATION).and_then(|comm| ref_of(&comm));
                t.trigger = Some((c.text_range(), event));
            }
            EXEC_TRIGGER => t.exec = Some(c.text_range()),
            PROBABILITY => t.probability = Some(c.text_range()),
            CLOCK_RESET => {
                if let Some(r) = ref_of(&c) {
                    t.resets.push(r);
                }
            }
            DEADLINE => t.deadline = Some(c.text_range()),
            CONDITION => {
                t.condition = Some(c.text_range());
                t.is_else = c.children().any(|e| e.kind() == ELSE_CONDITION);
            }
            TRANSITION_ACTION => t.action = Some(c.text_range()),
            _ => {}
        }
    }
    t
}
