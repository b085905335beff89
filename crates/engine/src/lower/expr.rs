//! Expressions as the engine's [`Expr`]: numbers, and tuples and sets
//! laid out in one slot (`typed`), with calls of functions defined in CSPm
//! by the instantiations inlined.

use std::collections::HashMap;

use robosim_hir::csp_fn::{CspBinOp, CspExpr, CspFunction};
use robosim_hir::model::{self, BinOp, ExprKind, UnOp};

use super::types::{stride, Layout};
use super::*;

impl MachineCx<'_, '_> {
    pub(super) fn expr(&mut self, e: &model::Expr) -> Result<Expr, Unsupported> {
        let num = self.cx.defaults.real;
        let int_dom = Dom { lo: self.cx.defaults.int.lo.min(num.lo), hi: self.cx.defaults.int.hi.max(num.hi) };
        let range = e.range;
        Ok(match &e.kind {
            ExprKind::Int(v) => Expr::Const(v.ok_or_else(|| self.err(range, "this number is too large"))?),
            ExprKind::Bool(b) => Expr::Const(*b as Val),
            ExprKind::Real(t) => {
                let v: f64 = t.parse().unwrap_or(f64::NAN);
                if v.fract() == 0.0 && v.abs() < 1e15 {
                    Expr::Const(v as Val)
                } else {
                    return Err(self.err(
                        range,
                        "real numbers with a fractional part are not supported (reals are bounded integers, as in RoboTool)",
                    ));
                }
            }
            ExprKind::Other(k) if k == "literal" => {
                return Err(self.err(range, "this literal is not supported by the native checker"))
            }
            ExprKind::Name { name: n, .. } => {
                if self.types.contains_key(n) {
                    return Err(self.err(range, format!("`{n}` is a tuple or a set, used here as a number")));
                }
                self.value_of(range, n)?
            }
            ExprKind::EnumLiteral { literal: lit, enumeration, .. } => {
                let lits = enumeration
                    .and_then(|en| self.literals(en))
                    .ok_or_else(|| self.err(range, "the enumeration could not be resolved"))?;
                let ix = lits
                    .iter()
                    .position(|l| l == lit)
                    .ok_or_else(|| self.err(range, format!("`{lit}` is not a literal of the enumeration")))?;
                Expr::Const(ix as Val)
            }
            ExprKind::SimRef { path, input: suffix, .. } => {
                let name = path.join("::");
                match self.names.get(&name) {
                    // `$x`: the variable's value (its register for an input).
                    Some(&Name::Var { slot, .. }) if suffix.is_none() => return Ok(Expr::Slot(slot)),
                    Some(Name::Var { .. }) => {
                        return Err(self.err(range, format!("`${name}` is a variable: it cannot be received")))
                    }
                    _ => {}
                }
                let Some(Name::Event { chan: Some((chan, Dir::In)), ty }) = self.names.get(&name).cloned() else {
                    return Err(
                        self.err(range, format!("`${name}` is not an input event or a variable of the machine"))
                    );
                };
                let Some(reg) = self.design().channels[chan as usize].register else {
                    return Err(self.err(range, "`$` references belong to RoboSim machines"));
                };
                if let Some((var, suffix_range)) = suffix {
                    let var = var.join("::");
                    let Some(Name::Var { slot, dom, .. }) = self.names.get(&var).cloned() else {
                        return Err(self.err(*suffix_range, format!("`{var}` is not a variable")));
                    };
                    if ty.is_none() {
                        return Err(self.err(*suffix_range, format!("`{name}` carries no value")));
                    }
                    self.binds.push((slot, dom, reg + 1));
                }
                Expr::Slot(reg)
            }
            ExprKind::Since(n) => match self.names.get(n) {
                Some(Name::Clock(s)) => Expr::Clock(*s),
                _ => return Err(self.err(range, format!("`{n}` is not a clock"))),
            },
            ExprKind::SinceEntry(path) => {
                let n = path.last().cloned().unwrap_or_default();
                let Some(node) = self.nodes.iter().position(|x| x.name == n && x.kind == NodeKind::State) else {
                    return Err(self.err(range, format!("`{n}` is not a state of the machine")));
                };
                let slot = match self.nodes[node].since_entry {
                    Some(s) => s,
                    None => {
                        let s = self.new_slot();
                        self.nodes[node].since_entry = Some(s);
                        if self.nodes.iter().any(|x| x.parent == Some(node as u16)) {
                            self.nodes[node].entered_flag = Some(self.new_slot());
                        }
                        let q = format!("{}::sinceEntry({n})", self.inst_prefix);
                        self.design().clocks.push(Clock { name: q, slot: s, cap: 0 });
                        self.clock_caps.insert(s, 0);
                        s
                    }
                };
                Expr::Clock(slot)
            }
            ExprKind::Unary(op, inner) => {
                if matches!(inner.kind, ExprKind::Missing) {
                    return Err(self.err(range, "an operator without an operand"));
                }
                let literal = matches!(inner.kind, ExprKind::Int(_) | ExprKind::Real(_));
                let inner = self.expr(inner)?;
                match op {
                    UnOp::Not => Expr::Not(Box::new(inner)),
                    // A negative literal is a number (not `Neg` of one).
                    UnOp::Neg if literal => match inner.constant() {
                        Some(v) => Expr::Const(-v),
                        None => return Err(self.err(range, "this number is not supported")),
                    },
                    UnOp::Neg => {
                        let neg = Expr::Neg(Box::new(inner), self.arith_dom(e).unwrap_or(int_dom));
                        match neg.constant() {
                            Some(v) => Expr::Const(v),
                            None => neg,
                        }
                    }
                    UnOp::Other => return Err(self.err(range, "this operator is not supported by the native checker")),
                }
            }
            ExprKind::Binary(op, a, b) => {
                if let Some(r) = self.structured_binary(e, *op, a, b)? {
                    return Ok(r);
                }
                let x = self.expr(a)?;
                let y = self.expr(b)?;
                // Clock comparisons bound the clock's range.
                if op.is_comparison() {
                    for (c, other) in [(&x, &y), (&y, &x)] {
                        if let Expr::Clock(s) = c {
                            let v = other.constant().map(|v| v.clamp(0, i32::MAX as Val) as i32).unwrap_or(-1);
                            // RoboTool's generator refuses this too: the clock
                            // would stop below the value and the guard would
                            // never change.
                            let max = self.cx.defaults.clock_max;
                            if v > max {
                                let clock =
                                    self.cx.design.as_ref().and_then(|d| d.clocks.iter().find(|k| k.slot == *s));
                                let name = clock.map_or("a clock".to_string(), |k| format!("`{}`", k.name));
                                return Err(self.err(
                                    range,
                                    format!(
                                        "{name} is compared with {v}, above the greatest clock value {max} \
                                         (`core_clock_type = {{0..{max}}}`): widen it with \
                                         `nametype core_clock_type = {{0..{v}}}` in a `csp` block of an assertion file"
                                    ),
                                ));
                            }
                            let cap = self.clock_caps.entry(*s).or_insert(0);
                            *cap = if v < 0 || *cap < 0 { -1 } else { (*cap).max(v) };
                        }
                    }
                }
                // RT-5: sticky in the domain of the expression's type.
                let dom = self.arith_dom(e).unwrap_or(int_dom);
                let ar = |op| Expr::Arith(op, Box::new(x.clone()), Box::new(y.clone()), dom);
                let result = match op {
                    BinOp::Add => ar(ArOp::Add),
                    BinOp::Sub => ar(ArOp::Sub),
                    BinOp::Mul => ar(ArOp::Mul),
                    BinOp::Div => ar(ArOp::Div),
                    BinOp::Mod => ar(ArOp::Mod),
                    BinOp::Eq => Expr::Cmp(CmpOp::Eq, Box::new(x), Box::new(y)),
                    BinOp::Ne => Expr::Cmp(CmpOp::Ne, Box::new(x), Box::new(y)),
                    BinOp::Lt => Expr::Cmp(CmpOp::Lt, Box::new(x), Box::new(y)),
                    BinOp::Le => Expr::Cmp(CmpOp::Le, Box::new(x), Box::new(y)),
                    BinOp::Gt => Expr::Cmp(CmpOp::Gt, Box::new(x), Box::new(y)),
                    BinOp::Ge => Expr::Cmp(CmpOp::Ge, Box::new(x), Box::new(y)),
                    BinOp::And => Expr::Log(LogOp::And, Box::new(x), Box::new(y)),
                    BinOp::Or => Expr::Log(LogOp::Or, Box::new(x), Box::new(y)),
                    BinOp::Implies => Expr::Log(LogOp::Implies, Box::new(x), Box::new(y)),
                    BinOp::Iff => Expr::Log(LogOp::Iff, Box::new(x), Box::new(y)),
                    BinOp::In | BinOp::Cat | BinOp::Other => {
                        return Err(self.err(range, "this operator is not supported by the native checker"))
                    }
                };
                // Fold constant subexpressions (`PI / av`).
                match result.constant() {
                    Some(v) if matches!(result, Expr::Arith(..)) => Expr::Const(v),
                    _ => result,
                }
            }
            ExprKind::If(c, a, b) => {
                Expr::If(Box::new(self.expr(c)?), Box::new(self.expr(a)?), Box::new(self.expr(b)?))
            }
            ExprKind::Field(base, field) => {
                // `r.f` of a record: its field's component.
                let t = self.infer(base);
                let Some(Layout::Record(names, ds)) = &t else {
                    return Err(self.err(range, "only the fields of records can be selected"));
                };
                let (names, ds) = (names.clone(), ds.clone());
                let t = t.expect("a record");
                let i = names
                    .iter()
                    .position(|n| n == field)
                    .ok_or_else(|| self.err(range, format!("the record has no field `{field}`")))?;
                let r = self.typed(base, &t)?;
                Expr::Proj(Box::new(r), stride(&ds, i), ds[i])
            }
            ExprKind::Index(base, ix) => {
                if ix.len() != 1 {
                    return Err(self.err(range, "an incomplete index"));
                }
                let ds = match self.infer(base) {
                    Some(Layout::Tuple(ds)) => ds,
                    Some(Layout::Product(cs)) => {
                        let ds: Vec<Dom> = cs.iter().map(Layout::dom).collect();
                        let i = self.component(range, ix, &ds)?;
                        if !cs[i].is_num() {
                            return Err(self.err(range, "a tuple or record component, used here as a number"));
                        }
                        let t = self.typed(base, &Layout::Product(cs.clone()))?;
                        return Ok(Expr::Proj(Box::new(t), stride(&ds, i), ds[i]));
                    }
                    _ => return Err(self.err(range, "only the components of tuples can be indexed")),
                };
                let i = self.component(range, ix, &ds)?;
                let t = self.typed(base, &Layout::Tuple(ds.clone()))?;
                Expr::Proj(Box::new(t), stride(&ds, i), ds[i])
            }
            ExprKind::Call { function: f, args, .. }
                if matches!(f.as_str(), "head" | "last" | "size" | "card" | "isNonEmpty")
                    && matches!(args.as_slice(), [s] if matches!(self.infer(s), Some(Layout::Seq(_)))) =>
            {
                let Some(t @ Layout::Seq(d)) = self.infer(&args[0]) else { unreachable!() };
                let s = self.typed(&args[0], &t)?;
                let op = |op| Expr::Seq(op, vec![s.clone()], d);
                match f.as_str() {
                    "head" => op(SeqOp::Head),
                    "last" => op(SeqOp::Last),
                    "isNonEmpty" => Expr::Cmp(CmpOp::Gt, Box::new(op(SeqOp::Len)), Box::new(Expr::Const(0))),
                    _ => op(SeqOp::Len),
                }
            }
            ExprKind::Call { function: f, args, .. } if matches!(f.as_str(), "member" | "size" | "card" | "subset") => {
                match (f.as_str(), args.as_slice()) {
                    ("member", [x, set]) => self.member(e, x, set)?,
                    ("size" | "card", [set]) => {
                        let Some(t @ Layout::Set(_)) = self.infer(set) else {
                            return Err(self.err(range, format!("`{f}` of a set whose type is not known")));
                        };
                        Expr::Card(Box::new(self.typed(set, &t)?))
                    }
                    ("subset", [x, y]) => {
                        let Some(t @ Layout::Set(_)) = self.infer(x).or_else(|| self.infer(y)) else {
                            return Err(self.err(range, "`subset` of sets whose type is not known"));
                        };
                        Expr::Set(SetOp::Subset, Box::new(self.typed(x, &t)?), Box::new(self.typed(y, &t)?))
                    }
                    _ => return Err(self.err(range, format!("`{f}` with {} arguments", args.len()))),
                }
            }
            ExprKind::Tuple(_) | ExprKind::Set(_) => {
                return Err(self.err(range, "a tuple or set where a number is expected"));
            }
            ExprKind::Call { function: f, args, res } => {
                let Some(name) = self.block_function(f, res.as_ref()) else {
                    // RT-2: RoboTool's function `f(x) = e` of `result == e`.
                    if let Some(inlined) = self.defined_call(range, f, res.as_ref(), args)? {
                        return Ok(inlined);
                    }
                    // RT-2: RoboTool's default for a function without a body.
                    return match self.bodiless_call(range, f, res.as_ref())? {
                        (v, Layout::Num(_)) => Ok(Expr::Const(v)),
                        _ => Err(self.err(range, format!("`{f}` returns a tuple or a set, used here as a number"))),
                    };
                };
                let mut values = Vec::new();
                for a in args {
                    values.push(self.expr(a)?);
                }
                self.csp_call(range, &name, values, 0)?
            }
            ExprKind::Missing => return Err(self.err(range, "an incomplete expression")),
            other => {
                let k = match other {
                    ExprKind::Seq(_) => "seq expr",
                    ExprKind::Record(_) => "record literal",
                    ExprKind::Interval { .. } => "interval expr",
                    ExprKind::SetRange(..) => "set range expr",
                    ExprKind::Result => "result expr",
                    ExprKind::Other(k) => k,
                    _ => "expression",
                };
                return Err(
                    self.err(range, format!("this expression ({k}) is not supported by the native checker yet"))
                );
            }
        })
    }

