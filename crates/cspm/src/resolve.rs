//! Name resolution: every name a text uses must be defined by the text
//! (top level, `let`, parameters, generators, input fields), by the model
//! through [`NameLookup`], or be a built-in. Unresolved and duplicate
//! names are diagnostics at their ranges.

use rustc_hash::{FxHashMap, FxHashSet};

use crate::ast::{Decl, DeclKind, Expr, ExprKind, Field, Pat, RepOp, Stmt};
use crate::{Code, Diagnostic, TextRange, Value};

/// Builds the LTS of an external process from its arguments (none for a
/// process name); the error is a message for the caller of the process.
pub type BuildLts = std::rc::Rc<dyn Fn(&[Value]) -> Result<crate::Lts, String>>;

/// A name supplied from outside the text (the model's channels, constants
/// and processes, for the bridge to the native engine).
#[derive(Clone)]
pub enum ExternalName {
    /// A channel and the value sets of its fields, in order (empty for a
    /// channel without data).
    Channel(Vec<Vec<Value>>),
    /// A constant, a set (a type), a function-free value.
    Value(Value),
    /// A process given as an explicit LTS (e.g. a model element compiled by
    /// the native engine): `arity` arguments (0 for a plain name) are
    /// passed to `build`. The events of the LTS are given by
    /// [`crate::Lts::event_values`], on channels this lookup also knows.
    Process {
        /// How many arguments the process takes.
        arity: usize,
        /// Builds its LTS.
        build: BuildLts,
    },
}

impl std::fmt::Debug for ExternalName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExternalName::Channel(fields) => f.debug_tuple("Channel").field(fields).finish(),
            ExternalName::Value(v) => f.debug_tuple("Value").field(v).finish(),
            ExternalName::Process { arity, .. } => f.debug_struct("Process").field("arity", arity).finish(),
        }
    }
}

/// The hook through which names a text does not define are supplied.
pub trait NameLookup {
    /// The meaning of `name` (as written, e.g. `M::e` or `const_M_x`), if
    /// the host knows it.
    fn lookup(&self, name: &str) -> Option<ExternalName>;
}

/// No names from outside: only the text and the built-ins.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoNames;

impl NameLookup for NoNames {
    fn lookup(&self, _: &str) -> Option<ExternalName> {
        None
    }
}

/// Every name of a pattern that binds (constructors are filtered later).
pub(crate) fn pat_names(p: &Pat, f: &mut dyn FnMut(&str, TextRange)) {
    match p {
        Pat::Name(n, r) => f(n, *r),
        Pat::Tuple(ps) | Pat::Seq(ps) | Pat::Set(ps) => ps.iter().for_each(|p| pat_names(p, f)),
        Pat::Dot(a, b) | Pat::Concat(a, b) | Pat::Double(a, b) => {
            pat_names(a, f);
            pat_names(b, f);
        }
        _ => {}
    }
}

/// Names declared by a declaration (with whether they are constructors,
/// which patterns match rather than bind).
fn decl_names(d: &Decl, out: &mut Vec<(String, TextRange, bool)>, ctors: &FxHashSet<String>) {
    match &d.kind {
        DeclKind::Fun(n, _) | DeclKind::Nametype(n, _) => out.push((n.to_string(), d.name_range, false)),
        DeclKind::PatBind(p, _) => pat_names(p, &mut |n, r| {
            if !ctors.contains(n) {
                out.push((n.to_string(), r, false))
            }
        }),
        DeclKind::Channel(ns, _) => out.extend(ns.iter().map(|(n, r)| (n.to_string(), *r, true))),
        DeclKind::Datatype(n, cs) | DeclKind::Subtype(n, cs) => {
            out.push((n.to_string(), d.name_range, false));
            if matches!(d.kind, DeclKind::Datatype(..)) {
                out.extend(cs.iter().map(|(c, r, _)| (c.to_string(), *r, true)));
            }
        }
        DeclKind::Module(m, inner) => {
            let mut sub = Vec::new();
            for d in inner.iter() {
                decl_names(d, &mut sub, ctors);
            }
            out.extend(sub.into_iter().map(|(n, r, c)| (format!("{m}::{n}"), r, c)));
        }
        DeclKind::Assert | DeclKind::Annotation(_) => {}
    }
}

