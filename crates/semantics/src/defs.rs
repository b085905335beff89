//! The two shared files: `robosim_defs.csp` (time, helper processes,
//! sticky arithmetic, registers) and `instantiations.csp` (the bounded
//! types and the constants' default values).

use crate::cspm::{bin, call, ext, name, prefix, BinOp, Decl, Expr, ReplOp};
use std::collections::{BTreeMap, BTreeSet};

use robosim_hir::assertions::AssertionFile;
use robosim_hir::domains::{number_domains, DomainInputs, NumRange, BASE, NAMES};
use robosim_hir::{File, FileKind};

use crate::export::{Exporter, OutFile};

/// Whether the shared file defines `name`: its own processes, or
/// RoboTool's library ([`robosim_hir::csp_defs`]).
pub fn is_shared(name: &str) -> bool {
    SHARED_PROCESSES.contains(&name) || robosim_hir::csp_defs::defines(name, true)
}

/// Names the shared file defines itself (for the structural checker);
/// RoboTool's library adds its own ([`is_shared`]).
pub const SHARED_PROCESSES: &[&str] = &[
    "TimedPriority",
    "TStop",
    "Wait",
    "WaitInterval",
    "Delayable",
    "TimelockFree__",
    "Plus",
    "Minus",
    "Mult",
    "Div",
    "Modulus",
    "Neg",
    "Max__",
    "Min__",
    "ClockTick",
    "Concat",
    "Filter",
    "Last",
    "Front",
    "Reverse",
    "in'",
    "out'",
];

fn def(n: &str, params: &[&str], body: Expr) -> Decl {
    Decl::Def(n.into(), params.iter().map(|s| s.to_string()).collect(), body)
}

fn n(s: &str) -> Expr {
    name(s)
}

fn sticky(op: BinOp) -> Expr {
    // RoboTool wraps every divisor so that `x / 0` is `x / 1` (RT-6).
    let divisor = match op {
        BinOp::Div => {
            Expr::If(Box::new(bin(BinOp::Eq, n("e2"), Expr::Int(0))), Box::new(Expr::Int(1)), Box::new(n("e2")))
        }
        _ => n("e2"),
    };
    let r = bin(op, n("e1"), divisor);
    Expr::If(Box::new(call("member", vec![r.clone(), n("T")])), Box::new(r), Box::new(n("e1")))
}

