//! An assertion file (`.rsa`, `.assertions`) as FDR assertions: its `csp`
//! blocks (copied), its simulations (see `sim`) and one `assert` per
//! assertion, with the constants and periods of its `with …` clause passed
//! to the processes.

use std::collections::HashMap;

use robosim_hir::assertions::{
    AssertionDecl, AssertionFile, AssertionKind, CspLineKind, Override, SemanticModelName, Value,
};
use robosim_hir::index::{resolve_item, ItemLoc};
use robosim_hir::model as m;
use robosim_hir::model::DefKind;
use robosim_hir::target::{self, Scope};
use robosim_hir::{File, TextRange};

use crate::compose::ElemDef;
use crate::cspm::{call, hide, name, Assert, AssertKind, Decl, Expr, Model};
use crate::export::{ConstParam, Elem, Exporter, Ty};

/// A subject of an assertion: a process to call, with its parameters.
#[derive(Clone)]
struct Subject {
    /// The CSPm module (or the raw process name of a `csp` block).
    module: String,
    /// The element (none for `csp` blocks).
    elem: Option<std::rc::Rc<Elem>>,
    /// Whether it is a simulation (`S::D__`, `S::TLF`).
    simulation: bool,
    /// Default period (RoboSim elements and simulations).
    period: Option<i64>,
    /// The model names it can be called by in `cycleDef of X`.
    names: Vec<Vec<String>>,
    /// RT-11: an operation checked on its own (its process takes its
    /// parameters after `id__`).
    op: Option<OpSubject>,
    /// The model element (with the machine or operation declared inside
    /// the controller `loc`): where reachability resolves a state.
    at: Option<(ItemLoc, Option<String>)>,
}

/// An operation as a subject: its parameters' values and its constants.
#[derive(Clone)]
struct OpSubject {
    /// Its parameters' values.
    params: Vec<Expr>,
    consts: Vec<ConstParam>,
    /// Its states' paths and tags.
    states: Vec<(Vec<String>, String)>,
    /// The functions without a body it calls.
    functions: std::collections::BTreeSet<String>,
}