struct Resolver<'a> {
    scopes: Vec<FxHashSet<String>>,
    ctors: FxHashSet<String>,
    names: &'a dyn crate::NameLookup,
    diags: &'a mut Vec<Diagnostic>,
    cache: FxHashMap<String, bool>,
    /// Inside a definition of a `Timed` section.
    timed: bool,
    stack: crate::stack::StackGuard,
}

pub(crate) fn resolve(decls: &[Decl], names: &dyn crate::NameLookup, diags: &mut Vec<Diagnostic>) {
    let mut ctors = FxHashSet::default();
    collect_ctors(decls, &mut ctors);
    let mut r = Resolver {
        scopes: Vec::new(),
        ctors,
        names,
        diags,
        cache: FxHashMap::default(),
        timed: false,
        stack: crate::stack::StackGuard::new(crate::stack::STATIC_PASS_STACK),
    };
    r.decls(decls, true);
}

fn collect_ctors(decls: &[Decl], ctors: &mut FxHashSet<String>) {
    for d in decls {
        match &d.kind {
            DeclKind::Module(m, inner) => {
                let mut sub = FxHashSet::default();
                collect_ctors(inner, &mut sub);
                ctors.extend(sub.iter().map(|c| format!("{m}::{c}")));
                ctors.extend(sub);
            }
            DeclKind::Channel(ns, _) => ctors.extend(ns.iter().map(|(n, _)| n.to_string())),
            DeclKind::Datatype(_, cs) => ctors.extend(cs.iter().map(|(c, _, _)| c.to_string())),
            _ => {}
        }
    }
}

