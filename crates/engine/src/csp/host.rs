//! The model's names as a CSPm [`NameLookup`]: what a `csp` block sees
//! besides its own file's blocks (RT-7). Channels of the element under
//! check take the values of its compiled domains (so that the two sides
//! agree on every event); other names take RoboTool's defaults.

use std::collections::BTreeSet;
use std::rc::Rc;

use robosim_cspm::{ExternalName, NameLookup, Value};
use robosim_hir::csp_names::{CspKind, CspNames, CspType, TypeDef};
use rustc_hash::FxHashMap;

use crate::ir::Dom;

/// The most values a field's set may have.
const MAX_VALUES: usize = 100_000;

/// The largest type whose subsets are a field's values (`Set(T)`).
const MAX_SET_ELEMENTS: usize = 10;

/// The lookup over the names table.
pub(crate) struct Host<'a> {
    /// The table.
    pub names: &'a CspNames,
    /// Channels whose field values the element under check fixes.
    pub own: FxHashMap<String, Vec<Vec<Value>>>,
    /// `core_nat`, `core_int`, `core_real`: the element's domains.
    pub domains: FxHashMap<String, Dom>,
    /// Generated processes the bridge gives (see [`super::native::processes`]):
    /// arity and LTS.
    pub processes: FxHashMap<String, (usize, robosim_cspm::BuildLts)>,
    /// Only resolving names: every generated process of a RoboChart
    /// element is known (with a placeholder LTS).
    pub resolve_only: bool,
    /// The timed script: `tock` is declared (RoboTool's untimed script has
    /// no `tock`, RT-9).
    pub timed: bool,
}

impl<'a> Host<'a> {
    /// The lookup for resolving names only.
    pub(crate) fn resolving(names: &'a CspNames, timed: bool) -> Host<'a> {
        Host {
            names,
            own: FxHashMap::default(),
            domains: FxHashMap::default(),
            processes: FxHashMap::default(),
            resolve_only: true,
            timed,
        }
    }
}

/// Whether the bridge can give the generated process `name`: `M::D__`
/// and `M::O__` of a RoboChart element.
fn givable(names: &CspNames, name: &str) -> bool {
    let Some((module, p)) = name.rsplit_once("::") else { return false };
    matches!(p, "D__" | "O__") && names.element(module).is_some_and(|e| !e.robosim)
}

fn ints(d: Dom) -> Vec<Value> {
    (d.lo..=d.hi).map(Value::Int).collect()
}

fn set(vs: Vec<Value>) -> Value {
    Value::Set(Rc::new(vs.into_iter().collect::<BTreeSet<_>>()))
}

/// Every tuple of one value of each of `parts`.
pub(crate) fn product(parts: &[Vec<Value>]) -> Option<Vec<Value>> {
    let mut out: Vec<Vec<Value>> = vec![Vec::new()];
    for p in parts {
        if out.len().checked_mul(p.len())? > MAX_VALUES {
            return None;
        }
        out = out.iter().flat_map(|prefix| p.iter().map(move |v| [prefix.clone(), vec![v.clone()]].concat())).collect();
    }
    Some(out.into_iter().map(|vs| Value::Tuple(vs.into())).collect())
}

impl Host<'_> {
    /// The default bounds of a number type (RT-5), or the element's.
    fn dom(&self, core: &str) -> Dom {
        if let Some(d) = self.domains.get(core) {
            return *d;
        }
        match core {
            "core_nat" => Dom { lo: 0, hi: 2 },
            "core_clock_type" => Dom { lo: 0, hi: 10 },
            _ => Dom { lo: -2, hi: 2 },
        }
    }

