//! Elements: state machines (see `machine`), controllers and modules,
//! composed as RoboTool does (paper Rules 1, 9, 10 and 11): the
//! components in parallel, synchronising on `tock` and `terminate` (each
//! element's own in RoboChart, as RoboTool's `M::terminate`), their events
//! renamed to the container's through the connections, connections
//! between components hidden; an asynchronous one between controllers is
//! RoboTool's one-place buffer (RT-12, `buffer`).

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::rc::Rc;

use robosim_hir::defs::{DefId, UseKind};
use robosim_hir::index::ItemLoc;
use robosim_hir::model as m;
use robosim_hir::{Db, File, FileKind, TextRange, Workspace};

use crate::cspm::{call, dot, hide, name, par, Decl, Expr};
use crate::export::{Chan, ChanKind, ConstParam, Dir, Elem, ElemKind, ElemState, Exporter, Reg, Ty};
use crate::machine::{Gen, Problem, ProvidedOp};
use crate::util::event_ident;

mod buffer;
mod shared;

/// A machine, controller or module of the model, to export.
#[derive(Clone, Copy)]
pub(crate) enum ElemDef<'a> {
    Machine(&'a m::Behaviour),
    Controller(&'a m::Controller),
    Module(&'a m::Module),
}

impl<'a> ElemDef<'a> {
    /// The top-level element `loc`, if it is a machine, controller or module.
    pub(crate) fn at(db: &'a dyn Db, ws: Workspace, loc: ItemLoc) -> Option<Self> {
        match m::item(db, ws, loc)? {
            m::Item::Machine(b) => Some(ElemDef::Machine(b)),
            m::Item::Controller(c) => Some(ElemDef::Controller(c)),
            m::Item::Module(x) => Some(ElemDef::Module(x)),
            _ => None,
        }
    }

    /// Its name.
    pub(crate) fn name(self) -> &'a str {
        match self {
            ElemDef::Machine(b) => &b.name,
            ElemDef::Controller(c) => &c.name,
            ElemDef::Module(x) => &x.name,
        }
    }

    /// Its whole range.
    fn range(self) -> TextRange {
        match self {
            ElemDef::Machine(b) => b.range,
            ElemDef::Controller(c) => c.range,
            ElemDef::Module(x) => x.range,
        }
    }

    /// Its name's range.
    pub(crate) fn name_range(self) -> TextRange {
        match self {
            ElemDef::Machine(b) => b.name_range,
            ElemDef::Controller(c) => c.name_range,
            ElemDef::Module(x) => x.name_range,
        }
    }

    fn kind(self) -> ElemKind {
        match self {
            ElemDef::Machine(_) => ElemKind::Machine,
            ElemDef::Controller(_) => ElemKind::Controller,
            ElemDef::Module(_) => ElemKind::Module,
        }
    }
}

/// The top-level element `loc`, exported on first use.
pub(crate) fn element_at(ex: &mut Exporter<'_>, loc: ItemLoc) -> Option<Rc<Elem>> {
    let def = ElemDef::at(ex.db, ex.ws, loc)?;
    let path = ex.path_of_item(loc);
    element(ex, loc.file, def, path)
}

/// The element `def` of `file`, whose qualified path (package, enclosing
/// elements, name) is `path`, exported on first use.
pub(crate) fn element<'a>(ex: &mut Exporter<'a>, file: File, def: ElemDef<'a>, path: Vec<String>) -> Option<Rc<Elem>> {
    element_in(ex, file, def, path, (file, def.range()), file, Scope::default())
}

/// What a machine is translated with: the operations defined for it
/// (its controller's; none on its own, RT-19) and, for an instance of a
/// controller, the machine's own model path (its constants' owner).
#[derive(Default)]
struct Scope<'a> {
    ops: Vec<ProvidedOp<'a>>,
    owner: Option<Vec<String>>,
}

/// [`element`], cached under `key`, its CSPm module named in the package
/// of `home` (the file of the controller of a machine instance).
fn element_in<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    def: ElemDef<'a>,
    path: Vec<String>,
    key: (File, TextRange),
    home: File,
    scope: Scope<'a>,
) -> Option<Rc<Elem>> {
    match ex.elems.get(&key) {
        Some(ElemState::Done(e)) => return Some(e.clone()),
        Some(ElemState::Failed) => return None,
        Some(ElemState::InProgress) => {
            ex.warn(file, def.name_range(), "the element refers to itself");
            return None;
        }
        None => {}
    }
    ex.elems.insert(key, ElemState::InProgress);
    let module = ex.element_module_name(home, &path);
    let kind = def.kind();
    let result = match def {
        ElemDef::Machine(b) => Gen::new(ex, file, Some(b), path.clone(), b.name_range, false)
            .provide(scope.ops, scope.owner)
            .run(module, path.clone())
            .map(|m| (m.elem, m.decls)),
        ElemDef::Controller(c) => controller(ex, file, c, module, path.clone()),
        ElemDef::Module(x) => module_(ex, file, x, module, path.clone()),
    };
    match result {
        Ok((elem, decls)) => {
            ex.emit(home, decls);
            let e = Rc::new(elem);
            ex.elems.insert(key, ElemState::Done(e.clone()));
            Some(e)
        }
        Err(problems) => {
            let mut lines = vec![format!("NOT EXPORTED: {} {}", kind.describe(), path.join("::"))];
            for (f, r, m) in &problems {
                lines.push(format!("  {}: {m}", ex.loc(*f, *r)));
                ex.warn(*f, *r, format!("{} {} is not exported: {m}", kind.describe(), path.join("::")));
            }
            ex.emit(home, vec![Decl::Comment(lines.join("\n")), Decl::Blank]);
            ex.elems.insert(key, ElemState::Failed);
            None
        }
    }
}

