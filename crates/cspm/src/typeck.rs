//! Type checking: Hindley–Milner inference over CSPm's simple types
//! (integers, booleans, characters, events, processes, sets, sequences,
//! tuples, functions, datatypes), with let-polymorphism. CSPm's dotted
//! types (channels and constructors with fields, `a.b`) are not modelled:
//! they are a wildcard type that agrees with everything, so every error
//! reported is a real one (`CSP-T01` at the offending expression); some
//! errors involving dotted values are not found.

use rustc_hash::FxHashMap;

use crate::ast::{BinOp, Decl, DeclKind, Expr, ExprKind, Field, Pat, RepOp, Stmt, UnOp};
use crate::{Code, Diagnostic, TextRange};

#[derive(Clone, Debug, PartialEq)]
enum Ty {
    Var(u32),
    /// Dotted values and anything else not modelled: agrees with all.
    Any,
    Int,
    Bool,
    Char,
    Event,
    Proc,
    Data(String),
    Set(Box<Ty>),
    Seq(Box<Ty>),
    Tuple(Vec<Ty>),
    Fn(Vec<Ty>, Box<Ty>),
    /// A map from keys to values (`(| k => v |)`).
    Map(Box<Ty>, Box<Ty>),
}

use Ty::*;

fn set(t: Ty) -> Ty {
    Set(Box::new(t))
}

fn seq(t: Ty) -> Ty {
    Seq(Box::new(t))
}

fn map(k: Ty, v: Ty) -> Ty {
    Map(Box::new(k), Box::new(v))
}

#[derive(Clone)]
enum Bind<'a> {
    Mono(Ty),
    Decl(&'a Decl),
}

enum State {
    Busy(FxHashMap<String, Ty>),
    Done(FxHashMap<String, Ty>),
}

struct Checker<'a> {
    subst: Vec<Option<Ty>>,
    scopes: Vec<FxHashMap<String, Bind<'a>>>,
    states: FxHashMap<*const Decl, State>,
    diags: &'a mut Vec<Diagnostic>,
    /// Whether the definition being checked already has an error (one per
    /// definition: the rest would be consequences).
    failed: bool,
    /// Channels and datatype constructors (patterns match them).
    ctors: rustc_hash::FxHashSet<&'a str>,
    /// Definitions of `let`s (monomorphic).
    local: rustc_hash::FxHashSet<*const Decl>,
    stack: crate::stack::StackGuard,
}

/// Type-checks `decls`, adding `CSP-T01` diagnostics.
pub(crate) fn check(decls: &[Decl], diags: &mut Vec<Diagnostic>) {
    let mut c = Checker {
        subst: Vec::new(),
        scopes: Vec::new(),
        states: FxHashMap::default(),
        diags,
        failed: false,
        ctors: Default::default(),
        local: Default::default(),
        stack: crate::stack::StackGuard::new(crate::stack::STATIC_PASS_STACK),
    };
    c.decls(decls);
}

impl<'a> Checker<'a> {
    fn fresh(&mut self) -> Ty {
        self.subst.push(None);
        Var(self.subst.len() as u32 - 1)
    }

    fn resolve(&self, t: &Ty) -> Ty {
        match t {
            Var(v) => match &self.subst[*v as usize] {
                Some(t) => self.resolve(t),
                None => t.clone(),
            },
            Set(t) => set(self.resolve(t)),
            Seq(t) => seq(self.resolve(t)),
            Tuple(ts) => Tuple(ts.iter().map(|t| self.resolve(t)).collect()),
            Fn(a, r) => Fn(a.iter().map(|t| self.resolve(t)).collect(), Box::new(self.resolve(r))),
            Map(k, v) => map(self.resolve(k), self.resolve(v)),
            t => t.clone(),
        }
    }

    fn occurs(&self, v: u32, t: &Ty) -> bool {
        match self.resolve(t) {
            Var(w) => v == w,
            Set(t) | Seq(t) => self.occurs(v, &t),
            Tuple(ts) => ts.iter().any(|t| self.occurs(v, t)),
            Fn(a, r) => a.iter().any(|t| self.occurs(v, t)) || self.occurs(v, &r),
            Map(k, w) => self.occurs(v, &k) || self.occurs(v, &w),
            _ => false,
        }
    }

