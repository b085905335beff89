//! What an assertion checks: the element each side names (a `simulation`,
//! a RoboSim module, controller or machine, or a RoboChart design), the
//! period it is simulated with, the constants its `with` clause binds, and
//! the semantics it is checked in (RT-8: timed, untimed, or both).
//!
//! This is the one reading of an assertion's subject: the native checker
//! and the CSPm export both ask here, so they cannot resolve a name or
//! choose a period differently.

use crate::assertions::{AssertionDecl, AssertionFile, Override, Value};
use crate::cycle::{simulation_period, Feasibility};
use crate::defs::{file_defs, DefId, DefKind};
use crate::index::{resolve_item, ItemLoc};
use crate::{Db, File, FileKind, Workspace};

/// An element an assertion names, and how it is checked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Subject {
    /// `simulation S of M`: the RoboChart element `M` under the
    /// simulation assumptions with period `period`.
    Constrained {
        /// The simulation's name.
        name: String,
        /// The assertion file that declares the simulation.
        sim_file: File,
        /// The RoboChart module, controller or machine simulated.
        loc: ItemLoc,
        /// Its period (`cycleDef` of the simulation, or of the assertion).
        period: Option<i64>,
    },
    /// A RoboSim module, controller or machine, with its period; with
    /// `inner`, the machine of that name declared inside the controller
    /// `loc`.
    Simulation {
        /// The name as written.
        name: String,
        /// The element (the controller, for an inner machine).
        loc: ItemLoc,
        /// The machine declared inside the controller `loc`, if any.
        inner: Option<String>,
        /// Its period: the assertion's `cycleDef of`, else the least its
        /// cycleDefs admit ([`simulation_period`]).
        period: Option<i64>,
    },
    /// A RoboChart module, controller or machine on its own; with `inner`,
    /// the machine of that name declared inside the controller `loc`.
    Design {
        /// The name as written.
        name: String,
        /// The element (the controller, for an inner machine).
        loc: ItemLoc,
        /// The machine declared inside the controller `loc`, if any.
        inner: Option<String>,
    },
}

impl Subject {
    /// The name as written in the assertion.
    pub fn name(&self) -> &str {
        match self {
            Subject::Constrained { name, .. } | Subject::Simulation { name, .. } | Subject::Design { name, .. } => name,
        }
    }
}

/// A constant's value given by an assertion's `with constant k of X set to
/// v` (booleans as 0 and 1).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Binding {
    /// The constant's name.
    pub name: String,
    /// The element it belongs to, as written.
    pub of: Vec<String>,
    /// The value.
    pub value: i64,
}

/// The semantics an assertion is checked in (RT-8): a plain `assertion`
/// in both the untimed and the timed semantics, `timed assertion` only in
/// the timed one, `untimed assertion` only in the untimed one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Timing {
    /// Checked in the timed semantics.
    pub timed: bool,
    /// Checked in the untimed semantics.
    pub untimed: bool,
}

/// The semantics of `a` (RT-8).
pub fn timing(a: &AssertionDecl) -> Timing {
    match a.timed {
        Some(true) => Timing { timed: true, untimed: false },
        Some(false) => Timing { timed: false, untimed: true },
        None => Timing { timed: true, untimed: true },
    }
}

/// The constants `a` binds, or what is wrong with a value.
pub fn bindings(a: &AssertionDecl) -> Result<Vec<Binding>, String> {
    let mut out = Vec::new();
    for o in &a.overrides {
        if let Override::Constant { name, of, value, .. } = o {
            let value = match value {
                Value::Int(v) => *v,
                Value::Bool(b) => i64::from(*b),
                Value::Other(_) => {
                    return Err(format!("the value of constant `{name}` is not an integer or boolean literal"))
                }
            };
            out.push(Binding { name: name.clone(), of: of.clone(), value });
        }
    }
    Ok(out)
}

/// Everything an assertion's sides are read in: the workspace, the
/// assertion file (`read`, the file `file`) and the workspace's other
/// assertion files (their simulations are visible too).
#[derive(Clone, Copy)]
pub struct Scope<'a> {
    /// The database.
    pub db: &'a dyn Db,
    /// The workspace.
    pub ws: Workspace,
    /// The assertion file.
    pub file: File,
    /// It, read.
    pub read: &'a AssertionFile,
    /// The other assertion files, read.
    pub others: &'a [(File, AssertionFile)],
}

