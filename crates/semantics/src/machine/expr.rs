//! Expressions: the model's expressions as CSPm values, in the memory or the behaviour.

use super::*;

impl<'e, 'a> Gen<'e, 'a> {
    pub(super) fn expr(&mut self, e: &m::Expr, cx: ECtx, want: Option<&Ty>) -> Option<EOut> {
        if self.nesting >= MAX_NESTING {
            self.problem(e.range, "this expression is nested too deeply for the export");
            return None;
        }
        self.nesting += 1;
        let out = self.expr_inner(e, cx, want);
        self.nesting -= 1;
        out
    }

    pub(super) fn expr_inner(&mut self, e: &m::Expr, cx: ECtx, want: Option<&Ty>) -> Option<EOut> {
        let r = e.range;
        match &e.kind {
            m::ExprKind::Int(Some(v)) => Some(EOut { e: Expr::Int(*v), ty: Ty::Nat, pure: true }),
            m::ExprKind::Int(None) => {
                self.problem(r, "this number is too large");
                None
            }
            m::ExprKind::Bool(b) => Some(EOut { e: Expr::Bool(*b), ty: Ty::Bool, pure: true }),
            m::ExprKind::Real(text) => {
                let v: f64 = text.parse().unwrap_or(f64::NAN);
                if v.fract() == 0.0 && v.abs() < 1e15 {
                    Some(EOut { e: Expr::Int(v as i64), ty: Ty::Real, pure: true })
                } else {
                    self.problem(r, "real numbers with a fractional part are not supported (reals are bounded integers, as in RoboTool)");
                    None
                }
            }
            m::ExprKind::Name { name: n, .. } => {
                let n = n.clone();
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
            m::ExprKind::EnumLiteral { path: en, literal: lit, .. } => {
                let found = m::resolve(self.ex.db, self.ex.ws, self.file, en, DefKind::Enumeration)
                    .and_then(|loc| Some((loc.file, loc.def(self.ex.db)?)));
                let Some((ef, eid)) = found else {
                    self.problem(r, "the enumeration could not be resolved");
                    return None;
                };
                let (dt, lits) = self.ex.enumeration(ef, eid);
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
            m::ExprKind::Since(_) | m::ExprKind::SinceEntry(_) => {
                if !self.timed() {
                    let clock = match &e.kind {
                        m::ExprKind::Since(n) => n.clone(),
                        m::ExprKind::SinceEntry(p) => format!("sinceEntry({})", p.join("::")),
                        _ => String::new(),
                    };
                    self.clock_read_refused(r, &clock);
                    return None;
                }
                let i = match &e.kind {
                    m::ExprKind::Since(n) => match self.names.get(n) {
                        Some(Nm::Clock(i)) => *i,
                        _ => {
                            self.problem(r, format!("`{n}` is not a clock"));
                            return None;
                        }
                    },
                    m::ExprKind::SinceEntry(p) => {
                        let n = p.last().cloned().unwrap_or_default();
                        let Some(s) = self.nodes.iter().position(|x| x.name == n && x.kind == NodeKind::State) else {
                            let what = self.what();
                            self.problem(r, format!("`{n}` is not a state of the {what}"));
                            return None;
                        };
                        self.since_entry_clock(s)
                    }
                    _ => return None,
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
            m::ExprKind::SimRef { path, input, sync } => {
                let n = path.join("::");
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
                if let Some((var, vr)) = input {
                    let var = var.join("::");
                    match self.names.get(&var) {
                        Some(Nm::Var(v)) if self.events[i].ty.is_some() => self.binds.push((*v, i)),
                        _ => {
                            self.problem(*vr, format!("`{var}` cannot receive the value of `${n}`"));
                            return None;
                        }
                    }
                }
                if sync.is_some() {
                    self.problem(r, "`$e.v` in guards is not supported by the export yet");
                    return None;
                }
                Some(EOut { e: name(self.events[i].csp.clone()), ty: Ty::Bool, pure: false })
            }
            m::ExprKind::Unary(op, inner) => {
                if matches!(inner.kind, m::ExprKind::Missing) {
                    return None;
                }
                let x = self.expr(inner, cx, want)?;
                match op {
                    m::UnOp::Not => Some(EOut { e: Expr::Not(Box::new(x.e)), ty: Ty::Bool, pure: x.pure }),
                    m::UnOp::Neg => match x.e {
                        Expr::Int(v) => Some(EOut { e: Expr::Int(-v), ty: Ty::Int, pure: true }),
                        ex => {
                            let t = if x.ty == Ty::Nat { Ty::Int } else { x.ty.clone() };
                            Some(EOut { e: call("Neg", vec![ex, t.set()]), ty: t, pure: x.pure })
                        }
                    },
                    m::UnOp::Other => {
                        self.problem(r, "this operator is not supported by the export yet");
                        None
                    }
                }
            }
            m::ExprKind::Binary(op, a, b) => {
                if matches!(a.kind, m::ExprKind::Missing) || matches!(b.kind, m::ExprKind::Missing) {
                    self.problem(r, "an incomplete expression");
                    return None;
                }
                let op = *op;
                // `BinOp::Other` is `^`, the one binary operator the model
                // does not name.
                if matches!(op, m::BinOp::In | m::BinOp::Cat | m::BinOp::Other) {
                    return self.collection_op(op, a, b, cx, want);
                }
                let arith = matches!(op, m::BinOp::Add | m::BinOp::Sub | m::BinOp::Mul | m::BinOp::Div | m::BinOp::Mod);
                let x = self.expr(a, cx, if arith { want } else { None })?;
                let y = self.expr(b, cx, if arith { want } else { None })?;
                let pure = x.pure && y.pure;
                if op.is_comparison() {
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
                    m::BinOp::Add => sticky("Plus", false),
                    m::BinOp::Sub => sticky("Minus", true),
                    m::BinOp::Mul => sticky("Mult", false),
                    m::BinOp::Div => sticky("Div", false),
                    m::BinOp::Mod => sticky("Modulus", false),
                    m::BinOp::Eq => cmp(BinOp::Eq),
                    m::BinOp::Ne => cmp(BinOp::Ne),
                    m::BinOp::Lt => cmp(BinOp::Lt),
                    m::BinOp::Le => cmp(BinOp::Le),
                    m::BinOp::Gt => cmp(BinOp::Gt),
                    m::BinOp::Ge => cmp(BinOp::Ge),
                    m::BinOp::And => cmp(BinOp::And),
                    m::BinOp::Or => cmp(BinOp::Or),
                    m::BinOp::Implies => {
                        Some(EOut { e: bin(BinOp::Or, Expr::Not(Box::new(x.e)), y.e), ty: Ty::Bool, pure })
                    }
                    m::BinOp::Iff => cmp(BinOp::Eq),
                    m::BinOp::In | m::BinOp::Cat | m::BinOp::Other => None,
                }
            }
            m::ExprKind::If(c, a, b) => {
                if [c, a, b].iter().any(|x| matches!(x.kind, m::ExprKind::Missing)) {
                    self.problem(r, "an incomplete conditional");
                    return None;
                }
                let c = self.expr(c, cx, None)?;
                let a = self.expr(a, cx, want)?;
                let b = self.expr(b, cx, want)?;
                let pure = c.pure && a.pure && b.pure;
                Some(EOut { e: Expr::If(Box::new(c.e), Box::new(a.e), Box::new(b.e)), ty: a.ty, pure })
            }
            m::ExprKind::Set(items) | m::ExprKind::Seq(items) => {
                let elem_want = match want {
                    Some(Ty::Set(t)) | Some(Ty::Seq(t)) => Some((**t).clone()),
                    _ => None,
                };
                let mut es = Vec::new();
                let mut elem = elem_want.clone();
                let mut pure = true;
                for x in items {
                    let o = self.expr(x, cx, elem_want.as_ref())?;
                    pure &= o.pure;
                    es.push(o.e);
                    elem.get_or_insert(o.ty);
                }
                // Unknown element type (an empty literal without context):
                // it only matters for arithmetic and projections.
                let elem = Box::new(elem.unwrap_or(Ty::Nat));
                if matches!(e.kind, m::ExprKind::Set(_)) {
                    Some(EOut { e: Expr::Set(es), ty: Ty::Set(elem), pure })
                } else {
                    self.ex.seq_literal_max = self.ex.seq_literal_max.max(es.len() as i64);
                    Some(EOut { e: Expr::SeqLit(es), ty: Ty::Seq(elem), pure })
                }
            }
            m::ExprKind::SetRange(lo, hi) => {
                if matches!(lo.kind, m::ExprKind::Missing) || matches!(hi.kind, m::ExprKind::Missing) {
                    self.problem(r, "a range needs two bounds");
                    return None;
                }
                let lo = self.expr(lo, cx, None)?;
                let hi = self.expr(hi, cx, None)?;
                let ty = Ty::Set(Box::new(Ty::join(&lo.ty, &hi.ty)));
                Some(EOut { e: Expr::Range(Box::new(lo.e), Box::new(hi.e)), ty, pure: lo.pure && hi.pure })
            }
            m::ExprKind::Call { function, args, .. } => self.call_expr(function, args, cx, r),
            m::ExprKind::Tuple(items) => {
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
            m::ExprKind::Record(values) => {
                // The record, from the type the checker gave the literal.
                // (by its name from this file, as written, rather than the
                // canonical copy of a record declared in several files).
                let rn = match &e.ty {
                    Some(robosim_hir::types::Ty::Named(_, n, DefKind::Record)) => n.clone(),
                    _ => String::new(),
                };
                let found = m::resolve(self.ex.db, self.ex.ws, self.file, std::slice::from_ref(&rn), DefKind::Record)
                    .and_then(|loc| Some((rn.clone(), loc.file, loc.def(self.ex.db)?)));
                let Some((rn, rf, rnode)) = found else {
                    self.problem(r, "this record literal's record is not one the export can resolve");
                    return None;
                };
                let rec = match self.ex.record(rf, rnode) {
                    Ok(x) => x,
                    Err(m) => {
                        self.problem(r, m);
                        return None;
                    }
                };
                let mut given: HashMap<&str, &m::Expr> = HashMap::new();
                for (f, x) in values {
                    if !matches!(x.kind, m::ExprKind::Missing) && !f.is_empty() {
                        given.insert(f, x);
                    }
                }
                let mut parts = vec![name(rec.ctor.clone())];
                let mut pure = true;
                for (f, t) in &rec.fields {
                    let Some(x) = given.remove(f.as_str()) else {
                        self.problem(r, format!("the record literal gives no value to the field `{f}`"));
                        return None;
                    };
                    let o = self.expr(x, cx, Some(t))?;
                    pure &= o.pure;
                    parts.push(o.e);
                }
                if let Some(f) = given.keys().next() {
                    self.problem(r, format!("`{f}` is not a field of the record `{rn}`"));
                    return None;
                }
                Some(EOut { e: dot(parts), ty: Ty::Record(rec), pure })
            }
            m::ExprKind::Field(inner, f) => {
                if matches!(inner.kind, m::ExprKind::Missing) {
                    return None;
                }
                let x = self.expr(inner, cx, None)?;
                match &x.ty {
                    Ty::Record(rec) => match rec.fields.iter().find(|(n, _)| n == f) {
                        Some((_, t)) => Some(EOut { e: call(rec.getter(f), vec![x.e]), ty: t.clone(), pure: x.pure }),
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
            m::ExprKind::Index(inner, indices) => {
                let [index] = indices.as_slice() else {
                    self.problem(r, "only one index is supported by the export");
                    return None;
                };
                let x = self.expr(inner, cx, None)?;
                match x.ty.clone() {
                    // Components of tuples are numbered from 1.
                    Ty::Product(ts) => {
                        let k = match index.kind {
                            m::ExprKind::Int(Some(k)) => usize::try_from(k).ok(),
                            _ => None,
                        }
                        .filter(|k| (1..=ts.len()).contains(k));
                        let Some(k) = k else {
                            self.problem(
                                index.range,
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
            m::ExprKind::Missing => {
                self.problem(r, "an incomplete expression");
                None
            }
            other => {
                let words = match other {
                    m::ExprKind::Other(w) => w.clone(),
                    m::ExprKind::Result => "result expr".into(),
                    m::ExprKind::Interval { .. } => "interval expr".into(),
                    _ => "expression".into(),
                };
                self.problem(r, format!("this expression ({words}) is not supported by the export yet"));
                None
            }
        }
    }

    /// `x in s`, `s ^ t`, `s cat t`.
    pub(super) fn collection_op(
        &mut self,
        op: m::BinOp,
        a: &m::Expr,
        b: &m::Expr,
        cx: ECtx,
        want: Option<&Ty>,
    ) -> Option<EOut> {
        if op == m::BinOp::In {
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
    pub(super) fn concat(&mut self, s: Expr, t: Expr) -> Expr {
        self.ex.uses_seq = true;
        self.ex.helpers.insert("Concat");
        call("Concat", vec![s, t])
    }

    /// A call of a function: a toolkit function mapped to CSPm's
    /// built-ins, or a function of the model with an explicit definition.
    pub(super) fn call_expr(&mut self, fname: &str, args: &[m::Expr], cx: ECtx, r: TextRange) -> Option<EOut> {
        if fname.is_empty() {
            self.problem(r, "only calls of named functions are supported by the export");
            return None;
        }
        let fname = fname.to_string();
        let (db, ws) = (self.ex.db, self.ex.ws);
        let found = robosim_hir::index::resolve_item(db, ws, self.file, std::slice::from_ref(&fname), |k| {
            k == DefKind::Function
        })
        .into_iter()
        .next()
        .and_then(|loc| Some((loc.file, m::item(db, ws, loc)?)));
        let Some((ff, fitem)) = found else {
            self.problem(r, format!("`{fname}` is not a function the export can resolve"));
            return None;
        };
        if ff.is_library(self.ex.db) {
            return self.toolkit(&fname, args, cx, r);
        }
        let m::Item::Function(fdef) = fitem else {
            self.problem(r, format!("the function `{fname}` is not in the model"));
            return None;
        };
        let f = match crate::machine::function(self.ex, ff, fdef) {
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
        if f.bodiless {
            self.fn_calls.insert(f.csp.clone());
            self.ex.fn_called.insert(f.csp.clone());
        }
        self.fn_calls.extend(f.calls.iter().cloned());
        let mut es = Vec::new();
        let mut pure = true;
        for (a, t) in args.iter().zip(&f.params) {
            let o = self.expr(a, cx, t.as_ref())?;
            pure &= o.pure;
            es.push(o.e);
        }
        Some(EOut { e: call(f.csp.clone(), es), ty: f.result.clone(), pure })
    }

    /// The toolkit functions with a CSPm counterpart.
    pub(super) fn toolkit(&mut self, f: &str, args: &[m::Expr], cx: ECtx, r: TextRange) -> Option<EOut> {
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
    pub(super) fn clock_bound(&mut self, side: &m::Expr, other: &EOut) {
        let i = match &side.kind {
            m::ExprKind::Since(n) => match self.names.get(n).cloned() {
                Some(Nm::Clock(i)) => i,
                _ => return,
            },
            m::ExprKind::SinceEntry(p) => {
                let n = p.last().cloned().unwrap_or_default();
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

    pub(super) fn since_entry_clock(&mut self, state: usize) -> usize {
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
    pub(super) fn record_term(&mut self, range: TextRange, kind: TermKind, expr: impl FnOnce() -> Expr) {
        if self.record && !self.display {
            self.terms.push(Term { range, kind, expr: expr(), guard: None });
        }
    }

    pub(super) fn with_reads(&self, reads: &[String], body: Expr) -> Expr {
        let mut p = body;
        for r in reads.iter().rev() {
            p = prefix(format!("get_{r}"), vec![Field::In(r.clone())], p);
        }
        p
    }

    /// Translates `e` in the behaviour, returning the reads it needs.
    pub(super) fn bexpr(&mut self, e: &m::Expr, want: Option<&Ty>) -> Option<(Expr, Vec<String>)> {
        let saved = std::mem::take(&mut self.reads);
        let out = self.expr(e, ECtx::Behaviour, want);
        let reads = std::mem::replace(&mut self.reads, saved);
        out.map(|o| (o.e, reads))
    }
}