    fn unify_inner(&mut self, a: &Ty, b: &Ty) -> bool {
        let (a, b) = (self.resolve(a), self.resolve(b));
        match (&a, &b) {
            (Any, _) | (_, Any) => true,
            (Var(v), Var(w)) if v == w => true,
            (Var(v), t) | (t, Var(v)) => {
                // A cyclic type is left alone (only ever fewer errors).
                if !self.occurs(*v, t) {
                    self.subst[*v as usize] = Some(t.clone());
                }
                true
            }
            (Set(x), Set(y)) | (Seq(x), Seq(y)) => self.unify_inner(x, y),
            (Map(xk, xv), Map(yk, yv)) => self.unify_inner(xk, yk) && self.unify_inner(xv, yv),
            (Tuple(xs), Tuple(ys)) => xs.len() == ys.len() && xs.iter().zip(ys).all(|(x, y)| self.unify_inner(x, y)),
            (Fn(xa, xr), Fn(ya, yr)) => {
                xa.len() == ya.len()
                    && xa.iter().zip(ya).all(|(x, y)| self.unify_inner(x, y))
                    && self.unify_inner(xr, yr)
            }
            (x, y) => x == y,
        }
    }

    /// Requires `found` to be `want`; reports at `at` otherwise.
    fn unify(&mut self, want: &Ty, found: &Ty, at: TextRange) {
        if !self.unify_inner(want, found) && !self.failed {
            self.failed = true;
            let (w, f) = (show(&self.resolve(want)), show(&self.resolve(found)));
            self.diags.push(Diagnostic::error(Code::Type, at, format!("type error: expected {w}, found {f}")));
        }
    }

    fn instantiate(&mut self, t: &Ty, map: &mut FxHashMap<u32, Ty>) -> Ty {
        match self.resolve(t) {
            Var(v) => map
                .entry(v)
                .or_insert_with(|| {
                    self.subst.push(None);
                    Var(self.subst.len() as u32 - 1)
                })
                .clone(),
            Set(t) => set(self.instantiate(&t, map)),
            Seq(t) => seq(self.instantiate(&t, map)),
            Tuple(ts) => Tuple(ts.iter().map(|t| self.instantiate(t, map)).collect()),
            Fn(a, r) => Fn(a.iter().map(|t| self.instantiate(t, map)).collect(), Box::new(self.instantiate(&r, map))),
            Map(k, v) => Map(Box::new(self.instantiate(&k, map)), Box::new(self.instantiate(&v, map))),
            t => t,
        }
    }

    fn decls(&mut self, decls: &'a [Decl]) {
        self.bind_decls(decls);
        for d in decls {
            let mut names = Vec::new();
            decl_names(d, &mut names);
            if let Some(n) = names.first() {
                self.decl_type(d, n);
            }
            if let DeclKind::Channel(_, Some(e)) = &d.kind {
                self.failed = false;
                self.expr(e);
            }
            if let DeclKind::Module(_, inner) = &d.kind {
                self.decls(inner);
                self.scopes.pop();
            }
        }
    }

    /// Puts the names of `decls` in a new scope (kept: the caller pops it).
    fn bind_decls(&mut self, decls: &'a [Decl]) {
        let mut scope: FxHashMap<String, Bind<'a>> = FxHashMap::default();
        for d in decls {
            match &d.kind {
                DeclKind::Fun(n, _) | DeclKind::Nametype(n, _) => {
                    scope.insert(n.to_string(), Bind::Decl(d));
                }
                DeclKind::PatBind(p, _) => crate::resolve::pat_names(p, &mut |n, _| {
                    if !scope.contains_key(n) {
                        scope.insert(n.to_owned(), Bind::Decl(d));
                    }
                }),
                DeclKind::Channel(ns, ty) => {
                    for (n, _) in ns {
                        self.ctors.insert(n);
                        scope.insert(n.to_string(), Bind::Mono(if ty.is_none() { Event } else { Any }));
                    }
                }
                DeclKind::Datatype(n, cs) => {
                    let plain = cs.iter().all(|c| c.2.is_none());
                    for (c, _, f) in cs {
                        self.ctors.insert(c);
                        scope.insert(c.to_string(), Bind::Mono(if f.is_none() { Data(n.to_string()) } else { Any }));
                    }
                    scope.insert(n.to_string(), Bind::Mono(set(if plain { Data(n.to_string()) } else { Any })));
                }
                DeclKind::Subtype(n, _) => {
                    scope.insert(n.to_string(), Bind::Mono(set(Any)));
                }
                DeclKind::Module(m, inner) => {
                    // Qualified names are not typed (no false errors).
                    let mut sub = Vec::new();
                    for d in inner.iter() {
                        decl_names(d, &mut sub);
                    }
                    for n in sub {
                        scope.insert(format!("{m}::{n}"), Bind::Mono(Any));
                    }
                }
                DeclKind::Assert | DeclKind::Annotation(_) => {}
            }
        }
        self.scopes.push(scope);
    }

