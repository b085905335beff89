//! tock-CSP terms for hovers: on a state machine, controller or module
//! name, a transition, an `exec`, a RoboSim output or a platform call, the
//! CSP term the export generates for it and a one-line reading in English.

use robosim_hir::element;
use robosim_hir::model as m;
use robosim_hir::{Db, File, FileKind, TextRange, TextSize, Workspace};

use crate::compose::ElemDef;
use crate::cspm::{print_expr, Decl, Expr};
use crate::export::{Exporter, Profile};
use crate::machine::{Gen, Term, TermKind};

/// A term for a hover.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HoverTerm {
    /// What the term is about (the name, the `exec`, the statement).
    pub range: TextRange,
    /// The CSPm term.
    pub term: String,
    /// Its reading, in English (Markdown).
    pub reading: String,
}

const WIDTH: usize = 80;

/// The machines, controllers and modules of the top-level elements of
/// `file` around `offset` (one, or two when `offset` is where one ends and
/// the next starts), nested ones included, each with its qualified path.
/// Only those elements' models are read ([`m::element_model`]): after an
/// edit elsewhere they are valid still, and the file's model is not put
/// together.
fn elements<'a>(db: &'a dyn Db, ws: Workspace, file: File, offset: TextSize) -> Vec<(ElemDef<'a>, Vec<String>)> {
    fn controller<'a>(c: &'a m::Controller, path: Vec<String>, out: &mut Vec<(ElemDef<'a>, Vec<String>)>) {
        for i in &c.machines {
            if let m::Definition::Inline(b) = &i.def {
                let mut p = path.clone();
                p.push(b.name.clone());
                out.push((ElemDef::Machine(b), p));
            }
        }
        out.push((ElemDef::Controller(c), path));
    }
    let package = element::file_package(db, file).to_vec();
    let around = element::file_elements(db, file).iter().filter(|(e, at)| {
        let start = TextSize::from(*at);
        start <= offset && offset <= start + e.green(db).0.text_len()
    });
    let mut out = Vec::new();
    for (_, item) in around.flat_map(|(e, _)| m::element_model(db, ws, *e)) {
        let mut path = package.clone();
        match item {
            m::Item::Machine(b) => {
                path.push(b.name.clone());
                out.push((ElemDef::Machine(b), path));
            }
            m::Item::Controller(c) => {
                path.push(c.name.clone());
                controller(c, path, &mut out);
            }
            m::Item::Module(x) => {
                path.push(x.name.clone());
                for c in &x.controllers {
                    if let m::Definition::Inline(c) = &c.def {
                        let mut p = path.clone();
                        p.push(c.name.clone());
                        controller(c, p, &mut out);
                    }
                }
                out.push((ElemDef::Module(x), path));
            }
            _ => {}
        }
    }
    out
}