pub(crate) fn assertion_file(ex: &mut Exporter<'_>, file: File, read: &AssertionFile) -> Vec<Decl> {
    let mut out = Vec::new();
    // `csp` blocks, copied; what the export already defines is commented
    // out (constant values are applied to this file's instantiations).
    let text = file.text(ex.db).clone();
    let mut raw_names = Vec::new();
    let ours = generated_names(ex);
    for b in &read.csp_blocks {
        // RT-8: `timed csp` blocks exist only in the timed script.
        if b.timed && !ex.timed {
            continue;
        }
        let Some(tr) = b.text_range else { continue };
        let body = &text[usize::from(tr.start())..usize::from(tr.end())];
        let mut lines = Vec::new();
        let mut offset = usize::from(tr.start());
        for l in body.split_inclusive('\n') {
            let lr = TextRange::new((offset as u32).into(), ((offset + l.len()) as u32).into());
            offset += l.len();
            let kind = b.lines.iter().find(|x| lr.contains_range(x.range)).map(|x| x.kind);
            let l = l.trim_end_matches(['\n', '\r']);
            let defined = crate::lint::raw_defined(l);
            let clash: Vec<&String> =
                defined.iter().filter(|n| ours.contains(n.as_str()) || ex.const_names.contains(*n)).collect();
            // RoboTool copies a block whole (RT-7): a type or standard
            // definition stays unless the export defines that name itself
            // (`nametype core_nat`, whose bounds instantiations.csp takes
            // from the block; `Plus`): old-style names (`nametype ID`,
            // `nametype nat`) define exactly those names, which specs use.
            // RT-7: a block's definition of a function without a body
            // (by RoboTool's name) replaces its generated default (RT-2) in
            // this file's script.
            let bodiless = defined.iter().find(|n| ex.fn_defaults.iter().any(|f| f.csp == **n)).cloned();
            // A package's function is `pkg_f` in RoboTool's CSPm: a block's
            // `f(x) = …` defines another name, which the calls do not use.
            let misnamed = defined
                .iter()
                .find_map(|n| ex.fn_defaults.iter().find(|f| f.name == *n && f.csp != *n && !ours.contains(n.as_str())))
                .map(|f| (f.name.clone(), f.csp.clone()));
            // (Any definition of the name: also one beyond the subset hir
            // reads, `f(x) = let … within …`, as RoboTool copies it.)
            // RoboTool's script includes its library whatever the blocks
            // define: a block defining one of its names again makes FDR stop
            // on the script ("multiple definitions"). Copied as it is, so FDR
            // says so on the export's script too: leaving it out would check
            // another specification than the one written.
            let library = defined.iter().find(|n| robosim_hir::csp_defs::defines(n, ex.timed)).cloned();
            if let Some(n) = bodiless {
                ex.fn_overrides.insert(n);
                lines.push(l.to_string());
            } else if let Some(n) = library {
                ex.warn(
                    file,
                    lr,
                    format!(
                        "`{n}` is defined by RoboTool's library, which RoboTool's script includes whatever the `csp` \
                         blocks define: FDR stops on the script of this file (\"multiple definitions\") and checks \
                         none of its assertions; give the block's definition a name of its own"
                    ),
                );
                lines.push(l.to_string());
            } else if let (Some((n, csp)), Some(CspLineKind::Function)) = (misnamed, kind) {
                ex.warn(
                    file,
                    lr,
                    format!(
                        "this defines `{n}`, but RoboTool's CSPm calls the model's function `{csp}` (its package's \
                         name first, RT-2), so the calls do not use it: write `{csp}(…) = …` to define it"
                    ),
                );
                lines.push(l.to_string());
            } else if matches!(kind, Some(CspLineKind::Type) | Some(CspLineKind::Standard)) && !clash.is_empty() {
                lines.push(format!("-- (in this script's instantiations or robosim_defs.csp) {}", l.trim()));
            } else if let Some(n) = clash.first() {
                let n = n.to_string();
                let value = read.instantiations.constants.iter().find(|(c, _, r)| *c == n && lr.contains_range(*r));
                match value.map(|(_, v, _)| v) {
                    Some(Value::Int(v)) if ex.const_names.contains(&n) => {
                        ex.set_constant(&n, Expr::Int(*v), format!("set by `csp {}` in {}", b.name, ex.loc(file, lr)));
                        lines.push(format!("-- (set in this script's instantiations) {}", l.trim()));
                    }
                    Some(Value::Bool(v)) if ex.const_names.contains(&n) => {
                        ex.set_constant(&n, Expr::Bool(*v), format!("set by `csp {}` in {}", b.name, ex.loc(file, lr)));
                        lines.push(format!("-- (set in this script's instantiations) {}", l.trim()));
                    }
                    _ => {
                        ex.warn(
                            file,
                            lr,
                            format!("this definition of `{n}` in `csp {}` is not used: the export defines `{n}` (edit instantiations.csp)", b.name),
                        );
                        lines.push(format!("-- NOT USED (the export defines `{n}`): {}", l.trim()));
                    }
                }
            } else {
                lines.push(l.to_string());
            }
        }
        let joined = lines.join("\n");
        raw_names.push(b.name.clone());
        out.push(Decl::Comment(format!(
            "{}csp {} (copied from {}; it may use names of RoboTool's generated CSP)",
            if b.timed { "timed " } else { "" },
            b.name,
            ex.loc(file, b.range)
        )));
        out.push(Decl::Raw(joined.trim_matches('\n').to_string(), b.name.clone()));
        out.push(Decl::Blank);
    }
    // RT-7: an `Instantiations` block (one of this script's, RT-8)
    // replaces the generated defaults: the functions without a body it does
    // not define have no definition in RoboTool's script.
    ex.fn_undefined.clear();
    if read.csp_blocks.iter().any(|b| b.name == "Instantiations" && (ex.timed || !b.timed)) {
        let defined = &ex.fn_overrides;
        ex.fn_undefined = ex.fn_defaults.iter().map(|d| d.csp.clone()).filter(|c| !defined.contains(c)).collect();
    }
    // Simulations.
    let mut sims: HashMap<String, Subject> = HashMap::new();
    // Simulations run in cycles: the untimed script has none.
    let timed = ex.timed;
    for s in read.simulations.iter().filter(|_| timed) {
        if s.name.is_empty() || s.of.is_empty() {
            continue;
        }
        let accept: fn(DefKind) -> bool =
            |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
        let Some(loc) = resolve_item(ex.db, ex.ws, file, &s.of, accept).into_iter().next() else {
            let msg = format!("simulation {}: `{}` could not be resolved", s.name, s.of.join("::"));
            ex.warn(file, s.of_range, msg.clone());
            out.push(Decl::Comment(format!("NOT EXPORTED: {msg}")));
            continue;
        };
        let Some(elem) = crate::compose::element_at(ex, loc) else {
            let msg = format!("simulation {}: `{}` is not exported", s.name, s.of.join("::"));
            ex.warn(file, s.of_range, msg.clone());
            out.push(Decl::Comment(format!("NOT EXPORTED: {msg}")));
            continue;
        };
        let module = ex.module_name(std::slice::from_ref(&s.name));
        match crate::sim::simulation(ex, &module, &s.name, &elem) {
            Ok(d) => {
                out.extend(d);
                let period = s.cycle.as_ref().and_then(Value::as_int);
                sims.insert(
                    s.name.clone(),
                    Subject {
                        module,
                        elem: Some(elem),
                        simulation: true,
                        period: Some(period.unwrap_or(1)),
                        names: vec![vec![s.name.clone()]],
                        op: None,
                        at: None,
                    },
                );
            }
            Err(m) => {
                let msg = format!("simulation {}: {m}", s.name);
                ex.warn(file, s.range, msg.clone());
                out.push(Decl::Comment(format!("NOT EXPORTED: {msg}")));
            }
        }
    }
    // Assertions.
    for a in &read.assertions {
        out.push(Decl::Comment(a.text.clone()));
        let timing = target::timing(a);
        // RT-8: each script holds the assertions checked in its semantics;
        // a plain one is in both, unless it has no untimed reading.
        let here = if ex.timed {
            if timing.timed {
                Ok(())
            } else {
                Err("an untimed assertion: in the untimed script".to_string())
            }
        } else if !timing.untimed {
            Err("a timed assertion: in the timed script".to_string())
        } else {
            match untimed_reading(ex, file, read, a) {
                Ok(()) => Ok(()),
                Err(m) if timing.timed => Err(format!("checked in the timed semantics only: {m}")),
                Err(m) => {
                    ex.warn(file, a.range, format!("assertion {} is not exported: {m}", a.name));
                    Err(format!("NOT EXPORTED: {m}"))
                }
            }
        };
        // Refused alike in both scripts: the timed one warns.
        let both = matches!(
            a.kind,
            AssertionKind::ClockInitialised { .. } | AssertionKind::Probabilistic { .. } | AssertionKind::Other(_)
        );
        let here = match here {
            Ok(()) if !ex.timed && timing.timed && both => Err("NOT EXPORTED, as in the timed script".to_string()),
            h => h,
        };
        if let Err(m) = here {
            out.push(Decl::Comment(m));
            out.push(Decl::Blank);
            continue;
        }
        let semantics = if ex.timed { "" } else { " in the untimed semantics" };
        match assertion(ex, file, read, a, &sims, &raw_names) {
            Ok(asserts) => out.extend(asserts.into_iter().map(Decl::Assert)),
            Err(m) => {
                ex.warn(file, a.range, format!("assertion {} is not exported{semantics}: {m}", a.name));
                out.push(Decl::Comment(format!("NOT EXPORTED: {m}")));
            }
        }
        out.push(Decl::Blank);
    }
    out
}

