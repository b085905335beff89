//! Rules that relate several elements: what controllers and platforms must
//! provide to their machines (RC:C3, RC:C4, RC:C8, RC:M2, RS-IO-09),
//! connections between levels (RC:Cn4, RC-CONN-01, RC-CONN-02, RC:Cn5–Cn9),
//! workspace-wide names (RC-PKG-01), vector and matrix sizes
//! (RC-TYPE-02…04), recursive operations (RC:O2), probabilities (RC:PJ3),
//! and RoboSim's statement deadlines and machine-level events (RS-STMT-02,
//! RS-IO-08).

use std::collections::{HashMap, HashSet};

use robosim_syntax::{FileKind, SyntaxKind::*, SyntaxNode, TextRange};
use rustc_hash::FxHashMap;
use salsa::plumbing::AsId;

use crate::checks::{Anchor, Place, Problem};
use crate::defs::{file_defs, DefData, DefId, DefKind, FileDefs, TypeRef, UseKind};
use crate::element::{element_defs, element_of, Element};
use crate::element_rules::{defs_at, name_place};
use crate::index::{index_for, resolve_item, ItemLoc};
use crate::resolve::{ctx_members, node_ctx, Ctx, Member};
use crate::types::{compatible, lower};
use crate::{parse, Db, File, Workspace};

/// The rules relating the containers of `defs` (one element of `file`) to
/// their parts, and the element's workspace-wide names.
pub(crate) fn element_more(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs, root: &SyntaxNode) -> Vec<Problem> {
    let mut out = Vec::new();
    if file.kind(db).is_assertions() {
        return out;
    }
    let rs = file.kind(db) == FileKind::RoboSim;
    unique_names(db, ws, file, defs, &mut out);
    for (id, d) in defs.iter() {
        match d.kind {
            DefKind::Controller => {
                controller_provides(db, ws, file, id, rs, &mut out);
                operation_requirements(db, ws, file, id, &mut out);
                operation_copies(db, ws, file, id, &mut out);
                connection_types(db, ws, file, id, &mut out);
                machine_directions(db, ws, file, id, &mut out);
                operation_callers(db, ws, file, id, rs, &mut out);
            }
            DefKind::Module => {
                platform_provides(db, ws, file, id, &mut out);
                connection_types(db, ws, file, id, &mut out);
                module_directions(db, ws, file, id, &mut out);
            }
            DefKind::StateMachine if rs => machine_level_events(db, ws, file, id, &mut out),
            DefKind::ProbabilisticJunction => probabilities(defs, root, id, &mut out),
            _ => {}
        }
    }
    recursion(db, ws, file, defs, &mut out);
    out
}

/// RC-PKG-01: fully qualified names are unique across the workspace (for
/// the top-level definitions of `defs`).
fn unique_names(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs, out: &mut Vec<Problem>) {
    let index = index_for(db, ws, file);
    for (id, d) in defs.children(None) {
        let mut path = defs.package.clone();
        path.push(d.name.clone());
        let Some(locs) = index.items.get(&path) else { continue };
        if locs.len() < 2 {
            continue;
        }
        // Report in every file but the first declaring one.
        let first = locs[0];
        for l in locs.iter().skip(1).filter(|l| l.file == file) {
            if l.def(db) != Some(id) {
                continue;
            }
            let Some(fdef) = first.def(db) else { continue };
            if first.file == file {
                // Same file: DUP-01 covers it.
                continue;
            }
            out.push(
                Problem::new(
                    "RC-PKG-01",
                    d.name_range,
                    format!("`{}` is declared more than once in the workspace", path.join("::")),
                )
                .with_related(name_place(db, first.file, fdef), "the other declaration"),
            );
        }
    }
}

/// RC-TYPE-02/03/04: vector and matrix sizes are literals or constants
/// (positions in the file). A file-level query, but one that runs again
/// only for files that write vector or matrix types.
#[salsa::tracked(returns(ref))]
pub(crate) fn size_checks(db: &dyn Db, ws: Workspace, file: File) -> Vec<Problem> {
    let mut out = Vec::new();
    if file.kind(db).is_assertions() {
        return out;
    }
    // Most files write no vector type: no walk of the whole file then.
    if !crate::element::element_list(db, file).iter().any(|e| e.public(db).sized) {
        return out;
    }
    let root = parse(db, file).syntax_node();
    let sized = crate::walk::file_nodes(db, file).nodes(&root, &[VECTOR_TYPE, MATRIX_TYPE], false);
    // The names in behaviour are resolved for the file only when it has
    // sizes to check (the per-element diagnostics do not need them).
    let refs: &[crate::resolve::ResolvedRef] =
        if sized.is_empty() { &[] } else { &crate::body::body_resolution(db, ws, file).refs };
    for t in sized {
        let code = if t.kind() == VECTOR_TYPE { "RC-TYPE-02" } else { "RC-TYPE-03" };
        for size in t.children().filter(|c| robosim_syntax::ast::is_expr_kind(c.kind())) {
            let inner = match size.kind() {
                PAREN_EXPR => {
                    size.children().find(|c| robosim_syntax::ast::is_expr_kind(c.kind())).unwrap_or(size.clone())
                }
                _ => size.clone(),
            };
            match inner.kind() {
                LITERAL if inner.first_token().is_some_and(|k| k.kind() == INT_NUMBER) => {}
                REF_EXPR => {
                    let name = crate::defs::name_text(&inner);
                    // The declaration the name resolves to in its own scope.
                    let target =
                        refs.iter().find(|r| inner.text_range().contains_range(r.range)).and_then(|r| r.target);
                    let decl = target.and_then(|t| crate::nav::declaration(db, t));
                    let owned = decl.map(|d| (d.def, file_defs(db, d.file).def(d.def).clone()));
                    let c = owned.as_ref().map(|(id, d)| (*id, d));
                    match c {
                        Some((_, d)) if d.kind == DefKind::Variable => out.push(
                            Problem::new(
                                code,
                                size.text_range(),
                                format!("a size must be an integer literal or a constant; `{name}` is a variable"),
                            )
                            .at(Anchor::File),
                        ),
                        Some((_, d)) => {
                            if let DefData::Typed { ty: Some(TypeRef::Named(p, _)), .. } = &d.data {
                                if p.last().is_some_and(|n| n != "nat") {
                                    out.push(
                                        Problem::new(
                                            "RC-TYPE-04",
                                            size.text_range(),
                                            format!("a size constant has type nat; `{name}` has type {}", p.join("::")),
                                        )
                                        .at(Anchor::File),
                                    );
                                }
                            }
                        }
                        None => {}
                    }
                }
                _ => out.push(
                    Problem::new(code, size.text_range(), "a size must be an integer literal or a constant")
                        .at(Anchor::File),
                ),
            }
        }
    }
    out
}