pub(crate) fn robosim_defs(ex: &Exporter<'_>) -> OutFile {
    let mut d = Vec::new();
    if ex.timed {
        d.push(Decl::Comment("Time: `tock` marks one time unit; `tock'` is its copy in timed deadlock checks.".into()));
        d.push(Decl::Channel(vec!["tock".into(), "tock'".into()], vec![]));
    } else {
        d.push(Decl::Comment("RoboChart's untimed semantics (robotool-facts RT-9): no time events, no clocks.".into()));
    }
    d.extend([
        Decl::Comment(if ex.timed {
            "`terminate` ends RoboSim cycles and the simulation assumptions together; `timelock` marks\n\
             the escape of a design that can do neither an output nor `tock` (schedulability checks)."
                .into()
        } else {
            "`terminate`, `timelock`: the timed script's names, kept for `csp` blocks.".into()
        }),
        Decl::Channel(vec!["terminate".into(), "timelock".into()], vec![]),
        Decl::Comment(if ex.timed {
            "`endexec` ends a RoboSim cycle. Each RoboSim element has its own `endexec`, `terminate` and\n\
             registers (RoboTool's `M::endexec`, `M::registerWrite.M::o_x`); these global names are those\n\
             two elements, or an element and a simulation, are compared on (RT-10: matched by name)."
                .into()
        } else {
            "`endexec`: the timed script's name, kept for `csp` blocks.".into()
        }),
        Decl::Channel(vec!["endexec".into()], vec![]),
        Decl::Channel(vec!["deadline_done__".into()], vec![]),
        Decl::Comment("`terminated__` follows termination in `terminates` checks (robotool-facts RT-10).".into()),
        Decl::Channel(vec!["terminated__".into()], vec![]),
        Decl::Comment("Directions of RoboChart events.".into()),
        Decl::Datatype("InOut".into(), vec![("in".into(), vec![]), ("out".into(), vec![])]),
        Decl::Transparent(vec!["sbisim".into()]),
        Decl::Blank,
    ]);
    // Registers.
    let regs = |m: &std::collections::BTreeMap<String, Vec<Expr>>, input: bool| -> Vec<(String, Vec<Expr>)> {
        m.iter()
            .map(|(c, vals)| {
                let mut f = Vec::new();
                // Inputs carry a presence flag; paper2019 outputs carry one too.
                if input || ex.profile == crate::Profile::Paper2019 {
                    f.push(n("Bool"));
                }
                f.extend(vals.iter().cloned());
                (c.clone(), f)
            })
            .collect()
    };
    if !ex.in_regs.is_empty() || !ex.out_regs.is_empty() {
        d.push(Decl::Comment(
            "Sensor and actuator registers of the simulations, and of the RoboSim elements when compared\n\
             (matched by name; each element's module has its own, renamed to these)."
                .into(),
        ));
    }
    if !ex.in_regs.is_empty() {
        d.push(Decl::Datatype("InputRegister".into(), regs(&ex.in_regs, true)));
        d.push(Decl::Channel(vec!["registerRead".into()], vec![n("InputRegister")]));
    }
    if !ex.out_regs.is_empty() {
        d.push(Decl::Datatype("OutputRegister".into(), regs(&ex.out_regs, false)));
        d.push(Decl::Channel(vec!["registerWrite".into()], vec![n("OutputRegister")]));
    }
    d.push(Decl::Blank);
    if ex.timed {
        time_defs(&mut d);
    }
    // RoboTool's library as RoboTool defines it, the same text the model
    // checker's CSPm bridge loads (`EDeadline` for urgent events, `EndBy`
    // for statement deadlines `P <{d}`, `StartBy`, `CRUN`, … for users'
    // `csp` blocks); its untimed script has the untimed one.
    d.push(Decl::Blank);
    d.push(Decl::Comment(format!(
        "RoboTool's library ({}state helpers, core functions), as in its {} script.",
        if ex.timed { "tock-CSP operators, " } else { "" },
        if ex.timed { "timed" } else { "untimed" }
    )));
    d.push(Decl::Raw(robosim_hir::csp_defs::text(ex.timed).trim_end().to_string(), String::new()));
    arithmetic(&mut d, ex.timed);
    helpers(ex, &mut d);
    OutFile {
        name: "robosim_defs.csp".into(),
        title: if ex.timed {
            "Shared definitions: time, helper processes, sticky arithmetic and registers".into()
        } else {
            "Shared definitions of the untimed semantics: sticky arithmetic and registers".into()
        },
        decls: d,
    }
}

/// The processes of time: `TimedPriority`, `TStop`, `Wait`, … (the timed
/// semantics only).
fn time_defs(d: &mut Vec<Decl>) {
    d.push(Decl::Comment("Maximal progress: internal events happen before time passes.".into()));
    d.push(def(
        "TimedPriority",
        &["P"],
        call("prioritise", vec![n("P"), Expr::SeqLit(vec![Expr::Set(vec![]), Expr::Set(vec![n("tock")])])]),
    ));
    d.push(Decl::Comment("Only time passes.".into()));
    d.push(def("TStop", &[], prefix("tock", vec![], n("TStop"))));
    d.push(Decl::Comment("Exactly n time units.".into()));
    d.push(def(
        "Wait",
        &["n"],
        Expr::If(
            Box::new(bin(BinOp::Le, n("n"), Expr::Int(0))),
            Box::new(Expr::Skip),
            Box::new(prefix("tock", vec![], call("Wait", vec![bin(BinOp::Sub, n("n"), Expr::Int(1))]))),
        ),
    ));
    d.push(Decl::Comment("wait([a, b]): an internal choice, made at once, of a duration in S.".into()));
    d.push(def(
        "WaitInterval",
        &["S"],
        Expr::Repl(ReplOp::IntChoice, vec![("n".into(), n("S"))], Box::new(call("Wait", vec![n("n")]))),
    ));
    d.push(Decl::Comment("The event e whenever the environment offers it; time may pass meanwhile.".into()));
    d.push(def(
        "Delayable",
        &["e"],
        ext(vec![prefix("e", vec![], Expr::Skip), prefix("tock", vec![], call("Delayable", vec![n("e")]))]),
    ));
    d.push(Decl::Comment(
        "timelock-free (robotool-facts RT-10): the environment may refuse any event of E, never tock.".into(),
    ));
    d.push(def(
        "TimelockFree__",
        &["E"],
        ext(vec![
            prefix("tock", vec![], call("TimelockFree__", vec![n("E")])),
            crate::cspm::nary(
                crate::cspm::ProcOp::IntChoice,
                vec![
                    Expr::Stop,
                    Expr::Repl(
                        ReplOp::ExtChoice,
                        vec![("e".into(), n("E"))],
                        Box::new(prefix("e", vec![], call("TimelockFree__", vec![n("E")]))),
                    ),
                ],
            ),
        ]),
    ));
}

