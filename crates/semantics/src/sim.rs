//! `simulation S of M { cycleDef cycle == p }`: the RoboChart design `M`
//! under the simulation assumptions (semantics.md §4.2–4.3, RoboTool 3):
//!
//! - A1: an input read as present (`registerRead.i_e.true`) may be
//!   consumed by the design once, until the next read (external choice);
//! - A2: each output (event or platform call) is written to its register
//!   at once, and at most once per period;
//! - A3: the cycle: read every input register, then the design runs
//!   (external events only now) until the first `tock`, then `p - 1` more;
//! - `D__`: the constrained design, external events hidden, τ before
//!   `tock` (the specification of soundness checks);
//! - `TLF`: the same with the timelock escape (`TLFree`), whose deadlock
//!   freedom is schedulability.

use crate::cspm::{
    bin, call, dot, ext, guard, hide, name, nary, par, prefix, seq, BinOp, Decl, Expr, Field, ProcOp, ReplOp,
};
use crate::export::{ChanKind, Dir, Elem, Exporter};
use crate::util::ident;

/// The design's process `m::D__(args)` with its own end, `m::terminate`,
/// hidden (RoboTool: `design \ {terminate}`): the assumptions end with
/// the design, on the shared `terminate`.
fn design_process(m: &str, args: Vec<Expr>) -> Expr {
    hide(call(format!("{m}::D__"), args), Expr::Events(vec![name(format!("{m}::terminate"))]))
}

