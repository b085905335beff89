//! RT-11: a RoboSim operation checked on its own, as RoboTool's
//! `OP_…::O__(id__, params)`: what the native checker refuses is refused
//! with its reasons, the rest translated by [`Gen`] in its `sim_op` mode.

use super::*;

/// RT-11: the CSPm module of the RoboSim operation `op` of `file`
/// (declared in `outer`) checked on its own, as RoboTool's
/// `OP_…::O__(id__, params)` (the reference's
/// `csp-gen/sim/defs/pkg223_aggregation_sim_clone_*.csp`), made on first
/// use; what the native checker refuses is refused with its reason.
pub(crate) fn sim_operation<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    op: &'a m::Behaviour,
    outer: Vec<String>,
) -> Result<Rc<OperationOut>, String> {
    let key = (file, op.range);
    if let Some(r) = ex.sim_operations.get(&key) {
        return r.clone();
    }
    if ex.profile == Profile::Paper2019 {
        // Rules 1–13 give operations no process of their own.
        return Err(format!(
            "the RoboSim operation `{}` on its own is RoboTool 3's process `OP_…::O__` (RT-11): the paper2019 \
             profile has none",
            op.name
        ));
    }
    let mut path = outer.clone();
    path.push(op.name.clone());
    let r = match sim_operation_supported(ex, op) {
        Err((range, why)) => {
            ex.warn(file, range, format!("operation {} is not exported on its own: {why}", path.join("::")));
            let at = ex.loc(file, range);
            ex.emit(
                file,
                vec![
                    Decl::Comment(format!(
                        "NOT EXPORTED: operation {} on its own
  {at}: {why}",
                        path.join("::")
                    )),
                    Decl::Blank,
                ],
            );
            Err(why)
        }
        Ok(()) => generate(ex, file, op, &outer, path, "on its own"),
    };
    let r = r.map_err(|why| format!("the RoboSim operation `{}` is not exported on its own: {why}", op.name));
    ex.sim_operations.insert(key, r.clone());
    r
}

/// The module of the RoboSim operation `op` (path `path`, declared in
/// `outer`) as [`Gen`] translates it in its `sim_op` mode, emitted; `how`
/// (`on its own`, `inside the machines that call it`) for messages.
fn generate<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    op: &'a m::Behaviour,
    outer: &[String],
    path: Vec<String>,
    how: &str,
) -> Result<Rc<OperationOut>, String> {
    let module = if outer.len() <= ex.package(file).len() {
        ex.unique_module(format!("OP_{}", util::qualified(&path)))
    } else {
        operation_module(ex, file, outer, &op.name)
    };
    let mut g = Gen::new(ex, file, Some(op), path.clone(), op.name_range, false);
    g.is_operation = true;
    g.sim_op = true;
    let mut params = Vec::new();
    let mut problems = Vec::new();
    for p in &op.params {
        match g.ex.ty_ref(file, p.ty.as_ref()) {
            Ok(t) => {
                let local = g.local(&p.name);
                g.names.insert(p.name.clone(), Nm::Param(local.clone(), t.clone()));
                g.op_params.push(local);
                params.push(t);
            }
            Err(m) => problems.push((file, p.range, format!("parameter `{}`: {m}", p.name))),
        }
    }
    let result = if problems.is_empty() { g.run_operation(module.clone(), path.clone()) } else { Err(problems) };
    match result {
        Ok((decls, out)) => {
            ex.emit(file, decls);
            Ok(Rc::new(OperationOut { module, params, ..out }))
        }
        Err(problems) => {
            let op = format!("operation {}", path.join("::"));
            let (what, warning) = (format!("{op} {how}"), format!("{op} is not exported {how}"));
            Err(refuse_operation(ex, file, &what, &warning, &problems))
        }
    }
}

/// RT-19: the CSPm module of the RoboSim operation `op` of `file`
/// (declared in `outer`) that a machine runs when its controller defines
/// it, as the native checker inlines it: the process of [`sim_operation`]
/// (the operation's own variables and clocks in its memory), its `exec`
/// and calls renamed to the machine's by the caller (`CALL__op`), the
/// variables it requires read and written in the caller's memory (its
/// copies, RT-23). What the export cannot run inside a machine yet is
/// refused with the reason.
pub(crate) fn inlined_sim_operation<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    op: &'a m::Behaviour,
    outer: Vec<String>,
) -> Result<Rc<OperationOut>, String> {
    let refused = |why: String| format!("the RoboSim operation `{}` is not exported inside a machine: {why}", op.name);
    if ex.profile == Profile::Paper2019 {
        return Err(refused(
            "the paper2019 profile gives operations no process of their own (Rules 1–13), so calls of them are \
             not exported"
                .into(),
        ));
    }
    inline_supported(ex, op).map_err(|(_, why)| refused(why))?;
    if sim_operation_supported(ex, op).is_ok() {
        // The same process as on its own.
        return sim_operation(ex, file, op, outer);
    }
    // It requires variables: a module of its own, as on its own it is refused.
    let key = (file, op.range);
    if let Some(r) = ex.inlined_sim_operations.get(&key) {
        return r.clone();
    }
    let mut path = outer.clone();
    path.push(op.name.clone());
    let r = generate(ex, file, op, &outer, path, "inside the machines that call it").map_err(refused);
    ex.inlined_sim_operations.insert(key, r.clone());
    r
}

