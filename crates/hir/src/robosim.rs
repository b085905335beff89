//! The paper's rules on inputs and outputs of RoboSim machines, controllers
//! and modules (RS:M3, RS:C3, RS:C4, RS:SM4, RS:SM5).

use robosim_syntax::{FileKind, TextRange};

use crate::checks::{Place, Problem};
use crate::defs::{DefData, DefId, DefKind, FileDefs, Io, UseKind};
use crate::element_rules::{context_places, defs_at, name_place};
use crate::index::resolve_item;
use crate::resolve::{ctx_members, node_ctx, Ctx, Member};
use crate::{Db, File, Workspace};

/// Outputs of a machine: required variables written, operations called
/// and events emitted through its output context.
#[derive(Debug, Default)]
struct Outputs {
    vars: Vec<String>,
    ops: Vec<String>,
}

fn outputs(members: &[Member]) -> Outputs {
    let mut o = Outputs::default();
    for m in members.iter().filter(|m| m.io == Some(Io::Output)) {
        match m.kind {
            DefKind::Variable if m.via == Some(UseKind::Requires) => o.vars.push(m.name.clone()),
            DefKind::OperationSig => o.ops.push(m.name.clone()),
            _ => {}
        }
    }
    o
}

/// The machines of a controller (inline or by `sref`): (node def, name, members).
fn machines(db: &dyn Db, ws: Workspace, file: File, controller: DefId) -> Vec<(DefId, String, Option<Ctx>)> {
    defs_at(db, file, controller)
        .0
        .children(Some(controller))
        .filter(|(_, m)| matches!(m.kind, DefKind::StateMachine | DefKind::MachineRef))
        .map(|(id, m)| (id, m.name.clone(), node_ctx(db, ws, file, id)))
        .collect()
}

/// RS rules of the definitions `defs` (one element's) of `file`.
pub(crate) fn element_robosim(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs) -> Vec<Problem> {
    let mut out = Vec::new();
    if file.kind(db) != FileKind::RoboSim {
        return out;
    }
    for (id, d) in defs.iter() {
        match d.kind {
            DefKind::Controller => {
                let ms = machines(db, ws, file, id);
                controller_io(db, ws, file, id, &ms, &mut out);
                controller_outputs(db, ws, file, defs, &ms, &mut out);
                required_operations(db, ws, file, id, &ms, &mut out);
            }
            DefKind::Module => module_outputs(db, ws, file, id, &mut out),
            DefKind::StateMachine => required_variables(db, ws, file, id, &mut out),
            _ => {}
        }
    }
    out
}

/// RS:C3: connections with a machine respect its inputs and outputs.
fn controller_io(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    controller: DefId,
    ms: &[(DefId, String, Option<Ctx>)],
    out: &mut Vec<Problem>,
) {
    let defs = defs_at(db, file, controller).0;
    for (_, c) in defs.children(Some(controller)) {
        let DefData::Connection(cd) = &c.data else { continue };
        for (end, event, as_target) in [(&cd.to, &cd.eto, true), (&cd.from, &cd.efrom, false)] {
            let (Some((node, _)), Some((ev, erange))) = (end, event) else { continue };
            let Some((_, _, Some(ctx))) = ms.iter().find(|(_, n, _)| n == node) else { continue };
            let members = ctx_members(db, ws, *ctx);
            let is = |io: Io| members.iter().any(|m| m.kind == DefKind::Event && &m.name == ev && m.io == Some(io));
            let (need_in, need_out) = if cd.is_mult { (true, true) } else { (as_target, !as_target) };
            if need_in && !is(Io::Input) && (is(Io::Output) || members.iter().any(|m| &m.name == ev)) {
                out.push(
                    Problem::new(
                        "RS:C3",
                        *erange,
                        format!("`{ev}` is not an input of `{node}`: a connection into a machine needs an event of its input context"),
                    )
                    .with_related_opt(context_of(db, *ctx, Io::Input), format!("the input context of `{node}`")),
                );
            } else if need_out && !is(Io::Output) && (is(Io::Input) || members.iter().any(|m| &m.name == ev)) {
                out.push(
                    Problem::new(
                        "RS:C3",
                        *erange,
                        format!("`{ev}` is not an output of `{node}`: a connection out of a machine needs an event of its output context"),
                    )
                    .with_related_opt(context_of(db, *ctx, Io::Output), format!("the output context of `{node}`")),
                );
            }
        }
    }
}

