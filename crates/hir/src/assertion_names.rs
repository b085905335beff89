//! LNK-01 for the names of assertion files (`.assertions`, `.rsa`): the
//! sides of an assertion, the state of a reachability assertion, the
//! elements, constants and parameters of its `with` clause, the element a
//! `simulation` simulates and those a `csp` block is associated to.
//!
//! RoboTool's linker rejects a name that denotes nothing (XT-LNK-01). What
//! a name denotes is read by [`crate::target`], the one reading the
//! verifier uses too, so the checker never rejects a name the verifier
//! reads. A name the verifier cannot read is reported only when it denotes
//! no element of the model at all, not even one the verifier refuses (a
//! state as the subject of `deadlock-free`, say): RoboTool links such
//! names, so they are no linking error; the verifier says why it refuses
//! them. Ranges are those of the first segment of the path that names
//! nothing.

use std::collections::HashMap;

use robosim_syntax::{ast, ast::AstNode, SyntaxKind::*, SyntaxNode, TextRange, TextSize};

use crate::assertions::{AssertionFile, AssertionKind, Override};
use crate::defs::{file_defs, DefData, DefId, DefKind};
use crate::index::{file_summary, import_matches, index_for, resolve_item, ItemLoc};
use crate::resolve::ResolveProblem;
use crate::target::{self, Owner, Scope, StateMatch};
use crate::{parse, Db, File, FileKind, Workspace};

/// The LNK-01 (and LNK-03) problems of the names of the assertion file
/// `file`; nothing for other files.
#[salsa::tracked(returns(ref))]
pub fn assertion_name_problems(db: &dyn Db, ws: Workspace, file: File) -> Vec<ResolveProblem> {
    if !file.kind(db).is_assertions() || file.is_library(db) {
        return Vec::new();
    }
    let read = crate::model::assertion_file(db, file);
    let others: Vec<(File, AssertionFile)> = ws
        .files(db)
        .iter()
        .filter(|f| !f.is_library(db) && f.kind(db).is_assertions())
        .map(|&f| (f, crate::model::assertion_file(db, f).clone()))
        .collect();
    let scope = Scope { db, ws, file, read, others: &others };
    let root = parse(db, file).syntax_node();
    let mut c = Checker { scope, segments: segment_ranges(&root), out: Vec::new() };
    for s in &read.simulations {
        let element = |k| matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine);
        if !s.of.is_empty() && resolve_item(db, ws, file, &s.of, element).is_empty() {
            c.name(&s.of, s.of_range, "module, controller or state machine");
        }
    }
    for a in &read.assertions {
        match &a.kind {
            AssertionKind::Reachable { state, state_range, machine, machine_range } => {
                if c.side(machine, *machine_range) {
                    c.state(a, state, *state_range, machine);
                }
            }
            AssertionKind::Refines { other, other_range, .. } | AssertionKind::Equals { other, other_range, .. } => {
                c.side(&a.subject, a.subject_range);
                c.side(other, *other_range);
            }
            AssertionKind::Schedulable
            | AssertionKind::DeadlockFree
            | AssertionKind::DivergenceFree
            | AssertionKind::Deterministic
            | AssertionKind::TimelockFree
            | AssertionKind::Terminates => {
                c.side(&a.subject, a.subject_range);
            }
            // A clock is reached through its element (`M::T`, `Mod::c::m::T`):
            // a path that names nothing is reported; a bare clock name is
            // left alone (what RoboTool's scoping finds for it is not
            // established). The names of a PRISM property are the
            // resolver's; a broken assertion is the parser's.
            AssertionKind::ClockInitialised { clock, clock_range } => {
                if clock.len() >= 2 {
                    c.name(clock, *clock_range, "module, controller or state machine");
                }
            }
            AssertionKind::Probabilistic { .. } | AssertionKind::Other(_) => {}
        }
        for o in &a.overrides {
            match o {
                Override::Constant { name, name_range, of, of_range, value, value_range, .. } => {
                    c.constant(name, *name_range, of, *of_range);
                    if let crate::assertions::Value::Other(text) = value {
                        c.value(text, *value_range);
                    }
                }
                Override::Parameter { name, name_range, of, of_range, .. } => {
                    c.parameter(name, *name_range, of, *of_range)
                }
                Override::CycleDef { of, of_range, .. } => {
                    c.side(of, *of_range);
                }
            }
        }
    }
    // `csp P associated to A, B`.
    let associated = root.descendants().filter(|n| n.kind() == ASSOCIATED_TO);
    for q in associated.flat_map(|a| a.children().filter_map(ast::QualifiedName::cast)) {
        c.side(&q.segments(), q.syntax().text_range());
    }
    c.out.sort_by_key(|p| (p.range.start(), p.range.end()));
    c.out
}