    /// The (instantiated) type of a name a declaration defines.
    fn decl_type(&mut self, d: &'a Decl, name: &str) -> Ty {
        let key = d as *const Decl;
        match self.states.get(&key) {
            Some(State::Busy(m)) => return m.get(name).cloned().unwrap_or(Any),
            Some(State::Done(m)) => {
                let t = m.get(name).cloned().unwrap_or(Any);
                // As in libcspm, only top-level definitions are polymorphic.
                if self.local.contains(&key) {
                    return t;
                }
                return self.instantiate(&t, &mut FxHashMap::default());
            }
            None => {}
        }
        let mut names = Vec::new();
        decl_names(d, &mut names);
        let vars: FxHashMap<String, Ty> = names.iter().map(|n| (n.clone(), self.fresh())).collect();
        self.states.insert(key, State::Busy(vars.clone()));
        // An included definition's errors are reported in its own file.
        let saved = std::mem::replace(&mut self.failed, d.foreign);
        // Definitions are checked in the scopes they were written in: the
        // current scopes are those of the use, so restore the definition's
        // scope depth by searching for it.
        let depth = self.scope_of(d);
        let hidden = self.scopes.split_off(depth);
        match &d.kind {
            DeclKind::Fun(n, clauses) => {
                let t = vars.get(&**n).cloned().unwrap_or(Any);
                for c in clauses {
                    self.scopes.push(FxHashMap::default());
                    let mut groups = Vec::new();
                    for g in &c.params {
                        groups.push(g.iter().map(|p| self.pat(p)).collect::<Vec<_>>());
                    }
                    let mut body = self.expr(&c.body);
                    for g in groups.into_iter().rev() {
                        body = Fn(g, Box::new(body));
                    }
                    self.unify(&t, &body, c.body.range);
                    self.scopes.pop();
                }
            }
            DeclKind::PatBind(p, e) => {
                self.scopes.push(FxHashMap::default());
                let pt = self.pat(p);
                let et = self.expr(e);
                self.unify(&pt, &et, e.range);
                let bound: Vec<(String, Ty)> = self
                    .scopes
                    .pop()
                    .unwrap_or_default()
                    .into_iter()
                    .filter_map(|(n, b)| match b {
                        Bind::Mono(t) => Some((n.to_string(), t)),
                        Bind::Decl(_) => None,
                    })
                    .collect();
                for (n, t) in bound {
                    if let Some(v) = vars.get(&n) {
                        self.unify_inner(v, &t);
                    }
                }
            }
            DeclKind::Nametype(n, e) => {
                let t = self.expr(e);
                if let Some(v) = vars.get(&**n) {
                    self.unify_inner(v, &t);
                }
            }
            _ => {}
        }
        self.scopes.extend(hidden);
        self.failed = saved;
        // Every type variable left is generalised: at worst a definition
        // is more polymorphic than in FDR, which only hides errors.
        let done: FxHashMap<String, Ty> = vars.iter().map(|(n, t)| (n.clone(), self.resolve(t))).collect();
        self.states.insert(key, State::Done(done.clone()));
        let t = done.get(name).cloned().unwrap_or(Any);
        if self.local.contains(&key) {
            return t;
        }
        self.instantiate(&t, &mut FxHashMap::default())
    }