    /// A call of `name`, defined in CSPm by an instantiation block, on
    /// argument values: its clauses tried in order, inlined.
    fn csp_call(&mut self, at: TextRange, name: &str, args: Vec<Expr>, depth: usize) -> Result<Expr, Unsupported> {
        if depth > 16 {
            return Err(self.err(at, format!("the CSPm definition of `{name}` calls itself too deeply to inline")));
        }
        let clauses: Vec<CspFunction> = self
            .cx
            .defaults
            .functions
            .iter()
            .filter(|c| c.name == name && c.params.len() == args.len())
            .cloned()
            .collect();
        if clauses.is_empty() {
            return Err(self.err(at, format!("no CSPm definition of `{name}` takes {} arguments", args.len())));
        }
        // From the last clause back: `if pattern then body else (the rest)`.
        let mut rest: Option<Expr> = None;
        for clause in clauses.iter().rev() {
            let mut env = HashMap::new();
            let mut conds = Vec::new();
            for (p, a) in clause.params.iter().zip(&args) {
                let v = match p {
                    CspExpr::Bool(b) => Some(*b as Val),
                    CspExpr::Name(n) => match self.csp_constructor(n) {
                        Some((v, _)) => Some(v),
                        None => {
                            env.insert(n.clone(), a.clone());
                            None
                        }
                    },
                    _ => Some(int_pattern(p).ok_or_else(|| {
                        self.err(at, format!("a pattern of `{name}` the native checker cannot match"))
                    })?),
                };
                if let Some(v) = v {
                    conds.push(Expr::Cmp(CmpOp::Eq, Box::new(a.clone()), Box::new(Expr::Const(v))));
                }
            }
            let body = self.csp_expr(at, &clause.body, &env, depth)?;
            let cond = conds.into_iter().reduce(|a, b| Expr::Log(LogOp::And, Box::new(a), Box::new(b)));
            rest = Some(match (cond, rest) {
                (None, _) => body,
                (Some(c), Some(r)) => Expr::If(Box::new(c), Box::new(body), Box::new(r)),
                (Some(_), None) => {
                    // The last clause matches on a value: the clauses must
                    // cover every value (FDR stops with an error otherwise).
                    if !self.csp_exhaustive(&clauses) {
                        return Err(self.err(
                            at,
                            format!(
                                "the CSPm clauses of `{name}` do not cover every value of its arguments \
                                 (add a clause with a variable pattern)"
                            ),
                        ));
                    }
                    body
                }
            });
        }
        Ok(rest.expect("at least one clause"))
    }