/// Members of the machines of a controller, with each machine's node.
fn machine_members(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    controller: DefId,
) -> Vec<(DefId, String, Ctx, Vec<Member>)> {
    defs_at(db, file, controller)
        .0
        .children(Some(controller))
        .filter(|(_, m)| matches!(m.kind, DefKind::StateMachine | DefKind::MachineRef))
        .filter_map(|(id, m)| {
            let ctx = node_ctx(db, ws, file, id)?;
            Some((id, m.name.clone(), ctx, ctx_members(db, ws, ctx).into_owned()))
        })
        .collect()
}

fn same_var(required: &Member, provided: &Member, db: &dyn Db, ws: Workspace, rf: File, pf: File) -> bool {
    if required.name != provided.name || !matches!(provided.kind, DefKind::Variable | DefKind::Constant) {
        return false;
    }
    match (&required.ty, &provided.ty) {
        (Some(a), Some(b)) => compatible(&lower(db, ws, rf, a), &lower(db, ws, pf, b)),
        _ => true,
    }
}

/// Whether two events carry the same type (both untyped, or both typed
/// with compatible types).
fn same_event_type(a: &Member, b: &Member, db: &dyn Db, ws: Workspace, af: File, bf: File) -> bool {
    match (&a.ty, &b.ty) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            let (tx, ty) =
                (lower(db, ws, member_file(a).unwrap_or(af), x), lower(db, ws, member_file(b).unwrap_or(bf), y));
            compatible(&tx, &ty) && compatible(&ty, &tx)
        }
        _ => false,
    }
}

fn member_file(m: &Member) -> Option<File> {
    match m.target {
        crate::resolve::Target::Def(f, _) => Some(f),
        crate::resolve::Target::Member(l, _) | crate::resolve::Target::Item(l) => Some(l.file),
    }
}

/// RC:C3, RC:C4 and RS-IO-09: a controller provides what its machines require.
fn controller_provides(db: &dyn Db, ws: Workspace, file: File, controller: DefId, rs: bool, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, controller).0;
    let c = defs.def(controller);
    let own = ctx_members(db, ws, Ctx::Local(file, controller));
    let defined: HashSet<String> = crate::resolve::defined_operations(db, ws, Ctx::Local(file, controller));
    for (mid, mname, mctx, members) in machine_members(db, ws, file, controller) {
        // The machine's own definition when an `sref` brings it from elsewhere.
        let remote = remote_name(db, mctx);
        let mut missing_vars = Vec::new();
        let mut missing_io_vars = Vec::new();
        let mut missing_ops = Vec::new();
        for r in members.iter().filter(|m| m.via == Some(UseKind::Requires)) {
            match r.kind {
                DefKind::Variable | DefKind::Constant => {
                    let rf = member_file(r).unwrap_or(file);
                    let ok = own.iter().any(|p| {
                        p.via != Some(UseKind::Provides) && same_var(r, p, db, ws, rf, member_file(p).unwrap_or(file))
                    });
                    if !ok {
                        if r.io.is_some() {
                            missing_io_vars.push(r.name.clone());
                        } else {
                            missing_vars.push(r.name.clone());
                        }
                    }
                }
                DefKind::OperationSig => {
                    let ok = defined.contains(&r.op_key())
                        || own.iter().any(|p| {
                            p.kind == DefKind::OperationSig
                                && p.op_key() == r.op_key()
                                && p.via == Some(UseKind::Requires)
                        });
                    if !ok && (r.io.is_none() || rs) {
                        missing_ops.push(r.op_key());
                    }
                }
                _ => {}
            }
        }
        let list = |v: &[String]| v.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
        let mrange = defs.def(mid).name_range;
        if !missing_vars.is_empty() {
            out.push(
                Problem::new(
                    "RC:C3",
                    c.name_range,
                    format!(
                        "controller `{}` lacks variable{} {} required by `{mname}`",
                        c.name,
                        plural(&missing_vars),
                        list(&missing_vars)
                    ),
                )
                .with_related(Place::here(file, mrange), format!("`{mname}` is here"))
                .with_related_opt(remote, "the machine's definition"),
            );
        }
        missing_io_vars.sort();
        missing_io_vars.dedup();
        if !missing_io_vars.is_empty() && rs {
            out.push(
                Problem::new(
                    "RS-IO-09",
                    c.name_range,
                    format!(
                        "controller `{}` lacks I/O variable{} {} of `{mname}`: declare or require {}",
                        c.name,
                        plural(&missing_io_vars),
                        list(&missing_io_vars),
                        if missing_io_vars.len() > 1 { "them" } else { "it" }
                    ),
                )
                .with_related(Place::here(file, mrange), format!("`{mname}` is here"))
                .with_related_opt(remote, "the machine's definition"),
            );
        }
        if !missing_ops.is_empty() {
            out.push(
                Problem::new(
                    "RC:C4",
                    c.name_range,
                    format!(
                        "controller `{}` lacks operation{} {} required by `{mname}`: define or require {}",
                        c.name,
                        plural(&missing_ops),
                        list(&missing_ops),
                        if missing_ops.len() > 1 { "them" } else { "it" }
                    ),
                )
                .with_related(Place::here(file, mrange), format!("`{mname}` is here"))
                .with_related_opt(remote, "the machine's definition"),
            );
        }
    }
}