/// RoboTool's sticky arithmetic, `Max__`, `Min__` and (timed) `ClockTick`.
fn arithmetic(d: &mut Vec<Decl>, timed: bool) {
    d.push(Decl::Blank);
    d.push(Decl::Comment(
        "RoboTool's arithmetic on the bounded types: a result outside the type T keeps the left operand.".into(),
    ));
    for (f, op) in [
        ("Plus", BinOp::Add),
        ("Minus", BinOp::Sub),
        ("Mult", BinOp::Mul),
        ("Div", BinOp::Div),
        ("Modulus", BinOp::Mod),
    ] {
        d.push(def(f, &["e1", "e2", "T"], sticky(op)));
    }
    d.push(def(
        "Neg",
        &["e1", "T"],
        Expr::If(
            Box::new(call("member", vec![Expr::Neg(Box::new(n("e1"))), n("T")])),
            Box::new(Expr::Neg(Box::new(n("e1")))),
            Box::new(n("e1")),
        ),
    ));
    d.push(def(
        "Max__",
        &["a", "b"],
        Expr::If(Box::new(bin(BinOp::Gt, n("a"), n("b"))), Box::new(n("a")), Box::new(n("b"))),
    ));
    d.push(def(
        "Min__",
        &["a", "b"],
        Expr::If(Box::new(bin(BinOp::Lt, n("a"), n("b"))), Box::new(n("a")), Box::new(n("b"))),
    ));
    if timed {
        d.push(Decl::Comment("Clocks count time units and stop at their bound m.".into()));
        d.push(def(
            "ClockTick",
            &["c", "m"],
            Expr::If(
                Box::new(bin(BinOp::Lt, n("c"), n("m"))),
                Box::new(bin(BinOp::Add, n("c"), Expr::Int(1))),
                Box::new(n("c")),
            ),
        ));
    }
}