/// The CSPm module of a simulation; `Err` says why it cannot be exported.
pub(crate) fn simulation(
    ex: &mut Exporter<'_>,
    module: &str,
    sim_name: &str,
    design: &Elem,
) -> Result<Vec<Decl>, String> {
    if design.robosim {
        return Err(format!(
            "`{}` is a RoboSim element: a simulation constrains a RoboChart design",
            design.path.join("::")
        ));
    }
    if ex.profile == crate::Profile::Paper2019 {
        return simulation_paper(ex, module, sim_name, design);
    }
    let m = &design.module;
    let q = |c: &str| format!("{m}::{c}");
    let mut d = Vec::new();
    // External events, in the design's vocabulary.
    let AssumedInputs { inputs, read_set, a1, reads } = assume_inputs(ex, design, &q, &mut d)?;
    let mut outputs = Vec::new();
    let mut a2_alts = Vec::new();
    let mut a2_flags = Vec::new();
    for ch in &design.chans {
        match (ch.kind, ch.dir) {
            (ChanKind::Event, Dir::In) => {}
            (ChanKind::Event, Dir::Out) | (ChanKind::Call, _) => {
                let o = assume_output(ex, ch, &q(&ch.csp))?;
                outputs.push(o.chan);
                a2_flags.push(o.flag.clone());
                let mut write = vec![name("registerWrite"), name(o.reg)];
                write.extend(o.vars.iter().map(|v| name(v.clone())));
                a2_alts.push((o.flag, q(&ch.csp), o.fields, dot(write)));
            }
            (ChanKind::Ret, _) => {}
        }
    }
    let mut exports = vec![
        Decl::Comment(format!("The external events of {}: its inputs and its outputs.", design.path.join("::"))),
        Decl::Def("Inputs".into(), vec![], set(&inputs)),
        Decl::Def("Outputs".into(), vec![], set(&outputs)),
        Decl::Def("External".into(), vec![], call("union", vec![name("Inputs"), name("Outputs")])),
        Decl::Comment("A1: an input read as present can be consumed once, until the next read.".into()),
        Decl::Def("A1".into(), vec![], if a1.is_empty() { Expr::Stop } else { nary(ProcOp::Interleave, a1) }),
    ];
    exports.extend(d);
    exports.push(Decl::Def(
        "TA1".into(),
        vec![],
        nary(ProcOp::Interrupt, vec![name("A1"), prefix("terminate", vec![], Expr::Skip)]),
    ));
    // A2.
    exports.push(Decl::Comment("A2: each output is written to its register at once, at most once per period.".into()));
    let mut params: Vec<String> = a2_flags.clone();
    params.push("cycle".into());
    let all_true: Vec<Expr> = a2_flags.iter().map(|_| Expr::Bool(true)).chain([name("cycle")]).collect();
    let mut alts = Vec::new();
    for (k, (flag, cname, fields, write)) in a2_alts.iter().enumerate() {
        let mut next: Vec<Expr> = a2_flags.iter().map(|f| name(f.clone())).collect();
        next[k] = Expr::Bool(false);
        next.push(name("cycle"));
        alts.push(guard(
            name(flag.clone()),
            prefix(cname.clone(), fields.clone(), prefix_dot(write.clone(), call("A2run__", next))),
        ));
    }
    alts.push(prefix("terminate", vec![], Expr::Skip));
    alts.push(prefix(
        "tock",
        vec![],
        call("A2wait__", vec![bin(BinOp::Sub, name("cycle"), Expr::Int(1)), name("cycle")]),
    ));
    exports.push(Decl::Def("A2".into(), vec!["cycle".into()], call("A2run__", all_true.clone())));
    exports.push(Decl::Def("A2run__".into(), params, ext(alts)));
    exports.push(Decl::Def(
        "A2wait__".into(),
        vec!["k".into(), "cycle".into()],
        Expr::If(
            Box::new(bin(BinOp::Le, name("k"), Expr::Int(0))),
            Box::new(call("A2run__", all_true)),
            Box::new(prefix(
                "tock",
                vec![],
                call("A2wait__", vec![bin(BinOp::Sub, name("k"), Expr::Int(1)), name("cycle")]),
            )),
        ),
    ));
    // A3.
    exports.push(Decl::Comment(
        "A3: the cycle: every input register is read (no time passes), then the design runs until\n\
         the first `tock`, then the rest of the period."
            .into(),
    ));
    exports.push(Decl::Def("Reads__".into(), vec![], nary(ProcOp::Interleave, reads)));
    exports.push(Decl::Def(
        "A3".into(),
        vec!["cycle".into()],
        seq(vec![name("Reads__"), call("A3run__", vec![name("cycle")])]),
    ));
    exports.push(Decl::Def(
        "A3run__".into(),
        vec!["cycle".into()],
        ext(vec![
            Expr::Repl(
                ReplOp::ExtChoice,
                vec![("e".into(), name("External"))],
                Box::new(prefix("e", vec![], call("A3run__", vec![name("cycle")]))),
            ),
            prefix("terminate", vec![], Expr::Skip),
            prefix(
                "tock",
                vec![],
                seq(vec![
                    call("Wait", vec![bin(BinOp::Sub, name("cycle"), Expr::Int(1))]),
                    call("A3", vec![name("cycle")]),
                ]),
            ),
        ]),
    ));
    let read_sync =
        call("union", vec![set(&read_set), call("union", vec![name("Inputs"), Expr::Set(vec![name("terminate")])])]);
    exports.push(Decl::Def(
        "SimAssumptions".into(),
        vec!["cycle".into()],
        par(
            par(name("TA1"), read_sync, call("A3", vec![name("cycle")])),
            call("union", vec![name("Outputs"), Expr::Set(vec![name("tock"), name("terminate")])]),
            call("A2", vec![name("cycle")]),
        ),
    ));
    // The constrained design.
    let mut dparams = vec!["id__".to_string()];
    dparams.extend(design.consts.iter().map(|c| c.global.clone()));
    let dargs: Vec<Expr> = dparams.iter().map(|p| name(p.clone())).collect();
    let mut sparams = vec!["id__".to_string(), "cycle".to_string()];
    sparams.extend(design.consts.iter().map(|c| c.global.clone()));
    let sargs: Vec<Expr> = sparams.iter().map(|p| name(p.clone())).collect();
    let sync = call("union", vec![name("External"), Expr::Set(vec![name("tock"), name("terminate")])]);
    let hidden = call("union", vec![name("External"), Expr::Set(vec![name("terminate")])]);
    let constrained = |p: Expr| {
        hide(
            par(
                seq(vec![p, prefix("terminate", vec![], Expr::Skip)]),
                sync.clone(),
                call("SimAssumptions", vec![name("cycle")]),
            ),
            hidden.clone(),
        )
    };
    exports.push(Decl::Comment(format!(
        "D__: {} under the assumptions, external events hidden (the specification of soundness);\n\
         TLF: the same with the timelock escape, deadlock-free iff schedulable (parameters: {}).",
        design.path.join("::"),
        sparams.join(", ")
    )));
    exports.push(Decl::Def(
        "D__".into(),
        sparams.clone(),
        call("TimedPriority", vec![constrained(design_process(m, dargs.clone()))]),
    ));
    exports.push(Decl::Def("O__".into(), sparams.clone(), call("sbisim", vec![call("D__", sargs)])));
    exports.push(Decl::Def(
        "TLFree".into(),
        dparams,
        call(
            "prioritise",
            vec![
                nary(
                    ProcOp::Interrupt,
                    vec![
                        design_process(m, dargs.clone()),
                        prefix("timelock", vec![], call("RUN", vec![Expr::Set(vec![name("tock")])])),
                    ],
                ),
                Expr::SeqLit(vec![
                    call("union", vec![name("Outputs"), Expr::Set(vec![name("tock")])]),
                    Expr::Set(vec![name("timelock")]),
                ]),
            ],
        ),
    ));
    exports.push(Decl::Def(
        "TLF".into(),
        sparams,
        seq(vec![
            call("TimedPriority", vec![constrained(call("TLFree", dargs))]),
            call("RUN", vec![Expr::Set(vec![name("tock")])]),
        ]),
    ));
    Ok(vec![
        Decl::Comment(format!("simulation {sim_name} of {}", design.path.join("::"))),
        Decl::Module(module.to_string(), vec![], exports),
        Decl::Blank,
    ])
}