    /// The values of `t`, if this bridge can enumerate them.
    pub(crate) fn values(&self, t: &CspType) -> Option<Vec<Value>> {
        Some(match t {
            CspType::Nat => ints(self.dom("core_nat")),
            CspType::Int => ints(self.dom("core_int")),
            CspType::Real => ints(self.dom("core_real")),
            CspType::Clock => ints(self.dom("core_clock_type")),
            CspType::Bool => vec![Value::Bool(false), Value::Bool(true)],
            CspType::InOut => vec![Value::Ctor("in".into()), Value::Ctor("out".into())],
            CspType::Tuple(ts) => product(&ts.iter().map(|t| self.values(t)).collect::<Option<Vec<_>>>()?)?,
            CspType::Named(n) => self.type_values(n)?,
            // Every subset of a small type (`Set(Skills)`).
            CspType::Set(t) => {
                let el = self.values(t)?;
                if el.len() > MAX_SET_ELEMENTS {
                    return None;
                }
                (0u32..1 << el.len())
                    .map(|bits| {
                        set(el.iter().enumerate().filter(|(i, _)| bits >> i & 1 == 1).map(|(_, v)| v.clone()).collect())
                    })
                    .collect()
            }
            CspType::Str | CspType::Seq(_) | CspType::Other(_) => return None,
        })
    }

    fn type_values(&self, name: &str) -> Option<Vec<Value>> {
        match &self.names.get(name)?.kind {
            CspKind::Type(TypeDef::Core) => match name {
                "core_boolean" => self.values(&CspType::Bool),
                "core_string" => None,
                n => Some(ints(self.dom(n))),
            },
            // RT-3.
            CspKind::Type(TypeDef::Primitive) => Some(ints(Dom { lo: 0, hi: 1 })),
            CspKind::Type(TypeDef::Enumeration(lits)) => {
                Some(lits.iter().map(|l| Value::Ctor(l.as_str().into())).collect())
            }
            CspKind::Type(TypeDef::Record(fields)) => {
                product(&fields.iter().map(|t| self.values(t)).collect::<Option<Vec<_>>>()?)
            }
            _ => None,
        }
    }

    /// A constant's value: its initialiser when it is a literal, else its
    /// type's default (RT-1: 0, the first literal, `true`).
    fn constant(&self, ty: &CspType, init: Option<&str>) -> Option<Value> {
        if let Some(init) = init {
            return match init {
                "true" => Some(Value::Bool(true)),
                "false" => Some(Value::Bool(false)),
                s => s.parse::<i64>().ok().map(Value::Int),
            };
        }
        match ty {
            CspType::Bool => Some(Value::Bool(true)),
            CspType::Named(n) => match &self.names.get(n)?.kind {
                CspKind::Type(TypeDef::Enumeration(lits)) => lits.first().map(|l| Value::Ctor(l.as_str().into())),
                CspKind::Type(TypeDef::Primitive) => Some(Value::Int(0)),
                CspKind::Type(TypeDef::Core) if n == "core_boolean" => Some(Value::Bool(true)),
                CspKind::Type(TypeDef::Core) => Some(Value::Int(0)),
                // A record: each field's default (RT-1), as the bridge
                // writes record values (the tuple of the fields), so that
                // `M::D__(…, const_M_r)` is applied to the value the
                // native LTS was compiled with.
                CspKind::Type(TypeDef::Record(fields)) => {
                    let vs = fields.iter().map(|t| self.constant(t, None)).collect::<Option<Vec<_>>>()?;
                    Some(Value::Tuple(vs.into()))
                }
                _ => None,
            },
            CspType::Nat | CspType::Int | CspType::Real | CspType::Clock => Some(Value::Int(0)),
            _ => None,
        }
    }

