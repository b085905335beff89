//! Lowering of a file's syntax into its [`FileModel`], and the queries
//! that read it.

use robosim_syntax::ast::{self, name_text, qualified_path};
use robosim_syntax::{SyntaxKind::*, SyntaxNode, TextRange};
use rustc_hash::FxHashMap;

use super::*;
use crate::cycle::CycleInfo;
use crate::defs::{file_defs, lower_type, DefId, DefKind, Io};
use crate::element::Element;
use crate::index::resolve_item;
use crate::resolve::Target;
use crate::{parse, Db, File, Workspace};

/// The lowering of one file.
pub(super) struct Cx<'a> {
    pub(super) db: &'a dyn Db,
    pub(super) ws: Workspace,
    pub(super) file: File,
    /// What each name in behaviour resolves to, by range.
    refs: FxHashMap<TextRange, Target>,
    /// The type of each expression, by range.
    pub(super) types: &'a FxHashMap<TextRange, crate::types::Ty>,
    /// The machines, operations, controllers and modules of the file, by
    /// range, and what their cycle definitions allow (RoboSim).
    elements: FxHashMap<TextRange, DefId>,
    cycles: FxHashMap<DefId, CycleInfo>,
}

/// The model of `file`: every top-level element, lowered. Put together
/// from the elements' ([`element_model`]): after an edit, only the edited
/// element is lowered again (the others are moved, when the edit moved
/// them).
#[salsa::tracked(returns(ref))]
pub fn file_model(db: &dyn Db, ws: Workspace, file: File) -> FileModel {
    if file.kind(db).is_assertions() {
        return FileModel::default();
    }
    let items = crate::element::file_elements(db, file)
        .iter()
        .flat_map(|(e, _)| element_model(db, ws, *e).iter().cloned())
        .collect();
    let root = parse(db, file).syntax_node();
    finish(db, file, &root, items)
}

/// The model of `file` lowered in one pass over its whole tree: what
/// [`file_model`] puts together from the elements (tests compare the two).
#[doc(hidden)]
pub fn lower_file_model(db: &dyn Db, ws: Workspace, file: File) -> FileModel {
    if file.kind(db).is_assertions() {
        return FileModel::default();
    }
    let structural = &crate::resolve::file_resolution(db, ws, file).refs;
    let behaviour = &crate::body::body_resolution(db, ws, file).refs;
    let defs = file_defs(db, file);
    let cycles = match file.kind(db) {
        crate::FileKind::RoboSim => crate::cycle::cycle_infos(db, ws, file).iter().copied().collect(),
        _ => FxHashMap::default(),
    };
    let types = crate::types::expr_types(db, ws, file);
    let mut cx = Cx::new(db, ws, file, structural.iter().chain(behaviour), types, defs, cycles);
    let root = parse(db, file).syntax_node();
    let mut items = Vec::new();
    for (id, def) in defs.children(None) {
        let Some(node) = root
            .children()
            .find(|n| n.text_range() == def.range && n.kind() == def.syntax)
            .or_else(|| find_node(&root, def.range, def.syntax))
        else {
            continue;
        };
        items.push((id, cx.item(&node)));
    }
    finish(db, file, &root, items)
}

/// The model of `file` with `items`: its package, literals and syntax
/// errors added.
fn finish(db: &dyn Db, file: File, root: &SyntaxNode, items: Vec<(DefId, Item)>) -> FileModel {
    let literals = int_literals(root);
    let syntax_errors = parse(db, file)
        .errors()
        .iter()
        .filter(|e| e.severity == robosim_syntax::Severity::Error)
        .map(|e| (e.range, e.message.clone()))
        .collect();
    let package = crate::element::file_package(db, file).to_vec();
    FileModel { package, items, literals, syntax_errors }
}

