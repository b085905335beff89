//! The states a reachability assertion (`S is reachable in M`) can name:
//! the machines of the design `M` stands for, named as the checker names
//! them, and the one reading of a state path against them. The verifier
//! (on its compiled design) and the checker's LNK-01 (on the model) both
//! match paths here, so they cannot read a state path differently.

use super::Subject;
use crate::model::{self, Behaviour, Definition, Item, Node};
use crate::{Db, Workspace};

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

/// The machines of the design `subject` stands for, named as the checker
/// composes them (a module's controllers' machines, a controller's
/// machines, a machine alone); `None` when that is not known from the
/// model (an operation, a reference that does not resolve), so that no
/// state path is judged against an incomplete list.
pub fn design_machines(db: &dyn Db, ws: Workspace, subject: &Subject) -> Option<Vec<MachineStates>> {
    let (loc, inner) = match subject {
        Subject::Design { loc, inner, .. } | Subject::Simulation { loc, inner, .. } => (*loc, inner.as_deref()),
        Subject::Constrained { loc, .. } => (*loc, None),
        Subject::SimOperation { .. } => return None,
    };
    let item = model::item(db, ws, loc)?;
    let mut out = Vec::new();
    match (item, inner) {
        (Item::Controller(c), Some(m)) => {
            if c.operations.iter().any(|o| o.name == m) {
                return None;
            }
            let b = c.machines.iter().find_map(|i| match &i.def {
                Definition::Inline(b) if i.name == m => Some(&**b),
                _ => None,
            })?;
            out.push(machine(m.to_string(), b));
        }
        (_, Some(_)) => return None,
        (Item::Module(m), None) => {
            for c in &m.controllers {
                let ctrl = match &c.def {
                    Definition::Inline(c) => &**c,
                    Definition::Ref { target, .. } => match model::item(db, ws, (*target)?)? {
                        Item::Controller(c) => c,
                        _ => return None,
                    },
                };
                controller(db, ws, &c.name, ctrl, &mut out)?;
            }
        }
        (Item::Controller(c), None) => controller(db, ws, &c.name, c, &mut out)?,
        (Item::Machine(b), None) => out.push(machine(b.name.clone(), b)),
        _ => return None,
    }
    Some(out)
}

/// The machines of the controller `c`, instance of name `cref`.
fn controller(
    db: &dyn Db,
    ws: Workspace,
    cref: &str,
    c: &model::Controller,
    out: &mut Vec<MachineStates>,
) -> Option<()> {
    for m in &c.machines {
        let body = match &m.def {
            Definition::Inline(b) => &**b,
            Definition::Ref { target, .. } => match model::item(db, ws, (*target)?)? {
                Item::Machine(b) => b,
                _ => return None,
            },
        };
        out.push(machine(format!("{cref}::{}", m.name), body));
    }
    Some(())
}

/// The machine `body` under the instance name `instance`.
fn machine(instance: String, body: &Behaviour) -> MachineStates {
    fn add(nodes: &[Node], parent: Option<usize>, out: &mut Vec<StateNode>) {
        for n in nodes {
            out.push(StateNode { name: n.name.clone(), parent, own: true });
            let me = out.len() - 1;
            add(&n.region.nodes, Some(me), out);
        }
    }
    let mut nodes = Vec::new();
    add(&body.region.nodes, None, &mut nodes);
    MachineStates { instance, decl: body.name.clone(), nodes }
}