/// The subject named `path` in assertion `a` of `file`: a simulation of
/// the file or a `csp` block by name, else the element hir's one reading
/// of assertions resolves (`robosim_hir::target`, as the native checker).
fn subject(
    ex: &mut Exporter<'_>,
    file: File,
    read: &AssertionFile,
    a: &AssertionDecl,
    path: &[String],
    sims: &HashMap<String, Subject>,
    raw: &[String],
) -> Result<Subject, String> {
    let s = subject_of(ex, file, read, a, path, sims, raw)?;
    // RT-7: this file's `Instantiations` block replaces the generated
    // defaults and leaves a function the subject calls undefined: FDR
    // stops on RoboTool's script, so no verdict (as the native checker).
    let mut calls = std::collections::BTreeSet::new();
    if let Some(e) = &s.elem {
        element_functions(e, &mut calls);
    }
    if let Some(op) = &s.op {
        calls.extend(op.functions.iter().cloned());
    }
    if let Some(f) = calls.iter().find(|f| ex.fn_undefined.contains(*f)) {
        return Err(format!(
            "`{}` calls `{f}`, a function without a body that this file's `csp Instantiations` block does not \
             define: the block replaces RoboTool's generated defaults (RT-7), so FDR stops on the undefined name; \
             define it there (`{f}(…) = …`)",
            path.join("::")
        ));
    }
    Ok(s)
}

/// The functions without a body `e` and its parts call.
fn element_functions(e: &Elem, out: &mut std::collections::BTreeSet<String>) {
    out.extend(e.functions.iter().cloned());
    for (_, p) in &e.parts {
        element_functions(p, out);
    }
}