/// RS:C4: the outputs of a controller's machines are disjoint.
fn controller_outputs(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    defs: &FileDefs,
    ms: &[(DefId, String, Option<Ctx>)],
    out: &mut Vec<Problem>,
) {
    let outs: Vec<(DefId, &String, Outputs, Ctx)> =
        ms.iter().filter_map(|(id, n, c)| c.map(|c| (*id, n, outputs(&ctx_members(db, ws, c)), c))).collect();
    for (i, (id, name, o, ctx)) in outs.iter().enumerate() {
        for (other_id, other, p, other_ctx) in &outs[..i] {
            let shared_vars: Vec<&String> = o.vars.iter().filter(|v| p.vars.contains(v)).collect();
            let shared_ops: Vec<&String> = o.ops.iter().filter(|v| p.ops.contains(v)).collect();
            if shared_vars.is_empty() && shared_ops.is_empty() {
                continue;
            }
            let what = describe_shared(&shared_vars, &shared_ops);
            out.push(
                Problem::new(
                    "RS:C4",
                    defs.def(*id).name_range,
                    format!("machines `{other}` and `{name}` both output {what}: outputs of a controller's machines must be disjoint"),
                )
                .with_related(Place::here(file, defs.def(*other_id).name_range), format!("`{other}` also outputs it"))
                .with_related_opt(context_of(db, *ctx, Io::Output), format!("the output context of `{name}`"))
                .with_related_opt(context_of(db, *other_ctx, Io::Output), format!("the output context of `{other}`")),
            );
        }
    }
}

