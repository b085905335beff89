//! The tock-CSP semantics of one state machine, RoboChart or RoboSim, as
//! a CSPm module.
//!
//! The shape follows RoboTool and the paper (§5.2, Rules 3–7 and 13): the
//! machine is the parallel composition of its *behaviour* (one process per
//! state, junction and final state, offering the transitions) and of its
//! *memory* (variables, clocks, and the guards, which enable or disable
//! each transition's trigger; Rule 5). A RoboSim machine also has its
//! *cycle* (Rule 4): read the input registers, `startexec`, run until an
//! `exec` (`endexec`), then let `cycle` time units pass.
//!
//! Time is explicit tock-CSP (no `Timed` sections): a process that may
//! wait offers `tock`; platform operation calls and RoboSim register writes
//! are urgent (`EDeadline(e, 0)`); internal events have priority over
//! `tock` (`TimedPriority`). Triggers are tagged with their transition
//! (`obstacle__.TID_t1.in`) so that the memory can check the right guard,
//! and renamed back to the machine's events (`obstacle.in`) at the end.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use robosim_hir::defs::DefKind;
use robosim_hir::File;
use robosim_syntax::{ast, SyntaxKind::*, SyntaxNode, TextRange};

use crate::cspm::{bin, call, dot, ext, guard, hide, name, nary, par, prefix, seq, BinOp, Decl, Expr, Field, ProcOp};
use crate::export::{Chan, ChanKind, ConstParam, Dir, Elem, ElemKind, Exporter, Profile, RecordTy, Reg, Ty};
use crate::util::{
    self, child, children, expr_child, ident, ident_text, name_of, path_of, ref_of, stmt_child, type_child,
};

/// What a term is about, for hovers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermKind {
    /// A transition (the process taking it from its source).
    Transition,
    /// An `exec` trigger or statement (RoboSim).
    Exec,
    /// A RoboSim output (`$op(…)`, `$e!v`).
    Output,
    /// A call of a platform operation (RoboChart).
    Call,
    /// A communication statement or trigger.
    Event,
}

/// A CSP term of a piece of the model, for hovers.
#[derive(Debug, Clone)]
pub struct Term {
    /// The piece's range (a transition's name, the `exec` keyword, the
    /// statement).
    pub range: TextRange,
    /// What it is.
    pub kind: TermKind,
    /// The term, with triggers shown as the machine's events.
    pub expr: Expr,
    /// For transitions: the guard the memory checks, if any.
    pub guard: Option<Expr>,
}

/// The result of translating a machine.
pub(crate) struct MachineOut {
    pub elem: Elem,
    pub decls: Vec<Decl>,
    pub terms: Vec<Term>,
}

/// Something the export does not support: where and why.
pub(crate) type Problem = (File, TextRange, String);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NodeKind {
    State,
    Junction,
    Initial,
    Final,
}

struct NodeI {
    name: String,
    kind: NodeKind,
    parent: Option<usize>,
    syn: SyntaxNode,
    /// Suffix of its process names (path of names joined by `_`).
    tag: String,
}

struct TransI {
    tid: String,
    source: usize,
    target: usize,
    syn: SyntaxNode,
}

#[derive(Debug, Clone)]
enum Nm {
    Var(usize),
    Const(usize),
    Clock(usize),
    Event(usize),
    Op(usize),
    /// A parameter of the function being exported: its CSPm name and type.
    Param(String, Ty),
}

struct VarI {
    csp: String,
    ty: Ty,
    init: Expr,
    /// An operation's variable of its caller (required through an
    /// interface): read and written through the caller's memory.
    shared: bool,
}

struct ClockI {
    csp: String,
    /// Expressions (over constants) it is compared with.
    bounds: Vec<Expr>,
    /// Compared with something that is not constant.
    unbounded: bool,
    /// Read by an action (`since(C)` outside guards).
    read: bool,
    /// The state whose `sinceEntry` it is.
    state: Option<usize>,
}

struct EvI {
    name: String,
    csp: String,
    ty: Option<Ty>,
    io: Option<robosim_hir::defs::Io>,
    received: bool,
    /// Tagged trigger channel in use.
    trig: bool,
}

struct OpI {
    name: String,
    params: Vec<Ty>,
    /// Defined in the model (an `operation` with its own body): calls run
    /// it (`CALL__op`) instead of calling the platform.
    defined: bool,
}

struct GateI {
    t: usize,
    cond: Expr,
    /// `$e?x` in the guard: (variable, input event).
    binds: Vec<(usize, usize)>,
    trigger: GateTrigger,
}

#[derive(Clone, Copy)]
enum GateTrigger {
    Internal,
    Exec,
    Event(usize),
}

/// How an expression is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ECtx {
    /// In the behaviour: variables and clocks are read from the memory.
    Behaviour,
    /// In the memory (guards): variables and clocks are its parameters.
    Memory,
    /// Constants only (initial values, bounds).
    Const,
}

struct EOut {
    e: Expr,
    ty: Ty,
    /// Only constants and literals.
    pure: bool,
}

pub(crate) struct Gen<'e, 'a> {
    ex: &'e mut Exporter<'a>,
    file: File,
    node: SyntaxNode,
    robosim: bool,
    profile: Profile,
    names: HashMap<String, Nm>,
    locals: HashSet<String>,
    vars: Vec<VarI>,
    consts: Vec<ConstParam>,
    const_ty: Vec<Ty>,
    clocks: Vec<ClockI>,
    events: Vec<EvI>,
    ops: Vec<OpI>,
    nodes: Vec<NodeI>,
    trans: Vec<TransI>,
    problems: Vec<Problem>,
    /// Local definitions of the machine's `let`.
    defs: Vec<Decl>,
    /// The guards of the transitions, evaluated by the memory.
    gates: Vec<GateI>,
    /// Reads of the expression being translated (behaviour).
    reads: Vec<String>,
    /// `$e?x` bindings of the guard being translated: (variable, input).
    binds: Vec<(usize, usize)>,
    uses_exec_stmt: bool,
    record: bool,
    terms: Vec<Term>,
    /// Whether a trigger is being rendered for display (hovers).
    display: bool,
    counter: usize,
    /// Depth of the statements and expressions being translated.
    nesting: usize,
    /// Per node: whether it is a state with an activity (see
    /// [`Gen::activity`]), started when it is entered and stopped by every
    /// transition that leaves it.
    active: Vec<bool>,
    /// The activity processes (`Activity__S`).
    activities: Vec<String>,
    /// Translating an `operation` of the model (its parameters are those
    /// of `D__`, after `id__`).
    is_operation: bool,
    op_params: Vec<String>,
    /// `CALL__op` of the operations of the model called (their names).
    op_calls: Vec<(String, Decl)>,
    /// The variables the machine requires through interfaces (kept in its
    /// own memory: its container must not share them).
    required: Vec<String>,
}

/// Statements and expressions nested deeper are not exported (the
/// translation, printing and checking recurse on them).
const MAX_NESTING: usize = 64;

const GENERATED: &[&str] = &["P__", "D__", "O__", "VS__", "Memory__", "Behaviour__", "Cycle__", "id__", "cycle"];

impl<'e, 'a> Gen<'e, 'a> {
    pub(crate) fn new(ex: &'e mut Exporter<'a>, file: File, node: &SyntaxNode, record: bool) -> Self {
        let robosim = file.kind(ex.db) == robosim_syntax::FileKind::RoboSim;
        let profile = ex.profile;
        Gen {
            ex,
            file,
            node: node.clone(),
            robosim,
            profile,
            names: HashMap::new(),
            locals: HashSet::new(),
            vars: Vec::new(),
            consts: Vec::new(),
            const_ty: Vec::new(),
            clocks: Vec::new(),
            events: Vec::new(),
            ops: Vec::new(),
            nodes: Vec::new(),
            trans: Vec::new(),
            problems: Vec::new(),
            defs: Vec::new(),
            gates: Vec::new(),
            reads: Vec::new(),
            binds: Vec::new(),
            uses_exec_stmt: false,
            record,
            terms: Vec::new(),
            display: false,
            counter: 0,
            nesting: 0,
            active: Vec::new(),
            activities: Vec::new(),
            is_operation: false,
            op_params: Vec::new(),
            op_calls: Vec::new(),
            required: Vec::new(),
        }
    }