fn plural<T>(v: &[T]) -> &'static str {
    if v.len() > 1 {
        "s"
    } else {
        ""
    }
}

/// RC:C8: a controller references each operation definition once.
fn operation_copies(db: &dyn Db, ws: Workspace, file: File, controller: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, controller).0;
    let mut seen: HashMap<(File, DefId), TextRange> = HashMap::new();
    for (id, d) in defs.children(Some(controller)) {
        let key = match d.kind {
            DefKind::Operation => Some((file, id)),
            DefKind::OperationRef => match &d.data {
                DefData::Reference { path, .. } => resolve_item(db, ws, file, path, |k| k == DefKind::Operation)
                    .first()
                    .and_then(|l| l.def(db).map(|def| (l.file, def))),
                _ => None,
            },
            _ => None,
        };
        let Some(key) = key else { continue };
        if let Some(first) = seen.get(&key) {
            out.push(
                Problem::new(
                    "RC:C8",
                    d.name_range,
                    format!("operation `{}` is already part of this controller", d.name),
                )
                .with_related(Place::here(file, *first), "the first copy"),
            );
        } else {
            seen.insert(key, d.name_range);
        }
    }
}

/// RC:M2: the platform provides what each controller requires.
fn platform_provides(db: &dyn Db, ws: Workspace, file: File, module: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, module).0;
    let m = defs.def(module);
    let Some((pid, _)) =
        defs.children(Some(module)).find(|(_, d)| matches!(d.kind, DefKind::Platform | DefKind::PlatformRef))
    else {
        return;
    };
    let Some(pctx) = node_ctx(db, ws, file, pid) else { return };
    let provided = ctx_members(db, ws, pctx);
    for (cid, c) in
        defs.children(Some(module)).filter(|(_, d)| matches!(d.kind, DefKind::Controller | DefKind::ControllerRef))
    {
        let Some(cctx) = node_ctx(db, ws, file, cid) else { continue };
        let required: Vec<Member> =
            ctx_members(db, ws, cctx).iter().filter(|r| r.via == Some(UseKind::Requires)).cloned().collect();
        let defined = crate::resolve::defined_operations(db, ws, cctx);
        let mut missing = Vec::new();
        for r in &required {
            let ok = match r.kind {
                DefKind::Variable | DefKind::Constant => provided.iter().any(|p| {
                    p.via != Some(UseKind::Requires)
                        && same_var(r, p, db, ws, member_file(r).unwrap_or(file), member_file(p).unwrap_or(file))
                }),
                DefKind::OperationSig => {
                    defined.contains(&r.op_key())
                        || provided.iter().any(|p| {
                            p.kind == DefKind::OperationSig
                                && p.op_key() == r.op_key()
                                && p.via != Some(UseKind::Requires)
                        })
                }
                _ => true,
            };
            if !ok {
                missing.push(if r.kind == DefKind::OperationSig { r.op_key() } else { r.name.clone() });
            }
        }
        if !missing.is_empty() {
            let list = missing.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
            out.push(
                Problem::new(
                    "RC:M2",
                    m.name_range,
                    format!("the robotic platform of `{}` does not provide {list}, required by `{}`", m.name, c.name),
                )
                .with_related(Place::here(file, c.name_range), format!("`{}` requires it", c.name))
                .with_related_opt(remote_name(db, cctx), "the controller's definition")
                .with_related_opt(remote_name(db, pctx), "the robotic platform's definition"),
            );
        }
    }
}

/// The name of a context's definition when it lives outside the current
/// definition (reached through a reference).
fn remote_name(db: &dyn Db, ctx: Ctx) -> Option<Place> {
    match ctx {
        Ctx::Item(_) => crate::resolve::ctx_def(db, ctx).map(|(f, d)| name_place(db, f, d)),
        Ctx::Local(..) => None,
    }
}

