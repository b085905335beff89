//! The tock-CSP semantics of one state machine, RoboChart or RoboSim, as
//! a CSPm module.
//!
//! The shape follows RoboTool and the paper (§5.2, Rules 3–7 and 13): the
//! machine is the parallel composition of its *behaviour* (one process per
//! state, junction and final state, offering the transitions) and of its
//! *memory* (variables, clocks, and the guards, which enable or disable
//! each transition's trigger; Rule 5). A RoboSim machine also has its
//! *cycle* (Rule 4): read the input registers, `startexec`, run until an
//! `exec` (`endexec__`, tagged with the transition, like a trigger), then
//! let `cycle` time units pass; RoboTool 3 hides only `startexec` (RT-21).
//!
//! Time is explicit tock-CSP (no `Timed` sections): a process that may
//! wait offers `tock`; platform operation calls and RoboSim register writes
//! are urgent (`EDeadline(e, 0)`); internal events have priority over
//! `tock` (`TimedPriority`). Triggers are tagged with their transition
//! (`obstacle__.TID_t1.in`) so that the memory can check the right guard,
//! and renamed back to the machine's events (`obstacle.in`) at the end.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use robosim_hir::model as m;
use robosim_hir::model::{DefKind, Io};
use robosim_hir::{File, FileKind, TextRange};

use crate::cspm::{bin, call, dot, ext, guard, hide, name, nary, par, prefix, seq, BinOp, Decl, Expr, Field, ProcOp};
use crate::export::{Chan, ChanKind, ConstParam, Dir, Elem, ElemKind, Exporter, Profile, RecordTy, Reg, SharedVar, Ty};
use crate::util::{self, ident, op_event};

mod assembly;
mod behaviour;
mod expr;
mod function;
mod sim_op;
mod stmt;
mod untimed;

pub(crate) use function::{function, FunctionOut};
use sim_op::inlined_sim_operation;
pub(crate) use sim_op::sim_operation;

/// What a term is about, for hovers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermKind {
    /// A transition (the process taking it from its source).
    Transition,
    /// An `exec` trigger or statement (RoboSim).
    Exec,
    /// A RoboSim output of an event or a variable (`$e!v`, `$x = v`).
    Output,
    /// A RoboSim call of a platform operation, written as an output
    /// (`$op(…)`).
    OperationOutput,
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
    /// The node in the model.
    m: m::Node,
    /// Suffix of its process names (path of names joined by `_`).
    tag: String,
}

struct TransI {
    tid: String,
    source: usize,
    target: usize,
    /// The transition in the model.
    m: m::Transition,
}

#[derive(Debug, Clone)]
enum Nm {
    Var(usize),
    Const(usize),
    Clock(usize),
    Event(usize),
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
    io: Option<Io>,
    received: bool,
    /// Tagged trigger channel in use.
    trig: bool,
    /// RoboSim: in both I/O contexts, read from its input register and
    /// written to its output register (`io` says `Input`).
    both: bool,
}