/// The element an instance of a controller (machines) or module
/// (controllers) is, declared inline or referenced (`sref`, `cref`),
/// exported on first use; `inline` picks the inline element.
fn instance<'a, T>(
    ex: &mut Exporter<'a>,
    file: File,
    inst: &'a m::Instance<T>,
    container: &[String],
    inline: fn(&'a T) -> ElemDef<'a>,
    problems: &mut Vec<Problem>,
) -> Option<Rc<Elem>> {
    match &inst.def {
        m::Definition::Ref { path, target } => {
            let Some(loc) = target else {
                problems.push((file, inst.range, format!("`{}` could not be resolved", path.join("::"))));
                return None;
            };
            let e = element_at(ex, *loc);
            if e.is_none() {
                problems.push((file, inst.range, format!("`{}` is not exported", path.join("::"))));
            }
            e
        }
        m::Definition::Inline(x) => {
            let def = inline(x);
            let mut path = container.to_vec();
            path.push(def.name().to_string());
            let e = element(ex, file, def, path);
            if e.is_none() {
                problems.push((file, def.name_range(), format!("`{}` is not exported", inst.name)));
            }
            e
        }
    }
}

/// The operations a controller defines for its machines, by the
/// name they call them with: an inline one by its own, a reference
/// (`opref r = P::op`) by the operation's (RT-19, as the engine matches
/// them).
fn controller_operations<'a>(
    ex: &Exporter<'a>,
    file: File,
    c: &'a m::Controller,
    path: &[String],
    problems: &mut Vec<Problem>,
) -> Vec<ProvidedOp<'a>> {
    let mut ops = Vec::new();
    for o in &c.operations {
        match &o.def {
            m::Definition::Inline(b) => ops.push((o.name.clone(), file, &**b, path.to_vec())),
            m::Definition::Ref { path: p, target } => {
                match target.and_then(|loc| Some((loc, m::item(ex.db, ex.ws, loc)?))) {
                    Some((loc, m::Item::Operation(b))) => ops.push((b.name.clone(), loc.file, b, ex.package(loc.file))),
                    _ => problems.push((file, o.range, format!("`{}` could not be resolved", p.join("::")))),
                }
            }
        }
    }
    ops
}

/// A machine of a controller, as RoboTool translates it inside
/// the controller: with the controller's operations inlined (RT-19), as
/// the module `<controller>::<instance>` (`pkg::C::stm_ref0`, whose
/// constants are `const_pkg_C_stm_ref0_k`) for a reference, or the inline
/// machine itself (`pkg::C::S`).
fn machine_instance<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    inst: &'a m::Instance<m::Behaviour>,
    container: &[String],
    ops: &[ProvidedOp<'a>],
    problems: &mut Vec<Problem>,
) -> Option<Rc<Elem>> {
    let (mfile, b, owner, key) = match &inst.def {
        m::Definition::Ref { path, target } => {
            let found = target.and_then(|loc| match m::item(ex.db, ex.ws, loc)? {
                m::Item::Machine(b) => Some((loc, b)),
                _ => None,
            });
            let Some((loc, b)) = found else {
                problems.push((file, inst.range, format!("`{}` could not be resolved", path.join("::"))));
                return None;
            };
            // The machine on its own too (RoboTool's `pkg::M`, with the
            // operations undefined), wherever it is declared.
            element_at(ex, loc);
            (loc.file, b, Some(ex.path_of_item(loc)), (file, inst.range))
        }
        m::Definition::Inline(b) => (file, &**b, None, (file, b.range)),
    };
    let mut path = container.to_vec();
    path.push(if owner.is_some() { inst.name.clone() } else { b.name.clone() });
    let scope = Scope { ops: ops.to_vec(), owner };
    let e = element_in(ex, mfile, ElemDef::Machine(b), path, key, file, scope);
    if e.is_none() {
        problems.push((file, inst.range, format!("`{}` is not exported", inst.name)));
    }
    e
}

/// The machine `inner` declared inside the controller `c` of `file`
/// (whose model path is `ctrl_path`), as its controller translates it
/// (RoboTool's module `pkg::C::S` is the one inside the controller).
pub(crate) fn inner_machine<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    c: &'a m::Controller,
    inner: &str,
    ctrl_path: &[String],
) -> Option<Rc<Elem>> {
    let inst = c.machines.iter().find(|i| matches!(&i.def, m::Definition::Inline(b) if b.name == inner))?;
    let mut problems = Vec::new();
    let ops = controller_operations(ex, file, c, ctrl_path, &mut problems);
    if file.kind(ex.db) == FileKind::RoboSim && ops.is_empty() {
        return instance(ex, file, inst, ctrl_path, ElemDef::Machine, &mut problems);
    }
    machine_instance(ex, file, inst, ctrl_path, &ops, &mut problems)
}

/// The period a RoboSim container is simulated with: hir's choice, the
/// least that its `cycleDef` and those of its components admit (the same
/// period the native checker explores).
pub(crate) fn declared_period(db: &dyn Db, ws: Workspace, file: File, def: Option<DefId>) -> Option<i64> {
    match robosim_hir::cycle::simulation_period(db, ws, file, def?, &[])? {
        robosim_hir::cycle::Feasibility::Feasible(p) => i64::try_from(p).ok(),
        _ => None,
    }
}

