//! The state a reachability assertion (`S is reachable in X`) names: one
//! node of one machine of `X`, by its path inside the machine (`C::S` for
//! the substate `S` of `C`), after the machine's name (its instance path,
//! `Ctl::a`, or a suffix of it, or its declaration's name), or by its own
//! name when that alone names one node. A path naming no node, or nodes of
//! several machines, is refused: a verdict about another state would be
//! wrong.
//!
//! This is the one reading of a state path: the native checker (over the
//! machines of its compiled design), the checker's LNK-01 and the CSPm
//! export (over the machines of the model, [`design_machines`],
//! [`state`]) all read paths with [`match_state`].

use super::Subject;
use crate::index::ItemLoc;
use crate::model::{self as m, Behaviour, Definition, Item, Node, NodeKind};
use crate::{Db, Workspace};

/// A node a reachability assertion names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateRef {
    /// Its machine's instance path in the subject: `["Ctl", "a"]` for the
    /// machine `a` of the controller `Ctl`, `["c", "a"]` for the machine
    /// `a` of a module's controller instance `c`, `["M"]` for a machine or
    /// an operation checked on its own or declared inside the controller
    /// checked.
    pub machine: Vec<String>,
    /// The machine's declared name.
    pub decl: String,
    /// The node's path inside its machine (`["C", "S"]`).
    pub state: Vec<String>,
    /// What the node is (a state, a junction, …).
    pub kind: NodeKind,
}

/// A machine of a design, as a state path names it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MachineStates {
    /// Its instance name: `c::q` for the machine `q` of the controller
    /// (reference) `c`, the machine's own name when it is checked alone.
    pub instance: String,
    /// The name of its declaration (`M` for `sref q = M`).
    pub decl: String,
    /// Its nodes, by index.
    pub nodes: Vec<StateNode>,
}

/// A node of a machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateNode {
    /// Its name.
    pub name: String,
    /// The index of the enclosing state.
    pub parent: Option<usize>,
    /// Whether it belongs to the machine's own body (not to the body of an
    /// operation inlined into it, whose states a path cannot name).
    pub own: bool,
}

/// What a state path names ([`match_state`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StateMatch {
    /// One state: its (machine, node) pair.
    Found(Vec<(usize, usize)>),
    /// No state.
    None,
    /// States of several machines: (machine, node) pairs.
    Several(Vec<(usize, usize)>),
}

/// The states the path `path` of a reachability assertion names among
/// `machines`: the path ends with the state's path inside its machine
/// (`S`, or `C::S` for `S` inside the composite `C`), and what comes
/// before names the machine's instance (`M` alone, `q` or `Ctl::q` in a
/// controller, `c::q` or `Mod::c::q` in a module) or its declaration (`M`
/// for `sref q = M`); an empty prefix names any machine. So `M::S` is
/// never a substate `S` of a composite of `M` when `M` has a state `S` of
/// its own, nor a state `S` of another machine. A path that leaves out the
/// composites around the state (`M::B` for `M::C::B`) names it when the
/// machine has only one state of that name.
pub fn match_state(path: &[String], machines: &[MachineStates]) -> StateMatch {
    let (mut found, mut by_name) = (Vec::new(), Vec::new());
    for (mi, m) in machines.iter().enumerate() {
        for (ni, n) in m.nodes.iter().enumerate().filter(|(_, n)| n.own) {
            let inner = inner_path(m, ni);
            if path.last() == Some(&n.name) && names_machine(m, &path[..path.len() - 1]) {
                by_name.push((mi, ni));
            }
            let Some(prefix) = path.len().checked_sub(inner.len()).map(|k| &path[..k]) else { continue };
            if path[prefix.len()..].iter().zip(&inner).all(|(a, b)| a == *b) && names_machine(m, prefix) {
                found.push((mi, ni));
            }
        }
    }
    if found.is_empty() && by_name.len() == 1 {
        found = by_name;
    }
    match found.len() {
        0 => StateMatch::None,
        1 => StateMatch::Found(found),
        _ => StateMatch::Several(found),
    }
}

/// The names of node `ni` and the states around it, outermost first.
fn inner_path(m: &MachineStates, ni: usize) -> Vec<&str> {
    let mut inner = vec![m.nodes[ni].name.as_str()];
    let mut up = m.nodes[ni].parent;
    while let Some(p) = up {
        inner.push(m.nodes[p].name.as_str());
        up = m.nodes[p].parent;
    }
    inner.reverse();
    inner
}

/// Whether `prefix` (the part of a state path before the state's own
/// path) names the machine `m`: empty, ending with its instance name or
/// its declaration's name, or the end of its instance name (`q` for
/// `Ctl::q`: a machine of the same name in another controller makes the
/// path name several states, which [`match_state`] says).
pub fn names_machine(m: &MachineStates, prefix: &[String]) -> bool {
    let ends_with = |names: &[&str]| {
        prefix.len() >= names.len() && prefix[prefix.len() - names.len()..].iter().zip(names).all(|(a, b)| a == b)
    };
    let instance: Vec<&str> = m.instance.split("::").collect();
    let ends_instance = prefix.len() <= instance.len()
        && instance[instance.len() - prefix.len()..].iter().zip(prefix).all(|(a, b)| *a == b.as_str());
    prefix.is_empty() || ends_with(&instance) || ends_with(&[m.decl.as_str()]) || ends_instance
}

/// A machine of the model with its nodes' kinds, index for index.
struct ModelMachine {
    states: MachineStates,
    kinds: Vec<NodeKind>,
}