    /// Whether the clauses of a one-argument function match every
    /// constructor of the enumeration their patterns name.
    fn csp_exhaustive(&self, clauses: &[CspFunction]) -> bool {
        let mut covered = Vec::new();
        let mut size = None;
        for c in clauses {
            let [CspExpr::Name(n)] = c.params.as_slice() else { return false };
            let Some((v, n)) = self.csp_constructor(n) else { return false };
            covered.push(v);
            size = Some(n);
        }
        size.is_some_and(|n| (0..n).all(|v| covered.contains(&v)))
    }

    /// A CSPm constructor `Type_Literal` of an enumeration in scope: its
    /// value and the enumeration's size.
    fn csp_constructor(&self, name: &str) -> Option<(Val, Val)> {
        name.match_indices('_').find_map(|(i, _)| {
            let (ty, lit) = (&name[..i], &name[i + 1..]);
            let (_, lits) = model::enum_literals(self.cx.db, self.cx.ws, self.file, &[ty.to_string()])?;
            let v = lits.iter().position(|l| l == lit)?;
            Some((v as Val, lits.len() as Val))
        })
    }

    /// A CSPm body with its parameters bound to `env`. CSPm arithmetic is
    /// not saturating: it is evaluated in a wide domain.
    fn csp_expr(
        &mut self,
        at: TextRange,
        e: &CspExpr,
        env: &HashMap<String, Expr>,
        depth: usize,
    ) -> Result<Expr, Unsupported> {
        let wide = Dom { lo: Val::MIN / 4, hi: Val::MAX / 4 };
        Ok(match e {
            CspExpr::Int(v) => Expr::Const(*v),
            CspExpr::Bool(b) => Expr::Const(*b as Val),
            CspExpr::Name(n) => {
                if let Some(x) = env.get(n) {
                    x.clone()
                } else if let Some((v, _)) = self.csp_constructor(n) {
                    Expr::Const(v)
                } else if let Some((_, v)) = self.cx.defaults.constants.iter().find(|(c, _)| c == n) {
                    Expr::Const(*v)
                } else if self.cx.defaults.functions.iter().any(|c| c.name == *n && c.params.is_empty()) {
                    self.csp_call(at, n, Vec::new(), depth + 1)?
                } else {
                    return Err(self.err(at, format!("`{n}` in a CSPm definition is not known to the native checker")));
                }
            }
            CspExpr::Call(f, args) => {
                let mut values = Vec::new();
                for a in args {
                    values.push(self.csp_expr(at, a, env, depth)?);
                }
                self.csp_call(at, f, values, depth + 1)?
            }
            CspExpr::Neg(x) => Expr::Neg(Box::new(self.csp_expr(at, x, env, depth)?), wide),
            CspExpr::Not(x) => Expr::Not(Box::new(self.csp_expr(at, x, env, depth)?)),
            CspExpr::Bin(op, a, b) => {
                let (a, b) = (Box::new(self.csp_expr(at, a, env, depth)?), Box::new(self.csp_expr(at, b, env, depth)?));
                match op {
                    CspBinOp::Add => Expr::Arith(ArOp::Add, a, b, wide),
                    CspBinOp::Sub => Expr::Arith(ArOp::Sub, a, b, wide),
                    CspBinOp::Mul => Expr::Arith(ArOp::Mul, a, b, wide),
                    CspBinOp::Div => Expr::Arith(ArOp::Div, a, b, wide),
                    CspBinOp::Mod => Expr::Arith(ArOp::Mod, a, b, wide),
                    CspBinOp::Eq => Expr::Cmp(CmpOp::Eq, a, b),
                    CspBinOp::Ne => Expr::Cmp(CmpOp::Ne, a, b),
                    CspBinOp::Lt => Expr::Cmp(CmpOp::Lt, a, b),
                    CspBinOp::Le => Expr::Cmp(CmpOp::Le, a, b),
                    CspBinOp::Gt => Expr::Cmp(CmpOp::Gt, a, b),
                    CspBinOp::Ge => Expr::Cmp(CmpOp::Ge, a, b),
                    CspBinOp::And => Expr::Log(LogOp::And, a, b),
                    CspBinOp::Or => Expr::Log(LogOp::Or, a, b),
                    CspBinOp::Cat => return Err(self.err(at, "sequences in CSPm definitions are not supported")),
                }
            }
            CspExpr::If(c, a, b) => Expr::If(
                Box::new(self.csp_expr(at, c, env, depth)?),
                Box::new(self.csp_expr(at, a, env, depth)?),
                Box::new(self.csp_expr(at, b, env, depth)?),
            ),
        })
    }
}