fn describe_shared(vars: &[&String], ops: &[&String]) -> String {
    let mut parts = Vec::new();
    if !vars.is_empty() {
        parts.push(format!(
            "variable{} {}",
            if vars.len() > 1 { "s" } else { "" },
            vars.iter().map(|v| format!("`{v}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    if !ops.is_empty() {
        parts.push(format!(
            "operation{} {}",
            if ops.len() > 1 { "s" } else { "" },
            ops.iter().map(|v| format!("`{v}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    parts.join(" and ")
}

/// RS:M3: the outputs of a module's controllers are disjoint.
fn module_outputs(db: &dyn Db, ws: Workspace, file: File, module: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, module).0;
    // Per controller: its outputs, and where each one is declared (the
    // machine's output context for variables; the controller for operations).
    type Loc = Option<Place>;
    type Sources = Vec<(String, Loc)>;
    let mut ctrls: Vec<(DefId, String, Outputs, Sources, Loc)> = Vec::new();
    for (cid, c) in defs.children(Some(module)) {
        if !matches!(c.kind, DefKind::Controller | DefKind::ControllerRef) {
            continue;
        }
        let Some(ctx) = node_ctx(db, ws, file, cid) else { continue };
        // Outputs of its machines, and the operations it requires itself
        // without defining them (platform operations it drives).
        let mut o = Outputs::default();
        let mut sources: Sources = Vec::new();
        let members = ctx_members(db, ws, ctx);
        let defined: Vec<String> = controller_operation_names(db, ws, ctx);
        for m in members.iter() {
            if m.kind == DefKind::OperationSig && m.via == Some(UseKind::Requires) && !defined.contains(&m.op_key()) {
                o.ops.push(m.name.clone());
            }
        }
        for mctx in controller_machine_ctxs(db, ws, ctx) {
            let mo = outputs(&ctx_members(db, ws, mctx));
            for v in &mo.vars {
                sources.push((v.clone(), context_of(db, mctx, Io::Output)));
            }
            o.vars.extend(mo.vars);
        }
        o.vars.sort();
        o.vars.dedup();
        let def_loc = crate::resolve::ctx_def(db, ctx).map(|(f, d)| name_place(db, f, d));
        ctrls.push((cid, c.name.clone(), o, sources, def_loc));
    }
    for (i, (id, name, o, src, loc)) in ctrls.iter().enumerate() {
        for (other_id, other, p, other_src, other_loc) in &ctrls[..i] {
            let shared_vars: Vec<&String> = o.vars.iter().filter(|v| p.vars.contains(v)).collect();
            let shared_ops: Vec<&String> = o.ops.iter().filter(|v| p.ops.contains(v)).collect();
            if shared_vars.is_empty() && shared_ops.is_empty() {
                continue;
            }
            let what = describe_shared(&shared_vars, &shared_ops);
            let mut problem = Problem::new(
                "RS:M3",
                defs.def(*id).name_range,
                format!("controllers `{other}` and `{name}` both drive {what}: outputs of a module's controllers must be disjoint"),
            )
            .with_related(Place::here(file, defs.def(*other_id).name_range), format!("`{other}` also drives it"));
            // Where the shared outputs are declared, on both sides.
            for v in &shared_vars {
                for (who, sources) in [(name, src), (other, other_src)] {
                    if let Some((_, Some(at))) = sources.iter().find(|(n, _)| n == *v) {
                        problem = problem.with_related(*at, format!("`{v}` is an output of a machine of `{who}` here"));
                    }
                }
            }
            if !shared_ops.is_empty() {
                problem = problem
                    .with_related_opt(*loc, format!("`{name}` requires the operation"))
                    .with_related_opt(*other_loc, format!("`{other}` requires the operation"));
            }
            out.push(problem);
        }
    }
}

/// The operation definitions (`operation`, `opref`) of a controller.
fn controller_operation_names(db: &dyn Db, ws: Workspace, ctx: Ctx) -> Vec<String> {
    crate::resolve::defined_operations(db, ws, ctx).into_iter().collect()
}

/// The contexts of the machines of a controller context.
fn controller_machine_ctxs(db: &dyn Db, ws: Workspace, ctx: Ctx) -> Vec<Ctx> {
    match ctx {
        Ctx::Local(file, id) => machines(db, ws, file, id).into_iter().filter_map(|(_, _, c)| c).collect(),
        Ctx::Item(loc) => {
            let Some(def) = loc.def(db) else { return Vec::new() };
            machines(db, ws, loc.file, def).into_iter().filter_map(|(_, _, c)| c).collect()
        }
    }
}

/// RS:SM4: variables a machine requires are inputs or outputs.
fn required_variables(db: &dyn Db, ws: Workspace, file: File, machine: DefId, out: &mut Vec<Problem>) {
    let defs = defs_at(db, file, machine).0;
    let io_vars: Vec<String> = ctx_members(db, ws, Ctx::Local(file, machine))
        .iter()
        .filter(|m| m.io.is_some() && m.kind == DefKind::Variable && m.via == Some(UseKind::Requires))
        .map(|m| m.name.clone())
        .collect();
    for u in defs.uses_of(machine).filter(|u| u.kind == UseKind::Requires && u.io.is_none()) {
        let Some(loc) = resolve_item(db, ws, file, &u.path, |k| k == DefKind::Interface).first().copied() else {
            continue;
        };
        let vars: Vec<&String> = loc
            .summary(db)
            .members
            .iter()
            .filter(|m| m.kind == DefKind::Variable && !io_vars.contains(&m.name))
            .map(|m| &m.name)
            .collect();
        if !vars.is_empty() {
            let list = vars.iter().map(|v| format!("`{v}`")).collect::<Vec<_>>().join(", ");
            let iname = u.path.join("::");
            out.push(Problem::new(
                "RS:SM4",
                u.range,
                format!(
                    "required variable{} {list} of `{iname}` must be an input or an output: require `{iname}` in the input or output context",
                    if vars.len() > 1 { "s" } else { "" }
                ),
            ));
        }
    }
}

/// RS:SM5: a machine-level required operation must be defined by the
/// controller; platform operations belong in the output context.
fn required_operations(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    controller: DefId,
    ms: &[(DefId, String, Option<Ctx>)],
    out: &mut Vec<Problem>,
) {
    let defs = defs_at(db, file, controller).0;
    let defined = controller_operation_names(db, ws, Ctx::Local(file, controller));
    for (mid, mname, ctx) in ms {
        let Some(ctx) = ctx else { continue };
        // Machine-level (not I/O) required operations.
        let Some((mfile, mdef)) = crate::resolve::ctx_def(db, *ctx) else { continue };
        let mut manchor = crate::checks::Anchor::File;
        let uses: Vec<(Vec<String>, TextRange)> = crate::element_rules::use_places(db, mfile, mdef)
            .iter()
            .filter(|(u, _)| u.kind == UseKind::Requires && u.io.is_none())
            .map(|(u, a)| {
                manchor = *a;
                (u.path.clone(), u.range)
            })
            .collect();
        for (path, range) in uses {
            let Some(loc) = resolve_item(db, ws, mfile, &path, |k| k == DefKind::Interface).first().copied() else {
                continue;
            };
            let missing: Vec<&String> = loc
                .summary(db)
                .members
                .iter()
                .filter(|m| {
                    m.kind == DefKind::OperationSig
                        && !defined.contains(&crate::resolve::op_key(
                            &m.name,
                            &m.params.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>(),
                        ))
                })
                .map(|m| &m.name)
                .collect();
            if missing.is_empty() {
                continue;
            }
            let list = missing.iter().map(|v| format!("`{v}`")).collect::<Vec<_>>().join(", ");
            let iname = path.join("::");
            let msg = format!(
                "operation{} {list} of `{iname}` {} not defined by controller `{}`: call platform operations as outputs (`requires {iname}` in the output context of `{mname}`, and `$op(…)`)",
                if missing.len() > 1 { "s" } else { "" },
                if missing.len() > 1 { "are" } else { "is" },
                defs.def(controller).name
            );
            let p = if mfile == file && matches!(ctx, Ctx::Local(..)) {
                Problem::new("RS:SM5", range, msg)
            } else {
                Problem::new("RS:SM5", defs.def(*mid).name_range, msg).with_related(
                    Place { file: mfile, anchor: manchor, range },
                    format!("`{mname}` requires `{iname}` here"),
                )
            };
            out.push(p);
        }
    }
}

/// The `input context`/`output context` keyword of a machine.
fn context_of(db: &dyn Db, ctx: Ctx, io: Io) -> Option<Place> {
    let (f, d) = crate::resolve::ctx_def(db, ctx)?;
    let (input, output) = context_places(db, f, d);
    match io {
        Io::Input => input,
        Io::Output => output,
    }
}