struct OpI {
    name: String,
    params: Vec<Ty>,
    /// Defined in the model (an `operation` with its own body): calls run
    /// it (`CALL__op`) instead of calling the platform.
    defined: bool,
    /// The RoboSim I/O context it comes through: `Some(Output)` for a
    /// platform operation (`$op(…)`, a register write), `None` for a
    /// software operation (`op(…)`, run or called).
    io: Option<Io>,
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
    /// The qualified path of what is translated (package, enclosing
    /// elements, its name).
    path: Vec<String>,
    /// Its name's range, for problems about it as a whole.
    name_range: TextRange,
    /// The machine or operation in the model (none for a function).
    model: Option<&'a m::Behaviour>,
    robosim: bool,
    profile: Profile,
    names: HashMap<String, Nm>,
    /// Operations by name, apart from `names`: an event and an operation
    /// may share a name, and the syntax says which is meant (a call or not).
    op_names: HashMap<String, usize>,
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
    /// Per node: whether it is a state with timers (see
    /// [`Gen::activity`]), started when it is entered and stopped by every
    /// transition that leaves it.
    active: Vec<bool>,
    /// Per node: whether it is a composite state with a during action
    /// (see [`Gen::during_process`]).
    during: Vec<bool>,
    /// The processes alongside the behaviour (`Activity__S`, `During__C`),
    /// with the transitions whose triggers each shares.
    activities: Vec<(String, Vec<usize>)>,
    /// Translating an `operation` of the model (its parameters are those
    /// of `D__`, after `id__`).
    is_operation: bool,
    /// RT-11: a RoboSim operation checked on its own (RoboTool's
    /// `OP_…::O__(id__, params)`): no cycle around it, `exec` is a visible
    /// `endexec -> startexec`, reaching the final state terminates.
    sim_op: bool,
    /// With `sim_op`: the operations called as other operations (their
    /// urgent call events `opCall`), by index in `ops`.
    sim_op_calls: std::collections::BTreeSet<usize>,
    /// RoboSim: the outputs it writes (model names), see
    /// [`OperationOut::outputs`].
    written: std::collections::BTreeSet<String>,
    /// The functions without a body it calls (RoboTool's names), its
    /// operations' included: a script whose `Instantiations` block leaves
    /// one undefined cannot check it (RT-7).
    fn_calls: std::collections::BTreeSet<String>,
    op_params: Vec<String>,
    /// `CALL__op` of the operations of the model called (their names).
    op_calls: Vec<(String, Decl)>,
    /// The variables the machine requires through interfaces (kept in its
    /// own memory: its container must not share them).
    required: Vec<String>,
    /// The operations defined for it, by the name it calls them with (see
    /// [`Gen::provide`]); `None`: those it resolves by name.
    provided: Option<Vec<ProvidedOp<'a>>>,
    /// The model path that owns its constants, when it differs from `path`
    /// (a machine instance of a controller: `path` is the instance's).
    owner_path: Option<Vec<String>>,
}

/// An operation a controller defines for its machines: the name they call
/// it by, its file, its definition and the path it is declared under.
pub(crate) type ProvidedOp<'a> = (String, File, &'a m::Behaviour, Vec<String>);

/// Statements and expressions nested deeper are not exported (the
/// translation, printing and checking recurse on them).
const MAX_NESTING: usize = 64;

const GENERATED: &[&str] = &["P__", "D__", "O__", "VS__", "Memory__", "Behaviour__", "Cycle__", "id__", "cycle"];

impl<'e, 'a> Gen<'e, 'a> {
    /// A translation of `model` (a machine or operation of `file`; none for
    /// a function), whose qualified path is `path`; `record`: keep the
    /// terms for hovers.
    pub(crate) fn new(
        ex: &'e mut Exporter<'a>,
        file: File,
        model: Option<&'a m::Behaviour>,
        path: Vec<String>,
        name_range: TextRange,
        record: bool,
    ) -> Self {
        let robosim = file.kind(ex.db) == FileKind::RoboSim;
        let profile = ex.profile;
        Gen {
            ex,
            file,
            path,
            name_range,
            model,
            robosim,
            profile,
            names: HashMap::new(),
            op_names: HashMap::new(),
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
            during: Vec::new(),
            activities: Vec::new(),
            is_operation: false,
            sim_op: false,
            sim_op_calls: Default::default(),
            written: Default::default(),
            fn_calls: Default::default(),
            op_params: Vec::new(),
            op_calls: Vec::new(),
            required: Vec::new(),
            provided: None,
            owner_path: None,
        }
    }

    /// Translates a machine with exactly the operations `ops` defined (its
    /// controller's, RT-19): every other operation it requires is a call
    /// event (`opCall`), as RoboTool leaves it undefined; `owner` is the
    /// machine's own model path when `path` is an instance's.
    pub(crate) fn provide(mut self, ops: Vec<ProvidedOp<'a>>, owner: Option<Vec<String>>) -> Self {
        self.provided = Some(ops);
        self.owner_path = owner;
        self
    }

    /// The definition of the operation `n` the machine calls: its
    /// container's (RT-19), else for an operation, the one it resolves by
    /// name.
    fn op_definition(&self, n: &str) -> Option<ProvidedOp<'a>> {
        if let Some(ops) = &self.provided {
            return ops.iter().find(|o| o.0 == n).cloned();
        }
        let (db, ws) = (self.ex.db, self.ex.ws);
        let loc = m::resolve(db, ws, self.file, &[n.to_string()], DefKind::Operation)?;
        let m::Item::Operation(def) = m::item(db, ws, loc)? else { return None };
        Some((n.to_string(), loc.file, def, self.ex.package(loc.file)))
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
            || crate::defs::is_shared(&s)
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

