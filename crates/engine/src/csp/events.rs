//! One event table for both sides of a check: the native model's events
//! named as RoboTool's CSPm names them (`M::e.in.3`, `M::opCall.1.0`,
//! `M::e.out.(1, 2)`, `M::e.in.pkg_T_L`), and the specification's events
//! mapped onto the same ids (events only the specification knows get ids
//! of their own after the model's).

use std::collections::BTreeSet;

use robosim_cspm::Value;
use robosim_hir::csp_names::{CspKind, CspNames, CspType, TypeDef};
use rustc_hash::FxHashMap;

use crate::design::channel_name;
use crate::events::{leaf_doms, tuple_values, EventTable, Param};
use crate::ir::{Design, Val};
use crate::lts::{Event, FIRST_VISIBLE, TAU, TICK, TOCK};

/// The most native events the bridge names.
const MAX_EVENTS: u64 = 1_000_000;

/// The events of both sides, by id.
#[derive(Debug, Default)]
pub(crate) struct Names {
    /// The CSPm name of each native event from [`FIRST_VISIBLE`] on (`None`:
    /// an event RoboTool's CSPm has no name for, e.g. a hidden one).
    native: Vec<Option<String>>,
    /// The native name of each native event (shown for one with no CSPm
    /// name).
    raw: Vec<String>,
    /// Native events by CSPm name.
    by_name: FxHashMap<String, Event>,
    /// Events of the specification the model does not have, from
    /// `first_extra` on.
    extra: Vec<String>,
    first_extra: Event,
    /// RoboSim: each absent read of an input event's register (flag
    /// `false`) and every absent read of that register. The native LTS
    /// reads one representative value (it is never observed); RoboTool's
    /// `registerRead.i_x?x__` takes any, so the bridge offers them all.
    aliases: FxHashMap<Event, std::sync::Arc<[Event]>>,
}

/// The value sets of the fields of the element's channels, by CSPm
/// channel name.
pub(crate) type OwnChannels = FxHashMap<String, Vec<BTreeSet<Value>>>;

impl Names {
    /// A table with no model events (both sides are CSPm).
    pub fn empty() -> Names {
        Names { first_extra: FIRST_VISIBLE, ..Names::default() }
    }

    /// The name of `e` on either side.
    pub fn name(&self, e: Event) -> String {
        match e {
            TAU => "τ".into(),
            TICK => "✓".into(),
            TOCK => "tock".into(),
            e if e >= self.first_extra => {
                self.extra.get((e - self.first_extra) as usize).cloned().unwrap_or_else(|| format!("e{e}"))
            }
            e => {
                let i = (e - FIRST_VISIBLE) as usize;
                self.native
                    .get(i)
                    .cloned()
                    .flatten()
                    .or_else(|| self.raw.get(i).cloned())
                    .unwrap_or_else(|| format!("e{e}"))
            }
        }
    }

    /// The events that stand for the native event `e` (see `aliases`), if
    /// others than `e` do.
    pub fn aliases(&self, e: Event) -> Option<&[Event]> {
        self.aliases.get(&e).map(|a| &a[..])
    }

    /// Whether the native event `e` has no CSPm name.
    pub fn unnamed(&self, e: Event) -> bool {
        e >= FIRST_VISIBLE
            && e < self.first_extra
            && self.native.get((e - FIRST_VISIBLE) as usize).is_some_and(|n| n.is_none())
    }

    /// The id of the event printed `name` (`tock`, a model event, or a new
    /// id for an event only the specification has).
    pub fn id(&mut self, name: &str) -> Event {
        if name == "tock" {
            return TOCK;
        }
        if let Some(&e) = self.by_name.get(name) {
            return e;
        }
        let e = self.first_extra + self.extra.len() as Event;
        self.extra.push(name.to_string());
        self.by_name.insert(name.to_string(), e);
        e
    }
}

/// The CSPm channel of a design channel, in element module `module`.
fn csp_channel(module: &str, c: &crate::ir::Channel) -> String {
    if c.is_call {
        format!("{module}::{}Call", c.name)
    } else if c.var {
        format!("{module}::set_{}", c.name)
    } else {
        format!("{module}::{}", c.name)
    }
}