#[allow(clippy::too_many_arguments)]
fn subject_of(
    ex: &mut Exporter<'_>,
    file: File,
    read: &AssertionFile,
    a: &AssertionDecl,
    path: &[String],
    sims: &HashMap<String, Subject>,
    raw: &[String],
) -> Result<Subject, String> {
    if path.len() == 1 {
        if let Some(s) = sims.get(&path[0]) {
            return Ok(s.clone());
        }
        if raw.contains(&path[0]) {
            return Ok(Subject {
                module: path[0].clone(),
                elem: None,
                simulation: false,
                period: None,
                names: vec![],
                op: None,
                at: None,
            });
        }
    }
    // The export writes one script per assertion file: simulations of the
    // other files are not in it.
    let scope = Scope { db: ex.db, ws: ex.ws, file, read, others: &[] };
    let (loc, inner, period) = match robosim_hir::target::subject(scope, a, path)? {
        target::Subject::Constrained { name, .. } => {
            return Err(format!("simulation `{name}` is not exported"));
        }
        target::Subject::Simulation { loc, inner, period, .. } => (loc, inner, period),
        target::Subject::Design { loc, inner, .. } => (loc, inner, None),
        target::Subject::SimOperation { name, loc, inner } => {
            return operation_subject(ex, scope, a, loc, inner.as_deref(), path)?
                .ok_or_else(|| format!("`{name}` could not be resolved"));
        }
    };
    if let Some(s) = operation_subject(ex, scope, a, loc, inner.as_deref(), path)? {
        return Ok(s);
    }
    let Some(def) = ElemDef::at(ex.db, ex.ws, loc) else {
        return Err(format!("`{}` could not be resolved", path.join("::")));
    };
    let qualified = ex.path_of_item(loc);
    let elem = match (inner.as_deref(), def) {
        (None, def) => crate::compose::element(ex, loc.file, def, qualified),
        // A machine declared inside the controller, as the controller has it.
        (Some(inner), ElemDef::Controller(c)) => {
            if !c.machines.iter().any(|i| matches!(&i.def, m::Definition::Inline(b) if b.name == inner)) {
                return Err(format!("`{}` could not be resolved", path.join("::")));
            }
            crate::compose::inner_machine(ex, loc.file, c, inner, &qualified)
        }
        (Some(_), _) => return Err(format!("`{}` could not be resolved", path.join("::"))),
    };
    let Some(elem) = elem else {
        return Err(format!("`{}` is not exported", path.join("::")));
    };
    let period = elem.robosim.then(|| period.unwrap_or(elem.period));
    Ok(Subject {
        module: elem.module.clone(),
        elem: Some(elem.clone()),
        simulation: false,
        period,
        names: vec![path.to_vec(), elem.path.clone()],
        op: None,
        at: Some((loc, inner)),
    })
}

/// RT-11: the operation `loc` names (a top-level one, or the one an
/// operation reference references), or with `inner` the operation of that
/// name the controller `loc` declares, as its own process (RoboChart:
/// `pkg::OP_op::D__`, `C::OP_op::D__`; RoboSim: RoboTool's `OP_…::D__`, see
/// `machine::sim_operation`): `None` when `loc` is no operation.
fn operation_subject(
    ex: &mut Exporter<'_>,
    scope: Scope<'_>,
    a: &AssertionDecl,
    loc: robosim_hir::index::ItemLoc,
    inner: Option<&str>,
    path: &[String],
) -> Result<Option<Subject>, String> {
    let (b, outer) = match (m::item(ex.db, ex.ws, loc), inner) {
        (Some(m::Item::Operation(b)), None) => (b, ex.package(loc.file)),
        (Some(m::Item::Controller(c)), Some(inner)) => {
            let op = c.operations.iter().find_map(|o| match &o.def {
                m::Definition::Inline(b) if o.name == inner => Some(&**b),
                _ => None,
            });
            match op {
                Some(b) => (b, ex.path_of_item(loc)),
                None => return Ok(None),
            }
        }
        _ => return Ok(None),
    };
    let written = path.join("::");
    if !b.region.nodes.iter().any(|n| n.kind == m::NodeKind::Initial) {
        return Err(format!("`{written}` is an operation without a body (initial junction): it has no process"));
    }
    let op = if loc.file.kind(ex.db) == robosim_hir::FileKind::RoboSim {
        crate::machine::sim_operation(ex, loc.file, b, outer)?
    } else {
        crate::machine::operation(ex, loc.file, b, outer)?
    };
    // `with parameter x of P`, bound by the operation's declared name, as
    // the native checker reads it; a parameter without one is RoboTool's
    // default (`param_x = 0`, `true` for a boolean).
    let bound = target::parameters_in(scope, a)?;
    let mut params = Vec::new();
    for (p, t) in b.params.iter().zip(&op.params) {
        let given = bound.iter().find(|x| x.name == p.name && x.of.len() == 1 && x.of[0] == b.name);
        let v = match (t, given) {
            (Ty::Nat | Ty::Int | Ty::Real, Some(x)) => Expr::Int(x.value),
            (Ty::Bool, Some(x)) => Expr::Bool(x.value != 0),
            (Ty::Nat | Ty::Int | Ty::Real | Ty::Bool, None) => t.default_value(),
            _ => {
                return Err(format!(
                    "the parameter `{}` of `{written}` is not a number or a boolean: not supported as a parameter of \
                     an operation checked on its own",
                    p.name
                ))
            }
        };
        params.push(v);
    }
    Ok(Some(Subject {
        module: op.module.clone(),
        elem: None,
        simulation: false,
        period: None,
        names: vec![path.to_vec()],
        at: Some((loc, inner.map(str::to_string))),
        op: Some(OpSubject {
            params,
            consts: op.consts.iter().map(|(c, _)| c.clone()).collect(),
            states: op.states.clone(),
            functions: op.functions.clone(),
        }),
    }))
}

