//! Elements: state machines (see `machine`), controllers and modules,
//! composed as RoboTool does (paper Rules 1, 9, 10 and 11): the
//! components in parallel, synchronising on `tock` (and, in RoboSim, on
//! `terminate`), their events renamed to the container's through the
//! connections, connections between components hidden.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::rc::Rc;

use robosim_hir::defs::DefKind;
use robosim_hir::{Db, File, Workspace};
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode};

use crate::cspm::{call, dot, hide, name, par, Decl, Expr};
use crate::export::{Chan, ChanKind, ConstParam, Dir, Elem, ElemKind, ElemState, Exporter, Reg, Ty};
use crate::machine::{Gen, Problem};
use crate::util::{self, children, ident, ident_text, name_of, path_of};

/// The element declared at `node` of `file`, exported on first use.
pub(crate) fn element(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode) -> Option<Rc<Elem>> {
    let key = (file, node.text_range());
    match ex.elems.get(&key) {
        Some(ElemState::Done(e)) => return Some(e.clone()),
        Some(ElemState::Failed) => return None,
        Some(ElemState::InProgress) => {
            ex.warn(file, util::name_range(node), "the element refers to itself");
            return None;
        }
        None => {}
    }
    ex.elems.insert(key, ElemState::InProgress);
    let path = ex.path_of_node(file, node);
    let module = ex.element_module_name(file, &path);
    let kind = match node.kind() {
        STATE_MACHINE => ElemKind::Machine,
        CONTROLLER => ElemKind::Controller,
        _ => ElemKind::Module,
    };
    let result = match kind {
        ElemKind::Machine => Gen::new(ex, file, node, false).run(module, path.clone()).map(|m| (m.elem, m.decls)),
        ElemKind::Controller => controller(ex, file, node, module, path.clone()),
        ElemKind::Module => module_(ex, file, node, module, path.clone()),
    };
    match result {
        Ok((elem, decls)) => {
            ex.emit(file, decls);
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
            ex.emit(file, vec![Decl::Comment(lines.join("\n")), Decl::Blank]);
            ex.elems.insert(key, ElemState::Failed);
            None
        }
    }
}

/// The element a reference (`sref`, `cref`) names, exported on first use.
fn referenced(
    ex: &mut Exporter<'_>,
    file: File,
    r: &SyntaxNode,
    kind: DefKind,
    problems: &mut Vec<Problem>,
) -> Option<Rc<Elem>> {
    let accept: fn(DefKind) -> bool = match kind {
        DefKind::StateMachine => |k| k == DefKind::StateMachine,
        DefKind::Controller => |k| k == DefKind::Controller,
        _ => |k| k == DefKind::Platform,
    };
    let p = path_of(r);
    let Some((f, n)) = util::resolve(ex.db, ex.ws, file, &p, accept) else {
        problems.push((file, r.text_range(), format!("`{}` could not be resolved", p.join("::"))));
        return None;
    };
    let e = element(ex, f, &n);
    if e.is_none() {
        problems.push((file, r.text_range(), format!("`{}` is not exported", p.join("::"))));
    }
    e
}

