//! Process expressions to process terms. Calls of named processes and of
//! functions stay lazy (`P::Call`), which keeps recursive definitions
//! finite. Inside a `Timed(f) { … }` section the terms are built exactly
//! as FDR's front end does (libcspm's desugarer and evaluator): a prefix
//! may idle (`tock`) and is followed by `f(e)` tocks, `STOP`/`SKIP` become
//! `TSTOP`/`TSKIP`, `[]` and `/\` synchronise on `tock`, `|||` and every
//! parallel synchronise on `tock`, and a false guard is `TSTOP`.

use std::rc::Rc;

use crate::ast::{Expr, ExprKind, Field, ProcOp, RepOp, SetOp, Stmt};
use crate::eval::{err, Evaluator, Func, Slot, R};
use crate::proc::{Events, P};
use crate::{Code, TextRange, Value};

/// Whether an expression is syntactically a process (so that a definition
/// with this body is built lazily).
pub(crate) fn is_process_syntax(e: &Expr) -> bool {
    use ExprKind::*;
    match &e.kind {
        Prefix(..) | Guard(..) | Proc(..) | Hide(..) | Project(..) | SetProc(..) | AlphaPar(..) | LinkPar(..)
        | Rename(..) | Replicated(..) => true,
        Let(_, b) => is_process_syntax(b),
        If(_, a, b) => is_process_syntax(a) || is_process_syntax(b),
        _ => false,
    }
}