fn value(v: &Value) -> Result<Expr, String> {
    match v {
        Value::Int(n) => Ok(Expr::Int(*n)),
        Value::Bool(b) => Ok(Expr::Bool(*b)),
        Value::Other(t) => Err(format!("the value `{t}` is not supported by the export (integers and booleans are)")),
    }
}

/// The call of `process` (`D__`, `TLF`, `VS__`) of a subject with the
/// assertion's overrides.
fn process(
    ex: &mut Exporter<'_>,
    file: File,
    read: &AssertionFile,
    a: &AssertionDecl,
    s: &Subject,
    process: &str,
) -> Result<Expr, String> {
    let (consts, robosim) = match (&s.elem, &s.op) {
        (Some(e), _) => (&e.consts, e.robosim),
        (None, Some(op)) => (&op.consts, false),
        (None, None) => return Ok(name(s.module.clone())),
    };
    let mut args = vec![Expr::Int(0)];
    if let Some(op) = &s.op {
        args.extend(op.params.iter().cloned());
    }
    if s.simulation || robosim {
        let mut period = s.period.unwrap_or(1);
        for o in &a.overrides {
            if let Override::CycleDef { of, value: v, .. } = o {
                let named = s.names.iter().any(|n| n == of || n.ends_with(of));
                if named {
                    period = v.as_int().ok_or_else(|| "the period must be an integer".to_string())?;
                }
            }
        }
        args.push(Expr::Int(period));
    }
    if !(s.simulation || robosim) {
        // RoboChart: hir's one reading of `with constant z of X` (RT-11: X
        // the machine, the controller that requires z, or the module whose
        // platform provides it), one binding per machine by its
        // declaration's name, as the native checker matches them.
        let scope = Scope { db: ex.db, ws: ex.ws, file, read, others: &[] };
        let bound = target::bindings_in(scope, a)?;
        for c in consts {
            let b = bound.iter().find(|b| b.name == c.name && b.of.last() == c.owner.last());
            let arg = match b {
                None => name(c.global.clone()),
                Some(b) => {
                    // The value as written: a boolean, an integer; an
                    // enumeration literal is refused below.
                    let written: Vec<&Value> = a
                        .overrides
                        .iter()
                        .filter_map(|o| match o {
                            Override::Constant { name: n, value: v, .. } if *n == b.name => Some(v),
                            _ => None,
                        })
                        .collect();
                    // An enumeration literal (or other value) is refused.
                    for v in &written {
                        value(v)?;
                    }
                    if written.iter().all(|v| matches!(v, Value::Bool(_))) {
                        Expr::Bool(b.value != 0)
                    } else if written.iter().all(|v| matches!(v, Value::Int(_))) {
                        Expr::Int(b.value)
                    } else {
                        return Err(format!("the constants named `{}` are given both booleans and integers", b.name));
                    }
                }
            };
            args.push(arg);
        }
        return Ok(call(format!("{}::{process}", s.module), args));
    }
    // RoboSim and simulations: the override whose element is the
    // constant's machine.
    let mut owners: HashMap<Vec<String>, Vec<String>> = HashMap::new();
    for o in &a.overrides {
        if let Override::Constant { of, .. } = o {
            if owners.contains_key(of) {
                continue;
            }
            let accept: fn(DefKind) -> bool =
                |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine | DefKind::Interface);
            if let Some(loc) = resolve_item(ex.db, ex.ws, file, of, accept).into_iter().next() {
                owners.insert(of.clone(), ex.path_of_item(loc));
            }
        }
    }
    for c in consts {
        let mut arg = name(c.global.clone());
        for o in &a.overrides {
            if let Override::Constant { name: n, of, value: v, .. } = o {
                let owner = owners.get(of).cloned().unwrap_or_else(|| of.clone());
                if *n == c.name && (owner == c.owner || c.owner.ends_with(of)) {
                    arg = value(v)?;
                }
            }
        }
        args.push(arg);
    }
    Ok(call(format!("{}::{process}", s.module), args))
}

fn model(m: SemanticModelName) -> Result<Model, String> {
    match m {
        SemanticModelName::Traces => Ok(Model::Traces),
        SemanticModelName::Failures => Ok(Model::Failures),
        SemanticModelName::FailuresDivergences | SemanticModelName::Default => Ok(Model::FailuresDivergences),
        SemanticModelName::TickTock => {
            Err("the tick-tock model needs RoboTool's tick-tock.csp encoding, which the export does not generate yet"
                .into())
        }
    }
}

