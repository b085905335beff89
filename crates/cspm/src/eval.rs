//! The evaluator: environments (an arena of frames, so that recursive
//! definitions need no reference cycles), lazily evaluated definitions,
//! values, patterns and dotted values. Processes are built in `proc_eval`
//! and explored in `lts`.

use std::collections::BTreeSet;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use rustc_hash::FxHashMap;

use crate::ast::{BinOp, Clause, Decl, DeclKind, Expr, ExprKind, Name, Pat, Stmt, Timed, UnOp};
use crate::proc::P;
use crate::resolve::ExternalName;
use crate::value::Opaque;
use crate::{Code, Diagnostic, Module, NameLookup, TextRange, Value};

pub(crate) type R<T> = Result<T, Diagnostic>;

/// Bounds on one evaluation. Reaching one is a `CSP-E02` diagnostic.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Deepest nesting of evaluation (recursion of functions included).
    pub max_depth: u32,
    /// Largest set, sequence or enumeration built.
    pub max_set: usize,
    /// Most states of one LTS.
    pub max_states: usize,
    /// Wall-clock budget of the evaluator (from its creation).
    pub time: Duration,
    /// Set to `true` from elsewhere to stop the evaluation.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Most bytes of stack one evaluation may use (measured from its
    /// outermost call), well below the thread's stack size.
    pub max_stack: usize,
    /// Compile processes only up to their traces: internal choices (`|~|`,
    /// its replicated form, `$` inputs) become external ones. Every CSP
    /// operator but priority is compositional in the traces model and
    /// `P |~| Q` has the traces of `P [] Q`, so each process keeps its
    /// traces, while an external choice of internal choices no longer
    /// multiplies its branches' states. `prioritise` and
    /// `timed_priority` are then refused (priority depends on more than
    /// traces).
    pub traces_only: bool,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_depth: 2_000,
            max_set: 200_000,
            max_states: 500_000,
            time: Duration::from_secs(20),
            cancel: None,
            // Half of the 2 MiB of a default spawned thread.
            max_stack: 1 << 20,
            traces_only: false,
        }
    }
}

/// A function value (opaque outside the crate).
pub struct Function(pub(crate) Func);

impl std::fmt::Debug for Function {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("<function>")
    }
}

pub(crate) enum Func {
    /// A definition's clauses, the frame they were defined in, and the
    /// argument groups given so far (curried definitions `f(x)(y)`).
    User {
        name: Name,
        clauses: Rc<[Rc<Clause>]>,
        env: u32,
        given: Vec<Vec<Value>>,
        timed: Option<Rc<Timed>>,
    },
    Lambda {
        pats: Rc<[Pat]>,
        body: Rc<Expr>,
        env: u32,
    },
    Builtin {
        name: &'static str,
        given: Vec<Value>,
    },
    /// A process the host supplies as an LTS (see `ExternalName::Process`).
    External {
        name: Name,
        arity: usize,
        build: crate::resolve::BuildLts,
    },
}

#[derive(Clone, Debug)]
pub(crate) enum Slot {
    Val(Value),
    Thunk(u32),
}

struct Frame {
    parent: Option<u32>,
    vars: Vec<(Name, Slot)>,
    timed: Option<Rc<Timed>>,
}

enum ThunkBody {
    Decl(Rc<[Decl]>, usize),
    /// One name of a pattern binding: the whole value is matched each time.
    PatName(Rc<[Decl]>, usize, Name),
}

enum ThunkState {
    Todo,
    Busy,
    Done(Value),
}

struct Thunk {
    body: ThunkBody,
    env: u32,
    state: ThunkState,
    range: TextRange,
}

/// Evaluates the definitions of a checked [`Module`]: values, and
/// processes as explicit LTSs ([`Evaluator::lts`]).
pub struct Evaluator<'m> {
    pub(crate) names: &'m dyn NameLookup,
    pub(crate) limits: Limits,
    frames: Vec<Frame>,
    thunks: Vec<Thunk>,
    next_id: u64,
    /// Channels and constructors: the value lists of their fields.
    pub(crate) fields: FxHashMap<Name, Rc<[Rc<[Value]>]>>,
    /// The number of fields of every channel and constructor.
    pub(crate) arity: FxHashMap<Name, usize>,
    pub(crate) channels: Vec<Name>,
    /// The constructors of each datatype, by its declaration's address.
    pub(crate) datatypes: FxHashMap<usize, Vec<Name>>,
    /// The frame patterns are matched in (see [`Evaluator::ctor_of`]):
    /// set before each match, to the scope of the pattern's definition.
    pub(crate) pat_env: u32,
    pub(crate) events: Vec<Value>,
    pub(crate) event_ids: FxHashMap<Value, u32>,
    pub(crate) calls: FxHashMap<(Value, Vec<Value>), Rc<P>>,
    /// Calls being evaluated (see `apply`).
    in_progress: rustc_hash::FxHashSet<(Value, Vec<Value>)>,
    pub(crate) depth: u32,
    /// Stack use since the outermost evaluation step.
    stack: crate::stack::StackGuard,
    started: Instant,
    steps: u64,
    pub(crate) global: u32,
}

pub(crate) fn err(code: Code, range: TextRange, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(code, range, msg)
}