impl MachineCx<'_, '_> {
    /// The type of `e` when it is a tuple or a set, as far as the names in
    /// it tell (literals take the type their context wants).
    fn infer(&self, e: &model::Expr) -> Option<Layout> {
        match &e.kind {
            ExprKind::Name { name, .. } => self.types.get(name).cloned(),
            ExprKind::Call { function, args, .. } => match function.as_str() {
                "union" | "inter" | "diff" => args.iter().find_map(|a| self.infer(a)),
                // Sequences from sequences (the first argument's type).
                "concat" | "tail" | "front" | "reverse" | "filter" => {
                    args.first().and_then(|a| self.infer(a)).filter(|t| matches!(t, Layout::Seq(_)))
                }
                _ => None,
            },
            ExprKind::Binary(BinOp::Cat, a, b) => self.infer(a).or_else(|| self.infer(b)),
            ExprKind::If(_, a, b) => self.infer(a).or_else(|| self.infer(b)),
            // `t[i]` of a tuple with structured components.
            ExprKind::Index(base, ix) => match (self.infer(base)?, ix.as_slice()) {
                (Layout::Product(cs), [model::Expr { kind: ExprKind::Int(Some(i)), .. }]) => {
                    let c = cs.get(usize::try_from(*i).ok()?.checked_sub(1)?)?;
                    (!c.is_num()).then(|| c.clone())
                }
                _ => None,
            },
            _ => None,
        }
    }

