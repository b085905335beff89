//! Moving lowered definitions: an element's definitions, lowered from its
//! own tree (positions from 0, ids from 0), placed at its offset and id in
//! the file. Every range of a definition moves (destructured exhaustively,
//! so that a new field does not go unmoved).

use robosim_syntax::{TextRange, TextSize};

use crate::defs::{ConnectionData, ContainerFacts, Def, DefData, FileDefs, TransitionData, TypeRef, Use};

fn r(range: &mut TextRange, by: TextSize) {
    *range += by;
}

fn opt(range: &mut Option<TextRange>, by: TextSize) {
    if let Some(x) = range {
        r(x, by);
    }
}

fn named(n: &mut Option<(String, TextRange)>, by: TextSize) {
    if let Some((_, x)) = n {
        r(x, by);
    }
}

pub(crate) fn ty(t: &mut TypeRef, by: TextSize) {
    match t {
        TypeRef::Named(_, x) => r(x, by),
        TypeRef::Set(a) | TypeRef::Seq(a) => ty(a, by),
        TypeRef::Product(v) => v.iter_mut().for_each(|t| ty(t, by)),
        TypeRef::Function(a, b) | TypeRef::Relation(a, b) => {
            ty(a, by);
            ty(b, by);
        }
        TypeRef::Vector(a, x) => {
            ty(a, by);
            r(x, by);
        }
        TypeRef::Matrix(a, x, y) => {
            ty(a, by);
            r(x, by);
            r(y, by);
        }
        TypeRef::Var(_) | TypeRef::Missing => {}
    }
}

fn data(d: &mut DefData, by: TextSize) {
    match d {
        DefData::None => {}
        DefData::Typed { ty: t, init, broadcast: _ } => {
            if let Some(t) = t {
                ty(t, by);
            }
            opt(init, by);
        }
        DefData::Signature { params, result, terminates: _ } => {
            for (_, t) in params.iter_mut() {
                if let Some(t) = t {
                    ty(t, by);
                }
            }
            if let Some(t) = result {
                ty(t, by);
            }
        }
        DefData::Transition(TransitionData {
            source,
            target,
            trigger,
            exec,
            probability,
            resets,
            deadline,
            condition,
            is_else: _,
            action,
        }) => {
            named(source, by);
            named(target, by);
            if let Some((x, event)) = trigger {
                r(x, by);
                named(event, by);
            }
            opt(exec, by);
            opt(probability, by);
            resets.iter_mut().for_each(|(_, x)| r(x, by));
            opt(deadline, by);
            opt(condition, by);
            opt(action, by);
        }
        DefData::Connection(ConnectionData { from, efrom, to, eto, is_async: _, async_range, is_mult: _ }) => {
            named(from, by);
            named(efrom, by);
            named(to, by);
            named(eto, by);
            opt(async_range, by);
        }
        DefData::Reference { path: _, range } => r(range, by),
        DefData::Literal { args } => args.iter_mut().for_each(|t| ty(t, by)),
    }
}

fn def(d: &mut Def, by: TextSize, base: u32) {
    let Def { kind: _, name: _, name_range, range, parent, io: _, data: dd, syntax: _ } = d;
    r(name_range, by);
    r(range, by);
    if let Some(p) = parent {
        p.0 += base;
    }
    data(dd, by);
}

fn use_(u: &mut Use, by: TextSize, base: u32) {
    let Use { kind: _, path: _, range, owner, io: _ } = u;
    r(range, by);
    owner.0 += base;
}

fn facts(f: &mut ContainerFacts, by: TextSize) {
    let ContainerFacts { cycle_defs, input_contexts, output_contexts, actions } = f;
    cycle_defs.iter_mut().chain(input_contexts).chain(output_contexts).for_each(|x| r(x, by));
    actions.iter_mut().for_each(|(_, x)| r(x, by));
}

/// Appends `part` (an element's definitions, ids and positions from 0) to
/// `out`, moved by `by` and numbered after `out`'s definitions.
pub(crate) fn append(out: &mut FileDefs, part: &FileDefs, by: TextSize) {
    let base = out.defs.len() as u32;
    for d in &part.defs {
        let mut d = d.clone();
        def(&mut d, by, base);
        out.defs.push(d);
    }
    for u in &part.uses {
        let mut u = u.clone();
        use_(&mut u, by, base);
        out.uses.push(u);
    }
    for f in &part.facts {
        let mut f = f.clone();
        facts(&mut f, by);
        out.facts.push(f);
    }
}

/// `defs` (an element's, with the file's ids) moved by `by`, ids kept: a
/// uniform move keeps the order of the start index.
pub(crate) fn moved(defs: &FileDefs, by: TextSize) -> FileDefs {
    let mut out = defs.clone();
    out.defs.iter_mut().for_each(|d| def(d, by, 0));
    out.uses.iter_mut().for_each(|u| use_(u, by, 0));
    out.facts.iter_mut().for_each(|f| facts(f, by));
    out
}