/// The CSPm value of native value `v` of shape `p`, typed `t` in the table.
fn value(names: &CspNames, p: &Param, t: &CspType, v: Val) -> Option<Value> {
    let literals = |t: &CspType| match t {
        CspType::Named(n) => match &names.get(n)?.kind {
            CspKind::Type(TypeDef::Enumeration(lits)) => Some(lits.clone()),
            _ => None,
        },
        _ => None,
    };
    let scalar = |t: &CspType, v: Val| -> Option<Value> {
        match t {
            CspType::Bool => Some(Value::Bool(v != 0)),
            CspType::Named(n) if n == "core_boolean" => Some(Value::Bool(v != 0)),
            CspType::Nat | CspType::Int | CspType::Real | CspType::Clock => Some(Value::Int(v)),
            CspType::Named(_) => match literals(t) {
                Some(lits) => Some(Value::Ctor(lits.get(usize::try_from(v).ok()?)?.as_str().into())),
                None => Some(Value::Int(v)), // A primitive type: numbers.
            },
            _ => None,
        }
    };
    match p {
        Param::Bool => matches!(t, CspType::Bool).then_some(Value::Bool(v != 0)).or_else(|| scalar(t, v)),
        Param::Named(native) => {
            let lits = literals(t)?;
            // The native names are RoboTool's without the package prefix.
            let n = native.get(usize::try_from(v).ok()?)?;
            let l = lits.get(usize::try_from(v).ok()?)?;
            (l == n || l.ends_with(&format!("_{n}"))).then(|| Value::Ctor(l.as_str().into()))
        }
        Param::Num(_) => scalar(t, v),
        // A bitmask over the element's values: the CSPm set of them.
        Param::Set(el) => {
            let CspType::Set(inner) = t else { return None };
            let d = el.dom();
            let items = (0..d.size().min(62) as Val)
                .filter(|i| v & (1 << i) != 0)
                .map(|i| value(names, el, inner, d.lo + i))
                .collect::<Option<BTreeSet<Value>>>()?;
            Some(Value::Set(std::rc::Rc::new(items)))
        }
        Param::Tuple(ps) => {
            // The flat numbers, nested again by the channel's type (a
            // tuple whose components are records: `((1, 0), 2)`).
            if !matches!(structure(names, t), Some(Some(_))) {
                return None;
            }
            let mut vs = tuple_values(&leaf_doms(ps), v).into_iter();
            let out = nest(names, t, &mut vs, &scalar)?;
            vs.next().is_none().then_some(out)
        }
    }
}

/// The components of `t` when it is a tuple or a record (`Some(None)`:
/// a scalar; `None`: unknown).
fn structure(names: &CspNames, t: &CspType) -> Option<Option<Vec<CspType>>> {
    Some(match t {
        CspType::Tuple(ts) => Some(ts.clone()),
        CspType::Named(n) => match &names.get(n)?.kind {
            CspKind::Type(TypeDef::Record(fs)) => Some(fs.clone()),
            _ => None,
        },
        _ => None,
    })
}

/// The value of type `t` made of the next numbers of `vs`.
fn nest(
    names: &CspNames,
    t: &CspType,
    vs: &mut impl Iterator<Item = Val>,
    scalar: &dyn Fn(&CspType, Val) -> Option<Value>,
) -> Option<Value> {
    match structure(names, t)? {
        Some(comps) => {
            let vals = comps.iter().map(|c| nest(names, c, vs, scalar)).collect::<Option<Vec<_>>>()?;
            Some(Value::Tuple(vals.into()))
        }
        None => scalar(t, vs.next()?),
    }
}

/// An empty naming of the native events before `end`, checked against
/// [`MAX_EVENTS`].
fn fresh_names(end: Event) -> Result<(Names, OwnChannels, Vec<Option<Value>>), String> {
    if (end - FIRST_VISIBLE) as u64 > MAX_EVENTS {
        return Err(format!("the model has more than {MAX_EVENTS} events: too many to name for the CSPm bridge"));
    }
    Ok((Names { first_extra: end, ..Names::default() }, OwnChannels::default(), Vec::new()))
}