/// What `path`, one side of assertion `a`, denotes; or why it cannot be
/// checked, in words for the user.
pub fn subject(scope: Scope<'_>, a: &AssertionDecl, path: &[String]) -> Result<Subject, String> {
    let Scope { db, ws, file, read, others } = scope;
    let name = path.join("::");
    let sim = read
        .simulation(&name)
        .map(|s| (file, s))
        .or_else(|| others.iter().find_map(|(f, r)| r.simulation(path.last()?).map(|s| (*f, s))));
    let overridden = a.overrides.iter().find_map(|o| match o {
        Override::CycleDef { of, value, .. } if of.last() == path.last() => Some(value.as_int()),
        _ => None,
    });
    let element = |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
    if let Some((sim_file, sim)) = sim {
        let loc = resolve_item(db, ws, sim_file, &sim.of, element)
            .into_iter()
            .next()
            .ok_or_else(|| format!("`{}` is not a RoboChart module, controller or machine", sim.of.join("::")))?;
        let period = overridden.unwrap_or_else(|| sim.cycle.as_ref().and_then(Value::as_int));
        return Ok(Subject::Constrained { name: sim.name.clone(), sim_file, loc, period });
    }
    let bound = bindings(a).unwrap_or_default();
    if let Some((ctrl, machine)) = inline_machine(db, ws, file, path) {
        let inner = path.last().cloned();
        if ctrl.file.kind(db) != FileKind::RoboSim {
            return Ok(Subject::Design { name, loc: ctrl, inner });
        }
        let period = match overridden {
            Some(p) => p,
            None => robosim_period(db, ws, &name, ctrl.file, machine, &bound)?,
        };
        return Ok(Subject::Simulation { name, loc: ctrl, inner, period });
    }
    let loc = resolve_item(db, ws, file, path, element).into_iter().next().ok_or_else(|| {
        let csp = std::iter::once(read)
            .chain(others.iter().map(|(_, r)| r))
            .any(|r| path.last().is_some_and(|n| r.csp_block(n).is_some()));
        if csp {
            format!("`{name}` is defined in a `csp` block: raw CSPm is not verifiable natively (check it with FDR)")
        } else {
            format!("`{name}` is not a simulation, module, controller or machine")
        }
    })?;
    if loc.file.kind(db) != FileKind::RoboSim {
        return Ok(Subject::Design { name, loc, inner: None });
    }
    let period = match (overridden, loc.def(db)) {
        (Some(p), _) => p,
        (None, Some(def)) => robosim_period(db, ws, &name, loc.file, def, &bound)?,
        (None, None) => None,
    };
    Ok(Subject::Simulation { name, loc, inner: None, period })
}

/// The period of the RoboSim element `def` of `file` with the constants
/// `bound`: the least its cycleDef and its components' admit; `None` when
/// nothing declares one.
fn robosim_period(
    db: &dyn Db,
    ws: Workspace,
    name: &str,
    file: File,
    def: DefId,
    bound: &[Binding],
) -> Result<Option<i64>, String> {
    let bound: Vec<(String, i64)> = bound.iter().map(|b| (b.name.clone(), b.value)).collect();
    match simulation_period(db, ws, file, def, &bound) {
        None => Ok(None),
        Some(Feasibility::Feasible(p)) => Ok(i64::try_from(p).ok()),
        Some(Feasibility::Infeasible) => Err(format!(
            "no positive period satisfies the cycleDef of `{name}` together with those of its components \
             (RS:M2/RS:C2): give them a common period"
        )),
        Some(Feasibility::Unknown) => Err(format!(
            "the period of `{name}` could not be decided from its cycleDefs: give one with `cycleDef cycle == N`"
        )),
    }
}

/// The controller `C` and its machine `M` when `path` is `C::M` and `C`
/// declares `M` in its own body.
fn inline_machine(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<(ItemLoc, DefId)> {
    let (last, prefix) = path.split_last()?;
    let controller = resolve_item(db, ws, file, prefix, |k| k == DefKind::Controller);
    controller.into_iter().find_map(|loc| {
        let id = loc.def(db)?;
        let defs = file_defs(db, loc.file);
        let machine = defs
            .children(Some(id))
            .find(|(_, d)| d.kind == DefKind::StateMachine && d.name == *last)
            .map(|(m, _)| m)?;
        Some((loc, machine))
    })
}