    /// Why a name the table knows cannot be given to a block, if so.
    pub(crate) fn unsupported(&self, name: &str) -> Option<String> {
        if self.own.contains_key(name) {
            return None;
        }
        let entry = self.names.get(name)?;
        let what = match &entry.kind {
            CspKind::Process { .. } if givable(self.names, name) => return None,
            CspKind::Process { .. } => {
                "a process RoboTool generates for a model element (the bridge gives `M::D__` and `M::O__` of \
                 RoboChart elements)"
            }
            CspKind::EventSet => "the set of an element's visible events (`sem__events`)",
            CspKind::Register { .. } => {
                "a register of a RoboSim element other than the one checked (the bridge gives the registers of the \
                 element under check)"
            }
            CspKind::Channel { .. } if register_channel(name) => {
                "the register channel of a RoboSim element other than the one checked (the bridge gives the \
                 registers of the element under check)"
            }
            CspKind::Module => "a CSPm module of the model",
            CspKind::Channel { .. } | CspKind::Constant { .. } | CspKind::Type(_) | CspKind::Literal { .. } => {
                if self.lookup(name).is_some() {
                    return None;
                }
                "a name whose values the native checker cannot enumerate (strings, sequences, functions, sets of more than 10 values)"
            }
        };
        Some(format!("`{name}` is {what}: the CSPm bridge does not support it here yet"))
    }
}

impl Host<'_> {
    /// Whether the event `v` of a specification is one of its channel's
    /// (the evaluator builds dotted values without checking them against
    /// the channel's fields, as FDR's type checker would).
    pub(crate) fn check_event(&self, v: &Value) -> Result<(), String> {
        let (chan, args) = match v {
            Value::Dot(parts) => match parts.first() {
                Some(Value::Ctor(c)) => (c.to_string(), &parts[1..]),
                _ => return Ok(()),
            },
            _ => return Ok(()),
        };
        if let Some(CspKind::Register { input, .. }) = self.names.get(&chan).map(|n| &n.kind) {
            // A register constructor is a value of `M::registerRead`
            // (`M::registerWrite`), not a channel: FDR's type checker
            // rejects it as an event.
            let (module, _) = chan.rsplit_once("::").unwrap_or_default();
            let via = if *input { "registerRead" } else { "registerWrite" };
            return Err(format!(
                "FDR stops with an error: `{v}` is not an event: `{chan}` is a register, a value of \
                 `{module}::{via}` (write `{module}::{via}.{v}`)"
            ));
        }
        let Some(ExternalName::Channel(fields)) = self.lookup(&chan) else { return Ok(()) };
        if fields.len() != args.len() {
            return Err(format!("the specification's event `{v}` is not an event of `{chan}`"));
        }
        for (i, (set, a)) in fields.iter().zip(args).enumerate() {
            if !set.contains(a) {
                // FDR's evaluator stops on such a value with this message
                // (libcspm's `dotIsNotValidMessage`): no verdict.
                let shown: Vec<String> = set.iter().take(12).map(|x| x.to_string()).collect();
                let more = if set.len() > 12 { ", …" } else { "" };
                return Err(format!(
                    "FDR stops with an error: the value `{v}` is invalid as it is not within the set of values \
                     defined for the channel `{chan}`; in particular its field {} `{a}` is not a member of the set \
                     {{{}{more}}} (the model's values: a value outside the model's domain)",
                    i + 1,
                    shown.join(", ")
                ));
            }
        }
        Ok(())
    }
}

impl NameLookup for Host<'_> {
    fn lookup(&self, name: &str) -> Option<ExternalName> {
        match name {
            "tock" => return self.timed.then(|| ExternalName::Channel(Vec::new())),
            "in" | "out" => return Some(ExternalName::Value(Value::Ctor(name.into()))),
            "InOut" => return Some(ExternalName::Value(set(self.values(&CspType::InOut)?))),
            _ => {}
        }
        if let Some(fields) = self.own.get(name) {
            return Some(ExternalName::Channel(fields.clone()));
        }
        match &self.names.get(name)?.kind {
            CspKind::Channel { .. } if register_channel(name) => {
                self.resolve_only.then(|| self.register_channel_field(name)).flatten().map(ExternalName::Channel)
            }
            CspKind::Channel { fields } => {
                let fields = fields.iter().map(|t| self.values(t)).collect::<Option<Vec<_>>>()?;
                Some(ExternalName::Channel(fields))
            }
            CspKind::Constant { ty, init } => self.constant(ty, init.as_deref()).map(ExternalName::Value),
            CspKind::Type(_) => Some(ExternalName::Value(set(self.type_values(name)?))),
            CspKind::Literal { .. } => Some(ExternalName::Value(Value::Ctor(name.into()))),
            CspKind::Process { params } => {
                if let Some((arity, build)) = self.processes.get(name) {
                    return Some(ExternalName::Process { arity: *arity, build: build.clone() });
                }
                (self.resolve_only && givable(self.names, name)).then(|| ExternalName::Process {
                    arity: params.len(),
                    build: Rc::new(|_: &[Value]| Err("not compiled".to_string())),
                })
            }
            // Registers of the element under check are in `own`; others'
            // are only resolved (see `Host::resolve_only`).
            CspKind::Register { .. } if self.resolve_only => Some(ExternalName::Channel(self.register_fields(name)?)),
            CspKind::Module | CspKind::Register { .. } | CspKind::EventSet => None,
        }
    }
}