/// The period a RoboSim container is simulated with: hir's choice, the
/// least that its `cycleDef` and those of its components admit (the same
/// period the native checker explores).
pub(crate) fn declared_period(db: &dyn Db, ws: Workspace, file: File, node: &SyntaxNode) -> Option<i64> {
    let defs = robosim_hir::defs::file_defs(db, file);
    let id = defs.iter().find(|(_, d)| d.range == node.text_range() && d.syntax == node.kind()).map(|(i, _)| i)?;
    match robosim_hir::cycle::simulation_period(db, ws, file, id, &[])? {
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

/// The non-constant variables of the interfaces `node` refers to with a
/// keyword `which` accepts (`provides`, `requires`, `uses`).
fn variables_of_interfaces(
    ex: &Exporter<'_>,
    file: File,
    node: &SyntaxNode,
    which: fn(SyntaxKind) -> bool,
) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for u in children(node, INTERFACE_USE) {
        if !u.first_token().is_some_and(|t| which(t.kind())) {
            continue;
        }
        let Some((_, i)) = util::resolve(ex.db, ex.ws, file, &path_of(&u), |k| k == DefKind::Interface) else {
            continue;
        };
        out.extend(variables(&i));
    }
    out
}

/// The non-constant variables `node` declares itself.
fn variables(node: &SyntaxNode) -> Vec<String> {
    children(node, VARIABLE_LIST)
        .filter(|l| !l.children_with_tokens().any(|t| t.kind() == CONST_KW))
        .flat_map(|l| children(&l, VARIABLE).map(|v| name_of(&v)).collect::<Vec<_>>())
        .collect()
}

/// Events an interface-using context declares: own events and those of
/// the interfaces it uses, provides or requires.
fn declared_events(
    ex: &mut Exporter<'_>,
    file: File,
    node: &SyntaxNode,
    problems: &mut Vec<Problem>,
) -> Vec<(String, Option<Ty>)> {
    let mut sources = vec![(file, node.clone())];
    for u in children(node, INTERFACE_USE) {
        let p = path_of(&u);
        if let Some((f, n)) = util::resolve(ex.db, ex.ws, file, &p, |k| k == DefKind::Interface) {
            sources.push((f, n));
        }
    }
    let mut out: Vec<(String, Option<Ty>)> = Vec::new();
    for (f, n) in sources {
        for ev in children(&n, EVENT) {
            let nm = name_of(&ev);
            if out.iter().any(|(x, _)| *x == nm) {
                continue;
            }
            let ty = match util::type_child(&ev) {
                Some(t) => match ex.ty(f, Some(&t)) {
                    Ok(t) => Some(t),
                    Err(m) => {
                        problems.push((f, ev.text_range(), format!("event `{nm}`: {m}")));
                        None
                    }
                },
                None => None,
            };
            out.push((nm, ty));
        }
    }
    out
}

/// A connection's ends: (node, event) × 2, and whether asynchronous.
fn ends(c: &SyntaxNode) -> ((String, String), (String, String), bool) {
    let refs: Vec<String> = children(c, NAME_REF).map(|n| ident_text(&n)).collect();
    let get = |i: usize| refs.get(i).cloned().unwrap_or_default();
    ((get(0), get(1)), (get(2), get(3)), c.children().any(|n| n.kind() == ASYNC_FLAG))
}

fn event_chan(csp: String, model: String, ty: Option<&Ty>, dir: Dir) -> Chan {
    let values: Vec<Expr> = ty.iter().flat_map(|t| t.field_sets()).collect();
    let mut fields = vec![name("InOut")];
    fields.extend(values.iter().cloned());
    Chan { csp, model, kind: ChanKind::Event, fields, dir, values }
}

/// Collects the instances of a controller (machines) or module
/// (controllers).
fn instances(
    ex: &mut Exporter<'_>,
    file: File,
    node: &SyntaxNode,
    inner: DefKind,
    problems: &mut Vec<Problem>,
) -> Vec<Inst> {
    let (refk, defk) = match inner {
        DefKind::StateMachine => (STATE_MACHINE_REF, STATE_MACHINE),
        _ => (CONTROLLER_REF, CONTROLLER),
    };
    let mut out = Vec::new();
    for c in node.children() {
        if c.kind() == refk {
            if let Some(e) = referenced(ex, file, &c, inner, problems) {
                out.push(Inst { name: name_of(&c), elem: e });
            }
        } else if c.kind() == defk {
            match element(ex, file, &c) {
                Some(e) => out.push(Inst { name: name_of(&c), elem: e }),
                None => problems.push((file, util::name_range(&c), format!("`{}` is not exported", name_of(&c)))),
            }
        }
    }
    out
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
    let Some((mut acc, mut used)) = it.next() else { return name("TStop") };
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

/// A register renaming: (component's constructor, container's, value types, input).
type RegRename = (String, String, Vec<Expr>, bool);

type Result2 = Result<(Elem, Vec<Decl>), Vec<Problem>>;

fn controller(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode, module: String, path: Vec<String>) -> Result2 {
    let robosim = file.kind(ex.db) == robosim_syntax::FileKind::RoboSim;
    let mut problems = Vec::new();
    let insts = instances(ex, file, node, DefKind::StateMachine, &mut problems);
    let own = name_of(node);
    let events = declared_events(ex, file, node, &mut problems);
    for c in node.children() {
        if matches!(c.kind(), OPERATION_DEF | OPERATION_REF) {
            // The machines run the operations they can resolve by name;
            // one they call the platform for is defined here only.
            let op =
                if c.kind() == OPERATION_REF { path_of(&c).last().cloned().unwrap_or_default() } else { name_of(&c) };
            let called =
                insts.iter().any(|i| i.elem.chans.iter().any(|ch| ch.kind == ChanKind::Call && ch.model == op))
                    || insts.iter().any(|i| i.elem.outputs.iter().any(|o| o.model == op));
            if called {
                problems.push((
                    file,
                    c.text_range(),
                    format!(
                        "operation `{op}` is provided by the controller, but the machines calling it cannot \
                         resolve its definition by name (they run an operation only where they resolve it): \
                         not supported by the export yet"
                    ),
                ));
            }
        }
    }
    if insts.is_empty() && problems.is_empty() {
        problems.push((file, util::name_range(node), "a controller without state machines".into()));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let connections: Vec<_> = children(node, CONNECTION).collect();
    if robosim {
        return robosim_container(
            ex,
            file,
            node,
            module,
            path,
            insts,
            &own,
            &events,
            &connections,
            ElemKind::Controller,
        );
    }
    robochart_container(ex, file, node, module, path, insts, &own, &events, &connections, ElemKind::Controller, &[])
}

fn module_(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode, module: String, path: Vec<String>) -> Result2 {
    let robosim = file.kind(ex.db) == robosim_syntax::FileKind::RoboSim;
    let mut problems = Vec::new();
    let insts = instances(ex, file, node, DefKind::Controller, &mut problems);
    // The robotic platform: its name and events.
    let mut platform_names = Vec::new();
    let mut events = Vec::new();
    for c in node.children() {
        let pnode = match c.kind() {
            ROBOTIC_PLATFORM => Some((file, c.clone())),
            PLATFORM_REF => {
                let p = path_of(&c);
                let r = util::resolve(ex.db, ex.ws, file, &p, |k| k == DefKind::Platform);
                if r.is_none() {
                    problems.push((file, c.text_range(), format!("`{}` could not be resolved", p.join("::"))));
                }
                r
            }
            _ => None,
        };
        if let Some((pf, pn)) = pnode {
            platform_names.push(name_of(&c));
            events.extend(declared_events(ex, pf, &pn, &mut problems));
            // Variables of the platform (its own, and those of the
            // interfaces it uses or provides, as `robosim verify` reads
            // them) are outputs (Rule 1): not exported yet.
            let mut vars = variables_of_interfaces(ex, pf, &pn, |_| true);
            vars.extend(variables(&pn));
            if let Some(v) = vars.iter().next() {
                problems.push((
                    pf,
                    util::name_range(&pn),
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
        problems.push((file, util::name_range(node), "a module without controllers".into()));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let connections: Vec<_> = children(node, CONNECTION).collect();
    let own = platform_names.first().cloned().unwrap_or_default();
    if robosim {
        return robosim_container(ex, file, node, module, path, insts, &own, &events, &connections, ElemKind::Module);
    }
    robochart_container(
        ex,
        file,
        node,
        module,
        path,
        insts,
        &own,
        &events,
        &connections,
        ElemKind::Module,
        &platform_names,
    )
}

/// A RoboChart controller (`own` = its name) or module (`own` = its
/// platform's name): components renamed to the container's channels.
#[allow(clippy::too_many_arguments)]
fn robochart_container(
    ex: &mut Exporter<'_>,
    file: File,
    node: &SyntaxNode,
    module: String,
    path: Vec<String>,
    insts: Vec<Inst>,
    own: &str,
    events: &[(String, Option<Ty>)],
    connections: &[SyntaxNode],
    kind: ElemKind,
    platforms: &[String],
) -> Result2 {
    let mut problems: Vec<Problem> = Vec::new();
    // Each machine keeps the variables it requires in its own memory, so a
    // variable two components require would not be shared (as it is in
    // the model, and in `robosim verify`): refused rather than exported
    // wrongly.
    let mut requirers: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for i in &insts {
        for v in &i.elem.required {
            requirers.entry(v.as_str()).or_default().push(i.name.as_str());
        }
    }
    for (v, users) in &requirers {
        if users.len() > 1 {
            problems.push((
                file,
                util::name_range(node),
                format!(
                    "`{v}` is required by {}: variables shared between machines or controllers are not exported \
                     yet (each would keep its own copy; `robosim verify` shares them)",
                    users.iter().map(|u| format!("`{u}`")).collect::<Vec<_>>().join(" and ")
                ),
            ));
        }
    }
    let provided = variables_of_interfaces(ex, file, node, |k| k == PROVIDES_KW);
    let required: Vec<String> = requirers.keys().filter(|v| !provided.contains(**v)).map(|v| v.to_string()).collect();
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
    let mut k = 0;
    for c in connections {
        let ((a, ea), (b, eb), is_async) = ends(c);
        let (ia, ib) = (inst_of(&a), inst_of(&b));
        match (is_own(&a), ia, is_own(&b), ib) {
            // Container ↔ component.
            (true, _, _, Some(j)) | (_, Some(j), true, _) => {
                let (cev, iev, dir) = if is_own(&a) { (&ea, &eb, Dir::In) } else { (&eb, &ea, Dir::Out) };
                let Some(ch) = insts[j].elem.chans.iter().find(|ch| ch.kind == ChanKind::Event && ch.model == *iev)
                else {
                    problems.push((file, c.text_range(), format!("`{iev}` is not an event of `{}`", insts[j].name)));
                    continue;
                };
                let Some((_, ty)) = events.iter().find(|(n, _)| n == cev) else {
                    problems.push((
                        file,
                        c.text_range(),
                        format!("`{cev}` is not an event of `{}`", if is_own(&a) { &a } else { &b }),
                    ));
                    continue;
                };
                let csp = ident(cev);
                renames[j].push((format!("{}::{}", insts[j].elem.module, ch.csp), csp.clone()));
                if !chans.iter().any(|x| x.csp == csp) {
                    chans.push(event_chan(csp, cev.clone(), ty.as_ref(), dir));
                }
            }
            // Component ↔ component: a hidden synchronisation.
            (_, Some(i), _, Some(j)) => {
                if is_async {
                    problems.push((
                        file,
                        c.text_range(),
                        "asynchronous connections between machines or controllers are not exported: the size of \
                         RoboTool's buffer and what it does when full are not pinned down (semantics.md §11, \
                         item 3)"
                            .into(),
                    ));
                    continue;
                }
                let find = |x: usize, e: &str| {
                    insts[x].elem.chans.iter().find(|ch| ch.kind == ChanKind::Event && ch.model == e).cloned()
                };
                let (Some(ca), Some(cb)) = (find(i, &ea), find(j, &eb)) else {
                    problems.push((file, c.text_range(), "a connection end is not an event of its component".into()));
                    continue;
                };
                if ca.values != cb.values {
                    problems.push((file, c.text_range(), "the connected events have different types".into()));
                    continue;
                }
                k += 1;
                let conn = format!("conn{k}__");
                private.push(Decl::Channel(vec![conn.clone()], ca.values.clone()));
                for (x, ch, d) in [(i, &ca, "out"), (j, &cb, "in")] {
                    let mut from = vec![name(format!("{}::{}", insts[x].elem.module, ch.csp)), name(d)];
                    let mut to = vec![name(conn.clone())];
                    let mut gens = Vec::new();
                    for (n, v) in ch.values.iter().enumerate() {
                        let var = format!("x{n}__");
                        from.push(name(var.clone()));
                        to.push(name(var.clone()));
                        gens.push((var, v.clone()));
                    }
                    conn_renames[x].push((dot(from), dot(to), gens));
                }
                internal[i].insert(conn.clone());
                internal[j].insert(conn.clone());
                hidden.push(conn);
            }
            _ => problems.push((file, c.text_range(), format!("the connection `{a}` → `{b}` has an unknown end"))),
        }
    }
    // Operation calls go to the platform by name.
    for (j, i) in insts.iter().enumerate() {
        for ch in i.elem.chans.iter().filter(|c| c.kind != ChanKind::Event) {
            match chans.iter().find(|x| x.csp == ch.csp) {
                Some(x) if x.values != ch.values => problems.push((
                    file,
                    util::name_range(node),
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
    let consts = union_consts(&insts);
    let mut params = vec!["id__".to_string()];
    params.extend(consts.iter().map(|c| c.global.clone()));
    let mut parts = Vec::new();
    for (j, i) in insts.iter().enumerate() {
        let mut p = rename(call(format!("{}::D__", i.elem.module), inst_args(&i.elem, false)), &renames[j]);
        for (from, to, gens) in &conn_renames[j] {
            p = Expr::Rename(Box::new(p), vec![(from.clone(), to.clone())], gens.clone());
        }
        parts.push((p, internal[j].clone()));
    }
    let comp = compose(parts, &["tock"]);
    let body = if hidden.is_empty() {
        comp
    } else {
        hide(comp, Expr::Events(hidden.iter().map(|h| name(h.clone())).collect()))
    };
    let mut exports = vec![Decl::Comment("Events and operation calls.".into())];
    for ch in &chans {
        exports.push(Decl::Channel(vec![ch.csp.clone()], ch.fields.clone()));
    }
    exports.push(Decl::Comment(format!(
        "D__: the {}'s semantics; O__: compressed (parameters: {}).",
        kind.describe(),
        params.join(", ")
    )));
    let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
    exports.push(Decl::Def("D__".into(), params.clone(), call("TimedPriority", vec![body])));
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
        },
        decls,
    ))
}

fn rename(p: Expr, pairs: &[(String, String)]) -> Expr {
    if pairs.is_empty() {
        return p;
    }
    Expr::Rename(Box::new(p), pairs.iter().map(|(a, b)| (name(a.clone()), name(b.clone()))).collect(), vec![])
}

/// A RoboSim controller or module: the components' register events are
/// renamed to the container's registers through the connections.
#[allow(clippy::too_many_arguments)]
fn robosim_container(
    ex: &mut Exporter<'_>,
    file: File,
    node: &SyntaxNode,
    module: String,
    path: Vec<String>,
    insts: Vec<Inst>,
    own: &str,
    events: &[(String, Option<Ty>)],
    connections: &[SyntaxNode],
    kind: ElemKind,
) -> Result2 {
    let mut problems: Vec<Problem> = Vec::new();
    let inst_of = |n: &str| insts.iter().position(|i| i.name == n);
    // Register renamings per instance: (instance ctor, container ctor, value types, input).
    let mut renames: Vec<Vec<RegRename>> = vec![Vec::new(); insts.len()];
    let mut mapped: HashMap<(usize, String), String> = HashMap::new();
    for c in connections {
        let ((a, ea), (b, eb), _) = ends(c);
        match (a == own, inst_of(&a), b == own, inst_of(&b)) {
            (true, _, _, Some(j)) | (_, Some(j), true, _) => {
                let (cev, iev) = if a == own { (&ea, &eb) } else { (&eb, &ea) };
                if !events.iter().any(|(n, _)| n == cev) {
                    problems.push((file, c.text_range(), format!("`{cev}` is not an event of `{own}`")));
                    continue;
                }
                mapped.insert((j, iev.clone()), cev.clone());
            }
            (_, Some(_), _, Some(_)) => problems.push((
                file,
                c.text_range(),
                "connections between RoboSim machines or controllers are not supported by the export yet".into(),
            )),
            _ => problems.push((file, c.text_range(), format!("the connection `{a}` → `{b}` has an unknown end"))),
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
                    problems.push((file, util::name_range(node), m));
                    continue;
                }
                if ctor != r.ctor {
                    renames[j].push((r.ctor.clone(), ctor.clone(), r.values.clone(), input));
                }
                let list = if input { &mut inputs } else { &mut outputs };
                if list.iter().any(|x| x.ctor == ctor) {
                    problems.push((
                        file,
                        util::name_range(node),
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
        let p = call(format!("{}::P__", i.elem.module), inst_args(&i.elem, true));
        let mut p = p;
        for (from, to, values, input) in &renames[j] {
            let chan = if *input { "registerRead" } else { "registerWrite" };
            let mut f = vec![name(chan), name(from.clone())];
            let mut t = vec![name(chan), name(to.clone())];
            let mut gens = Vec::new();
            if *input {
                f.push(name("b__"));
                t.push(name("b__"));
                gens.push(("b__".to_string(), name("Bool")));
            }
            for (k, v) in values.iter().enumerate() {
                let x = format!("x{k}__");
                f.push(name(x.clone()));
                t.push(name(x.clone()));
                gens.push((x, v.clone()));
            }
            p = Expr::Rename(Box::new(p), vec![(dot(f), dot(t))], gens);
        }
        parts.push((p, BTreeSet::new()));
    }
    let comp = compose(parts, &["tock", "terminate"]);
    let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
    let exports = vec![
        Decl::Comment(format!(
            "P__: the {} with `terminate` visible; D__: its semantics; O__: compressed\n(parameters: {}).",
            kind.describe(),
            params.join(", ")
        )),
        Decl::Def("P__".into(), params.clone(), call("TimedPriority", vec![comp])),
        Decl::Def(
            "D__".into(),
            params.clone(),
            call(
                "TimedPriority",
                vec![hide(
                    Expr::Exception(
                        Box::new(call("P__", args.clone())),
                        Box::new(Expr::Set(vec![name("terminate")])),
                        Box::new(Expr::Skip),
                    ),
                    Expr::Set(vec![name("terminate")]),
                )],
            ),
        ),
        Decl::Def("O__".into(), params.clone(), call("sbisim", vec![call("D__", args)])),
    ];
    let decls = vec![
        Decl::Comment(format!("RoboSim {} {}", kind.describe(), path.join("::"))),
        Decl::Module(module.clone(), vec![], exports),
        Decl::Blank,
    ];
    let period = declared_period(ex.db, ex.ws, file, node).unwrap_or(1);
    Ok((
        Elem { kind, robosim: true, module, path, consts, chans: vec![], inputs, outputs, period, required: vec![] },
        decls,
    ))
}
