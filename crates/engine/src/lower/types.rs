//! How the values of a type are laid out in the state vector: every value
//! is one slot, a product its components in mixed radix, a finite set a
//! bitmask.

use robosim_hir::index::ItemLoc;
use robosim_hir::model::DefKind;
use robosim_hir::model::{Item, TyRef};
use robosim_hir::types::Ty;
use robosim_hir::{File, TextRange};

use super::*;
use crate::events::{tuple_size, Param};

/// The largest tuple type (number of tuples): its encoding must fit a slot.
const MAX_TUPLES: u64 = 1 << 30;

/// The largest element type of a set: a set is a bitmask in one slot.
const MAX_SET_ELEMENTS: u64 = 31;

/// The longest sequence the checker holds (less when the sequences of
/// this length would be more than [`MAX_TUPLES`]). RoboChart's sequences
/// are unbounded: a machine that makes a longer one stops the check with
/// an error (`EvalError::SeqTooLong`), never a verdict that ignores it.
const MAX_SEQ_LEN: u32 = 8;

/// The layout of a type's values (the type itself is the model's
/// [`Ty`]). Every value is one slot: a product is its components in mixed
/// radix (first component most significant, so that the codes count
/// tuples in CSPm's order and one event parameter carries a tuple: the
/// event table prints the components as fields); a finite set is a bitmask
/// over its element type's codes.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Layout {
    /// Numbers, booleans, enumerations.
    Num(Dom),
    /// `A * B * …` of numeric components.
    Tuple(Vec<Dom>),
    /// A record of numeric fields (names, domains): encoded as the tuple
    /// of its fields in declaration order.
    Record(Vec<String>, Vec<Dom>),
    /// `Set(T)` of a type with at most [`MAX_SET_ELEMENTS`] values.
    Set(Box<Layout>),
    /// `A * B * …` with a component that is itself a tuple or a record
    /// (`Velocities * nat`): the components' codes in mixed radix, which
    /// is the mixed radix of all their numbers in order, so that one event
    /// parameter carries the flat numbers ([`Layout::leaves`]) and the
    /// CSPm side nests them again by the channel's type.
    Product(Vec<Layout>),
    /// `Seq(T)` of numbers, bounded in length (see [`SeqDom`]).
    Seq(SeqDom),
}

impl Layout {
    /// The slot's range.
    pub(super) fn dom(&self) -> Dom {
        match self {
            Layout::Num(d) => *d,
            Layout::Tuple(ds) | Layout::Record(_, ds) => Dom { lo: 0, hi: tuple_size(ds) as Val - 1 },
            Layout::Set(el) => Dom { lo: 0, hi: (1 << el.dom().size()) - 1 },
            Layout::Product(_) => Dom { lo: 0, hi: tuple_size(&self.leaves()) as Val - 1 },
            Layout::Seq(d) => Dom { lo: 0, hi: d.count() as Val - 1 },
        }
    }

    /// The numbers of a product, in order, nested products opened (a
    /// number: itself).
    pub(super) fn leaves(&self) -> Vec<Dom> {
        match self {
            Layout::Tuple(ds) | Layout::Record(_, ds) => ds.clone(),
            Layout::Product(cs) => cs.iter().flat_map(Layout::leaves).collect(),
            t => vec![t.dom()],
        }
    }

    /// The value whose code is `v`, as written: a number as itself, a
    /// tuple `(a, b)`, a record `(| x = a, y = b |)`, a set `{a, b}`.
    pub(super) fn show(&self, v: Val) -> String {
        // The components' values from the code, in mixed radix (the first
        // component most significant).
        fn digits(v: Val, sizes: &[u64]) -> Vec<Val> {
            let mut out = vec![0; sizes.len()];
            let mut rest = v;
            for (i, n) in sizes.iter().enumerate().rev() {
                let n = (*n).max(1) as Val;
                out[i] = rest.rem_euclid(n);
                rest = rest.div_euclid(n);
            }
            out
        }
        match self {
            Layout::Num(_) => v.to_string(),
            Layout::Tuple(ds) => {
                let xs = digits(v, &ds.iter().map(|d| d.size()).collect::<Vec<_>>());
                let xs: Vec<String> = xs.iter().zip(ds).map(|(x, d)| (x + d.lo).to_string()).collect();
                format!("({})", xs.join(", "))
            }
            Layout::Record(names, ds) => {
                let xs = digits(v, &ds.iter().map(|d| d.size()).collect::<Vec<_>>());
                let fs: Vec<String> =
                    names.iter().zip(xs.iter().zip(ds)).map(|(n, (x, d))| format!("{n} = {}", x + d.lo)).collect();
                format!("(| {} |)", fs.join(", "))
            }
            Layout::Product(cs) => {
                let xs = digits(v, &cs.iter().map(|c| c.dom().size()).collect::<Vec<_>>());
                let parts: Vec<String> = xs.iter().zip(cs).map(|(x, c)| c.show(x + c.dom().lo)).collect();
                format!("({})", parts.join(", "))
            }
            Layout::Set(el) => {
                let lo = el.dom().lo;
                let xs: Vec<String> =
                    (0..el.dom().size().min(63)).filter(|i| v >> i & 1 == 1).map(|i| el.show(lo + i as Val)).collect();
                format!("{{{}}}", xs.join(", "))
            }
            Layout::Seq(d) => {
                let xs: Vec<String> = d.decode(v).iter().map(|x| x.to_string()).collect();
                format!("<{}>", xs.join(", "))
            }
        }
    }