    /// What is being translated, for messages.
    fn what(&self) -> &'static str {
        if self.is_operation {
            "operation"
        } else {
            "machine"
        }
    }

    fn problem(&mut self, range: TextRange, msg: impl Into<String>) {
        self.problems.push((self.file, range, msg.into()));
    }

    /// A local name for the model name `n`, unique among the machine's.
    fn local(&mut self, n: &str) -> String {
        let mut s = ident(n);
        while s.contains("__")
            || GENERATED.contains(&s.as_str())
            || crate::defs::SHARED_PROCESSES.contains(&s.as_str())
            || s.starts_with("core_")
            || self.locals.contains(&s)
        {
            s.push('_');
            if s.len() > 200 {
                break;
            }
        }
        self.locals.insert(s.clone());
        s
    }

    /// Translates the machine: its CSPm module and its interface.
    pub(crate) fn run(mut self, module: String, path: Vec<String>) -> Result<MachineOut, Vec<Problem>> {
        let node = self.node.clone();
        self.declarations(&node);
        self.collect_nodes(&node, None);
        self.collect_transitions();
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        let decls = self.generate(&module);
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        let elem = self.interface(module, path);
        Ok(MachineOut { elem, decls, terms: self.terms })
    }

    /// Translates an operation of the model: its CSPm module and its
    /// channels and constants.
    fn run_operation(mut self, module: String, path: Vec<String>) -> Result<(Vec<Decl>, OperationOut), Vec<Problem>> {
        let node = self.node.clone();
        self.declarations(&node);
        self.collect_nodes(&node, None);
        self.collect_transitions();
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        if !self.nodes.iter().any(|n| n.parent.is_none() && n.kind == NodeKind::Initial) {
            self.problem(
                util::name_range(&node),
                "the operation has no body (initial junction): only operations defined by a state machine are exported",
            );
            return Err(self.problems);
        }
        let decls = self.generate(&module);
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        let _ = path;
        let mut chans = Vec::new();
        for e in &self.events {
            chans.push(OpChan {
                csp: e.csp.clone(),
                model: e.name.clone(),
                kind: OpChanKind::Event,
                dir: if e.received { Dir::In } else { Dir::Out },
                ty: e.ty.clone(),
                params: Vec::new(),
            });
        }
        let names: HashMap<String, usize> = self
            .names
            .iter()
            .filter_map(|(k, v)| if let Nm::Var(i) = v { Some((k.clone(), *i)) } else { None })
            .collect();
        let mut shared: Vec<(&String, &usize)> = names.iter().filter(|(_, i)| self.vars[**i].shared).collect();
        shared.sort_by_key(|(_, i)| **i);
        for (model, i) in shared {
            chans.push(OpChan {
                csp: self.vars[*i].csp.clone(),
                model: model.clone(),
                kind: OpChanKind::Var,
                dir: Dir::Out,
                ty: Some(self.vars[*i].ty.clone()),
                params: Vec::new(),
            });
        }
        for o in self.ops.iter().filter(|o| !o.defined) {
            let mut kinds = vec![OpChanKind::Call];
            if self.profile == Profile::Paper2019 {
                kinds.push(OpChanKind::Ret);
            }
            for kind in kinds {
                let suffix = if kind == OpChanKind::Call { "Call" } else { "Ret" };
                chans.push(OpChan {
                    csp: format!("{}{suffix}", ident(&o.name)),
                    model: o.name.clone(),
                    kind,
                    dir: Dir::Out,
                    ty: None,
                    params: o.params.clone(),
                });
            }
        }
        let consts = self.consts.iter().cloned().zip(self.const_ty.iter().cloned()).collect();
        Ok((decls, OperationOut { module: String::new(), params: Vec::new(), consts, chans }))
    }

    // ------------------------------------------------------ declarations

    fn declarations(&mut self, node: &SyntaxNode) {
        let file = self.file;
        let mut sources: Vec<(File, SyntaxNode, Option<robosim_hir::defs::Io>)> = vec![(file, node.clone(), None)];
        let contexts: Vec<SyntaxNode> =
            node.children().filter(|c| matches!(c.kind(), INPUT_CONTEXT | OUTPUT_CONTEXT)).collect();
        for c in &contexts {
            let io =
                if c.kind() == INPUT_CONTEXT { robosim_hir::defs::Io::Input } else { robosim_hir::defs::Io::Output };
            sources.push((file, c.clone(), Some(io)));
        }
        let mut uses: Vec<(SyntaxNode, Option<robosim_hir::defs::Io>)> =
            children(node, INTERFACE_USE).map(|u| (u, None)).collect();
        for c in &contexts {
            let io =
                if c.kind() == INPUT_CONTEXT { robosim_hir::defs::Io::Input } else { robosim_hir::defs::Io::Output };
            uses.extend(children(c, INTERFACE_USE).map(|u| (u, Some(io))));
        }
        for (u, io) in uses {
            let p = path_of(&u);
            match util::resolve(self.ex.db, self.ex.ws, file, &p, |k| k == DefKind::Interface) {
                Some((f, n)) => sources.push((f, n, io)),
                None => self.problem(u.text_range(), format!("the interface `{}` could not be resolved", p.join("::"))),
            }
        }
        for (f, n, io) in sources {
            for c in n.children() {
                match c.kind() {
                    VARIABLE_LIST => {
                        let is_const = c.children_with_tokens().any(|t| t.kind() == CONST_KW);
                        let shared = self.is_operation && !is_const && n != *node;
                        for v in children(&c, VARIABLE) {
                            if !is_const && !self.is_operation && io.is_none() && n != *node {
                                self.required.push(name_of(&v));
                            }
                            self.variable(f, &v, is_const, io, shared);
                        }
                    }
                    CLOCK => {
                        let n = name_of(&c);
                        let csp = self.local(&n);
                        self.clocks.push(ClockI {
                            csp,
                            bounds: Vec::new(),
                            unbounded: false,
                            read: false,
                            state: None,
                        });
                        self.names.insert(n, Nm::Clock(self.clocks.len() - 1));
                    }
                    EVENT => {
                        let n = name_of(&c);
                        if self.names.contains_key(&n) {
                            continue;
                        }
                        let ty = match type_child(&c) {
                            Some(t) => match self.ex.ty(f, Some(&t)) {
                                Ok(t) => Some(t),
                                Err(m) => {
                                    self.problems.push((f, c.text_range(), format!("event `{n}`: {m}")));
                                    None
                                }
                            },
                            None => None,
                        };
                        let csp = self.local(&n);
                        self.events.push(EvI { name: n.clone(), csp, ty, io, received: false, trig: false });
                        self.names.insert(n, Nm::Event(self.events.len() - 1));
                    }
                    OPERATION_SIG => {
                        let n = name_of(&c);
                        if self.names.contains_key(&n) {
                            continue;
                        }
                        let mut params = Vec::new();
                        if let Some(pl) = child(&c, PARAM_LIST) {
                            for p in children(&pl, PARAM) {
                                match self.ex.ty(f, type_child(&p).as_ref()) {
                                    Ok(t) => params.push(t),
                                    Err(m) => self.problems.push((f, p.text_range(), format!("operation `{n}`: {m}"))),
                                }
                            }
                        }
                        // An operation of the model with this name and a body (RoboTool
                        // matches a required operation and its definition by name); one
                        // with a contract only (`terminates`) stays a call event.
                        let defined = !self.robosim
                            && util::resolve(self.ex.db, self.ex.ws, file, std::slice::from_ref(&n), |k| {
                                k == DefKind::Operation
                            })
                            .is_some_and(|(_, d)| child(&d, INITIAL).is_some());
                        self.ops.push(OpI { name: n.clone(), params, defined });
                        self.names.insert(n, Nm::Op(self.ops.len() - 1));
                    }
                    OPERATION_DEF | OPERATION_REF | FUNCTION => self.problem(
                        c.text_range(),
                        "operations and functions defined in a machine are not supported by the export yet",
                    ),
                    _ => {}
                }
            }
        }
    }

    fn variable(&mut self, f: File, v: &SyntaxNode, is_const: bool, io: Option<robosim_hir::defs::Io>, shared: bool) {
        let n = name_of(v);
        if self.names.contains_key(&n) {
            return;
        }
        let ty = match self.ex.ty(f, type_child(v).as_ref()) {
            Ok(t) => t,
            Err(m) => {
                self.problems.push((f, v.text_range(), format!("`{n}`: {m}")));
                return;
            }
        };
        if io.is_some() && !is_const {
            self.problems.push((
                f,
                v.text_range(),
                format!("`{n}` is an input or output variable: platform variables are not supported by the export yet"),
            ));
            return;
        }
        let init = expr_child(v);
        if is_const {
            let local = self.local(&n);
            let mut owner = self.ex.path_of_node(self.file, &self.node);
            if self.is_operation {
                owner.push(name_of(&self.node));
            }
            let global = ident(&format!("const_{}_{}", util::qualified(&owner), n));
            let default = match &init {
                Some(e) if f == self.file => match self.expr(e, ECtx::Const, Some(&ty)) {
                    Some(o) => (o.e, String::new()),
                    None => {
                        self.problems.pop();
                        (self.const_default(&ty), format!("{n}: the model's value could not be exported"))
                    }
                },
                _ => (
                    self.const_default(&ty),
                    format!(
                        "{}::{n} has no value in the model: set it here, or with `with constant {n} of {} set to …`",
                        owner.join("::"),
                        owner.last().cloned().unwrap_or_default()
                    ),
                ),
            };
            self.ex.constant_default(&global, default.0, default.1);
            owner.shrink_to_fit();
            self.consts.push(ConstParam { global, local, owner, name: n.clone() });
            self.const_ty.push(ty);
            self.names.insert(n, Nm::Const(self.consts.len() - 1));
        } else {
            let csp = self.local(&n);
            let init = match &init {
                Some(e) => match self.expr(e, ECtx::Const, Some(&ty)) {
                    Some(o) => o.e,
                    None => return,
                },
                None => ty.default_value(),
            };
            self.vars.push(VarI { csp, ty, init, shared });
            self.names.insert(n, Nm::Var(self.vars.len() - 1));
        }
    }

    fn const_default(&self, ty: &Ty) -> Expr {
        match ty {
            // 1 rather than 0: constants are often divisors (PI / av).
            Ty::Nat | Ty::Int | Ty::Real => Expr::Int(1),
            t => t.default_value(),
        }
    }

    fn collect_nodes(&mut self, region: &SyntaxNode, parent: Option<usize>) {
        for c in region.children() {
            let kind = match c.kind() {
                STATE => NodeKind::State,
                JUNCTION => NodeKind::Junction,
                INITIAL => NodeKind::Initial,
                FINAL => NodeKind::Final,
                PROBABILISTIC_JUNCTION => {
                    self.problem(
                        c.text_range(),
                        "probabilistic junctions have no meaning in the tock-CSP semantics and are not exported",
                    );
                    continue;
                }
                _ => continue,
            };
            let name = name_of(&c);
            let tag = match parent {
                Some(p) => format!("{}_{}", self.nodes[p].tag, ident(&name)),
                None => ident(&name),
            };
            self.nodes.push(NodeI { name, kind, parent, syn: c.clone(), tag });
            if kind == NodeKind::State {
                let id = self.nodes.len() - 1;
                self.collect_nodes(&c, Some(id));
            }
        }
    }

    fn sibling(&self, parent: Option<usize>, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.parent == parent && n.name == name)
    }

    fn collect_transitions(&mut self) {
        let mut regions = vec![(self.node.clone(), None)];
        for (i, n) in self.nodes.iter().enumerate() {
            if n.kind == NodeKind::State {
                regions.push((n.syn.clone(), Some(i)));
            }
        }
        let mut used_tids = HashSet::new();
        for (region, parent) in regions {
            for t in children(&region, TRANSITION) {
                let name = name_of(&t);
                let end = |k| child(&t, k).and_then(|c| ref_of(&c));
                let (Some(src), Some(dst)) = (end(TRANSITION_SOURCE), end(TRANSITION_TARGET)) else {
                    self.problem(t.text_range(), format!("transition `{name}` lacks a source or a target"));
                    continue;
                };
                let (Some(source), Some(target)) = (self.sibling(parent, &src), self.sibling(parent, &dst)) else {
                    self.problem(t.text_range(), format!("transition `{name}`: its ends are not nodes of its region"));
                    continue;
                };
                let base = match parent {
                    Some(p) => format!("TID_{}_{}", self.nodes[p].tag, ident(&name)),
                    None => format!("TID_{}", ident(&name)),
                };
                let mut tid = base.clone();
                let mut k = 2;
                while !used_tids.insert(tid.clone()) {
                    tid = format!("{base}_{k}");
                    k += 1;
                }
                self.trans.push(TransI { tid, source, target, syn: t });
            }
        }
    }

    // ------------------------------------------------------ expressions

    fn expr(&mut self, e: &SyntaxNode, cx: ECtx, want: Option<&Ty>) -> Option<EOut> {
        if self.nesting >= MAX_NESTING {
            self.problem(e.text_range(), "this expression is nested too deeply for the export");
            return None;
        }
        self.nesting += 1;
        let out = self.expr_inner(e, cx, want);
        self.nesting -= 1;
        out
    }

    fn expr_inner(&mut self, e: &SyntaxNode, cx: ECtx, want: Option<&Ty>) -> Option<EOut> {
        let r = e.text_range();
        match e.kind() {
            PAREN_EXPR => {
                let inner = expr_child(e)?;
                self.expr(&inner, cx, want)
            }
            LITERAL => {
                let tok = e.first_token()?;
                match tok.kind() {
                    INT_NUMBER => match tok.text().parse::<i64>() {
                        Ok(v) => Some(EOut { e: Expr::Int(v), ty: Ty::Nat, pure: true }),
                        Err(_) => {
                            self.problem(r, "this number is too large");
                            None
                        }
                    },
                    TRUE_KW => Some(EOut { e: Expr::Bool(true), ty: Ty::Bool, pure: true }),
                    FALSE_KW => Some(EOut { e: Expr::Bool(false), ty: Ty::Bool, pure: true }),
                    FLOAT_NUMBER => {
                        let v: f64 = tok.text().parse().unwrap_or(f64::NAN);
                        if v.fract() == 0.0 && v.abs() < 1e15 {
                            Some(EOut { e: Expr::Int(v as i64), ty: Ty::Real, pure: true })
                        } else {
                            self.problem(r, "real numbers with a fractional part are not supported (reals are bounded integers, as in RoboTool)");
                            None
                        }
                    }
                    _ => {
                        self.problem(r, "this literal is not supported by the export yet");
                        None
                    }
                }
            }
            REF_EXPR => {
                let n = ident_text(e);
                match self.names.get(&n).cloned() {
                    Some(Nm::Const(i)) => {
                        let e = match cx {
                            // Initial values of constants refer to the others' defaults.
                            ECtx::Const => name(self.consts[i].global.clone()),
                            _ => name(self.consts[i].local.clone()),
                        };
                        Some(EOut { e, ty: self.const_ty[i].clone(), pure: true })
                    }
                    // In a guard, a variable bound by `$e?x` earlier in it is
                    // the input's value.
                    Some(Nm::Var(i)) if cx == ECtx::Memory && self.binds.iter().any(|(v, _)| *v == i) => {
                        let ev = self.binds.iter().find(|(v, _)| *v == i).map(|(_, e)| *e).unwrap_or(0);
                        let ty = self.vars[i].ty.clone();
                        Some(EOut { e: name(format!("{}_value", self.events[ev].csp)), ty, pure: false })
                    }
                    Some(Nm::Param(p, ty)) => Some(EOut { e: name(p), ty, pure: true }),
                    Some(Nm::Var(i)) if cx == ECtx::Memory && self.vars[i].shared => {
                        self.problem(
                            r,
                            format!("`{n}` is a variable of the operation's caller: guards cannot read it in the export yet"),
                        );
                        None
                    }
                    Some(Nm::Var(i)) if cx != ECtx::Const => {
                        let v = &self.vars[i];
                        let (csp, ty) = (v.csp.clone(), v.ty.clone());
                        if cx == ECtx::Behaviour && !self.reads.contains(&csp) {
                            self.reads.push(csp.clone());
                        }
                        Some(EOut { e: name(csp), ty, pure: false })
                    }
                    _ => {
                        self.problem(r, format!("`{n}` is not a variable or constant the export can read here"));
                        None
                    }
                }
            }
            ENUM_LITERAL_EXPR => {
                let parts: Vec<String> = children(e, NAME_REF).map(|c| ident_text(&c)).collect();
                let Some((lit, en)) = parts.split_last() else {
                    self.problem(r, "an empty literal");
                    return None;
                };
                let Some((ef, enode)) =
                    util::resolve(self.ex.db, self.ex.ws, self.file, en, |k| k == DefKind::Enumeration)
                else {
                    self.problem(r, "the enumeration could not be resolved");
                    return None;
                };
                let (dt, lits) = self.ex.enumeration(ef, &enode);
                match lits.iter().find(|(l, _)| l == lit) {
                    Some((_, c)) => {
                        let first = name(lits[0].1.clone());
                        Some(EOut { e: name(c.clone()), ty: Ty::Named(dt, first), pure: true })
                    }
                    None => {
                        self.problem(r, format!("`{lit}` is not a literal of the enumeration"));
                        None
                    }
                }
            }
            SINCE_EXPR | SINCE_ENTRY_EXPR => {
                let i = if e.kind() == SINCE_EXPR {
                    let n = ref_of(e).unwrap_or_default();
                    match self.names.get(&n) {
                        Some(Nm::Clock(i)) => *i,
                        _ => {
                            self.problem(r, format!("`{n}` is not a clock"));
                            return None;
                        }
                    }
                } else {
                    let p = path_of(e);
                    let n = p.last().cloned().unwrap_or_default();
                    let Some(s) = self.nodes.iter().position(|x| x.name == n && x.kind == NodeKind::State) else {
                        let what = self.what();
                        self.problem(r, format!("`{n}` is not a state of the {what}"));
                        return None;
                    };
                    self.since_entry_clock(s)
                };
                match cx {
                    ECtx::Const => {
                        self.problem(r, "clocks cannot be read here");
                        return None;
                    }
                    ECtx::Behaviour => {
                        self.clocks[i].read = true;
                        let csp = self.clocks[i].csp.clone();
                        if !self.reads.contains(&csp) {
                            self.reads.push(csp);
                        }
                    }
                    ECtx::Memory => {}
                }
                Some(EOut { e: name(self.clocks[i].csp.clone()), ty: Ty::Nat, pure: false })
            }
            SIM_REF_EXPR => {
                let n = path_of(e).join("::");
                let Some(Nm::Event(i)) = self.names.get(&n).cloned() else {
                    self.problem(
                        r,
                        format!("`${n}` is not an input event of the machine (input variables are not supported yet)"),
                    );
                    return None;
                };
                if cx != ECtx::Memory || !self.robosim {
                    self.problem(r, format!("`${n}` can only be read in guards here"));
                    return None;
                }
                self.events[i].received = true;
                if let Some(suffix) = child(e, SIM_INPUT_SUFFIX) {
                    let var = path_of(&suffix).join("::");
                    match self.names.get(&var) {
                        Some(Nm::Var(v)) if self.events[i].ty.is_some() => self.binds.push((*v, i)),
                        _ => {
                            self.problem(suffix.text_range(), format!("`{var}` cannot receive the value of `${n}`"));
                            return None;
                        }
                    }
                }
                if child(e, SIM_SYNC_SUFFIX).is_some() {
                    self.problem(r, "`$e.v` in guards is not supported by the export yet");
                    return None;
                }
                Some(EOut { e: name(self.events[i].csp.clone()), ty: Ty::Bool, pure: false })
            }
            PREFIX_EXPR => {
                let op = e.first_token().map(|t| t.kind());
                let inner = expr_child(e)?;
                let x = self.expr(&inner, cx, want)?;
                match op {
                    Some(NOT_KW) => Some(EOut { e: Expr::Not(Box::new(x.e)), ty: Ty::Bool, pure: x.pure }),
                    Some(MINUS) => match x.e {
                        Expr::Int(v) => Some(EOut { e: Expr::Int(-v), ty: Ty::Int, pure: true }),
                        ex => {
                            let t = if x.ty == Ty::Nat { Ty::Int } else { x.ty.clone() };
                            Some(EOut { e: call("Neg", vec![ex, t.set()]), ty: t, pure: x.pure })
                        }
                    },
                    _ => {
                        self.problem(r, "this operator is not supported by the export yet");
                        None
                    }
                }
            }
            BIN_EXPR => {
                let ops = ast::operand_exprs(e);
                let [a, b] = ops.as_slice() else {
                    self.problem(r, "an incomplete expression");
                    return None;
                };
                let op = ast::binary_operator(e);
                if matches!(op, Some(IN_KW | CAT_KW | CARET)) {
                    return self.collection_op(op, a, b, cx, want);
                }
                let arith = matches!(op, Some(PLUS | MINUS | STAR | SLASH | PERCENT));
                let x = self.expr(a, cx, if arith { want } else { None })?;
                let y = self.expr(b, cx, if arith { want } else { None })?;
                let pure = x.pure && y.pure;
                if matches!(op, Some(EQ2 | NEQ | LT | LTEQ | GT | GTEQ)) {
                    self.clock_bound(a, &y);
                    self.clock_bound(b, &x);
                }
                let cmp = |o| Some(EOut { e: bin(o, x.e.clone(), y.e.clone()), ty: Ty::Bool, pure });
                let sticky = |f: &str, sub: bool| {
                    let mut t = Ty::join(&x.ty, &y.ty);
                    if sub && t == Ty::Nat {
                        t = Ty::Int;
                    }
                    if let Some(w) = want.filter(|w| w.is_number()) {
                        t = w.clone();
                    }
                    Some(EOut { e: call(f, vec![x.e.clone(), y.e.clone(), t.set()]), ty: t, pure })
                };
                match op {
                    Some(PLUS) => sticky("Plus", false),
                    Some(MINUS) => sticky("Minus", true),
                    Some(STAR) => sticky("Mult", false),
                    Some(SLASH) => sticky("Div", false),
                    Some(PERCENT) => sticky("Modulus", false),
                    Some(EQ2) => cmp(BinOp::Eq),
                    Some(NEQ) => cmp(BinOp::Ne),
                    Some(LT) => cmp(BinOp::Lt),
                    Some(LTEQ) => cmp(BinOp::Le),
                    Some(GT) => cmp(BinOp::Gt),
                    Some(GTEQ) => cmp(BinOp::Ge),
                    Some(AND) => cmp(BinOp::And),
                    Some(OR) => cmp(BinOp::Or),
                    Some(IMPLIES) => {
                        Some(EOut { e: bin(BinOp::Or, Expr::Not(Box::new(x.e)), y.e), ty: Ty::Bool, pure })
                    }
                    Some(IFF_KW) => cmp(BinOp::Eq),
                    _ => {
                        self.problem(r, "this operator is not supported by the export yet");
                        None
                    }
                }
            }
            IF_EXPR => {
                let parts = ast::operand_exprs(e);
                let [c, a, b] = parts.as_slice() else {
                    self.problem(r, "an incomplete conditional");
                    return None;
                };
                let c = self.expr(c, cx, None)?;
                let a = self.expr(a, cx, want)?;
                let b = self.expr(b, cx, want)?;
                let pure = c.pure && a.pure && b.pure;
                Some(EOut { e: Expr::If(Box::new(c.e), Box::new(a.e), Box::new(b.e)), ty: a.ty, pure })
            }
            SET_EXPR | SEQ_EXPR => {
                let items = ast::operand_exprs(e);
                let elem_want = match want {
                    Some(Ty::Set(t)) | Some(Ty::Seq(t)) => Some((**t).clone()),
                    _ => None,
                };
                let mut es = Vec::new();
                let mut elem = elem_want.clone();
                let mut pure = true;
                for x in &items {
                    let o = self.expr(x, cx, elem_want.as_ref())?;
                    pure &= o.pure;
                    es.push(o.e);
                    elem.get_or_insert(o.ty);
                }
                // Unknown element type (an empty literal without context):
                // it only matters for arithmetic and projections.
                let elem = Box::new(elem.unwrap_or(Ty::Nat));
                if e.kind() == SET_EXPR {
                    Some(EOut { e: Expr::Set(es), ty: Ty::Set(elem), pure })
                } else {
                    self.ex.seq_literal_max = self.ex.seq_literal_max.max(es.len() as i64);
                    Some(EOut { e: Expr::SeqLit(es), ty: Ty::Seq(elem), pure })
                }
            }
            SET_RANGE_EXPR => {
                let parts = ast::operand_exprs(e);
                let [lo, hi] = parts.as_slice() else {
                    self.problem(r, "a range needs two bounds");
                    return None;
                };
                let lo = self.expr(lo, cx, None)?;
                let hi = self.expr(hi, cx, None)?;
                let ty = Ty::Set(Box::new(Ty::join(&lo.ty, &hi.ty)));
                Some(EOut { e: Expr::Range(Box::new(lo.e), Box::new(hi.e)), ty, pure: lo.pure && hi.pure })
            }
            CALL_EXPR => self.call_expr(e, cx),
            TUPLE_EXPR => {
                let items = ast::operand_exprs(e);
                let wants: Vec<Option<Ty>> = match want {
                    Some(Ty::Product(ts)) if ts.len() == items.len() => ts.iter().cloned().map(Some).collect(),
                    _ => vec![None; items.len()],
                };
                let mut es = Vec::new();
                let mut tys = Vec::new();
                let mut pure = true;
                for (x, w) in items.iter().zip(&wants) {
                    let o = self.expr(x, cx, w.as_ref())?;
                    pure &= o.pure;
                    es.push(o.e);
                    tys.push(w.clone().unwrap_or(o.ty));
                }
                Some(EOut { e: Expr::Tuple(es), ty: Ty::Product(tys), pure })
            }
            RECORD_LITERAL => {
                let rn = ref_of(e).unwrap_or_default();
                let Some((rf, rnode)) =
                    util::resolve(self.ex.db, self.ex.ws, self.file, std::slice::from_ref(&rn), |k| {
                        k == DefKind::Record
                    })
                else {
                    self.problem(r, format!("`{rn}` is not a record the export can resolve"));
                    return None;
                };
                let rec = match self.ex.record(rf, &rnode) {
                    Ok(x) => x,
                    Err(m) => {
                        self.problem(r, m);
                        return None;
                    }
                };
                let mut given: HashMap<String, SyntaxNode> = HashMap::new();
                for fv in children(e, FIELD_VALUE) {
                    if let (Some(f), Some(x)) = (ref_of(&fv), expr_child(&fv)) {
                        given.insert(f, x);
                    }
                }
                let mut parts = vec![name(rec.ctor.clone())];
                let mut pure = true;
                for (f, t) in &rec.fields {
                    let Some(x) = given.remove(f) else {
                        self.problem(r, format!("the record literal gives no value to the field `{f}`"));
                        return None;
                    };
                    let o = self.expr(&x, cx, Some(t))?;
                    pure &= o.pure;
                    parts.push(o.e);
                }
                if let Some(f) = given.keys().next() {
                    self.problem(r, format!("`{f}` is not a field of the record `{rn}`"));
                    return None;
                }
                Some(EOut { e: dot(parts), ty: Ty::Record(rec), pure })
            }
            SELECT_EXPR => {
                let inner = expr_child(e)?;
                let f = ref_of(e).unwrap_or_default();
                let x = self.expr(&inner, cx, None)?;
                match &x.ty {
                    Ty::Record(rec) => match rec.fields.iter().find(|(n, _)| *n == f) {
                        Some((_, t)) => Some(EOut { e: call(rec.getter(&f), vec![x.e]), ty: t.clone(), pure: x.pure }),
                        None => {
                            self.problem(r, format!("`{f}` is not a field of the record"));
                            None
                        }
                    },
                    _ => {
                        self.problem(r, "only fields of records can be selected here");
                        None
                    }
                }
            }
            INDEX_EXPR => {
                let parts = ast::operand_exprs(e);
                let [inner, index] = parts.as_slice() else {
                    self.problem(r, "only one index is supported by the export");
                    return None;
                };
                let x = self.expr(inner, cx, None)?;
                match x.ty.clone() {
                    // Components of tuples are numbered from 1.
                    Ty::Product(ts) => {
                        let k = index
                            .text()
                            .to_string()
                            .trim()
                            .parse::<usize>()
                            .ok()
                            .filter(|k| (1..=ts.len()).contains(k));
                        let Some(k) = k else {
                            self.problem(
                                index.text_range(),
                                format!(
                                    "a tuple of {} components is indexed by a number from 1 to {}",
                                    ts.len(),
                                    ts.len()
                                ),
                            );
                            return None;
                        };
                        let c = self.ex.components(ts.len(), x.e).swap_remove(k - 1);
                        Some(EOut { e: c, ty: ts[k - 1].clone(), pure: x.pure })
                    }
                    _ => {
                        self.problem(r, "indexing is supported on tuples only by the export");
                        None
                    }
                }
            }
            k => {
                self.problem(r, format!("this expression ({}) is not supported by the export yet", kind_words(k)));
                None
            }
        }
    }

    /// `x in s`, `s ^ t`, `s cat t`.
    fn collection_op(
        &mut self,
        op: Option<robosim_syntax::SyntaxKind>,
        a: &SyntaxNode,
        b: &SyntaxNode,
        cx: ECtx,
        want: Option<&Ty>,
    ) -> Option<EOut> {
        if op == Some(IN_KW) {
            let y = self.expr(b, cx, None)?;
            let elem = match &y.ty {
                Ty::Set(t) | Ty::Seq(t) => Some((**t).clone()),
                _ => None,
            };
            let x = self.expr(a, cx, elem.as_ref())?;
            let f = if matches!(y.ty, Ty::Seq(_)) { "elem" } else { "member" };
            return Some(EOut { e: call(f, vec![x.e, y.e]), ty: Ty::Bool, pure: x.pure && y.pure });
        }
        let x = self.expr(a, cx, want)?;
        let y = self.expr(b, cx, Some(&x.ty))?;
        Some(EOut { e: self.concat(x.e, y.e), ty: x.ty, pure: x.pure && y.pure })
    }

    /// `s ^ t`, sticky like arithmetic: when the result would be longer
    /// than the bound of sequences, `s`.
    fn concat(&mut self, s: Expr, t: Expr) -> Expr {
        self.ex.uses_seq = true;
        self.ex.helpers.insert("Concat");
        call("Concat", vec![s, t])
    }

    /// A call of a function: a toolkit function mapped to CSPm's
    /// built-ins, or a function of the model with an explicit definition.
    fn call_expr(&mut self, e: &SyntaxNode, cx: ECtx) -> Option<EOut> {
        let r = e.text_range();
        let callee = e.children().find(|c| ast::is_expr_kind(c.kind()));
        let args: Vec<SyntaxNode> = child(e, ARG_LIST)
            .map(|a| a.children().filter(|x| ast::is_expr_kind(x.kind())).collect())
            .unwrap_or_default();
        let fname = match &callee {
            Some(c) if c.kind() == REF_EXPR => ident_text(c),
            _ => {
                self.problem(r, "only calls of named functions are supported by the export");
                return None;
            }
        };
        let Some((ff, fnode)) =
            util::resolve(self.ex.db, self.ex.ws, self.file, std::slice::from_ref(&fname), |k| k == DefKind::Function)
        else {
            self.problem(r, format!("`{fname}` is not a function the export can resolve"));
            return None;
        };
        if ff.is_library(self.ex.db) {
            return self.toolkit(&fname, &args, cx, r);
        }
        let f = match crate::machine::function(self.ex, ff, &fnode) {
            Ok(f) => f,
            Err(m) => {
                self.problem(r, m);
                return None;
            }
        };
        if args.len() != f.params.len() {
            self.problem(r, format!("`{fname}` takes {} arguments", f.params.len()));
            return None;
        }
        let mut es = Vec::new();
        let mut pure = true;
        for (a, t) in args.iter().zip(&f.params) {
            let o = self.expr(a, cx, Some(t))?;
            pure &= o.pure;
            es.push(o.e);
        }
        Some(EOut { e: call(f.csp.clone(), es), ty: f.result.clone(), pure })
    }

    /// The toolkit functions with a CSPm counterpart.
    fn toolkit(&mut self, f: &str, args: &[SyntaxNode], cx: ECtx, r: TextRange) -> Option<EOut> {
        let mut outs = Vec::new();
        for a in args {
            outs.push(self.expr(a, cx, None)?);
        }
        let pure = outs.iter().all(|o| o.pure);
        let is_seq = outs.first().is_some_and(|o| matches!(o.ty, Ty::Seq(_)));
        let elem = outs.first().and_then(|o| match &o.ty {
            Ty::Set(t) | Ty::Seq(t) => Some((**t).clone()),
            _ => None,
        });
        let es: Vec<Expr> = outs.iter().map(|o| o.e.clone()).collect();
        let first_ty = outs.first().map(|o| o.ty.clone());
        let out = |e: Expr, ty: Ty| Some(EOut { e, ty, pure });
        match (f, es.as_slice()) {
            ("size", [s]) => out(call(if is_seq { "length" } else { "card" }, vec![s.clone()]), Ty::Nat),
            ("union" | "inter" | "diff", [a, b]) => out(call(f, vec![a.clone(), b.clone()]), first_ty?),
            ("notin", [x, s]) => out(Expr::Not(Box::new(call("member", vec![x.clone(), s.clone()]))), Ty::Bool),
            ("subseteq", [a, b]) => out(call("empty", vec![call("diff", vec![a.clone(), b.clone()])]), Ty::Bool),
            ("subset", [a, b]) => out(
                bin(
                    BinOp::And,
                    call("empty", vec![call("diff", vec![a.clone(), b.clone()])]),
                    bin(BinOp::Ne, a.clone(), b.clone()),
                ),
                Ty::Bool,
            ),
            ("head", [s]) if is_seq => out(call("head", vec![s.clone()]), elem?),
            ("tail", [s]) if is_seq => out(call("tail", vec![s.clone()]), first_ty?),
            ("isNonEmpty", [s]) => {
                out(Expr::Not(Box::new(call(if is_seq { "null" } else { "empty" }, vec![s.clone()]))), Ty::Bool)
            }
            ("concat", [a, b]) if is_seq => {
                let e = self.concat(a.clone(), b.clone());
                out(e, first_ty?)
            }
            ("filter", [s, a]) if is_seq => {
                self.ex.helpers.insert("Filter");
                out(call("Filter", vec![s.clone(), a.clone()]), first_ty?)
            }
            ("last" | "front" | "reverse", [s]) if is_seq => {
                let h = match f {
                    "last" => "Last",
                    "front" => "Front",
                    _ => "Reverse",
                };
                self.ex.helpers.insert(h);
                out(call(h, vec![s.clone()]), if f == "last" { elem? } else { first_ty? })
            }
            _ => {
                self.problem(
                    r,
                    format!("the toolkit function `{f}` is not supported by the export yet (with these arguments)"),
                );
                None
            }
        }
    }

    /// Records that the clock read by `side` (if any) is compared with `other`.
    fn clock_bound(&mut self, side: &SyntaxNode, other: &EOut) {
        let mut s = side.clone();
        while s.kind() == PAREN_EXPR {
            match expr_child(&s) {
                Some(i) => s = i,
                None => return,
            }
        }
        let i = match s.kind() {
            SINCE_EXPR => match ref_of(&s).and_then(|n| self.names.get(&n).cloned()) {
                Some(Nm::Clock(i)) => i,
                _ => return,
            },
            SINCE_ENTRY_EXPR => {
                let n = path_of(&s).last().cloned().unwrap_or_default();
                match self.nodes.iter().position(|x| x.name == n && x.kind == NodeKind::State) {
                    Some(st) => self.since_entry_clock(st),
                    None => return,
                }
            }
            _ => return,
        };
        if other.pure {
            if !self.clocks[i].bounds.contains(&other.e) {
                self.clocks[i].bounds.push(other.e.clone());
            }
        } else {
            self.clocks[i].unbounded = true;
        }
    }

    fn since_entry_clock(&mut self, state: usize) -> usize {
        if let Some(i) = self.clocks.iter().position(|c| c.state == Some(state)) {
            return i;
        }
        let csp = self.local(&format!("sinceEntry_{}", self.nodes[state].tag));
        self.clocks.push(ClockI { csp, bounds: Vec::new(), unbounded: false, read: false, state: Some(state) });
        self.clocks.len() - 1
    }

    /// `get_x?x -> …` for the variables and clocks `reads` mentions.
    /// Records `expr` as the meaning of the element at `range`, for hover,
    /// when terms are being recorded (and not while rendering a display).
    fn record_term(&mut self, range: TextRange, kind: TermKind, expr: impl FnOnce() -> Expr) {
        if self.record && !self.display {
            self.terms.push(Term { range, kind, expr: expr(), guard: None });
        }
    }

    fn with_reads(&self, reads: &[String], body: Expr) -> Expr {
        let mut p = body;
        for r in reads.iter().rev() {
            p = prefix(format!("get_{r}"), vec![Field::In(r.clone())], p);
        }
        p
    }

    /// Translates `e` in the behaviour, returning the reads it needs.
    fn bexpr(&mut self, e: &SyntaxNode, want: Option<&Ty>) -> Option<(Expr, Vec<String>)> {
        let saved = std::mem::take(&mut self.reads);
        let out = self.expr(e, ECtx::Behaviour, want);
        let reads = std::mem::replace(&mut self.reads, saved);
        out.map(|o| (o.e, reads))
    }

    // ------------------------------------------------------ statements

    fn stmt(&mut self, s: &SyntaxNode) -> Option<Expr> {
        if self.nesting >= MAX_NESTING {
            self.problem(s.text_range(), "this statement is nested too deeply for the export");
            return None;
        }
        self.nesting += 1;
        let out = self.stmt_inner(s);
        self.nesting -= 1;
        out
    }

    fn stmt_inner(&mut self, s: &SyntaxNode) -> Option<Expr> {
        let r = s.text_range();
        match s.kind() {
            SEQ_STMT => {
                let mut parts = Vec::new();
                for c in s.children().filter(|c| ast::is_stmt_kind(c.kind())) {
                    parts.push(self.stmt(&c)?);
                }
                Some(fold_seq(parts))
            }
            SKIP_STMT => Some(Expr::Skip),
            ASSIGN_STMT => {
                let assignable = child(s, ASSIGNABLE);
                let target = assignable.as_ref().map(|a| path_of(a).join("::")).unwrap_or_default();
                let Some(Nm::Var(v)) = self.names.get(&target).cloned() else {
                    self.problem(r, format!("`{target}` is not a variable the export can assign"));
                    return None;
                };
                // `r.f.g = e`: the record fields on the way to the assigned one.
                let mut path: Vec<(Rc<RecordTy>, String)> = Vec::new();
                let mut ty = self.vars[v].ty.clone();
                for a in assignable.iter().flat_map(|a| a.children()) {
                    match a.kind() {
                        FIELD_ACCESS => {
                            let f = ref_of(&a).unwrap_or_default();
                            let Ty::Record(rec) = ty.clone() else {
                                self.problem(a.text_range(), "only fields of records can be assigned");
                                return None;
                            };
                            let Some((_, t)) = rec.fields.iter().find(|(n, _)| *n == f) else {
                                self.problem(a.text_range(), format!("`{f}` is not a field of the record"));
                                return None;
                            };
                            ty = t.clone();
                            path.push((rec, f));
                        }
                        INDEX_ACCESS => {
                            self.problem(
                                a.text_range(),
                                "assignments to indexed elements are not supported by the export yet",
                            );
                            return None;
                        }
                        _ => {}
                    }
                }
                let e = expr_child(s)?;
                let (mut val, mut reads) = self.bexpr(&e, Some(&ty))?;
                if !path.is_empty() {
                    // r.f.g = e is r = set_f(r, set_g(get_f(r), e)).
                    let csp = self.vars[v].csp.clone();
                    if !reads.contains(&csp) {
                        reads.push(csp.clone());
                    }
                    let mut olds = vec![name(csp)];
                    for (rec, f) in &path[..path.len() - 1] {
                        let prev = olds.last().cloned().expect("a value");
                        olds.push(call(rec.getter(f), vec![prev]));
                    }
                    for ((rec, f), old) in path.iter().zip(olds).rev() {
                        val = call(rec.setter(f), vec![old, val]);
                    }
                }
                let set = prefix(format!("set_{}", self.vars[v].csp), vec![Field::Out(val)], Expr::Skip);
                Some(self.with_reads(&reads, set))
            }
            CLOCK_RESET_STMT => {
                let n = ref_of(s).unwrap_or_default();
                match self.names.get(&n) {
                    Some(Nm::Clock(c)) => Some(prefix(format!("reset_{}", self.clocks[*c].csp), vec![], Expr::Skip)),
                    _ => {
                        self.problem(r, format!("`{n}` is not a clock"));
                        None
                    }
                }
            }
            IF_STMT => {
                let c = expr_child(s)?;
                let (cond, reads) = self.bexpr(&c, None)?;
                let branches: Vec<SyntaxNode> = s.children().filter(|c| ast::is_stmt_kind(c.kind())).collect();
                let a = match branches.first() {
                    Some(b) => self.stmt(b)?,
                    None => Expr::Skip,
                };
                let b = match branches.get(1) {
                    Some(b) => self.stmt(b)?,
                    None => Expr::Skip,
                };
                Some(self.with_reads(&reads, Expr::If(Box::new(cond), Box::new(a), Box::new(b))))
            }
            COMM_STMT => {
                let comm = child(s, COMMUNICATION)?;
                let term = self.communication(&comm, None)?;
                let head = child(&comm, NAME_REF).map(|n| n.text_range()).unwrap_or(r);
                self.record_term(head, TermKind::Event, || term.clone());
                Some(term)
            }
            CALL_STMT => {
                let n = path_of(s).join("::");
                let Some(Nm::Op(o)) = self.names.get(&n).cloned() else {
                    self.problem(
                        r,
                        format!("`{n}` is not an operation of the platform: calls of operations defined in the model are not supported by the export yet"),
                    );
                    return None;
                };
                if self.robosim {
                    self.problem(r, format!("`{n}(…)` in a RoboSim machine must be an output: `${n}(…)`"));
                    return None;
                }
                if self.ops[o].defined {
                    return self.call_operation(s, o);
                }
                let (args, reads) = self.arguments(s, o)?;
                let op = &self.ops[o];
                let mut fields = vec![name(format!("{}Call", ident(&op.name)))];
                fields.extend(args);
                let mut p = call("EDeadline", vec![dot(fields), Expr::Int(0)]);
                if self.profile == Profile::Paper2019 {
                    p = seq(vec![p, call("EDeadline", vec![name(format!("{}Ret", ident(&op.name))), Expr::Int(0)])]);
                }
                let p = self.with_reads(&reads, p);
                self.record_term(head_range(s), TermKind::Call, || p.clone());
                Some(p)
            }
            WAIT_STMT => {
                let e = expr_child(s)?;
                if e.kind() == INTERVAL_EXPR {
                    let bounds = ast::operand_exprs(&e);
                    let [lo, hi] = bounds.as_slice() else {
                        self.problem(e.text_range(), "an interval needs two bounds");
                        return None;
                    };
                    let open_lo = e.first_token().is_some_and(|t| t.kind() == L_PAREN);
                    let open_hi = e.last_token().is_some_and(|t| t.kind() == R_PAREN);
                    let (mut lo, mut r1) = self.bexpr(lo, None)?;
                    let (mut hi, r2) = self.bexpr(hi, None)?;
                    if open_lo {
                        lo = bin(BinOp::Add, lo, Expr::Int(1));
                    }
                    if open_hi {
                        hi = bin(BinOp::Sub, hi, Expr::Int(1));
                    }
                    for x in r2 {
                        if !r1.contains(&x) {
                            r1.push(x);
                        }
                    }
                    let p = call("WaitInterval", vec![Expr::Range(Box::new(lo), Box::new(hi))]);
                    Some(self.with_reads(&r1, p))
                } else {
                    let (n, reads) = self.bexpr(&e, None)?;
                    Some(self.with_reads(&reads, call("Wait", vec![n])))
                }
            }
            TIMED_STMT => {
                let body = stmt_child(s)?;
                let limit = child(s, DEADLINE).and_then(|d| expr_child(&d))?;
                let (d, reads) = self.bexpr(&limit, None)?;
                let b = self.stmt(&body)?;
                Some(self.with_reads(&reads, call("EndBy", vec![b, d])))
            }
            PAR_STMT => {
                let inner: Vec<SyntaxNode> = s.children().filter(|c| ast::is_stmt_kind(c.kind())).collect();
                match inner.as_slice() {
                    [one] => self.stmt(one),
                    _ => {
                        self.problem(r, "parallel statements are not supported by the export yet");
                        None
                    }
                }
            }
            SIM_CALL_STMT => {
                let n = path_of(s).join("::");
                let Some(Nm::Op(o)) = self.names.get(&n).cloned() else {
                    self.problem(r, format!("`${n}` is not an output operation of the machine"));
                    return None;
                };
                let (args, reads) = self.arguments(s, o)?;
                let model = self.ops[o].name.clone();
                let p = self.output(&model, args, r)?;
                let p = self.with_reads(&reads, p);
                self.record_term(head_range(s), TermKind::Output, || p.clone());
                Some(p)
            }
            OUTPUT_COMM_STMT => {
                let n = path_of(s).join("::");
                let Some(Nm::Event(i)) = self.names.get(&n).cloned() else {
                    self.problem(r, format!("`${n}` is not an output event of the machine"));
                    return None;
                };
                let ty = self.events[i].ty.clone();
                let value = expr_child(s);
                let (args, reads) = match (&ty, value) {
                    (Some(t), Some(v)) => {
                        let (e, reads) = self.bexpr(&v, Some(t))?;
                        (self.fields_of(t, e), reads)
                    }
                    (None, None) => (Vec::new(), Vec::new()),
                    _ => {
                        self.problem(r, format!("`${n}` needs exactly its declared value"));
                        return None;
                    }
                };
                let model = self.events[i].name.clone();
                let p = self.output(&model, args, r)?;
                let p = self.with_reads(&reads, p);
                self.record_term(head_range(s), TermKind::Output, || p.clone());
                Some(p)
            }
            EXEC_STMT => {
                if !self.robosim {
                    self.problem(r, "`exec` belongs to RoboSim machines");
                    return None;
                }
                self.uses_exec_stmt = true;
                let p = prefix("endexec", vec![Field::Dot(name("TID_exec"))], name("StartExec__"));
                self.record_term(r, TermKind::Exec, || {
                    prefix("endexec", vec![Field::Dot(name("TID_exec"))], prefix("startexec", vec![], Expr::Skip))
                });
                Some(p)
            }
            k => {
                self.problem(r, format!("this statement ({}) is not supported by the export yet", kind_words(k)));
                None
            }
        }
    }

    /// A call of an operation defined in the model: its process
    /// (`Op::D__(id__, args, constants)`, its events renamed to the
    /// caller's), through `CALL__op(args)` as RoboTool names it. The
    /// operation's events and platform calls become the caller's.
    fn call_operation(&mut self, s: &SyntaxNode, o: usize) -> Option<Expr> {
        let r = s.text_range();
        let n = self.ops[o].name.clone();
        let callee = |k| k == DefKind::Operation;
        let (of, onode) = util::resolve(self.ex.db, self.ex.ws, self.file, std::slice::from_ref(&n), callee)?;
        let op = match operation(self.ex, of, &onode) {
            Ok(op) => op,
            Err(m) => {
                self.problem(r, m);
                return None;
            }
        };
        if op.params != self.ops[o].params {
            self.problem(r, format!("`{n}`: its definition's parameters differ from the required signature"));
            return None;
        }
        let helper = format!("CALL__{}", ident(&n));
        if !self.op_calls.iter().any(|(h, _)| *h == helper) {
            let def = self.operation_helper(&op, &helper, r)?;
            self.op_calls.push((helper.clone(), def));
        }
        let (args, reads) = self.arguments(s, o)?;
        let p = if args.is_empty() { name(helper) } else { call(helper, args) };
        let p = self.with_reads(&reads, p);
        self.record_term(head_range(s), TermKind::Call, || p.clone());
        Some(p)
    }

    /// `CALL__op(x…) = Op::D__(id__, x…, constants) [[ Op::e <- e, … ]]`:
    /// the operation's constants become the caller's, its channels the
    /// caller's channels of the same name.
    fn operation_helper(&mut self, op: &OperationOut, helper: &str, r: TextRange) -> Option<Decl> {
        let params: Vec<String> = (0..op.params.len()).map(|k| format!("x{k}__")).collect();
        let mut args = vec![name("id__")];
        args.extend(params.iter().map(|p| name(p.clone())));
        for (c, t) in &op.consts {
            let local = match self.consts.iter().find(|x| x.global == c.global) {
                Some(x) => x.local.clone(),
                None => {
                    let local = self.local(&format!("{}_{}", c.owner.last().cloned().unwrap_or_default(), c.name));
                    self.consts.push(ConstParam { local: local.clone(), ..c.clone() });
                    self.const_ty.push(t.clone());
                    local
                }
            };
            args.push(name(local));
        }
        let mut renames = Vec::new();
        for ch in &op.chans {
            let mine = match ch.kind {
                OpChanKind::Var => {
                    let mine = match self.names.get(&ch.model).cloned() {
                        Some(Nm::Var(i)) if Some(&self.vars[i].ty) == ch.ty.as_ref() => self.vars[i].csp.clone(),
                        _ => {
                            self.problem(
                                r,
                                format!(
                                    "the operation uses the variable `{}`, which the caller lacks (or of another type)",
                                    ch.model
                                ),
                            );
                            return None;
                        }
                    };
                    for g in ["get_", "set_"] {
                        renames.push((name(format!("{}::{g}{}", op.module, ch.csp)), name(format!("{g}{mine}"))));
                    }
                    continue;
                }
                OpChanKind::Event => {
                    let ty = ch.ty.clone();
                    let i = match self.names.get(&ch.model).cloned() {
                        Some(Nm::Event(i)) => i,
                        None => {
                            let csp = self.local(&ch.model);
                            self.events.push(EvI {
                                name: ch.model.clone(),
                                csp,
                                ty: ty.clone(),
                                io: None,
                                received: false,
                                trig: false,
                            });
                            self.names.insert(ch.model.clone(), Nm::Event(self.events.len() - 1));
                            self.events.len() - 1
                        }
                        Some(_) => {
                            self.problem(r, format!("`{}` of the operation is not an event of the caller", ch.model));
                            return None;
                        }
                    };
                    if self.events[i].ty != ty {
                        self.problem(r, format!("the event `{}` has another type in the operation", ch.model));
                        return None;
                    }
                    if ch.dir == Dir::In {
                        self.events[i].received = true;
                    }
                    self.events[i].csp.clone()
                }
                OpChanKind::Call | OpChanKind::Ret => {
                    let i = match self.names.get(&ch.model).cloned() {
                        Some(Nm::Op(i)) => i,
                        None => {
                            let params = ch.params.clone();
                            self.ops.push(OpI { name: ch.model.clone(), params, defined: false });
                            self.names.insert(ch.model.clone(), Nm::Op(self.ops.len() - 1));
                            self.ops.len() - 1
                        }
                        Some(_) => {
                            self.problem(
                                r,
                                format!("`{}` of the operation is not an operation of the caller", ch.model),
                            );
                            return None;
                        }
                    };
                    if self.ops[i].params != ch.params || self.ops[i].defined {
                        self.problem(r, format!("the operation `{}` has another signature in the callee", ch.model));
                        return None;
                    }
                    let suffix = if ch.kind == OpChanKind::Call { "Call" } else { "Ret" };
                    format!("{}{suffix}", ident(&ch.model))
                }
            };
            renames.push((name(format!("{}::{}", op.module, ch.csp)), name(mine)));
        }
        let mut body = call(format!("{}::D__", op.module), args);
        if !renames.is_empty() {
            body = Expr::Rename(Box::new(body), renames, vec![]);
        }
        Some(Decl::Def(helper.to_string(), params, body))
    }

    /// A RoboSim output: the register write, urgent (robotool3), or its
    /// record in the machine's buffer (paper2019, Rule 7).
    fn output(&mut self, model: &str, args: Vec<Expr>, _r: TextRange) -> Option<Expr> {
        let ctor = self.ex.out_reg(model);
        if self.profile == Profile::Paper2019 {
            let mut f = vec![Field::Dot(name(ctor)), Field::Dot(Expr::Bool(true))];
            f.extend(args.into_iter().map(Field::Dot));
            return Some(prefix("stmout", f, Expr::Skip));
        }
        let mut f = vec![name("registerWrite"), name(ctor)];
        f.extend(args);
        Some(call("EDeadline", vec![dot(f), Expr::Int(0)]))
    }

    fn arguments(&mut self, s: &SyntaxNode, o: usize) -> Option<(Vec<Expr>, Vec<String>)> {
        let args: Vec<SyntaxNode> = child(s, ARG_LIST)
            .map(|a| a.children().filter(|e| ast::is_expr_kind(e.kind())).collect())
            .unwrap_or_default();
        let params = self.ops[o].params.clone();
        if args.len() != params.len() {
            self.problem(s.text_range(), format!("`{}` takes {} arguments", self.ops[o].name, params.len()));
            return None;
        }
        let mut out = Vec::new();
        let mut reads = Vec::new();
        for (a, t) in args.iter().zip(&params) {
            let (e, r) = self.bexpr(a, Some(t))?;
            for x in r {
                if !reads.contains(&x) {
                    reads.push(x);
                }
            }
            out.push(e);
        }
        Some((out, reads))
    }

    /// A communication `e`, `e!v`, `e.v` or `e?x`: as a statement
    /// (`trigger = None`: delayable) or as the trigger of a transition
    /// (tagged with its identifier), followed by `then`.
    fn communication(&mut self, comm: &SyntaxNode, trigger: Option<(&str, Expr)>) -> Option<Expr> {
        let r = comm.text_range();
        let ev = ref_of(comm).unwrap_or_default();
        let Some(Nm::Event(i)) = self.names.get(&ev).cloned() else {
            let what = self.what();
            self.problem(r, format!("`{ev}` is not an event of the {what} (declared or used through an interface)"));
            return None;
        };
        if self.robosim {
            self.problem(r, "RoboSim machines communicate through `$` inputs and outputs only");
            return None;
        }
        let ty = self.events[i].ty.clone();
        let mut dir = if trigger.is_some() { "in" } else { "out" };
        let mut value: Option<Vec<Expr>> = None;
        let mut bind: Option<usize> = None;
        let mut reads = Vec::new();
        for p in comm.children() {
            match p.kind() {
                COMM_SYNC | COMM_OUTPUT => {
                    let Some(t) = ty.clone() else {
                        self.problem(r, format!("`{ev}` carries no value"));
                        return None;
                    };
                    let e = expr_child(&p)?;
                    let (v, rd) = self.bexpr(&e, Some(&t))?;
                    reads = rd;
                    value = Some(self.fields_of(&t, v));
                    dir = if p.kind() == COMM_SYNC { "in" } else { "out" };
                }
                COMM_INPUT => {
                    if p.children().any(|n| ast::is_expr_kind(n.kind()) || n.kind() == COMM_GUARD) {
                        self.problem(p.text_range(), "guarded inputs `e[|g|]?x` are not supported by the export yet");
                        return None;
                    }
                    let var = path_of(&p).join("::");
                    match self.names.get(&var) {
                        Some(Nm::Var(v)) if ty.is_some() => bind = Some(*v),
                        _ => {
                            self.problem(p.text_range(), format!("`{var}` cannot receive a value of `{ev}`"));
                            return None;
                        }
                    }
                    dir = "in";
                }
                _ => {}
            }
        }
        if dir == "in" {
            self.events[i].received = true;
        }
        let csp = self.events[i].csp.clone();
        let mut fields = vec![Field::Dot(name(dir))];
        // The input fields (one per component of a product) and the value
        // they make, stored in the variable.
        let bound = match (bind, &ty) {
            (Some(v), Some(t)) => {
                let base = if self.display { self.vars[v].csp.clone() } else { format!("{}__in", self.vars[v].csp) };
                Some(t.input_fields(&base))
            }
            _ => None,
        };
        if let Some(v) = &value {
            fields.extend(v.iter().cloned().map(Field::Dot));
        } else if let Some((f, _)) = &bound {
            fields.extend(f.iter().cloned());
        }
        let store = |then: Expr| match (bind, &bound) {
            (Some(v), Some((_, val))) => {
                prefix(format!("set_{}", self.vars[v].csp), vec![Field::Out(val.clone())], then)
            }
            _ => then,
        };
        match trigger {
            Some((tid, then)) => {
                let chan = if self.display {
                    csp.clone()
                } else {
                    self.events[i].trig = true;
                    fields.insert(0, Field::Dot(name(tid)));
                    format!("{csp}__")
                };
                let p = prefix(chan, fields, store(then));
                Some(self.with_reads(&reads, p))
            }
            None => {
                let p = match (bind, &bound) {
                    (Some(_), Some(_)) => {
                        // An input: wait for it, then store it.
                        self.counter += 1;
                        let n = format!("Input__{}", self.counter);
                        let body = ext(vec![
                            prefix(csp.clone(), fields, store(Expr::Skip)),
                            prefix("tock", vec![], name(n.clone())),
                        ]);
                        self.defs.push(Decl::Def(n.clone(), vec![], body));
                        name(n)
                    }
                    _ => {
                        let mut f = vec![name(csp.clone())];
                        for x in fields {
                            if let Field::Dot(e) = x {
                                f.push(e);
                            }
                        }
                        call("Delayable", vec![dot(f)])
                    }
                };
                Some(self.with_reads(&reads, p))
            }
        }
    }

    /// The channel fields carrying value `v` of type `t`: its components
    /// when `t` is a product (see [`Ty::field_sets`]).
    fn fields_of(&mut self, t: &Ty, v: Expr) -> Vec<Expr> {
        match t {
            Ty::Product(ts) => self.ex.components(ts.len(), v),
            _ => vec![v],
        }
    }

    // ------------------------------------------------------ behaviour

    fn enter(&self, n: usize) -> Expr {
        let node = &self.nodes[n];
        match node.kind {
            NodeKind::State => name(format!("Enter__{}", node.tag)),
            NodeKind::Junction | NodeKind::Initial => name(format!("Junction__{}", node.tag)),
            NodeKind::Final if node.parent.is_some() => name(format!("Rest__{}", node.tag)),
            NodeKind::Final if self.robosim => name("Ending__"),
            NodeKind::Final => Expr::Skip,
        }
    }

    fn action_of(&mut self, n: &SyntaxNode, kind: robosim_syntax::SyntaxKind) -> Option<Option<Expr>> {
        match child(n, kind) {
            Some(a) => match stmt_child(&a) {
                Some(s) => Some(Some(self.stmt(&s)?)),
                None => Some(None),
            },
            None => Some(None),
        }
    }

    /// The process taking transition `t` from the leaf `leaf` (or from
    /// its source when `leaf` is `None`, for junctions and hovers).
    fn transition(&mut self, t: usize, leaf: Option<usize>) -> Option<Expr> {
        let syn = self.trans[t].syn.clone();
        let mut rest = Vec::new();
        // The activities of the states it leaves stop at once, innermost
        // first (RoboChart: the trigger interrupts the during actions).
        let mut cur = Some(leaf.unwrap_or(self.trans[t].source));
        while let Some(c) = cur {
            if self.active.get(c).copied().unwrap_or(false) {
                let sid = format!("SID_{}", self.nodes[c].tag);
                rest.push(prefix("deactivate__", vec![Field::Dot(name(sid))], Expr::Skip));
            }
            if c == self.trans[t].source {
                break;
            }
            cur = self.nodes[c].parent;
        }
        // Exit actions from the leaf up to the source.
        if let Some(l) = leaf {
            let mut cur = Some(l);
            while let Some(c) = cur {
                if self.nodes[c].kind == NodeKind::State {
                    let s = self.nodes[c].syn.clone();
                    if let Some(a) = self.action_of(&s, EXIT_ACTION)? {
                        rest.push(a);
                    }
                }
                if c == self.trans[t].source {
                    break;
                }
                cur = self.nodes[c].parent;
            }
        }
        for c in children(&syn, CLOCK_RESET) {
            let n = ref_of(&c).unwrap_or_default();
            match self.names.get(&n) {
                Some(Nm::Clock(k)) => rest.push(prefix(format!("reset_{}", self.clocks[*k].csp), vec![], Expr::Skip)),
                _ => {
                    self.problem(c.text_range(), format!("`{n}` is not a clock"));
                    return None;
                }
            }
        }
        if let Some(a) = self.action_of(&syn, TRANSITION_ACTION)? {
            rest.push(a);
        }
        rest.push(self.enter(self.trans[t].target));
        let then = fold_seq(rest);
        let tid = self.trans[t].tid.clone();
        if let Some(d) = child(&syn, DEADLINE) {
            // Its timer is part of the source's activity.
            if self.nodes[self.trans[t].source].kind != NodeKind::State {
                self.problem(
                    d.text_range(),
                    "deadlines on transitions from junctions are not supported by the export yet \
                     (a junction is left at once or waits for a guard)",
                );
                return None;
            }
        }
        if let Some(p) = child(&syn, PROBABILITY) {
            self.problem(p.text_range(), "probabilistic transitions have no meaning in the tock-CSP semantics");
            return None;
        }
        if let Some(x) = child(&syn, EXEC_TRIGGER) {
            if !self.robosim {
                self.problem(x.text_range(), "`exec` belongs to RoboSim machines");
                return None;
            }
            self.record_term(x.text_range(), TermKind::Exec, || {
                prefix("endexec", vec![Field::Dot(name(tid.clone()))], prefix("startexec", vec![], Expr::Skip))
            });
            return Some(prefix("endexec", vec![Field::Dot(name(tid))], fold_seq(vec![name("StartExec__"), then])));
        }
        match child(&syn, TRIGGER).and_then(|tr| child(&tr, COMMUNICATION)) {
            Some(comm) => self.communication(&comm, Some((&tid, then))),
            None => Some(prefix("internal__", vec![Field::Dot(name(tid))], then)),
        }
    }

    fn generate(&mut self, module: &str) -> Vec<Decl> {
        // Guards: the memory enables each transition's trigger.
        for t in 0..self.trans.len() {
            if let Some(g) = self.guard_of(t) {
                self.gates.push(g);
            }
        }
        // States with an activity: a composite state's during action, the
        // deadlines of the transitions from a state.
        self.active = (0..self.nodes.len())
            .map(|n| {
                let node = &self.nodes[n];
                node.kind == NodeKind::State
                    && ((self.nodes.iter().any(|c| c.parent == Some(n)) && child(&node.syn, DURING_ACTION).is_some())
                        || self.trans.iter().any(|t| t.source == n && child(&t.syn, DEADLINE).is_some()))
            })
            .collect();
        // States, junctions and finals.
        for n in 0..self.nodes.len() {
            self.node_process(n);
        }
        // Hover terms of the transitions, with triggers as the machine's events.
        if self.record {
            for t in 0..self.trans.len() {
                self.display = true;
                let saved_defs = self.defs.len();
                let saved_counter = self.counter;
                if let Some(e) = self.transition(t, None) {
                    let syn = self.trans[t].syn.clone();
                    // On its name, and on its trigger.
                    let mut ranges = vec![util::name_range(&syn)];
                    ranges.extend(child(&syn, TRIGGER).map(|t| t.text_range()));
                    let guard =
                        self.gates.iter().find(|g| g.t == t).map(|g| g.cond.clone()).filter(|c| *c != Expr::Bool(true));
                    for range in ranges {
                        self.terms.push(Term {
                            range,
                            kind: TermKind::Transition,
                            expr: e.clone(),
                            guard: guard.clone(),
                        });
                    }
                }
                self.defs.truncate(saved_defs);
                self.counter = saved_counter;
                self.display = false;
            }
        }
        if !self.problems.is_empty() {
            return Vec::new();
        }
        self.assemble(module)
    }

    /// Translates the guard of transition `t` (evaluated by the memory).
    fn guard_of(&mut self, t: usize) -> Option<GateI> {
        let syn = self.trans[t].syn.clone();
        self.binds.clear();
        let cond = match child(&syn, CONDITION) {
            Some(c) if c.children().any(|n| n.kind() == ELSE_CONDITION) => self.else_condition(t)?,
            Some(c) => match expr_child(&c) {
                Some(e) => self.expr(&e, ECtx::Memory, None)?.e,
                None => Expr::Bool(true),
            },
            None => Expr::Bool(true),
        };
        let trigger = if child(&syn, EXEC_TRIGGER).is_some() {
            GateTrigger::Exec
        } else {
            match child(&syn, TRIGGER).and_then(|tr| child(&tr, COMMUNICATION)) {
                Some(comm) => {
                    let ev = ref_of(&comm).unwrap_or_default();
                    let Some(Nm::Event(i)) = self.names.get(&ev).cloned() else {
                        let what = self.what();
                        self.problem(
                            comm.text_range(),
                            format!("`{ev}` is not an event of the {what} (declared or used through an interface)"),
                        );
                        return None;
                    };
                    GateTrigger::Event(i)
                }
                None => GateTrigger::Internal,
            }
        };
        Some(GateI { t, cond, binds: std::mem::take(&mut self.binds), trigger })
    }

    /// `condition else` of transition `t`: none of the guards of the other
    /// transitions from its source holds (an unguarded one always holds).
    fn else_condition(&mut self, t: usize) -> Option<Expr> {
        let saved = std::mem::take(&mut self.binds);
        let mut others = Vec::new();
        for u in 0..self.trans.len() {
            if u == t || self.trans[u].source != self.trans[t].source {
                continue;
            }
            let syn = self.trans[u].syn.clone();
            match child(&syn, CONDITION) {
                Some(c) if c.children().any(|n| n.kind() == ELSE_CONDITION) => {}
                Some(c) => match expr_child(&c) {
                    Some(e) => others.push(self.expr(&e, ECtx::Memory, None)?.e),
                    None => others.push(Expr::Bool(true)),
                },
                None => others.push(Expr::Bool(true)),
            }
        }
        // Inputs the other guards read (`$e?x`) bind nothing here.
        self.binds = saved;
        if others.contains(&Expr::Bool(true)) {
            return Some(Expr::Bool(false));
        }
        Some(match others.into_iter().reduce(|a, b| bin(BinOp::Or, a, b)) {
            Some(e) => Expr::Not(Box::new(e)),
            None => Expr::Bool(true),
        })
    }

    /// The memory's alternative enabling transition `g.t` when its guard holds.
    fn gate(&self, g: &GateI) -> Expr {
        let tid = self.trans[g.t].tid.clone();
        let mut args: Vec<Expr> = self.memory_params().into_iter().map(name).collect();
        for &(v, i) in &g.binds {
            args[v] = name(format!("{}_value", self.events[i].csp));
        }
        let next = self.memory_call(args);
        let ev = match g.trigger {
            GateTrigger::Exec => prefix("endexec", vec![Field::Dot(name(tid))], next),
            GateTrigger::Internal => prefix("internal__", vec![Field::Dot(name(tid))], next),
            GateTrigger::Event(i) => {
                let chan = format!("{}__", self.events[i].csp);
                Expr::Repl(
                    crate::cspm::ReplOp::ExtChoice,
                    vec![("ev__".into(), Expr::Events(vec![dot(vec![name(chan), name(tid)])]))],
                    Box::new(prefix("ev__", vec![], next)),
                )
            }
        };
        guard(g.cond.clone(), ev)
    }

    fn memory_params(&self) -> Vec<String> {
        let mut p: Vec<String> = self.vars.iter().filter(|v| !v.shared).map(|v| v.csp.clone()).collect();
        p.extend(self.clocks.iter().map(|c| c.csp.clone()));
        for e in self.events.iter().filter(|e| self.is_input(e)) {
            p.push(e.csp.clone());
            if e.ty.is_some() {
                p.push(format!("{}_value", e.csp));
            }
        }
        p
    }

    fn is_input(&self, e: &EvI) -> bool {
        self.robosim && (e.io == Some(robosim_hir::defs::Io::Input) || (e.io.is_none() && e.received))
    }

    fn memory_call(&self, args: Vec<Expr>) -> Expr {
        if args.is_empty() {
            name("Memory__")
        } else {
            call("Memory__", args)
        }
    }

    fn node_process(&mut self, n: usize) {
        let node_syn = self.nodes[n].syn.clone();
        let tag = self.nodes[n].tag.clone();
        match self.nodes[n].kind {
            NodeKind::State => {
                let mut parts = vec![];
                if let Some(c) = self.clocks.iter().find(|c| c.state == Some(n)) {
                    parts.push(prefix(format!("reset_{}", c.csp), vec![], Expr::Skip));
                }
                let Some(entry) = self.action_of(&node_syn, ENTRY_ACTION) else { return };
                parts.extend(entry);
                let composite = self.nodes.iter().any(|c| c.parent == Some(n));
                if self.active[n] {
                    if !self.activity(n, composite) {
                        return;
                    }
                    parts.push(prefix("activate__", vec![Field::Dot(name(format!("SID_{tag}")))], Expr::Skip));
                }
                if composite {
                    let Some(init) = self.nodes.iter().position(|c| c.parent == Some(n) && c.kind == NodeKind::Initial)
                    else {
                        self.problem(util::name_range(&node_syn), "a composite state without an initial junction");
                        return;
                    };
                    parts.push(self.enter(init));
                } else {
                    parts.push(name(format!("Rest__{tag}")));
                    self.rest(n);
                }
                let body = prefix("entered__", vec![Field::Dot(name(format!("SID_{tag}")))], fold_seq(parts));
                self.defs.push(Decl::Def(format!("Enter__{tag}"), vec![], body));
            }
            NodeKind::Final if self.nodes[n].parent.is_some() => self.rest(n),
            NodeKind::Final => {}
            NodeKind::Junction | NodeKind::Initial => {
                let mut alts = Vec::new();
                for t in 0..self.trans.len() {
                    if self.trans[t].source == n {
                        if let Some(p) = self.transition(t, None) {
                            alts.push(p);
                        }
                    }
                }
                let me = format!("Junction__{tag}");
                // RoboChart: time passes until a guard holds; RoboSim: the
                // cycle forbids it, so a dead end is stuck.
                alts.push(prefix("tock", vec![], name(me.clone())));
                self.defs.push(Decl::Def(me, vec![], ext(alts)));
            }
        }
    }

    /// `Activity__S`: what state `S` does alongside its substates and
    /// transitions, from the end of its entry action until a transition
    /// leaves it (`activate__.SID_S` … `deactivate__.SID_S`): the during
    /// action of a composite state (RoboChart: it runs in parallel with the
    /// substates and is interrupted by the exit), and one timer per
    /// transition from `S` with a deadline `<{d}`, which refuses time after
    /// `d` time units (the transition must be taken by then). Returns false
    /// when something is not exported.
    fn activity(&mut self, n: usize, composite: bool) -> bool {
        let syn = self.nodes[n].syn.clone();
        let tag = self.nodes[n].tag.clone();
        let mut parts = Vec::new();
        if self.robosim {
            // RoboSim has no transition deadlines: only a composite's during action gets here.
            self.problem(
                util::name_range(&syn),
                "during actions of composite RoboSim states are not exported: how they share the \
                 cycle with the substates (`exec`) is not pinned down",
            );
            return false;
        }
        if composite && child(&syn, DURING_ACTION).is_some() {
            match self.action_of(&syn, DURING_ACTION) {
                Some(Some(d)) => parts.push(seq(vec![d, name("TStop")])),
                Some(None) => {}
                None => return false,
            }
        }
        for t in 0..self.trans.len() {
            if self.trans[t].source != n {
                continue;
            }
            let Some(limit) = child(&self.trans[t].syn, DEADLINE).and_then(|d| expr_child(&d)) else { continue };
            let Some((d, reads)) = self.bexpr(&limit, None) else { return false };
            let p = self.with_reads(&reads, call("Timer__", vec![d]));
            parts.push(p);
            if !self.defs.iter().any(|x| matches!(x, Decl::Def(f, _, _) if f == "Timer__")) {
                // Time passes d times, then no more.
                let body = guard(
                    bin(BinOp::Gt, name("d__"), Expr::Int(0)),
                    prefix("tock", vec![], call("Timer__", vec![bin(BinOp::Sub, name("d__"), Expr::Int(1))])),
                );
                self.defs.push(Decl::Def("Timer__".into(), vec!["d__".into()], body));
            }
        }
        let run = parts
            .into_iter()
            .rev()
            .reduce(|acc, p| par(p, Expr::Set(vec![name("tock")]), acc))
            .unwrap_or_else(|| name("TStop"));
        let me = format!("Activity__{tag}");
        let sid = Field::Dot(name(format!("SID_{tag}")));
        let body = ext(vec![
            prefix(
                "activate__",
                vec![sid.clone()],
                nary(ProcOp::Interrupt, vec![run, prefix("deactivate__", vec![sid], name(me.clone()))]),
            ),
            prefix("tock", vec![], name(me.clone())),
            prefix("end__", vec![], Expr::Skip),
        ]);
        self.defs.push(Decl::Def(me.clone(), vec![], body));
        self.activities.push(me);
        true
    }

    /// `Rest__L`: the leaf `L` offers its transitions and those of its
    /// ancestors; time passes meanwhile; its during action runs until a
    /// transition interrupts it.
    fn rest(&mut self, leaf: usize) {
        let mut alts = Vec::new();
        let mut cur = Some(leaf);
        while let Some(c) = cur {
            for t in 0..self.trans.len() {
                if self.trans[t].source == c {
                    if let Some(p) = self.transition(t, Some(leaf)) {
                        alts.push(p);
                    }
                }
            }
            cur = self.nodes[c].parent;
        }
        let syn = self.nodes[leaf].syn.clone();
        let me = format!("Rest__{}", self.nodes[leaf].tag);
        let during = if self.nodes[leaf].kind == NodeKind::State {
            match self.action_of(&syn, DURING_ACTION) {
                Some(d) => d,
                None => return,
            }
        } else {
            None
        };
        let body = match during {
            Some(d) => nary(ProcOp::Interrupt, vec![seq(vec![d, name("TStop")]), ext(alts)]),
            None => {
                alts.push(prefix("tock", vec![], name(me.clone())));
                ext(alts)
            }
        };
        self.defs.push(Decl::Def(me, vec![], body));
    }

    // ------------------------------------------------------ assembly

    fn memory(&mut self) -> Decl {
        let params = self.memory_params();
        let mut alts = Vec::new();
        let same: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
        let with = |i: usize, v: Expr| {
            let mut a = same.clone();
            a[i] = v;
            a
        };
        for (i, v) in self.vars.iter().filter(|v| !v.shared).enumerate() {
            alts.push(prefix(
                format!("get_{}", v.csp),
                vec![Field::Out(name(v.csp.clone()))],
                self.memory_call(same.clone()),
            ));
            alts.push(prefix(
                format!("set_{}", v.csp),
                vec![Field::In("v__".into())],
                self.memory_call(with(i, name("v__"))),
            ));
        }
        let nv = self.vars.iter().filter(|v| !v.shared).count();
        let mut ticked = same.clone();
        for (k, c) in self.clocks.iter().enumerate() {
            let i = nv + k;
            if c.read {
                alts.push(prefix(
                    format!("get_{}", c.csp),
                    vec![Field::Out(name(c.csp.clone()))],
                    self.memory_call(same.clone()),
                ));
            }
            alts.push(prefix(format!("reset_{}", c.csp), vec![], self.memory_call(with(i, Expr::Int(0)))));
            ticked[i] = call("ClockTick", vec![name(c.csp.clone()), name(format!("ClockMax__{}", c.csp))]);
        }
        alts.push(prefix("tock", vec![], self.memory_call(ticked)));
        // RoboSim: the cycle's reads update the inputs (Rule 5).
        let mut pos = nv + self.clocks.len();
        for e in self.events.iter().filter(|e| self.is_input(e)) {
            let ctor = self.ex.in_reg(&e.name);
            let mut fields = vec![Field::Dot(name(ctor)), Field::In("b__".into())];
            let mut args = same.clone();
            args[pos] = name("b__");
            if let Some(t) = &e.ty {
                let (f, v) = t.input_fields("x__");
                fields.extend(f);
                args[pos + 1] = v;
                pos += 1;
            }
            pos += 1;
            alts.push(prefix("registerRead", fields, self.memory_call(args)));
        }
        for g in &self.gates {
            alts.push(self.gate(g));
        }
        if self.robosim {
            if self.uses_exec_stmt {
                alts.push(prefix("endexec", vec![Field::Dot(name("TID_exec"))], self.memory_call(same.clone())));
            }
            alts.push(prefix("endexec", vec![Field::Dot(name("TID_final"))], self.memory_call(same.clone())));
            alts.push(prefix("terminate", vec![], Expr::Skip));
        } else {
            alts.push(prefix("end__", vec![], Expr::Skip));
        }
        Decl::Def("Memory__".into(), params, ext(alts))
    }

    fn assemble(&mut self, module: &str) -> Vec<Decl> {
        let mut private = Vec::new();
        let mut exports = Vec::new();
        // Identifiers.
        let mut tids: Vec<(String, Vec<Expr>)> = self.trans.iter().map(|t| (t.tid.clone(), vec![])).collect();
        if self.robosim {
            if self.uses_exec_stmt {
                tids.push(("TID_exec".into(), vec![]));
            }
            tids.push(("TID_final".into(), vec![]));
        }
        if tids.is_empty() {
            tids.push(("TID_none".into(), vec![]));
        }
        let mut sids: Vec<(String, Vec<Expr>)> = self
            .nodes
            .iter()
            .filter(|n| n.kind == NodeKind::State)
            .map(|n| (format!("SID_{}", n.tag), vec![]))
            .collect();
        if sids.is_empty() {
            sids.push(("SID_none".into(), vec![]));
        }
        private.push(Decl::Comment("Transition identifiers.".into()));
        private.push(Decl::Datatype("TIDS".into(), tids));
        private.push(Decl::Channel(vec!["internal__".into()], vec![name("TIDS")]));
        let mut hidden = vec![name("internal__")];
        let mut sync = vec![name("internal__"), name("tock")];
        for e in &self.events {
            if e.trig {
                let mut f = vec![name("TIDS"), name("InOut")];
                f.extend(e.ty.iter().flat_map(|t| t.field_sets()));
                private.push(Decl::Channel(vec![format!("{}__", e.csp)], f));
                sync.push(name(format!("{}__", e.csp)));
            }
        }
        if !self.vars.is_empty() || !self.clocks.is_empty() {
            private.push(Decl::Comment("Memory: variables and clocks.".into()));
        }
        for v in self.vars.iter().filter(|v| !v.shared) {
            private.push(Decl::Channel(vec![format!("get_{}", v.csp), format!("set_{}", v.csp)], vec![v.ty.set()]));
            for c in [format!("get_{}", v.csp), format!("set_{}", v.csp)] {
                hidden.push(name(c.clone()));
                sync.push(name(c));
            }
        }
        for c in &self.clocks {
            private.push(Decl::Channel(vec![format!("reset_{}", c.csp)], vec![]));
            hidden.push(name(format!("reset_{}", c.csp)));
            sync.push(name(format!("reset_{}", c.csp)));
            if c.read {
                private.push(Decl::Channel(vec![format!("get_{}", c.csp)], vec![name("core_clock_type")]));
                hidden.push(name(format!("get_{}", c.csp)));
                sync.push(name(format!("get_{}", c.csp)));
            }
        }
        if self.robosim {
            private.push(Decl::Comment("Cycle events (Rules 4 and 6).".into()));
            private.push(Decl::Channel(vec!["startexec".into()], vec![]));
            private.push(Decl::Channel(vec!["endexec".into()], vec![name("TIDS")]));
            if self.profile == Profile::Paper2019 && !self.output_regs().is_empty() {
                private.push(Decl::Comment("The outputs buffer (Rule 12).".into()));
                private.push(Decl::Channel(vec!["stmout".into()], vec![name("OutputRegister")]));
                private.push(Decl::Datatype(
                    "BufOut__".into(),
                    vec![("noOut__".into(), vec![]), ("out__".into(), vec![name("OutputRegister")])],
                ));
                private.push(Decl::Channel(vec!["cyclein".into()], vec![name("BufOut__")]));
            }
        } else {
            private.push(Decl::Channel(vec!["end__".into()], vec![]));
            hidden.push(name("end__"));
            sync.push(name("end__"));
        }
        if !self.activities.is_empty() {
            private.push(Decl::Comment(
                "Start and end of the activities of states (during actions of composite states, deadlines\n\
                 of transitions)."
                    .into(),
            ));
            private.push(Decl::Channel(vec!["activate__".into(), "deactivate__".into()], vec![name("SIDS")]));
            hidden.extend([name("activate__"), name("deactivate__")]);
        }
        // Exported interface.
        exports.push(Decl::Comment("State identifiers; `entered__` marks the entry into a state.".into()));
        exports.push(Decl::Datatype("SIDS".into(), sids));
        exports.push(Decl::Channel(vec!["entered__".into()], vec![name("SIDS")]));
        let shared: Vec<&VarI> = self.vars.iter().filter(|v| v.shared).collect();
        if !shared.is_empty() {
            exports.push(Decl::Comment("The caller's variables, in the caller's memory.".into()));
        }
        for v in shared {
            exports.push(Decl::Channel(vec![format!("get_{}", v.csp), format!("set_{}", v.csp)], vec![v.ty.set()]));
        }
        if !self.robosim {
            for e in &self.events {
                let mut f = vec![name("InOut")];
                f.extend(e.ty.iter().flat_map(|t| t.field_sets()));
                exports.push(Decl::Channel(vec![e.csp.clone()], f));
            }
            for o in self.ops.iter().filter(|o| !o.defined) {
                let f: Vec<Expr> = o.params.iter().map(|t| t.set()).collect();
                exports.push(Decl::Channel(vec![format!("{}Call", ident(&o.name))], f));
                if self.profile == Profile::Paper2019 {
                    exports.push(Decl::Channel(vec![format!("{}Ret", ident(&o.name))], vec![]));
                }
            }
        } else {
            // Registers of the machine.
            let inputs: Vec<(String, Vec<Expr>)> = self
                .events
                .iter()
                .filter(|e| self.is_input(e))
                .map(|e| (self.ex.in_reg(&e.name), e.ty.iter().flat_map(|t| t.field_sets()).collect()))
                .collect();
            for (c, v) in inputs {
                if let Err(m) = self.ex.register(true, &c, &v) {
                    self.problem(util::name_range(&self.node), m);
                }
            }
            for (c, v) in self.output_regs() {
                if let Err(m) = self.ex.register(false, &c, &v) {
                    self.problem(util::name_range(&self.node), m);
                }
            }
        }

        // The let of P__.
        let mut lets = Vec::new();
        for c in &self.clocks {
            let mut bound = Expr::Int(0);
            for b in &c.bounds {
                bound = call("Max__", vec![bound, b.clone()]);
            }
            let bound = if c.unbounded || c.read {
                name("core_clock_max")
            } else {
                call("Min__", vec![bound, name("core_clock_max")])
            };
            lets.push(Decl::Def(format!("ClockMax__{}", c.csp), vec![], bin(BinOp::Add, bound, Expr::Int(1))));
        }
        let start_node = self.nodes.iter().position(|n| n.parent.is_none() && n.kind == NodeKind::Initial);
        let Some(start_node) = start_node else {
            self.problem(util::name_range(&self.node), "the machine has no initial junction");
            return Vec::new();
        };
        let start = self.enter(start_node);
        if self.robosim {
            lets.push(Decl::Def(
                "StartExec__".into(),
                vec![],
                ext(vec![prefix("startexec", vec![], Expr::Skip), prefix("tock", vec![], name("StartExec__"))]),
            ));
            lets.push(Decl::Def("Behaviour__".into(), vec![], seq(vec![name("StartExec__"), start.clone()])));
        } else {
            lets.push(Decl::Def("Behaviour__".into(), vec![], start.clone()));
        }
        lets.append(&mut self.defs);
        lets.extend(std::mem::take(&mut self.op_calls).into_iter().map(|(_, d)| d));
        if self.robosim {
            // Rule 13: a finished machine keeps ending its cycles until all agree to terminate.
            lets.push(Decl::Def(
                "Ending__".into(),
                vec![],
                prefix("endexec", vec![Field::Dot(name("TID_final"))], name("EndWait__")),
            ));
            lets.push(Decl::Def(
                "EndWait__".into(),
                vec![],
                ext(vec![
                    prefix("startexec", vec![], name("Ending__")),
                    prefix("terminate", vec![], Expr::Skip),
                    prefix("tock", vec![], name("EndWait__")),
                ]),
            ));
        }
        lets.push(self.memory());
        let init: Vec<Expr> = self
            .vars
            .iter()
            .filter(|v| !v.shared)
            .map(|v| v.init.clone())
            .chain(self.clocks.iter().map(|_| Expr::Int(0)))
            .chain(
                self.events
                    .iter()
                    .filter(|e| self.is_input(e))
                    .flat_map(|e| {
                        let mut v = vec![Expr::Bool(false)];
                        if let Some(t) = &e.ty {
                            v.push(t.default_value());
                        }
                        v
                    })
                    .collect::<Vec<_>>(),
            )
            .collect();
        let memory = self.memory_call(init);

        let mut params = vec!["id__".to_string()];
        if self.robosim {
            params.push("cycle".into());
        }
        params.extend(self.op_params.iter().cloned());
        params.extend(self.consts.iter().map(|c| c.local.clone()));
        let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();

        let body = if self.robosim {
            let (cycle_defs, has_in, has_out) = self.cycle();
            lets.extend(cycle_defs);
            let mut inner_sync = vec![name("endexec"), name("tock"), name("terminate")];
            if has_in {
                inner_sync.push(name("registerRead"));
            }
            let inner = par(memory, Expr::Events(inner_sync), name("Cycle__"));
            let mut outer_sync = sync.clone();
            outer_sync.extend([name("endexec"), name("startexec"), name("terminate")]);
            hidden.extend([name("endexec"), name("startexec")]);
            let inner = match (self.profile, has_out) {
                (Profile::RoboTool3, true) => {
                    outer_sync.push(name("registerWrite"));
                    inner
                }
                // Rule 3: the outputs go through the buffer to the cycle.
                (Profile::Paper2019, true) => {
                    outer_sync.push(name("stmout"));
                    hidden.extend([name("stmout"), name("cyclein")]);
                    par(name("Buffer__"), Expr::Events(vec![name("cyclein")]), inner)
                }
                (_, false) => inner,
            };
            let comp = par(name("Behaviour__"), Expr::Events(outer_sync), inner);
            call("TimedPriority", vec![hide(comp, Expr::Events(hidden))])
        } else {
            let mut beh = seq(vec![name("Behaviour__"), prefix("end__", vec![], Expr::Skip)]);
            if !self.activities.is_empty() {
                let acts = self
                    .activities
                    .iter()
                    .rev()
                    .map(|a| name(a.clone()))
                    .reduce(|acc, a| par(a, Expr::Events(vec![name("tock"), name("end__")]), acc))
                    .expect("an activity");
                let with = Expr::Events(vec![name("activate__"), name("deactivate__"), name("tock"), name("end__")]);
                beh = par(beh, with, acts);
            }
            let comp = hide(par(beh, Expr::Events(sync), memory), Expr::Events(hidden));
            // Tagged triggers become the machine's events.
            let mut comp = comp;
            for e in self.events.iter().filter(|e| e.trig) {
                let mut from = vec![name(format!("{}__", e.csp)), name("t__"), name("d__")];
                let mut to = vec![name(e.csp.clone()), name("d__")];
                let mut gens = vec![("t__".to_string(), name("TIDS")), ("d__".to_string(), name("InOut"))];
                let sets: Vec<Expr> = e.ty.iter().flat_map(|t| t.field_sets()).collect();
                for (k, set) in sets.iter().cloned().enumerate() {
                    let v = if sets.len() == 1 { "v__".to_string() } else { format!("v{k}__") };
                    from.push(name(v.clone()));
                    to.push(name(v.clone()));
                    gens.push((v, set));
                }
                comp = Expr::Rename(Box::new(comp), vec![(dot(from), dot(to))], gens);
            }
            call("TimedPriority", vec![comp])
        };
        let p_def = Decl::Def("P__".into(), params.clone(), Expr::Let(lets, Box::new(body)));
        let entered = Expr::Events(vec![name("entered__")]);
        let d_body = if self.robosim {
            call(
                "TimedPriority",
                vec![hide(
                    Expr::Exception(
                        Box::new(hide(call("P__", args.clone()), entered.clone())),
                        Box::new(Expr::Set(vec![name("terminate")])),
                        Box::new(Expr::Skip),
                    ),
                    Expr::Set(vec![name("terminate")]),
                )],
            )
        } else {
            call("TimedPriority", vec![hide(call("P__", args.clone()), entered)])
        };
        let vs_body = if self.robosim {
            call(
                "TimedPriority",
                vec![hide(
                    Expr::Exception(
                        Box::new(call("P__", args.clone())),
                        Box::new(Expr::Set(vec![name("terminate")])),
                        Box::new(Expr::Skip),
                    ),
                    Expr::Set(vec![name("terminate")]),
                )],
            )
        } else {
            call("P__", args.clone())
        };
        let mut doc = vec![Decl::Comment(format!(
            "{} (parameters: {}).",
            if self.robosim {
                "P__: the machine with `terminate` visible (for composition); D__: its semantics;\n\
                 VS__: with `entered__` visible (reachability); O__: D__ compressed"
            } else if self.is_operation {
                "D__: the operation's semantics, terminating at its final state (callers rename its\n\
                 channels to theirs); VS__: with `entered__` visible; O__: D__ compressed"
            } else {
                "D__: the machine's semantics; VS__: with `entered__` visible (reachability);\n\
                 O__: D__ compressed"
            },
            params.join(", ")
        ))];
        if self.robosim {
            doc.push(p_def);
        } else {
            private.push(p_def);
        }
        doc.push(Decl::Def("D__".into(), params.clone(), d_body));
        doc.push(Decl::Def("VS__".into(), params.clone(), vs_body));
        doc.push(Decl::Def("O__".into(), params.clone(), call("sbisim", vec![call("D__", args)])));
        exports.extend(doc);
        let kind = if self.robosim { "RoboSim" } else { "RoboChart" };
        let mut path = self.ex.path_of_node(self.file, &self.node);
        let what = if self.is_operation {
            path.push(name_of(&self.node));
            "operation"
        } else {
            "state machine"
        };
        vec![
            Decl::Comment(format!("{kind} {what} {}", path.join("::"))),
            Decl::Module(module.to_string(), private, exports),
            Decl::Blank,
        ]
    }

    fn output_regs(&self) -> Vec<(String, Vec<Expr>)> {
        let mut out = Vec::new();
        for e in self.events.iter().filter(|e| !self.is_input(e)) {
            if e.io == Some(robosim_hir::defs::Io::Output) || e.io.is_none() {
                out.push((self.ex.out_reg(&e.name), e.ty.iter().flat_map(|t| t.field_sets()).collect()));
            }
        }
        for o in &self.ops {
            out.push((self.ex.out_reg(&o.name), o.params.iter().map(|t| t.set()).collect()));
        }
        out
    }

    /// Rule 4 as the paper states it (paper2019): read every input
    /// register, `startexec`, `endexec`, then write the buffered outputs in
    /// order (`registerWrite.o.true.args`) and the others as absent
    /// (`registerWrite.o.false.args`, any arguments), then terminate or
    /// let `cycle` time units pass; the buffer of Rule 12.
    fn cycle_paper(&mut self, reads: Expr, has_in: bool) -> (Vec<Decl>, bool, bool) {
        let outs = self.output_regs();
        let mut d = Vec::new();
        let end = ext(vec![
            prefix("terminate", vec![], Expr::Skip),
            seq(vec![call("Wait", vec![name("cycle")]), name("Cycle__")]),
        ]);
        if outs.is_empty() {
            d.push(Decl::Def(
                "Cycle__".into(),
                vec![],
                seq(vec![reads, prefix("startexec", vec![], prefix("endexec", vec![Field::In("t__".into())], end))]),
            ));
            return (d, has_in, false);
        }
        let flags: Vec<String> = outs.iter().map(|(c, _)| format!("w_{c}")).collect();
        let all = |v: bool| -> Vec<Expr> { flags.iter().map(|_| Expr::Bool(v)).collect() };
        d.push(Decl::Def(
            "Cycle__".into(),
            vec![],
            seq(vec![
                reads,
                prefix(
                    "startexec",
                    vec![],
                    prefix("endexec", vec![Field::In("t__".into())], seq(vec![call("Collect__", all(true)), end])),
                ),
            ]),
        ));
        // CollectOutputs: the buffered outputs in order, then NoOther.
        let mut alts = vec![prefix(
            "cyclein",
            vec![Field::Dot(name("noOut__"))],
            call("NoOther__", flags.iter().map(|f| name(f.clone())).collect()),
        )];
        let mut others = Vec::new();
        for (k, (c, vals)) in outs.iter().enumerate() {
            let vars: Vec<String> = (0..vals.len()).map(|i| format!("x{i}__")).collect();
            let mut next: Vec<Expr> = flags.iter().map(|f| name(f.clone())).collect();
            next[k] = Expr::Bool(false);
            let mut inf = vec![Field::Dot(name("out__")), Field::Dot(name(c.clone())), Field::In("b__".into())];
            inf.extend(vars.iter().map(|v| Field::In(v.clone())));
            let mut outf = vec![Field::Dot(name(c.clone())), Field::Dot(name("b__"))];
            outf.extend(vars.iter().map(|v| Field::Dot(name(v.clone()))));
            alts.push(guard(
                name(flags[k].clone()),
                prefix("cyclein", inf, prefix("registerWrite", outf, call("Collect__", next))),
            ));
            let mut falsef = vec![Field::Dot(name(c.clone())), Field::Dot(Expr::Bool(false))];
            falsef.extend(vars.iter().map(|v| Field::In(v.clone())));
            others.push(Expr::If(
                Box::new(name(flags[k].clone())),
                Box::new(prefix("registerWrite", falsef, Expr::Skip)),
                Box::new(Expr::Skip),
            ));
        }
        d.push(Decl::Def("Collect__".into(), flags.clone(), ext(alts)));
        d.push(Decl::Def("NoOther__".into(), flags.clone(), nary(ProcOp::Interleave, others)));
        // Rule 12: the buffer, of capacity the number of outputs.
        let n = outs.len() as i64;
        d.push(Decl::Def(
            "Buffer__".into(),
            vec![],
            ext(vec![
                prefix(
                    "stmout",
                    vec![Field::In("o__".into())],
                    call("BufferF__", vec![Expr::SeqLit(vec![name("o__")])]),
                ),
                prefix("cyclein", vec![Field::Dot(name("noOut__"))], name("Buffer__")),
            ]),
        ));
        d.push(Decl::Def(
            "BufferF__".into(),
            vec!["s__".into()],
            ext(vec![
                guard(
                    bin(BinOp::Lt, call("length", vec![name("s__")]), Expr::Int(n)),
                    prefix(
                        "stmout",
                        vec![Field::In("o__".into())],
                        call("BufferF__", vec![bin(BinOp::Cat, name("s__"), Expr::SeqLit(vec![name("o__")]))]),
                    ),
                ),
                call("Flush__", vec![name("s__")]),
            ]),
        ));
        d.push(Decl::Def(
            "Flush__".into(),
            vec!["s__".into()],
            Expr::If(
                Box::new(call("null", vec![name("s__")])),
                Box::new(name("Buffer__")),
                Box::new(prefix(
                    "cyclein",
                    vec![Field::Dot(name("out__")), Field::Dot(call("head", vec![name("s__")]))],
                    call("Flush__", vec![call("tail", vec![name("s__")])]),
                )),
            ),
        ));
        (d, has_in, true)
    }

    /// Rule 4 (robotool3): read every input register (in any order, no
    /// time passing), `startexec`, accept each output register at most
    /// once until `endexec`, then terminate or let `cycle` time units pass.
    fn cycle(&mut self) -> (Vec<Decl>, bool, bool) {
        let mut d = Vec::new();
        let reads: Vec<Expr> = self
            .events
            .iter()
            .filter(|e| self.is_input(e))
            .map(|e| {
                let mut f = vec![Field::Dot(name(self.ex.in_reg(&e.name))), Field::In("b__".into())];
                if let Some(t) = &e.ty {
                    f.extend(t.input_fields("x__").0);
                }
                prefix("registerRead", f, Expr::Skip)
            })
            .collect();
        let has_in = !reads.is_empty();
        if self.profile == Profile::Paper2019 {
            return self.cycle_paper(nary(ProcOp::Interleave, reads), has_in);
        }
        let outs = self.output_regs();
        let has_out = !outs.is_empty();
        let flags: Vec<String> = outs.iter().map(|(c, _)| format!("w_{c}")).collect();
        let mut alts = Vec::new();
        for (k, (c, _)) in outs.iter().enumerate() {
            let mut next: Vec<Expr> = flags.iter().map(|f| name(f.clone())).collect();
            next[k] = Expr::Bool(false);
            alts.push(guard(
                name(flags[k].clone()),
                Expr::Repl(
                    crate::cspm::ReplOp::ExtChoice,
                    vec![("w__".into(), Expr::Events(vec![dot(vec![name("registerWrite"), name(c.clone())])]))],
                    Box::new(prefix("w__", vec![], call("Collect__", next))),
                ),
            ));
        }
        alts.push(prefix("endexec", vec![Field::In("t__".into())], name("CycleEnd__")));
        d.push(Decl::Def(
            "Cycle__".into(),
            vec![],
            seq(vec![
                nary(ProcOp::Interleave, reads),
                prefix(
                    "startexec",
                    vec![],
                    if flags.is_empty() {
                        call("Collect__", vec![])
                    } else {
                        call("Collect__", flags.iter().map(|_| Expr::Bool(true)).collect())
                    },
                ),
            ]),
        ));
        let collect = ext(alts);
        if flags.is_empty() {
            d.push(Decl::Def("Collect__".into(), vec![], collect));
        } else {
            d.push(Decl::Def("Collect__".into(), flags, collect));
        }
        d.push(Decl::Def(
            "CycleEnd__".into(),
            vec![],
            ext(vec![
                prefix("terminate", vec![], Expr::Skip),
                prefix(
                    "tock",
                    vec![],
                    seq(vec![call("Wait", vec![bin(BinOp::Sub, name("cycle"), Expr::Int(1))]), name("Cycle__")]),
                ),
            ]),
        ));
        // A machine without outputs: `Collect__` is a plain name.
        if outs.is_empty() {
            for x in d.iter_mut() {
                replace_call(x, "Collect__");
            }
        }
        (d, has_in, has_out)
    }

    /// The machine's interface for its users.
    fn interface(&self, module: String, path: Vec<String>) -> Elem {
        let mut chans = Vec::new();
        let mut inputs = Vec::new();
        let mut outputs = Vec::new();
        if self.robosim {
            for e in self.events.iter().filter(|e| self.is_input(e)) {
                inputs.push(Reg {
                    ctor: self.ex.in_reg(&e.name),
                    model: e.name.clone(),
                    values: e.ty.iter().flat_map(|t| t.field_sets()).collect(),
                });
            }
            for e in self.events.iter().filter(|e| !self.is_input(e)) {
                outputs.push(Reg {
                    ctor: self.ex.out_reg(&e.name),
                    model: e.name.clone(),
                    values: e.ty.iter().flat_map(|t| t.field_sets()).collect(),
                });
            }
            for o in &self.ops {
                outputs.push(Reg {
                    ctor: self.ex.out_reg(&o.name),
                    model: o.name.clone(),
                    values: o.params.iter().map(|t| t.set()).collect(),
                });
            }
        } else {
            for e in &self.events {
                let values: Vec<Expr> = e.ty.iter().flat_map(|t| t.field_sets()).collect();
                let mut fields = vec![name("InOut")];
                fields.extend(values.iter().cloned());
                chans.push(Chan {
                    csp: e.csp.clone(),
                    model: e.name.clone(),
                    kind: ChanKind::Event,
                    fields,
                    dir: if e.received { Dir::In } else { Dir::Out },
                    values,
                });
            }
            for o in self.ops.iter().filter(|o| !o.defined) {
                let values: Vec<Expr> = o.params.iter().map(|t| t.set()).collect();
                chans.push(Chan {
                    csp: format!("{}Call", ident(&o.name)),
                    model: o.name.clone(),
                    kind: ChanKind::Call,
                    fields: values.clone(),
                    dir: Dir::Out,
                    values,
                });
                if self.profile == Profile::Paper2019 {
                    chans.push(Chan {
                        csp: format!("{}Ret", ident(&o.name)),
                        model: o.name.clone(),
                        kind: ChanKind::Ret,
                        fields: vec![],
                        dir: Dir::In,
                        values: vec![],
                    });
                }
            }
        }
        Elem {
            kind: ElemKind::Machine,
            robosim: self.robosim,
            module,
            path,
            consts: self.consts.clone(),
            chans,
            inputs,
            outputs,
            period: crate::compose::declared_period(self.ex.db, self.ex.ws, self.file, &self.node).unwrap_or(1),
            required: self.required.clone(),
        }
    }
}