/// The sequence helpers in use and the tuple projections.
fn helpers(ex: &Exporter<'_>, d: &mut Vec<Decl>) {
    let s = || n("s");
    let empty = || Expr::SeqLit(vec![]);
    let hd = || call("head", vec![n("s")]);
    let tl = || call("tail", vec![n("s")]);
    let if_ = |c: Expr, a: Expr, b: Expr| Expr::If(Box::new(c), Box::new(a), Box::new(b));
    for h in &ex.helpers {
        let (comment, params, body): (&str, &[&str], Expr) = match *h {
            "Concat" => (
                "s ^ t, or s when the result would be longer than core_seq_max (sticky, as arithmetic).",
                &["s", "t"],
                if_(
                    bin(
                        BinOp::Le,
                        bin(BinOp::Add, call("length", vec![s()]), call("length", vec![n("t")])),
                        n("core_seq_max"),
                    ),
                    bin(BinOp::Cat, s(), n("t")),
                    s(),
                ),
            ),
            "Filter" => (
                "The elements of s that are in A, in order.",
                &["s", "A"],
                if_(
                    call("null", vec![s()]),
                    empty(),
                    if_(
                        call("member", vec![hd(), n("A")]),
                        bin(BinOp::Cat, Expr::SeqLit(vec![hd()]), call("Filter", vec![tl(), n("A")])),
                        call("Filter", vec![tl(), n("A")]),
                    ),
                ),
            ),
            "Last" => (
                "The last element of a non-empty sequence.",
                &["s"],
                if_(call("null", vec![tl()]), hd(), call("Last", vec![tl()])),
            ),
            "Front" => (
                "A non-empty sequence without its last element.",
                &["s"],
                if_(
                    call("null", vec![tl()]),
                    empty(),
                    bin(BinOp::Cat, Expr::SeqLit(vec![hd()]), call("Front", vec![tl()])),
                ),
            ),
            "Reverse" => (
                "The sequence backwards.",
                &["s"],
                if_(
                    call("null", vec![s()]),
                    empty(),
                    bin(BinOp::Cat, call("Reverse", vec![tl()]), Expr::SeqLit(vec![hd()])),
                ),
            ),
            "in'" | "out'" => (
                "InOut's direction by another name, for the modules whose own event bears RoboTool's name\n\
                 `in` or `out`, which hides the constructor there.",
                &[],
                n(&h[..h.len() - 1]),
            ),
            _ => continue,
        };
        d.push(Decl::Comment(comment.into()));
        d.push(def(h, params, body));
    }
    if !ex.tuple_arities.is_empty() {
        d.push(Decl::Comment("Components of tuples (values of product types).".into()));
    }
    for &k in &ex.tuple_arities {
        let xs: Vec<String> = (1..=k).map(|i| format!("x{i}")).collect();
        let pat = format!("({})", xs.join(", "));
        for (i, x) in xs.iter().enumerate() {
            d.push(Decl::Def(format!("Proj{k}_{}", i + 1), vec![pat.clone()], n(x)));
        }
    }
}