/// The ranges of the segments of every qualified name of a file, by the
/// name's range.
fn segment_ranges(root: &SyntaxNode) -> HashMap<TextRange, Vec<TextRange>> {
    root.descendants()
        .filter(|n| n.kind() == QUALIFIED_NAME)
        .map(|q| {
            let ranges = q
                .children_with_tokens()
                .filter_map(|e| e.into_token())
                .filter(|t| t.kind() == IDENT || (t.kind().is_keyword() && t.kind() != COLON2))
                .map(|t| t.text_range())
                .collect();
            (q.text_range(), ranges)
        })
        .collect()
}

struct Checker<'a> {
    scope: Scope<'a>,
    segments: HashMap<TextRange, Vec<TextRange>>,
    out: Vec<ResolveProblem>,
}

impl Checker<'_> {
    /// The range of segment `i` of the path written at `range` (the whole
    /// range when the segments cannot be told apart).
    fn segment(&self, range: TextRange, i: usize, len: usize) -> TextRange {
        match self.segments.get(&range) {
            Some(s) if s.len() == len && i < len => s[i],
            _ => range,
        }
    }

    /// A side of an assertion (or the element of a `cycleDef of` or a `csp
    /// … associated to`): reported when it names nothing; whether it names
    /// something the verifier reads.
    fn side(&mut self, path: &[String], range: TextRange) -> bool {
        if path.is_empty() {
            return false;
        }
        if target::resolves(self.scope, path) {
            return true;
        }
        self.name(path, range, "simulation, module, controller, state machine, operation or `csp` block");
        false
    }

    /// Reports `path` (written at `range`, which should be a `what`) when
    /// it names no element of the model at all.
    fn name(&mut self, path: &[String], range: TextRange, what: &str) {
        let Scope { db, ws, file, .. } = self.scope;
        let Some(i) = unresolved_segment(db, ws, file, path).filter(|&i| i < path.len()) else { return };
        let at = self.segment(range, i, path.len());
        let seg = &path[i];
        let mut message = if i == 0 {
            format!("cannot resolve `{seg}`: no {what} of that name is in scope")
        } else {
            format!("cannot resolve `{seg}` in `{}`", path[..i].join("::"))
        };
        if let (0, 1, Some(full)) = (i, path.len(), unimported(db, ws, file, seg)) {
            if file.kind(db) == FileKind::SimAssertions {
                // RoboTool's RoboSim scoping also finds some plain names that no
                // import reaches (LNK-02): not an error here either.
                let message = format!(
                    "`{seg}` is not imported here: the verifier does not read it (add `import {full}`, or write `{full}`)"
                );
                self.out.push(ResolveProblem { code: "LNK-02", range: at, message });
                return;
            }
            message.push_str(&format!(" (`{full}` is not imported: add `import {full}`)"));
        }
        self.report(at, message);
    }

    /// LNK-01, or LNK-03 when the file imports a package the workspace does
    /// not hold (which may declare the name: it cannot be checked).
    fn report(&mut self, range: TextRange, message: String) {
        let Scope { db, ws, file, .. } = self.scope;
        let missing =
            file_summary(db, file).imports.iter().find(|(p, wild)| !import_matches(db, ws, file, p, *wild)).cloned();
        let (code, message) = match missing {
            Some((p, _)) => (
                "LNK-03",
                format!(
                    "{message}; it may be declared in the package `{}`, which is not in the workspace",
                    p.join("::")
                ),
            ),
            None => ("LNK-01", message),
        };
        self.out.push(ResolveProblem { code, range, message });
    }

    /// The state of `S is reachable in M`, read as the verifier reads it
    /// ([`target::match_state`]) among the machines of `M`.
    fn state(&mut self, a: &crate::assertions::AssertionDecl, state: &[String], range: TextRange, machine: &[String]) {
        let Scope { db, ws, .. } = self.scope;
        if state.is_empty() {
            return;
        }
        // A machine the verifier refuses (an undecidable period, …) says
        // nothing about its states.
        let Ok(subject) = target::subject(self.scope, a, machine) else { return };
        let Some(machines) = target::design_machines(db, ws, &subject) else { return };
        if !matches!(target::match_state(state, &machines), StateMatch::None) {
            return;
        }
        // The first segment no machine or state of `M` explains: after the
        // longest prefix that names one of its machines, the state path
        // inside it.
        let (k, named): (usize, Vec<_>) = (0..state.len())
            .rev()
            .map(|k| {
                (k, machines.iter().filter(|m| k > 0 && target::names_machine(m, &state[..k])).collect::<Vec<_>>())
            })
            .find(|(_, ms)| !ms.is_empty())
            .unwrap_or((0, machines.iter().collect()));
        let mut level: Vec<(&target::MachineStates, Option<usize>)> = named.iter().map(|m| (*m, None)).collect();
        let mut i = k;
        while i < state.len() {
            let next: Vec<_> = level
                .iter()
                .flat_map(|&(m, parent)| {
                    m.nodes
                        .iter()
                        .enumerate()
                        .filter(move |(_, n)| n.own && n.parent == parent && n.name == state[i])
                        .map(move |(ni, _)| (m, Some(ni)))
                })
                .collect();
            if next.is_empty() {
                break;
            }
            level = next;
            i += 1;
        }
        let i = i.min(state.len() - 1);
        let at = self.segment(range, i, state.len());
        let written = machine.join("::");
        let inside = if i == 0 { written.clone() } else { state[..i].join("::") };
        let message = if i + 1 == state.len() {
            format!("cannot resolve state `{}` in `{inside}`", state[i])
        } else {
            format!("cannot resolve `{}` in `{inside}`: no machine or state of that name", state[i])
        };
        let message = if i == 0 && state.len() > 1 {
            format!("{message} (a reachability assertion names a state of the machines of `{written}`)")
        } else {
            message
        };
        self.report(at, message);
    }

    /// `with constant name of of`.
    fn constant(&mut self, name: &str, name_range: TextRange, of: &[String], of_range: TextRange) {
        let Scope { db, ws, .. } = self.scope;
        if of.is_empty() {
            return;
        }
        let loc = match target::constant_owner(self.scope, of) {
            Some(Owner::Element(loc)) => loc,
            Some(Owner::Simulation) => return,
            None => return self.name(of, of_range, "module, controller or state machine"),
        };
        if name.is_empty() || target::constant_reads(self.scope, name, of) {
            return;
        }
        // The verifier refuses some constants it finds (one of a part of a
        // RoboSim element, one of a machine several controllers share): only
        // a name that is no constant anywhere in `of` is a linking error.
        let Some(id) = loc.def(db) else { return };
        if !has_constant_within(db, ws, loc.file, id, name, &mut Vec::new()) {
            let what = file_defs(db, loc.file).def(id).kind.describe();
            self.report(
                name_range,
                format!(
                    "cannot resolve constant `{name}` of the {what} `{}`: neither it, its interfaces nor its parts declare one",
                    of.join("::")
                ),
            );
        }
    }

    /// The value of `set to E::L` (RT-11: an enumeration literal): reported
    /// when the path names nothing. Other values (an expression, a real)
    /// are no names: the verifier says why it refuses them.
    fn value(&mut self, text: &str, range: TextRange) {
        let path: Vec<String> = text.split("::").map(|p| p.trim().to_string()).collect();
        let ident = |p: &String| {
            p.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
                && p.chars().all(|c| c.is_alphanumeric() || c == '_')
        };
        if path.len() >= 2 && path.iter().all(ident) {
            // Written without spaces (as usual), the segments' ranges follow
            // from the text: the squiggle goes under the one not found.
            if usize::from(range.len()) == text.len() && !self.segments.contains_key(&range) {
                let mut at = range.start();
                let ranges = text
                    .split("::")
                    .map(|seg| {
                        let r = TextRange::at(at, TextSize::of(seg));
                        at = r.end() + TextSize::of("::");
                        r
                    })
                    .collect();
                self.segments.insert(range, ranges);
            }
            self.name(&path, range, "enumeration");
        }
    }

    /// `with parameter name of of`.
    fn parameter(&mut self, name: &str, name_range: TextRange, of: &[String], of_range: TextRange) {
        let Scope { db, ws, .. } = self.scope;
        if of.is_empty() {
            return;
        }
        let Some((f, op)) = target::parameter_operation(self.scope, of) else {
            return self.name(of, of_range, "operation");
        };
        let defs = file_defs(db, f);
        let op_name = &defs.def(op).name;
        let has = |defs: &crate::defs::FileDefs, id: DefId| {
            defs.children(Some(id)).any(|(_, d)| d.kind == DefKind::Parameter && d.name == name)
        };
        // Any operation of that name with the parameter (the verifier binds
        // it by the operation's name) keeps it from being a linking error.
        let anywhere = || {
            ws.files(db).iter().filter(|g| !g.is_library(db)).any(|&g| {
                let d = file_defs(db, g);
                d.iter().any(|(id, o)| o.kind == DefKind::Operation && o.name == *op_name && has(d, id))
            })
        };
        if !name.is_empty() && !has(defs, op) && !anywhere() {
            self.report(name_range, format!("cannot resolve parameter `{name}` of the operation `{}`", of.join("::")));
        }
    }
}