/// The model of the top-level element `element` (normally one item; none
/// for an element that declares nothing, as a stray token), lowered from
/// its own tree: positions relative to its start, definition ids the
/// file's. It reads the element's input and what it resolves to (what
/// other elements publish), never their syntax, so that an edit of
/// another element leaves it valid without re-validating underneath (see
/// [`crate::element::Element`]).
#[salsa::tracked(returns(ref))]
pub fn element_items(db: &dyn Db, ws: Workspace, element: Element) -> Vec<(DefId, Item)> {
    let file = element.file(db);
    if file.kind(db).is_assertions() {
        return Vec::new();
    }
    let unit = crate::element::Unit::of_element(db, element);
    let structural = crate::element::element_refs(db, ws, element);
    let behaviour = crate::body::resolve_body(db, ws, &unit).refs;
    let types = crate::types::unit_types(db, ws, &unit, structural, &behaviour);
    let cycles = match file.kind(db) {
        crate::FileKind::RoboSim => crate::element_rules::element_cycles(db, ws, element).1.iter().copied().collect(),
        _ => FxHashMap::default(),
    };
    let mut cx = Cx::new(db, ws, file, structural.iter().chain(&behaviour), &types, unit.defs, cycles);
    let root = &unit.root;
    let mut items = Vec::new();
    for (id, def) in unit.defs.children(None) {
        let node = if root.text_range() == def.range && root.kind() == def.syntax {
            Some(root.clone())
        } else {
            find_node(root, def.range, def.syntax)
        };
        if let Some(node) = node {
            items.push((id, cx.item(&node)));
        }
    }
    items
}

/// The model of the top-level element `element` ([`element_items`]) at
/// its place in the file: what requests about one place read (hover),
/// instead of the whole file's model. Recomputed (moved, not lowered)
/// when an edit before the element moves it.
#[salsa::tracked(returns(ref))]
pub fn element_model(db: &dyn Db, ws: Workspace, element: Element) -> Vec<(DefId, Item)> {
    let mut items = element_items(db, ws, element).clone();
    let at = crate::element::element_start(db, element);
    if at != 0 {
        for (_, item) in &mut items {
            super::shift::item(item, at.into());
        }
    }
    items
}

/// The integer literals under `n`, in order.
fn int_literals(n: &SyntaxNode) -> Vec<i64> {
    n.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| t.kind() == INT_NUMBER)
        .filter_map(|t| t.text().parse().ok())
        .collect()
}

fn find_node(root: &SyntaxNode, range: TextRange, kind: robosim_syntax::SyntaxKind) -> Option<SyntaxNode> {
    let node = match root.covering_element(range) {
        robosim_syntax::SyntaxElement::Node(n) => n,
        robosim_syntax::SyntaxElement::Token(t) => t.parent()?,
    };
    node.ancestors().find(|n| n.kind() == kind && n.text_range() == range)
}

/// What the assertion file `file` says (empty for a model file): the
/// assertions and the instantiation blocks, read once per text.
#[salsa::tracked(returns(ref))]
pub fn assertion_file(db: &dyn Db, file: File) -> crate::assertions::AssertionFile {
    if !file.kind(db).is_assertions() {
        return Default::default();
    }
    crate::assertions::read_assertions(&parse(db, file).syntax_node())
}

/// The model of the top-level element `loc`.
pub fn item(db: &dyn Db, ws: Workspace, loc: ItemLoc) -> Option<&Item> {
    item_of(db, ws, loc.file, loc.def(db)?)
}

/// The model of the top-level definition `id` of `file` (from its
/// element's model alone, [`element_model`]).
pub fn item_of(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> Option<&Item> {
    if file.kind(db).is_assertions() {
        return None;
    }
    let element = crate::element::element_of(db, file, id)?;
    element_model(db, ws, element).iter().find(|(d, _)| *d == id).map(|(_, i)| i)
}

/// The element of kind `kind` that the path `path`, written in `from`,
/// names (the first, when several do).
pub fn resolve(db: &dyn Db, ws: Workspace, from: File, path: &[String], kind: DefKind) -> Option<ItemLoc> {
    if path.is_empty() {
        return None;
    }
    let accept: fn(DefKind) -> bool = match kind {
        DefKind::Interface => |k| k == DefKind::Interface,
        DefKind::Platform => |k| k == DefKind::Platform,
        DefKind::Controller => |k| k == DefKind::Controller,
        DefKind::StateMachine => |k| k == DefKind::StateMachine,
        DefKind::Operation => |k| k == DefKind::Operation,
        DefKind::Enumeration => |k| k == DefKind::Enumeration,
        DefKind::Record => |k| k == DefKind::Record,
        DefKind::PrimitiveType => |k| k == DefKind::PrimitiveType,
        DefKind::Function => |k| k == DefKind::Function,
        _ => |_| false,
    };
    resolve_item(db, ws, from, path, accept).into_iter().next()
}

/// The enumeration `path` names from `from`, and its literals.
pub fn enum_literals<'db>(
    db: &'db dyn Db,
    ws: Workspace,
    from: File,
    path: &[String],
) -> Option<(ItemLoc, &'db [String])> {
    let loc = resolve(db, ws, from, path, DefKind::Enumeration)?;
    match item(db, ws, loc)? {
        Item::Enumeration(_, lits) => Some((loc, lits.as_slice())),
        _ => None,
    }
}