/// A component instance of a controller or module.
struct Inst {
    /// Its name in the container (`sref`/`cref` name).
    name: String,
    elem: Rc<Elem>,
}

/// The non-constant variables of the interfaces `decls` refers to with a
/// keyword `which` accepts (`provides`, `requires`, `uses`).
fn variables_of_interfaces(ex: &Exporter<'_>, decls: &m::Decls, which: fn(UseKind) -> bool) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for u in decls.uses.iter().filter(|u| which(u.kind)) {
        if let Some((_, i)) = interface(ex, u) {
            out.extend(variables(&i.decls));
        }
    }
    out
}

/// The interface a `uses`, `provides` or `requires` clause names, and its
/// file.
fn interface<'a>(ex: &Exporter<'a>, u: &m::InterfaceUse) -> Option<(File, &'a m::Platform)> {
    let loc = u.target?;
    match m::item(ex.db, ex.ws, loc)? {
        m::Item::Interface(i) => Some((loc.file, i)),
        _ => None,
    }
}

/// The non-constant variables `decls` declares itself.
fn variables(decls: &m::Decls) -> Vec<String> {
    decls
        .decls
        .iter()
        .filter_map(|d| match d {
            m::Decl::Vars { is_const: false, vars, .. } => Some(vars.iter().map(|v| v.name.clone())),
            _ => None,
        })
        .flatten()
        .collect()
}

/// Events an interface-using context (`decls`, of `file`) declares: own
/// events and those of the interfaces it uses, provides or requires.
fn declared_events(
    ex: &mut Exporter<'_>,
    file: File,
    decls: &m::Decls,
    problems: &mut Vec<Problem>,
) -> Vec<(String, Option<Ty>)> {
    let mut sources = vec![(file, decls)];
    for u in &decls.uses {
        if let Some((f, i)) = interface(ex, u) {
            sources.push((f, &i.decls));
        }
    }
    let mut out: Vec<(String, Option<Ty>)> = Vec::new();
    for (f, d) in sources {
        for decl in &d.decls {
            let m::Decl::Event { name: nm, ty, range, .. } = decl else { continue };
            if out.iter().any(|(x, _)| x == nm) {
                continue;
            }
            let ty = match ty {
                Some(t) => match ex.ty_ref(f, Some(t)) {
                    Ok(t) => Some(t),
                    Err(msg) => {
                        problems.push((f, *range, format!("event `{nm}`: {msg}")));
                        None
                    }
                },
                None => None,
            };
            out.push((nm.clone(), ty));
        }
    }
    out
}

fn event_chan(csp: String, model: String, ty: Option<&Ty>, dir: Dir) -> Chan {
    let values: Vec<Expr> = ty.iter().flat_map(|t| t.field_sets()).collect();
    let mut fields = vec![name("InOut")];
    fields.extend(values.iter().cloned());
    Chan { csp, model, kind: ChanKind::Event, fields, dir, values }
}

fn union_consts(insts: &[Inst]) -> Vec<ConstParam> {
    let mut out: Vec<ConstParam> = Vec::new();
    for i in insts {
        for c in &i.elem.consts {
            if !out.iter().any(|o| o.global == c.global) {
                let mut c = c.clone();
                c.local = c.global.clone();
                out.push(c);
            }
        }
    }
    out
}

/// The arguments of an instance's processes, from the container's
/// parameters.
fn inst_args(e: &Elem, robosim: bool) -> Vec<Expr> {
    let mut a = vec![name("id__")];
    if robosim {
        a.push(name("cycle"));
    }
    a.extend(e.consts.iter().map(|c| name(c.global.clone())));
    a
}

/// Composes `parts` (process, internal channels it uses) in parallel,
/// synchronising on `always` and on the internal channels shared between
/// the left group and the next part.
fn compose(parts: Vec<(Expr, BTreeSet<String>)>, always: &[&str]) -> Expr {
    let mut it = parts.into_iter();
    // No component: only time passes (untimed, nothing happens).
    let Some((mut acc, mut used)) = it.next() else {
        return if always.contains(&"tock") { name("TStop") } else { Expr::Stop };
    };
    for (p, chans) in it {
        let mut sync: Vec<Expr> = always.iter().map(|s| name(*s)).collect();
        sync.extend(used.intersection(&chans).map(|c| name(c.clone())));
        acc = par(acc, Expr::Events(sync), p);
        used.extend(chans);
    }
    acc
}

/// A renaming `from <- to | generators`.
type CompRename = (Expr, Expr, Vec<(String, Expr)>);

/// A synchronous link between two components: (sender's instance and
/// event, receiver's, the connection's range).
type SyncLink = ((usize, Chan), (usize, Chan), TextRange);

/// A register renaming: (component's constructor, container's, value types, input).
type RegRename = (String, String, Vec<Expr>, bool);

type Result2 = Result<(Elem, Vec<Decl>), Vec<Problem>>;

/// What a container passes to its composition: where it is, its
/// instances, the name its connections use for it, its events and its
/// connections.
struct Container<'m> {
    file: File,
    /// Its name's range, for problems.
    name_range: TextRange,
    module: String,
    path: Vec<String>,
    kind: ElemKind,
    insts: Vec<Inst>,
    own: String,
    events: Vec<(String, Option<Ty>)>,
    connections: &'m [m::Connection],
}