/// An operation of the model exported as its own CSPm module.
#[derive(Debug, Clone)]
pub(crate) struct OperationOut {
    /// Its module's name.
    pub module: String,
    /// The types of its parameters.
    pub params: Vec<Ty>,
    /// Its constants (parameters of its processes, after its parameters).
    pub consts: Vec<(ConstParam, Ty)>,
    /// Its channels: events, platform calls (and returns, paper2019).
    pub chans: Vec<OpChan>,
}

/// What a channel of an exported operation is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OpChanKind {
    Event,
    Call,
    Ret,
    /// `get_x` and `set_x` of a variable of the caller.
    Var,
}

/// A channel of an exported operation.
#[derive(Debug, Clone)]
pub(crate) struct OpChan {
    /// Its name in the operation's module (a variable's name for `Var`).
    pub csp: String,
    /// The model's event, operation or variable name.
    pub model: String,
    pub kind: OpChanKind,
    /// For events: whether the operation receives it.
    pub dir: Dir,
    /// For events and variables: the type carried.
    pub ty: Option<Ty>,
    /// For calls: the parameters' types.
    pub params: Vec<Ty>,
}

/// The CSPm module of the operation at `node` in `file` (RoboChart), made
/// on first use; the reason when it cannot be exported.
pub(crate) fn operation(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode) -> Result<Rc<OperationOut>, String> {
    let key = (file, node.text_range());
    let oname = name_of(node);
    match ex.operations.get(&key) {
        Some(Some(r)) => return r.clone(),
        Some(None) => return Err(format!("the operation `{oname}` calls itself: not supported by the export yet")),
        None => {}
    }
    ex.operations.insert(key, None);
    let mut path = ex.path_of_node(file, node);
    path.push(oname.clone());
    let module = ex.module_name(&path);
    let mut g = Gen::new(ex, file, node, false);
    g.is_operation = true;
    let mut params = Vec::new();
    let mut problems = Vec::new();
    for p in child(node, PARAM_LIST).iter().flat_map(|pl| children(pl, PARAM)) {
        let pn = name_of(&p);
        match g.ex.ty(file, type_child(&p).as_ref()) {
            Ok(t) => {
                let local = g.local(&pn);
                g.names.insert(pn, Nm::Param(local.clone(), t.clone()));
                g.op_params.push(local);
                params.push(t);
            }
            Err(m) => problems.push((file, p.text_range(), format!("parameter `{pn}`: {m}"))),
        }
    }
    let result = if problems.is_empty() { g.run_operation(module.clone(), path.clone()) } else { Err(problems) };
    let r = match result {
        Ok((decls, out)) => {
            ex.emit(file, decls);
            Ok(Rc::new(OperationOut { module, params, ..out }))
        }
        Err(problems) => {
            let mut lines = vec![format!("NOT EXPORTED: operation {}", path.join("::"))];
            for (f, r, m) in &problems {
                lines.push(format!("  {}: {m}", ex.loc(*f, *r)));
                ex.warn(*f, *r, format!("operation {} is not exported: {m}", path.join("::")));
            }
            ex.emit(file, vec![Decl::Comment(lines.join("\n")), Decl::Blank]);
            let why = problems.first().map(|p| p.2.clone()).unwrap_or_default();
            Err(format!("the operation `{oname}` is not exported: {why}"))
        }
    };
    ex.operations.insert(key, Some(r.clone()));
    r
}