/// RC:Cn4, RC-CONN-01, RC-CONN-02: broadcast and event types of connections.
fn connection_types(db: &dyn Db, ws: Workspace, file: File, owner: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, owner).0;
    let o = defs.def(owner);
    let event = |node: &str, ev: &str| -> Option<(Member, DefKind)> {
        let (nid, kind) = if o.kind == DefKind::Controller && o.name == node {
            (owner, DefKind::Controller)
        } else {
            let (id, d) = defs.children(Some(owner)).find(|(_, d)| d.name == node && d.kind != DefKind::Connection)?;
            (id, d.kind)
        };
        let ctx = if nid == owner { Ctx::Local(file, owner) } else { node_ctx(db, ws, file, nid)? };
        let kind = match kind {
            DefKind::PlatformRef => DefKind::Platform,
            DefKind::ControllerRef => DefKind::Controller,
            DefKind::MachineRef => DefKind::StateMachine,
            k => k,
        };
        ctx_members(db, ws, ctx).iter().find(|m| m.kind == DefKind::Event && m.name == ev).map(|m| (m.clone(), kind))
    };
    for (_, c) in defs.children(Some(owner)) {
        let DefData::Connection(cd) = &c.data else { continue };
        let (Some(f), Some(ef), Some(t), Some(et)) = (&cd.from, &cd.efrom, &cd.to, &cd.eto) else { continue };
        let (Some((a, ak)), Some((b, bk))) = (event(&f.0, &ef.0), event(&t.0, &et.0)) else { continue };
        if a.broadcast != b.broadcast {
            let (range, name) = if a.broadcast { (et.1, &et.0) } else { (ef.1, &ef.0) };
            out.push(Problem::new(
                "RC:Cn4",
                range,
                format!("`{name}` is not a broadcast event: a broadcast event connects only to a broadcast event"),
            ));
        } else if a.broadcast && ak == bk {
            out.push(Problem::new(
                "RC-CONN-01",
                ef.1,
                "broadcast connections relay between levels, not between two nodes of the same kind",
            ));
        }
        match (&a.ty, &b.ty) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                let (tx, ty) = (
                    lower(db, ws, member_file(&a).unwrap_or(file), x),
                    lower(db, ws, member_file(&b).unwrap_or(file), y),
                );
                if !compatible(&tx, &ty) {
                    out.push(Problem::new(
                        "RC-CONN-02",
                        ef.1,
                        format!(
                            "events `{}` ({tx}) and `{}` ({ty}) have incompatible types{}",
                            ef.0,
                            et.0,
                            if tx.to_string() == ty.to_string() {
                                ": their types are different declarations of the same name"
                            } else {
                                ""
                            }
                        ),
                    ));
                }
            }
            _ => out.push(Problem::new(
                "RC-CONN-02",
                ef.1,
                format!("`{}` and `{}` must be both typed or both untyped", ef.0, et.0),
            )),
        }
    }
}

/// How a machine or operation uses events: inputs, outputs and the
/// operations it calls (position-free: an edit that moves text inside the
/// element leaves it equal).
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Usage {
    inputs: HashSet<String>,
    outputs: HashSet<String>,
    calls: HashSet<String>,
}

fn usage_of(db: &dyn Db, file: File, def: DefId) -> Usage {
    let Some(e) = element_of(db, file, def) else { return Usage::default() };
    match element_usages(db, e).get(&def) {
        Some(u) => u.clone(),
        None => walk_usage(&element_root(db, e), element_defs(db, e), def).0,
    }
}

/// The calls of `def` of `file`, each with the range of the called name,
/// and what the ranges are relative to.
fn call_sites_of(db: &dyn Db, file: File, def: DefId) -> (Vec<(String, TextRange)>, Anchor) {
    let Some(e) = element_of(db, file, def) else { return (Vec::new(), Anchor::File) };
    let sites = match element_call_sites(db, e).get(&def) {
        Some(s) => s.clone(),
        None => walk_usage(&element_root(db, e), element_defs(db, e), def).1,
    };
    (sites, Anchor::Element(e.as_id()))
}

fn element_root(db: &dyn Db, e: Element) -> SyntaxNode {
    SyntaxNode::new_root(e.green(db).0.clone())
}

/// How every machine and operation of `element` uses events and calls.
#[salsa::tracked(returns(ref))]
pub(crate) fn element_usages(db: &dyn Db, element: Element) -> FxHashMap<DefId, Usage> {
    let (root, defs) = (element_root(db, element), element_defs(db, element));
    defs.iter()
        .filter(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::Operation))
        .map(|(id, _)| (id, walk_usage(&root, defs, id).0))
        .collect()
}

/// The calls of every machine and operation of `element`, with the ranges
/// of the called names relative to the element's start.
#[salsa::tracked(returns(ref))]
pub(crate) fn element_call_sites(db: &dyn Db, element: Element) -> FxHashMap<DefId, Vec<(String, TextRange)>> {
    let (root, defs) = (element_root(db, element), element_defs(db, element));
    defs.iter()
        .filter(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::Operation))
        .map(|(id, _)| (id, walk_usage(&root, defs, id).1))
        .collect()
}