/// `e -> P` where `e` is an event expression (`c.a.b`).
fn prefix_dot(e: Expr, p: Expr) -> Expr {
    match e {
        Expr::Dot(mut parts) => {
            let head = parts.remove(0);
            let Expr::Name(c) = head else { return p };
            prefix(c, parts.into_iter().map(Field::Dot).collect(), p)
        }
        Expr::Name(c) => prefix(c, vec![], p),
        _ => p,
    }
}

/// What the inputs contribute to the assumptions (the same in both profiles).
struct AssumedInputs {
    /// The design's input events (`e.in`).
    inputs: Vec<Expr>,
    /// Their registers' reads (`registerRead.i_e`).
    read_set: Vec<Expr>,
    /// `A1_e` for each.
    a1: Vec<Expr>,
    /// One read of each register, then `SKIP`.
    reads: Vec<Expr>,
}

/// TA1 for the inputs of `design`, one `A1_e = registerRead.i_e?b?x ->
/// (if b then (e.in.x -> A1_e [] A1_e) else A1_e)` each, defined in `d`: the
/// external choice (semantics.md §4.2).
fn assume_inputs(
    ex: &mut Exporter<'_>,
    design: &Elem,
    q: &dyn Fn(&str) -> String,
    d: &mut Vec<Decl>,
) -> Result<AssumedInputs, String> {
    let mut out = AssumedInputs { inputs: Vec::new(), read_set: Vec::new(), a1: Vec::new(), reads: Vec::new() };
    for ch in design.chans.iter().filter(|c| c.kind == ChanKind::Event && c.dir == Dir::In) {
        let csp = q(&ch.csp);
        let reg = ex.in_reg(&ch.model);
        ex.register(true, &reg, &ch.values)?;
        out.inputs.push(dot(vec![name(csp.clone()), name("in")]));
        out.read_set.push(dot(vec![name("registerRead"), name(reg.clone())]));
        let me = format!("A1_{}", ident(&ch.model));
        let mut rf = vec![Field::Dot(name(reg)), Field::In("b".into())];
        let mut ev = vec![name(csp), name("in")];
        // One name per value field (a product is one field, a tuple).
        for k in 0..ch.values.len() {
            let x = if ch.values.len() == 1 { "x".to_string() } else { format!("x{k}") };
            rf.push(Field::In(x.clone()));
            ev.push(name(x));
        }
        let consume = ext(vec![prefix_dot(dot(ev), name(me.clone())), name(me.clone())]);
        let body = prefix(
            "registerRead",
            rf.clone(),
            Expr::If(Box::new(name("b")), Box::new(consume), Box::new(name(me.clone()))),
        );
        d.push(Decl::Def(me.clone(), vec![], body));
        out.a1.push(name(me));
        out.reads.push(prefix("registerRead", rf, Expr::Skip));
    }
    Ok(out)
}