/// Whether `name` is a RoboSim element's `M::registerRead` or
/// `M::registerWrite`.
fn register_channel(name: &str) -> bool {
    name.ends_with("::registerRead") || name.ends_with("::registerWrite")
}

impl Host<'_> {
    /// Makes the element's register constructors (`M::i_x`, `M::o_x`)
    /// known to `ev` with their fields, so that the dotted values of
    /// `M::registerRead` it builds (`M::registerRead.M::i_x.true.1`) are
    /// complete events, whether or not the script names the constructor
    /// on its own (`{| M::registerRead |}`).
    pub(crate) fn declare_registers(&self, ev: &mut robosim_cspm::Evaluator<'_>) {
        let mut regs: Vec<&String> = self
            .own
            .keys()
            .filter(|n| matches!(self.names.get(n).map(|e| &e.kind), Some(CspKind::Register { .. })))
            .collect();
        regs.sort();
        for r in regs {
            let _ = ev.value(r);
        }
    }

    /// The fields of the register constructor `reg` (`M::i_x`, `M::o_x`)
    /// by the table's types: an input's presence flag, then its value or
    /// its operation's parameters. (A variable's input register has no
    /// flag: the table cannot tell, so this is for resolving names only;
    /// the element under check gives its registers exactly.)
    fn register_fields(&self, reg: &str) -> Option<Vec<Vec<Value>>> {
        let CspKind::Register { input, ty } = &self.names.get(reg)?.kind else { return None };
        let (module, x) = reg.rsplit_once("::")?;
        let types = match ty {
            Some(t) => vec![t.clone()],
            None => match self.names.get(&format!("{module}::{}Call", x.get(2..)?)).map(|n| &n.kind) {
                Some(CspKind::Channel { fields }) => fields.clone(),
                _ => Vec::new(),
            },
        };
        let mut fields = if *input { vec![self.values(&CspType::Bool)?] } else { Vec::new() };
        for t in &types {
            fields.push(self.values(t)?);
        }
        Some(fields)
    }

    /// `M::registerRead`'s (`M::registerWrite`'s) one field when resolving
    /// names: every value of every input (output) register of `M`.
    fn register_channel_field(&self, name: &str) -> Option<Vec<Vec<Value>>> {
        let (module, chan) = name.rsplit_once("::")?;
        let (prefix, input) = if chan == "registerRead" { ("i_", true) } else { ("o_", false) };
        let mut all = Vec::new();
        for n in self.names.iter() {
            let Some(rest) = n.name.strip_prefix(module).and_then(|r| r.strip_prefix("::")) else { continue };
            if !rest.starts_with(prefix) || rest.contains("::") {
                continue;
            }
            if !matches!(n.kind, CspKind::Register { input: i, .. } if i == input) {
                continue;
            }
            let fields = self.register_fields(&n.name)?;
            let mut parts = vec![vec![Value::Ctor(n.name.as_str().into())]];
            parts.extend(fields);
            for t in product(&parts)? {
                let Value::Tuple(vs) = t else { continue };
                all.push(if vs.len() == 1 { vs[0].clone() } else { Value::Dot(vs.iter().cloned().collect()) });
            }
        }
        Some(vec![all])
    }
}