/// The term of the construct at `offset` of `file`, if it has one.
pub fn hover_term(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Option<HoverTerm> {
    if !matches!(file.kind(db), FileKind::RoboChart | FileKind::RoboSim) {
        return None;
    }
    let elements = elements(db, ws, file, offset);
    // On the name of a machine, controller or module: its process.
    if let Some((def, path)) = elements.iter().find(|(d, _)| d.name_range().contains_inclusive(offset)) {
        return element_term(db, ws, file, *def, path.clone());
    }
    // Inside a machine (the innermost: machines do not nest).
    let (machine, path) = elements.into_iter().find_map(|(d, p)| match d {
        ElemDef::Machine(b) if b.range.contains_inclusive(offset) => Some((b, p)),
        _ => None,
    })?;
    let mut ex = Exporter::new(db, ws, Profile::RoboTool3);
    let module = crate::util::element_module(&ex.package(file), &path);
    let out = Gen::new(&mut ex, file, Some(machine), path.clone(), machine.name_range, true)
        .run(module.clone(), path)
        .ok()?;
    // The most specific term around the offset: statements and `exec`
    // before transitions (whose range is their name).
    let best = out
        .terms
        .iter()
        .filter(|t| t.range.contains_inclusive(offset))
        .min_by_key(|t| (t.range.len(), t.kind == TermKind::Transition))?;
    let reading = reading(best, file.kind(db) == FileKind::RoboSim, &module);
    Some(HoverTerm { range: best.range, term: print_expr(&best.expr, WIDTH), reading })
}

fn element_term(db: &dyn Db, ws: Workspace, file: File, decl: ElemDef<'_>, path: Vec<String>) -> Option<HoverTerm> {
    let mut ex = Exporter::new(db, ws, Profile::RoboTool3);
    let robosim = file.kind(db) == FileKind::RoboSim;
    let elem = crate::compose::element(&mut ex, file, decl, path)?;
    let decls = ex.out.remove(&file).unwrap_or_default();
    // The definitions of the element's module.
    let module = decls.iter().find_map(|d| match d {
        Decl::Module(n, private, exports) if *n == elem.module => Some((private.clone(), exports.clone())),
        _ => None,
    })?;
    let find = |n: &str| {
        module.0.iter().chain(module.1.iter()).find_map(|d| match d {
            Decl::Def(x, params, body) if x == n => Some((params.clone(), body.clone())),
            _ => None,
        })
    };
    let (params, body) = find("D__")?;
    let mut term = format!("{}::D__({})", elem.module, params.join(", "));
    let shown = match (elem.kind, find("P__")) {
        // A machine: what its `let` composes.
        (crate::export::ElemKind::Machine, Some((_, Expr::Let(_, within)))) => {
            term.push_str(&format!(
                "\n  -- P__ with `entered__` hidden, where P__ = let … within\n{}",
                indent(&print_expr(&abbreviate(&within), WIDTH - 4))
            ));
            None
        }
        (_, Some((_, p))) if robosim => Some(p),
        _ => Some(body),
    };
    if let Some(b) = shown {
        term.push_str(" =\n");
        term.push_str(&indent(&print_expr(&abbreviate(&b), WIDTH - 4)));
    }
    let what = decl.name();
    let reading = match (elem.kind, robosim) {
        (crate::export::ElemKind::Machine, false) => format!(
            "The machine `{what}`: its states are processes (`Enter__S` runs the entry action, `Rest__S` offers the transitions while time passes) in parallel with its memory (`Memory__`: variables, clocks, and the guards, which enable each transition's trigger); internal events are hidden and happen before time passes (`TimedPriority`); once finished, it offers its `terminate` while time passes."
        ),
        (crate::export::ElemKind::Machine, true) => format!(
            "The machine `{what}` (paper Rules 3–7, 13): its behaviour, its memory (inputs, variables, clocks, guards) and its cycle: read every input register (`{m}::registerRead.{m}::i_x`), `startexec`, run until an `exec` ends the cycle (`{m}::endexec`, visible on its own: RT-21), each output register written at once and at most once (`{m}::registerWrite.{m}::o_x`), then `{m}::terminate` if it has finished, or `cycle` time units pass. The cycle and register events are the machine's own, as RoboTool names them.",
            m = elem.module
        ),
        (kind, false) => format!(
            "The {} `{what}`: its components in parallel, synchronising on `tock` and `terminate` (they end together), their events renamed through the connections; connections between components are hidden{}.",
            kind.describe(),
            if kind == crate::export::ElemKind::Module { ", and so is `terminate`: the module ends at once" } else { "" }
        ),
        (_, true) => format!(
            "The {} `{what}` (paper Rules 1, 9–11): its components in parallel, synchronising on `tock`, `terminate` and the end of each cycle (one `endexec`, after every machine's: a controller shows both, a module hides them, RT-21), their registers renamed through the connections. Its components' cycle and register events are renamed to its own (`{m}::endexec`, `{m}::terminate`, `{m}::registerRead.{m}::i_x`, `{m}::registerWrite.{m}::o_x`), following RoboTool's RoboChart pattern.",
            elem.kind.describe(),
            m = elem.module
        ),
    };
    Some(HoverTerm { range: decl.name_range(), term, reading })
}

fn indent(s: &str) -> String {
    s.lines().map(|l| format!("  {l}")).collect::<Vec<_>>().join("\n")
}

/// Long synchronisation sets shortened for display.
fn abbreviate(e: &Expr) -> Expr {
    match e {
        Expr::Events(items) if items.len() > 3 => {
            let mut v: Vec<Expr> = items.iter().take(2).cloned().collect();
            v.push(Expr::Name("…".into()));
            Expr::Events(v)
        }
        Expr::Call(f, args) => Expr::Call(f.clone(), args.iter().map(abbreviate).collect()),
        Expr::Par(a, b, c) => Expr::Par(Box::new(abbreviate(a)), Box::new(abbreviate(b)), Box::new(abbreviate(c))),
        Expr::Exception(a, b, c) => {
            Expr::Exception(Box::new(abbreviate(a)), Box::new(abbreviate(b)), Box::new(abbreviate(c)))
        }
        Expr::Hide(a, b) => Expr::Hide(Box::new(abbreviate(a)), Box::new(abbreviate(b))),
        Expr::Nary(op, v) => Expr::Nary(*op, v.iter().map(abbreviate).collect()),
        Expr::Rename(p, pairs, gens) => {
            if pairs.len() > 2 {
                let mut v: Vec<(Expr, Expr)> = pairs.iter().take(2).cloned().collect();
                v.push((Expr::Name("…".into()), Expr::Name("…".into())));
                Expr::Rename(Box::new(abbreviate(p)), v, gens.clone())
            } else {
                Expr::Rename(Box::new(abbreviate(p)), pairs.clone(), gens.clone())
            }
        }
        e => e.clone(),
    }
}

/// What the term `t` of a machine of the CSPm module `module` does;
/// RoboSim's cycle and registers by the names RoboTool gives them (the
/// machine's own, `M::endexec`, `M::registerWrite.M::o_x`), as `csp`
/// blocks write them.
fn reading(t: &Term, robosim: bool, module: &str) -> String {
    let text = |e: &Expr| print_expr(e, usize::MAX);
    match t.kind {
        TermKind::Exec => format!("`exec` ends this machine's cycle (`endexec__`, tagged with the transition and seen as `{module}::endexec`; enabled only while the transition's guard holds); what follows runs in the next cycle, after its inputs are read (`startexec`), `cycle` time units later (paper Rule 6)."),
        TermKind::OperationOutput => {
            let reg = first_register(&t.expr).unwrap_or_default();
            let op = reg.strip_prefix("o_").unwrap_or(&reg);
            format!(
                "Calls the platform operation `{op}` by writing its actuator register `{module}::{reg}` (`{module}::registerWrite.{module}::{reg}`) at once: urgent, no time passes (`EDeadline(…, 0)`), and the cycle admits each output register at most once (RoboTool 3). In the paper's semantics (Rule 7) the call is buffered (`stmout!…U.true.… -> SKIP`) and written when the cycle's processing ends."
            )
        }
        TermKind::Output => {
            let reg = first_register(&t.expr).unwrap_or_default();
            format!(
                "Writes the actuator register `{module}::{reg}` (`{module}::registerWrite.{module}::{reg}`) at once: urgent, no time passes (`EDeadline(…, 0)`), and the cycle admits each output register at most once (RoboTool 3). In the paper's semantics (Rule 7) the output is buffered (`stmout!…U.true.… -> SKIP`) and written when the cycle's processing ends."
            )
        }
        TermKind::Call => "Calls the platform operation: urgent (`EDeadline(…, 0)`), no time passes before the platform accepts the call.".into(),
        TermKind::Event => format!(
            "Offers `{}` to the environment; time may pass until it is accepted.",
            text(&t.expr).split(" ->").next().unwrap_or("")
        ),
        TermKind::Transition => {
            let first = match &t.expr {
                Expr::Prefix(c, f, _) => {
                    let mut s = c.clone();
                    for x in f {
                        match x {
                            crate::cspm::Field::Dot(e) => s.push_str(&format!(".{}", text(e))),
                            crate::cspm::Field::Out(e) => s.push_str(&format!("!{}", text(e))),
                            crate::cspm::Field::In(v) => s.push_str(&format!("?{v}")),
                            crate::cspm::Field::InFrom(v, _) => s.push_str(&format!("?{v}")),
                        }
                    }
                    s
                }
                _ => String::new(),
            };
            let guard = match &t.guard {
                Some(g) => format!(" The memory enables it only while `{}` holds.", text(g)),
                None => String::new(),
            };
            if first.starts_with("endexec") {
                format!("Taken at an `exec`: `{first}` ends the machine's cycle; the clock resets, action and target's entry run in the next cycle, after `startexec`.{guard}")
            } else if first.starts_with("internal__") {
                format!(
                    "No trigger: `{first}` is hidden, so the transition is taken as soon as it is enabled, before time passes{}.{guard}",
                    if robosim { "" } else { " (while it is not, time passes)" }
                )
            } else {
                format!("Waits for `{first}` (time may pass meanwhile), then runs the exit actions, clock resets and action, and enters the target.{guard}")
            }
        }
    }
}

fn first_register(e: &Expr) -> Option<String> {
    match e {
        Expr::Call(_, args) => args.iter().find_map(first_register),
        Expr::Dot(parts) if matches!(parts.first(), Some(Expr::Name(n)) if n == "registerWrite") => {
            match parts.get(1) {
                Some(Expr::Name(r)) => Some(r.clone()),
                _ => None,
            }
        }
        Expr::Prefix(_, _, b) => first_register(b),
        _ => None,
    }
}
