//! Name resolution of the declaration-level references of a file: types,
//! interfaces, `rref/cref/sref/opref` targets, imports, transition ends,
//! connection ends and their events, trigger events and clocks. The result
//! maps each reference to its target, for diagnostics (LNK-01 and the more
//! precise rules) and for navigation.

use robosim_syntax::{SyntaxKind::*, SyntaxNode, TextRange};

use crate::defs::{file_defs, Def, DefData, DefId, DefKind, FileDefs, Io, UseKind};
mod assertions;
mod prob;

use crate::element::Unit;
use crate::index::{file_summary, import_matches, resolve_in_scope, resolve_item, ItemLoc};
use crate::{parse, Db, File, Workspace};

/// Where a name leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    /// A definition in a file (the same file or another).
    Def(File, DefId),
    /// A top-level item found through the index.
    Item(ItemLoc),
    /// A member of an item in another file, by index in its summary.
    Member(ItemLoc, u32),
}

/// What kind of reference it is (for messages and navigation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum RefKind {
    Type,
    Interface,
    Platform,
    Controller,
    Machine,
    Operation,
    TransitionSource,
    TransitionTarget,
    ConnectionNode,
    ConnectionEvent,
    TriggerEvent,
    Clock,
}

impl RefKind {
    fn describe(self) -> &'static str {
        match self {
            RefKind::Type => "type",
            RefKind::Interface => "interface",
            RefKind::Platform => "robotic platform",
            RefKind::Controller => "controller",
            RefKind::Machine => "state machine",
            RefKind::Operation => "operation",
            RefKind::TransitionSource | RefKind::TransitionTarget => "node",
            RefKind::ConnectionNode => "connection end",
            RefKind::ConnectionEvent | RefKind::TriggerEvent => "event",
            RefKind::Clock => "clock",
        }
    }
}

/// One reference of the file and what it resolved to.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ResolvedRef {
    /// The reference's range.
    pub range: TextRange,
    /// The name as written (`a::b` joined).
    pub text: String,
    /// What it should denote.
    pub kind: RefKind,
    /// The target, when found.
    pub target: Option<Target>,
}

/// A problem found while resolving, before it becomes a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ResolveProblem {
    /// Rule code (`LNK-01`, `RC:IJ1`, `RC:FS1`, `RC-PKG-02`, …).
    pub code: &'static str,
    /// Where.
    pub range: TextRange,
    /// What.
    pub message: String,
}

/// The references of one file.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct FileResolution {
    /// Every reference, in source order.
    pub refs: Vec<ResolvedRef>,
    /// Problems (unresolved names and the like).
    pub problems: Vec<ResolveProblem>,
}

/// A member visible in a context: declared there or brought in by an
/// interface.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Member {
    /// Name.
    pub name: String,
    /// Kind (event, variable, constant, clock, operation signature, …).
    pub kind: DefKind,
    /// The I/O context (own, or of the use that brought it).
    pub io: Option<Io>,
    /// The interface use that brought it, if any.
    pub via: Option<UseKind>,
    /// The declared type (without positions).
    pub ty: Option<crate::defs::TypeRef>,
    /// Where it is declared.
    pub target: Target,
    /// Whether `_broadcast`.
    pub broadcast: bool,
    /// Parameter names, for operation signatures.
    pub params: Vec<String>,
}

impl Member {
    /// The signature key of an operation member ([`op_key`]).
    pub fn op_key(&self) -> String {
        op_key(&self.name, &self.params)
    }
}

/// A context whose members can be listed: a definition of a file, or an
/// item of the index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Ctx {
    /// A definition (any nesting) of a file.
    Local(File, DefId),
    /// A top-level item.
    Item(ItemLoc),
}

fn accept_interface(k: DefKind) -> bool {
    k == DefKind::Interface
}