impl Evaluator<'_> {
    /// `|~|` of `ps`, or `[]` when compiling up to traces
    /// ([`crate::Limits::traces_only`]).
    fn internal_choice(&self, ps: Vec<Rc<P>>) -> P {
        if self.limits.traces_only {
            P::Ext(ps)
        } else {
            P::Int(ps)
        }
    }

    /// The tock event and the event function of a timed frame.
    fn timed(&mut self, env: u32, at: TextRange) -> R<Option<(u32, Option<Value>)>> {
        let Some(t) = self.timed_of(env) else { return Ok(None) };
        let tock = self.lookup("tock", self.global, at)?;
        let tock = self.event(tock, at)?;
        let f = match &t.f {
            Some(f) => Some(self.eval(f, self.global)?),
            None => None,
        };
        Ok(Some((tock, f)))
    }

    fn tock_set(&mut self, env: u32, at: TextRange) -> R<Option<u32>> {
        Ok(if self.timed_of(env).is_some() { self.timed(env, at)?.map(|t| t.0) } else { None })
    }

    fn events_of(&mut self, e: &Expr, env: u32, with_tock: bool) -> R<Events> {
        let v = self.eval(e, env)?;
        let set = self.event_set(&v, e.range)?;
        if with_tock {
            if let Some(t) = self.tock_set(env, e.range)? {
                let mut s = set.to_vec();
                if let Err(i) = s.binary_search(&t) {
                    s.insert(i, t);
                }
                return Ok(s.into());
            }
        }
        Ok(set)
    }

    fn stop(&mut self, env: u32, at: TextRange) -> R<Rc<P>> {
        Ok(Rc::new(match self.tock_set(env, at)? {
            Some(t) => P::TStop(t),
            None => P::Stop,
        }))
    }

    pub(crate) fn call_body(&mut self, key: &(Value, Vec<Value>), at: TextRange) -> R<Rc<P>> {
        let v = match &key.0 {
            Value::Int(t) if key.1.is_empty() => self.force(*t as u32, at)?,
            f => self.apply(f.clone(), key.1.clone(), at)?,
        };
        match v {
            Value::Proc(p) => Ok(p.inner),
            v => Err(err(Code::Type, at, format!("expected a process, found {}", v.kind_name()))),
        }
    }

    /// A process term for `e`, lazy at calls.
    pub(crate) fn eval_proc(&mut self, e: &Expr, env: u32) -> R<Rc<P>> {
        self.enter(e.range)?;
        let r = self.eval_proc_inner(e, env);
        self.depth -= 1;
        r
    }

    fn proc_of(&mut self, v: Value, at: TextRange) -> R<Rc<P>> {
        match v {
            Value::Proc(p) => Ok(p.inner),
            v => Err(err(Code::Type, at, format!("expected a process, found {}", v.kind_name()))),
        }
    }

    fn eval_proc_inner(&mut self, e: &Expr, env: u32) -> R<Rc<P>> {
        use ExprKind::*;
        let at = e.range;
        let timed = self.timed_of(env).is_some();
        Ok(match &e.kind {
            Var(n) => match self.slot(n, env) {
                // A definition not evaluated yet: a lazy call (`thunk` id
                // as the key).
                Some(Slot::Thunk(t)) if self.thunk_done(t).is_none() => {
                    Rc::new(P::Call(Rc::new((Value::Int(t as i64), Vec::new()))))
                }
                _ => match (&**n, timed) {
                    ("STOP", true) | ("SKIP", true) => {
                        let t = self.tock_set(env, at)?.unwrap_or(0);
                        Rc::new(if &**n == "STOP" { P::TStop(t) } else { P::TSkip(t) })
                    }
                    _ => {
                        let v = self.eval(e, env)?;
                        self.proc_of(v, at)?
                    }
                },
            },
            App(f, args) => {
                let fv = match &f.kind {
                    Var(n) if timed && &**n == "WAIT" => {
                        let t = self.tock_set(env, at)?.unwrap_or(0);
                        let n =
                            self.int(args.first().ok_or_else(|| err(Code::Type, at, "WAIT takes a number"))?, env)?;
                        return Ok(P::tocks(t, n, Rc::new(P::TSkip(t))));
                    }
                    _ => self.eval(f, env)?,
                };
                let args = self.eval_all(args, env)?;
                let lazy = matches!(&fv, Value::Func(func) if !matches!(func.inner.0, Func::Builtin { .. }));
                if lazy {
                    Rc::new(P::Call(Rc::new((fv, args))))
                } else {
                    let v = self.apply(fv, args, at)?;
                    self.proc_of(v, at)?
                }
            }
            Let(decls, body) => return self.let_proc(decls, body, env),
            If(c, a, b) => {
                if self.bool(c, env)? {
                    self.eval_proc(a, env)?
                } else {
                    self.eval_proc(b, env)?
                }
            }
            Guard(b, p) => {
                if self.bool(b, env)? {
                    self.eval_proc(p, env)?
                } else {
                    self.stop(env, at)?
                }
            }
            Prefix(ev, fields, body) => {
                let head = self.eval(ev, env)?;
                let mut branches = Vec::new();
                self.prefix_fields(head, fields, 0, env, body, &mut branches)?;
                self.assemble_prefix(branches, env, at)?
            }
            Proc(op, a, b) => {
                let pa = self.eval_proc(a, env)?;
                let pb = self.eval_proc(b, env)?;
                let tock = self.tock_set(env, at)?;
                Rc::new(match (op, tock) {
                    (ProcOp::Ext, Some(t)) => P::SyncExt(Rc::from([t]), vec![pa, pb]),
                    (ProcOp::Ext, None) => P::Ext(vec![pa, pb]),
                    (ProcOp::Int, _) => self.internal_choice(vec![pa, pb]),
                    (ProcOp::Interleave, t) => P::Par(t.map_or(Rc::from([]), |t| Rc::from([t])), vec![pa, pb]),
                    (ProcOp::Seq, _) => P::Seq(pa, pb),
                    (ProcOp::Interrupt, Some(t)) => P::SyncInt(Rc::from([t]), pa, pb),
                    (ProcOp::Interrupt, None) => P::Interrupt(pa, pb),
                    (ProcOp::Slide, _) => P::Slide(pa, pb),
                })
            }
            Hide(p, s) => {
                let pp = self.eval_proc(p, env)?;
                let s = self.events_of(s, env, false)?;
                if s.is_empty() {
                    pp
                } else {
                    Rc::new(P::Hide(s, pp))
                }
            }
            Project(p, s) => {
                let pp = self.eval_proc(p, env)?;
                let keep = self.events_of(s, env, false)?;
                let all = self.all_events(at)?;
                let all = self.event_set(&all, at)?;
                let hidden: Vec<u32> = all.iter().copied().filter(|e| keep.binary_search(e).is_err()).collect();
                Rc::new(P::Hide(hidden.into(), pp))
            }
            SetProc(op, a, s, b) => {
                let pa = self.eval_proc(a, env)?;
                let with_tock = matches!(op, SetOp::GenPar | SetOp::SyncExt | SetOp::SyncInt);
                let set = self.events_of(s, env, with_tock)?;
                let pb = self.eval_proc(b, env)?;
                Rc::new(match op {
                    SetOp::GenPar => P::Par(set, vec![pa, pb]),
                    SetOp::Exception => P::Exception(set, pa, pb),
                    SetOp::SyncExt => P::SyncExt(set, vec![pa, pb]),
                    SetOp::SyncInt => P::SyncInt(set, pa, pb),
                })
            }
            AlphaPar(a, x, y, b) => {
                let pa = self.eval_proc(a, env)?;
                let sx = self.events_of(x, env, true)?;
                let sy = self.events_of(y, env, true)?;
                let pb = self.eval_proc(b, env)?;
                Rc::new(P::AlphaPar(vec![(sx, pa), (sy, pb)]))
            }
            LinkPar(a, links, stmts, b) => {
                let pa = self.eval_proc(a, env)?;
                let pb = self.eval_proc(b, env)?;
                let map = self.pairs(links, stmts, env)?;
                Rc::new(P::Link(map, pa, pb))
            }
            Rename(p, pairs, stmts) => {
                let pp = self.eval_proc(p, env)?;
                let map = self.pairs(pairs, stmts, env)?;
                if map.is_empty() {
                    pp
                } else {
                    Rc::new(P::Rename(map, pp))
                }
            }
            Replicated(op, stmts, body) => self.replicated(op, stmts, body, env, at)?,
            _ => {
                let v = self.eval(e, env)?;
                self.proc_of(v, at)?
            }
        })
    }

    /// The choice between a prefix's branches; in a `Timed` section each
    /// event is followed by `f(e)` tocks and the prefix may idle (`tock`).
    fn assemble_prefix(&mut self, branches: Vec<Branch>, env: u32, at: TextRange) -> R<Rc<P>> {
        let mut events = Vec::new();
        let mut procs = Vec::new();
        for b in branches {
            match b {
                Branch::Event(e, p) => events.push((e, p)),
                Branch::Proc(p) => procs.push(p),
            }
        }
        let timed = self.timed(env, at)?;
        if let Some((tock, f)) = timed {
            let mut bs = Vec::new();
            for (ev, p) in events {
                let n = match &f {
                    Some(f) => {
                        let v = self.events[ev as usize].clone();
                        match self.apply(f.clone(), vec![v], at)? {
                            Value::Int(n) => n,
                            v => {
                                return Err(err(
                                    Code::Type,
                                    at,
                                    format!("the `Timed` function returned {}", v.kind_name()),
                                ))
                            }
                        }
                    }
                    None => 1,
                };
                bs.push((ev, P::tocks(tock, n, p)));
            }
            if !bs.is_empty() || procs.is_empty() {
                procs.insert(0, Rc::new(P::TimedPrefix(tock, bs.into())));
            }
            return Ok(if procs.len() == 1 { procs.remove(0) } else { Rc::new(P::SyncExt(Rc::from([tock]), procs)) });
        }
        let mut all: Vec<Rc<P>> = events.into_iter().map(|(e, p)| Rc::new(P::Prefix(e, p))).collect();
        all.extend(procs);
        Ok(if all.len() == 1 { all.remove(0) } else { Rc::new(P::Ext(all)) })
    }

    fn let_proc(&mut self, decls: &Rc<[crate::ast::Decl]>, body: &Expr, env: u32) -> R<Rc<P>> {
        let fr = self.frame_with(env, Vec::new(), None);
        self.bind_decls(decls, fr);
        self.eval_proc(body, fr)
    }

    /// Renaming / linking pairs, each side possibly a channel prefix
    /// (`c <- d` renames every `c.x` to `d.x`).
    fn pairs(&mut self, pairs: &[(Expr, Expr)], stmts: &[Stmt], env: u32) -> R<Rc<[(u32, u32)]>> {
        let mut raw = Vec::new();
        self.comprehend(stmts, 0, env, &mut |ev, env| {
            for (a, b) in pairs {
                raw.push((ev.eval(a, env)?, ev.eval(b, env)?, a.range));
            }
            Ok(())
        })?;
        let mut out = Vec::new();
        for (a, b, at) in raw {
            for full in self.completions(a.clone(), at)? {
                // The fields `full` adds to `a` are added to `b` as well.
                let extra: Vec<Value> = match (&a, &full) {
                    (Value::Dot(x), Value::Dot(y)) => y[x.len()..].to_vec(),
                    (Value::Ctor(_), Value::Dot(y)) => y[1..].to_vec(),
                    _ => Vec::new(),
                };
                let mut target = b.clone();
                for x in extra {
                    target = self.dot(target, x, at)?;
                }
                let (ea, eb) = (self.event(full, at)?, self.event(target, at)?);
                out.push((ea, eb));
            }
        }
        out.sort_unstable();
        out.dedup();
        Ok(out.into())
    }

    /// Expands the fields of a prefix into (event, continuation) branches.
    fn prefix_fields(
        &mut self,
        head: Value,
        fields: &[Field],
        i: usize,
        env: u32,
        body: &Expr,
        out: &mut Vec<Branch>,
    ) -> R<()> {
        let Some(f) = fields.get(i) else {
            let ev = self.event(head, body.range)?;
            let p = self.eval_proc(body, env)?;
            out.push(Branch::Event(ev, p));
            return Ok(());
        };
        match f {
            Field::Output(e) => {
                let v = self.eval(e, env)?;
                let head = self.dot(head, v, e.range)?;
                self.prefix_fields(head, fields, i + 1, env, body, out)
            }
            Field::Input(p, restrict) => {
                let heads = self.input_heads(&head, p, restrict.as_ref(), i + 1 == fields.len(), env, body.range)?;
                self.input_branches(&head, heads, p, fields, i, env, body, out)
            }
            Field::NonDet(p, restrict) => {
                // `c$x -> P` is `|~| x @ c.x -> P`: one process per value.
                let at = body.range;
                let heads = self.input_heads(&head, p, restrict.as_ref(), i + 1 == fields.len(), env, at)?;
                let mut procs = Vec::new();
                for h in heads {
                    let mut sub = Vec::new();
                    self.input_branches(&head, vec![h], p, fields, i, env, body, &mut sub)?;
                    if !sub.is_empty() {
                        procs.push(self.assemble_prefix(sub, env, at)?);
                    }
                }
                if procs.is_empty() {
                    return Err(err(Code::Runtime, at, "nondeterministic input over no values"));
                }
                out.push(Branch::Proc(Rc::new(self.internal_choice(procs))));
                Ok(())
            }
        }
    }

    /// The heads an input field extends `head` to: the values of `?x:S`,
    /// or whole fields of the declared values, one at a time until the
    /// pattern has as many components as it has parts (`?x.y` over
    /// `{0,1}.{0,1}` takes two fields, `?X.x` over a datatype field one);
    /// the last field of a prefix takes the rest.
    fn input_heads(
        &mut self,
        head: &Value,
        p: &crate::ast::Pat,
        restrict: Option<&Expr>,
        last: bool,
        env: u32,
        at: TextRange,
    ) -> R<Vec<Value>> {
        if let Some(s) = restrict {
            let mut full = Vec::new();
            for c in self.set_of(s, env)?.iter() {
                full.push(self.dot(head.clone(), c.clone(), at)?);
            }
            return Ok(full);
        }
        let want = crate::dotted::pat_width(p);
        let mut heads = std::collections::BTreeSet::new();
        for e in self.completions(head.clone(), at)? {
            let rest = remaining_fields(head, &e);
            if rest.is_empty() {
                continue;
            }
            let mut j = 0;
            let mut width = 0;
            while j < rest.len() && (last || width < want) {
                width += crate::dotted::value_width(&rest[j]);
                j += 1;
            }
            let mut h = head.clone();
            for v in &rest[..j] {
                h = self.dot(h, v.clone(), at)?;
            }
            heads.insert(h);
        }
        Ok(heads.into_iter().collect())
    }

    #[allow(clippy::too_many_arguments)]
    fn input_branches(
        &mut self,
        head: &Value,
        extended: Vec<Value>,
        p: &crate::ast::Pat,
        fields: &[Field],
        i: usize,
        env: u32,
        body: &Expr,
        out: &mut Vec<Branch>,
    ) -> R<()> {
        let skip = match head {
            Value::Dot(x) => x.len(),
            _ => 1,
        };
        let mut head_flat = Vec::new();
        crate::dotted::flatten_value(head, &mut head_flat);
        for v in extended {
            self.tick(body.range)?;
            // The value the pattern sees: the fields added to the head (one
            // field as it is; several, or a nested field, as components).
            let seen = match &v {
                Value::Dot(y) if y.len() == skip + 1 => y[skip].clone(),
                _ => {
                    let mut flat = Vec::new();
                    crate::dotted::flatten_value(&v, &mut flat);
                    if flat.len() <= head_flat.len() {
                        continue;
                    }
                    let added = &flat[head_flat.len()..];
                    if added.len() == 1 {
                        added[0].clone()
                    } else {
                        Value::Dot(added.into())
                    }
                }
            };
            let mut binds = Vec::new();
            self.pat_env = env;
            if self.matches(p, &seen, &mut binds)? {
                let fr = self.frame_with(env, binds, None);
                self.prefix_fields(v, fields, i + 1, fr, body, out)?;
            }
        }
        Ok(())
    }

    fn replicated(&mut self, op: &RepOp, stmts: &[Stmt], body: &Expr, env: u32, at: TextRange) -> R<Rc<P>> {
        let mut ps = Vec::new();
        let mut alphas = Vec::new();
        let mut links = Vec::new();
        self.comprehend(stmts, 0, env, &mut |ev, fr| {
            ps.push(ev.eval_proc(body, fr)?);
            match op {
                RepOp::AlphaPar(a) => alphas.push(ev.events_of(a, fr, true)?),
                RepOp::Link(l, s) => links.push(ev.pairs(l, s, fr)?),
                _ => {}
            }
            ev.check_size(ps.len(), at)
        })?;
        let tock = self.tock_set(env, at)?;
        if ps.is_empty() {
            return match (op, tock) {
                (RepOp::Int, _) => Err(err(Code::Runtime, at, "replicated internal choice over an empty set")),
                (RepOp::Seq, _) => Ok(Rc::new(if tock.is_some() { P::TSkip(tock.unwrap_or(0)) } else { P::Skip })),
                (RepOp::Link(..), _) => {
                    Err(err(Code::Runtime, at, "replicated linked parallel over an empty sequence"))
                }
                (_, Some(t)) => Ok(Rc::new(P::TStop(t))),
                (RepOp::Ext, None) => Ok(Rc::new(P::Stop)),
                (_, None) => Ok(Rc::new(P::Skip)),
            };
        }
        let tockset: Events = tock.map_or(Rc::from([]), |t| Rc::from([t]));
        Ok(Rc::new(match op {
            RepOp::Ext if tock.is_some() => P::SyncExt(tockset, ps),
            RepOp::Ext => P::Ext(ps),
            RepOp::Int => self.internal_choice(ps),
            RepOp::Interleave => P::Par(tockset, ps),
            // Flat, however long the sequence (no deep terms).
            RepOp::Seq => P::SeqList(ps[0].clone(), ps.into(), 1),
            RepOp::GenPar(a) => P::Par(self.events_of(a, env, true)?, ps),
            RepOp::SyncExt(a) => P::SyncExt(self.events_of(a, env, true)?, ps),
            RepOp::AlphaPar(_) => P::AlphaPar(alphas.into_iter().zip(ps).collect()),
            RepOp::Link(..) => {
                self.check_size(ps.len() * 100, at)?;
                let mut it = ps.into_iter().zip(links).rev();
                let Some((mut acc, _)) = it.next() else { return Ok(Rc::new(P::Stop)) };
                for (p, l) in it {
                    acc = Rc::new(P::Link(l, p, acc));
                }
                return Ok(acc);
            }
        }))
    }
}

/// The field values a complete value `e` adds to its prefix `head`, in
/// order (the rest of a nested incomplete field first).
fn remaining_fields(head: &Value, e: &Value) -> Vec<Value> {
    let (hp, ep): (Vec<Value>, Vec<Value>) = match (head, e) {
        (Value::Dot(h), Value::Dot(x)) => (h.to_vec(), x.to_vec()),
        (h, Value::Dot(x)) => (vec![h.clone()], x.to_vec()),
        _ => return Vec::new(),
    };
    let k = hp.len();
    if k > ep.len() {
        return Vec::new();
    }
    let mut out = Vec::new();
    if k > 1 && hp[k - 1] != ep[k - 1] {
        // The head's last field is an incomplete constructor value.
        out = remaining_fields(&hp[k - 1], &ep[k - 1]);
    }
    out.extend(ep[k..].iter().cloned());
    out
}

/// One alternative of a prefix: an event and what follows, or (for a
/// nondeterministic input) a whole process.
enum Branch {
    Event(u32, Rc<P>),
    Proc(Rc<P>),
}
