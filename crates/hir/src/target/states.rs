//! The state a reachability assertion (`S is reachable in X`) names: one
//! state of one machine of `X`, by its path inside the machine (`C::S` for
//! the substate `S` of `C`), after the machine's name (its instance path,
//! `Ctl::a`, or a suffix of it, or its declaration's name), or by its own
//! name when that alone names one node. A path naming no node, or nodes of
//! several machines, is refused: a verdict about another state would be
//! wrong. The native checker and the CSPm export both resolve here.

use crate::index::ItemLoc;
use crate::model::{self as m, Definition, Item, NodeKind, Region};
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

/// One machine of a subject: instance path, declared name, its region.
pub type Machine<'a> = (Vec<String>, String, &'a Region);

/// The machines the subject `loc` (with `inner`, the machine or operation
/// of that name declared inside the controller `loc`) consists of, named as
/// the native checker names them; an operation is one machine.
pub fn machines<'a>(db: &'a dyn Db, ws: Workspace, loc: ItemLoc, inner: Option<&str>) -> Vec<Machine<'a>> {
    let machine = |i: &'a m::Instance<m::Behaviour>| -> Option<&'a m::Behaviour> {
        match &i.def {
            Definition::Inline(b) => Some(&**b),
            Definition::Ref { target, .. } => match m::item(db, ws, (*target)?)? {
                Item::Machine(b) => Some(b),
                _ => None,
            },
        }
    };
    let of_controller = |prefix: &str, c: &'a m::Controller, out: &mut Vec<Machine<'a>>| {
        for i in &c.machines {
            if let Some(b) = machine(i) {
                out.push((vec![prefix.to_string(), i.name.clone()], b.name.clone(), &b.region));
            }
        }
    };
    let mut out = Vec::new();
    match (m::item(db, ws, loc), inner) {
        (Some(Item::Machine(b) | Item::Operation(b)), None) => {
            out.push((vec![b.name.clone()], b.name.clone(), &b.region))
        }
        (Some(Item::Controller(c)), None) => of_controller(&c.name, c, &mut out),
        (Some(Item::Controller(c)), Some(inner)) => {
            let inline = c.machines.iter().find_map(|i| match &i.def {
                Definition::Inline(b) if b.name == inner => Some(&**b),
                _ => None,
            });
            let op = c.operations.iter().find_map(|o| match &o.def {
                Definition::Inline(b) if o.name == inner => Some(&**b),
                _ => None,
            });
            if let Some(b) = inline.or(op) {
                out.push((vec![b.name.clone()], b.name.clone(), &b.region));
            }
        }
        (Some(Item::Module(x)), None) => {
            for i in &x.controllers {
                let c = match &i.def {
                    Definition::Inline(c) => Some(&**c),
                    Definition::Ref { target, .. } => match target.and_then(|t| m::item(db, ws, t)) {
                        Some(Item::Controller(c)) => Some(c),
                        _ => None,
                    },
                };
                if let Some(c) = c {
                    of_controller(&i.name, c, &mut out);
                }
            }
        }
        _ => {}
    }
    out
}

/// Whether `prefix` names the instance `instance`: empty, or ending with
/// it.
fn names_instance(prefix: &[String], instance: &[String]) -> bool {
    prefix.is_empty() || prefix.ends_with(instance)
}

/// The node `path` names in the subject `loc` (see [`machines`]), or why
/// it names none, or several.
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
    let (mut found, mut by_name) = (Vec::new(), Vec::new());
    for (inst, decl, region) in machines(db, ws, loc, inner) {
        let names_machine =
            |prefix: &[String]| names_instance(prefix, &inst) || names_instance(prefix, std::slice::from_ref(&decl));
        let mut nodes = Vec::new();
        collect(region, &mut Vec::new(), &mut nodes);
        for (inside, kind) in nodes {
            let r = || StateRef { machine: inst.clone(), decl: decl.clone(), state: inside.clone(), kind };
            if path.last() == inside.last() && names_machine(&path[..path.len() - 1]) {
                by_name.push(r());
            }
            let Some(k) = path.len().checked_sub(inside.len()) else { continue };
            if path[k..] == inside[..] && names_machine(&path[..k]) {
                found.push(r());
            }
        }
    }
    if found.is_empty() && by_name.len() == 1 {
        found = by_name;
    }
    match found.len() {
        0 => Err(format!("`{written}` names no state of the machines checked")),
        1 => Ok(found.remove(0)),
        _ => Err(format!(
            "`{written}` names a state of several machines ({}): qualify it with the machine's name",
            found.iter().map(|s| s.machine.join("::")).collect::<Vec<_>>().join(", ")
        )),
    }
}

/// The nodes of `region` and of its states' regions, with their paths
/// (probabilistic junctions left out, as the native checker refuses them).
fn collect(region: &Region, at: &mut Vec<String>, out: &mut Vec<(Vec<String>, NodeKind)>) {
    for n in &region.nodes {
        if n.kind == NodeKind::Probabilistic {
            continue;
        }
        at.push(n.name.clone());
        out.push((at.clone(), n.kind));
        if n.kind == NodeKind::State {
            collect(&n.region, at, out);
        }
        at.pop();
    }
}