/// The CSPm names of the events of `table`, the design's own (see
/// [`crate::design::shared_events`]), for the element whose CSPm module is
/// `module`.
pub(crate) fn design_names(
    design: &Design,
    table: &EventTable,
    module: &str,
    names: &CspNames,
) -> Result<(Names, OwnChannels, Vec<Option<Value>>), String> {
    let end = table.next_event();
    let (mut out, mut own, mut values) = fresh_names(end)?;
    // Channels by their native name.
    let by_native: FxHashMap<String, &crate::ir::Channel> =
        design.channels.iter().filter(|c| !c.internal).map(|c| (channel_name(c), c)).rev().collect();
    for e in FIRST_VISIBLE..end {
        let value = table.decode(e).and_then(|(g, args)| {
            let group = table.group(g);
            let c = by_native.get(&group.name)?;
            let chan = csp_channel(module, c);
            let CspKind::Channel { fields } = &names.get(&chan)?.kind else { return None };
            let mut parts = vec![Value::Ctor(chan.as_str().into())];
            let typed = if c.is_call || c.var {
                fields.as_slice()
            } else {
                parts.push(Value::Ctor(if c.dir == crate::ir::Dir::In { "in" } else { "out" }.into()));
                fields.get(1..)?
            };
            if typed.len() != args.len() || group.params.len() != args.len() {
                return None;
            }
            for ((p, t), &v) in group.params.iter().zip(typed).zip(&args) {
                parts.push(value(names, p, t, v)?);
            }
            let own = own.entry(chan.clone()).or_insert_with(|| vec![BTreeSet::new(); parts.len() - 1]);
            for (set, v) in own.iter_mut().zip(&parts[1..]) {
                set.insert(v.clone());
            }
            Some(if parts.len() == 1 { parts.remove(0) } else { Value::Dot(parts.into()) })
        });
        let name = value.as_ref().map(|v| v.to_string());
        if let Some(n) = &name {
            out.by_name.insert(n.clone(), e);
        }
        out.native.push(name);
        out.raw.push(crate::lts::event_name_in(table, e));
        values.push(value);
    }
    // An event `e` has both directions in CSPm, whichever the model uses.
    for (chan, fields) in own.iter_mut() {
        if let Some(CspKind::Channel { fields: ts }) = names.get(chan).map(|n| &n.kind) {
            if ts.first() == Some(&CspType::InOut) && !chan.ends_with("Call") {
                if let Some(first) = fields.first_mut() {
                    first.insert(Value::Ctor("in".into()));
                    first.insert(Value::Ctor("out".into()));
                }
            }
        }
    }
    Ok((out, own, values))
}