/// The usage and call sites of `def`, read from `root` (the tree `defs`'
/// positions are in).
fn walk_usage(root: &SyntaxNode, defs: &FileDefs, def: DefId) -> (Usage, Vec<(String, TextRange)>) {
    let d = defs.def(def);
    let mut sites = Vec::new();
    let Some(node) = find_node(root, d.range, d.syntax) else { return (Usage::default(), sites) };
    let mut u = Usage::default();
    for n in node.descendants() {
        match n.kind() {
            COMMUNICATION => {
                let Some(ev) = n.children().find(|c| c.kind() == NAME_REF) else { continue };
                let ev = crate::defs::name_text(&ev);
                let in_trigger = n.parent().is_some_and(|p| p.kind() == TRIGGER);
                let payload =
                    n.children().find(|c| matches!(c.kind(), COMM_INPUT | COMM_OUTPUT | COMM_SYNC)).map(|c| c.kind());
                match (in_trigger, payload) {
                    (_, Some(COMM_INPUT)) => u.inputs.insert(ev),
                    (true, None) => u.inputs.insert(ev),
                    (_, Some(_)) | (false, None) => u.outputs.insert(ev),
                };
            }
            CALL_STMT => {
                if let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) {
                    let name = q.text().to_string().trim().to_string();
                    sites.push((name.clone(), q.text_range()));
                    u.calls.insert(name);
                }
            }
            _ => {}
        }
    }
    (u, sites)
}

fn find_node(root: &SyntaxNode, range: TextRange, kind: robosim_syntax::SyntaxKind) -> Option<SyntaxNode> {
    let el = root.covering_element(range);
    let start = match el {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    start.ancestors().find(|n| n.text_range() == range && n.kind() == kind)
}

/// Usage of a machine including, transitively, the operations of the
/// controller it calls (with the operation through which each event is
/// used).
fn machine_usage(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    controller: DefId,
    machine: Ctx,
) -> (Usage, HashMap<String, (String, File, DefId)>) {
    let (mf, mdef) = match machine {
        Ctx::Local(f, id) => (f, id),
        Ctx::Item(l) => match l.def(db) {
            Some(d) => (l.file, d),
            None => return (Usage::default(), HashMap::new()),
        },
    };
    let mut total = usage_of(db, mf, mdef);
    let mut via: HashMap<String, (String, File, DefId)> = HashMap::new();
    let ops: HashMap<String, (File, DefId)> = defs_at(db, file, controller)
        .0
        .children(Some(controller))
        .filter_map(|(id, d)| match d.kind {
            DefKind::Operation => Some((d.name.clone(), (file, id))),
            DefKind::OperationRef => match &d.data {
                DefData::Reference { path, .. } => {
                    resolve_item(db, ws, file, path, |k| k == DefKind::Operation).first().and_then(|l: &ItemLoc| {
                        l.def(db).map(|def| (path.last().cloned().unwrap_or_default(), (l.file, def)))
                    })
                }
                _ => None,
            },
            _ => None,
        })
        .collect();
    let mut todo: Vec<String> = total.calls.iter().cloned().collect();
    let mut done: HashSet<String> = HashSet::new();
    while let Some(op) = todo.pop() {
        if !done.insert(op.clone()) {
            continue;
        }
        let Some((of, od)) = ops.get(&op) else { continue };
        let u = usage_of(db, *of, *od);
        for e in &u.inputs {
            if total.inputs.insert(e.clone()) {
                via.insert(format!("in:{e}"), (op.clone(), *of, *od));
            }
        }
        for e in &u.outputs {
            if total.outputs.insert(e.clone()) {
                via.insert(format!("out:{e}"), (op.clone(), *of, *od));
            }
        }
        todo.extend(u.calls.iter().cloned());
    }
    (total, via)
}

/// RC:Cn8 / RC:Cn9: one-way controller connections agree with how the
/// machine uses the event (RoboChart only; RS:C3 covers RoboSim).
fn machine_directions(db: &dyn Db, ws: Workspace, file: File, controller: DefId, out: &mut Vec<Problem>) {
    if file.kind(db) == FileKind::RoboSim {
        return;
    }
    let defs = defs_at(db, file, controller).0;
    let machines: HashMap<String, Ctx> = defs
        .children(Some(controller))
        .filter(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::MachineRef))
        .filter_map(|(id, d)| node_ctx(db, ws, file, id).map(|c| (d.name.clone(), c)))
        .collect();
    for (_, c) in defs.children(Some(controller)) {
        let DefData::Connection(cd) = &c.data else { continue };
        if cd.is_mult {
            continue;
        }
        if let (Some(t), Some(et)) = (&cd.to, &cd.eto) {
            if let Some(m) = machines.get(&t.0) {
                let (u, via) = machine_usage(db, ws, file, controller, *m);
                if u.outputs.contains(&et.0) {
                    let op = via.get(&format!("out:{}", et.0)).cloned();
                    let through = op.as_ref().map(|o| format!(" (through operation `{}`)", o.0)).unwrap_or_default();
                    let op_loc = op.map(|(_, f, d)| name_place(db, f, d));
                    out.push(Problem::new(
                        "RC:Cn8",
                        t.1,
                        format!("`{}` on `{}` ends a one-way connection, but `{}` outputs on `{}`{through}: make the connection bidirectional (`[ mult ]`) or reverse it", et.0, t.0, t.0, et.0),
                    ).with_related_opt(op_loc, "the operation that outputs on it"));
                }
            }
        }
        if let (Some(f), Some(ef)) = (&cd.from, &cd.efrom) {
            if let Some(m) = machines.get(&f.0) {
                let (u, via) = machine_usage(db, ws, file, controller, *m);
                if u.inputs.contains(&ef.0) {
                    let op = via.get(&format!("in:{}", ef.0)).cloned();
                    let through = op.as_ref().map(|o| format!(" (through operation `{}`)", o.0)).unwrap_or_default();
                    let op_loc = op.map(|(_, f, d)| name_place(db, f, d));
                    out.push(Problem::new(
                        "RC:Cn9",
                        f.1,
                        format!("`{}` on `{}` starts a one-way connection, but `{}` receives on `{}`{through}: make the connection bidirectional (`[ mult ]`) or reverse it", ef.0, f.0, f.0, ef.0),
                    ).with_related_opt(op_loc, "the operation that receives on it"));
                }
            }
        }
    }
}