    /// Lowers `e` as a value of type `want`.
    pub(super) fn typed(&mut self, e: &model::Expr, want: &Layout) -> Result<Expr, Unsupported> {
        if want.is_num() {
            return self.expr(e);
        }
        let range = e.range;
        let r = match (&e.kind, want) {
            (ExprKind::If(c, a, b), _) => {
                Expr::If(Box::new(self.expr(c)?), Box::new(self.typed(a, want)?), Box::new(self.typed(b, want)?))
            }
            (ExprKind::Tuple(exprs), Layout::Product(cs)) => {
                if exprs.len() != cs.len() {
                    return Err(self.err(range, format!("a tuple of {} components is expected", cs.len())));
                }
                let mut parts = Vec::new();
                for (x, c) in exprs.iter().zip(cs) {
                    parts.push((self.typed(x, c)?, c.dom()));
                }
                Expr::Tuple(parts)
            }
            // A structured component of a tuple: `t[i]`.
            (ExprKind::Index(base, ix), _) if matches!(self.infer(base), Some(Layout::Product(_))) => {
                let Some(Layout::Product(cs)) = self.infer(base) else { unreachable!() };
                let ds: Vec<Dom> = cs.iter().map(Layout::dom).collect();
                let i = self.component(range, ix, &ds)?;
                if cs[i] != *want {
                    return Err(self.err(range, "this component does not have the type expected here"));
                }
                let t = self.typed(base, &Layout::Product(cs.clone()))?;
                Expr::Proj(Box::new(t), stride(&ds, i), ds[i])
            }
            (ExprKind::Tuple(exprs), Layout::Tuple(ds)) => {
                if exprs.len() != ds.len() {
                    return Err(self.err(range, format!("a tuple of {} components is expected", ds.len())));
                }
                let mut parts = Vec::new();
                for (x, d) in exprs.iter().zip(ds) {
                    parts.push((self.expr(x)?, *d));
                }
                Expr::Tuple(parts)
            }
            (ExprKind::Record(fields), Layout::Record(names, ds)) => {
                let mut parts = Vec::new();
                for (n, d) in names.iter().zip(ds) {
                    let value = fields
                        .iter()
                        .find(|(f, _)| f == n)
                        .map(|(_, v)| v)
                        .filter(|v| !matches!(v.kind, ExprKind::Missing))
                        .ok_or_else(|| self.err(range, format!("the record literal gives no value to `{n}`")))?;
                    parts.push((self.expr(value)?, *d));
                }
                Expr::Tuple(parts)
            }
            (ExprKind::Set(exprs), Layout::Set(el)) => {
                let mut acc: Option<Expr> = None;
                for x in exprs {
                    let bit = Expr::Elem(Box::new(self.typed(x, el)?), el.dom());
                    acc = Some(match acc {
                        None => bit,
                        Some(a) => Expr::Set(SetOp::Union, Box::new(a), Box::new(bit)),
                    });
                }
                acc.unwrap_or(Expr::Const(0))
            }
            (ExprKind::Seq(items), Layout::Seq(d)) => {
                let el = Layout::Num(d.el);
                let mut parts = Vec::new();
                for x in items {
                    parts.push(self.typed(x, &el)?);
                }
                if parts.len() > d.max as usize {
                    return Err(self.err(
                        range,
                        format!("a sequence of {} elements: the native checker holds at most {}", parts.len(), d.max),
                    ));
                }
                Expr::Seq(SeqOp::Lit, parts, *d)
            }
            (ExprKind::Binary(BinOp::Cat, a, b), Layout::Seq(d)) => {
                Expr::Seq(SeqOp::Cat, vec![self.typed(a, want)?, self.typed(b, want)?], *d)
            }
            (ExprKind::Call { function: f, args, .. }, Layout::Seq(d))
                if matches!(f.as_str(), "concat" | "tail" | "front" | "reverse" | "filter") =>
            {
                let (op, n) = match f.as_str() {
                    "concat" => (SeqOp::Cat, 2),
                    "tail" => (SeqOp::Tail, 1),
                    "front" => (SeqOp::Front, 1),
                    "reverse" => (SeqOp::Reverse, 1),
                    _ => (SeqOp::Filter, 2),
                };
                if args.len() != n {
                    return Err(self.err(range, format!("`{f}` takes {n} arguments")));
                }
                let mut parts = vec![self.typed(&args[0], want)?];
                if n == 2 {
                    // `filter`'s second argument is a set of the elements.
                    let second = if op == SeqOp::Filter {
                        if d.el.size() > 31 {
                            return Err(self.err(range, "`filter` by a set of a type of more than 31 values"));
                        }
                        Layout::Set(Box::new(Layout::Num(d.el)))
                    } else {
                        want.clone()
                    };
                    parts.push(self.typed(&args[1], &second)?);
                }
                Expr::Seq(op, parts, *d)
            }
            (ExprKind::Call { function: f, args, .. }, Layout::Set(_))
                if matches!(f.as_str(), "union" | "inter" | "diff") =>
            {
                let [a, b] = args.as_slice() else {
                    return Err(self.err(range, format!("`{f}` takes two sets")));
                };
                let op = match f.as_str() {
                    "union" => SetOp::Union,
                    "inter" => SetOp::Inter,
                    _ => SetOp::Diff,
                };
                Expr::Set(op, Box::new(self.typed(a, want)?), Box::new(self.typed(b, want)?))
            }
            // RT-2: a function without a body returns the default of its
            // (tuple, record or set) result type.
            (ExprKind::Call { function: f, res, .. }, _) if self.block_function(f, res.as_ref()).is_none() => {
                let (v, ty) = self.bodiless_call(range, f, res.as_ref())?;
                if ty != *want {
                    return Err(self.err(range, format!("`{f}` does not return the type expected here")));
                }
                Expr::Const(v)
            }
            (ExprKind::Name { name: n, .. }, _) => {
                if self.types.get(n) != Some(want) {
                    return Err(self.err(range, format!("`{n}` does not have the type expected here")));
                }
                self.value_of(range, n)?
            }
            _ => {
                let what = match want {
                    Layout::Set(_) => "a set",
                    Layout::Seq(_) => "a sequence",
                    _ => "a tuple",
                };
                return Err(self.err(
                    range,
                    format!("{what} is expected here; this expression is not supported as one by the native checker"),
                ));
            }
        };
        // Fold constant values (initial values, constants).
        Ok(match r.constant() {
            Some(v) if !matches!(r, Expr::Slot(_)) => Expr::Const(v),
            _ => r,
        })
    }