    fn scope_of(&self, d: &Decl) -> usize {
        for (i, s) in self.scopes.iter().enumerate().rev() {
            if s.values().any(|b| matches!(b, Bind::Decl(x) if std::ptr::eq(*x, d))) {
                return i + 1;
            }
        }
        self.scopes.len()
    }

    fn lookup(&mut self, n: &str) -> Ty {
        for i in (0..self.scopes.len()).rev() {
            if let Some(b) = self.scopes[i].get(n).cloned() {
                return match b {
                    Bind::Mono(t) => t,
                    Bind::Decl(d) => self.decl_type(d, n),
                };
            }
        }
        self.builtin(n)
    }

    fn builtin(&mut self, n: &str) -> Ty {
        let a = self.fresh();
        let b = self.fresh();
        let mab = map(a.clone(), b.clone());
        let pairs = seq(Tuple(vec![a.clone(), b.clone()]));
        let sa = set(a.clone());
        let qa = seq(a.clone());
        let f = |args: Vec<Ty>, r: Ty| Fn(args, Box::new(r));
        match n {
            "STOP" | "SKIP" | "DIV" => Proc,
            "Events" => set(Event),
            "Int" => set(Int),
            "Bool" => set(Bool),
            "union" | "inter" | "diff" => f(vec![sa.clone(), sa.clone()], sa),
            "Union" | "Inter" => f(vec![set(sa.clone())], sa),
            "member" => f(vec![a, sa], Bool),
            "card" => f(vec![sa], Int),
            "empty" => f(vec![sa], Bool),
            "set" => f(vec![qa], sa),
            "seq" => f(vec![sa], qa),
            "Set" => f(vec![sa.clone()], set(sa)),
            "concat" => f(vec![seq(qa.clone())], qa),
            "head" => f(vec![qa], a),
            "tail" => f(vec![qa.clone()], qa),
            "length" => f(vec![qa], Int),
            "null" => f(vec![qa], Bool),
            "elem" => f(vec![a, qa], Bool),
            "show" => f(vec![a], seq(Char)),
            "RUN" | "CHAOS" => f(vec![set(Event)], Proc),
            "prioritise" | "prioritise_nocache" => f(vec![Proc, seq(set(Event))], Proc),
            "WAIT" => f(vec![Int], Proc),
            "emptyMap" => mab,
            "mapFromList" => f(vec![pairs], mab),
            "mapToList" => f(vec![mab], pairs),
            "mapLookup" => f(vec![mab, a], b),
            "mapMember" => f(vec![mab, a], Bool),
            "mapUpdate" => f(vec![mab.clone(), a, b], mab),
            "mapUpdateMultiple" => f(vec![mab.clone(), pairs], mab),
            "mapDelete" => f(vec![mab.clone(), a], mab),
            "Map" => f(vec![set(a), set(b)], set(mab)),
            "timed_priority" | "loop" | "dbisim" | "sbisim" | "wbisim" | "diamond" | "normal" | "normalise"
            | "normalize" | "explicate" | "lazyenumerate" | "chase" | "chase_nocache" | "deter" | "model_compress"
            | "tau_loop_factor" | "lazynorm" => f(vec![Proc], Proc),
            _ => Any,
        }
    }

    /// Processes and functions cannot be compared, nor be set elements.
    fn comparable(&mut self, t: &Ty, at: TextRange) {
        fn bad(t: &Ty) -> bool {
            match t {
                Proc | Fn(..) => true,
                Set(t) | Seq(t) => bad(t),
                Map(k, v) => bad(k) || bad(v),
                Tuple(ts) => ts.iter().any(bad),
                _ => false,
            }
        }
        let t = self.resolve(t);
        if bad(&t) && !self.failed {
            self.failed = true;
            self.diags.push(Diagnostic::error(
                Code::Type,
                at,
                format!("type error: {} cannot be compared or put in a set", show(&t)),
            ));
        }
    }

    fn bind_mono(&mut self, n: &'a str, t: Ty) {
        if let Some(s) = self.scopes.last_mut() {
            s.insert(n.to_owned(), Bind::Mono(t));
        }
    }