/// Members of `ctx`: its own events, variables, constants, clocks and
/// operation signatures, plus those of the interfaces it uses, provides or
/// requires (in I/O contexts too). Memoised per file.
pub fn ctx_members(db: &dyn Db, ws: Workspace, ctx: Ctx) -> std::borrow::Cow<'_, [Member]> {
    // Items of other files are described by their position-free summaries,
    // so that editing their bodies does not invalidate this file's results.
    // Borrowed when memoised: checks ask for the same lists many times.
    if let Ctx::Local(file, def) = ctx {
        // From the element that declares it: its members do not change
        // when text before it moves, the file's do.
        if let Some(e) = crate::element::element_of(db, file, def) {
            if let Some(m) = crate::element::element_members(db, ws, e).get(&def) {
                return std::borrow::Cow::Borrowed(m);
            }
        }
        if let Some(m) = file_members(db, ws, file).get(&def) {
            return std::borrow::Cow::Borrowed(m);
        }
    }
    if let Ctx::Item(loc) = ctx {
        return std::borrow::Cow::Borrowed(item_members(db, ws, loc.file, loc.index));
    }
    std::borrow::Cow::Owned(compute_members(db, ws, ctx))
}

/// The members of the item `index` of `file`'s summary: position-free,
/// and asked for by every reference to the item.
#[salsa::tracked(returns(ref))]
fn item_members(db: &dyn Db, ws: Workspace, file: File, index: u32) -> Vec<Member> {
    compute_members(db, ws, Ctx::Item(ItemLoc { file, index }))
}

/// The members of every context definition of a file, computed once per
/// revision (checks ask for the same contexts many times, hence the fast
/// hash).
#[salsa::tracked(returns(ref))]
pub fn file_members(db: &dyn Db, ws: Workspace, file: File) -> rustc_hash::FxHashMap<DefId, Vec<Member>> {
    file_defs(db, file)
        .iter()
        .filter(|(_, d)| is_context_kind(d.kind))
        .map(|(id, _)| (id, compute_members(db, ws, Ctx::Local(file, id))))
        .collect()
}

/// The kinds of definition [`file_members`] lists the members of.
pub(crate) fn is_context_kind(k: DefKind) -> bool {
    matches!(
        k,
        DefKind::Interface
            | DefKind::Platform
            | DefKind::Controller
            | DefKind::StateMachine
            | DefKind::Operation
            | DefKind::Function
            | DefKind::Module
    )
}

/// The members of `ctx`, computed afresh ([`ctx_members`] reads them from
/// the file's memoised members when it can).
pub(crate) fn compute_members(db: &dyn Db, ws: Workspace, ctx: Ctx) -> Vec<Member> {
    match ctx {
        Ctx::Local(file, id) => members_in(db, ws, file, file_defs(db, file), id),
        Ctx::Item(_) => members_with(db, ws, ctx, None),
    }
}

/// The members of the definition `id` of `file`, read from `defs` (the
/// file's, or those of the element that holds `id`).
pub(crate) fn members_in(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs, id: DefId) -> Vec<Member> {
    members_with(db, ws, Ctx::Local(file, id), Some(defs))
}

fn members_with(db: &dyn Db, ws: Workspace, ctx: Ctx, local: Option<&FileDefs>) -> Vec<Member> {
    let mut out = Vec::new();
    let (file, uses): (File, Vec<UseSummary>) = match ctx {
        Ctx::Local(file, id) => {
            let defs = match local {
                Some(d) => d,
                None => file_defs(db, file),
            };
            for (mid, m) in defs.children(Some(id)) {
                if is_member_kind(m.kind) && !m.name.is_empty() {
                    out.push(Member {
                        name: m.name.clone(),
                        kind: m.kind,
                        io: m.io,
                        via: None,
                        ty: typed(m),
                        target: Target::Def(file, mid),
                        broadcast: matches!(m.data, DefData::Typed { broadcast: true, .. }),
                        params: match &m.data {
                            DefData::Signature { params, .. } => params.iter().map(|(n, _)| n.clone()).collect(),
                            _ => Vec::new(),
                        },
                    });
                }
            }
            (file, defs.uses_of(id).map(|u| (u.kind, u.path.clone(), u.io)).collect())
        }
        Ctx::Item(loc) => {
            let s = loc.summary(db);
            push_summary_members(loc, &s.members, |m| m.io, None, &mut out);
            (loc.file, s.uses.clone())
        }
    };
    for (kind, path, io) in uses {
        for loc in resolve_item(db, ws, file, &path, accept_interface).into_iter().take(1) {
            push_summary_members(loc, &loc.summary(db).members, |_| io, Some(kind), &mut out);
        }
    }
    out
}