/// An output as both profiles' TA2 see it.
struct AssumedOutput {
    /// Its register.
    reg: String,
    /// The design's event (`e.out` or `opCall`).
    chan: Expr,
    /// The flag saying it may still happen in the period (`w_e`).
    flag: String,
    /// Names for its values.
    vars: Vec<String>,
    /// The fields that bind them (after `.out` for an event).
    fields: Vec<Field>,
}

/// The register of output `ch` (named `csp` in the design) and how TA2
/// refers to it.
fn assume_output(ex: &mut Exporter<'_>, ch: &crate::export::Chan, csp: &str) -> Result<AssumedOutput, String> {
    let reg = ex.out_reg(&ch.model);
    ex.register(false, &reg, &ch.values)?;
    let event = ch.kind == ChanKind::Event;
    let chan = if event { dot(vec![name(csp.to_string()), name("out")]) } else { name(csp.to_string()) };
    let vars: Vec<String> = (0..ch.values.len()).map(|k| format!("x{k}")).collect();
    let mut fields = if event { vec![Field::Dot(name("out"))] } else { vec![] };
    fields.extend(vars.iter().map(|v| Field::In(v.clone())));
    Ok(AssumedOutput { reg, chan, flag: format!("w_{}", ident(&ch.model)), vars, fields })
}

/// An output of the paper's assumptions: its flag, channel, fields binding
/// the values, register and value names.
type PaperOut = (String, String, Vec<Field>, String, Vec<String>);