/// `core_nat`, `core_int` and `core_real`, and a comment saying how they
/// were found: RoboTool's (RT-5, computed once in hir for every back end)
/// for the models of each project (the widest range when the workspace
/// holds several), the types a `csp` block fixes as given. A project with
/// RoboSim models gets the types RoboTool computes for its RoboSim
/// elements (`sim/instantiations.csp`: RoboChart and RoboSim models
/// together); the one file written here serves both languages, and the
/// comment says when RoboTool's RoboChart types would differ.
pub(crate) fn number_types(
    ex: &Exporter<'_>,
    files: &[File],
    assertion_files: &[(File, &AssertionFile)],
) -> ([(i64, i64); 3], String) {
    let (db, ws) = (ex.db, ex.ws);
    // RT-7: a block's other definitions (functions, constants) belong to
    // its own file's script, and old-style names (`nametype real = …`)
    // define exactly those names: the shared types are RoboTool's generated
    // ones, unless a block gives `core_nat`, `core_int` or `core_real`.
    let mut inputs = DomainInputs::default();
    // The functions a file's blocks define give the values of the calls of
    // them (RoboTool's instantiations widen by the calls, evaluated in the
    // script, RT-5); the other calls return their defaults (RT-2).
    for (_, read) in assertion_files {
        inputs.functions.extend(read.instantiations.functions.iter().cloned());
    }
    for (_, read) in assertion_files {
        for (name, lo, hi, _) in &read.instantiations.types {
            if let Some(r) = NAMES.iter().position(|n| n == name) {
                inputs.fixed[r] = Some(NumRange { lo: *lo, hi: *hi });
            }
        }
    }
    // Each project, and whether it holds RoboChart and RoboSim models.
    let mut projects: BTreeMap<Option<u32>, (bool, bool)> = BTreeMap::new();
    for f in files {
        let at = projects.entry(robosim_hir::index::project_of(db, ws, *f)).or_default();
        match f.kind(db) {
            FileKind::RoboChart => at.0 = true,
            FileKind::RoboSim => at.1 = true,
            _ => {}
        }
    }
    projects.retain(|_, (rc, rs)| *rc || *rs);
    let fixed: Vec<&str> = (0..3).filter(|r| inputs.fixed[*r].is_some()).map(|r| NAMES[r]).collect();
    let fixed = match fixed.is_empty() {
        true => String::new(),
        false => format!("\n{} as set by a `csp` block of an assertion file.", fixed.join(", ")),
    };
    let hull = |a: Option<[(i64, i64); 3]>, b: [(i64, i64); 3]| match a {
        None => b,
        Some(a) => [0, 1, 2].map(|r| (a[r].0.min(b[r].0), a[r].1.max(b[r].1))),
    };
    let mut doms: Option<[(i64, i64); 3]> = None;
    let mut chart_only: Option<[(i64, i64); 3]> = None;
    for (p, (rc, rs)) in &projects {
        let mut got = Vec::new();
        for robosim in [false, true].into_iter().filter(|r| if *r { *rs } else { *rc }) {
            match number_domains(db, ws, *p, inputs.clone(), robosim) {
                Ok(nd) => got.push(nd.domains.map(|d| (d.lo, d.hi))),
                Err(e) => {
                    // RoboTool leaves the values to FDR; without them, the
                    // defaults (a `csp` block gives the types).
                    let base = [0, 1, 2].map(|r| inputs.fixed[r].unwrap_or(BASE[r])).map(|d| (d.lo, d.hi));
                    let note = format!(
                        "Bounded types: RoboTool's defaults {{0..2}}, {{-2..2}}, {{-2..2}}; their widening by the values of \n\
                         the models' expressions (RT-5) is not worked out here: {}{fixed}",
                        e.message
                    );
                    return (base, note);
                }
            }
        }
        if *rc {
            chart_only = Some(hull(chart_only, got[0]));
        }
        // The RoboSim computation when the project has RoboSim models.
        if let Some(g) = got.last() {
            doms = Some(hull(doms, *g));
        }
    }
    let sim = projects.values().any(|(_, rs)| *rs);
    let differ = match (chart_only, doms) {
        (Some(c), Some(d)) if sim && c != d => {
            let ts: Vec<String> = (0..3).map(|r| format!("{} = {{{}..{}}}", NAMES[r], c[r].0, c[r].1)).collect();
            format!(
                "\nRoboTool's RoboChart elements have {} (their lists leave the RoboSim models out).",
                ts.join(", ")
            )
        }
        _ => String::new(),
    };
    if sim {
        let note = format!(
            "Bounded types (RT-5, as RoboTool's sim/instantiations.csp): RoboTool's defaults {{0..2}}, {{-2..2}},\n\
             {{-2..2}}, widened to the values of the RoboChart and RoboSim models' expressions (sticky arithmetic,\n\
             `x / 0` as `x / 1`); the values assertions give constants widen nothing.{differ}{fixed}"
        );
        return (doms.unwrap_or([(0, 2), (-2, 2), (-2, 2)]), note);
    }
    let note = format!(
        "Bounded types (RT-5): RoboTool's defaults {{0..2}}, {{-2..2}}, {{-2..2}}, widened to the values of\n\
         the models' expressions (sticky arithmetic, `x / 0` as `x / 1`); the values assertions give\n\
         constants widen nothing.{fixed}"
    );
    (doms.unwrap_or([(0, 2), (-2, 2), (-2, 2)]), note)
}

/// RoboTool's default `core_clock_type` is `{0..10}`; a `csp` block may
/// set it.
pub(crate) const CLOCK_MAX: i64 = 10;

/// instantiations.csp: the generated defaults, which the scripts of
/// assertion files that set nothing include (RT-7).
pub(crate) fn instantiations(ex: &Exporter<'_>) -> OutFile {
    OutFile {
        name: "instantiations.csp".into(),
        title: "Instantiations: bounded types and constant values".into(),
        decls: instantiation_decls(ex, &ex.number_types, CLOCK_MAX, &BTreeMap::new(), &Functions::default()),
    }
}

/// What one script's `csp` blocks do to the defaults of the functions
/// without a body (RT-2, RT-7).
#[derive(Debug, Default)]
pub(crate) struct Functions {
    /// The functions a block defines (the default is left out).
    pub defined: BTreeSet<String>,
    /// Whether a block named `Instantiations` replaces the generated
    /// defaults: then the functions no block defines have no definition.
    pub replaced: bool,
}

