//! RT-16: a variable a controller provides to several of its machines.
//!
//! It lives in the controller's memory; each machine keeps its own copy
//! (its memory's, read with `get_x`) and writes it with `set_x`, visible in
//! the machine's `DS__` and `VSS__`. The controller's memory takes a write
//! only once the previous one has reached every machine, and forwards it
//! to the other machines' copies with `set_EXT_x`, one machine after
//! another in the controller's order, each a hidden step of its own: a
//! machine may meanwhile read the old value. `robosim verify` does the same
//! (`engine::lower::compose`, `Cx::forwards`: the lowest pending machine
//! first).
//!
//! The reference output has no controller sharing a variable, so the
//! controller's side is not RoboTool's text: the names `set_x` (a write)
//! and `set_EXT_x` (an update from outside) follow RoboTool's style for a
//! machine's memory channels (`get_x`, `set_x`, `setL_x`), and the
//! controller's memory process of `x` is `Memory__x`, named as the
//! export's generated names are (`__`).

use std::collections::BTreeSet;

use robosim_hir::{File, TextRange};

use super::Inst;
use crate::cspm::{name, prefix, Decl, Expr, Field};
use crate::machine::Problem;

/// How a controller shares its machines' variables.
#[derive(Default)]
pub(super) struct Sharing {
    /// The memory processes' definitions (private to the controller).
    pub decls: Vec<Decl>,
    /// The memory processes, each with the channels it synchronises on.
    pub parts: Vec<(Expr, BTreeSet<String>)>,
    /// Per instance: the channels it synchronises on with a memory.
    pub chans: Vec<BTreeSet<String>>,
    /// The channels to hide.
    pub hidden: Vec<String>,
}

impl Sharing {
    /// Whether the instance `j` writes a shared variable (its `DS__` and
    /// `VSS__` are composed).
    pub fn open(&self, j: usize) -> bool {
        self.chans.get(j).is_some_and(|c| !c.is_empty())
    }
}

/// The variables that several machines of a controller (`insts`) require,
/// shared through the controller's memory (`timed`: the memory lets time
/// pass), or the reasons they cannot be (those `robosim verify` refuses,
/// with its reasons).
pub(super) fn share(
    (file, name_range): (File, TextRange),
    insts: &[Inst],
    timed: bool,
    problems: &mut Vec<Problem>,
) -> Sharing {
    let mut out = Sharing { chans: vec![BTreeSet::new(); insts.len()], ..Sharing::default() };
    let mut names: Vec<&str> = Vec::new();
    for i in insts {
        for s in &i.elem.shared {
            if !names.contains(&s.model.as_str()) {
                names.push(&s.model);
            }
        }
    }
    names.sort_unstable();
    for x in names {
        // The machines requiring `x`, in the controller's order.
        let users: Vec<(usize, &crate::export::SharedVar)> = insts
            .iter()
            .enumerate()
            .filter_map(|(j, i)| Some((j, i.elem.shared.iter().find(|s| s.model == x)?)))
            .collect();
        if users.len() < 2 {
            // One copy: its own memory is the controller's.
            continue;
        }
        let first = users[0].1;
        if users.iter().any(|(_, s)| s.ty != first.ty) {
            problems.push((file, name_range, format!("`{x}` is required with two different types")));
            continue;
        }
        if users.iter().any(|(_, s)| s.init != first.init) {
            problems.push((
                file,
                name_range,
                format!(
                    "`{x}` is required with different initial values: `robosim verify` starts every copy with the \
                     first machine's, the export each machine with its own"
                ),
            ));
            continue;
        }
        let chan = |j: usize, what: &str, csp: &str| format!("{}::{what}_{csp}", insts[j].elem.module);
        let memory = format!("Memory__{}", first.csp);
        let mut alts = Vec::new();
        let mut sync = BTreeSet::new();
        for &(k, s) in &users {
            // A write of the `k`th machine, then its forwarding to the
            // others, the first first.
            let mut then = name(memory.clone());
            for &(j, o) in users.iter().rev().filter(|(j, _)| *j != k) {
                then = prefix(chan(j, "set_EXT", &o.csp), vec![Field::Out(name("w__"))], then);
            }
            alts.push(prefix(chan(k, "set", &s.csp), vec![Field::In("w__".into())], then));
            for c in [chan(k, "set", &s.csp), chan(k, "set_EXT", &s.csp)] {
                out.chans[k].insert(c.clone());
                sync.insert(c.clone());
                out.hidden.push(c);
            }
        }
        if timed {
            alts.push(prefix("tock", vec![], name(memory.clone())));
        }
        alts.push(prefix("terminate", vec![], Expr::Skip));
        out.decls.push(Decl::Comment(format!(
            "RT-16: `{x}`, in the controller's memory: a write of one machine, then its forwarding to\n\
             each other machine's copy, one after another."
        )));
        out.decls.push(Decl::Def(memory.clone(), vec![], crate::cspm::ext(alts)));
        out.parts.push((name(memory), sync));
    }
    out
}