/// The CSPm names of a RoboSim element's events (`events`: its
/// [`crate::sim::SimModule`]'s table), for the element whose CSPm module
/// is `module`, as RoboTool's generated CSPm declares them (the
/// reference's `sim/defs/…_Movement.csp`): `M::registerRead.M::i_x.b.v`
/// (an event's register: its presence flag `b`, then its value; a
/// variable's: its value alone), `M::registerWrite.M::o_x.v`,
/// `M::opCall.args` (RT-19), `M::endexec`, `M::terminate`. The register
/// constructors `M::i_x`, `M::o_x` are among the own channels (their
/// fields' values), so that a block can build the dotted values.
pub(crate) fn sim_names(
    design: &Design,
    events: &EventTable,
    module: &str,
    names: &CspNames,
) -> Result<(Names, OwnChannels, Vec<Option<Value>>), String> {
    let end = events.next_event();
    let (mut out, mut own, mut values) = fresh_names(end)?;
    let note = |own: &mut OwnChannels, chan: &str, parts: &[Value]| {
        let fields = own.entry(chan.to_string()).or_insert_with(|| vec![BTreeSet::new(); parts.len()]);
        for (set, v) in fields.iter_mut().zip(parts) {
            set.insert(v.clone());
        }
    };
    for e in FIRST_VISIBLE..end {
        let value = events.decode(e).and_then(|(g, args)| {
            let group = events.group(g);
            let ctor = |n: &str| Value::Ctor(n.into());
            let dotted =
                |mut parts: Vec<Value>| if parts.len() == 1 { parts.remove(0) } else { Value::Dot(parts.into()) };
            if let Some(x) = group.name.strip_prefix("registerRead.i_") {
                let c = design.channels.iter().find(|c| !c.internal && c.dir == crate::ir::Dir::In && c.name == x)?;
                let reg = format!("{module}::i_{x}");
                let flag = usize::from(!c.var);
                let types = register_types(names, module, &reg, group.params.len() - flag)?;
                let mut fields = Vec::new();
                if flag == 1 {
                    fields.push(Value::Bool(*args.first()? != 0));
                }
                for ((p, t), &v) in group.params[flag..].iter().zip(&types).zip(&args[flag..]) {
                    fields.push(value(names, p, t, v)?);
                }
                note(&mut own, &reg, &fields);
                let inner = dotted([vec![ctor(&reg)], fields].concat());
                let chan = format!("{module}::registerRead");
                note(&mut own, &chan, std::slice::from_ref(&inner));
                return Some(Value::Dot(vec![ctor(&chan), inner].into()));
            }
            if let Some(x) = group.name.strip_prefix("registerWrite.o_") {
                let reg = format!("{module}::o_{x}");
                let types = register_types(names, module, &reg, group.params.len())?;
                let fields = group
                    .params
                    .iter()
                    .zip(&types)
                    .zip(&args)
                    .map(|((p, t), &v)| value(names, p, t, v))
                    .collect::<Option<Vec<_>>>()?;
                note(&mut own, &reg, &fields);
                let inner = dotted([vec![ctor(&reg)], fields].concat());
                let chan = format!("{module}::registerWrite");
                note(&mut own, &chan, std::slice::from_ref(&inner));
                return Some(Value::Dot(vec![ctor(&chan), inner].into()));
            }
            let chan = match group.name.as_str() {
                "terminate" | "endexec" => format!("{module}::{}", group.name),
                // RT-19: a call of a software operation nothing defines.
                n if n.ends_with("Call") => format!("{module}::{n}"),
                _ => return None,
            };
            let CspKind::Channel { fields: types } = &names.get(&chan)?.kind else { return None };
            if types.len() != args.len() || group.params.len() != args.len() {
                return None;
            }
            let fields = group
                .params
                .iter()
                .zip(types)
                .zip(&args)
                .map(|((p, t), &v)| value(names, p, t, v))
                .collect::<Option<Vec<_>>>()?;
            note(&mut own, &chan, &fields);
            Some(dotted([vec![ctor(&chan)], fields].concat()))
        });
        let name = value.as_ref().map(|v| v.to_string());
        if let Some(n) = &name {
            out.by_name.insert(n.clone(), e);
        }
        out.native.push(name);
        out.raw.push(crate::lts::event_name_in(events, e));
        values.push(value);
    }
    // Absent reads of an event's register, by register.
    let mut absent: FxHashMap<usize, Vec<Event>> = FxHashMap::default();
    for e in FIRST_VISIBLE..end {
        let Some((g, args)) = events.decode(e) else { continue };
        let Some(x) = events.group(g).name.strip_prefix("registerRead.i_") else { continue };
        let flagged =
            design.channels.iter().any(|c| !c.internal && c.dir == crate::ir::Dir::In && c.name == x && !c.var);
        if flagged && args.first() == Some(&0) {
            absent.entry(g).or_default().push(e);
        }
    }
    for list in absent.into_values().filter(|l| l.len() > 1) {
        let list: std::sync::Arc<[Event]> = list.into();
        for &e in list.iter() {
            out.aliases.insert(e, list.clone());
        }
    }
    Ok((out, own, values))
}

/// The CSPm types of the `n` values of register `reg` of `module`: its
/// event's type, or its operation's parameters (`M::opCall`'s fields:
/// RoboTool's `o_move.core_real.core_real`).
pub(crate) fn register_types(names: &CspNames, module: &str, reg: &str, n: usize) -> Option<Vec<CspType>> {
    let CspKind::Register { ty, .. } = &names.get(reg)?.kind else { return None };
    let types = match ty {
        Some(t) => vec![t.clone()],
        None if n == 0 => Vec::new(),
        None => {
            let (_, x) = reg.rsplit_once("::")?;
            let op = format!("{module}::{}Call", x.get(2..)?);
            match &names.get(&op)?.kind {
                CspKind::Channel { fields } => fields.clone(),
                _ => return None,
            }
        }
    };
    (types.len() == n).then_some(types)
}