    /// `==`, `!=` of tuples and sets, and `x in s`; `None` for numbers.
    fn structured_binary(
        &mut self,
        e: &model::Expr,
        op: BinOp,
        a: &model::Expr,
        b: &model::Expr,
    ) -> Result<Option<Expr>, Unsupported> {
        Ok(match op {
            BinOp::Eq | BinOp::Ne => {
                let Some(t) = self.infer(a).or_else(|| self.infer(b)) else { return Ok(None) };
                let cmp = if op == BinOp::Eq { CmpOp::Eq } else { CmpOp::Ne };
                Some(Expr::Cmp(cmp, Box::new(self.typed(a, &t)?), Box::new(self.typed(b, &t)?)))
            }
            BinOp::In => Some(self.member(e, a, b)?),
            _ => None,
        })
    }

    /// `x in set`, `member(x, set)`.
    fn member(&mut self, e: &model::Expr, x: &model::Expr, set: &model::Expr) -> Result<Expr, Unsupported> {
        if let Some(t @ Layout::Set(_)) = self.infer(set) {
            let Layout::Set(el) = &t else { unreachable!() };
            let bit = Expr::Elem(Box::new(self.typed(x, el)?), el.dom());
            return Ok(Expr::Set(SetOp::Meets, Box::new(bit), Box::new(self.typed(set, &t)?)));
        }
        // A literal set of numbers: one of the elements.
        if let (ExprKind::Set(elements), None) = (&set.kind, self.infer(x)) {
            let v = self.expr(x)?;
            let mut acc = Expr::Const(0);
            for el in elements {
                let eq = Expr::Cmp(CmpOp::Eq, Box::new(v.clone()), Box::new(self.expr(el)?));
                acc = Expr::Log(LogOp::Or, Box::new(acc), Box::new(eq));
            }
            return Ok(acc);
        }
        Err(self.err(e.range, "membership in a set whose type is not known"))
    }