    /// The value of a variable declared without one: the least value of
    /// each number (0 when in range), the empty set.
    pub(super) fn default_value(&self) -> Val {
        let num = |d: Dom| d.lo.max(0).min(d.hi);
        match self {
            Layout::Num(d) => num(*d),
            Layout::Tuple(ds) | Layout::Record(_, ds) => {
                ds.iter().fold(0, |code, d| code * d.size() as Val + (num(*d) - d.lo))
            }
            // The empty set and the empty sequence.
            Layout::Set(_) | Layout::Seq(_) => 0,
            Layout::Product(cs) => {
                cs.iter().fold(0, |code, c| code * c.dom().size() as Val + (c.default_value() - c.dom().lo))
            }
        }
    }

    /// How an event parameter of this type is named.
    pub(super) fn param(&self) -> Param {
        match self {
            Layout::Tuple(ds) | Layout::Record(_, ds) => Param::Tuple(ds.iter().map(|d| Param::Num(*d)).collect()),
            Layout::Product(_) => Param::Tuple(self.leaves().into_iter().map(Param::Num).collect()),
            Layout::Set(el) => Param::Set(Box::new(el.param())),
            t => Param::Num(t.dom()),
        }
    }

    /// Whether values of the type are plain numbers.
    pub(super) fn is_num(&self) -> bool {
        matches!(self, Layout::Num(_))
    }
}

/// The weight of component `i` in a tuple's code.
pub(super) fn stride(ds: &[Dom], i: usize) -> Val {
    tuple_size(&ds[i + 1..]) as Val
}

impl MachineCx<'_, '_> {
    /// A type whose values are plain numbers (parameters of operations).
    pub(super) fn ty(&self, file: File, node: Option<&TyRef>, at: TextRange) -> Result<Dom, Unsupported> {
        match self.ty_of(file, node, at)? {
            Layout::Num(d) => Ok(d),
            _ => Err(self.cx.unsupported(
                file,
                node.map_or(at, |n| n.range),
                "product and set types are supported for variables, constants and events (not parameters) yet",
            )),
        }
    }

    /// The literals of the enumeration `loc`.
    pub(super) fn literals(&self, loc: ItemLoc) -> Option<&[String]> {
        match self.cx.item(Some(loc))? {
            Item::Enumeration(_, lits) => Some(lits),
            _ => None,
        }
    }

    /// A type: numbers, products of them, finite sets.
    pub(super) fn ty_of(&self, file: File, node: Option<&TyRef>, at: TextRange) -> Result<Layout, Unsupported> {
        let Some(node) = node else {
            return Err(self.err(at, "an untyped declaration cannot be checked"));
        };
        self.layout(file, &node.ty, node)
    }