fn tau_priority() -> Option<Expr> {
    Some(Expr::Set(vec![name("tock")]))
}

fn assertion(
    ex: &mut Exporter<'_>,
    file: File,
    read: &AssertionFile,
    a: &AssertionDecl,
    sims: &HashMap<String, Subject>,
    raw: &[String],
) -> Result<Vec<Assert>, String> {
    if let Some(p) = a.problems.first() {
        return Err(p.message.clone());
    }
    let one = |kind| Ok(vec![Assert { negated: a.negated, kind, tau_priority: None }]);
    match &a.kind {
        AssertionKind::Schedulable => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            if !s.simulation {
                return Err(format!("`{}` is not a simulation: only simulations are (not) schedulable", a.subject.join("::")));
            }
            let p = process(ex, file, read, a, &s, "TLF")?;
            Ok(vec![Assert { negated: a.negated, kind: AssertKind::DeadlockFree(p, Model::Failures), tau_priority: tau_priority() }])
        }
        AssertionKind::DeadlockFree if !ex.timed => {
            // RT-9: FDR's plain deadlock freedom, failures-divergences model.
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            one(AssertKind::DeadlockFree(p, Model::FailuresDivergences))
        }
        AssertionKind::DeadlockFree => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            // Timed deadlock (semantics.md §7.4): a state from which only
            // time passes, forever.
            let renamed = Expr::Rename(
                Box::new(p),
                vec![(name("tock"), name("tock")), (name("tock"), name("tock'"))],
                vec![],
            );
            let prio = call(
                "prioritise",
                vec![
                    renamed,
                    Expr::SeqLit(vec![
                        call("diff", vec![name("Events"), Expr::Set(vec![name("tock"), name("tock'")])]),
                        Expr::Set(vec![name("tock")]),
                    ]),
                ],
            );
            one(AssertKind::DivergenceFree(hide(prio, Expr::Set(vec![name("tock")])), Model::FailuresDivergences))
        }
        AssertionKind::DivergenceFree => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            one(AssertKind::DivergenceFree(p, Model::FailuresDivergences))
        }
        AssertionKind::Deterministic => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            one(AssertKind::Deterministic(p, Model::FailuresDivergences))
        }
        AssertionKind::TimelockFree => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            // RT-10, as the native checker reads it: after any trace, with
            // every other event refusable (urgent ones included), `tock` is
            // never refused; termination counts as a timelock.
            let others = call("diff", vec![name("Events"), Expr::Set(vec![name("tock")])]);
            one(AssertKind::Refines(Model::Failures, call("TimelockFree__", vec![others]), p))
        }
        AssertionKind::Terminates => {
            let s = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let p = process(ex, file, read, a, &s, "D__")?;
            // RT-10, as the native checker reads it: ✓ is reachable (P
            // has a trace outside CHAOS(Events), whose traces never end in
            // ✓), and P deadlocks only after ✓ (followed by endless
            // `terminated__`, it never deadlocks).
            if a.negated {
                return Err("`does not terminate` is a disjunction of two checks, which FDR cannot assert at once".into());
            }
            let after = call("RUN", vec![Expr::Set(vec![name("terminated__")])]);
            Ok(vec![
                Assert {
                    negated: true,
                    kind: AssertKind::Refines(Model::Traces, call("CHAOS", vec![name("Events")]), p.clone()),
                    tau_priority: None,
                },
                Assert {
                    negated: false,
                    kind: AssertKind::DeadlockFree(crate::cspm::seq(vec![p, after]), Model::Failures),
                    tau_priority: None,
                },
            ])
        }
        AssertionKind::Refines { other, model: m, .. } | AssertionKind::Equals { other, model: m, .. } => {
            let m = model(*m)?;
            let x = subject(ex, file, read, a, &a.subject, sims, raw)?;
            let y = subject(ex, file, read, a, other, sims, raw)?;
            // An operation's events are channels of its own module
            // (`C::OP_op::e`): FDR never identifies them with another
            // process's, which the native checker compares by name.
            if (x.op.is_some() || y.op.is_some()) && x.module != y.module {
                return Err(format!(
                    "comparing the operation's process with another process is not exported: their events are \
                     channels of different CSPm modules (`{}`, `{}`), which FDR would never match, while \
                     `robosim verify` matches them by name",
                    x.module, y.module
                ));
            }
            let mut px = process(ex, file, read, a, &x, "D__")?;
            let mut py = process(ex, file, read, a, &y, "D__")?;
            // RT-10: registers are matched by name. A RoboSim element's events
            // are its module's own (`M::registerWrite.M::o_x`, RoboTool's
            // names, which `csp` blocks use): compared with another element
            // or a simulation, it is read on the global names.
            if x.module != y.module {
                for (s, o, p) in [(&x, &y, &mut px), (&y, &x, &mut py)] {
                    let model = |s: &Subject| s.elem.is_some() || s.simulation || s.op.is_some();
                    if let Some(e) = s.elem.as_ref().filter(|e| e.robosim && !s.simulation && model(o)) {
                        *p = crate::sim_names::globalise(ex, e, p.clone());
                    }
                }
            }
            // RT-21: a cycle-constrained design has no `endexec`: a RoboSim
            // machine or controller compared with one is read at a
            // module's alphabet, its `endexec` and `terminate` hidden (as
            // the native checker does, and says).
            if x.simulation != y.simulation {
                for (s, p) in [(&x, &mut px), (&y, &mut py)] {
                    if shows_end(ex, s) {
                        let end = Expr::Set(vec![name("endexec"), name("terminate")]);
                        *p = call("TimedPriority", vec![hide(p.clone(), end)]);
                    }
                }
            }
            let timed = [&x, &y].iter().any(|s| s.simulation || s.elem.as_ref().is_some_and(|e| e.robosim));
            let tp = if timed { tau_priority() } else { None };
            let mut v = vec![Assert { negated: a.negated, kind: AssertKind::Refines(m, py.clone(), px.clone()), tau_priority: tp.clone() }];
            if matches!(a.kind, AssertionKind::Equals { .. }) {
                if a.negated {
                    return Err("`is not equal to` is a disjunction of two refinements, which FDR cannot assert at once".into());
                }
                v.push(Assert { negated: false, kind: AssertKind::Refines(m, px, py), tau_priority: tp });
            }
            Ok(v)
        }
        AssertionKind::Reachable { state, machine, .. } => {
            let s = subject(ex, file, read, a, machine, sims, raw)?;
            let Some((loc, inner)) = &s.at else {
                return Err("reachability needs a state machine, controller or module".into());
            };
            // hir's one reading of the state's path, as the native checker's.
            let st = target::state(ex.db, ex.ws, *loc, inner.as_deref(), state)?;
            // RoboTool's states and final states have `entered`; junctions
            // have none.
            if !matches!(st.kind, m::NodeKind::State | m::NodeKind::Final) {
                return Err(format!(
                    "`{}` is a junction, not a state: RoboTool's semantics marks the entries of states and final \
                     states only (`entered`)",
                    state.join("::")
                ));
            }
            // The state's machine (or operation): a controller's machine
            // `Ctl::a` is its part `a`; a module's `c::a` its part `c`'s `a`.
            let (module, states) = match (&s.elem, &s.op) {
                (Some(elem), _) => {
                    let skip = usize::from(elem.kind == crate::export::ElemKind::Controller);
                    let mut at = elem.clone();
                    if elem.kind != crate::export::ElemKind::Machine {
                        for part in &st.machine[skip..] {
                            let next = at.parts.iter().find(|(n, _)| n == part).map(|(_, e)| e.clone());
                            at = next
                                .ok_or_else(|| format!("the machine `{}` is not exported", st.machine.join("::")))?;
                        }
                    }
                    (at.module.clone(), at.states.clone())
                }
                (None, Some(op)) => (s.module.clone(), op.states.clone()),
                (None, None) => return Err("reachability needs a state machine, controller or module".into()),
            };
            // The machine's own tag for the state (tags are made unique).
            let tag = states.iter().find(|(p, _)| *p == st.state).map(|(_, t)| t.clone()).ok_or_else(|| {
                format!("the state `{}` is not exported in `{}`", st.state.join("::"), st.machine.join("::"))
            })?;
            let p = process(ex, file, read, a, &s, "VS__")?;
            let ev = crate::cspm::dot(vec![
                name(format!("{module}::entered__")),
                name(format!("{module}::SID_{tag}")),
            ]);
            let only = hide(p, call("diff", vec![name("Events"), Expr::Set(vec![ev])]));
            // Reachable iff the entry can happen: STOP does not trace-refine it.
            Ok(vec![Assert { negated: !a.negated, kind: AssertKind::Refines(Model::Traces, Expr::Stop, only), tau_priority: None }])
        }
        AssertionKind::ClockInitialised { .. } => {
            Err("clock initialisation checks need RoboTool's instrumented semantics, which the export does not generate yet".into())
        }
        AssertionKind::Probabilistic { .. } => {
            Err("probabilistic properties are checked with PRISM, not with FDR: not exported".into())
        }
        AssertionKind::Other(t) => Err(format!("the assertion `{t}` could not be read")),
    }
}

