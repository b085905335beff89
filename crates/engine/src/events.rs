//! Event tables: channels with bounded parameters, numbered densely so that
//! an event is a `u32` computed from its channel and argument values
//! (mixed radix), and named back for counterexamples.

use crate::ir::{Dom, Val};
use crate::lts::{Event, FIRST_VISIBLE};

/// How a parameter is printed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Param {
    /// A number in a domain.
    Num(Dom),
    /// `true`/`false`.
    Bool,
    /// A value with a name: an enumeration's literal (`Level_Mid`, the
    /// CSPm constructor RoboTool writes), by position.
    Named(Vec<String>),
    /// A tuple (or a record) of scalar components encoded in one value
    /// (see [`crate::ir::Expr::Tuple`]), printed as CSPm prints a tuple,
    /// `(1, true)`: each component as its own parameter would be.
    Tuple(Vec<Param>),
    /// A finite set of values of the element parameter, encoded as a
    /// bitmask over the element's values (see [`crate::ir::Expr::Elem`]),
    /// printed as CSPm prints a set (`{Skills_MOVE, Skills_EXPLORE}`).
    Set(Box<Param>),
}

impl Param {
    /// The values of the parameter.
    pub fn dom(&self) -> Dom {
        match self {
            Param::Num(d) => *d,
            Param::Bool => Dom::BOOL,
            Param::Named(names) => Dom { lo: 0, hi: names.len().saturating_sub(1) as Val },
            Param::Tuple(ps) => Dom { lo: 0, hi: tuple_size(&leaf_doms(ps)).saturating_sub(1) as Val },
            Param::Set(el) => Dom { lo: 0, hi: (1i64 << el.dom().size().min(62)) - 1 },
        }
    }

    /// The parameter of two sides that must agree on it (a refinement):
    /// numbers take both ranges; tuples must be the same.
    pub fn union(&self, other: &Param) -> Option<Param> {
        match (self, other) {
            (Param::Tuple(a), Param::Tuple(b)) => (a == b).then(|| self.clone()),
            (Param::Tuple(_), _) | (_, Param::Tuple(_)) => None,
            (Param::Set(a), Param::Set(b)) => (a == b).then(|| self.clone()),
            (Param::Set(_), _) | (_, Param::Set(_)) => None,
            (Param::Named(a), Param::Named(b)) if a == b => Some(self.clone()),
            (Param::Bool, Param::Bool) => Some(Param::Bool),
            _ => {
                let (p, q) = (self.dom(), other.dom());
                Some(Param::Num(Dom { lo: p.lo.min(q.lo), hi: p.hi.max(q.hi) }))
            }
        }
    }

    /// Writes value `v` as `.v` fields.
    fn print(&self, v: Val, s: &mut String) {
        match self {
            Param::Set(el) => {
                s.push('.');
                s.push_str(&self.set_text(el, v));
            }
            Param::Bool => s.push_str(if v != 0 { ".true" } else { ".false" }),
            Param::Named(names) => match usize::try_from(v).ok().and_then(|i| names.get(i)) {
                Some(n) => {
                    s.push('.');
                    s.push_str(n);
                }
                None => s.push_str(&format!(".{v}")),
            },
            Param::Num(_) => s.push_str(&format!(".{v}")),
            // FDR writes a tuple-typed field as one value, `e.(1, 2)` (RoboTool
            // declares a product-typed event over a tuple set).
            Param::Tuple(ps) => {
                let xs: Vec<String> = tuple_values(&leaf_doms(ps), v)
                    .into_iter()
                    .zip(ps)
                    .map(|(x, p)| {
                        let mut one = String::new();
                        p.print(x, &mut one);
                        one.trim_start_matches('.').to_string()
                    })
                    .collect();
                s.push_str(&format!(".({})", xs.join(", ")));
            }
        }
    }
}

impl Param {
    /// The set whose bitmask (over `el`'s values) is `v`, as `{a, b}`.
    pub fn set_text(&self, el: &Param, v: Val) -> String {
        let d = el.dom();
        let items: Vec<String> = (0..d.size().min(62) as Val)
            .filter(|i| v & (1 << i) != 0)
            .map(|i| {
                let mut one = String::new();
                el.print(d.lo + i, &mut one);
                one.trim_start_matches('.').to_string()
            })
            .collect();
        format!("{{{}}}", items.join(", "))
    }
}