/// A use as written: keyword, path, I/O context.
type UseSummary = (UseKind, Vec<String>, Option<Io>);

/// Pushes the members of the summarised item at `loc`; `io` gives each
/// one's I/O context (its own, or that of the use that brought it).
fn push_summary_members(
    loc: ItemLoc,
    members: &[crate::index::MemberSummary],
    io: impl Fn(&crate::index::MemberSummary) -> Option<Io>,
    via: Option<UseKind>,
    out: &mut Vec<Member>,
) {
    for (i, m) in members.iter().enumerate() {
        if is_member_kind(m.kind) {
            out.push(Member {
                name: m.name.clone(),
                kind: m.kind,
                io: io(m),
                via,
                ty: m.ty.clone(),
                target: Target::Member(loc, i as u32),
                broadcast: m.broadcast,
                params: m.params.iter().map(|(n, _)| n.clone()).collect(),
            });
        }
    }
}

fn is_member_kind(k: DefKind) -> bool {
    matches!(k, DefKind::Event | DefKind::Variable | DefKind::Constant | DefKind::Clock | DefKind::OperationSig)
}

fn typed(d: &Def) -> Option<crate::defs::TypeRef> {
    match &d.data {
        DefData::Typed { ty, .. } => ty.clone(),
        _ => None,
    }
}

/// The context a (connection/reference) node denotes: an inline definition,
/// or the definition a `cref/sref/rref` names.
pub fn node_ctx(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> Option<Ctx> {
    // From the element's definitions, which an edit elsewhere leaves alone.
    node_ctx_in(db, ws, file, crate::element_rules::defs_at(db, file, id).0, id)
}

/// [`node_ctx`], the definition read from `defs` (which hold `id`).
pub(crate) fn node_ctx_in(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs, id: DefId) -> Option<Ctx> {
    let d = defs.def(id);
    match (&d.kind, &d.data) {
        (
            DefKind::PlatformRef | DefKind::ControllerRef | DefKind::MachineRef | DefKind::OperationRef,
            DefData::Reference { path, .. },
        ) => {
            let accept = ref_accept(d.kind);
            resolve_item(db, ws, file, path, accept).first().map(|l| Ctx::Item(*l))
        }
        _ => Some(Ctx::Local(file, id)),
    }
}

fn ref_accept(k: DefKind) -> fn(DefKind) -> bool {
    match k {
        DefKind::PlatformRef => |k| k == DefKind::Platform,
        DefKind::ControllerRef => |k| k == DefKind::Controller,
        DefKind::MachineRef => |k| k == DefKind::StateMachine,
        _ => |k| k == DefKind::Operation,
    }
}

/// The definitions whose members (variables, constants, events, operations,
/// parameters) a name in behaviour sees: the nearest one of these kinds
/// around it, found with [`enclosing`].
pub const MEMBER_CONTEXTS: &[DefKind] = &[
    DefKind::Operation,
    DefKind::StateMachine,
    DefKind::Controller,
    DefKind::Function,
    DefKind::Interface,
    DefKind::Platform,
    DefKind::Module,
];

/// The nearest enclosing definition of one of the given kinds.
pub fn enclosing(defs: &FileDefs, mut id: DefId, kinds: &[DefKind]) -> Option<DefId> {
    loop {
        let d = defs.def(id);
        if kinds.contains(&d.kind) {
            return Some(id);
        }
        id = d.parent?;
    }
}

/// Resolves every declaration-level reference of `file`.
#[salsa::tracked(returns(ref))]
pub fn file_resolution(db: &dyn Db, ws: Workspace, file: File) -> FileResolution {
    let unit = Unit::of_file(db, file);
    let mut r = Resolver::new(db, ws, &unit);
    r.imports();
    r.resolve();
    if file.kind(db).is_assertions() {
        r.probabilistic(&unit.root);
        r.assertion_names(&unit.root);
    }
    r.out.refs.sort_by_key(|x| x.range.start());
    r.out
}

/// The problems of the imports of `file` (the part of [`file_resolution`]
/// that belongs to no element).
pub(crate) fn import_problems(db: &dyn Db, ws: Workspace, file: File) -> Vec<ResolveProblem> {
    // The package and imports only: not the file's definitions, which
    // every keystroke changes.
    let defs = crate::element::file_header(db, file);
    let unit = Unit {
        file,
        defs,
        root: parse(db, file).syntax_node(),
        // The imports need no node of the tree.
        nodes: &crate::walk::NodeTable::default(),
        element: None,
    };
    let mut r = Resolver {
        db,
        ws,
        file,
        unit: &unit,
        defs,
        named_types: Vec::new(),
        clocks: Vec::new(),
        out: FileResolution::default(),
    };
    r.imports();
    r.out.problems
}

/// [`file_resolution`] of one element (no imports, no assertion names).
pub(crate) fn resolve_unit(db: &dyn Db, ws: Workspace, unit: &Unit<'_>) -> FileResolution {
    let mut r = Resolver::new(db, ws, unit);
    r.resolve();
    r.out.refs.sort_by_key(|x| x.range.start());
    r.out
}

struct Resolver<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    unit: &'a Unit<'a>,
    defs: &'a FileDefs,
    /// The `NAMED_TYPE` nodes of the file, in order.
    named_types: Vec<SyntaxNode>,
    /// The clock resets and `since` expressions of the file, in order.
    clocks: Vec<SyntaxNode>,
    out: FileResolution,
}