/// The paper's assumptions (semantics.md §4.4, paper §6.1): `TA1` as in
/// RoboTool 3 (external choice), `TA2 = Order` (outputs recorded in order,
/// written `true` in that order, then the others `false`), `TA3` (reads,
/// external events until the first write, every output register written
/// once, then `terminate` or `p` time units), and
/// `PConstrained = prioritise(Constrained, <External, {registerWrite, tock}>)`.
fn simulation_paper(ex: &mut Exporter<'_>, module: &str, sim_name: &str, design: &Elem) -> Result<Vec<Decl>, String> {
    let m = &design.module;
    let q = |c: &str| format!("{m}::{c}");
    let mut d = Vec::new();
    let AssumedInputs { inputs, read_set, a1, reads } = assume_inputs(ex, design, &q, &mut d)?;
    let mut outputs = Vec::new();
    let mut rets = Vec::new();
    let mut outs: Vec<PaperOut> = Vec::new();
    for ch in &design.chans {
        match (ch.kind, ch.dir) {
            (ChanKind::Event, Dir::In) => {}
            (ChanKind::Event, Dir::Out) | (ChanKind::Call, _) => {
                let o = assume_output(ex, ch, &q(&ch.csp))?;
                outputs.push(o.chan);
                outs.push((o.flag, q(&ch.csp), o.fields, o.reg, o.vars));
            }
            (ChanKind::Ret, _) => rets.push(name(q(&ch.csp))),
        }
    }
    let flags: Vec<String> = outs.iter().map(|o| o.0.clone()).collect();
    let fresh: Vec<Expr> = flags.iter().map(|_| Expr::Bool(true)).collect();
    let writes: Vec<Expr> = outs.iter().map(|o| dot(vec![name("registerWrite"), name(o.3.clone())])).collect();
    let mut exports = vec![
        Decl::Comment(format!(
            "The external events of {}: inputs, outputs (calls and output events) and returns.",
            design.path.join("::")
        )),
        Decl::Def("Inputs".into(), vec![], set(&inputs)),
        Decl::Def("Outputs".into(), vec![], set(&outputs)),
        Decl::Def(
            "External".into(),
            vec![],
            call("union", vec![name("Inputs"), call("union", vec![name("Outputs"), set(&rets)])]),
        ),
        Decl::Def("Writes".into(), vec![], set(&writes)),
        Decl::Comment("TA1: an input read as present can be consumed once, until the next read.".into()),
        Decl::Def("A1".into(), vec![], if a1.is_empty() { Expr::Stop } else { nary(ProcOp::Interleave, a1) }),
    ];
    exports.extend(d);
    exports.push(Decl::Def(
        "TA1".into(),
        vec![],
        nary(ProcOp::Interrupt, vec![name("A1"), prefix("terminate", vec![], Expr::Skip)]),
    ));
    // TA2 = Order.
    exports.push(Decl::Comment(
        "TA2 (Order): outputs are recorded in order, written `true` in that order, then the others\n\
         `false`; then afresh."
            .into(),
    ));
    let n = outs.len() as i64;
    let mut params = vec!["occ".to_string()];
    params.extend(flags.iter().cloned());
    let cur: Vec<Expr> = flags.iter().map(|f| name(f.clone())).collect();
    let mut record = Vec::new();
    let mut absent = Vec::new();
    for (k, (flag, chan, fields, reg, vars)) in outs.iter().enumerate() {
        let mut value = vec![name(reg.clone()), Expr::Bool(true)];
        value.extend(vars.iter().map(|v| name(v.clone())));
        let mut args = vec![bin(BinOp::Cat, name("occ"), Expr::SeqLit(vec![dot(value)]))];
        let mut next = cur.clone();
        next[k] = Expr::Bool(false);
        args.extend(next);
        record.push(prefix(chan.clone(), fields.clone(), call("Order", args)));
        let mut ff = vec![Field::Dot(name(reg.clone())), Field::Dot(Expr::Bool(false))];
        ff.extend(vars.iter().map(|v| Field::In(v.clone())));
        absent.push(Expr::If(
            Box::new(name(flag.clone())),
            Box::new(prefix("registerWrite", ff, Expr::Skip)),
            Box::new(Expr::Skip),
        ));
    }
    let mut fresh_args = vec![Expr::SeqLit(vec![])];
    fresh_args.extend(fresh.iter().cloned());
    let mut head_args = vec![call("tail", vec![name("occ")])];
    head_args.extend(cur.iter().cloned());
    exports.push(Decl::Def(
        "Order".into(),
        params.clone(),
        ext(vec![
            guard(bin(BinOp::Lt, call("length", vec![name("occ")]), Expr::Int(n)), ext(record)),
            guard(
                Expr::Not(Box::new(call("null", vec![name("occ")]))),
                prefix("registerWrite", vec![Field::Out(call("head", vec![name("occ")]))], call("Order", head_args)),
            ),
            guard(
                call("null", vec![name("occ")]),
                seq(vec![nary(ProcOp::Interleave, absent), call("Order", fresh_args.clone())]),
            ),
        ]),
    ));
    exports.push(Decl::Def(
        "TA2".into(),
        vec![],
        nary(ProcOp::Interrupt, vec![call("Order", fresh_args), prefix("terminate", vec![], Expr::Skip)]),
    ));
    // TA3.
    exports.push(Decl::Comment(
        "TA3: every input register is read; external events until the first write; every output\n\
         register written once; then `terminate`, or `cycle` time units and the next cycle."
            .into(),
    ));
    exports.push(Decl::Def("Reads__".into(), vec![], nary(ProcOp::Interleave, reads)));
    exports.push(Decl::Def(
        "TA3".into(),
        vec!["cycle".into()],
        seq(vec![name("Reads__"), call("Run__", vec![name("cycle")])]),
    ));
    let mut run_alts = vec![Expr::Repl(
        ReplOp::ExtChoice,
        vec![("e".into(), name("External"))],
        Box::new(prefix("e", vec![], call("Run__", vec![name("cycle")]))),
    )];
    let mut write_alts = Vec::new();
    for (k, (flag, _, _, reg, vars)) in outs.iter().enumerate() {
        let mut f = vec![Field::Dot(name(reg.clone())), Field::In("b".into())];
        f.extend(vars.iter().map(|v| Field::In(v.clone())));
        let mut first: Vec<Expr> = fresh.clone();
        first[k] = Expr::Bool(false);
        first.push(name("cycle"));
        run_alts.push(prefix("registerWrite", f.clone(), call("Writes__", first)));
        let mut next = cur.clone();
        next[k] = Expr::Bool(false);
        next.push(name("cycle"));
        write_alts.push(guard(name(flag.clone()), prefix("registerWrite", f, call("Writes__", next))));
    }
    exports.push(Decl::Def("Run__".into(), vec!["cycle".into()], ext(run_alts)));
    let none_left = flags.iter().fold(Expr::Bool(true), |acc, f| {
        let nf = Expr::Not(Box::new(name(f.clone())));
        if acc == Expr::Bool(true) {
            nf
        } else {
            bin(BinOp::And, acc, nf)
        }
    });
    let mut wparams = flags.clone();
    wparams.push("cycle".into());
    exports.push(Decl::Def(
        "Writes__".into(),
        wparams,
        Expr::If(
            Box::new(none_left),
            Box::new(ext(vec![
                prefix("terminate", vec![], Expr::Skip),
                seq(vec![call("Wait", vec![name("cycle")]), call("TA3", vec![name("cycle")])]),
            ])),
            Box::new(ext(write_alts)),
        ),
    ));
    let read_sync =
        call("union", vec![set(&read_set), call("union", vec![name("Inputs"), Expr::Set(vec![name("terminate")])])]);
    exports.push(Decl::Def(
        "TA1A2A3".into(),
        vec!["cycle".into()],
        par(
            par(name("TA1"), read_sync, call("TA3", vec![name("cycle")])),
            call(
                "union",
                vec![name("Outputs"), call("union", vec![name("Writes"), Expr::Set(vec![name("terminate")])])],
            ),
            name("TA2"),
        ),
    ));
    let mut dparams = vec!["id__".to_string()];
    dparams.extend(design.consts.iter().map(|c| c.global.clone()));
    let dargs: Vec<Expr> = dparams.iter().map(|p| name(p.clone())).collect();
    let mut sparams = vec!["id__".to_string(), "cycle".to_string()];
    sparams.extend(design.consts.iter().map(|c| c.global.clone()));
    let sargs: Vec<Expr> = sparams.iter().map(|p| name(p.clone())).collect();
    exports.push(Decl::Comment(format!(
        "PConstrained: {} under the assumptions, external events visible and before register\n\
         writes and time; D__: with them hidden (the specification of soundness); TLF: deadlock-free\n\
         iff schedulable (parameters: {}).",
        design.path.join("::"),
        sparams.join(", ")
    )));
    let constrained = hide(
        par(
            seq(vec![design_process(m, dargs), prefix("terminate", vec![], Expr::Skip)]),
            call("union", vec![name("External"), Expr::Set(vec![name("tock"), name("terminate")])]),
            call("TA1A2A3", vec![name("cycle")]),
        ),
        Expr::Set(vec![name("terminate")]),
    );
    exports.push(Decl::Def(
        "PConstrained".into(),
        sparams.clone(),
        call(
            "prioritise",
            vec![
                constrained,
                Expr::SeqLit(vec![
                    name("External"),
                    call("union", vec![name("Writes"), Expr::Set(vec![name("tock")])]),
                ]),
            ],
        ),
    ));
    exports.push(Decl::Def(
        "D__".into(),
        sparams.clone(),
        call("TimedPriority", vec![hide(call("PConstrained", sargs.clone()), name("External"))]),
    ));
    exports.push(Decl::Def("O__".into(), sparams.clone(), call("sbisim", vec![call("D__", sargs.clone())])));
    exports.push(Decl::Def(
        "TLF".into(),
        sparams,
        seq(vec![call("PConstrained", sargs), call("RUN", vec![Expr::Set(vec![name("tock")])])]),
    ));
    Ok(vec![
        Decl::Comment(format!("simulation {sim_name} of {} (the paper's assumptions)", design.path.join("::"))),
        Decl::Module(module.to_string(), vec![], exports),
        Decl::Blank,
    ])
}

/// The set of events `v` (`{}` when empty rather than an empty `{| |}`).
fn set(v: &[Expr]) -> Expr {
    if v.is_empty() {
        Expr::Set(vec![])
    } else {
        Expr::Events(v.to_vec())
    }
}
