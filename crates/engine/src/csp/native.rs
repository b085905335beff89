//! Model elements as the CSPm side sees them: an element an assertion or
//! a block names, compiled natively, its events named as RoboTool names
//! them; and, for a block that applies a generated process (`M::O__(…)`),
//! the element's LTS made explicit for the CSPm evaluator.

use std::rc::Rc;

use robosim_cspm::{BuildLts, Label as CspLabel, Value};
use robosim_hir::csp_names::{CspElement, CspNames};
use robosim_hir::defs::DefKind;
use robosim_hir::target::Subject as Target;
use rustc_hash::FxHashMap;

use crate::design::{shared_events, DesignLts};
use crate::ir::{Design, Val};
use crate::lower::ConstValue;
use crate::lts::{Event, Lts, FIRST_VISIBLE, TAU, TICK, TOCK};
use crate::pack::{Encoding, VectorLts, Vectors};
use crate::sched::{Profile, Registers};
use crate::sim::SimModule;
use crate::verify::Cx;

use super::events::{design_names, sim_names, Names, OwnChannels};
use super::lts::Imp;

/// An element compiled for the bridge.
pub(crate) struct Compiled<'n> {
    /// Its names.
    pub element: &'n CspElement,
    /// The compiled design.
    pub design: Design,
    /// Its events' CSPm names (and the other side's, once mapped).
    pub ids: Names,
    /// The value sets of its channels' fields.
    pub own: OwnChannels,
    /// The CSPm value of each native event from `FIRST_VISIBLE` on.
    pub values: Vec<Option<Value>>,
    /// Read in RoboChart's untimed semantics (RT-9): no `tock`.
    pub untimed: bool,
    /// A RoboSim element: its cycle period and register events.
    pub sim: Option<(u32, Registers)>,
}

impl Compiled<'_> {
    /// Whether the bridge adds RoboTool's `M::terminate` before ✓: a
    /// RoboChart controller's or machine's process shows it (its
    /// `sem__events` hold it), a module's does not. A RoboSim element's
    /// LTS has its own `terminate` (visible or not, RT-21).
    pub fn shows_terminate(&self) -> bool {
        self.sim.is_none() && matches!(self.element.kind, DefKind::Controller | DefKind::StateMachine)
    }

    /// The element's LTS in the semantics checked.
    pub fn lts(&self) -> Result<NativeLts<'_>, String> {
        if let Some((period, regs)) = &self.sim {
            // RT-21 in RoboTool 3's reading: the profile whose names
            // (`registerRead.i_x`) the generated CSPm has.
            return Ok(NativeLts::Sim(SimModule::with_profile(&self.design, *period, regs, Profile::RoboTool3)?));
        }
        let lts = DesignLts::new(&self.design)?;
        Ok(NativeLts::Design(if self.untimed { lts.without_time() } else { lts }))
    }
}

/// The native LTS of a compiled element: a RoboChart design, or a RoboSim
/// module, controller or machine with its cycles.
pub(crate) enum NativeLts<'a> {
    /// A RoboChart element.
    Design(DesignLts<'a>),
    /// A RoboSim element.
    Sim(SimModule<'a>),
}

impl NativeLts<'_> {
    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        match self {
            NativeLts::Design(l) => l.error(),
            NativeLts::Sim(l) => l.error(),
        }
    }
}

impl VectorLts for NativeLts<'_> {
    fn encoding(&self) -> &Encoding {
        match self {
            NativeLts::Design(l) => l.encoding(),
            NativeLts::Sim(l) => l.encoding(),
        }
    }

    fn initial_values(&self) -> Box<[i32]> {
        match self {
            NativeLts::Design(l) => l.initial_values(),
            NativeLts::Sim(l) => l.initial_values(),
        }
    }

    fn successor_values(&self, st: &[i32], out: &mut Vectors) {
        match self {
            NativeLts::Design(l) => l.successor_values(st, out),
            NativeLts::Sim(l) => l.successor_values(st, out),
        }
    }
}

/// The element `path` names (an assertion's side), with constants
/// `consts`.
pub(crate) fn compile<'n>(
    cx: &Cx<'_>,
    names: &'n CspNames,
    path: &[String],
    consts: &[ConstValue],
    types: &[(String, Val, Val)],
) -> Result<Compiled<'n>, String> {
    let target = cx.target(path)?;
    let (loc, inner) = match &target {
        Target::Design { loc, inner, .. } | Target::Simulation { loc, inner, .. } => (loc, inner),
        Target::Constrained { .. } => {
            return Err(format!(
                "`{}` is a simulation of a RoboChart element (`simulation … of …`): RoboTool generates no CSPm \
                 module for it, so a `csp` block cannot be checked against it",
                path.join("::")
            ))
        }
        Target::SimOperation { .. } => {
            return Err(format!(
                "`{}` is a RoboSim operation: the CSPm bridge checks RoboChart and RoboSim modules, controllers \
                 and machines so far",
                path.join("::")
            ))
        }
    };
    let robosim = matches!(target, Target::Simulation { .. });
    // The element, found by its declaration.
    let decl_range = loc.def(cx.db).map(|d| robosim_hir::defs::file_defs(cx.db, loc.file).def(d).name_range);
    let outer = names.elements().iter().find(|e| e.decl.file == loc.file && Some(e.decl.range) == decl_range);
    let element = match (outer, inner) {
        (Some(o), Some(m)) => {
            let mut p = o.path.clone();
            p.push(m.clone());
            names.element_by_path(&p)
        }
        (o, None) => o,
        _ => None,
    }
    .ok_or_else(|| format!("`{}` has no name in RoboTool's CSPm", path.join("::")))?;
    let (design, period) = cx.compile_with_types(&target, consts, types)?;
    let untimed = cx.semantics == crate::untimed::Semantics::Untimed;
    if robosim {
        if untimed {
            // RT-8: RoboTool generates a timed script only for RoboSim.
            return Err(format!("`{}` is a RoboSim element: it has a timed semantics only", path.join("::")));
        }
        let regs = Registers::new(&[&design], Profile::RoboTool3)?;
        let lts = SimModule::with_profile(&design, period, &regs, Profile::RoboTool3)?;
        let (ids, own, values) = sim_names(&design, &lts.encoding().events, &element.module, names)?;
        drop(lts);
        return Ok(Compiled { element, design, ids, own, values, untimed, sim: Some((period, regs)) });
    }
    // RT-8: in the untimed semantics, the element as RoboTool's untimed
    // script has it (RT-9).
    let design = cx.in_semantics(design)?;
    let table = shared_events(&[&design])?;
    let (ids, own, values) = design_names(&design, &table, &element.module, names)?;
    Ok(Compiled { element, design, ids, own, values, untimed, sim: None })
}