/// A function of the model exported as a CSPm function.
#[derive(Debug, Clone)]
pub(crate) struct FunctionOut {
    /// Its CSPm name.
    pub csp: String,
    /// The types of its parameters.
    pub params: Vec<Ty>,
    /// The type of its result.
    pub result: Ty,
}

/// The CSPm function of the model's function at `node` in `file`, made on
/// first use: only explicit definitions (`postcondition result == e`)
/// are exported.
pub(crate) fn function(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode) -> Result<Rc<FunctionOut>, String> {
    let key = (file, node.text_range());
    let fname = name_of(node);
    match ex.functions.get(&key) {
        Some(Some(f)) => return Ok(f.clone()),
        Some(None) => return Err(format!("the function `{fname}` is recursive: not supported by the export yet")),
        None => {}
    }
    ex.functions.insert(key, None);
    let r = function_inner(ex, file, node);
    match &r {
        Ok(f) => {
            ex.functions.insert(key, Some(f.clone()));
        }
        Err(_) => {
            ex.functions.remove(&key);
        }
    }
    r
}

fn function_inner(ex: &mut Exporter<'_>, file: File, node: &SyntaxNode) -> Result<Rc<FunctionOut>, String> {
    let fname = name_of(node);
    let mut params = Vec::new();
    for p in child(node, PARAM_LIST).iter().flat_map(|pl| children(pl, PARAM)) {
        let t = ex.ty(file, type_child(&p).as_ref()).map_err(|m| format!("function `{fname}`: {m}"))?;
        params.push((name_of(&p), t));
    }
    let result = ex.ty(file, type_child(node).as_ref()).map_err(|m| format!("function `{fname}`: {m}"))?;
    // The one postcondition `result == e` (or `result iff e`) defines it.
    let defining: Vec<SyntaxNode> = children(node, POSTCONDITION)
        .filter_map(|pc| expr_child(&pc))
        .filter(|x| {
            x.kind() == BIN_EXPR
                && matches!(ast::binary_operator(x), Some(EQ2 | IFF_KW))
                && ast::operand_exprs(x).first().is_some_and(|l| l.kind() == RESULT_EXPR)
        })
        .collect();
    let [def] = defining.as_slice() else {
        return Err(format!(
            "the function `{fname}` has no explicit definition (`postcondition result == …`): calls of it are not exported"
        ));
    };
    let body = ast::operand_exprs(def)
        .get(1)
        .cloned()
        .ok_or_else(|| format!("function `{fname}`: an incomplete postcondition"))?;
    let mut path = ex.package(file);
    path.push(fname.clone());
    let csp = ex.module_name(&path);
    let mut g = Gen::new(ex, file, node, false);
    let mut names = Vec::new();
    for (n, t) in &params {
        let local = g.local(n);
        g.names.insert(n.clone(), Nm::Param(local.clone(), t.clone()));
        names.push(local);
    }
    let out = g.expr(&body, ECtx::Const, Some(&result));
    let problems = std::mem::take(&mut g.problems);
    let Some(out) = out else {
        let why = problems.first().map(|p| p.2.clone()).unwrap_or_default();
        return Err(format!("function `{fname}` is not exported: {why}"));
    };
    ex.emit(
        file,
        vec![Decl::Comment(format!("function {}", path.join("::"))), Decl::Def(csp.clone(), names, out.e), Decl::Blank],
    );
    Ok(Rc::new(FunctionOut { csp, params: params.into_iter().map(|(_, t)| t).collect(), result }))
}