/// RC:Cn5–Cn7: module connections to a controller agree in direction with
/// the controller's own connections on that event.
fn module_directions(db: &dyn Db, ws: Workspace, file: File, module: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, module).0;
    for (_, c) in defs.children(Some(module)) {
        let DefData::Connection(cd) = &c.data else { continue };
        for (node, ev, ends_here) in [(&cd.to, &cd.eto, true), (&cd.from, &cd.efrom, false)] {
            let (Some(node), Some(ev)) = (node, ev) else { continue };
            let Some((cid, _)) = defs
                .children(Some(module))
                .find(|(_, d)| d.name == node.0 && matches!(d.kind, DefKind::Controller | DefKind::ControllerRef))
            else {
                continue;
            };
            let Some(Ctx::Local(cf, cdef)) = node_ctx(db, ws, file, cid).map(|c| match c {
                Ctx::Item(l) => l.def(db).map(|d| Ctx::Local(l.file, d)).unwrap_or(c),
                c => c,
            }) else {
                continue;
            };
            let (cdefs, canchor) = defs_at(db, cf, cdef);
            let cname = cdefs.def(cdef).name.clone();
            for (_, inner) in cdefs.children(Some(cdef)) {
                let DefData::Connection(ic) = &inner.data else { continue };
                let starts =
                    ic.from.as_ref().is_some_and(|f| f.0 == cname) && ic.efrom.as_ref().is_some_and(|e| e.0 == ev.0);
                let ends = ic.to.as_ref().is_some_and(|f| f.0 == cname) && ic.eto.as_ref().is_some_and(|e| e.0 == ev.0);
                if !starts && !ends {
                    continue;
                }
                if cd.is_mult && !ic.is_mult {
                    out.push(
                        Problem::new(
                            "RC:Cn5",
                            node.1,
                            format!("`{}` on `{}` is bidirectional here but not inside the controller", ev.0, node.0),
                        )
                        .with_related(
                            Place { file: cf, anchor: canchor, range: inner.name_range },
                            format!("the connection inside `{cname}`"),
                        ),
                    );
                } else if !cd.is_mult && (ic.is_mult || (ends_here && !starts) || (!ends_here && !ends)) {
                    let code = if ends_here { "RC:Cn6" } else { "RC:Cn7" };
                    out.push(
                        Problem::new(
                            code,
                            node.1,
                            format!("the direction of `{}` inside `{}` contradicts this connection", ev.0, node.0),
                        )
                        .with_related(
                            Place { file: cf, anchor: canchor, range: inner.name_range },
                            format!("the connection inside `{cname}`"),
                        ),
                    );
                }
            }
        }
    }
}

/// RS-IO-08: machine-level `uses I` with events in RoboSim.
fn machine_level_events(db: &dyn Db, ws: Workspace, file: File, machine: DefId, out: &mut Vec<Problem>) {
    for u in defs_at(db, file, machine).0.uses_of(machine).filter(|u| u.kind == UseKind::Uses && u.io.is_none()) {
        let Some(loc) = resolve_item(db, ws, file, &u.path, |k| k == DefKind::Interface).first().copied() else {
            continue;
        };
        if loc.summary(db).members.iter().any(|m| m.kind == DefKind::Event) {
            let iname = u.path.join("::");
            out.push(Problem::new(
                "RS-IO-08",
                u.range,
                format!("events of `{iname}` are invisible here: a RoboSim machine sees events only through its input and output contexts; move `uses {iname}` into one"),
            ));
        }
    }
}

/// RC:PJ3: probabilities leaving a probabilistic junction add up to 1.
fn probabilities(defs: &FileDefs, root: &SyntaxNode, junction: DefId, out: &mut Vec<Problem>) {
    let j = defs.def(junction);
    let Some(container) = j.parent else { return };
    let mut num: i128 = 0;
    let mut den: i128 = 1;
    for (_, t) in defs.children(Some(container)) {
        let DefData::Transition(td) = &t.data else { continue };
        if td.source.as_ref().is_none_or(|s| s.0 != j.name) {
            continue;
        }
        let Some(p) = td.probability else { return };
        let Some(lit) = find_node(root, p, PROBABILITY).and_then(|n| n.children().find(|c| c.kind() == LITERAL)) else {
            return;
        };
        let text = lit.text().to_string();
        let (i, f) = text.trim().split_once('.').unwrap_or((text.trim(), ""));
        let Some(d) = 10i128.checked_pow(f.len() as u32) else { return };
        let Ok(v) = format!("{i}{f}").parse::<i128>() else { return };
        // num/den + v/d
        num = num * d + v * den;
        den *= d;
        if den > 1_000_000_000_000 {
            return;
        }
    }
    if num != den && num != 0 {
        out.push(Problem::new(
            "RC:PJ3",
            j.name_range,
            format!("the probabilities leaving `{}` add up to {}, not 1", j.name, num as f64 / den as f64),
        ));
    }
}