    /// The channel of the event `n`: as [`Gen::local`], but an event
    /// called `in` or `out` keeps RoboTool's name (its channel hides
    /// InOut's constructor in the module, which then writes the direction
    /// as `in'`/`out'`, see [`Gen::direction`]).
    fn event_local(&mut self, n: &str) -> String {
        if !self.robosim && matches!(n, "in" | "out") && self.locals.insert(n.to_string()) {
            return n.to_string();
        }
        self.local(n)
    }

    /// InOut's constructor `d` (`in` or `out`) as the module can name it:
    /// `in'`/`out'` (robosim_defs.csp) when an event's channel bears its
    /// name.
    fn direction(&mut self, d: &str) -> Expr {
        if self.events.iter().any(|e| e.csp == d) {
            let alias: &'static str = if d == "in" { "in'" } else { "out'" };
            self.ex.helpers.insert(alias);
            name(alias)
        } else {
            name(d)
        }
    }

    /// Translates the machine: its CSPm module and its interface.
    pub(crate) fn run(mut self, module: String, path: Vec<String>) -> Result<MachineOut, Vec<Problem>> {
        self.declarations();
        if self.robosim {
            // RT-19: every software operation nothing defines for it has its
            // call event, called or not (the reference's `Movement` declares
            // them all: "all required operations will be undefined").
            let undefined = self.ops.iter().enumerate().filter(|(_, o)| o.io.is_none() && !o.defined);
            self.sim_op_calls.extend(undefined.map(|(k, _)| k).collect::<Vec<_>>());
        }
        self.collect_structure();
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
        self.declarations();
        self.collect_structure();
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        if !self.nodes.iter().any(|n| n.parent.is_none() && n.kind == NodeKind::Initial) {
            self.problem(
                self.name_range,
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
        // RoboSim: its events are registers (`registerWrite`, shared by name).
        for e in self.events.iter().filter(|_| !self.robosim) {
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
        // RoboSim: its platform operations are registers; its calls of
        // others, the call events it declares.
        let calls =
            self.ops.iter().enumerate().filter(|(k, o)| !o.defined && (!self.robosim || self.sim_op_calls.contains(k)));
        for (_, o) in calls {
            let mut kinds = vec![OpChanKind::Call];
            if self.profile == Profile::Paper2019 {
                kinds.push(OpChanKind::Ret);
            }
            for kind in kinds {
                let suffix = if kind == OpChanKind::Call { "Call" } else { "Ret" };
                chans.push(OpChan {
                    csp: op_event(&o.name, suffix),
                    model: o.name.clone(),
                    kind,
                    dir: Dir::Out,
                    ty: None,
                    params: o.params.clone(),
                });
            }
        }
        let consts = self.consts.iter().cloned().zip(self.const_ty.iter().cloned()).collect();
        let states = self.state_tags();
        let functions = self.fn_calls.clone();
        let (uses_exec, outputs) = (self.robosim && self.uses_exec_stmt, self.written.clone());
        let out = OperationOut {
            module: String::new(),
            params: Vec::new(),
            consts,
            chans,
            states,
            functions,
            uses_exec,
            outputs,
        };
        Ok((decls, out))
    }

    // ------------------------------------------------------ declarations

    fn declarations(&mut self) {
        let Some(beh) = self.model else { return };
        let file = self.file;
        // The machine's own declarations, its RoboSim contexts', then those
        // of the interfaces they use.
        let mut sources: Vec<(File, &m::Decls, Option<Io>, bool)> = vec![(file, &beh.decls, None, true)];
        for (io, d) in &beh.contexts {
            sources.push((file, d, Some(*io), false));
        }
        let mut uses: Vec<(&m::InterfaceUse, Option<Io>)> = beh.decls.uses.iter().map(|u| (u, None)).collect();
        for (io, d) in &beh.contexts {
            uses.extend(d.uses.iter().map(|u| (u, Some(*io))));
        }
        let db = self.ex.db;
        let ws = self.ex.ws;
        for (u, io) in uses {
            let found = m::resolve(db, ws, file, &u.path, DefKind::Interface)
                .and_then(|loc| Some((loc.file, m::item(db, ws, loc)?)));
            match found {
                Some((f, m::Item::Interface(p) | m::Item::Platform(p))) => sources.push((f, &p.decls, io, false)),
                _ => self.problem(u.range, format!("the interface `{}` could not be resolved", u.path.join("::"))),
            }
        }
        for (f, decls, io, own) in sources {
            for c in &decls.decls {
                match c {
                    m::Decl::Vars { is_const, vars, .. } => {
                        let is_const = *is_const;
                        let shared = self.is_operation && !is_const && !own;
                        for v in vars {
                            if !is_const && !self.is_operation && io.is_none() && !own {
                                self.required.push(v.name.clone());
                            }
                            self.variable(f, v, is_const, io, shared);
                        }
                    }
                    m::Decl::Clock { name: n, .. } => {
                        let csp = self.local(n);
                        self.clocks.push(ClockI {
                            csp,
                            bounds: Vec::new(),
                            unbounded: false,
                            read: false,
                            state: None,
                        });
                        self.names.insert(n.clone(), Nm::Clock(self.clocks.len() - 1));
                    }
                    m::Decl::Event { name: n, ty, range, .. } => {
                        if let Some(Nm::Event(i)) = self.names.get(n).cloned() {
                            // RoboSim: an event of both I/O contexts is read from
                            // its input register and written to its output one.
                            let e = &mut self.events[i];
                            match (e.io, io) {
                                (Some(Io::Input), Some(Io::Output)) => e.both = true,
                                (Some(Io::Output), Some(Io::Input)) => (e.io, e.both) = (Some(Io::Input), true),
                                _ => {}
                            }
                            if e.both && self.profile == Profile::Paper2019 {
                                let msg = format!(
                                    "`{n}` is an event of both I/O contexts: the paper2019 profile names its input \
                                     and output registers alike (`{}`), which CSPm cannot declare twice",
                                    self.ex.in_reg(n)
                                );
                                self.problems.push((f, *range, msg));
                            }
                            continue;
                        }
                        if self.names.contains_key(n) {
                            continue;
                        }
                        let ty = match ty {
                            Some(t) => match self.ex.ty_ref(f, Some(t)) {
                                Ok(t) => Some(t),
                                Err(m) => {
                                    self.problems.push((f, *range, format!("event `{n}`: {m}")));
                                    None
                                }
                            },
                            None => None,
                        };
                        let csp = self.event_local(n);
                        self.events.push(EvI {
                            name: n.clone(),
                            csp,
                            ty,
                            io,
                            received: false,
                            trig: false,
                            both: false,
                        });
                        self.names.insert(n.clone(), Nm::Event(self.events.len() - 1));
                    }
                    m::Decl::OperationSig { name: n, params: ps, .. } => {
                        if self.op_names.contains_key(n) {
                            continue;
                        }
                        let mut params = Vec::new();
                        for p in ps {
                            match self.ex.ty_ref(f, p.ty.as_ref()) {
                                Ok(t) => params.push(t),
                                Err(m) => self.problems.push((f, p.range, format!("operation `{n}`: {m}"))),
                            }
                        }
                        // An operation of the model with this name and a body (RoboTool
                        // matches a required operation and its definition by name); one
                        // with a contract only (`terminates`) stays a call event. A
                        // machine's definitions are its controller's (RT-19). A RoboSim
                        // machine's software operations (not of its output context) are
                        // too; a RoboSim operation on its own calls others as events (RT-11).
                        let robosim_ok = !self.robosim || (!self.sim_op && io.is_none() && self.provided.is_some());
                        let defined = robosim_ok
                            && self.op_definition(n).is_some_and(|(_, _, b, _)| {
                                b.region.nodes.iter().any(|x| x.kind == m::NodeKind::Initial)
                            });
                        self.ops.push(OpI { name: n.clone(), params, defined, io });
                        self.op_names.insert(n.clone(), self.ops.len() - 1);
                    }
                    m::Decl::Nested { range, .. } => self.problem(
                        *range,
                        "operations and functions defined in a machine are not supported by the export yet",
                    ),
                }
            }
        }
    }

    fn variable(&mut self, f: File, v: &m::VarDecl, is_const: bool, io: Option<Io>, shared: bool) {
        let n = v.name.clone();
        if self.names.contains_key(&n) {
            return;
        }
        let ty = match self.ex.ty_ref(f, v.ty.as_ref()) {
            Ok(t) => t,
            Err(m) => {
                self.problems.push((f, v.range, format!("`{n}`: {m}")));
                return;
            }
        };
        if io.is_some() && !is_const {
            self.problems.push((
                f,
                v.range,
                format!("`{n}` is an input or output variable: platform variables are not supported by the export yet"),
            ));
            return;
        }
        let init = v.init.as_ref();
        if is_const {
            let local = self.local(&n);
            let mut owner = self.owner_path.clone().unwrap_or_else(|| self.path.clone());
            let global = ident(&format!("const_{}_{}", util::qualified(&self.path), n));
            let default = match init {
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
            let init = match init {
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

    /// RoboTool's value for a constant the model gives none (RT-1): its
    /// type's default, 0 for numbers — a divisor of 0 is harmless, as
    /// division is `x / 0 = x / 1` (RT-6).
    fn const_default(&self, ty: &Ty) -> Expr {
        ty.default_value()
    }

    /// The nodes and transitions of the machine, from the model.
    fn collect_structure(&mut self) {
        let Some(beh) = self.model else {
            let what = self.what();
            self.problem(self.name_range, format!("the model of this {what} is not available"));
            return;
        };
        self.collect_nodes(&beh.region, None);
        self.collect_transitions(&beh.region);
    }

    fn collect_nodes(&mut self, region: &m::Region, parent: Option<usize>) {
        for c in &region.nodes {
            let kind = match c.kind {
                m::NodeKind::State => NodeKind::State,
                m::NodeKind::Junction => NodeKind::Junction,
                m::NodeKind::Initial => NodeKind::Initial,
                m::NodeKind::Final => NodeKind::Final,
                m::NodeKind::Probabilistic => {
                    self.problem(
                        c.range,
                        "probabilistic junctions have no meaning in the tock-CSP semantics and are not exported",
                    );
                    continue;
                }
            };
            let name = c.name.clone();
            let base = match parent {
                Some(p) => format!("{}_{}", self.nodes[p].tag, ident(&name)),
                None => ident(&name),
            };
            // Tags share one namespace (`A_B` for B in A, and for a state
            // named `A_B`), where RoboTool nests a module per state: a
            // taken one gets a suffix, so that every node's is its own.
            let mut tag = base.clone();
            let mut k = 2;
            while self.nodes.iter().any(|n| n.tag == tag) {
                tag = format!("{base}_{k}");
                k += 1;
            }
            self.nodes.push(NodeI { name, kind, parent, m: c.clone(), tag });
            if kind == NodeKind::State {
                let id = self.nodes.len() - 1;
                self.collect_nodes(&c.region, Some(id));
            }
        }
    }

    /// The states and final states: their paths and tags (`SID_tag`).
    pub(crate) fn state_tags(&self) -> Vec<(Vec<String>, String)> {
        (0..self.nodes.len())
            .filter(|&i| matches!(self.nodes[i].kind, NodeKind::State | NodeKind::Final))
            .map(|i| (self.node_path(i), self.nodes[i].tag.clone()))
            .collect()
    }

    /// The names of node `n` and of the states around it, outermost first.
    fn node_path(&self, n: usize) -> Vec<String> {
        let mut path = vec![self.nodes[n].name.clone()];
        let mut cur = self.nodes[n].parent;
        while let Some(c) = cur {
            path.insert(0, self.nodes[c].name.clone());
            cur = self.nodes[c].parent;
        }
        path
    }

    fn sibling(&self, parent: Option<usize>, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.parent == parent && n.name == name)
    }

    fn collect_transitions(&mut self, root: &m::Region) {
        let mut regions = vec![(root.clone(), None)];
        for (i, n) in self.nodes.iter().enumerate() {
            if n.kind == NodeKind::State {
                regions.push((n.m.region.clone(), Some(i)));
            }
        }
        let mut used_tids = HashSet::new();
        for (region, parent) in regions {
            for t in &region.transitions {
                let name = t.name.clone();
                let (Some(src), Some(dst)) = (&t.source, &t.target) else {
                    self.problem(t.range, format!("transition `{name}` lacks a source or a target"));
                    continue;
                };
                let (Some(source), Some(target)) = (self.sibling(parent, src), self.sibling(parent, dst)) else {
                    self.problem(t.range, format!("transition `{name}`: its ends are not nodes of its region"));
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
                self.trans.push(TransI { tid, source, target, m: t.clone() });
            }
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
    /// Its states' paths and tags, as [`Elem::states`](crate::export::Elem).
    pub states: Vec<(Vec<String>, String)>,
    /// The functions without a body it calls, as [`Elem::functions`](crate::export::Elem).
    pub functions: std::collections::BTreeSet<String>,
    /// RoboSim: it has an `exec` statement (its own `endexec` and
    /// `startexec`, which a calling machine renames to its cycle's).
    pub uses_exec: bool,
    /// RoboSim: the outputs it writes (model names of events and platform
    /// operations): registers its caller must have.
    pub outputs: std::collections::BTreeSet<String>,
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

/// The CSPm module of the operation `op` of `file` (RoboChart), declared
/// in `outer` (its package and enclosing elements), made on first use;
/// the reason when it cannot be exported.
pub(crate) fn operation<'a>(
    ex: &mut Exporter<'a>,
    file: File,
    op: &'a m::Behaviour,
    outer: Vec<String>,
) -> Result<Rc<OperationOut>, String> {
    let key = (file, op.range);
    let oname = op.name.clone();
    match ex.operations.get(&key) {
        Some(Some(r)) => return r.clone(),
        Some(None) => return Err(format!("the operation `{oname}` calls itself: not supported by the export yet")),
        None => {}
    }
    ex.operations.insert(key, None);
    let module = operation_module(ex, file, &outer, &oname);
    let mut path = outer;
    path.push(oname.clone());
    let mut g = Gen::new(ex, file, Some(op), path.clone(), op.name_range, false);
    g.is_operation = true;
    let mut params = Vec::new();
    let mut problems = Vec::new();
    let model_params = g.model.map(|b| b.params.clone()).unwrap_or_default();
    for p in &model_params {
        let pn = p.name.clone();
        match g.ex.ty_ref(file, p.ty.as_ref()) {
            Ok(t) => {
                let local = g.local(&pn);
                g.names.insert(pn, Nm::Param(local.clone(), t.clone()));
                g.op_params.push(local);
                params.push(t);
            }
            Err(m) => problems.push((file, p.range, format!("parameter `{pn}`: {m}"))),
        }
    }
    let result = if problems.is_empty() { g.run_operation(module.clone(), path.clone()) } else { Err(problems) };
    let r = match result {
        Ok((decls, out)) => {
            ex.emit(file, decls);
            Ok(Rc::new(OperationOut { module, params, ..out }))
        }
        Err(problems) => {
            let what = format!("operation {}", path.join("::"));
            let why = refuse_operation(ex, file, &what, &format!("{what} is not exported"), &problems);
            Err(format!("the operation `{oname}` is not exported: {why}"))
        }
    };
    ex.operations.insert(key, Some(r.clone()));
    r
}

/// The CSPm module of the operation `name` declared in `outer` (of
/// `file`), RoboTool's `OP_<name>`: a top-level one's inside its
/// package's module (`pkg::OP_op`, as the reference's
/// `pkg223_main::OP_tStop`; `OP_op` in the default package), one declared
/// inside a controller inside the controller's module (`pkg::C::OP_op`, as
/// the reference's `pkg223_::CommunicationC::OP_…`).
pub(super) fn operation_module(ex: &mut Exporter<'_>, file: File, outer: &[String], name: &str) -> String {
    let package = ex.package(file);
    if outer.len() <= package.len() {
        let mut path = outer.to_vec();
        path.push(format!("OP_{}", ident(name)));
        let module = crate::util::element_module(outer, &path);
        return ex.unique_module(module);
    }
    let named = robosim_hir::csp_names::csp_names(ex.db, ex.ws).element_by_path(outer);
    let container = match named {
        Some(e) if e.module.split("::").all(|s| ident(s) == s) => e.module.clone(),
        _ => crate::util::element_module(&package, outer),
    };
    ex.unique_module(format!("{container}::OP_{}", ident(name)))
}

/// Leaves an operation out of the export: a `NOT EXPORTED: {what}`
/// comment listing `problems`, and a warning `{warning}: problem` for
/// each; the first problem's message.
pub(crate) fn refuse_operation(
    ex: &mut Exporter<'_>,
    file: File,
    what: &str,
    warning: &str,
    problems: &[Problem],
) -> String {
    let mut lines = vec![format!("NOT EXPORTED: {what}")];
    for (f, r, m) in problems {
        lines.push(format!("  {}: {m}", ex.loc(*f, *r)));
        ex.warn(*f, *r, format!("{warning}: {m}"));
    }
    ex.emit(file, vec![Decl::Comment(lines.join("\n")), Decl::Blank]);
    problems.first().map(|p| p.2.clone()).unwrap_or_default()
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