impl<'a> Resolver<'a> {
    fn new(db: &'a dyn Db, ws: Workspace, unit: &'a Unit<'a>) -> Resolver<'a> {
        // One walk finds the nodes both `types` and `clocks` need.
        let (named_types, clocks) = unit
            .nodes
            .nodes(&unit.root, &[NAMED_TYPE, CLOCK_RESET, CLOCK_RESET_STMT, SINCE_EXPR], false)
            .into_iter()
            .partition(|n| n.kind() == NAMED_TYPE);
        Resolver { db, ws, file: unit.file, unit, defs: unit.defs, named_types, clocks, out: FileResolution::default() }
    }

    /// Everything but the imports.
    fn resolve(&mut self) {
        self.uses();
        self.types();
        self.definitions();
    }

    fn push(&mut self, range: TextRange, text: String, kind: RefKind, target: Option<Target>) {
        self.out.refs.push(ResolvedRef { range, text, kind, target });
    }

    fn unresolved(&mut self, range: TextRange, kind: RefKind, text: &str) {
        self.problem("LNK-01", range, format!("cannot resolve {} `{text}`", kind.describe()));
    }

    fn problem(&mut self, code: &'static str, range: TextRange, message: String) {
        self.out.problems.push(ResolveProblem { code, range, message });
    }

    fn item(
        &mut self,
        path: &[String],
        range: TextRange,
        kind: RefKind,
        accept: fn(DefKind) -> bool,
    ) -> Option<ItemLoc> {
        let text = path.join("::");
        let found = resolve_item(self.db, self.ws, self.file, path, accept).first().copied();
        self.push(range, text.clone(), kind, found.map(Target::Item));
        if let Some(l) = found {
            if resolve_in_scope(self.db, self.ws, self.file, path, accept).is_empty() {
                let pkg = crate::index::file_summary(self.db, l.file).package.join("::");
                let full = if pkg.is_empty() { text.clone() } else { format!("{pkg}::{text}") };
                self.problem(
                    "LNK-02",
                    range,
                    format!("`{text}` is not imported here; taken to be `{full}`, the only {} of that name (every declaration of it is the same): add `import {full}`", kind.describe()),
                );
            }
        }
        if found.is_none() {
            // Say what the name is when it exists with another kind.
            let any = resolve_item(self.db, self.ws, self.file, path, |_| true);
            match any.first() {
                Some(l) => {
                    let other = l.summary(self.db).kind.describe();
                    self.problem("LNK-01", range, format!("`{text}` is a {other}, not a {}", kind.describe()));
                }
                None => match self
                    .defs
                    .imports
                    .iter()
                    .find(|i| !import_matches(self.db, self.ws, self.file, &i.path, i.wildcard))
                {
                    // A package the workspace does not hold (a physical
                    // model's) may declare it: it cannot be checked.
                    Some(i) => self.problem(
                        "LNK-03",
                        range,
                        format!(
                            "{} `{text}` is not declared in the workspace: it may come from `{}`, which no file here declares (a physical model?); load that package to check it",
                            kind.describe(),
                            i.path.join("::")
                        ),
                    ),
                    None => self.unresolved(range, kind, &text),
                },
            }
        }
        found
    }

    fn imports(&mut self) {
        for imp in &self.defs.imports {
            if !import_matches(self.db, self.ws, self.file, &imp.path, imp.wildcard) {
                let text = imp.path.join("::");
                let written = if imp.wildcard { format!("{text}::*") } else { text.clone() };
                let message = match crate::index::project_declaring(self.db, self.ws, &imp.path) {
                    Some(root) => format!(
                        "`import {written}` matches no package or element of this file's project: `{text}` is in the project at `{root}`, and RoboTool resolves names within a project"
                    ),
                    None => format!("`import {written}` matches no package or element of the workspace"),
                };
                self.problem("RC-PKG-02", imp.range, message);
            }
        }
    }

    fn uses(&mut self) {
        for u in &self.defs.uses {
            self.item(&u.path, u.range, RefKind::Interface, accept_interface);
        }
    }

    fn types(&mut self) {
        for n in std::mem::take(&mut self.named_types) {
            let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { continue };
            let path = segments(&q);
            if path.is_empty() {
                continue;
            }
            self.item(&path, q.text_range(), RefKind::Type, DefKind::is_type);
        }
    }

    fn definitions(&mut self) {
        for (id, d) in self.defs.iter() {
            match (&d.kind, &d.data) {
                (DefKind::PlatformRef, DefData::Reference { path, range }) => {
                    self.item(path, *range, RefKind::Platform, |k| k == DefKind::Platform);
                }
                (DefKind::ControllerRef, DefData::Reference { path, range }) => {
                    self.item(path, *range, RefKind::Controller, |k| k == DefKind::Controller);
                }
                (DefKind::MachineRef, DefData::Reference { path, range }) => {
                    self.item(path, *range, RefKind::Machine, |k| k == DefKind::StateMachine);
                }
                (DefKind::OperationRef, DefData::Reference { path, range }) => {
                    self.item(path, *range, RefKind::Operation, |k| k == DefKind::Operation);
                }
                (DefKind::Transition, DefData::Transition(t)) => self.transition(id, d, t),
                (DefKind::Connection, DefData::Connection(c)) => self.connection(id, d, c),
                _ => {}
            }
        }
        self.clocks();
    }

    fn transition(&mut self, _id: DefId, d: &Def, t: &crate::defs::TransitionData) {
        let Some(container) = d.parent else { return };
        let rs = self.file.kind(self.db) == robosim_syntax::FileKind::RoboSim;
        for (end, kind) in [(&t.source, RefKind::TransitionSource), (&t.target, RefKind::TransitionTarget)] {
            let Some((name, range)) = end else { continue };
            let local = self.defs.children(Some(container)).find(|(_, n)| n.kind.is_node() && &n.name == name);
            match local {
                Some((nid, n)) => {
                    self.push(*range, name.clone(), kind, Some(Target::Def(self.file, nid)));
                    // RoboChart's scopes exclude these; say why precisely.
                    if kind == RefKind::TransitionSource && n.kind == DefKind::Final {
                        self.problem("RC:FS1", *range, format!("no transition may leave the final state `{name}`"));
                    }
                    if kind == RefKind::TransitionTarget && n.kind == DefKind::Initial {
                        self.problem(
                            "RC:IJ1",
                            *range,
                            format!("no transition may enter the initial junction `{name}`"),
                        );
                    }
                    let _ = rs;
                }
                None => {
                    self.push(*range, name.clone(), kind, None);
                    // Is it a node elsewhere in the machine (an inter-level transition)?
                    let elsewhere = self.defs.iter().any(|(_, n)| {
                        n.kind.is_node()
                            && &n.name == name
                            && n.parent.is_some()
                            && enclosing_machine(self.defs, n.parent.unwrap())
                                == enclosing_machine(self.defs, container)
                    });
                    if elsewhere {
                        self.problem(
                            "LNK-01",
                            *range,
                            format!(
                                "`{name}` is not a node of the {} that declares this transition: transitions cannot cross levels (RC:T1)",
                                self.defs.def(container).kind.describe()
                            ),
                        );
                    } else {
                        self.unresolved(*range, kind, name);
                    }
                }
            }
        }
        // Trigger events: events of the enclosing machine, operation or controller.
        if let Some((_, Some((ev, range)))) = &t.trigger {
            let owner =
                enclosing(self.defs, container, &[DefKind::StateMachine, DefKind::Operation, DefKind::Controller]);
            if let Some(owner) = owner {
                let members = self.unit.members(self.db, self.ws, owner);
                let found = members.iter().find(|m| m.kind == DefKind::Event && &m.name == ev).map(|m| m.target);
                self.push(*range, ev.clone(), RefKind::TriggerEvent, found);
                if found.is_none() {
                    self.unresolved(*range, RefKind::TriggerEvent, ev);
                }
            }
        }
    }

    fn connection(&mut self, id: DefId, d: &Def, c: &crate::defs::ConnectionData) {
        let Some(owner) = d.parent else { return };
        let _ = id;
        let owner_def = self.defs.def(owner);
        for (node, event) in [(&c.from, &c.efrom), (&c.to, &c.eto)] {
            let Some((name, range)) = node else { continue };
            // Nodes: the owner's node members (inline or referenced); a
            // controller's own name stands for the controller itself.
            let found = if owner_def.kind == DefKind::Controller && &owner_def.name == name {
                Some(owner)
            } else {
                self.defs
                    .children(Some(owner))
                    .find(|(_, n)| {
                        &n.name == name
                            && matches!(
                                n.kind,
                                DefKind::Controller
                                    | DefKind::ControllerRef
                                    | DefKind::StateMachine
                                    | DefKind::MachineRef
                                    | DefKind::Platform
                                    | DefKind::PlatformRef
                            )
                    })
                    .map(|(nid, _)| nid)
            };
            self.push(*range, name.clone(), RefKind::ConnectionNode, found.map(|f| Target::Def(self.file, f)));
            let Some(nid) = found else {
                let (what, code) =
                    if owner_def.kind == DefKind::Module { ("module", "RC:Cn1") } else { ("controller", "RC:Cn3") };
                // A node declared elsewhere is a connection that leaves its
                // container; a name declared nowhere does not resolve.
                let elsewhere = !resolve_item(self.db, self.ws, self.file, std::slice::from_ref(name), |k| {
                    matches!(k, DefKind::Controller | DefKind::StateMachine | DefKind::Platform)
                })
                .is_empty();
                if elsewhere {
                    let at = event.as_ref().map(|e| e.1).unwrap_or(*range);
                    self.problem(
                        code,
                        at,
                        format!("`{name}` is not part of this {what}: a {what}'s connections join only its own nodes"),
                    );
                } else {
                    self.problem(
                        "LNK-01",
                        *range,
                        format!("cannot resolve `{name}`: it is not a controller, machine or platform of this {what}"),
                    );
                }
                continue;
            };
            let Some((ev, erange)) = event else { continue };
            let ctx = if nid == owner {
                Some(Ctx::Local(self.file, owner))
            } else {
                self.unit.node_ctx(self.db, self.ws, nid)
            };
            let Some(ctx) = ctx else { continue };
            let members = match ctx {
                Ctx::Local(f, id) if f == self.file && self.defs.holds(id) => self.unit.members(self.db, self.ws, id),
                _ => ctx_members(self.db, self.ws, ctx),
            };
            let mut m = members.iter().find(|m| m.kind == DefKind::Event && &m.name == ev).cloned();
            if m.is_none() {
                m = machine_event(self.db, self.ws, ctx, ev);
            }
            self.push(*erange, ev.clone(), RefKind::ConnectionEvent, m.as_ref().map(|m| m.target));
            if m.is_none() {
                self.problem("RC:Cn10", *erange, format!("`{ev}` is not an event of `{name}`"));
            }
        }
    }

    fn clocks(&mut self) {
        // `#C` resets (in transitions and statements) and `since(C)`.
        for n in std::mem::take(&mut self.clocks) {
            let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { continue };
            let name = crate::defs::name_text(&r);
            let Some(inner) = self.defs.innermost(n.text_range()) else { continue };
            let Some(owner) = enclosing(self.defs, inner, &[DefKind::StateMachine, DefKind::Operation]) else {
                continue;
            };
            let members = self.unit.members(self.db, self.ws, owner);
            let found = members
                .iter()
                .find(|m| m.kind == DefKind::Clock && m.name == name && m.via != Some(UseKind::Provides))
                .map(|m| m.target);
            self.push(r.text_range(), name.clone(), RefKind::Clock, found);
            if found.is_none() {
                let owner_kind = self.defs.def(owner).kind.describe();
                self.problem(
                    "LNK-01",
                    r.text_range(),
                    format!("cannot resolve clock `{name}`: it is not a clock of this {owner_kind} or of an interface it uses"),
                );
            }
        }
    }
}

/// An event `name` of a RoboSim controller's machines, for a connection
/// end on a controller that does not declare the event itself: RoboTool
/// lets the controller's events come from the interfaces its machines
/// use (the connection makes the relay explicit).
fn machine_event(db: &dyn Db, ws: Workspace, ctx: Ctx, name: &str) -> Option<Member> {
    let (file, def) = ctx_def(db, ctx)?;
    let defs = crate::element_rules::defs_at(db, file, def).0;
    if file.kind(db) != robosim_syntax::FileKind::RoboSim || defs.def(def).kind != DefKind::Controller {
        return None;
    }
    defs.children(Some(def)).filter(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::MachineRef)).find_map(
        |(id, _)| {
            let mctx = node_ctx(db, ws, file, id)?;
            ctx_members(db, ws, mctx).iter().find(|m| m.kind == DefKind::Event && m.name == name).cloned()
        },
    )
}