/// The machines of the design `subject` stands for, named as the checker
/// composes them (a module's controllers' machines, a controller's
/// machines, a machine or an operation alone); `None` when that is not
/// known from the model (a RoboSim operation, a reference that does not
/// resolve), so that no state path is judged against an incomplete list.
pub fn design_machines(db: &dyn Db, ws: Workspace, subject: &Subject) -> Option<Vec<MachineStates>> {
    let (loc, inner) = match subject {
        Subject::Design { loc, inner, .. } | Subject::Simulation { loc, inner, .. } => (*loc, inner.as_deref()),
        Subject::Constrained { loc, .. } => (*loc, None),
        Subject::SimOperation { .. } => return None,
    };
    Some(model_machines(db, ws, loc, inner)?.into_iter().map(|m| m.states).collect())
}

/// The node `path` names in the subject `loc` (with `inner`, the machine
/// or operation of that name declared inside the controller `loc`), read
/// by [`match_state`] over [`design_machines`], or why it names none, or
/// several.
pub fn state(
    db: &dyn Db,
    ws: Workspace,
    loc: ItemLoc,
    inner: Option<&str>,
    path: &[String],
) -> Result<StateRef, String> {
    let written = path.join("::");
    if path.is_empty() {
        return Err("the state is missing".into());
    }
    let machines = model_machines(db, ws, loc, inner)
        .ok_or_else(|| "a machine of the element checked could not be resolved".to_string())?;
    let states: Vec<MachineStates> = machines.iter().map(|m| m.states.clone()).collect();
    match match_state(path, &states) {
        StateMatch::None => Err(format!("`{written}` names no state of the machines checked")),
        StateMatch::Several(found) => Err(format!(
            "`{written}` names a state of several machines ({}): qualify it with the machine's name",
            found.iter().map(|&(mi, _)| states[mi].instance.as_str()).collect::<Vec<_>>().join(", ")
        )),
        StateMatch::Found(found) => {
            let (mi, ni) = found[0];
            let m = &machines[mi];
            if m.kinds[ni] == NodeKind::Probabilistic {
                return Err(format!(
                    "`{written}` is a probabilistic junction, which has no meaning in the tock-CSP semantics"
                ));
            }
            Ok(StateRef {
                machine: m.states.instance.split("::").map(str::to_string).collect(),
                decl: m.states.decl.clone(),
                state: inner_path(&m.states, ni).into_iter().map(str::to_string).collect(),
                kind: m.kinds[ni],
            })
        }
    }
}

/// The machines of the subject `loc` (with `inner`, see [`state`]), named
/// as the native checker names them: `None` when a reference does not
/// resolve or `inner` names nothing.
fn model_machines(db: &dyn Db, ws: Workspace, loc: ItemLoc, inner: Option<&str>) -> Option<Vec<ModelMachine>> {
    let mut out = Vec::new();
    match (m::item(db, ws, loc)?, inner) {
        (Item::Controller(c), Some(inner)) => {
            // The checker's reading (RT-11): an operation declared in the
            // controller's body comes first, checked as a top-level one.
            let op = c.operations.iter().find_map(|o| match &o.def {
                Definition::Inline(b) if o.name == inner => Some(&**b),
                _ => None,
            });
            let b = op.or_else(|| {
                c.machines.iter().find_map(|i| match &i.def {
                    Definition::Inline(b) if i.name == inner => Some(&**b),
                    _ => None,
                })
            })?;
            out.push(machine(inner.to_string(), b));
        }
        (_, Some(_)) => return None,
        (Item::Module(x), None) => {
            for c in &x.controllers {
                let ctrl = definition(db, ws, &c.def, |i| match i {
                    Item::Controller(c) => Some(c),
                    _ => None,
                })?;
                controller_machines(db, ws, &c.name, ctrl, &mut out)?;
            }
        }
        (Item::Controller(c), None) => controller_machines(db, ws, &c.name, c, &mut out)?,
        (Item::Machine(b) | Item::Operation(b), None) => out.push(machine(b.name.clone(), b)),
        _ => return None,
    }
    Some(out)
}

/// What an instance's definition is: declared inline, or the item its
/// reference resolves to, when `pick` takes it (`None` otherwise).
fn definition<'a, T>(
    db: &'a dyn Db,
    ws: Workspace,
    def: &'a Definition<T>,
    pick: impl Fn(&'a Item) -> Option<&'a T>,
) -> Option<&'a T> {
    match def {
        Definition::Inline(x) => Some(&**x),
        Definition::Ref { target, .. } => pick(m::item(db, ws, (*target)?)?),
    }
}

/// The machines of the controller `c`, instance of name `cref`.
fn controller_machines(
    db: &dyn Db,
    ws: Workspace,
    cref: &str,
    c: &m::Controller,
    out: &mut Vec<ModelMachine>,
) -> Option<()> {
    for m in &c.machines {
        let body = definition(db, ws, &m.def, |i| match i {
            Item::Machine(b) => Some(b),
            _ => None,
        })?;
        out.push(machine(format!("{cref}::{}", m.name), body));
    }
    Some(())
}

/// The machine `body` under the instance name `instance`.
fn machine(instance: String, body: &Behaviour) -> ModelMachine {
    fn add(nodes: &[Node], parent: Option<usize>, out: &mut Vec<StateNode>, kinds: &mut Vec<NodeKind>) {
        for n in nodes {
            out.push(StateNode { name: n.name.clone(), parent, own: true });
            kinds.push(n.kind);
            let me = out.len() - 1;
            add(&n.region.nodes, Some(me), out, kinds);
        }
    }
    let (mut nodes, mut kinds) = (Vec::new(), Vec::new());
    add(&body.region.nodes, None, &mut nodes, &mut kinds);
    ModelMachine { states: MachineStates { instance, decl: body.name.clone(), nodes }, kinds }
}