/// Whether the element `id` of `file`, an interface it uses, provides or
/// requires, or one of its parts (inline or referenced: machines,
/// controllers, platforms, operations) declares a constant `name`.
fn has_constant_within(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    id: DefId,
    name: &str,
    seen: &mut Vec<(File, DefId)>,
) -> bool {
    if seen.contains(&(file, id)) {
        return false;
    }
    seen.push((file, id));
    let defs = file_defs(db, file);
    let interface = |path: &[String]| {
        resolve_item(db, ws, file, path, |k| k == DefKind::Interface).into_iter().any(|i| {
            i.def(db).is_some_and(|iid| {
                file_defs(db, i.file).children(Some(iid)).any(|(_, d)| d.kind == DefKind::Constant && d.name == name)
            })
        })
    };
    if defs.uses_of(id).any(|u| interface(&u.path)) {
        return true;
    }
    for (cid, d) in defs.children(Some(id)) {
        let found = match (&d.kind, &d.data) {
            (DefKind::Constant, _) => d.name == name,
            (
                DefKind::PlatformRef | DefKind::ControllerRef | DefKind::MachineRef | DefKind::OperationRef,
                DefData::Reference { path, .. },
            ) => resolve_item(db, ws, file, path, |_| true)
                .into_iter()
                .any(|l| l.def(db).is_some_and(|t| has_constant_within(db, ws, l.file, t, name, seen))),
            (k, _) if k.is_node() || k == &DefKind::Transition => false,
            _ => has_constant_within(db, ws, file, cid, name, seen),
        };
        if found {
            return true;
        }
    }
    false
}