/// RC:O2: the operations of a controller do not call themselves, directly
/// or through each other. Reported once per cycle, on the call that closes
/// it (or, when that call is in another file, on the controller's `opref`).
fn recursion(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs, out: &mut Vec<Problem>) {
    for (cid, _) in defs.iter().filter(|(_, d)| d.kind == DefKind::Controller) {
        // name → (file, definition, the controller member that brings it in)
        let mut ops: HashMap<String, (File, DefId, TextRange)> = HashMap::new();
        for (id, d) in defs.children(Some(cid)) {
            match (&d.kind, &d.data) {
                (DefKind::Operation, _) => {
                    ops.insert(d.name.clone(), (file, id, d.name_range));
                }
                (DefKind::OperationRef, DefData::Reference { path, .. }) => {
                    if let Some(l) = resolve_item(db, ws, file, path, |k| k == DefKind::Operation).first() {
                        if let Some(def) = l.def(db) {
                            ops.insert(path.last().cloned().unwrap_or_default(), (l.file, def, d.name_range));
                        }
                    }
                }
                _ => {}
            }
        }
        // The ranges of an operation's calls are relative to its element.
        let sites: HashMap<String, (Vec<(String, TextRange)>, Anchor)> = ops
            .iter()
            .map(|(n, (f, d, _))| {
                let (sites, anchor) = call_sites_of(db, *f, *d);
                (n.clone(), (sites.into_iter().filter(|(c, _)| ops.contains_key(c)).collect(), anchor))
            })
            .collect();
        let mut reported: HashSet<Vec<String>> = HashSet::new();
        let mut names: Vec<&String> = ops.keys().collect();
        names.sort();
        for start in names {
            // Depth-first search for a path start → … → start.
            let mut stack: Vec<(String, Vec<String>)> = vec![(start.clone(), vec![start.clone()])];
            let mut seen = HashSet::new();
            while let Some((cur, path)) = stack.pop() {
                let (calls, anchor) = match sites.get(&cur) {
                    Some((calls, anchor)) => (&calls[..], *anchor),
                    None => (&[][..], Anchor::File),
                };
                for (callee, range) in calls {
                    if callee == start {
                        let mut key = path.clone();
                        key.sort();
                        if !reported.insert(key) {
                            continue;
                        }
                        let cycle = path.iter().chain(std::iter::once(start)).cloned().collect::<Vec<_>>().join(" → ");
                        let (of, _, member) = ops[&cur];
                        let msg = format!("operation `{start}` calls itself: {cycle}");
                        if of == file {
                            out.push(Problem::new("RC:O2", *range, msg).at(anchor));
                        } else {
                            out.push(Problem::new("RC:O2", member, msg).with_related(
                                Place { file: of, anchor, range: *range },
                                "the call that closes the cycle",
                            ));
                        }
                    } else if seen.insert(callee.clone()) {
                        let mut p = path.clone();
                        p.push(callee.clone());
                        stack.push((callee.clone(), p));
                    }
                }
            }
        }
    }
}