/// Whether the subject's `D__` shows `endexec` and `terminate` (RT-21): a
/// RoboSim machine or controller in RoboTool 3's profile.
fn shows_end(ex: &Exporter<'_>, s: &Subject) -> bool {
    let kind = s.elem.as_ref().filter(|e| e.robosim && !s.simulation).map(|e| e.kind);
    ex.profile == crate::Profile::RoboTool3
        && matches!(kind, Some(crate::export::ElemKind::Machine | crate::export::ElemKind::Controller))
}

/// Whether `a` means something in RoboChart's untimed semantics (RT-8,
/// RT-9), as the native checker decides it (`has_untimed_reading`): `Ok`
/// for properties of RoboChart elements and refinements between them in a
/// `.assertions` file, the reason otherwise (RoboSim and simulations are
/// timed only; schedulability is about cycles, timelock freedom and the
/// tick-tock model about time).
fn untimed_reading(ex: &Exporter<'_>, file: File, read: &AssertionFile, a: &AssertionDecl) -> Result<(), String> {
    if file.kind(ex.db) == robosim_hir::FileKind::SimAssertions {
        return Err("the assertions of a RoboSim assertion file (.rsa) are checked in the timed semantics only".into());
    }
    let subjects: Vec<&[String]> = match &a.kind {
        AssertionKind::DeadlockFree
        | AssertionKind::DivergenceFree
        | AssertionKind::Deterministic
        | AssertionKind::Terminates => vec![&a.subject],
        AssertionKind::Reachable { machine, .. } => vec![machine],
        AssertionKind::Refines { other, model, .. } | AssertionKind::Equals { other, model, .. } => {
            if *model == SemanticModelName::TickTock {
                return Err("the tick-tock model is about `tock`, which the untimed semantics does not have".into());
            }
            vec![&a.subject, other]
        }
        AssertionKind::Schedulable => {
            return Err("schedulability is a property of cycles: it is checked in the timed semantics only".into())
        }
        AssertionKind::TimelockFree => {
            return Err("timelock freedom is about time passing: the untimed semantics has no `tock`, so it is \
                        checked timed only"
                .into())
        }
        // Refused alike in both semantics, for reasons of their own.
        AssertionKind::ClockInitialised { .. } | AssertionKind::Probabilistic { .. } | AssertionKind::Other(_) => {
            return Ok(())
        }
    };
    for path in subjects {
        let name = path.join("::");
        if let [one] = path {
            if let Some(b) = read.csp_blocks.iter().find(|b| b.name == *one) {
                if b.timed {
                    return Err(format!(
                        "`{name}` is a `timed csp` block: it exists only in RoboTool's timed script (RT-8), so it is \
                         checked in the timed semantics only"
                    ));
                }
                continue;
            }
        }
        let scope = Scope { db: ex.db, ws: ex.ws, file, read, others: &[] };
        match target::subject(scope, a, path) {
            Ok(target::Subject::Simulation { .. } | target::Subject::SimOperation { .. }) => {
                return Err(format!(
                    "`{name}` is a RoboSim element: RoboSim has only a timed semantics (RoboTool generates no untimed \
                     script for it)"
                ))
            }
            Ok(target::Subject::Constrained { .. }) => {
                return Err(format!(
                    "`{name}` is a simulation of a RoboChart element, which runs in cycles: it is checked in the \
                     timed semantics only"
                ))
            }
            // Unresolved subjects are refused by the export itself.
            Ok(target::Subject::Design { .. }) | Err(_) => {}
        }
    }
    Ok(())
}