/// The index of the first segment of `path`, written in `file`, that
/// names nothing of the model (an item, a member, a state, … at any
/// depth, through references); `None` when the whole path names
/// something.
fn unresolved_segment(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<usize> {
    for k in (1..=path.len()).rev() {
        let locs = resolve_item(db, ws, file, &path[..k], |_| true);
        if locs.is_empty() {
            continue;
        }
        let mut furthest = k;
        for l in locs {
            match walk(db, ws, l, &path[k..]) {
                None => return None,
                Some(i) => furthest = furthest.max(k + i),
            }
        }
        return Some(furthest);
    }
    // No prefix is an item: the segment after the longest package prefix.
    let index = index_for(db, ws, file);
    let here = file_summary(db, file);
    let package = |p: &[String]| {
        index.packages.contains(p)
            || index.packages.contains(&here.package.iter().chain(p).cloned().collect::<Vec<_>>())
    };
    Some((1..path.len()).rev().find(|&j| package(&path[..j])).unwrap_or(0))
}

/// Walks `rest` down from the item `loc` through children by name (and
/// the targets of references); the index in `rest` of the first segment
/// not found, `None` when all are (or when `loc` has no definition to walk:
/// nothing is claimed then).
fn walk(db: &dyn Db, ws: Workspace, loc: ItemLoc, rest: &[String]) -> Option<usize> {
    let mut at: Vec<(File, DefId)> = vec![(loc.file, loc.def(db)?)];
    for (i, seg) in rest.iter().enumerate() {
        let mut next = Vec::new();
        for &(f, id) in &at {
            let defs = file_defs(db, f);
            // A reference stands for what it references.
            let (f, id) = match &defs.def(id).data {
                // One that does not resolve claims nothing.
                DefData::Reference { path, .. } => {
                    resolve_item(db, ws, f, path, |_| true).into_iter().find_map(|l| Some((l.file, l.def(db)?)))?
                }
                _ => (f, id),
            };
            next.extend(file_defs(db, f).children(Some(id)).filter(|(_, d)| d.name == *seg).map(|(c, _)| (f, c)));
        }
        if next.is_empty() {
            return Some(i);
        }
        at = next;
    }
    None
}

/// `pkg::name` when a module, controller, machine or operation called
/// `name` is declared in the project but not visible from `file`.
fn unimported(db: &dyn Db, ws: Workspace, file: File, name: &str) -> Option<String> {
    let index = index_for(db, ws, file);
    let mut found: Vec<String> = index
        .items
        .iter()
        .filter(|(full, locs)| {
            full.last().is_some_and(|n| n == name)
                && locs.iter().any(|l| {
                    matches!(
                        l.summary(db).kind,
                        DefKind::Module | DefKind::Controller | DefKind::StateMachine | DefKind::Operation
                    )
                })
        })
        .map(|(full, _)| full.join("::"))
        .collect();
    found.sort();
    found.into_iter().next().filter(|f| f.contains("::"))
}