/// The bounded types (`numbers`, `clock_max`), constant values (the
/// defaults, with `overrides`) and the defaults of functions without a
/// body (but those `functions` says a block defines, or replaces) of one
/// script.
pub(crate) fn instantiation_decls(
    ex: &Exporter<'_>,
    numbers: &([(i64, i64); 3], String),
    clock_max: i64,
    overrides: &BTreeMap<String, (Expr, String)>,
    functions: &Functions,
) -> Vec<Decl> {
    let (doms, note) = numbers;
    let mut d = vec![Decl::Comment(note.clone())];
    for (t, (lo, hi)) in ["nat", "int", "real"].iter().zip(doms) {
        d.push(Decl::Nametype(format!("core_{t}"), Expr::Range(Box::new(Expr::Int(*lo)), Box::new(Expr::Int(*hi)))));
    }
    d.push(Decl::Nametype("core_boolean".into(), n("Bool")));
    d.push(Decl::Comment(
        "Clocks stop one above the greatest value they are compared with, and at most at core_clock_max + 1.".into(),
    ));
    d.push(Decl::Def("core_clock_max".into(), vec![], Expr::Int(clock_max)));
    d.push(Decl::Nametype(
        "core_clock_type".into(),
        Expr::Range(Box::new(Expr::Int(0)), Box::new(bin(BinOp::Add, n("core_clock_max"), Expr::Int(1)))),
    ));
    if ex.uses_seq {
        d.push(Decl::Comment(
            "Sequences (`Seq(T)`) have at most this many elements: 2, or the longest literal of the models.".into(),
        ));
        d.push(Decl::Def("core_seq_max".into(), vec![], Expr::Int(ex.seq_literal_max.max(2))));
    }
    if ex.uses_string {
        d.push(Decl::Nametype("core_string".into(), call("LSeq", vec![n("Char"), Expr::Int(2)])));
    }
    let mut abstracts: Vec<&String> = ex.abstract_types.values().collect();
    abstracts.sort();
    if !abstracts.is_empty() {
        d.push(Decl::Blank);
        d.push(Decl::Comment("Primitive types declared in the models (`type T`): two values unless set here.".into()));
        for a in abstracts {
            d.push(Decl::Nametype(a.clone(), Expr::Range(Box::new(Expr::Int(0)), Box::new(Expr::Int(1)))));
        }
    }
    if !ex.constants.is_empty() {
        d.push(Decl::Blank);
        d.push(Decl::Comment(
            "Constants: the model's value, or a default; assertions pass other values to the processes\n\
             (`with constant k of M set to v`)."
                .into(),
        ));
        for (c, v, comment) in &ex.constants {
            let (v, comment) = overrides.get(c).map_or((v, comment), |(v, w)| (v, w));
            if !comment.is_empty() {
                d.push(Decl::Comment(comment.clone()));
            }
            d.push(Decl::Def(c.clone(), vec![], v.clone()));
        }
    }
    if !ex.fn_defaults.is_empty() {
        d.push(Decl::Blank);
        d.push(Decl::Comment(
            "Functions without a body return their result type's default (RT-2), unless a `csp` block of the\n\
             assertion file defines them (RT-7)."
                .into(),
        ));
        for f in &ex.fn_defaults {
            if functions.defined.contains(&f.csp) {
                d.push(Decl::Comment(format!("{}: defined by a `csp` block of this assertion file", f.comment)));
            } else if functions.replaced {
                // Written so that the rest of the script loads; the
                // assertions about elements that call it are not exported.
                d.push(Decl::Comment(format!(
                    "{}: NOT IN ROBOTOOL'S SCRIPT: this assertion file's `csp Instantiations` block replaces the\n\
                     generated defaults (RT-7) and does not define `{}`, so FDR stops on it there; written here so that\n\
                     the rest loads, the assertions about elements that call it are not exported",
                    f.comment, f.csp
                )));
                d.push(Decl::Def(f.csp.clone(), f.params.clone(), f.value.clone()));
            } else {
                d.push(Decl::Comment(f.comment.clone()));
                d.push(Decl::Def(f.csp.clone(), f.params.clone(), f.value.clone()));
            }
        }
    }
    d
}