/// The element's LTS, explored in full (at most `max_states` states),
/// with its events as CSPm values.
pub(crate) fn explicit(c: &mut Compiled<'_>, max_states: usize) -> Result<robosim_cspm::Lts, String> {
    let terminate = c.shows_terminate().then(|| c.ids.id(&format!("{}::terminate", c.element.module)));
    let native = c.lts()?;
    let imp = Imp { inner: &native, terminate, names: &c.ids, tau_priority: c.sim.is_some() };
    let mut events: Vec<Value> = Vec::new();
    let mut event_ix: FxHashMap<Event, u32> = FxHashMap::default();
    let mut label = |e: Event| -> Result<CspLabel, String> {
        Ok(match e {
            TAU => CspLabel::Tau,
            TICK => CspLabel::Tick,
            e => {
                if let Some(&i) = event_ix.get(&e) {
                    return Ok(CspLabel::Event(i));
                }
                let v = if e == TOCK {
                    Value::Ctor("tock".into())
                } else if Some(e) == terminate {
                    Value::Ctor(format!("{}::terminate", c.element.module).into())
                } else {
                    c.values.get((e - FIRST_VISIBLE) as usize).cloned().flatten().ok_or_else(|| {
                        format!("the model's event `{}` has no name in RoboTool's CSPm", c.ids.name(e))
                    })?
                };
                let i = events.len() as u32;
                events.push(v);
                event_ix.insert(e, i);
                CspLabel::Event(i)
            }
        })
    };
    let mut ids = FxHashMap::default();
    let mut states = vec![imp.initial()];
    ids.insert(states[0].clone(), 0u32);
    let mut transitions = Vec::new();
    let mut succ = Vec::new();
    let mut i = 0;
    while i < states.len() {
        succ.clear();
        imp.successors(&states[i], &mut succ);
        let mut out = Vec::new();
        for (l, t) in succ.drain(..) {
            let id = match ids.get(&t) {
                Some(&id) => id,
                None => {
                    if states.len() >= max_states {
                        return Err(format!(
                            "`{}` has more than {max_states} states: too many to apply it inside CSPm",
                            c.element.module
                        ));
                    }
                    let id = states.len() as u32;
                    ids.insert(t.clone(), id);
                    states.push(t);
                    id
                }
            };
            out.push((label(l.event)?, id));
        }
        out.sort_unstable();
        out.dedup();
        transitions.push(out);
        i += 1;
    }
    if let Some(err) = native.error() {
        return Err(format!("the model met a run-time error: {err}"));
    }
    Ok(robosim_cspm::Lts {
        events: events.iter().map(|v| v.to_string()).collect(),
        event_values: events,
        initial: 0,
        transitions,
    })
}

/// The generated processes a script applies that the bridge can give:
/// `M::D__` and `M::O__` of RoboChart elements, with the model's constant
/// values (the arguments must be those values).
pub(crate) fn processes(
    cx: &Cx<'_>,
    names: &CspNames,
    text: &str,
    constant: &dyn Fn(&str) -> Option<Value>,
    types: &[(String, Val, Val)],
    max_states: usize,
) -> Result<FxHashMap<String, (usize, BuildLts)>, String> {
    let mut out = FxHashMap::default();
    for el in names.elements() {
        for p in ["D__", "O__"] {
            let name = format!("{}::{p}", el.module);
            if !mentions_qualified(text, &name) {
                continue;
            }
            if el.robosim {
                return Err(format!("`{name}` is a RoboSim process: the CSPm bridge gives RoboChart ones so far"));
            }
            let mut c = compile(cx, names, &el.path, &[], types).map_err(|e| format!("`{name}`: {e}"))?;
            let lts = Rc::new(explicit(&mut c, max_states)?);
            let expected: Vec<Value> = el
                .constants
                .iter()
                .map(|k| constant(k).ok_or_else(|| format!("`{name}`: no value for `{k}`")))
                .collect::<Result<_, _>>()?;
            let shown = name.clone();
            let build: BuildLts = Rc::new(move |args: &[Value]| {
                if args.get(1..) != Some(&expected[..]) {
                    return Err(format!(
                        "`{shown}` is applied to constant values other than the model's ({}): the CSPm bridge \
                         compiles elements with the model's values only",
                        expected.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
                    ));
                }
                Ok((*lts).clone())
            });
            out.insert(name, (1 + el.constants.len(), build));
        }
    }
    Ok(out)
}

/// Whether the qualified name `name` occurs in `text` on its own (not as
/// the end of a longer path: `M::O__` is not in `p::M::O__`).
fn mentions_qualified(text: &str, name: &str) -> bool {
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + name.len()..].chars().next();
        let part = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '\'' || c == ':');
        !part(before) && !part(after)
    })
}