    /// The layout of `ty`, written as `node` in `file`.
    fn layout(&self, file: File, ty: &Ty, node: &TyRef) -> Result<Layout, Unsupported> {
        let range = node.range;
        let d = &self.cx.defaults;
        match ty {
            Ty::Product(parts) => {
                let mut comps = Vec::new();
                for c in parts {
                    match self.layout(file, c, node)? {
                        Layout::Set(_) | Layout::Seq(_) => {
                            return Err(self.cx.unsupported(
                                file,
                                range,
                                "tuples whose components are sets or sequences are not supported yet",
                            ))
                        }
                        l => comps.push(l),
                    }
                }
                let product = Layout::Product(comps);
                self.small_product(file, node, &product.leaves())?;
                Ok(match product {
                    Layout::Product(cs) if cs.iter().all(Layout::is_num) => {
                        Layout::Tuple(cs.iter().map(Layout::dom).collect())
                    }
                    p => p,
                })
            }
            Ty::Set(inner) => {
                let el = self.layout(file, inner, node)?;
                let n = el.dom().size();
                if matches!(el, Layout::Set(_) | Layout::Seq(_)) || n > MAX_SET_ELEMENTS {
                    return Err(self.cx.unsupported(
                        file,
                        range,
                        format!(
                            "the set type `{}` is not supported: sets are checked over types with at most {MAX_SET_ELEMENTS} values, and its elements have {n}",
                            node.text
                        ),
                    ));
                }
                Ok(Layout::Set(Box::new(el)))
            }
            Ty::Seq(inner) => {
                let el = match self.layout(file, inner, node)? {
                    Layout::Num(d) => d,
                    _ => {
                        return Err(self.cx.unsupported(
                            file,
                            range,
                            format!(
                                "the sequence type `{}` is not supported: sequences of numbers, booleans and \
                                 enumerations are",
                                node.text
                            ),
                        ))
                    }
                };
                let fits = |max| SeqDom { el, max }.count() <= MAX_TUPLES;
                match (1..=MAX_SEQ_LEN).rev().find(|&max| fits(max)) {
                    Some(max) => Ok(Layout::Seq(SeqDom { el, max })),
                    None => Err(self.cx.unsupported(
                        file,
                        range,
                        format!("the sequence type `{}` has too many values to check natively", node.text),
                    )),
                }
            }
            Ty::Bool => Ok(Layout::Num(Dom::BOOL)),
            Ty::Nat => Ok(Layout::Num(d.nat)),
            Ty::Int => Ok(Layout::Num(d.int)),
            Ty::Real => Ok(Layout::Num(d.real)),
            // A primitive type the model declares (`type ID`) takes the range
            // an instantiation gives it (`nametype ID = {0..1}`), else
            // RoboTool's {0, 1} (RT-3).
            Ty::Named(_, name, DefKind::PrimitiveType) => {
                let core = format!("core_{name}");
                match d.types.iter().rev().find(|(n, _)| n == name || *n == core) {
                    Some((_, dom)) => Ok(Layout::Num(*dom)),
                    None => {
                        self.cx.primitive_defaults.borrow_mut().insert(format!("type {name} = {{0, 1}} (RT-3)"));
                        Ok(Layout::Num(Dom { lo: 0, hi: 1 }))
                    }
                }
            }
            Ty::Named(loc, _, DefKind::Enumeration) => {
                let n = self.literals(*loc).map_or(0, |l| l.len()) as Val;
                Ok(Layout::Num(Dom { lo: 0, hi: (n - 1).max(0) }))
            }
            Ty::Named(loc, _, DefKind::Record) => {
                let Some(Item::Record(_, fields)) = self.cx.item(Some(*loc)) else {
                    return Err(self.unsupported_type(file, node));
                };
                let (mut names, mut doms) = (Vec::new(), Vec::new());
                for f in fields {
                    match self.ty_of(loc.file, f.ty.as_ref(), f.range)? {
                        Layout::Num(d) => doms.push(d),
                        _ => {
                            return Err(self.cx.unsupported(
                                loc.file,
                                f.range,
                                "records whose fields are records, tuples or sets are not supported yet",
                            ))
                        }
                    }
                    names.push(f.name.clone());
                }
                self.small_product(file, node, &doms)?;
                Ok(Layout::Record(names, doms))
            }
            _ => Err(self.unsupported_type(file, node)),
        }
    }

    fn unsupported_type(&self, file: File, node: &TyRef) -> Unsupported {
        self.cx.unsupported(
            file,
            node.range,
            format!(
                "the type `{}` is not supported by the native checker (booleans, numbers, enumerations, their products and small finite sets are)",
                node.text
            ),
        )
    }

    /// A product type (tuple or record) `node` of components `doms` is
    /// small enough to be one slot.
    fn small_product(&self, file: File, node: &TyRef, doms: &[Dom]) -> Result<(), Unsupported> {
        let n = tuple_size(doms);
        if n > MAX_TUPLES {
            return Err(self.cx.unsupported(
                file,
                node.range,
                format!("the type `{}` has {n} values: too many to check natively", node.text),
            ));
        }
        Ok(())
    }

    /// How event values of the type `node` are named when they are not
    /// numbers: booleans, and enumerations (RoboTool's CSPm constructors
    /// `Enum_Literal`).
    pub(super) fn param_of(&self, node: Option<&TyRef>) -> Option<Param> {
        match &node?.ty {
            Ty::Set(inner) => Some(Param::Set(Box::new(self.scalar_param(inner)?))),
            t => self.scalar_param(t),
        }
    }