/// What the export cannot run yet of a RoboSim operation inside a machine
/// that calls it, which the native checker inlines: a required clock
/// (the caller's), inputs of the platform (the caller's registers), an
/// `exec` inside a composite state or an `exec`-triggered transition (the
/// process of [`sim_operation`] has no cycle of its own to take them in).
fn inline_supported(ex: &Exporter<'_>, b: &m::Behaviour) -> Result<(), (TextRange, String)> {
    let interface = |u: &m::InterfaceUse| match u.target.and_then(|loc| m::item(ex.db, ex.ws, loc)) {
        Some(m::Item::Interface(i)) => Some(&i.decls),
        _ => None,
    };
    let has_vars = |d: &m::Decls| d.decls.iter().any(|x| matches!(x, m::Decl::Vars { is_const: false, .. }));
    let has_clocks = |d: &m::Decls| d.decls.iter().any(|x| matches!(x, m::Decl::Clock { .. }));
    let not_yet = |range: TextRange, what: &str| {
        Err((
            range,
            format!("it {what}, which the export does not run inside a calling machine yet (`robosim verify` does)"),
        ))
    };
    for u in &b.decls.uses {
        if interface(u).is_some_and(has_clocks) {
            return not_yet(u.range, "requires clocks (the machine's)");
        }
    }
    for (io, ctx) in &b.contexts {
        let reads = *io == Io::Input && (!ctx.decls.is_empty() || !ctx.uses.is_empty());
        let vars = has_vars(ctx) || ctx.uses.iter().any(|u| interface(u).is_some_and(has_vars));
        if reads || vars {
            return not_yet(b.name_range, "reads inputs or variables of the platform (the machine's registers)");
        }
    }
    if let Some(range) = b.region.exec_in_composite() {
        return not_yet(range, "has an `exec` inside a composite state");
    }
    if let Some(t) = b.region.exec_transition() {
        return not_yet(t.exec_range.unwrap_or(t.range), "has an `exec`-triggered transition");
    }
    Ok(())
}

/// What the native checker refuses of a RoboSim operation on its own
/// (`robosim-engine`'s `sim_operation_supported`), with the same reasons:
/// RoboTool's process for it has no memory for what it requires or reads
/// (visible `get_x?x`, `set_x!v`, `clockReset` events the checker does not
/// model), an `exec` inside a composite state, an `exec`-triggered
/// transition (not established by any generated output).
fn sim_operation_supported(ex: &Exporter<'_>, b: &m::Behaviour) -> Result<(), (TextRange, String)> {
    let interface = |u: &m::InterfaceUse| match u.target.and_then(|loc| m::item(ex.db, ex.ws, loc)) {
        Some(m::Item::Interface(i)) => Some(&i.decls),
        _ => None,
    };
    let has_vars = |d: &m::Decls| d.decls.iter().any(|x| matches!(x, m::Decl::Vars { is_const: false, .. }));
    let has_clocks = |d: &m::Decls| d.decls.iter().any(|x| matches!(x, m::Decl::Clock { .. }));
    let refuse = |range: TextRange, what: &str| {
        Err((
            range,
            format!(
                "it {what}: RoboTool's process for it on its own (`OP_…::O__`) has no memory for them, so it reads \
                 them with visible events at every step (`get_x?x`, values chosen by the environment) and writes or \
                 resets them with visible events (`set_x!v`, `clockReset`), which `robosim verify` does not model \
                 yet (check a machine that calls it)"
            ),
        ))
    };
    for u in &b.decls.uses {
        if interface(u).is_some_and(has_vars) {
            return refuse(u.range, "requires variables");
        }
        if interface(u).is_some_and(has_clocks) {
            return refuse(u.range, "requires clocks");
        }
    }
    for (io, ctx) in &b.contexts {
        let reads = *io == Io::Input && (!ctx.decls.is_empty() || !ctx.uses.is_empty());
        let vars = has_vars(ctx) || ctx.uses.iter().any(|u| interface(u).is_some_and(has_vars));
        if reads || vars {
            return refuse(b.name_range, "reads inputs or variables of the platform");
        }
    }
    if let Some(range) = b.region.exec_in_composite() {
        return Err((
            range,
            "it has an `exec` inside a composite state: in RoboTool's process the composite's own transitions may \
             interrupt what runs inside it before `endexec`, which `robosim verify` does not model for an operation \
             on its own"
                .into(),
        ));
    }
    if let Some(t) = b.region.exec_transition() {
        return Err((
            t.exec_range.unwrap_or(t.range),
            "it has an `exec`-triggered transition: how RoboTool's process for the operation on its own takes one \
             is not established by any generated output (an `exec` statement in an action is: `endexec`, then \
             `startexec`)"
                .into(),
        ));
    }
    Ok(())
}