    fn pat(&mut self, p: &'a Pat) -> Ty {
        match p {
            Pat::Wild => self.fresh(),
            Pat::Name(n, _) => {
                // A constructor or channel is matched, not bound.
                if self.ctors.contains(&**n) {
                    return self.lookup(n);
                }
                let t = self.fresh();
                self.bind_mono(n, t.clone());
                t
            }
            Pat::Int(_) => Int,
            Pat::Bool(_) => Bool,
            Pat::Char(_) => Char,
            Pat::Str(_) => seq(Char),
            Pat::Tuple(ps) => Tuple(ps.iter().map(|p| self.pat(p)).collect()),
            Pat::Seq(ps) => {
                let a = self.fresh();
                for p in ps {
                    let t = self.pat(p);
                    self.unify_inner(&a, &t);
                }
                seq(a)
            }
            Pat::Set(ps) => {
                let a = self.fresh();
                for p in ps {
                    let t = self.pat(p);
                    self.unify_inner(&a, &t);
                }
                set(a)
            }
            Pat::Concat(x, y) => {
                let (tx, ty) = (self.pat(x), self.pat(y));
                let a = seq(self.fresh());
                self.unify_inner(&a, &tx);
                self.unify_inner(&a, &ty);
                a
            }
            Pat::Dot(x, y) => {
                self.dot_pat(x);
                self.dot_pat(y);
                Any
            }
            Pat::Double(x, y) => {
                let (tx, ty) = (self.pat(x), self.pat(y));
                self.unify_inner(&tx, &ty);
                tx
            }
        }
    }

    /// Names inside dotted patterns get the wildcard type.
    fn dot_pat(&mut self, p: &'a Pat) {
        let mut names = Vec::new();
        crate::resolve::pat_names(p, &mut |n, _| names.push(leak(p, n)));
        for n in names {
            if !self.ctors.contains(n) {
                self.bind_mono(n, Any);
            }
        }
    }

    /// Statements: generators bind their patterns in a new scope (popped
    /// by the caller); `seq` tells whether generators draw from sequences.
    fn stmts(&mut self, stmts: &'a [Stmt], seq_gen: bool) {
        self.scopes.push(FxHashMap::default());
        for s in stmts {
            match s {
                Stmt::Pred(e) => {
                    let t = self.expr(e);
                    self.unify(&Bool, &t, e.range);
                }
                Stmt::Gen(p, e) => {
                    let t = self.expr(e);
                    let elem = self.fresh();
                    let want = if seq_gen { seq(elem.clone()) } else { set(elem.clone()) };
                    self.unify(&want, &t, e.range);
                    let pt = self.pat(p);
                    self.unify_inner(&elem, &pt);
                }
            }
        }
    }

    fn want(&mut self, want: Ty, e: &'a Expr) {
        let t = self.expr(e);
        self.unify(&want, &t, e.range);
    }