fn controller<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    c: &'a m::Controller,
    module: String,
    path: Vec<String>,
) -> Result2 {
    let robosim = file.kind(ex.db) == FileKind::RoboSim;
    let mut problems = Vec::new();
    let mut insts = Vec::new();
    let ops = controller_operations(ex, file, c, &path, &mut problems);
    for i in &c.machines {
        // A RoboSim controller defining no operation has its machines as they
        // are on their own.
        let e = if robosim && ops.is_empty() {
            instance(ex, file, i, &path, ElemDef::Machine, &mut problems)
        } else {
            machine_instance(ex, file, i, &path, &ops, &mut problems)
        };
        if let Some(e) = e {
            insts.push(Inst { name: i.name.clone(), elem: e });
        }
    }
    let events = declared_events(ex, file, &c.decls, &mut problems);
    // RoboTool exports the operations a controller defines (`pkg::C::OP_op`),
    // called or not: each may be checked on its own (RT-11). One that
    // cannot be exported is reported by itself (and by its callers).
    for o in &c.operations {
        if let m::Definition::Inline(b) = &o.def {
            if b.region.nodes.iter().any(|n| n.kind == m::NodeKind::Initial) {
                if robosim && ex.profile == crate::export::Profile::RoboTool3 {
                    let _ = crate::machine::sim_operation(ex, file, b, path.clone());
                } else if !robosim {
                    let _ = crate::machine::operation(ex, file, b, path.clone());
                }
            }
        }
    }
    if insts.is_empty() && problems.is_empty() {
        problems.push((
            file,
            c.name_range,
            "a controller without state machines (RC:C1: RoboTool requires at least one)".into(),
        ));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let k = Container {
        file,
        name_range: c.name_range,
        module,
        path,
        kind: ElemKind::Controller,
        insts,
        own: c.name.clone(),
        events,
        connections: &c.connections,
    };
    if robosim {
        return robosim_container(ex, k, c.def);
    }
    // What it declares or provides is in its own memory (RT-16).
    let mut provided = variables_of_interfaces(ex, &c.decls, |k| k == UseKind::Provides);
    provided.extend(variables(&c.decls));
    robochart_container(ex, k, &[], &provided)
}

fn module_<'a>(ex: &mut Exporter<'a>, file: File, x: &'a m::Module, module: String, path: Vec<String>) -> Result2 {
    let robosim = file.kind(ex.db) == FileKind::RoboSim;
    let mut problems = Vec::new();
    let mut insts = Vec::new();
    for i in &x.controllers {
        if let Some(e) = instance(ex, file, i, &path, ElemDef::Controller, &mut problems) {
            insts.push(Inst { name: i.name.clone(), elem: e });
        }
    }
    // The robotic platform: its name and events.
    let mut platform_names = Vec::new();
    let mut events = Vec::new();
    for p in &x.platforms {
        let platform = match &p.def {
            m::Definition::Inline(pl) => Some((file, &**pl)),
            m::Definition::Ref { path, target } => {
                let found = target.and_then(|loc| match m::item(ex.db, ex.ws, loc)? {
                    m::Item::Platform(pl) => Some((loc.file, pl)),
                    _ => None,
                });
                if found.is_none() {
                    problems.push((file, p.range, format!("`{}` could not be resolved", path.join("::"))));
                }
                found
            }
        };
        if let Some((pf, pl)) = platform {
            platform_names.push(p.name.clone());
            events.extend(declared_events(ex, pf, &pl.decls, &mut problems));
            // Variables of the platform (its own, and those of the
            // interfaces it uses or provides, as `robosim verify` reads
            // them) are outputs (Rule 1): not exported yet.
            let mut vars = variables_of_interfaces(ex, &pl.decls, |_| true);
            vars.extend(variables(&pl.decls));
            if let Some(v) = vars.iter().next() {
                problems.push((
                    pf,
                    pl.name_range,
                    format!(
                        "platform variables (`{v}`) are not exported yet: `robosim verify` reads them as the paper \
                         does (outputs whose updates are visible, §5.2), but RoboTool's CSPm names for them are \
                         not known"
                    ),
                ));
            }
        }
    }
    if insts.is_empty() && problems.is_empty() {
        problems.push((file, x.name_range, "a module without controllers".into()));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let own = platform_names.first().cloned().unwrap_or_default();
    let k = Container {
        file,
        name_range: x.name_range,
        module,
        path,
        kind: ElemKind::Module,
        insts,
        own,
        events,
        connections: &x.connections,
    };
    if robosim {
        return robosim_container(ex, k, x.def);
    }
    // A module provides no variables (it has no interface clauses).
    robochart_container(ex, k, &platform_names, &BTreeSet::new())
}

/// A RoboChart controller (`own` = its name) or module (`own` = its
/// platform's name): components renamed to the container's channels.
fn robochart_container(
    ex: &mut Exporter<'_>,
    k: Container<'_>,
    platforms: &[String],
    provided: &BTreeSet<String>,
) -> Result2 {
    let Container { file, name_range, module, path, kind, insts, own, events, connections } = k;
    let mut problems: Vec<Problem> = Vec::new();
    // RT-16: a controller shares a variable between its machines through
    // its memory (`shared`); two controllers of a module each keep their
    // own (as `robosim verify` does). A variable of the platform several
    // controllers require is refused with the platform's variables.
    let sharing = shared::share((file, name_range), &insts, ex.timed, &mut problems);
    let receives: Vec<(String, File, TextRange)> = insts.iter().flat_map(|i| i.elem.receives.clone()).collect();
    let required: BTreeSet<&String> = insts.iter().flat_map(|i| &i.elem.required).collect();
    let required: Vec<String> = required.into_iter().filter(|v| !provided.contains(*v)).cloned().collect();
    let is_own = |n: &str| n == own || platforms.iter().any(|p| p == n);
    // Renamings per instance: whole channels, and directed events of
    // internal connections (with the generators of their values).
    let mut renames: Vec<Vec<(String, String)>> = vec![Vec::new(); insts.len()];
    let mut conn_renames: Vec<Vec<CompRename>> = vec![Vec::new(); insts.len()];
    let mut internal: Vec<BTreeSet<String>> = vec![BTreeSet::new(); insts.len()];
    let mut private = Vec::new();
    let mut chans: Vec<Chan> = Vec::new();
    let mut hidden: Vec<String> = Vec::new();
    let inst_of = |n: &str| insts.iter().position(|i| i.name == n);
    // InOut's constructors, as this module can name them: its own event
    // `in` or `out` (RoboTool's name) hides them.
    let own_events: BTreeSet<String> = connections
        .iter()
        .filter_map(|c| match (is_own(&c.from), is_own(&c.to)) {
            (true, _) => Some(event_ident(&c.efrom)),
            (_, true) => Some(event_ident(&c.eto)),
            _ => None,
        })
        .collect();
    let mut direction = |d: &'static str| {
        if own_events.contains(d) {
            let alias = if d == "in" { "in'" } else { "out'" };
            ex.helpers.insert(alias);
            name(alias)
        } else {
            name(d)
        }
    };
    // The events of each instance some connection names.
    let mut connected: Vec<BTreeSet<&str>> = vec![BTreeSet::new(); insts.len()];
    // Synchronous links between components: (sender end, receiver end).
    let mut links: Vec<SyncLink> = Vec::new();
    // Asynchronous links between controllers, and how many connections
    // name each (instance, event).
    let mut async_links: Vec<buffer::AsyncLink> = Vec::new();
    let mut uses: BTreeMap<(usize, String), usize> = BTreeMap::new();
    for c in connections {
        let ((a, ea), (b, eb), is_async) =
            ((c.from.clone(), c.efrom.clone()), (c.to.clone(), c.eto.clone()), c.is_async);
        let (ia, ib) = (inst_of(&a), inst_of(&b));
        for (x, e) in [(ia, &c.efrom), (ib, &c.eto)] {
            if let Some(x) = x {
                connected[x].insert(e.as_str());
                *uses.entry((x, e.clone())).or_default() += 1;
            }
        }
        match (is_own(&a), ia, is_own(&b), ib) {
            // Container ↔ component.
            (true, _, _, Some(j)) | (_, Some(j), true, _) => {
                let (cev, iev, dir) = if is_own(&a) { (&ea, &eb, Dir::In) } else { (&eb, &ea, Dir::Out) };
                let Some(ch) = insts[j].elem.chans.iter().find(|ch| ch.kind == ChanKind::Event && ch.model == *iev)
                else {
                    problems.push((file, c.range, format!("`{iev}` is not an event of `{}`", insts[j].name)));
                    continue;
                };
                let Some((_, ty)) = events.iter().find(|(n, _)| n == cev) else {
                    problems.push((
                        file,
                        c.range,
                        format!("`{cev}` is not an event of `{}`", if is_own(&a) { &a } else { &b }),
                    ));
                    continue;
                };
                let csp = event_ident(cev);
                renames[j].push((format!("{}::{}", insts[j].elem.module, ch.csp), csp.clone()));
                if !chans.iter().any(|x| x.csp == csp) {
                    chans.push(event_chan(csp, cev.clone(), ty.as_ref(), dir));
                }
            }
            // Component ↔ component: a hidden synchronisation (RT-14), or
            // between controllers, a buffer (RT-12).
            (_, Some(i), _, Some(j)) => {
                if is_async && kind != ElemKind::Module {
                    problems.push((
                        file,
                        c.range,
                        "asynchronous connections between two machines of a controller are not exported: they \
                         have no semantics (RC:Cn11), and RoboTool's buffer is pinned down between two \
                         controllers only (RT-12)"
                            .into(),
                    ));
                    continue;
                }
                if is_async && c.is_mult {
                    problems.push((
                        file,
                        c.range,
                        "a bidirectional (`[ mult ]`) asynchronous connection between controllers is not exported: \
                         RoboTool's buffer is known one way only, from the connection's source (RT-12)"
                            .into(),
                    ));
                    continue;
                }
                let find = |x: usize, e: &str| {
                    insts[x].elem.chans.iter().find(|ch| ch.kind == ChanKind::Event && ch.model == e).cloned()
                };
                let (Some(ca), Some(cb)) = (find(i, &ea), find(j, &eb)) else {
                    problems.push((file, c.range, "a connection end is not an event of its component".into()));
                    continue;
                };
                if ca.values != cb.values {
                    problems.push((file, c.range, "the connected events have different types".into()));
                    continue;
                }
                if is_async {
                    async_links.push(((i, ca), (j, cb), c.range));
                } else {
                    links.push(((i, ca), (j, cb), c.range));
                }
            }
            _ => problems.push((file, c.range, format!("the connection `{a}` → `{b}` has an unknown end"))),
        }
    }
    // RT-14: the ends linked (directly or through other links) form one
    // synchronisation, its one sender's output with every receiver's
    // input at once, hidden: one channel `connK__` each.
    let mut classes: Vec<Vec<(usize, &Chan, &'static str)>> = Vec::new();
    let mut class_range: Vec<TextRange> = Vec::new();
    for ((i, ca), (j, cb), range) in &links {
        let ends = [(*i, ca, "out"), (*j, cb, "in")];
        let found: Vec<usize> = (0..classes.len())
            .filter(|&x| classes[x].iter().any(|(y, ch, _)| ends.iter().any(|(z, c, _)| y == z && ch.csp == c.csp)))
            .collect();
        let target = match found.first() {
            Some(&t) => {
                // Merge the other classes the link touches into the first.
                for &x in found[1..].iter().rev() {
                    let moved = classes.remove(x);
                    class_range.remove(x);
                    classes[t].extend(moved);
                }
                t
            }
            None => {
                classes.push(Vec::new());
                class_range.push(*range);
                classes.len() - 1
            }
        };
        for e in ends {
            if !classes[target].iter().any(|(y, ch, d)| *y == e.0 && ch.csp == e.1.csp && *d == e.2) {
                classes[target].push(e);
            }
        }
    }
    for (k, (class, range)) in classes.iter().zip(&class_range).enumerate() {
        let senders: BTreeSet<(usize, &str)> =
            class.iter().filter(|e| e.2 == "out").map(|(x, ch, _)| (*x, ch.csp.as_str())).collect();
        if senders.len() != 1 {
            problems.push((
                file,
                *range,
                format!(
                    "the event `{}` links {} senders: a synchronisation of several senders is not exported (RT-14 \
                     reads one sender and several receivers)",
                    class[0].1.model,
                    senders.len()
                ),
            ));
            continue;
        }
        let conn = format!("conn{}__", k + 1);
        private.push(Decl::Channel(vec![conn.clone()], class[0].1.values.clone()));
        for &(x, ch, d) in class {
            let mut from = vec![name(format!("{}::{}", insts[x].elem.module, ch.csp)), direction(d)];
            let mut to = vec![name(conn.clone())];
            let mut gens = Vec::new();
            for (n, v) in ch.values.iter().enumerate() {
                let var = format!("x{n}__");
                from.push(name(var.clone()));
                to.push(name(var.clone()));
                gens.push((var, v.clone()));
            }
            conn_renames[x].push((dot(from), dot(to), gens));
            internal[x].insert(conn.clone());
        }
        hidden.push(conn);
    }
    // RT-12: each asynchronous link is a buffer in parallel with the
    // components on both ends' whole channels, which are hidden.
    buffer::check_ends(file, &async_links, &uses, &mut problems);
    let mut buffers: Vec<Expr> = Vec::new();
    let mut buffered: Vec<Expr> = Vec::new();
    for (k, ((i, ca), (j, cb), _)) in async_links.iter().enumerate() {
        let sender = format!("{}::{}", insts[*i].elem.module, ca.csp);
        let receiver = format!("{}::{}", insts[*j].elem.module, cb.csp);
        let (decls, p) = buffer::buffer(k + 1, &sender, &receiver, &ca.values, direction("out"), direction("in"));
        private.extend(decls);
        buffers.push(p);
        for ch in [sender, receiver] {
            buffered.push(name(ch.clone()));
            hidden.push(ch);
        }
    }
    // RT-15: a machine's event connected to nothing is hidden by its
    // controller (no generated example shows RoboTool's text; its
    // meaning, τ, is the fact's). A controller's such event in a module is
    // left visible: the facts do not say.
    if kind == ElemKind::Controller {
        for (j, i) in insts.iter().enumerate() {
            for ch in i.elem.chans.iter().filter(|ch| ch.kind == ChanKind::Event) {
                if !connected[j].contains(ch.model.as_str()) {
                    hidden.push(format!("{}::{}", i.elem.module, ch.csp));
                }
            }
        }
    }
    // Operation calls go to the platform by name.
    for (j, i) in insts.iter().enumerate() {
        for ch in i.elem.chans.iter().filter(|c| c.kind != ChanKind::Event) {
            match chans.iter().find(|x| x.csp == ch.csp) {
                Some(x) if x.values != ch.values => problems.push((
                    file,
                    name_range,
                    format!("operation `{}` is required with different parameter types", ch.model),
                )),
                Some(_) => {}
                None => chans.push(ch.clone()),
            }
            renames[j].push((format!("{}::{}", i.elem.module, ch.csp), ch.csp.clone()));
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    private.extend(sharing.decls.iter().cloned());
    hidden.extend(sharing.hidden.iter().cloned());
    let consts = union_consts(&insts);
    let mut params = vec!["id__".to_string()];
    params.extend(consts.iter().map(|c| c.global.clone()));
    // The composition of the components' `process` (`D__`; `VS__`, with
    // the entries of states visible, as RoboTool's controllers and
    // modules compose their components' `VS__`), ending together on the
    // container's `terminate`.
    for (j, i) in insts.iter().enumerate() {
        renames[j].push((format!("{}::terminate", i.elem.module), "terminate".into()));
    }
    let timed = ex.timed;
    let body = |process: &str| {
        let mut parts = Vec::new();
        for (j, i) in insts.iter().enumerate() {
            // RT-16: with its writes of the shared variables visible.
            let process = match (sharing.open(j), process) {
                (true, "D__") => "DS__",
                (true, _) => "VSS__",
                (false, p) => p,
            };
            let mut p = rename(call(format!("{}::{process}", i.elem.module), inst_args(&i.elem, false)), &renames[j]);
            for (from, to, gens) in &conn_renames[j] {
                p = Expr::Rename(Box::new(p), vec![(from.clone(), to.clone())], gens.clone());
            }
            let mut chans = internal[j].clone();
            chans.extend(sharing.chans[j].iter().cloned());
            parts.push((p, chans));
        }
        parts.extend(sharing.parts.iter().cloned());
        let mut comp = compose(parts, if timed { &["tock", "terminate"] } else { &["terminate"] });
        if !buffers.is_empty() {
            let all = crate::cspm::nary(crate::cspm::ProcOp::Interleave, buffers.clone());
            comp = par(all, Expr::Events(buffered.clone()), comp);
        }
        let body = if hidden.is_empty() {
            comp
        } else {
            hide(comp, Expr::Events(hidden.iter().map(|h| name(h.clone())).collect()))
        };
        // RoboTool: `P [|{|terminate|}|> SKIP`; a controller shows its
        // `terminate`, a module hides it (so it ends at once, τ before `tock`).
        let end = Expr::Events(vec![name("terminate")]);
        let body = Expr::Exception(Box::new(body), Box::new(end.clone()), Box::new(Expr::Skip));
        if kind == ElemKind::Module {
            hide(body, end)
        } else {
            body
        }
    };
    let mut exports = vec![
        Decl::Comment(format!("Its end (RoboTool's `terminate`, per {}).", kind.describe())),
        Decl::Channel(vec!["terminate".into()], vec![]),
        Decl::Comment("Events and operation calls.".into()),
    ];
    for ch in &chans {
        exports.push(Decl::Channel(vec![ch.csp.clone()], ch.fields.clone()));
    }
    exports.push(Decl::Comment(format!(
        "D__: the {}'s semantics; VS__: with its machines' `entered__` visible (reachability);\nO__: D__ compressed (parameters: {}).",
        kind.describe(),
        params.join(", ")
    )));
    let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
    // Untimed (RT-9), no `TimedPriority`: there is no `tock`.
    let prioritised = |p: Expr| if timed { call("TimedPriority", vec![p]) } else { p };
    exports.push(Decl::Def("D__".into(), params.clone(), prioritised(body("D__"))));
    exports.push(Decl::Def("VS__".into(), params.clone(), prioritised(body("VS__"))));
    exports.push(Decl::Def("O__".into(), params.clone(), call("sbisim", vec![call("D__", args)])));
    let decls = vec![
        Decl::Comment(format!("RoboChart {} {}", kind.describe(), path.join("::"))),
        Decl::Module(module.clone(), private, exports),
        Decl::Blank,
    ];
    let _ = ex;
    Ok((
        Elem {
            kind,
            robosim: false,
            module,
            path,
            consts,
            chans,
            inputs: vec![],
            outputs: vec![],
            period: 1,
            required,
            shared: vec![],
            receives,
            parts: insts.into_iter().map(|i| (i.name, i.elem)).collect(),
            states: Vec::new(),
            functions: Default::default(),
        },
        decls,
    ))
}

/// The CSPm modules of the machines inside `e` (itself when a machine).
fn machine_modules(e: &Elem, out: &mut Vec<String>) {
    if e.kind == ElemKind::Machine {
        out.push(e.module.clone());
    }
    for (_, p) in &e.parts {
        machine_modules(p, out);
    }
}

fn rename(p: Expr, pairs: &[(String, String)]) -> Expr {
    if pairs.is_empty() {
        return p;
    }
    Expr::Rename(Box::new(p), pairs.iter().map(|(a, b)| (name(a.clone()), name(b.clone()))).collect(), vec![])
}

/// A RoboSim controller or module: the components' register events are
/// renamed to the container's registers through the connections.
fn robosim_container(ex: &mut Exporter<'_>, k: Container<'_>, def: Option<DefId>) -> Result2 {
    let Container { file, name_range, module, path, kind, insts, own, events, connections } = k;
    let mut problems: Vec<Problem> = Vec::new();
    let inst_of = |n: &str| insts.iter().position(|i| i.name == n);
    // Register renamings per instance: (instance ctor, container ctor, value types, input).
    let mut renames: Vec<Vec<RegRename>> = vec![Vec::new(); insts.len()];
    let mut mapped: HashMap<(usize, String), String> = HashMap::new();
    for c in connections {
        let ((a, ea), (b, eb)) = ((c.from.clone(), c.efrom.clone()), (c.to.clone(), c.eto.clone()));
        match (a == own, inst_of(&a), b == own, inst_of(&b)) {
            (true, _, _, Some(j)) | (_, Some(j), true, _) => {
                let (cev, iev) = if a == own { (&ea, &eb) } else { (&eb, &ea) };
                if !events.iter().any(|(n, _)| n == cev) {
                    problems.push((file, c.range, format!("`{cev}` is not an event of `{own}`")));
                    continue;
                }
                mapped.insert((j, iev.clone()), cev.clone());
            }
            (_, Some(_), _, Some(_)) => problems.push((
                file,
                c.range,
                "connections between RoboSim machines or controllers are not supported by the export yet".into(),
            )),
            _ => problems.push((file, c.range, format!("the connection `{a}` → `{b}` has an unknown end"))),
        }
    }
    let mut inputs: Vec<Reg> = Vec::new();
    let mut outputs: Vec<Reg> = Vec::new();
    for (j, i) in insts.iter().enumerate() {
        for (regs, input) in [(&i.elem.inputs, true), (&i.elem.outputs, false)] {
            for r in regs {
                let model = mapped.get(&(j, r.model.clone())).cloned().unwrap_or_else(|| r.model.clone());
                let ctor = if input { ex.in_reg(&model) } else { ex.out_reg(&model) };
                if let Err(m) = ex.register(input, &ctor, &r.values) {
                    problems.push((file, name_range, m));
                    continue;
                }
                if ctor != r.ctor {
                    renames[j].push((r.ctor.clone(), ctor.clone(), r.values.clone(), input));
                }
                let list = if input { &mut inputs } else { &mut outputs };
                if list.iter().any(|x| x.ctor == ctor) {
                    problems.push((
                        file,
                        name_range,
                        format!("the register `{ctor}` is used by two components: each input and output belongs to one (RS:C3, RS:M3)"),
                    ));
                    continue;
                }
                list.push(Reg { ctor, model, values: r.values.clone() });
            }
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let consts = union_consts(&insts);
    let mut params = vec!["id__".to_string(), "cycle".to_string()];
    params.extend(consts.iter().map(|c| c.global.clone()));
    let mut parts = Vec::new();
    for (j, i) in insts.iter().enumerate() {
        // Each component's names (its module's own, as RoboTool's) become
        // the container's: RoboTool has no RoboSim controller or module,
        // so this follows its RoboChart pattern.
        let regs: Vec<crate::sim_names::RegRename> = i
            .elem
            .inputs
            .iter()
            .map(|r| (r, true))
            .chain(i.elem.outputs.iter().map(|r| (r, false)))
            .map(|(r, input)| {
                let to = renames[j]
                    .iter()
                    .find(|(from, _, _, inp)| *from == r.ctor && *inp == input)
                    .map_or_else(|| r.ctor.clone(), |(_, to, _, _)| to.clone());
                crate::sim_names::RegRename { from: r.ctor.clone(), to, values: r.values.clone(), input }
            })
            .collect();
        let p = call(format!("{}::P__", i.elem.module), inst_args(&i.elem, true));
        let p = crate::sim_names::unqualify(ex.profile, p, &i.elem.module, &regs, true);
        parts.push((p, BTreeSet::new()));
    }
    // RT-21: the components end each cycle together, on one `endexec`
    // (after every machine's), shown by a controller and hidden by a
    // module, as is `terminate`. The paper's machines hide their own.
    let visible_end = ex.profile == crate::Profile::RoboTool3;
    let comp = compose(parts, if visible_end { &["tock", "terminate", "endexec"] } else { &["tock", "terminate"] });
    let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
    // The machines' `P__` show their `entered__`: D__ hides them, VS__
    // keeps them (reachability), as RoboTool's `VS__` of a container.
    let mut machines = Vec::new();
    for i in &insts {
        machine_modules(&i.elem, &mut machines);
    }
    let entered = Expr::Events(machines.iter().map(|m| name(format!("{m}::entered__"))).collect());
    let shown = visible_end && kind == ElemKind::Controller;
    let ending = |p: Expr| {
        let end = Expr::Exception(Box::new(p), Box::new(Expr::Set(vec![name("terminate")])), Box::new(Expr::Skip));
        let end = match (shown, visible_end) {
            (true, _) => end,
            (false, true) => hide(end, Expr::Set(vec![name("endexec"), name("terminate")])),
            (false, false) => hide(end, Expr::Set(vec![name("terminate")])),
        };
        call("TimedPriority", vec![end])
    };
    let p_call = call("P__", args.clone());
    let d_body = if machines.is_empty() { ending(p_call.clone()) } else { ending(hide(p_call.clone(), entered)) };
    let sig = |regs: &[Reg]| -> Vec<crate::sim_names::RegSig> {
        regs.iter().map(|r| (r.ctor.clone(), r.values.clone())).collect()
    };
    let mut exports = crate::sim_names::own_names(ex.profile, &sig(&inputs), &sig(&outputs), true);
    exports.extend([
        Decl::Comment(format!(
            "P__: the {} with `terminate`{} and its machines' `entered__` visible;{}D__: its semantics{};\n\
             VS__: with the machines' `entered__` visible (reachability); O__: D__ compressed\n(parameters: {}).",
            kind.describe(),
            if visible_end { ", one `endexec` per cycle" } else { "" },
            if visible_end { "\n" } else { " " },
            match (shown, visible_end) {
                (true, _) => ", `endexec` and `terminate` visible (RT-21)",
                (false, true) => ", `endexec` and `terminate` hidden (RT-21)",
                (false, false) => "",
            },
            params.join(", ")
        )),
        Decl::Def("P__".into(), params.clone(), call("TimedPriority", vec![comp])),
        Decl::Def("D__".into(), params.clone(), d_body),
        Decl::Def("VS__".into(), params.clone(), ending(p_call)),
        Decl::Def("O__".into(), params.clone(), call("sbisim", vec![call("D__", args)])),
    ]);
    let decls = vec![
        Decl::Comment(format!(
            "RoboSim {} {}\n\
             Its own names, and its components' renamed into them, follow RoboTool's RoboChart\n\
             pattern: RoboTool's reference output has no RoboSim controller or module.",
            kind.describe(),
            path.join("::")
        )),
        Decl::Module(module.clone(), vec![], exports),
        Decl::Blank,
    ];
    let period = declared_period(ex.db, ex.ws, file, def).unwrap_or(1);
    Ok((
        Elem {
            kind,
            robosim: true,
            module,
            path,
            consts,
            chans: vec![],
            inputs,
            outputs,
            period,
            required: vec![],
            shared: vec![],
            receives: vec![],
            parts: insts.into_iter().map(|i| (i.name, i.elem)).collect(),
            states: Vec::new(),
            functions: Default::default(),
        },
        decls,
    ))
}