fn enclosing_machine(defs: &FileDefs, id: DefId) -> Option<DefId> {
    enclosing(defs, id, &[DefKind::StateMachine, DefKind::Operation])
}

fn segments(q: &SyntaxNode) -> Vec<String> {
    q.children_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| t.kind() == IDENT || (t.kind().is_keyword() && t.kind() != COLON2))
        .map(|t| t.text().trim_start_matches('^').to_string())
        .collect()
}

/// The summary item that declares `loc`'s member `index`.
pub fn member_of(db: &dyn Db, loc: ItemLoc, index: u32) -> &crate::index::MemberSummary {
    &file_summary(db, loc.file).items[loc.index as usize].members[index as usize]
}

/// The key that identifies an operation signature for matching:
/// name and parameter names (the metamodel's operation equality).
pub fn op_key(name: &str, params: &[String]) -> String {
    format!("{name}({})", params.join(","))
}

/// The operations a controller defines, as [`op_key`]s: `operation`
/// definitions, and `opref`s by the definition they reference (`opref o =
/// Op` defines `Op`).
pub fn defined_operations(db: &dyn Db, ws: Workspace, ctx: Ctx) -> std::collections::HashSet<String> {
    let params_of = |d: &DefData| match d {
        DefData::Signature { params, .. } => params.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>(),
        _ => Vec::new(),
    };
    let by_ref = |file: File, path: &[String]| {
        resolve_item(db, ws, file, path, |k| k == DefKind::Operation).first().map(|l| {
            let s = l.summary(db);
            op_key(&s.name, &s.params.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>())
        })
    };
    match ctx {
        Ctx::Local(f, id) => crate::element_rules::defs_at(db, f, id)
            .0
            .children(Some(id))
            .filter_map(|(_, d)| match (&d.kind, &d.data) {
                (DefKind::Operation, data) => Some(op_key(&d.name, &params_of(data))),
                (DefKind::OperationRef, DefData::Reference { path, .. }) => by_ref(f, path),
                _ => None,
            })
            .collect(),
        Ctx::Item(l) => l
            .summary(db)
            .members
            .iter()
            .filter_map(|m| match m.kind {
                DefKind::Operation => {
                    Some(op_key(&m.name, &m.params.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>()))
                }
                DefKind::OperationRef => by_ref(l.file, &m.target),
                _ => None,
            })
            .collect(),
    }
}

/// The definition a context stands for: itself, or the item it names.
pub fn ctx_def(db: &dyn Db, ctx: Ctx) -> Option<(File, DefId)> {
    match ctx {
        Ctx::Local(f, d) => Some((f, d)),
        Ctx::Item(l) => Some((l.file, l.def(db)?)),
    }
}