impl Resolver<'_> {
    fn is_ctor(&mut self, n: &str) -> bool {
        if self.ctors.contains(n) {
            return true;
        }
        if self.scopes.iter().any(|s| s.contains(n)) {
            return false;
        }
        let names = self.names;
        *self.cache.entry(n.to_owned()).or_insert_with(|| {
            matches!(names.lookup(n), Some(ExternalName::Channel(_) | ExternalName::Value(Value::Ctor(_))))
                || matches!(n, "true" | "false")
        })
    }

    fn defined(&mut self, n: &str) -> bool {
        self.scopes.iter().any(|s| s.contains(n)) || self.ctors.contains(n) || crate::builtins::is_builtin(n) || {
            let names = self.names;
            *self.cache.entry(n.to_owned()).or_insert_with(|| names.lookup(n).is_some())
        }
    }

    fn decls(&mut self, decls: &[Decl], top: bool) {
        let mut local_ctors = FxHashSet::default();
        if !top {
            collect_ctors(decls, &mut local_ctors);
            self.ctors.extend(local_ctors.iter().cloned());
        }
        let mut names = Vec::new();
        for d in decls {
            let ctors = self.ctors.clone();
            decl_names(d, &mut names, &ctors);
        }
        let mut scope = FxHashSet::default();
        for (n, r, _) in &names {
            if !scope.insert(n.clone()) {
                self.diags.push(Diagnostic::error(
                    Code::Duplicate,
                    *r,
                    format!("`{n}` is defined more than once here"),
                ));
            }
        }
        self.scopes.push(scope);
        for d in decls {
            self.decl(d);
        }
        // Top-level scope stays for nothing after; locals are popped.
        self.scopes.pop();
    }

    fn decl(&mut self, d: &Decl) {
        if d.foreign {
            return;
        }
        let saved = self.timed;
        self.timed |= d.timed.is_some();
        self.decl_inner(d);
        self.timed = saved;
    }

    fn decl_inner(&mut self, d: &Decl) {
        if let Some(t) = &d.timed {
            if let Some(f) = &t.f {
                self.expr(f);
            }
            if !self.defined("tock") {
                self.diags.push(Diagnostic::error(
                    Code::Unresolved,
                    t.range,
                    "a `Timed` section needs a channel `tock` to be declared",
                ));
            }
        }
        match &d.kind {
            DeclKind::Fun(_, clauses) => {
                for c in clauses {
                    let mut scope = FxHashSet::default();
                    for group in &c.params {
                        for p in group {
                            self.bind_pat(p, &mut scope);
                        }
                    }
                    self.scopes.push(scope);
                    self.expr(&c.body);
                    self.scopes.pop();
                }
            }
            DeclKind::PatBind(_, e) => self.expr(e),
            DeclKind::Channel(_, Some(e)) | DeclKind::Nametype(_, e) => self.expr(e),
            DeclKind::Datatype(_, cs) | DeclKind::Subtype(_, cs) => {
                for (_, _, e) in cs {
                    if let Some(e) = e {
                        self.expr(e);
                    }
                }
            }
            DeclKind::Module(_, inner) => self.decls(inner, false),
            DeclKind::Channel(_, None) | DeclKind::Assert | DeclKind::Annotation(_) => {}
        }
    }

    /// Adds the names `p` binds to `scope`; checks the constants it matches.
    fn bind_pat(&mut self, p: &Pat, scope: &mut FxHashSet<String>) {
        let mut bound = Vec::new();
        pat_names(p, &mut |n, r| bound.push((n.to_owned(), r)));
        for (n, r) in bound {
            if self.is_ctor(&n) {
                continue;
            }
            if !scope.insert(n.clone()) {
                self.diags.push(Diagnostic::error(Code::Duplicate, r, format!("`{n}` is bound twice in this pattern")));
            }
        }
    }

    /// Reports a name `p` binds that an earlier generator or input of the
    /// same list already bound.
    fn no_rebinding(&mut self, p: &Pat, all: &mut FxHashSet<String>) {
        let mut bound = Vec::new();
        pat_names(p, &mut |n, r| bound.push((n.to_owned(), r)));
        for (n, r) in bound {
            if self.is_ctor(&n) {
                continue;
            }
            if !all.insert(n.clone()) {
                self.diags.push(Diagnostic::error(
                    Code::Duplicate,
                    r,
                    format!("`{n}` is already bound earlier in this list"),
                ));
            }
        }
    }

    fn stmts_then(&mut self, stmts: &[Stmt], then: &mut dyn FnMut(&mut Self)) {
        let depth = self.scopes.len();
        // One name is bound once per statement list (as in FDR).
        let mut all = FxHashSet::default();
        for s in stmts {
            match s {
                Stmt::Gen(p, e) => {
                    self.expr(e);
                    let mut scope = FxHashSet::default();
                    self.bind_pat(p, &mut scope);
                    self.no_rebinding(p, &mut all);
                    self.scopes.push(scope);
                }
                Stmt::Pred(e) => self.expr(e),
            }
        }
        then(self);
        self.scopes.truncate(depth);
    }

    fn expr(&mut self, e: &Expr) {
        use ExprKind::*;
        if self.stack.exceeded() {
            return; // Lowering already reported the nesting.
        }
        match &e.kind {
            Int(_) | Bool(_) | Char(_) | Str(_) | Error => {}
            Var(n)
                if matches!(&**n, "WAIT" | "timed_priority")
                    && !self.timed
                    && !self.scopes.iter().any(|s| s.contains(&**n)) =>
            {
                self.diags.push(Diagnostic::error(
                    Code::Unresolved,
                    e.range,
                    format!("`{n}` is only defined inside a `Timed` section"),
                ));
            }
            Var(n) => {
                if !self.defined(n) {
                    self.diags.push(Diagnostic::error(Code::Unresolved, e.range, format!("`{n}` is not defined")));
                }
            }
            Tuple(es) | Set(es) | Seq(es) => es.iter().for_each(|e| self.expr(e)),
            App(f, args) => {
                self.expr(f);
                args.iter().for_each(|e| self.expr(e));
            }
            Bin(_, a, b) | Proc(_, a, b) | Hide(a, b) | Project(a, b) | Guard(a, b) => {
                self.expr(a);
                self.expr(b);
            }
            Un(_, a) => self.expr(a),
            SetRange(a, b) | SeqRange(a, b) => {
                self.expr(a);
                if let Some(b) = b {
                    self.expr(b);
                }
            }
            SetComp(x, stmts) | SeqComp(x, stmts) => self.stmts_then(stmts, &mut |r| r.expr(x)),
            Closure(es, stmts) => self.stmts_then(stmts, &mut |r| es.iter().for_each(|e| r.expr(e))),
            Map(kvs) => kvs.iter().for_each(|(k, v)| {
                self.expr(k);
                self.expr(v);
            }),
            Let(decls, body) => {
                let saved = self.ctors.clone();
                let mut names = Vec::new();
                collect_ctors(decls, &mut self.ctors);
                for d in decls.iter() {
                    let ctors = self.ctors.clone();
                    decl_names(d, &mut names, &ctors);
                }
                self.decls(decls, false);
                self.scopes.push(names.into_iter().map(|(n, _, _)| n).collect());
                self.expr(body);
                self.scopes.pop();
                self.ctors = saved;
            }
            If(a, b, c) | SetProc(_, a, b, c) => {
                self.expr(a);
                self.expr(b);
                self.expr(c);
            }
            AlphaPar(a, b, c, d) => [a, b, c, d].iter().for_each(|e| self.expr(e)),
            Lambda(pats, body) => {
                let mut scope = FxHashSet::default();
                pats.iter().for_each(|p| self.bind_pat(p, &mut scope));
                self.scopes.push(scope);
                self.expr(body);
                self.scopes.pop();
            }
            Prefix(ev, fields, body) => {
                self.expr(ev);
                let depth = self.scopes.len();
                let mut all = FxHashSet::default();
                for f in fields {
                    match f {
                        Field::Output(e) => self.expr(e),
                        Field::Input(p, s) | Field::NonDet(p, s) => {
                            if let Some(s) = s {
                                self.expr(s);
                            }
                            let mut scope = FxHashSet::default();
                            self.bind_pat(p, &mut scope);
                            self.no_rebinding(p, &mut all);
                            self.scopes.push(scope);
                        }
                    }
                }
                self.expr(body);
                self.scopes.truncate(depth);
            }
            LinkPar(a, links, stmts, b) => {
                self.expr(a);
                self.expr(b);
                self.stmts_then(stmts, &mut |r| {
                    links.iter().for_each(|(x, y)| {
                        r.expr(x);
                        r.expr(y);
                    })
                });
            }
            Rename(p, pairs, stmts) => {
                self.expr(p);
                self.stmts_then(stmts, &mut |r| {
                    pairs.iter().for_each(|(x, y)| {
                        r.expr(x);
                        r.expr(y);
                    })
                });
            }
            Replicated(op, stmts, body) => {
                if let RepOp::GenPar(a) | RepOp::SyncExt(a) = op {
                    self.expr(a);
                }
                self.stmts_then(stmts, &mut |r| {
                    match op {
                        RepOp::AlphaPar(a) => r.expr(a),
                        RepOp::Link(links, s) => r.stmts_then(s, &mut |r| {
                            links.iter().for_each(|(x, y)| {
                                r.expr(x);
                                r.expr(y);
                            })
                        }),
                        _ => {}
                    }
                    r.expr(body);
                });
            }
        }
    }
}
