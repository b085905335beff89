//! Moving a lowered element: the model of a top-level element is lowered
//! from its own tree (positions from 0, [`super::element_items`]) and
//! moved to its offset in the file ([`super::element_model`]). Every range
//! moves; types are destructured exhaustively, so that a new field does
//! not go unmoved.

use robosim_syntax::{TextRange, TextSize};

use super::*;
use crate::defs_shift::ty as type_ref;

fn r(range: &mut TextRange, by: TextSize) {
    *range += by;
}

fn opt(range: &mut Option<TextRange>, by: TextSize) {
    if let Some(x) = range {
        r(x, by);
    }
}

/// Moves every range of `item` by `by`.
pub(super) fn item(item: &mut Item, by: TextSize) {
    match item {
        Item::Machine(b) | Item::Operation(b) => behaviour(b, by),
        Item::Controller(c) => controller(c, by),
        Item::Module(m) => module(m, by),
        Item::Platform(p) | Item::Interface(p) => platform(p, by),
        Item::Record(_, fields) => {
            for Field { name: _, ty, range } in fields {
                opt_ty(ty, by);
                r(range, by);
            }
        }
        Item::Function(Function { name: _, range, params: ps, result, preconditions, postconditions }) => {
            r(range, by);
            params(ps, by);
            opt_ty(result, by);
            preconditions.iter_mut().chain(postconditions).for_each(|e| expr(e, by));
        }
        Item::Enumeration(..) | Item::PrimitiveType(_) | Item::Other => {}
    }
}

fn opt_ty(t: &mut Option<TyRef>, by: TextSize) {
    if let Some(TyRef { ty: _, written, text: _, range }) = t {
        type_ref(written, by);
        r(range, by);
    }
}

fn params(ps: &mut [Param], by: TextSize) {
    for Param { name: _, ty, range } in ps {
        opt_ty(ty, by);
        r(range, by);
    }
}

fn decls(d: &mut Decls, by: TextSize) {
    let Decls { decls, uses } = d;
    for d in decls {
        match d {
            Decl::Vars { is_const: _, vars, range } => {
                for VarDecl { name: _, ty, init, range } in vars {
                    opt_ty(ty, by);
                    opt_expr(init, by);
                    r(range, by);
                }
                r(range, by);
            }
            Decl::Clock { name: _, range } | Decl::Nested { kind: _, name: _, range } => r(range, by),
            Decl::Event { name: _, ty, broadcast: _, range } => {
                opt_ty(ty, by);
                r(range, by);
            }
            Decl::OperationSig { name: _, params: ps, range } => {
                params(ps, by);
                r(range, by);
            }
        }
    }
    for InterfaceUse { kind: _, path: _, target: _, range } in uses {
        r(range, by);
    }
}

fn behaviour(b: &mut Behaviour, by: TextSize) {
    let Behaviour {
        name: _,
        name_range,
        range,
        params: ps,
        decls: ds,
        contexts,
        region: reg,
        literals: _,
        def: _,
        cycle: _,
    } = b;
    r(name_range, by);
    r(range, by);
    params(ps, by);
    decls(ds, by);
    for (_, d) in contexts {
        decls(d, by);
    }
    region(reg, by);
}

fn region(reg: &mut Region, by: TextSize) {
    let Region { nodes, transitions } = reg;
    for Node { kind: _, name: _, name_range, range, actions, entry, during, exit, region: inner } in nodes {
        r(name_range, by);
        r(range, by);
        for (_, x) in actions {
            r(x, by);
        }
        for a in [entry, during, exit] {
            action(a, by);
        }
        region(inner, by);
    }
    for t in transitions {
        transition(t, by);
    }
}

fn transition(t: &mut Transition, by: TextSize) {
    let Transition {
        name: _,
        name_range,
        range,
        source: _,
        target: _,
        source_node: _,
        target_node: _,
        trigger,
        trigger_range,
        exec: _,
        exec_range,
        probability,
        resets,
        condition,
        deadline,
        action: act,
    } = t;
    r(name_range, by);
    r(range, by);
    if let Some(c) = trigger {
        comm(c, by);
    }
    opt(trigger_range, by);
    opt(exec_range, by);
    opt(probability, by);
    for (_, x) in resets {
        r(x, by);
    }
    if let Some(Condition { is_else: _, expr: e, range }) = condition {
        opt_expr(e, by);
        r(range, by);
    }
    if let Some((x, e)) = deadline {
        r(x, by);
        opt_expr(e, by);
    }
    action(act, by);
}

fn action(a: &mut Option<Action>, by: TextSize) {
    if let Some(Action { stmt: s, range }) = a {
        if let Some(s) = s {
            stmt(s, by);
        }
        r(range, by);
    }
}

fn instance<T>(i: &mut Instance<T>, by: TextSize, inline: fn(&mut T, TextSize)) {
    let Instance { name: _, range, def } = i;
    r(range, by);
    match def {
        Definition::Inline(x) => inline(x, by),
        Definition::Ref { path: _, target: _ } => {}
    }
}