/// The domains of a tuple's components.
pub fn leaf_doms(ps: &[Param]) -> Vec<Dom> {
    ps.iter().map(Param::dom).collect()
}

/// The number of tuples of components `ds`.
pub fn tuple_size(ds: &[Dom]) -> u64 {
    ds.iter().fold(1u64, |acc, d| acc.saturating_mul(d.size().max(1)))
}

/// The components of the encoded tuple `code`.
pub fn tuple_values(ds: &[Dom], code: Val) -> Vec<Val> {
    let mut code = code.max(0) as u64;
    let mut out = vec![0; ds.len()];
    for (i, d) in ds.iter().enumerate().rev() {
        let n = d.size().max(1);
        out[i] = d.lo + (code % n) as Val;
        code /= n;
    }
    out
}

/// A channel of the table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    /// Printed name (`registerRead.i_obstacle`, `moveCall`).
    pub name: String,
    /// Parameters.
    pub params: Vec<Param>,
    /// First event id.
    pub base: Event,
    /// Number of events.
    pub size: u64,
    /// The parameters' domains ([`Param::dom`]), kept for [`EventTable::event`],
    /// which runs for nearly every transition.
    doms: Vec<Dom>,
}

/// A table of channels.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EventTable {
    groups: Vec<Group>,
}

/// The table would need more than `u32` events.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooManyEvents(pub String);

impl EventTable {
    /// Adds a channel; returns its index.
    pub fn add(&mut self, name: impl Into<String>, params: Vec<Param>) -> Result<usize, TooManyEvents> {
        let name = name.into();
        let size = params.iter().try_fold(1u64, |acc, p| acc.checked_mul(p.dom().size().max(1)));
        let base = self.groups.last().map_or(FIRST_VISIBLE as u64, |g| g.base as u64 + g.size);
        let size = size.filter(|s| base + s < u32::MAX as u64).ok_or_else(|| TooManyEvents(name.clone()))?;
        let doms = params.iter().map(Param::dom).collect();
        self.groups.push(Group { name, params, base: base as Event, size, doms });
        Ok(self.groups.len() - 1)
    }

    /// The event of channel `group` with `args` (values outside the
    /// domains are clamped: callers only pass values of the domains).
    pub fn event(&self, group: usize, args: &[Val]) -> Event {
        let g = &self.groups[group];
        let mut ix: u64 = 0;
        for (d, &v) in g.doms.iter().zip(args) {
            ix = ix * d.size().max(1) + (v.clamp(d.lo, d.hi) - d.lo) as u64;
        }
        g.base + ix as Event
    }

    /// The id the next added channel starts at.
    pub fn next_event(&self) -> Event {
        self.groups.last().map_or(FIRST_VISIBLE, |g| g.base + g.size as Event)
    }

    /// The channel and arguments of `event`.
    pub fn decode(&self, event: Event) -> Option<(usize, Vec<Val>)> {
        let gi = self.groups.iter().position(|g| event >= g.base && ((event - g.base) as u64) < g.size)?;
        let g = &self.groups[gi];
        let mut ix = (event - g.base) as u64;
        let mut args = vec![0; g.params.len()];
        for (i, p) in g.params.iter().enumerate().rev() {
            let d = p.dom();
            let n = d.size().max(1);
            args[i] = d.lo + (ix % n) as Val;
            ix /= n;
        }
        Some((gi, args))
    }

    /// The printed name of `event` (`registerRead.i_obstacle.true`).
    pub fn name(&self, event: Event) -> Option<String> {
        let (gi, args) = self.decode(event)?;
        let g = &self.groups[gi];
        let mut s = g.name.clone();
        for (p, v) in g.params.iter().zip(args) {
            p.print(v, &mut s);
        }
        Some(s)
    }

    /// The channel named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.groups.iter().position(|g| g.name == name)
    }

    /// The channel's description.
    pub fn group(&self, group: usize) -> &Group {
        &self.groups[group]
    }
}
