//! RoboTool's per-element names of RoboSim (the reference's
//! `csp-gen/sim/defs/pkg223_aggregation_sim_Movement.csp`): each element's
//! module declares its own `terminate`, `endexec`, `RegisterDataInput`,
//! `RegisterDataOutput` (constructors `i_x`, `o_x`), `registerRead` and
//! `registerWrite`, so that a `csp` block written against RoboTool's
//! output (`M::registerWrite.M::o_op`, `M::endexec`) names the export's
//! events. Inside the module the bare names are the element's own (CSPm's
//! scoping), so the machine's processes need no change; a container renames
//! its components' names into its own, and comparisons between elements
//! (RT-10: registers matched by name) rename both sides to the global
//! names of `robosim_defs.csp`.

use crate::cspm::{dot, name, Decl, Expr};
use crate::export::{Elem, Exporter, Profile};

/// A register: its constructor and the types of its values.
pub(crate) type RegSig = (String, Vec<Expr>);

/// The fields after the constructor: inputs carry a presence flag, and so
/// do paper2019 outputs (as the global `InputRegister`, `OutputRegister`).
fn flagged(profile: Profile, input: bool) -> bool {
    input || profile == Profile::Paper2019
}

/// The element's own names, for its module's exports; `endexec` unless the
/// module declares it itself (an operation on its own).
pub(crate) fn own_names(profile: Profile, inputs: &[RegSig], outputs: &[RegSig], endexec: bool) -> Vec<Decl> {
    let mut d = vec![Decl::Comment(
        "Its own end, cycle and registers, as RoboTool declares them per element (`M::terminate`,\n\
         `M::endexec`, `M::registerRead.M::i_x`, `M::registerWrite.M::o_x`)."
            .into(),
    )];
    let mut chans = vec!["terminate".to_string()];
    if endexec {
        chans.push("endexec".into());
    }
    d.push(Decl::Channel(chans, vec![]));
    for (regs, input, ty, chan) in
        [(inputs, true, "RegisterDataInput", "registerRead"), (outputs, false, "RegisterDataOutput", "registerWrite")]
    {
        // CSPm has no empty datatype: an element without registers of a
        // kind has no channel for them (nor has RoboTool's).
        if regs.is_empty() {
            continue;
        }
        let ctors = regs
            .iter()
            .map(|(c, vals)| {
                let mut f = Vec::new();
                if flagged(profile, input) {
                    f.push(name("Bool"));
                }
                f.extend(vals.iter().cloned());
                (c.clone(), f)
            })
            .collect();
        d.push(Decl::Datatype(ty.into(), ctors));
        d.push(Decl::Channel(vec![chan.into()], vec![name(ty)]));
    }
    d
}

/// A register renaming: the component's constructor, the one it becomes,
/// the value types, whether it is an input.
pub(crate) struct RegRename {
    pub from: String,
    pub to: String,
    pub values: Vec<Expr>,
    pub input: bool,
}

/// `p`, a process of the element module `module`, with the module's own
/// names renamed to the bare ones of the scope it is used in: a
/// container's own (inside its module) or the global ones (at the top
/// level); `endexec` when the module declares it.
pub(crate) fn unqualify(profile: Profile, p: Expr, module: &str, regs: &[RegRename], endexec: bool) -> Expr {
    let q = |n: &str| name(format!("{module}::{n}"));
    let mut pairs = vec![(q("terminate"), name("terminate"))];
    if endexec {
        pairs.push((q("endexec"), name("endexec")));
    }
    rename_regs(profile, Expr::Rename(Box::new(p), pairs, vec![]), module, regs)
}

/// `p` with the registers `regs` of the module `module` renamed to the
/// bare names.
pub(crate) fn rename_regs(profile: Profile, mut p: Expr, module: &str, regs: &[RegRename]) -> Expr {
    let q = |n: &str| name(format!("{module}::{n}"));
    for r in regs {
        let chan = if r.input { "registerRead" } else { "registerWrite" };
        let mut f = vec![q(chan), q(&r.from)];
        let mut t = vec![name(chan), name(r.to.clone())];
        let mut gens = Vec::new();
        if flagged(profile, r.input) {
            f.push(name("b__"));
            t.push(name("b__"));
            gens.push(("b__".to_string(), name("Bool")));
        }
        for (k, v) in r.values.iter().enumerate() {
            let x = format!("x{k}__");
            f.push(name(x.clone()));
            t.push(name(x.clone()));
            gens.push((x, v.clone()));
        }
        p = Expr::Rename(Box::new(p), vec![(dot(f), dot(t))], gens);
    }
    p
}

/// RT-10: the process `p` of the RoboSim element `e` on the global names
/// (`terminate`, `endexec`, `registerRead.i_x`, `registerWrite.o_x`), so
/// that two elements, or an element and a simulation, are compared on
/// common names (registers matched by name).
pub(crate) fn globalise(ex: &Exporter<'_>, e: &Elem, p: Expr) -> Expr {
    let regs: Vec<RegRename> = e
        .inputs
        .iter()
        .map(|r| (r, true))
        .chain(e.outputs.iter().map(|r| (r, false)))
        .map(|(r, input)| RegRename { from: r.ctor.clone(), to: r.ctor.clone(), values: r.values.clone(), input })
        .collect();
    unqualify(ex.profile, p, &e.module, &regs, true)
}
