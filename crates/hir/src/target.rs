//! What an assertion checks: the element each side names (a `simulation`,
//! a RoboSim module, controller or machine, or a RoboChart design), the
//! period it is simulated with, the constants its `with` clause binds, and
//! the semantics it is checked in (RT-8: timed, untimed, or both).
//!
//! This is the one reading of an assertion's subject: the native checker
//! and the CSPm export both ask here, so they cannot resolve a name or
//! choose a period differently.

mod states;

pub use states::{design_machines, match_state, names_machine, state, MachineStates, StateMatch, StateNode, StateRef};

use crate::assertions::{AssertionDecl, AssertionFile, Override, Value};
use crate::cycle::{simulation_period, Feasibility};
use crate::defs::{file_defs, DefData, DefId, DefKind, UseKind};
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
    /// RT-11: a RoboSim operation checked on its own, as RoboTool's
    /// `OP_…::O__(id__, params)`: the top-level operation `loc`, or with
    /// `inner` the one of that name declared inside the controller `loc`
    /// (an operation reference is the operation it references).
    SimOperation {
        /// The name as written.
        name: String,
        /// The operation (the controller, for an inner one).
        loc: ItemLoc,
        /// The operation declared inside the controller `loc`, if any.
        inner: Option<String>,
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
            Subject::Constrained { name, .. }
            | Subject::Simulation { name, .. }
            | Subject::SimOperation { name, .. }
            | Subject::Design { name, .. } => name,
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

/// The constants `a` binds, read in `scope`: as [`bindings`], and an
/// enumeration literal (`set to IType::L2`, RT-11) as its index in its
/// enumeration, the order RoboTool's constructors and the checker's values
/// follow. Every constant of that name in the workspace must be of that
/// enumeration (a value of another type is refused, not converted).
pub fn bindings_in(scope: Scope<'_>, a: &AssertionDecl) -> Result<Vec<Binding>, String> {
    let mut out = Vec::new();
    for o in &a.overrides {
        if let Override::Constant { name, of, value, .. } = o {
            let value = match value {
                Value::Int(v) => *v,
                Value::Bool(b) => i64::from(*b),
                Value::Other(text) => enum_literal(scope, name, text)?,
            };
            out.extend(spread(scope, Binding { name: name.clone(), of: of.clone(), value })?);
        }
    }
    Ok(out)
}

/// What the `X` of `with constant z of X` names.
pub enum Owner {
    /// A module, controller or state machine (also through an instance
    /// path, or by a simple name no import reaches).
    Element(ItemLoc),
    /// A `simulation` of an assertion file.
    Simulation,
}

/// The element `of` names in `with constant z of of` ([`spread`] reads
/// it; the checker's LNK-01 asks it too); `None` when it names nothing
/// the checker reads.
pub fn constant_owner(scope: Scope<'_>, of: &[String]) -> Option<Owner> {
    let Scope { db, ws, file, read, others } = scope;
    let element = |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
    let resolved = resolve_item(db, ws, file, of, element).into_iter().next().or_else(|| {
        // An instance path (`Mod::c`, `Ctl::s`) names the element it
        // references.
        match instance(db, ws, file, of) {
            Some(Ok((loc, None))) => Some(loc),
            _ => None,
        }
    });
    // RoboTool also reads a plain name no import reaches (LNK-02), as the
    // checker matches the binding by the element's name.
    let resolved = resolved.or_else(|| {
        let [n] = of else { return None };
        ws.files(db).iter().filter(|f| !f.is_library(db)).find_map(|&file| {
            let items = &crate::index::file_summary(db, file).items;
            let index = items.iter().position(|i| element(i.kind) && i.name == *n)?;
            Some(ItemLoc { file, index: index as u32 })
        })
    });
    if let Some(loc) = resolved {
        return Some(Owner::Element(loc));
    }
    let simulation = matches!(of, [n]
        if std::iter::once(read).chain(others.iter().map(|(_, r)| r)).any(|r| r.simulation(n).is_some()));
    simulation.then_some(Owner::Simulation)
}

/// RT-11: in `with constant z of X`, `X` may be the machine, the
/// controller that requires `z`, or the module whose platform provides it.
/// The binding as the checker reads it: one per machine that has `z` from
/// `X`, named by its declaration. A RoboChart `X` through which no machine
/// has `z` is an error (never silently a default); other `X` (RoboSim,
/// unresolved) are left as written.
fn spread(scope: Scope<'_>, b: Binding) -> Result<Vec<Binding>, String> {
    let Scope { db, ws, .. } = scope;
    let loc = match constant_owner(scope, &b.of) {
        Some(Owner::Element(loc)) => loc,
        // A simulation of an assertion file is read by the RoboSim
        // checker.
        Some(Owner::Simulation) => return Ok(vec![b]),
        // Anything else names nothing, and the value would be silently
        // dropped.
        None => {
            return Err(format!(
                "`{}` is not a module, controller or state machine: `with constant {} of X` names the machine, \
                 the controller that requires `{}`, or the module whose platform provides it",
                b.of.join("::"),
                b.name,
                b.name
            ))
        }
    };
    let Some(id) = loc.def(db) else { return Ok(vec![b]) };
    if loc.file.kind(db) != FileKind::RoboChart {
        // RoboSim: the binding is read by the element's name; one that no
        // part of the element declares would be silently dropped.
        if !has_constant(db, ws, loc.file, id, &b.name) {
            return Err(format!(
                "`{}` has no constant `{}` of its own: in RoboSim, name the element that declares it (or \
                 requires it)",
                b.of.join("::"),
                b.name
            ));
        }
        return Ok(vec![b]);
    }
    let of = b.of.join("::");
    let defs = file_defs(db, loc.file);
    let at = |b: &Binding, m: &str| Binding { name: b.name.clone(), of: vec![m.to_string()], value: b.value };
    match defs.def(id).kind {
        DefKind::StateMachine => {
            let own = defs.children(Some(id)).any(|(_, d)| d.kind == DefKind::Constant && d.name == b.name);
            if own || interface_constant(db, ws, loc.file, id, &b.name, None) {
                Ok(vec![b])
            } else {
                Err(format!("the state machine `{of}` has no constant `{}`", b.name))
            }
        }
        DefKind::Controller => {
            let machines = machines_of(db, ws, loc.file, id);
            let mut out = Vec::new();
            for (mf, m) in &machines {
                if !interface_constant(db, ws, *mf, *m, &b.name, Some(UseKind::Requires)) {
                    continue;
                }
                let name = file_defs(db, *mf).def(*m).name.clone();
                // The checker matches a machine by its declaration: one
                // used by another controller too would receive the value
                // there as well.
                if referenced_elsewhere(db, ws, &name, loc.file, id) {
                    return Err(format!(
                        "`{name}`, which has `{}` from `{of}`, is used by another controller too: give the value \
                         of the machine (`with constant {} of {name}`) or of the module",
                        b.name, b.name
                    ));
                }
                out.push(at(&b, &name));
            }
            if out.is_empty() {
                return Err(format!("no state machine of the controller `{of}` requires a constant `{}`", b.name));
            }
            Ok(out)
        }
        _ => {
            let mut out = Vec::new();
            for (cf, c) in controllers_of(db, ws, loc.file, id) {
                for (mf, m) in machines_of(db, ws, cf, c) {
                    if interface_constant(db, ws, mf, m, &b.name, Some(UseKind::Requires)) {
                        out.push(at(&b, &file_defs(db, mf).def(m).name));
                    }
                }
            }
            if out.is_empty() {
                return Err(format!("no state machine of the module `{of}` requires a constant `{}`", b.name));
            }
            Ok(out)
        }
    }
}

/// Whether the element `id` of `file` itself declares a constant `name`
/// or has one through an interface it uses, provides or requires: the
/// RoboSim checker binds a value to the element the assertion names by
/// its declaration's name, so a constant of one of its parts (a machine of
/// a controller, a platform of a module) would not receive it.
fn has_constant(db: &dyn Db, ws: Workspace, file: File, id: DefId, name: &str) -> bool {
    let defs = file_defs(db, file);
    interface_constant(db, ws, file, id, name, None)
        || defs.children(Some(id)).any(|(_, d)| d.kind == DefKind::Constant && d.name == name)
}

/// Whether the context `owner` of `file` has a constant `name` through an
/// interface it uses, provides or requires (only `kind`, if given).
fn interface_constant(db: &dyn Db, ws: Workspace, file: File, owner: DefId, name: &str, kind: Option<UseKind>) -> bool {
    let defs = file_defs(db, file);
    defs.uses_of(owner).filter(|u| kind.is_none_or(|k| u.kind == k)).any(|u| {
        resolve_item(db, ws, file, &u.path, |k| k == DefKind::Interface).into_iter().next().is_some_and(|i| {
            let Some(iid) = i.def(db) else { return false };
            file_defs(db, i.file).children(Some(iid)).any(|(_, d)| d.kind == DefKind::Constant && d.name == name)
        })
    })
}

/// The machines of a controller: referenced and declared inside.
fn machines_of(db: &dyn Db, ws: Workspace, file: File, ctrl: DefId) -> Vec<(File, DefId)> {
    children_of(db, ws, file, ctrl, DefKind::MachineRef, DefKind::StateMachine)
}

/// The controllers of a module: referenced and declared inside.
fn controllers_of(db: &dyn Db, ws: Workspace, file: File, module: DefId) -> Vec<(File, DefId)> {
    children_of(db, ws, file, module, DefKind::ControllerRef, DefKind::Controller)
}

/// The children of `parent` of kind `kind`, and the targets of its
/// references of kind `reference`.
fn children_of(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    parent: DefId,
    reference: DefKind,
    kind: DefKind,
) -> Vec<(File, DefId)> {
    let defs = file_defs(db, file);
    let mut out = Vec::new();
    for (cid, d) in defs.children(Some(parent)) {
        if d.kind == kind {
            out.push((file, cid));
        } else if let (true, DefData::Reference { path, .. }) = (d.kind == reference, &d.data) {
            let found = match kind {
                DefKind::Controller => resolve_item(db, ws, file, path, |k| k == DefKind::Controller),
                _ => resolve_item(db, ws, file, path, |k| k == DefKind::StateMachine),
            };
            out.extend(found.into_iter().next().and_then(|l| Some((l.file, l.def(db)?))));
        }
    }
    out
}

/// Whether a controller other than `ctrl` (of `file`) references a machine
/// named `name`.
fn referenced_elsewhere(db: &dyn Db, ws: Workspace, name: &str, file: File, ctrl: DefId) -> bool {
    ws.files(db).iter().filter(|f| !f.is_library(db)).any(|&f| {
        let defs = file_defs(db, f);
        defs.iter().any(|(id, d)| {
            d.kind == DefKind::Controller
                && !(f == file && id == ctrl)
                && machines_of(db, ws, f, id).iter().any(|&(mf, m)| file_defs(db, mf).def(m).name == name)
        })
    })
}

/// The index of the literal `text` (`E::L`, `P::E::L`) in its enumeration,
/// when every constant named `constant` is of that enumeration.
fn enum_literal(scope: Scope<'_>, constant: &str, text: &str) -> Result<i64, String> {
    let not_literal =
        || format!("the value of constant `{constant}` is not an integer, boolean or enumeration literal");
    let path: Vec<String> = text.split("::").map(|p| p.trim().to_string()).collect();
    let ident = |p: &String| !p.is_empty() && p.chars().all(|c| c.is_alphanumeric() || c == '_');
    if path.len() < 2 || !path.iter().all(ident) {
        return Err(not_literal());
    }
    let (literal, enumeration) = path.split_last().ok_or_else(not_literal)?;
    let Scope { db, ws, file, .. } = scope;
    let loc = resolve_item(db, ws, file, enumeration, |k| k == DefKind::Enumeration)
        .into_iter()
        .next()
        .ok_or_else(|| format!("`{}` is not an enumeration", enumeration.join("::")))?;
    let id = loc.def(db).ok_or_else(not_literal)?;
    let defs = file_defs(db, loc.file);
    let enum_name = defs.def(id).name.clone();
    let literals: Vec<&crate::defs::Def> =
        defs.children(Some(id)).map(|(_, d)| d).filter(|d| d.kind == DefKind::EnumLiteral).collect();
    let index = literals
        .iter()
        .position(|d| d.name == *literal)
        .ok_or_else(|| format!("`{literal}` is not a literal of the enumeration `{enum_name}`"))?;
    if matches!(&literals[index].data, crate::defs::DefData::Literal { args } if !args.is_empty()) {
        return Err(format!("`{text}` takes arguments: literals with arguments are not supported as values"));
    }
    // The constant's type, wherever it is declared.
    let mut found = false;
    for &f in ws.files(db) {
        if f.is_library(db) {
            continue;
        }
        for (_, d) in file_defs(db, f).iter().filter(|(_, d)| d.kind == DefKind::Constant && d.name == constant) {
            found = true;
            let of_enum = matches!(&d.data, crate::defs::DefData::Typed { ty: Some(crate::defs::TypeRef::Named(p, _)), .. }
                if p.last() == Some(&enum_name));
            if !of_enum {
                return Err(format!(
                    "a constant `{constant}` of the workspace is not of the enumeration `{enum_name}`: \
                     `{text}` cannot be its value"
                ));
            }
        }
    }
    if !found {
        return Err(format!("no constant `{constant}` is declared"));
    }
    Ok(index as i64)
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

/// What a side of an assertion resolves to, before it is read as a
/// [`Subject`]: the one resolution of assertion names, which
/// [`subject`] reads and the checker's LNK-01 asks ([`resolves`]).
enum Side<'a> {
    /// A `simulation` of the assertion file (by its name) or of another
    /// assertion file (by the path's last segment).
    Simulation(File, &'a crate::assertions::SimulationDecl),
    /// `C::M`: a machine or operation declared in the controller `C`.
    Inline(ItemLoc, DefId),
    /// A RoboChart instance path ([`instance`]).
    Instance(Result<(ItemLoc, Option<String>), String>),
    /// A RoboChart operation (not also a module, controller or machine).
    ChartOperation(ItemLoc),
    /// A RoboSim operation: top-level, or reached through a path.
    SimOperation(ItemLoc, Option<String>),
    /// A module, controller or state machine.
    Element(ItemLoc),
    /// A `csp` block of an assertion file.
    CspBlock,
}

/// Resolves `path`, one side of an assertion (also the `of` of a
/// `cycleDef of`), in the order [`subject`] reads it.
fn side<'a>(scope: Scope<'a>, path: &[String]) -> Option<Side<'a>> {
    let Scope { db, ws, file, read, others } = scope;
    let name = path.join("::");
    let sim = read
        .simulation(&name)
        .map(|s| (file, s))
        .or_else(|| others.iter().find_map(|(f, r)| r.simulation(path.last()?).map(|s| (*f, s))));
    if let Some((sim_file, sim)) = sim {
        return Some(Side::Simulation(sim_file, sim));
    }
    if let Some((ctrl, machine)) = inline_machine(db, ws, file, path) {
        return Some(Side::Inline(ctrl, machine));
    }
    if let Some(found) = instance(db, ws, file, path) {
        return Some(Side::Instance(found));
    }
    let element = |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
    // RT-11: a RoboChart operation, checked as its own process with its
    // parameters.
    let operations = resolve_item(db, ws, file, path, |k| k == DefKind::Operation);
    let elements = resolve_item(db, ws, file, path, element);
    let operation = |kind| operations.iter().copied().find(|l| l.file.kind(db) == kind);
    if let (Some(loc), true) = (operation(FileKind::RoboChart), elements.is_empty()) {
        return Some(Side::ChartOperation(loc));
    }
    if let (Some(loc), true) = (operation(FileKind::RoboSim), elements.is_empty()) {
        return Some(Side::SimOperation(loc, None));
    }
    // RT-11: `C::o` (an operation reference of a RoboSim controller) is
    // the operation it references; `Mod::c::o` and `Mod::c::Op` reach it
    // through the module's controller reference.
    if let Some((loc, inner)) = robosim_operation_path(db, ws, file, path) {
        return Some(Side::SimOperation(loc, inner));
    }
    if let Some(loc) = elements.first() {
        return Some(Side::Element(*loc));
    }
    let csp = std::iter::once(read)
        .chain(others.iter().map(|(_, r)| r))
        .any(|r| path.last().is_some_and(|n| r.csp_block(n).is_some()));
    csp.then_some(Side::CspBlock)
}