impl<'m> Evaluator<'m> {
    /// An evaluator of `module`'s definitions, with the model's names from
    /// `names` (pass the same lookup as to [`Module::check`]).
    pub fn new(module: &Module, names: &'m dyn NameLookup, limits: Limits) -> Evaluator<'m> {
        let mut ev = Evaluator {
            names,
            limits,
            frames: Vec::new(),
            thunks: Vec::new(),
            next_id: 1,
            fields: FxHashMap::default(),
            arity: FxHashMap::default(),
            channels: Vec::new(),
            datatypes: FxHashMap::default(),
            pat_env: 0,
            events: Vec::new(),
            event_ids: FxHashMap::default(),
            calls: FxHashMap::default(),
            in_progress: Default::default(),
            depth: 0,
            stack: crate::stack::StackGuard::new(1 << 20),
            started: Instant::now(),
            steps: 0,
            global: 0,
        };
        ev.frames.push(Frame { parent: None, vars: Vec::new(), timed: None });
        ev.bind_decls(&module.decls, 0);
        ev
    }

    /// The value of a top-level name (a constant, a set, a function, a
    /// process). The name may also be one the model supplies.
    pub fn value(&mut self, name: &str) -> Result<Value, Diagnostic> {
        let at = TextRange::empty(0.into());
        self.lookup(name, self.global, at)
    }

    /// Evaluates an expression (written in CSPm) in the scope of the
    /// module's top-level definitions.
    pub fn eval_text(&mut self, expr: &str) -> Result<Value, Diagnostic> {
        let m = Module::check(&format!("x__ = {expr}"), self.names);
        if let Some(d) = m.diagnostics().iter().find(|d| d.severity == crate::Severity::Error) {
            if d.code != Code::Unresolved {
                return Err(d.clone());
            }
        }
        let Some(Decl { kind: DeclKind::Fun(_, clauses), .. }) = m.decls.first() else {
            return Err(err(Code::Syntax, TextRange::empty(0.into()), "expected an expression"));
        };
        let body = &clauses[0].body;
        self.eval(body, self.global)
    }

    pub(crate) fn fresh_id(&mut self) -> u64 {
        self.next_id += 1;
        self.next_id
    }

    pub(crate) fn func(&mut self, f: Func) -> Value {
        Value::Func(Opaque { id: self.fresh_id(), inner: Rc::new(Function(f)) })
    }

    pub(crate) fn proc_value(&mut self, p: Rc<P>) -> Value {
        Value::Proc(Opaque { id: self.fresh_id(), inner: p })
    }

    /// Counts a step; fails when the time is up or the caller cancelled.
    pub(crate) fn tick(&mut self, at: TextRange) -> R<()> {
        self.steps += 1;
        if self.steps.is_multiple_of(256) {
            if self.limits.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed)) {
                return Err(err(Code::Cancelled, at, "evaluation cancelled"));
            }
            if self.started.elapsed() > self.limits.time {
                return Err(err(Code::Limit, at, format!("evaluation took longer than {:?}", self.limits.time)));
            }
        }
        Ok(())
    }

    pub(crate) fn check_size(&self, n: usize, at: TextRange) -> R<()> {
        if n > self.limits.max_set {
            return Err(err(
                Code::Limit,
                at,
                format!("a set or sequence of more than {} elements", self.limits.max_set),
            ));
        }
        Ok(())
    }

    fn new_frame(&mut self, parent: u32, timed: Option<Rc<Timed>>) -> u32 {
        let timed = timed.or_else(|| self.frames[parent as usize].timed.clone());
        self.frames.push(Frame { parent: Some(parent), vars: Vec::new(), timed });
        (self.frames.len() - 1) as u32
    }

    pub(crate) fn timed_of(&self, env: u32) -> Option<Rc<Timed>> {
        self.frames[env as usize].timed.clone()
    }

    fn bind(&mut self, env: u32, name: Name, slot: Slot) {
        self.frames[env as usize].vars.push((name, slot));
    }

    /// Binds declarations in `env` (lazily: each is evaluated when first
    /// used). Channels and constructors get their number of fields from
    /// the syntax first, then their value sets once every name is bound
    /// (declarations may refer to later ones, and datatypes to themselves).
    pub(crate) fn bind_decls(&mut self, decls: &Rc<[Decl]>, env: u32) {
        let mut typed = Vec::new();
        self.bind_names(decls, env, "", &mut typed);
        // Field types may use each other in any order (`channel c : T.N`
        // before `datatype T`, `nametype N`): evaluated until no progress.
        loop {
            let before = typed.len();
            let mut failed = Vec::new();
            for (name, ty, own, env) in typed {
                if !self.field_types(&name, ty, own, env) {
                    failed.push((name, ty, own, env));
                }
            }
            typed = failed;
            if typed.is_empty() || typed.len() == before {
                break;
            }
        }
    }

    /// Binds the names of `decls` (modules recursively), collecting the
    /// field types of channels and constructors to evaluate. A channel or
    /// constructor declared in module `M` (`prefix` `M::`) is the value
    /// `M::c`, as FDR prints it, bound as `c` inside the module: two
    /// modules' `c` are different events, with their own fields.
    fn bind_names<'d>(
        &mut self,
        decls: &'d Rc<[Decl]>,
        env: u32,
        prefix: &str,
        typed: &mut Vec<(Name, &'d Expr, Option<u32>, u32)>,
    ) {
        let qualify = |n: &Name| -> Name {
            if prefix.is_empty() {
                n.clone()
            } else {
                format!("{prefix}{n}").into()
            }
        };
        for (i, d) in decls.iter().enumerate() {
            match &d.kind {
                DeclKind::Fun(name, _) | DeclKind::Nametype(name, _) => {
                    let t = self.new_thunk(ThunkBody::Decl(decls.clone(), i), env, d.range);
                    self.bind(env, name.clone(), Slot::Thunk(t));
                }
                DeclKind::PatBind(p, _) => {
                    let mut names = Vec::new();
                    crate::resolve::pat_names(p, &mut |n, _| names.push(Name::from(n)));
                    for n in names {
                        if self.ctor_of(&n, env).is_some() {
                            continue;
                        }
                        let t = self.new_thunk(ThunkBody::PatName(decls.clone(), i, n.clone()), env, d.range);
                        self.bind(env, n, Slot::Thunk(t));
                    }
                }
                DeclKind::Channel(names, ty) => {
                    for (n, _) in names {
                        let q = qualify(n);
                        self.arity.insert(q.clone(), ty.as_ref().map_or(0, dot_count));
                        self.fields.remove(&q);
                        if ty.is_none() {
                            self.fields.insert(q.clone(), Rc::from(Vec::new()));
                        }
                        self.channels.push(q.clone());
                        self.bind(env, n.clone(), Slot::Val(Value::Ctor(q.clone())));
                        if let Some(ty) = ty {
                            typed.push((q, ty, None, env));
                        }
                    }
                }
                DeclKind::Datatype(name, clauses) | DeclKind::Subtype(name, clauses) => {
                    let is_sub = matches!(d.kind, DeclKind::Subtype(..));
                    let t = self.new_thunk(ThunkBody::Decl(decls.clone(), i), env, d.range);
                    self.bind(env, name.clone(), Slot::Thunk(t));
                    if is_sub {
                        continue;
                    }
                    let mut ctors = Vec::new();
                    for (c, _, fe) in clauses {
                        let q = qualify(c);
                        self.arity.insert(q.clone(), fe.as_ref().map_or(0, dot_count));
                        self.fields.remove(&q);
                        match fe {
                            Some(fe) => typed.push((q.clone(), fe, Some(t), env)),
                            None => {
                                self.fields.insert(q.clone(), Rc::from(Vec::new()));
                            }
                        }
                        self.bind(env, c.clone(), Slot::Val(Value::Ctor(q.clone())));
                        ctors.push(q);
                    }
                    let _ = name;
                    self.datatypes.insert(d as *const Decl as usize, ctors);
                }
                DeclKind::Module(m, inner) => {
                    // The module's own frame, then its names again as `M::x`
                    // (the same slots: evaluated once, in the module).
                    let fr = self.new_frame(env, None);
                    self.bind_names(inner, fr, &format!("{prefix}{m}::"), typed);
                    let vars = self.frames[fr as usize].vars.clone();
                    for (n, slot) in vars {
                        self.bind(env, format!("{m}::{n}").into(), slot);
                    }
                }
                DeclKind::Assert | DeclKind::Annotation(_) => {}
            }
        }
    }

    /// Evaluates the field types of a channel or constructor; whether it
    /// could (a recursive type or `Int` cannot: its values can then be
    /// built and matched but not enumerated).
    fn field_types(&mut self, name: &Name, ty: &Expr, own: Option<u32>, env: u32) -> bool {
        // A datatype's own name in its fields (a recursive type) fails fast:
        // its thunk is busy meanwhile.
        if let Some(t) = own {
            if matches!(self.thunks[t as usize].state, ThunkState::Todo) {
                self.thunks[t as usize].state = ThunkState::Busy;
            }
        }
        let r = self.eval(ty, env).and_then(|v| self.type_fields(v, ty.range));
        if let Some(t) = own {
            if matches!(self.thunks[t as usize].state, ThunkState::Busy) {
                self.thunks[t as usize].state = ThunkState::Todo;
            }
        }
        match r {
            Ok(f) => {
                self.arity.insert(name.clone(), f.len());
                self.fields.insert(name.clone(), f.into());
                true
            }
            Err(_) => false,
        }
    }

    fn new_thunk(&mut self, body: ThunkBody, env: u32, range: TextRange) -> u32 {
        self.thunks.push(Thunk { body, env, state: ThunkState::Todo, range });
        (self.thunks.len() - 1) as u32
    }

    /// The fields of a channel or constructor from its type expression's
    /// value: `A.B` gives two fields, a set of dotted values is split.
    pub(crate) fn type_fields(&mut self, v: Value, at: TextRange) -> R<Vec<Rc<[Value]>>> {
        let mut out = Vec::new();
        let parts: Vec<Value> = match v {
            Value::Dot(vs) if !matches!(vs.first(), Some(Value::Ctor(_))) => vs.to_vec(),
            v => vec![v],
        };
        for part in parts {
            let set = self.type_set(part, at)?;
            let all_dots = !set.is_empty()
                && set.iter().all(|x| matches!(x, Value::Dot(d) if !matches!(d.first(), Some(Value::Ctor(_)))));
            if all_dots {
                let n = set.iter().map(|x| if let Value::Dot(d) = x { d.len() } else { 0 }).min().unwrap_or(0);
                for k in 0..n {
                    let col: BTreeSet<Value> = set
                        .iter()
                        .filter_map(|x| if let Value::Dot(d) = x { d.get(k).cloned() } else { None })
                        .collect();
                    out.push(col.into_iter().collect());
                }
            } else {
                out.push(set.into_iter().collect());
            }
        }
        Ok(out)
    }

    /// The values of a type expression: a set, a tuple of sets (their
    /// product), `Int` is refused (it cannot be enumerated).
    fn type_set(&mut self, v: Value, at: TextRange) -> R<BTreeSet<Value>> {
        match v {
            Value::Set(s) => Ok((*s).clone()),
            Value::Tuple(parts) => {
                let mut acc = vec![Vec::new()];
                for p in parts.iter() {
                    let s = self.type_set(p.clone(), at)?;
                    let mut next = Vec::new();
                    for a in &acc {
                        for x in &s {
                            let mut t = a.clone();
                            t.push(x.clone());
                            next.push(t);
                        }
                    }
                    self.check_size(next.len(), at)?;
                    acc = next;
                }
                Ok(acc.into_iter().map(|t| Value::Tuple(t.into())).collect())
            }
            Value::Ints => Err(err(Code::Limit, at, "a channel or constructor of type `Int` cannot be enumerated")),
            other => Err(err(Code::Type, at, format!("expected a set as a type, found {}", other.kind_name()))),
        }
    }

    pub(crate) fn lookup(&mut self, name: &str, env: u32, at: TextRange) -> R<Value> {
        let mut f = Some(env);
        while let Some(i) = f {
            let frame = &self.frames[i as usize];
            if let Some((_, slot)) = frame.vars.iter().rev().find(|(n, _)| &**n == name) {
                return match slot.clone() {
                    Slot::Val(v) => Ok(v),
                    Slot::Thunk(t) => self.force(t, at),
                };
            }
            f = frame.parent;
        }
        if let Some(v) = crate::builtins::value(self, name) {
            return Ok(v);
        }
        match self.names.lookup(name) {
            Some(ExternalName::Value(v)) => Ok(v),
            Some(ExternalName::Channel(fields)) => {
                let n: Name = name.into();
                if !self.arity.contains_key(&n) {
                    self.arity.insert(n.clone(), fields.len());
                    self.fields.insert(n.clone(), fields.into_iter().map(Rc::from).collect());
                    self.channels.push(n.clone());
                }
                Ok(Value::Ctor(n))
            }
            Some(ExternalName::Process { arity: 0, build }) => {
                let key = (Value::Ctor(format!("{name}()").into()), Vec::new());
                if let Some(p) = self.calls.get(&key).cloned() {
                    return Ok(self.proc_value(p));
                }
                let lts = build(&[]).map_err(|m| err(Code::Runtime, at, format!("`{name}`: {m}")))?;
                let p = self.external_process(lts, at)?;
                self.calls.insert(key, p.clone());
                Ok(self.proc_value(p))
            }
            Some(ExternalName::Process { arity, build }) => {
                Ok(self.func(Func::External { name: name.into(), arity, build }))
            }
            None => Err(err(Code::Unresolved, at, format!("`{name}` is not defined"))),
        }
    }

    /// The slot of a name (for process calls, which must not force it).
    pub(crate) fn slot(&self, name: &str, env: u32) -> Option<Slot> {
        let mut f = Some(env);
        while let Some(i) = f {
            let frame = &self.frames[i as usize];
            if let Some((_, slot)) = frame.vars.iter().rev().find(|(n, _)| &**n == name) {
                return Some(slot.clone());
            }
            f = frame.parent;
        }
        None
    }

    pub(crate) fn thunk_done(&self, t: u32) -> Option<Value> {
        match &self.thunks[t as usize].state {
            ThunkState::Done(v) => Some(v.clone()),
            _ => None,
        }
    }

    pub(crate) fn force(&mut self, t: u32, _at: TextRange) -> R<Value> {
        let th = &self.thunks[t as usize];
        match &th.state {
            ThunkState::Done(v) => return Ok(v.clone()),
            // A definition used while it is being evaluated (`P = F(P)`):
            // a lazy reference, which only a process can be (anything else
            // is then a type error where it is used).
            ThunkState::Busy => {
                let key = (Value::Int(t as i64), Vec::new());
                return Ok(self.proc_value(Rc::new(P::Call(Rc::new(key)))));
            }
            ThunkState::Todo => {}
        }
        let env = th.env;
        let range = th.range;
        let (decls, i, pat_name) = match &th.body {
            ThunkBody::Decl(d, i) => (d.clone(), *i, None),
            ThunkBody::PatName(d, i, n) => (d.clone(), *i, Some(n.clone())),
        };
        self.thunks[t as usize].state = ThunkState::Busy;
        let d = &decls[i];
        let r = self.eval_decl(d, env, pat_name, range);
        self.thunks[t as usize].state = match &r {
            Ok(v) => ThunkState::Done(v.clone()),
            Err(_) => ThunkState::Todo,
        };
        r
    }

    fn eval_decl(&mut self, d: &Decl, env: u32, pat_name: Option<Name>, range: TextRange) -> R<Value> {
        match &d.kind {
            DeclKind::Fun(name, clauses) => {
                if clauses.len() == 1 && clauses[0].params.is_empty() {
                    let e = self.new_frame(env, d.timed.clone());
                    let c = clauses[0].clone();
                    return self.eval_maybe_proc(&c.body, e);
                }
                let f = Func::User {
                    name: name.clone(),
                    clauses: clauses.clone().into(),
                    env,
                    given: Vec::new(),
                    timed: d.timed.clone(),
                };
                Ok(self.func(f))
            }
            DeclKind::PatBind(p, e) => {
                let fr = self.new_frame(env, d.timed.clone());
                let v = self.eval_maybe_proc(e, fr)?;
                let mut binds = Vec::new();
                self.pat_env = env;
                if !self.matches(p, &v, &mut binds)? {
                    return Err(err(Code::Runtime, range, format!("the value {v} does not match the pattern")));
                }
                let want = pat_name.unwrap_or_default();
                binds
                    .into_iter()
                    .find(|(n, _)| **n == *want)
                    .map(|(_, v)| v)
                    .ok_or_else(|| err(Code::Runtime, range, "pattern binding without that name"))
            }
            DeclKind::Nametype(_, e) => {
                let v = self.eval(e, env)?;
                self.type_value(v, e.range)
            }
            DeclKind::Subtype(_, clauses) => {
                let mut out = BTreeSet::new();
                for (c, _, fe) in clauses {
                    // The constructor as declared in scope (`M::c` in a module).
                    let head = self.lookup(c, env, range)?;
                    let Some(fe) = fe else {
                        out.extend(self.completions(head, range)?);
                        continue;
                    };
                    let v = self.eval(fe, env)?;
                    let mut acc = vec![head];
                    for set in self.type_fields(v, fe.range)? {
                        let mut next = Vec::new();
                        for a in &acc {
                            for x in set.iter() {
                                next.push(self.dot(a.clone(), x.clone(), fe.range)?);
                            }
                        }
                        self.check_size(next.len(), fe.range)?;
                        acc = next;
                    }
                    out.extend(acc);
                }
                Ok(Value::Set(Rc::new(out)))
            }
            DeclKind::Datatype(name, _) => {
                let mut out = BTreeSet::new();
                let _ = name;
                let ctors = self.datatypes.get(&(d as *const Decl as usize)).cloned().unwrap_or_default();
                for c in ctors {
                    for v in self.completions(Value::Ctor(c), range)? {
                        out.insert(v);
                    }
                }
                Ok(Value::Set(Rc::new(out)))
            }
            _ => Err(err(Code::Runtime, range, "not a value")),
        }
    }

    /// A nametype's value: dotted sets become the set of dotted values.
    fn type_value(&mut self, v: Value, at: TextRange) -> R<Value> {
        match v {
            Value::Dot(parts) if !matches!(parts.first(), Some(Value::Ctor(_))) => {
                let mut acc: Vec<Value> = Vec::new();
                for (i, p) in parts.iter().enumerate() {
                    let s = self.type_set(p.clone(), at)?;
                    if i == 0 {
                        acc = s.into_iter().collect();
                        continue;
                    }
                    let mut next = Vec::new();
                    for a in &acc {
                        for x in &s {
                            next.push(self.dot(a.clone(), x.clone(), at)?);
                        }
                    }
                    self.check_size(next.len(), at)?;
                    acc = next;
                }
                Ok(Value::set(acc))
            }
            Value::Tuple(_) => Ok(Value::Set(Rc::new(self.type_set(v, at)?))),
            v => Ok(v),
        }
    }

    /// Evaluates a definition's body; process bodies stay lazy in their
    /// recursive calls (see `proc_eval`).
    pub(crate) fn eval_maybe_proc(&mut self, e: &Expr, env: u32) -> R<Value> {
        if crate::proc_eval::is_process_syntax(e) {
            let p = self.eval_proc(e, env)?;
            return Ok(self.proc_value(p));
        }
        self.eval(e, env)
    }

    pub(crate) fn enter(&mut self, at: TextRange) -> R<()> {
        if self.depth == 0 {
            self.stack = crate::stack::StackGuard::new(self.limits.max_stack);
        } else if self.stack.exceeded() {
            return Err(err(Code::Limit, at, "evaluation nested too deeply for the stack (a runaway recursion?)"));
        }
        self.depth += 1;
        if self.depth > self.limits.max_depth {
            self.depth -= 1;
            return Err(err(
                Code::Limit,
                at,
                format!("evaluation nested deeper than {} (a runaway recursion?)", self.limits.max_depth),
            ));
        }
        self.tick(at)
    }

    pub(crate) fn eval(&mut self, e: &Expr, env: u32) -> R<Value> {
        self.enter(e.range)?;
        let r = self.eval_inner(e, env);
        self.depth -= 1;
        r
    }

    fn eval_inner(&mut self, e: &Expr, env: u32) -> R<Value> {
        use ExprKind::*;
        let at = e.range;
        Ok(match &e.kind {
            Int(i) => Value::Int(*i),
            Bool(b) => Value::Bool(*b),
            Char(c) => Value::Char(*c),
            Str(s) => Value::Seq(s.chars().map(Value::Char).collect()),
            Var(n) => self.lookup(n, env, at)?,
            Tuple(es) => Value::Tuple(self.eval_all(es, env)?.into()),
            App(f, args) => {
                let fv = self.eval(f, env)?;
                let args = self.eval_all(args, env)?;
                self.apply(fv, args, at)?
            }
            Bin(op, a, b) => self.binary(*op, a, b, env, at)?,
            Un(op, a) => {
                let v = self.eval(a, env)?;
                match (op, v) {
                    (UnOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    (UnOp::Neg, Value::Int(i)) => Value::Int(i.checked_neg().ok_or_else(|| overflow(at))?),
                    (UnOp::Len, Value::Seq(s)) => Value::Int(s.len() as i64),
                    (_, v) => {
                        return Err(err(Code::Type, at, format!("this operator does not apply to {}", v.kind_name())))
                    }
                }
            }
            Set(es) => Value::set(self.eval_all(es, env)?),
            Seq(es) => Value::Seq(self.eval_all(es, env)?.into()),
            SetRange(a, b) | SeqRange(a, b) => {
                let lo = self.int(a, env)?;
                let Some(b) = b else {
                    return Err(err(Code::Limit, at, "an infinite range cannot be evaluated"));
                };
                let hi = self.int(b, env)?;
                let n = if hi >= lo { (hi - lo) as u128 + 1 } else { 0 };
                self.check_size(n.min(usize::MAX as u128) as usize, at)?;
                let items = (lo..=hi).map(Value::Int);
                if matches!(e.kind, SetRange(..)) {
                    Value::set(items)
                } else {
                    Value::Seq(items.collect())
                }
            }
            SetComp(x, stmts) | SeqComp(x, stmts) => {
                let mut out = Vec::new();
                let seq = matches!(e.kind, SeqComp(..));
                self.comprehend(stmts, 0, env, &mut |ev, env| {
                    let v = ev.eval(x, env)?;
                    match (&x.kind, v) {
                        (SetRange(..), Value::Set(s)) if !seq => out.extend(s.iter().cloned()),
                        (SeqRange(..), Value::Seq(s)) if seq => out.extend(s.iter().cloned()),
                        (_, v) => out.push(v),
                    }
                    ev.check_size(out.len(), x.range)
                })?;
                if seq {
                    Value::Seq(out.into())
                } else {
                    Value::set(out)
                }
            }
            Closure(es, stmts) => {
                let mut heads = Vec::new();
                self.comprehend(stmts, 0, env, &mut |ev, env| {
                    for x in es {
                        heads.push(ev.eval(x, env)?);
                    }
                    Ok(())
                })?;
                let mut out = BTreeSet::new();
                for h in heads {
                    out.extend(self.completions(h, at)?);
                    self.check_size(out.len(), at)?;
                }
                Value::Set(Rc::new(out))
            }
            // `(| k => v, … |)`: a later pair for the same key wins (libcspm's
            // `M.fromList`).
            Map(kvs) => {
                let mut m = std::collections::BTreeMap::new();
                for (k, v) in kvs {
                    let k = self.eval(k, env)?;
                    let v = self.eval(v, env)?;
                    m.insert(k, v);
                }
                Value::Map(Rc::new(m))
            }
            Let(decls, body) => {
                let fr = self.new_frame(env, None);
                self.bind_decls(decls, fr);
                self.eval_maybe_proc(body, fr)?
            }
            If(c, t, f) => {
                if self.bool(c, env)? {
                    self.eval_maybe_proc(t, env)?
                } else {
                    self.eval_maybe_proc(f, env)?
                }
            }
            Lambda(pats, body) => self.func(Func::Lambda { pats: pats.clone(), body: body.clone(), env }),
            Error => return Err(err(Code::Syntax, at, "this expression has errors")),
            _ => {
                let p = self.eval_proc(e, env)?;
                self.proc_value(p)
            }
        })
    }

    pub(crate) fn eval_all(&mut self, es: &[Expr], env: u32) -> R<Vec<Value>> {
        es.iter().map(|e| self.eval(e, env)).collect()
    }

    pub(crate) fn int(&mut self, e: &Expr, env: u32) -> R<i64> {
        match self.eval(e, env)? {
            Value::Int(i) => Ok(i),
            v => Err(err(Code::Type, e.range, format!("expected an integer, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn bool(&mut self, e: &Expr, env: u32) -> R<bool> {
        match self.eval(e, env)? {
            Value::Bool(b) => Ok(b),
            v => Err(err(Code::Type, e.range, format!("expected a boolean, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn set_of(&mut self, e: &Expr, env: u32) -> R<Rc<BTreeSet<Value>>> {
        match self.eval(e, env)? {
            Value::Set(s) => Ok(s),
            Value::Ints => Err(err(Code::Limit, e.range, "the set of all integers cannot be enumerated")),
            v => Err(err(Code::Type, e.range, format!("expected a set, found {}", v.kind_name()))),
        }
    }

    fn binary(&mut self, op: BinOp, a: &Expr, b: &Expr, env: u32, at: TextRange) -> R<Value> {
        if op == BinOp::Dot {
            // `a.b.c` is parsed to the right but built from the left, so
            // that each value fills the next free field (as libcspm does).
            let mut parts = Vec::new();
            flatten_dot_expr(a, &mut parts);
            flatten_dot_expr(b, &mut parts);
            let mut acc = self.eval(parts[0], env)?;
            for p in &parts[1..] {
                let v = self.eval(p, env)?;
                acc = self.dot(acc, v, at)?;
            }
            return Ok(acc);
        }
        match op {
            BinOp::And => return Ok(Value::Bool(self.bool(a, env)? && self.bool(b, env)?)),
            BinOp::Or => return Ok(Value::Bool(self.bool(a, env)? || self.bool(b, env)?)),
            _ => {}
        }
        let x = self.eval(a, env)?;
        let y = self.eval(b, env)?;
        Ok(match (op, x, y) {
            (BinOp::Add, Value::Int(x), Value::Int(y)) => Value::Int(x.checked_add(y).ok_or_else(|| overflow(at))?),
            (BinOp::Sub, Value::Int(x), Value::Int(y)) => Value::Int(x.checked_sub(y).ok_or_else(|| overflow(at))?),
            (BinOp::Mul, Value::Int(x), Value::Int(y)) => Value::Int(x.checked_mul(y).ok_or_else(|| overflow(at))?),
            (BinOp::Div | BinOp::Mod, Value::Int(_), Value::Int(0)) => {
                return Err(err(Code::Runtime, at, "division by zero"))
            }
            // Haskell's `quot` and `rem` (libcspm): truncation towards zero.
            (BinOp::Div, Value::Int(x), Value::Int(y)) => Value::Int(x.checked_div(y).ok_or_else(|| overflow(at))?),
            (BinOp::Mod, Value::Int(x), Value::Int(y)) => Value::Int(x.checked_rem(y).ok_or_else(|| overflow(at))?),
            (BinOp::Eq, x, y) => Value::Bool(x == y),
            (BinOp::Ne, x, y) => Value::Bool(x != y),
            (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, Value::Set(x), Value::Set(y)) => Value::Bool(match op {
                BinOp::Lt => x.is_subset(&y) && x.len() < y.len(),
                BinOp::Le => x.is_subset(&y),
                BinOp::Gt => y.is_subset(&x) && y.len() < x.len(),
                _ => y.is_subset(&x),
            }),
            (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, Value::Seq(x), Value::Seq(y)) => Value::Bool(match op {
                BinOp::Lt => y.starts_with(&x) && x.len() < y.len(),
                BinOp::Le => y.starts_with(&x),
                BinOp::Gt => x.starts_with(&y) && y.len() < x.len(),
                _ => x.starts_with(&y),
            }),
            // Maps: libcspm's submap order (`isSubmapOfBy` with `<=` on values).
            (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, Value::Map(x), Value::Map(y)) => {
                let (a, b) = if matches!(op, BinOp::Lt | BinOp::Le) { (&x, &y) } else { (&y, &x) };
                let strict = matches!(op, BinOp::Lt | BinOp::Gt);
                Value::Bool(crate::builtins::submap(a, b) && !(strict && a == b))
            }
            (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, x, y)
                if matches!(
                    (&x, &y),
                    (Value::Int(_), Value::Int(_))
                        | (Value::Char(_), Value::Char(_))
                        | (Value::Tuple(_), Value::Tuple(_))
                ) =>
            {
                Value::Bool(match op {
                    BinOp::Lt => x < y,
                    BinOp::Le => x <= y,
                    BinOp::Gt => x > y,
                    _ => x >= y,
                })
            }
            (BinOp::Concat, Value::Seq(x), Value::Seq(y)) => {
                self.check_size(x.len() + y.len(), at)?;
                Value::Seq(x.iter().chain(y.iter()).cloned().collect())
            }
            (BinOp::Dot, x, y) => self.dot(x, y, at)?,
            (_, x, y) => {
                return Err(err(
                    Code::Type,
                    at,
                    format!("this operator does not apply to {} and {}", x.kind_name(), y.kind_name()),
                ))
            }
        })
    }

    /// Runs `body` for every binding of the statements (generators and
    /// predicates, left to right).
    pub(crate) fn comprehend(
        &mut self,
        stmts: &[Stmt],
        i: usize,
        env: u32,
        body: &mut dyn FnMut(&mut Self, u32) -> R<()>,
    ) -> R<()> {
        let Some(s) = stmts.get(i) else { return body(self, env) };
        match s {
            Stmt::Pred(e) => {
                if self.bool(e, env)? {
                    self.comprehend(stmts, i + 1, env, body)?;
                }
            }
            Stmt::Gen(p, e) => {
                let items: Vec<Value> = match self.eval(e, env)? {
                    Value::Set(s) => s.iter().cloned().collect(),
                    Value::Seq(s) => s.to_vec(),
                    Value::Ints => return Err(err(Code::Limit, e.range, "cannot draw from the set of all integers")),
                    v => {
                        return Err(err(
                            Code::Type,
                            e.range,
                            format!("expected a set or sequence, found {}", v.kind_name()),
                        ))
                    }
                };
                for v in items {
                    self.tick(e.range)?;
                    let mut binds = Vec::new();
                    self.pat_env = env;
                    if self.matches(p, &v, &mut binds)? {
                        let fr = self.new_frame(env, None);
                        for (n, v) in binds {
                            self.bind(fr, n, Slot::Val(v));
                        }
                        self.comprehend(stmts, i + 1, fr, body)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// A frame binding the names of a successful match.
    pub(crate) fn frame_with(&mut self, env: u32, binds: Vec<(Name, Value)>, timed: Option<Rc<Timed>>) -> u32 {
        let fr = self.new_frame(env, timed);
        for (n, v) in binds {
            self.bind(fr, n, Slot::Val(v));
        }
        fr
    }

    pub(crate) fn apply(&mut self, f: Value, args: Vec<Value>, at: TextRange) -> R<Value> {
        // A process-valued call is evaluated once per arguments, so that
        // every path to `F(x)` reaches the same term (and the same state).
        let user = matches!(&f, Value::Func(func) if !matches!(func.inner.0, Func::Builtin { .. }));
        let key = if user { Some((f.clone(), args.clone())) } else { None };
        if let Some(k) = &key {
            if let Some(p) = self.calls.get(k) {
                let p = p.clone();
                return Ok(self.proc_value(p));
            }
            // The same call inside its own evaluation (`P(x) = F(P(x))`,
            // arguments being evaluated eagerly): a lazy reference to it.
            if self.in_progress.contains(k) {
                let call = Rc::new(P::Call(Rc::new(k.clone())));
                return Ok(self.proc_value(call));
            }
            self.in_progress.insert(k.clone());
        }
        let entered = self.enter(at);
        let r = entered.and_then(|_| {
            let r = self.apply_inner(f, args, at);
            self.depth -= 1;
            r
        });
        if let Some(k) = key {
            self.in_progress.remove(&k);
            if let Ok(Value::Proc(p)) = &r {
                self.calls.insert(k, p.inner.clone());
            }
        }
        r
    }

    fn apply_inner(&mut self, f: Value, args: Vec<Value>, at: TextRange) -> R<Value> {
        let Value::Func(func) = f else {
            return Err(err(Code::Type, at, format!("{} is not a function", f.kind_name())));
        };
        match &func.inner.0 {
            Func::Builtin { name, given } => {
                let mut all = given.clone();
                all.extend(args);
                crate::builtins::call(self, name, all, at)
            }
            Func::External { name, arity, build } => {
                if args.len() != *arity {
                    return Err(err(Code::Type, at, format!("`{name}` takes {arity} argument(s), not {}", args.len())));
                }
                let lts = build(&args).map_err(|m| err(Code::Runtime, at, format!("`{name}`: {m}")))?;
                let p = self.external_process(lts, at)?;
                Ok(self.proc_value(p))
            }
            Func::Lambda { pats, body, env } => {
                if pats.len() != args.len() {
                    return Err(err(
                        Code::Type,
                        at,
                        format!("this function takes {} arguments, not {}", pats.len(), args.len()),
                    ));
                }
                let mut binds = Vec::new();
                for (p, v) in pats.iter().zip(&args) {
                    self.pat_env = *env;
                    if !self.matches(p, v, &mut binds)? {
                        return Err(err(Code::Runtime, at, "the arguments do not match the lambda's patterns"));
                    }
                }
                let fr = self.frame_with(*env, binds, None);
                let body = body.clone();
                self.eval_maybe_proc(&body, fr)
            }
            Func::User { name, clauses, env, given, timed } => {
                let mut given = given.clone();
                given.push(args);
                let groups = clauses.first().map_or(0, |c| c.params.len());
                if given.len() < groups {
                    let f = Func::User {
                        name: name.clone(),
                        clauses: clauses.clone(),
                        env: *env,
                        given,
                        timed: timed.clone(),
                    };
                    return Ok(self.func(f));
                }
                for c in clauses.iter() {
                    if c.params.len() != given.len() {
                        continue;
                    }
                    let mut binds = Vec::new();
                    let mut ok = true;
                    for (ps, vs) in c.params.iter().zip(&given) {
                        self.pat_env = *env;
                        if ps.len() != vs.len() || !self.all_match(ps, vs, &mut binds)? {
                            ok = false;
                            break;
                        }
                    }
                    if ok {
                        let fr = self.frame_with(*env, binds, timed.clone());
                        let c = c.clone();
                        return self.eval_maybe_proc(&c.body, fr);
                    }
                }
                let shown: Vec<String> = given.iter().flatten().map(|v| v.to_string()).collect();
                Err(err(Code::Runtime, at, format!("no clause of `{name}` matches ({})", shown.join(", "))))
            }
        }
    }
}

fn overflow(at: TextRange) -> Diagnostic {
    err(Code::Runtime, at, "integer overflow")
}

/// The number of `.`-separated parts of a type expression.
fn dot_count(e: &Expr) -> usize {
    match &e.kind {
        ExprKind::Bin(BinOp::Dot, a, b) => dot_count(a) + dot_count(b),
        _ => 1,
    }
}

fn flatten_dot_expr<'e>(e: &'e Expr, out: &mut Vec<&'e Expr>) {
    match &e.kind {
        ExprKind::Bin(BinOp::Dot, a, b) => {
            flatten_dot_expr(a, out);
            flatten_dot_expr(b, out);
        }
        _ => out.push(e),
    }
}