    fn expr(&mut self, e: &'a Expr) -> Ty {
        use ExprKind::*;
        if self.stack.exceeded() {
            return Any;
        }
        match &e.kind {
            ExprKind::Int(_) => Ty::Int,
            ExprKind::Bool(_) => Ty::Bool,
            ExprKind::Char(_) => Ty::Char,
            Str(_) => seq(Ty::Char),
            Var(n) => self.lookup(n),
            ExprKind::Tuple(es) => Ty::Tuple(es.iter().map(|e| self.expr(e)).collect()),
            App(f, args) => {
                let ft = self.expr(f);
                let ats: Vec<Ty> = args.iter().map(|a| self.expr(a)).collect();
                let r = self.fresh();
                self.unify(&ft, &Fn(ats, Box::new(r.clone())), e.range);
                // A map's keys are compared (FDR's `Set k` on every map).
                if let Ty::Map(k, _) = self.resolve(&r) {
                    self.comparable(&k, e.range);
                }
                r
            }
            Bin(op, a, b) => match op {
                BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Mod => {
                    self.want(Ty::Int, a);
                    self.want(Ty::Int, b);
                    Ty::Int
                }
                BinOp::And | BinOp::Or => {
                    self.want(Ty::Bool, a);
                    self.want(Ty::Bool, b);
                    Ty::Bool
                }
                BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                    let ta = self.expr(a);
                    let tb = self.expr(b);
                    self.unify(&ta, &tb, b.range);
                    self.comparable(&ta, e.range);
                    Ty::Bool
                }
                BinOp::Concat => {
                    let t = seq(self.fresh());
                    self.want(t.clone(), a);
                    self.want(t.clone(), b);
                    t
                }
                BinOp::Dot => {
                    self.expr(a);
                    self.expr(b);
                    Any
                }
            },
            Un(op, a) => match op {
                UnOp::Not => {
                    self.want(Ty::Bool, a);
                    Ty::Bool
                }
                UnOp::Neg => {
                    self.want(Ty::Int, a);
                    Ty::Int
                }
                UnOp::Len => {
                    let t = seq(self.fresh());
                    self.want(t, a);
                    Ty::Int
                }
            },
            ExprKind::Set(es) | ExprKind::Seq(es) => {
                let a = self.fresh();
                for x in es {
                    self.want(a.clone(), x);
                }
                if matches!(e.kind, ExprKind::Set(_)) {
                    set(a)
                } else {
                    seq(a)
                }
            }
            SetRange(a, b) | SeqRange(a, b) => {
                self.want(Ty::Int, a);
                if let Some(b) = b {
                    self.want(Ty::Int, b);
                }
                if matches!(e.kind, SetRange(..)) {
                    set(Ty::Int)
                } else {
                    seq(Ty::Int)
                }
            }
            SetComp(x, stmts) | SeqComp(x, stmts) => {
                let is_seq = matches!(e.kind, SeqComp(..));
                self.stmts(stmts, is_seq);
                let t = self.expr(x);
                self.scopes.pop();
                // A range element (`{a..b | …}`) is already a collection.
                match (&x.kind, is_seq) {
                    (SetRange(..), false) | (SeqRange(..), true) => t,
                    (_, false) => set(t),
                    (_, true) => seq(t),
                }
            }
            Closure(es, stmts) => {
                self.stmts(stmts, false);
                for x in es {
                    self.expr(x);
                }
                self.scopes.pop();
                set(Event)
            }
            Map(kvs) => {
                let (kt, vt) = (self.fresh(), self.fresh());
                for (k, v) in kvs {
                    self.want(kt.clone(), k);
                    self.want(vt.clone(), v);
                }
                self.comparable(&kt, e.range);
                map(kt, vt)
            }
            Let(decls, body) => {
                // Definitions with a type annotation may be polymorphic.
                let annotated: Vec<&str> = decls
                    .iter()
                    .flat_map(|d| match &d.kind {
                        DeclKind::Annotation(ns) => ns.iter().map(|n| &**n).collect(),
                        _ => Vec::new(),
                    })
                    .collect();
                self.local.extend(
                    decls
                        .iter()
                        .filter(|d| !matches!(&d.kind, DeclKind::Fun(n, _) if annotated.contains(&&**n)))
                        .map(|d| d as *const Decl),
                );
                self.bind_decls(decls);
                for d in decls.iter() {
                    let mut names = Vec::new();
                    decl_names(d, &mut names);
                    if let Some(n) = names.first() {
                        self.decl_type(d, n);
                    }
                }
                let t = self.expr(body);
                self.scopes.pop();
                t
            }
            If(c, a, b) => {
                self.want(Ty::Bool, c);
                let t = self.expr(a);
                self.want(t.clone(), b);
                t
            }
            Lambda(pats, body) => {
                self.scopes.push(FxHashMap::default());
                let ps = pats.iter().map(|p| self.pat(p)).collect();
                let r = self.expr(body);
                self.scopes.pop();
                Fn(ps, Box::new(r))
            }
            Prefix(ev, fields, body) => {
                self.expr(ev);
                self.scopes.push(FxHashMap::default());
                for f in fields {
                    match f {
                        Field::Output(x) => {
                            self.expr(x);
                        }
                        Field::Input(p, s) | Field::NonDet(p, s) => {
                            let pt = if matches!(p, Pat::Dot(..)) {
                                self.dot_pat(p);
                                Any
                            } else {
                                self.pat(p)
                            };
                            if let Some(s) = s {
                                self.want(set(pt), s);
                            }
                        }
                    }
                }
                self.want(Ty::Proc, body);
                self.scopes.pop();
                Ty::Proc
            }
            Guard(b, p) => {
                self.want(Ty::Bool, b);
                self.want(Ty::Proc, p);
                Ty::Proc
            }
            ExprKind::Proc(_, a, b) => {
                self.want(Ty::Proc, a);
                self.want(Ty::Proc, b);
                Ty::Proc
            }
            Hide(p, s) | Project(p, s) => {
                self.want(Ty::Proc, p);
                self.want(set(Event), s);
                Ty::Proc
            }
            SetProc(_, a, s, b) => {
                self.want(Ty::Proc, a);
                self.want(set(Event), s);
                self.want(Ty::Proc, b);
                Ty::Proc
            }
            AlphaPar(a, x, y, b) => {
                self.want(Ty::Proc, a);
                self.want(set(Event), x);
                self.want(set(Event), y);
                self.want(Ty::Proc, b);
                Ty::Proc
            }
            LinkPar(a, links, stmts, b) => {
                self.want(Ty::Proc, a);
                self.want(Ty::Proc, b);
                self.stmts(stmts, false);
                for (x, y) in links {
                    self.expr(x);
                    self.expr(y);
                }
                self.scopes.pop();
                Ty::Proc
            }
            Rename(p, pairs, stmts) => {
                self.want(Ty::Proc, p);
                self.stmts(stmts, false);
                for (x, y) in pairs {
                    self.expr(x);
                    self.expr(y);
                }
                self.scopes.pop();
                Ty::Proc
            }
            Replicated(op, stmts, body) => {
                if let RepOp::GenPar(a) | RepOp::SyncExt(a) = op {
                    self.want(set(Event), a);
                }
                self.stmts(stmts, matches!(op, RepOp::Seq | RepOp::Link(..)));
                match op {
                    RepOp::AlphaPar(a) => self.want(set(Event), a),
                    RepOp::Link(links, s) => {
                        self.stmts(s, false);
                        for (x, y) in links {
                            self.expr(x);
                            self.expr(y);
                        }
                        self.scopes.pop();
                    }
                    _ => {}
                }
                self.want(Ty::Proc, body);
                self.scopes.pop();
                Ty::Proc
            }
            Error => Any,
        }
    }
}