/// Whether `path`, one side of an assertion (or the element of a `cycleDef
/// of`), names something [`subject`] reads: a simulation, an element, an
/// operation, an instance path or a `csp` block, even one the checker then
/// refuses. The checker's LNK-01 asks this, so that it and the verifier
/// cannot disagree on what a name means.
pub fn resolves(scope: Scope<'_>, path: &[String]) -> bool {
    !path.is_empty() && side(scope, path).is_some()
}

/// What `path`, one side of assertion `a`, denotes; or why it cannot be
/// checked, in words for the user.
pub fn subject(scope: Scope<'_>, a: &AssertionDecl, path: &[String]) -> Result<Subject, String> {
    let Scope { db, ws, .. } = scope;
    let name = path.join("::");
    let overridden = a.overrides.iter().find_map(|o| match o {
        Override::CycleDef { of, value, .. } if of.last() == path.last() => Some(value.as_int()),
        _ => None,
    });
    let element = |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
    let Some(found) = side(scope, path) else {
        return Err(format!("`{name}` is not a simulation, module, controller or machine"));
    };
    let bound = || bindings_in(scope, a).unwrap_or_default();
    let loc = match found {
        Side::Simulation(sim_file, sim) => {
            let loc = resolve_item(db, ws, sim_file, &sim.of, element)
                .into_iter()
                .next()
                .ok_or_else(|| format!("`{}` is not a RoboChart module, controller or machine", sim.of.join("::")))?;
            let period = overridden.unwrap_or_else(|| sim.cycle.as_ref().and_then(Value::as_int));
            return Ok(Subject::Constrained { name: sim.name.clone(), sim_file, loc, period });
        }
        Side::Inline(ctrl, machine) => {
            let inner = path.last().cloned();
            let is_operation = file_defs(db, ctrl.file).def(machine).kind == DefKind::Operation;
            if is_operation && ctrl.file.kind(db) == FileKind::RoboSim {
                return Ok(Subject::SimOperation { name, loc: ctrl, inner });
            }
            if ctrl.file.kind(db) != FileKind::RoboSim {
                return Ok(Subject::Design { name, loc: ctrl, inner });
            }
            let period = match overridden {
                Some(p) => p,
                None => robosim_period(db, ws, &name, ctrl.file, machine, &bound())?,
            };
            return Ok(Subject::Simulation { name, loc: ctrl, inner, period });
        }
        Side::Instance(found) => {
            let (loc, inner) = found?;
            return Ok(Subject::Design { name, loc, inner });
        }
        Side::ChartOperation(loc) => return Ok(Subject::Design { name, loc, inner: None }),
        Side::SimOperation(loc, inner) => return Ok(Subject::SimOperation { name, loc, inner }),
        Side::CspBlock => {
            return Err(format!(
                "`{name}` is defined in a `csp` block: raw CSPm is not verifiable natively (check it with FDR)"
            ))
        }
        Side::Element(loc) => loc,
    };
    if loc.file.kind(db) != FileKind::RoboSim {
        return Ok(Subject::Design { name, loc, inner: None });
    }
    let period = match (overridden, loc.def(db)) {
        (Some(p), _) => p,
        (None, Some(def)) => robosim_period(db, ws, &name, loc.file, def, &bound())?,
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
    let bound: Vec<(String, String, i64)> =
        bound.iter().map(|b| (b.of.last().cloned().unwrap_or_default(), b.name.clone(), b.value)).collect();
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

/// The RoboSim operation an instance path names, checked on its own
/// (RT-11): `C::o` for the operation reference `o` of controller `C`, and
/// `Mod::c::o` or `Mod::c::Op` through the controller reference `c` of
/// module `Mod`; the operation's location, with the name of the operation
/// declared inside the controller the path ends at, if it is one. (`C::Op`
/// itself is read by [`inline_machine`], RoboChart paths by [`instance`].)
fn robosim_operation_path(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    path: &[String],
) -> Option<(ItemLoc, Option<String>)> {
    let robosim = |l: ItemLoc| l.file.kind(db) == FileKind::RoboSim;
    match operation_path(db, ws, file, path)? {
        PathOperation::Declared(ctrl, _) if robosim(ctrl) => Some((ctrl, path.last().cloned())),
        PathOperation::Referenced(op) if robosim(op) => Some((op, None)),
        _ => None,
    }
}

/// What [`operation_path`] finds.
enum PathOperation {
    /// An operation declared in the controller `ItemLoc`, by its definition.
    Declared(ItemLoc, DefId),
    /// The operation an operation reference references.
    Referenced(ItemLoc),
}

/// The operation an instance path names through controllers and their
/// references: `C::op` or `C::o` (an operation reference of `C`), also
/// from a module through its controller reference (`Mod::c::op`,
/// `Mod::c::o`).
fn operation_path(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<PathOperation> {
    let container = |k| matches!(k, DefKind::Module | DefKind::Controller);
    let (start, mut loc) = (1..path.len())
        .rev()
        .find_map(|k| resolve_item(db, ws, file, &path[..k], container).into_iter().next().map(|l| (k, l)))?;
    for (i, seg) in path.iter().enumerate().skip(start) {
        let last = i + 1 == path.len();
        let defs = file_defs(db, loc.file);
        let (cid, child) = defs.children(Some(loc.def(db)?)).find(|(_, d)| d.name == *seg)?;
        match (child.kind, &child.data) {
            (DefKind::ControllerRef, DefData::Reference { path: target, .. }) if !last => {
                loc = resolve_item(db, ws, loc.file, target, |k| k == DefKind::Controller).into_iter().next()?;
            }
            (DefKind::Operation, _) if last => return Some(PathOperation::Declared(loc, cid)),
            (DefKind::OperationRef, DefData::Reference { path: target, .. }) if last => {
                let op = resolve_item(db, ws, loc.file, target, |k| k == DefKind::Operation).into_iter().next()?;
                return Some(PathOperation::Referenced(op));
            }
            _ => return None,
        }
    }
    None
}

/// RT-11: the definition of the operation `path` names (in `with parameter
/// x of P`): a top-level operation by its (qualified) name, one declared
/// inside a controller (`C::op`), or the operation an operation reference
/// references (`D::o` for `opref o = Op`, also through a module's
/// controller reference, `Mod::c::o`), in RoboChart and RoboSim alike.
pub fn operation_def(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<(File, DefId)> {
    if let Some(l) = resolve_item(db, ws, file, path, |k| k == DefKind::Operation).into_iter().next() {
        return Some((l.file, l.def(db)?));
    }
    match operation_path(db, ws, file, path)? {
        PathOperation::Declared(ctrl, id) => Some((ctrl.file, id)),
        PathOperation::Referenced(op) => Some((op.file, op.def(db)?)),
    }
}

/// An operation of the workspace declared (anywhere, also inside a
/// controller) under the one name `of`: the checker binds parameters by
/// the operation's declared name, as RoboTool's `param_x` of its process.
fn declared_operation(db: &dyn Db, ws: Workspace, of: &[String]) -> Option<(File, DefId)> {
    let [name] = of else { return None };
    ws.files(db).iter().filter(|f| !f.is_library(db)).find_map(|&f| {
        file_defs(db, f).iter().find(|(_, d)| d.kind == DefKind::Operation && d.name == *name).map(|(id, _)| (f, id))
    })
}

/// The operation `of` names in `with parameter x of of` (read by
/// [`parameters_in`]; the checker's LNK-01 asks it too): through
/// [`operation_def`], else an operation of the workspace declared under
/// that one name.
pub fn parameter_operation(scope: Scope<'_>, of: &[String]) -> Option<(File, DefId)> {
    let Scope { db, ws, file, .. } = scope;
    operation_def(db, ws, file, of).or_else(|| declared_operation(db, ws, of))
}

/// Whether the checker reads `with constant name of of` ([`bindings_in`]
/// gives it a value rather than refusing it).
pub fn constant_reads(scope: Scope<'_>, name: &str, of: &[String]) -> bool {
    spread(scope, Binding { name: name.to_string(), of: of.to_vec(), value: 0 }).is_ok()
}

/// The values `a` gives operations' parameters (`with parameter x of P
/// set to v`, RT-11), each named by the operation's declaration (through
/// references: [`operation_def`]); what `P` or `x` fails to name, in words.
pub fn parameters_in(scope: Scope<'_>, a: &AssertionDecl) -> Result<Vec<Binding>, String> {
    let db = scope.db;
    let mut out = Vec::new();
    for o in &a.overrides {
        let Override::Parameter { name, of, value, .. } = o else { continue };
        let written = of.join("::");
        let (f, id) = parameter_operation(scope, of).ok_or_else(|| {
            format!(
                "`{written}` is not an operation: `with parameter {name} of {written}` names an operation, an \
                 operation declared in a controller, or an operation reference"
            )
        })?;
        let defs = file_defs(db, f);
        let op = defs.def(id).name.clone();
        if !defs.children(Some(id)).any(|(_, d)| d.kind == DefKind::Parameter && d.name == *name) {
            let op = if op == written { String::new() } else { format!(" (`{op}`)") };
            return Err(format!("the operation `{written}`{op} has no parameter `{name}`"));
        }
        let value = match value {
            Value::Int(v) => *v,
            Value::Bool(b) => i64::from(*b),
            Value::Other(t) => return Err(format!("the value `{t}` of the parameter `{name}` is not supported")),
        };
        out.push(Binding { name: name.clone(), of: vec![op], value });
    }
    Ok(out)
}

/// RT-11: the RoboChart element an instance path names, checked on its
/// own: `C::s` for the machine reference `s` of controller `C`, `M::c`
/// for the controller reference `c` of module `M`, and longer paths
/// (`M::c::s`, `M::c::o`); with the operation declared inside the
/// controller it ends at, if any. `None` when `path` is no such path
/// (inline elements and qualified names are found otherwise).
fn instance(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    path: &[String],
) -> Option<Result<(ItemLoc, Option<String>), String>> {
    let container = |k| matches!(k, DefKind::Module | DefKind::Controller);
    let (start, mut loc) = (1..path.len())
        .rev()
        .find_map(|k| resolve_item(db, ws, file, &path[..k], container).into_iter().next().map(|l| (k, l)))?;
    if loc.file.kind(db) == FileKind::RoboSim {
        return None;
    }
    let name = path.join("::");
    for seg in &path[start..] {
        let defs = file_defs(db, loc.file);
        let id = loc.def(db)?;
        let (_, child) = defs.children(Some(id)).find(|(_, d)| d.name == *seg)?;
        match (child.kind, &child.data) {
            (DefKind::ControllerRef, DefData::Reference { path: target, .. }) => {
                loc = resolve_item(db, ws, loc.file, target, |k| k == DefKind::Controller).into_iter().next()?;
            }
            (DefKind::MachineRef, DefData::Reference { path: target, .. }) => {
                // RT-19: inside its controller a machine's calls of the
                // controller's operations are inlined, on its own they are
                // visible events; which one an instance path means is not
                // established.
                if defs.children(Some(id)).any(|(_, d)| matches!(d.kind, DefKind::Operation | DefKind::OperationRef)) {
                    return Some(Err(format!(
                        "`{name}` is a machine of a controller that defines operations: whether RoboTool inlines \
                         them for an instance path or leaves them as visible calls is not established (check the \
                         controller, or the machine `{}` on its own)",
                        target.join("::")
                    )));
                }
                loc = resolve_item(db, ws, loc.file, target, |k| k == DefKind::StateMachine).into_iter().next()?;
            }
            // RT-11: an operation reference is the operation it references,
            // checked as its own process with its parameters.
            (DefKind::OperationRef, DefData::Reference { path: target, .. }) if seg == path.last()? => {
                loc = resolve_item(db, ws, loc.file, target, |k| k == DefKind::Operation).into_iter().next()?;
            }
            // RT-11: an operation declared inside the controller, on its own
            // (as a top-level one).
            (DefKind::Operation, _) if seg == path.last()? => return Some(Ok((loc, Some(seg.clone())))),
            (DefKind::Operation | DefKind::OperationRef, _) => {
                return Some(Err(format!("`{name}`: `{seg}` is an operation, which declares no element to name")))
            }
            _ => return None,
        }
    }
    Some(Ok((loc, None)))
}

/// The controller `C` and its machine (or operation, RT-11) `M` when
/// `path` is `C::M` and `C` declares `M` in its own body.
fn inline_machine(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<(ItemLoc, DefId)> {
    let (last, prefix) = path.split_last()?;
    let controller = resolve_item(db, ws, file, prefix, |k| k == DefKind::Controller);
    controller.into_iter().find_map(|loc| {
        let id = loc.def(db)?;
        let defs = file_defs(db, loc.file);
        let machine = defs
            .children(Some(id))
            .find(|(_, d)| matches!(d.kind, DefKind::StateMachine | DefKind::Operation) && d.name == *last)
            .map(|(m, _)| m)?;
        Some((loc, machine))
    })
}