fn connections(cs: &mut [Connection], by: TextSize) {
    for c in cs {
        let Connection { from: _, efrom: _, to: _, eto: _, is_async: _, is_mult: _, from_end: _, to_end: _, range } = c;
        r(range, by);
    }
}

fn controller(c: &mut Controller, by: TextSize) {
    let Controller { name: _, name_range, range, decls: ds, machines, operations, connections: cs, def: _, cycle: _ } =
        c;
    r(name_range, by);
    r(range, by);
    decls(ds, by);
    machines.iter_mut().chain(operations).for_each(|i| instance(i, by, behaviour));
    connections(cs, by);
}

fn platform(p: &mut Platform, by: TextSize) {
    let Platform { name: _, name_range, range, decls: ds } = p;
    r(name_range, by);
    r(range, by);
    decls(ds, by);
}

fn module(m: &mut Module, by: TextSize) {
    let Module { name: _, name_range, range, platforms, controllers, machines, connections: cs, def: _, cycle: _ } = m;
    r(name_range, by);
    r(range, by);
    platforms.iter_mut().for_each(|i| instance(i, by, platform));
    controllers.iter_mut().for_each(|i| instance(i, by, controller));
    machines.iter_mut().for_each(|i| instance(i, by, behaviour));
    connections(cs, by);
}

fn opt_expr(e: &mut Option<Expr>, by: TextSize) {
    if let Some(e) = e {
        expr(e, by);
    }
}

fn expr(e: &mut Expr, by: TextSize) {
    let Expr { kind, ty: _, range } = e;
    r(range, by);
    match kind {
        ExprKind::SimRef { path: _, input, sync } => {
            if let Some((_, x)) = input {
                r(x, by);
            }
            if let Some(s) = sync {
                expr(s, by);
            }
        }
        ExprKind::Unary(_, a) | ExprKind::Field(a, _) => expr(a, by),
        ExprKind::Binary(_, a, b) | ExprKind::SetRange(a, b) | ExprKind::Interval { lo: a, hi: b, .. } => {
            expr(a, by);
            expr(b, by);
        }
        ExprKind::If(a, b, c) => {
            expr(a, by);
            expr(b, by);
            expr(c, by);
        }
        ExprKind::Index(a, v) => {
            expr(a, by);
            v.iter_mut().for_each(|e| expr(e, by));
        }
        ExprKind::Call { function: _, res: _, args: v } | ExprKind::Tuple(v) | ExprKind::Set(v) | ExprKind::Seq(v) => {
            v.iter_mut().for_each(|e| expr(e, by))
        }
        ExprKind::Record(v) => v.iter_mut().for_each(|(_, e)| expr(e, by)),
        ExprKind::Int(_)
        | ExprKind::Real(_)
        | ExprKind::Bool(_)
        | ExprKind::Name { .. }
        | ExprKind::EnumLiteral { .. }
        | ExprKind::Since(_)
        | ExprKind::SinceEntry(_)
        | ExprKind::Result
        | ExprKind::Missing
        | ExprKind::Other(_) => {}
    }
}

fn comm(c: &mut Comm, by: TextSize) {
    let Comm { event: _, res: _, event_range, guard, part, range } = c;
    r(event_range, by);
    opt(guard, by);
    match part {
        Some(CommPart::Sync(e) | CommPart::Output(e)) => opt_expr(e, by),
        Some(CommPart::Input(_, x)) => r(x, by),
        None => {}
    }
    r(range, by);
}

fn stmt(s: &mut Stmt, by: TextSize) {
    let Stmt { kind, range, head } = s;
    r(range, by);
    r(head, by);
    match kind {
        StmtKind::Seq(v) | StmtKind::Par(v) => v.iter_mut().for_each(|s| stmt(s, by)),
        StmtKind::Assign { target: _, res: _, selectors, value } => {
            for sel in selectors {
                match sel {
                    Selector::Field(_, x) => r(x, by),
                    Selector::Index(v, x) => {
                        v.iter_mut().for_each(|e| expr(e, by));
                        r(x, by);
                    }
                }
            }
            expr(value, by);
        }
        StmtKind::If(c, a, b) => {
            expr(c, by);
            stmt(a, by);
            if let Some(b) = b {
                stmt(b, by);
            }
        }
        StmtKind::Comm(c) => comm(c, by),
        StmtKind::Call { name: _, args } | StmtKind::SimCall { name: _, args } => {
            args.iter_mut().for_each(|e| expr(e, by))
        }
        StmtKind::Output(_, e) => opt_expr(e, by),
        StmtKind::Wait(e) => expr(e, by),
        StmtKind::Timed(s, e) => {
            if let Some(s) = s {
                stmt(s, by);
            }
            opt_expr(e, by);
        }
        StmtKind::Skip | StmtKind::ClockReset(_) | StmtKind::Exec | StmtKind::Other(_) => {}
    }
}