/// Names the export defines in the shared files and as modules.
fn generated_names(ex: &Exporter<'_>) -> std::collections::HashSet<String> {
    let mut s: std::collections::HashSet<String> = [
        "core_nat",
        "core_int",
        "core_real",
        "core_boolean",
        "core_clock_type",
        "core_clock_max",
        "InOut",
        "in",
        "out",
        "tock",
        "tock'",
        "terminate",
        "endexec",
        "timelock",
        "deadline_done__",
        "InputRegister",
        "OutputRegister",
        "registerRead",
        "registerWrite",
    ]
    .iter()
    .map(|x| x.to_string())
    .collect();
    s.extend(crate::defs::SHARED_PROCESSES.iter().map(|x| x.to_string()));
    s.extend(robosim_hir::csp_defs::DEFINITIONS.iter().flat_map(|d| d.names.iter().map(|x| x.to_string())));
    s.extend(ex.module_names.iter().cloned());
    s.extend(ex.in_regs.keys().cloned());
    s.extend(ex.out_regs.keys().cloned());
    // The types instantiations.csp and the model files declare.
    s.extend(ex.abstract_types.values().cloned());
    for (ty, literals) in ex.enums.values() {
        s.insert(ty.clone());
        s.extend(literals.iter().map(|(_, c)| c.clone()));
    }
    if ex.uses_string {
        s.insert("core_string".to_string());
    }
    if ex.uses_seq {
        s.insert("core_seq_max".to_string());
    }
    s
}