fn name_of(n: &SyntaxNode) -> String {
    n.children().find(|c| c.kind() == NAME).map(|c| name_text(&c)).unwrap_or_default()
}

/// The range of `n`'s name; when it has none, of its first token (its
/// keyword), as the definitions have it.
fn name_range(n: &SyntaxNode) -> TextRange {
    n.children().find(|c| c.kind() == NAME).map(|c| c.text_range()).unwrap_or_else(|| {
        n.children_with_tokens().find(|t| !t.kind().is_trivia()).map(|t| t.text_range()).unwrap_or(n.text_range())
    })
}

fn type_child(n: &SyntaxNode) -> Option<SyntaxNode> {
    n.children().find(|t| ast::is_type_kind(t.kind()))
}

impl<'a> Cx<'a> {
    /// A lowering of (part of) `file` with the references `refs` and the
    /// expression types `types` of its tree, its definitions `defs` and
    /// its cycle facts `cycles`.
    fn new<'r>(
        db: &'a dyn Db,
        ws: Workspace,
        file: File,
        refs: impl Iterator<Item = &'r crate::resolve::ResolvedRef>,
        types: &'a FxHashMap<TextRange, crate::types::Ty>,
        defs: &crate::defs::FileDefs,
        cycles: FxHashMap<DefId, CycleInfo>,
    ) -> Cx<'a> {
        let refs = refs.filter_map(|r| Some((r.range, r.target?))).collect();
        let elements = defs
            .iter()
            .filter(|(_, d)| {
                matches!(d.kind, DefKind::StateMachine | DefKind::Operation | DefKind::Controller | DefKind::Module)
            })
            .map(|(id, d)| (d.range, id))
            .collect();
        Cx { db, ws, file, refs, types, elements, cycles }
    }

    /// What the name at `n` (its node, or its first name child) resolves to.
    pub(super) fn target_at(&self, n: &SyntaxNode) -> Option<Target> {
        self.refs.get(&n.text_range()).copied().or_else(|| {
            n.children()
                .find(|c| matches!(c.kind(), NAME_REF | QUALIFIED_NAME))
                .and_then(|c| self.refs.get(&c.text_range()).copied())
        })
    }

    fn item(&mut self, n: &SyntaxNode) -> Item {
        match n.kind() {
            STATE_MACHINE => Item::Machine(self.behaviour(n)),
            OPERATION_DEF => Item::Operation(self.behaviour(n)),
            CONTROLLER => Item::Controller(self.controller(n)),
            MODULE => Item::Module(self.module(n)),
            ROBOTIC_PLATFORM => Item::Platform(self.platform(n)),
            INTERFACE => Item::Interface(self.platform(n)),
            ENUM_DECL => Item::Enumeration(
                name_of(n),
                n.children().filter(|c| c.kind() == ENUM_LITERAL).map(|l| name_of(&l)).collect(),
            ),
            RECORD_DECL => Item::Record(
                name_of(n),
                n.children()
                    .filter(|c| c.kind() == FIELD)
                    .map(|f| Field { name: name_of(&f), ty: self.ty(type_child(&f)), range: f.text_range() })
                    .collect(),
            ),
            PRIMITIVE_TYPE_DECL => Item::PrimitiveType(name_of(n)),
            FUNCTION => {
                let mut conditions = |k| {
                    n.descendants()
                        .filter(|c| c.kind() == k)
                        .filter_map(|c| c.children().find(|e| ast::is_expr_kind(e.kind())))
                        .map(|e| self.expr(&e))
                        .collect::<Vec<_>>()
                };
                let (preconditions, postconditions) = (conditions(PRECONDITION), conditions(POSTCONDITION));
                Item::Function(Function {
                    name: name_of(n),
                    range: n.text_range(),
                    params: self.params(n),
                    result: self.ty(type_child(n)),
                    preconditions,
                    postconditions,
                })
            }
            _ => Item::Other,
        }
    }

    fn ty(&self, t: Option<SyntaxNode>) -> Option<TyRef> {
        let t = t?;
        let written = lower_type(&t);
        let ty = crate::types::lower(self.db, self.ws, self.file, &written);
        Some(TyRef { ty, written, text: t.text().to_string(), range: t.text_range() })
    }

    fn params(&self, n: &SyntaxNode) -> Vec<Param> {
        let Some(pl) = n.children().find(|p| p.kind() == PARAM_LIST) else { return Vec::new() };
        pl.children()
            .filter(|p| p.kind() == PARAM)
            .map(|p| Param { name: name_of(&p), ty: self.ty(type_child(&p)), range: p.text_range() })
            .collect()
    }

    /// The declarations and interface clauses of `n`.
    fn decls(&mut self, n: &SyntaxNode) -> Decls {
        let mut out = Decls::default();
        for c in n.children() {
            let range = c.text_range();
            let decl = match c.kind() {
                VARIABLE_LIST => Decl::Vars {
                    is_const: c.children_with_tokens().any(|t| t.kind() == CONST_KW),
                    vars: c
                        .children()
                        .filter(|v| v.kind() == VARIABLE)
                        .map(|v| VarDecl {
                            name: name_of(&v),
                            ty: self.ty(type_child(&v)),
                            init: v.children().find(|e| ast::is_expr_kind(e.kind())).map(|e| self.expr(&e)),
                            range: v.text_range(),
                        })
                        .collect(),
                    range,
                },
                CLOCK => Decl::Clock { name: name_of(&c), range },
                EVENT => Decl::Event {
                    name: name_of(&c),
                    ty: self.ty(type_child(&c)),
                    broadcast: c.children_with_tokens().any(|t| t.kind() == BROADCAST_KW),
                    range,
                },
                OPERATION_SIG => Decl::OperationSig { name: name_of(&c), params: self.params(&c), range },
                OPERATION_DEF | OPERATION_REF | FUNCTION => Decl::Nested {
                    kind: match c.kind() {
                        OPERATION_DEF => NestedKind::OperationDef,
                        OPERATION_REF => NestedKind::OperationRef,
                        _ => NestedKind::Function,
                    },
                    name: name_of(&c),
                    range,
                },
                INTERFACE_USE => {
                    let kind = match c.children_with_tokens().find(|t| !t.kind().is_trivia()).map(|t| t.kind()) {
                        Some(PROVIDES_KW) => UseKind::Provides,
                        Some(REQUIRES_KW) => UseKind::Requires,
                        _ => UseKind::Uses,
                    };
                    let path = qualified_path(&c);
                    let target = resolve(self.db, self.ws, self.file, &path, DefKind::Interface);
                    out.uses.push(InterfaceUse { kind, path, target, range });
                    continue;
                }
                _ => continue,
            };
            out.decls.push(decl);
        }
        out
    }

    /// A state machine or an operation definition.
    fn behaviour(&mut self, n: &SyntaxNode) -> Behaviour {
        let contexts = n
            .children()
            .filter_map(|c| match c.kind() {
                INPUT_CONTEXT => Some((Io::Input, self.decls(&c))),
                OUTPUT_CONTEXT => Some((Io::Output, self.decls(&c))),
                _ => None,
            })
            .collect();
        let literals = int_literals(n);
        Behaviour {
            name: name_of(n),
            name_range: name_range(n),
            range: n.text_range(),
            params: self.params(n),
            decls: self.decls(n),
            contexts,
            region: self.region(n),
            literals,
            def: self.def_of(n),
            cycle: self.cycle_of(n),
        }
    }

    fn region(&mut self, n: &SyntaxNode) -> Region {
        let mut region = Region::default();
        for c in n.children().filter(|c| c.kind() != TRANSITION) {
            let kind = match c.kind() {
                STATE => NodeKind::State,
                JUNCTION => NodeKind::Junction,
                INITIAL => NodeKind::Initial,
                FINAL => NodeKind::Final,
                PROBABILISTIC_JUNCTION => NodeKind::Probabilistic,
                _ => continue,
            };
            let action = |cx: &mut Self, k| c.children().find(|a| a.kind() == k).map(|a| cx.action(&a));
            let actions = c
                .children()
                .filter_map(|a| {
                    let kind = match a.kind() {
                        ENTRY_ACTION => ActionKind::Entry,
                        DURING_ACTION => ActionKind::During,
                        EXIT_ACTION => ActionKind::Exit,
                        _ => return None,
                    };
                    Some((kind, a.text_range()))
                })
                .collect();
            region.nodes.push(Node {
                kind,
                name: name_of(&c),
                name_range: name_range(&c),
                range: c.text_range(),
                actions,
                entry: action(self, ENTRY_ACTION),
                during: action(self, DURING_ACTION),
                exit: action(self, EXIT_ACTION),
                region: if kind == NodeKind::State { self.region(&c) } else { Region::default() },
            });
        }
        // Transitions name nodes of their own region.
        for t in n.children().filter(|c| c.kind() == TRANSITION) {
            let mut t = self.transition(&t);
            let index = |name: &Option<String>| region.nodes.iter().position(|x| Some(&x.name) == name.as_ref());
            (t.source_node, t.target_node) = (index(&t.source), index(&t.target));
            region.transitions.push(t);
        }
        region
    }

    fn transition(&mut self, t: &SyntaxNode) -> Transition {
        let end = |k| {
            t.children()
                .find(|c| c.kind() == k)
                .and_then(|c| c.children().find(|n| n.kind() == NAME_REF))
                .map(|n| name_text(&n))
        };
        let child = |k| t.children().find(|c| c.kind() == k);
        let trigger =
            child(TRIGGER).and_then(|c| c.children().find(|n| n.kind() == COMMUNICATION)).map(|c| self.comm(&c));
        let resets = t
            .children()
            .filter(|c| c.kind() == CLOCK_RESET)
            .map(|c| {
                let n = c.children().find(|n| n.kind() == NAME_REF).map(|n| name_text(&n)).unwrap_or_default();
                (n, c.text_range())
            })
            .collect();
        let condition = child(CONDITION).map(|c| Condition {
            is_else: c.children().any(|n| n.kind() == ELSE_CONDITION),
            expr: c.children().find(|e| ast::is_expr_kind(e.kind())).map(|e| self.expr(&e)),
            range: c.text_range(),
        });
        let deadline = child(DEADLINE)
            .map(|c| (c.text_range(), c.children().find(|e| ast::is_expr_kind(e.kind())).map(|e| self.expr(&e))));
        Transition {
            name: name_of(t),
            name_range: name_range(t),
            range: t.text_range(),
            source: end(TRANSITION_SOURCE),
            target: end(TRANSITION_TARGET),
            source_node: None,
            target_node: None,
            trigger,
            trigger_range: child(TRIGGER).map(|c| c.text_range()),
            exec: child(EXEC_TRIGGER).is_some(),
            exec_range: child(EXEC_TRIGGER).map(|c| c.text_range()),
            probability: child(PROBABILITY).map(|p| p.text_range()),
            resets,
            condition,
            deadline,
            action: child(TRANSITION_ACTION).map(|a| self.action(&a)),
        }
    }

    fn reference<T>(&self, c: &SyntaxNode, kind: DefKind) -> Instance<T> {
        let path = qualified_path(c);
        let target = resolve(self.db, self.ws, self.file, &path, kind);
        Instance { name: name_of(c), range: c.text_range(), def: Definition::Ref { path, target } }
    }

    /// The connections of `n`, their ends found by `end`.
    fn connections(&self, n: &SyntaxNode, end: impl Fn(&str) -> End) -> Vec<Connection> {
        n.children()
            .filter(|c| c.kind() == CONNECTION)
            .map(|c| {
                let refs: Vec<String> = c.children().filter(|n| n.kind() == NAME_REF).map(|n| name_text(&n)).collect();
                let get = |i: usize| refs.get(i).cloned().unwrap_or_default();
                Connection {
                    from: get(0),
                    efrom: get(1),
                    to: get(2),
                    eto: get(3),
                    is_async: c.children().any(|n| n.kind() == ASYNC_FLAG),
                    is_mult: c.children().any(|n| n.kind() == MULT_FLAG),
                    from_end: end(&get(0)),
                    to_end: end(&get(2)),
                    range: c.text_range(),
                }
            })
            .collect()
    }

    fn controller(&mut self, n: &SyntaxNode) -> Controller {
        let (mut machines, mut operations) = (Vec::new(), Vec::new());
        for c in n.children() {
            match c.kind() {
                STATE_MACHINE_REF => machines.push(self.reference(&c, DefKind::StateMachine)),
                OPERATION_REF => operations.push(self.reference(&c, DefKind::Operation)),
                STATE_MACHINE | OPERATION_DEF => {
                    let inst = Instance {
                        name: name_of(&c),
                        range: c.text_range(),
                        def: Definition::Inline(Box::new(self.behaviour(&c))),
                    };
                    if c.kind() == STATE_MACHINE {
                        machines.push(inst)
                    } else {
                        operations.push(inst)
                    }
                }
                _ => {}
            }
        }
        // Its operations are described as instances, not declarations.
        let mut decls = self.decls(n);
        decls.decls.retain(|d| !matches!(d, Decl::Nested { .. }));
        let name = name_of(n);
        Controller {
            name: name.clone(),
            name_range: name_range(n),
            range: n.text_range(),
            decls,
            operations,
            connections: self.connections(n, |e| {
                if e == name {
                    End::This
                } else {
                    machines.iter().position(|m: &Instance<Behaviour>| m.name == e).map_or(End::Unknown, End::Machine)
                }
            }),
            machines,
            def: self.def_of(n),
            cycle: self.cycle_of(n),
        }
    }

    fn def_of(&self, n: &SyntaxNode) -> Option<DefId> {
        self.elements.get(&n.text_range()).copied()
    }

    fn cycle_of(&self, n: &SyntaxNode) -> Option<CycleInfo> {
        self.cycles.get(&self.def_of(n)?).copied()
    }

    fn platform(&mut self, n: &SyntaxNode) -> Platform {
        Platform { name: name_of(n), name_range: name_range(n), range: n.text_range(), decls: self.decls(n) }
    }

    fn module(&mut self, n: &SyntaxNode) -> Module {
        let (mut platforms, mut controllers, mut machines) = (Vec::new(), Vec::new(), Vec::new());
        for c in n.children() {
            match c.kind() {
                ROBOTIC_PLATFORM => platforms.push(Instance {
                    name: name_of(&c),
                    range: c.text_range(),
                    def: Definition::Inline(Box::new(self.platform(&c))),
                }),
                PLATFORM_REF => platforms.push(self.reference(&c, DefKind::Platform)),
                CONTROLLER_REF => controllers.push(self.reference(&c, DefKind::Controller)),
                CONTROLLER => controllers.push(Instance {
                    name: name_of(&c),
                    range: c.text_range(),
                    def: Definition::Inline(Box::new(self.controller(&c))),
                }),
                STATE_MACHINE_REF => machines.push(self.reference(&c, DefKind::StateMachine)),
                STATE_MACHINE => machines.push(Instance {
                    name: name_of(&c),
                    range: c.text_range(),
                    def: Definition::Inline(Box::new(self.behaviour(&c))),
                }),
                _ => {}
            }
        }
        let name = name_of(n);
        let connections = self.connections(n, |e| {
            if let Some(i) = platforms.iter().position(|p| p.name == e) {
                End::Platform(i)
            } else if let Some(i) = controllers.iter().position(|c| c.name == e) {
                End::Controller(i)
            } else if e == name {
                End::This
            } else {
                End::Unknown
            }
        });
        Module {
            name,
            name_range: name_range(n),
            range: n.text_range(),
            platforms,
            controllers,
            machines,
            connections,
            def: self.def_of(n),
            cycle: self.cycle_of(n),
        }
    }
}