    /// The component (0-based) an index `[i]` (at `at`) selects, `i` from 1.
    pub(super) fn component(&mut self, at: TextRange, index: &[model::Expr], ds: &[Dom]) -> Result<usize, Unsupported> {
        let i = match index.last() {
            Some(ix) => self.expr(ix)?.constant(),
            None => None,
        };
        match i {
            Some(i) if 1 <= i && i as usize <= ds.len() => Ok(i as usize - 1),
            _ => Err(self.err(
                at,
                format!("a tuple of {} components is indexed by a constant from 1 to {}", ds.len(), ds.len()),
            )),
        }
    }
}

/// The value of an integer pattern `n` or `-n` of a CSPm clause.
fn int_pattern(p: &CspExpr) -> Option<Val> {
    match p {
        CspExpr::Int(v) => Some(*v),
        CspExpr::Neg(x) => match **x {
            CspExpr::Int(v) => Some(-v),
            _ => None,
        },
        _ => None,
    }
}

impl MachineCx<'_, '_> {
    /// The domain of the sticky arithmetic at `e`: its type's (RoboTool's
    /// `Plus(e1, e2, core_nat)` for a `nat` sum, `core_real` for every
    /// division); `None` when the type checker did not type it.
    pub(super) fn arith_dom(&self, e: &robosim_hir::model::Expr) -> Option<Dom> {
        let d = &self.cx.defaults;
        let t = robosim_hir::types::expr_types(self.cx.db, self.cx.ws, self.file).get(&e.range)?;
        match t {
            robosim_hir::types::Ty::Nat => Some(d.nat),
            robosim_hir::types::Ty::Int => Some(d.int),
            robosim_hir::types::Ty::Real => Some(d.real),
            _ => None,
        }
    }
}