/// RC:STM8–STM10 and RS-IO-05: an operation defined in a controller gets
/// what it requires from each machine or operation that calls it.
fn operation_callers(db: &dyn Db, ws: Workspace, file: File, controller: DefId, rs: bool, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, controller).0;
    let c = defs.def(controller);
    // The controller's operations: name → (file, definition).
    let mut ops: Vec<(String, File, DefId)> = Vec::new();
    for (id, d) in defs.children(Some(controller)) {
        match (&d.kind, &d.data) {
            (DefKind::Operation, _) => ops.push((d.name.clone(), file, id)),
            (DefKind::OperationRef, DefData::Reference { path, .. }) => {
                if let Some(l) = resolve_item(db, ws, file, path, |k| k == DefKind::Operation).first() {
                    if let Some(def) = l.def(db) {
                        ops.push((path.last().cloned().unwrap_or_default(), l.file, def));
                    }
                }
            }
            _ => {}
        }
    }
    if ops.is_empty() {
        return;
    }
    // Callers: the machines, and the operations themselves.
    let mut callers: Vec<(String, File, DefId)> = Vec::new();
    for (id, d) in
        defs.children(Some(controller)).filter(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::MachineRef))
    {
        match node_ctx(db, ws, file, id) {
            Some(Ctx::Local(f, def)) => callers.push((d.name.clone(), f, def)),
            Some(Ctx::Item(l)) => {
                if let Some(def) = l.def(db) {
                    callers.push((d.name.clone(), l.file, def));
                }
            }
            None => {}
        }
    }
    let machines = callers.len();
    callers.extend(ops.iter().cloned());
    // RoboSim operations work on their machine's copies of the variables
    // (RT-23), so a variable an operation's callee needs may come from the
    // machines that reach the calling operation instead of from the
    // operation itself (RoboTool's generated operations rely on this).
    let reach: Vec<HashSet<String>> = callers[..machines]
        .iter()
        .map(|(_, f, d)| {
            let mut seen: HashSet<String> = HashSet::new();
            let mut stack: Vec<String> = usage_of(db, *f, *d).calls.iter().cloned().collect();
            while let Some(n) = stack.pop() {
                if seen.insert(n.clone()) {
                    for (_, of, od) in ops.iter().filter(|(o, _, _)| *o == n) {
                        stack.extend(usage_of(db, *of, *od).calls.iter().cloned());
                    }
                }
            }
            seen
        })
        .collect();
    for (k, (xname, xf, xdef)) in callers.iter().enumerate() {
        let calls = usage_of(db, *xf, *xdef).calls;
        let xmembers = ctx_members(db, ws, Ctx::Local(*xf, *xdef));
        let xdefs = defs_at(db, *xf, *xdef).0;
        let xclocks: HashSet<String> = xdefs
            .children(Some(*xdef))
            .filter(|(_, d)| d.kind == DefKind::Clock)
            .map(|(_, d)| d.name.clone())
            .chain(xmembers.iter().filter(|m| m.kind == DefKind::Clock).map(|m| m.name.clone()))
            .collect();
        for (oname, of, odef) in &ops {
            if !calls.contains(oname) || (of == xf && odef == xdef) {
                continue;
            }
            let omembers = ctx_members(db, ws, Ctx::Local(*of, *odef));
            let mut missing: Vec<(&'static str, String)> = Vec::new();
            for m in omembers.iter() {
                let has = |want: &dyn Fn(&Member) -> bool| xmembers.iter().any(want);
                match (m.kind, m.via, m.io) {
                    (DefKind::Variable | DefKind::Constant, Some(UseKind::Requires), None) => {
                        // Same name, same var/const, compatible type (catalogue RC:STM8).
                        let same_kind = m.kind;
                        let mf = member_file(m).unwrap_or(*of);
                        let provides = |members: &[Member], xf: File| {
                            members.iter().any(|x: &Member| {
                                x.kind == same_kind
                                    && x.io.is_none()
                                    && same_var(m, x, db, ws, mf, member_file(x).unwrap_or(xf))
                            })
                        };
                        let from_machines = rs
                            && k >= machines
                            && callers[..machines]
                                .iter()
                                .zip(&reach)
                                .filter(|(_, r)| r.contains(xname))
                                .all(|((_, mf, md), _)| provides(&ctx_members(db, ws, Ctx::Local(*mf, *md)), *mf));
                        if !provides(&xmembers, *xf) && !from_machines {
                            missing.push(("RC:STM8", format!("variable `{}`", m.name)));
                        }
                    }
                    (DefKind::Event, _, None)
                        if !rs
                            && !has(&|x: &Member| {
                                x.kind == DefKind::Event && x.name == m.name && same_event_type(m, x, db, ws, *of, *xf)
                            }) =>
                    {
                        missing.push(("RC:STM9", format!("event `{}`", m.name)));
                    }
                    (DefKind::Clock, Some(UseKind::Requires), _) if !xclocks.contains(&m.name) => {
                        missing.push(("RC:STM10", format!("clock `{}`", m.name)));
                    }
                    (DefKind::Event | DefKind::Variable | DefKind::OperationSig, _, Some(io))
                        if rs && !has(&|x: &Member| x.kind == m.kind && x.name == m.name && x.io == Some(io)) =>
                    {
                        let what = match (m.kind, io) {
                            (DefKind::Event, crate::defs::Io::Input) => "input event",
                            (DefKind::Event, _) => "output event",
                            (DefKind::Variable, crate::defs::Io::Input) => "input variable",
                            (DefKind::Variable, _) => "output variable",
                            _ => "output operation",
                        };
                        missing.push(("RS-IO-05", format!("{what} `{}`", m.name)));
                    }
                    _ => {}
                }
            }
            for (code, what) in missing {
                out.push(
                    Problem::new(
                        code,
                        c.name_range,
                        format!(
                            "operation `{oname}` uses {what}, which its caller `{xname}` does not declare{}",
                            if matches!(code, "RC:STM8" | "RC:STM9") { " with a compatible type" } else { "" }
                        ),
                    )
                    .with_related(name_place(db, *xf, *xdef), format!("`{xname}` calls `{oname}`"))
                    .with_related(name_place(db, *of, *odef), format!("`{oname}` is defined here")),
                );
            }
        }
    }
}

/// RC:C4-weak: every operation an operation of the controller requires is
/// defined or required by the controller.
fn operation_requirements(db: &dyn Db, ws: Workspace, file: File, controller: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, controller).0;
    let c = defs.def(controller);
    let defined = crate::resolve::defined_operations(db, ws, Ctx::Local(file, controller));
    let own = ctx_members(db, ws, Ctx::Local(file, controller));
    for (id, d) in defs.children(Some(controller)) {
        let ctx = match d.kind {
            DefKind::Operation => Ctx::Local(file, id),
            DefKind::OperationRef => match node_ctx(db, ws, file, id) {
                Some(ctx) => ctx,
                None => continue,
            },
            _ => continue,
        };
        let missing: Vec<String> = ctx_members(db, ws, ctx)
            .iter()
            .filter(|m| m.kind == DefKind::OperationSig && m.via == Some(UseKind::Requires) && m.io.is_none())
            .filter(|m| {
                !defined.contains(&m.op_key())
                    && !own.iter().any(|p| {
                        p.kind == DefKind::OperationSig && p.via == Some(UseKind::Requires) && p.op_key() == m.op_key()
                    })
            })
            .map(|m| m.op_key())
            .collect();
        if !missing.is_empty() {
            let list = missing.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
            out.push(
                Problem::new(
                    "RC:C4-weak",
                    d.name_range,
                    format!(
                        "operation `{}` requires {list}, which controller `{}` neither defines nor requires",
                        d.name, c.name
                    ),
                )
                .with_related_opt(remote_name(db, ctx), "the operation's definition"),
            );
        }
    }
}