/// The range of a statement up to its arguments or value (`$move` of
/// `$move(lv, 0)`), where a hover shows the statement's term.
fn head_range(s: &SyntaxNode) -> TextRange {
    let start = s.text_range().start();
    let end = s
        .children()
        .find(|c| c.kind() == ARG_LIST || ast::is_expr_kind(c.kind()))
        .map(|c| c.text_range().start())
        .unwrap_or_else(|| s.text_range().end());
    TextRange::new(start, end.max(start))
}

/// `a -> SKIP ; P` becomes `a -> P`; `SKIP`s disappear.
pub(crate) fn fold_seq(parts: Vec<Expr>) -> Expr {
    let mut parts: Vec<Expr> = parts.into_iter().filter(|p| *p != Expr::Skip).collect();
    if parts.is_empty() {
        return Expr::Skip;
    }
    let mut acc = parts.pop().expect("a part");
    while let Some(p) = parts.pop() {
        acc = match p {
            // (a -> B) ; C = a -> (B ; C), while the result stays shallow:
            // long statement sequences stay flat `;` chains.
            Expr::Prefix(c, f, body) if depth(&acc) < 16 && depth(&body) < 16 => {
                Expr::Prefix(c, f, Box::new(fold_seq(vec![*body, acc])))
            }
            p => seq(vec![p, acc]),
        };
    }
    acc
}

/// How deep prefixes and sequences nest along the right of `e` (up to 16).
fn depth(e: &Expr) -> usize {
    let mut d = 0;
    let mut cur = e;
    while d < 16 {
        cur = match cur {
            Expr::Prefix(_, _, b) => b,
            Expr::Nary(_, v) if !v.is_empty() => {
                if v.len() > 8 {
                    return 16;
                }
                &v[v.len() - 1]
            }
            _ => return d,
        };
        d += 1;
    }
    d
}

fn replace_call(d: &mut Decl, f: &str) {
    fn go(e: &mut Expr, f: &str) {
        match e {
            Expr::Call(n, args) if n == f && args.is_empty() => *e = name(f),
            Expr::Prefix(_, _, b) | Expr::Guard(_, b) => go(b, f),
            Expr::Nary(_, ps) => ps.iter_mut().for_each(|p| go(p, f)),
            Expr::Repl(_, _, b) => go(b, f),
            _ => {}
        }
    }
    if let Decl::Def(_, _, e) = d {
        go(e, f);
    }
}

fn kind_words(k: robosim_syntax::SyntaxKind) -> String {
    format!("{k:?}").to_lowercase().replace('_', " ")
}