/// A name of a pattern, with the pattern's lifetime.
fn leak<'a>(p: &'a Pat, n: &str) -> &'a str {
    fn find<'a>(p: &'a Pat, n: &str) -> Option<&'a str> {
        match p {
            Pat::Name(m, _) if &**m == n => Some(m),
            Pat::Tuple(ps) | Pat::Seq(ps) | Pat::Set(ps) => ps.iter().find_map(|p| find(p, n)),
            Pat::Dot(a, b) | Pat::Concat(a, b) | Pat::Double(a, b) => find(a, n).or_else(|| find(b, n)),
            _ => None,
        }
    }
    find(p, n).unwrap_or("")
}

fn decl_names(d: &Decl, out: &mut Vec<String>) {
    match &d.kind {
        DeclKind::Fun(n, _) | DeclKind::Nametype(n, _) => out.push(n.to_string()),
        DeclKind::PatBind(p, _) => crate::resolve::pat_names(p, &mut |n, _| out.push(n.to_owned())),
        _ => {}
    }
}

fn show(t: &Ty) -> String {
    match t {
        Var(_) | Any => "a value".to_owned(),
        Int => "Int".to_owned(),
        Bool => "Bool".to_owned(),
        Char => "Char".to_owned(),
        Event => "an event".to_owned(),
        Proc => "a process".to_owned(),
        Data(n) => format!("a value of datatype `{n}`"),
        Set(t) => format!("a set of {}", show_inner(t)),
        Seq(t) => format!("a sequence of {}", show_inner(t)),
        Tuple(ts) => format!("a tuple ({})", ts.iter().map(show_inner).collect::<Vec<_>>().join(", ")),
        Fn(a, r) => format!("a function of {} argument(s) returning {}", a.len(), show(r)),
        Map(k, v) => format!("a map from {} to {}", show_inner(k), show_inner(v)),
    }
}

fn show_inner(t: &Ty) -> String {
    match t {
        Var(_) | Any => "values".to_owned(),
        Int | Bool | Char => show(t),
        Event => "events".to_owned(),
        Proc => "processes".to_owned(),
        t => show(t),
    }
}