    /// How event values of the type `node`, laid out as `ty`, are named:
    /// [`Self::param_of`], and a tuple's or a record's boolean and
    /// enumeration components by name (`(1, true)`).
    pub(super) fn shape_of(&self, node: Option<&TyRef>, ty: &Layout) -> Param {
        if let Some(p) = self.param_of(node) {
            return p;
        }
        let kinds: Option<Vec<Option<Param>>> = match (node.map(|n| &n.ty), ty) {
            (Some(Ty::Product(parts)), Layout::Tuple(ds)) if parts.len() == ds.len() => {
                Some(parts.iter().map(|t| self.scalar_param(t)).collect())
            }
            (Some(Ty::Named(loc, _, DefKind::Record)), Layout::Record(_, ds)) => match self.cx.item(Some(*loc)) {
                Some(Item::Record(_, fields)) if fields.len() == ds.len() => {
                    Some(fields.iter().map(|f| f.ty.as_ref().and_then(|t| self.scalar_param(&t.ty))).collect())
                }
                _ => None,
            },
            _ => None,
        };
        match (kinds, ty) {
            (Some(kinds), Layout::Tuple(ds) | Layout::Record(_, ds)) => {
                Param::Tuple(kinds.into_iter().zip(ds).map(|(k, d)| k.unwrap_or(Param::Num(*d))).collect())
            }
            _ => ty.param(),
        }
    }

    /// How values of the type `t` are named when they are booleans or
    /// enumerations' literals.
    fn scalar_param(&self, t: &Ty) -> Option<Param> {
        match t {
            Ty::Bool => Some(Param::Bool),
            Ty::Named(loc, ty, DefKind::Enumeration) => {
                Some(Param::Named(self.literals(*loc)?.iter().map(|l| format!("{ty}_{l}")).collect()))
            }
            _ => None,
        }
    }

    /// The default of the type `node` (`ty` lowered): RoboTool's, true for
    /// booleans (RT-1, RT-4), otherwise the least value of each number
    /// (0 when in range), the first literal, the empty set.
    pub(super) fn default_of(&self, node: Option<&TyRef>, ty: &Layout) -> Val {
        match (self.param_of(node), node.map(|n| &n.ty), ty) {
            (Some(Param::Bool), _, _) => 1,
            // A tuple's boolean components are `true` too (RT-1, RT-4).
            (_, Some(robosim_hir::types::Ty::Product(parts)), Layout::Tuple(ds)) if parts.len() == ds.len() => {
                parts.iter().zip(ds).fold(0, |code, (t, d)| {
                    let v = if matches!(t, robosim_hir::types::Ty::Bool) { d.hi.min(1) } else { d.lo.max(0).min(d.hi) };
                    code * d.size() as Val + (v - d.lo)
                })
            }
            _ => ty.default_value(),
        }
    }

    /// The initial value of a variable declared without one (RT-4): the
    /// type's default; a boolean's `true` is recorded as a default the
    /// verdict rests on, since a modeller may expect `false`.
    pub(super) fn uninitialised(&mut self, q: &str, node: Option<&TyRef>, ty: &Layout) -> Val {
        let v = self.default_of(node, ty);
        if matches!(self.param_of(node), Some(Param::Bool)) {
            self.design().defaults.push(format!("variable {q} starts true (RT-4)"));
        }
        v
    }

    /// A value of the type `node` (laid out as `ty`) as the modeller
    /// writes it.
    pub(super) fn value_text(&self, node: Option<&TyRef>, ty: &Layout, v: Val) -> String {
        // A sequence of booleans or literals, by their names
        // (`<Skills_MOVE>`), as CSPm prints it.
        if let (Some(Ty::Seq(inner)), Layout::Seq(d)) = (node.map(|n| &n.ty), ty) {
            if let Some(p) = self.scalar_param(inner) {
                let name = |x: Val| match &p {
                    Param::Named(names) => names.get(x as usize).cloned().unwrap_or_else(|| x.to_string()),
                    _ => (x != 0).to_string(),
                };
                let xs: Vec<String> = d.decode(v).into_iter().map(name).collect();
                return format!("<{}>", xs.join(", "));
            }
        }
        match self.param_of(node) {
            Some(Param::Bool) => (v != 0).to_string(),
            Some(Param::Named(names)) => names.get(v as usize).cloned().unwrap_or_else(|| v.to_string()),
            _ => ty.show(v),
        }
    }
}
