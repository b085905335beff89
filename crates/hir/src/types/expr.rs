//! Typing of expressions: operators, calls, and the type every expression
//! form has.

use std::collections::HashMap;

use robosim_syntax::ast::{binary_operator, operand_exprs};
use robosim_syntax::{ast, SyntaxKind::*, SyntaxNode};

use crate::defs::{lower_type, DefKind};
use crate::index::resolve_item;
use crate::resolve::Target;

use super::{
    arguments, compatible, first_operand, has_open_interval, is_timed, join, op_text, operands, substitute, unify,
    unparen, Ty, Typer,
};

impl Typer<'_> {
    /// The join of the types of a set's or sequence's elements.
    fn element_type(&mut self, n: &SyntaxNode) -> Ty {
        let mut el = Ty::Any;
        for e in operand_exprs(n) {
            let t = self.expr(&e);
            el = join(&el, &t);
        }
        el
    }

    pub(super) fn expr_type(&mut self, n: &SyntaxNode) -> Ty {
        match n.kind() {
            LITERAL => match n.first_token().map(|t| t.kind()) {
                Some(INT_NUMBER) => Ty::Nat,
                Some(FLOAT_NUMBER) => Ty::Real,
                Some(STRING) => Ty::Str,
                Some(TRUE_KW | FALSE_KW) => Ty::Bool,
                _ => Ty::Error,
            },
            CYCLE_EXPR => Ty::Nat,
            RESULT_EXPR => self.result.clone().unwrap_or(Ty::Error),
            FROM_EXPR | TO_EXPR => Ty::Error,
            REF_EXPR => {
                // One lookup of the name serves both.
                let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { return Ty::Error };
                self.bare_literal_named(n, &r);
                self.name_type(&r)
            }
            PAREN_EXPR => first_operand(n).map(|e| self.expr(&e)).unwrap_or(Ty::Error),
            ENUM_LITERAL_EXPR => {
                self.bare_literal(n);
                let refs: Vec<SyntaxNode> = n.children().filter(|c| c.kind() == NAME_REF).collect();
                match refs.first().and_then(|r| self.targets.get(&r.text_range())) {
                    Some(Target::Item(loc)) => self.named(*loc, DefKind::Enumeration),
                    _ => Ty::Error,
                }
            }
            RECORD_LITERAL => {
                let name = n.children().find(|c| c.kind() == NAME_REF).map(|r| crate::defs::name_text(&r));
                let loc = name.and_then(|nm| {
                    resolve_item(self.db, self.ws, self.file, &[nm], |k| k == DefKind::Record).first().copied()
                });
                for fv in n.children().filter(|c| c.kind() == FIELD_VALUE) {
                    let Some(e) = operand_exprs(&fv).first().cloned() else { continue };
                    let t = self.expr(&e);
                    // RC-EXP-12: each value fits its field.
                    let (Some(loc), Some(f)) = (loc, fv.children().find(|c| c.kind() == NAME_REF)) else { continue };
                    let fname = crate::defs::name_text(&f);
                    let s = loc.summary(self.db);
                    match s.members.iter().find(|m| m.kind == DefKind::Field && m.name == fname).cloned() {
                        Some(m) => {
                            let ft = m.ty.as_ref().map(|ty| self.lower(loc.file, ty)).unwrap_or(Ty::Error);
                            if !compatible(&t, &ft) {
                                self.problem(
                                    "RC-EXP-12",
                                    e.text_range(),
                                    format!("field `{fname}` has type {ft}, but the value has type {t}"),
                                );
                            }
                        }
                        None => self.problem(
                            "LNK-01",
                            f.text_range(),
                            format!("record `{}` has no field `{fname}`", s.name),
                        ),
                    }
                }
                match loc {
                    Some(loc) => self.named(loc, DefKind::Record),
                    None => Ty::Error,
                }
            }
            PREFIX_EXPR => {
                let e = first_operand(n);
                let t = e.as_ref().map(|x| self.expr(x)).unwrap_or(Ty::Error);
                if n.children_with_tokens().any(|t| t.kind() == NOT_KW) {
                    if let Some(x) = &e {
                        self.expect_bool(&t, x, "RC-EXP-14", "the operand of `not`");
                    }
                    Ty::Bool
                } else {
                    match t {
                        Ty::Nat | Ty::Int => Ty::Int,
                        Ty::Real => Ty::Real,
                        Ty::Vector(..) | Ty::Matrix(..) => t,
                        t if t.is_unknown() => Ty::Error,
                        t => {
                            if let Some(x) = &e {
                                self.problem(
                                    "RC-EXP-14",
                                    x.text_range(),
                                    format!("unary `-` needs a number; this has type {t}"),
                                );
                            }
                            Ty::Error
                        }
                    }
                }
            }
            BIN_EXPR => self.binary(n),
            IF_EXPR => {
                let e = operand_exprs(n);
                if e.len() != 3 {
                    return Ty::Error;
                }
                let c = self.expr(&e[0]);
                self.expect_bool(&c, &e[0], "RC-EXP-14", "the condition of `if`");
                let a = self.expr(&e[1]);
                let b = self.expr(&e[2]);
                if !compatible(&a, &b) && !compatible(&b, &a) {
                    self.problem(
                        "RC-EXP-14",
                        e[2].text_range(),
                        format!("the branches of `if` have different types: {a} and {b}"),
                    );
                    return Ty::Error;
                }
                join(&a, &b)
            }
            TYPE_TEST_EXPR => {
                let e = operand_exprs(n);
                let t = e.first().map(|x| self.expr(x)).unwrap_or(Ty::Error);
                let target = n
                    .children()
                    .find(|c| ast::is_type_kind(c.kind()))
                    .map(|t| self.lower(self.file, &lower_type(&t)))
                    .unwrap_or(Ty::Error);
                if n.children_with_tokens().any(|t| t.kind() == IS_KW) {
                    Ty::Bool
                } else {
                    // Widening silently, numeric narrowing allowed (RC-EXP-11).
                    let castable = compatible(&t, &target)
                        || compatible(&target, &t)
                        || (t.rank().is_some() && target.rank().is_some());
                    if !castable {
                        self.problem("RC-EXP-11", n.text_range(), format!("cannot cast {t} to {target}"));
                    } else if let (Some(from), Some(to)) = (t.rank(), target.rank()) {
                        if to < from {
                            self.problem(
                                "RC-EXP-11-narrow",
                                n.text_range(),
                                format!("casting {t} to {target} narrows the value: it must be checked to fit"),
                            );
                        }
                    }
                    target
                }
            }
            FORALL_EXPR | EXISTS_EXPR => {
                let mark = self.bind(n);
                self.such_that(n);
                if let Some(body) = operand_exprs(n).last() {
                    let t = self.expr(body);
                    self.expect_bool(&t, body, "RC-EXP-14", "the body of a quantifier");
                }
                self.env.truncate(mark);
                Ty::Bool
            }
            LAMBDA_EXPR => {
                let mark = self.bind(n);
                let dom = self.binder_types(n, mark);
                self.such_that(n);
                let body = operand_exprs(n).last().map(|b| self.expr(b)).unwrap_or(Ty::Error);
                self.env.truncate(mark);
                let dom = if dom.len() == 1 { dom.into_iter().next().unwrap() } else { Ty::Product(dom) };
                Ty::Function(Box::new(dom), Box::new(body))
            }
            THE_EXPR => {
                let mark = self.bind(n);
                self.such_that(n);
                let t = operand_exprs(n).last().map(|b| self.expr(b)).unwrap_or(Ty::Error);
                self.env.truncate(mark);
                t
            }
            SET_COMP_EXPR => {
                let mark = self.bind(n);
                let dom = self.binder_types(n, mark);
                // Without `@ term`, RoboTool's library writes the term where
                // the predicate goes (`{x : ?X | maplet(x, x)}`): only check
                // the predicate when a term is given.
                if n.children_with_tokens().any(|t| t.kind() == AT) {
                    self.such_that(n);
                }
                let t = match operand_exprs(n).last() {
                    Some(b) => self.expr(b),
                    None if dom.len() == 1 => dom[0].clone(),
                    None => Ty::Product(dom),
                };
                self.env.truncate(mark);
                Ty::Set(Box::new(t))
            }
            LET_EXPR => {
                let mark = self.env.len();
                for d in n.children().filter(|c| c.kind() == LET_DECL) {
                    let t = operand_exprs(&d).first().map(|e| self.expr(e)).unwrap_or(Ty::Error);
                    if let Some(name) = d.children().find(|c| c.kind() == NAME) {
                        self.env.push((crate::defs::name_text(&name), t));
                    }
                }
                let t = operand_exprs(n).last().map(|b| self.expr(b)).unwrap_or(Ty::Error);
                self.env.truncate(mark);
                t
            }
            SET_EXPR => Ty::Set(Box::new(self.element_type(n))),
            SEQ_EXPR => Ty::Seq(Box::new(self.element_type(n))),
            SET_RANGE_EXPR | INTERVAL_EXPR => {
                let mut el = Ty::Nat;
                for e in operand_exprs(n) {
                    let t = self.expr(&e);
                    if !t.is_numeric() {
                        self.problem(
                            "RC-EXP-14",
                            e.text_range(),
                            format!("the bounds of a range are numbers; this has type {t}"),
                        );
                    }
                    el = join(&el, &t);
                }
                Ty::Set(Box::new(el))
            }
            TUPLE_EXPR => Ty::Product(operand_exprs(n).iter().map(|e| self.expr(e)).collect()),
            MATRIX_EXPR => {
                let rows: Vec<Vec<Ty>> = n
                    .children()
                    .filter(|c| c.kind() == MATRIX_ROW)
                    .map(|r| operand_exprs(&r).iter().map(|e| self.expr(e)).collect())
                    .collect();
                let el = rows.iter().flatten().fold(Ty::Any, |a, t| join(&a, t));
                if rows.len() == 1 {
                    Ty::Vector(Box::new(el), Some(rows[0].len() as i128))
                } else {
                    Ty::Matrix(Box::new(el), Some(rows.len() as i128), rows.first().map(|r| r.len() as i128))
                }
            }
            INVERSE_EXPR | TRANSPOSE_EXPR => {
                let t = operand_exprs(n).first().map(|e| self.expr(e)).unwrap_or(Ty::Error);
                match (n.kind(), t) {
                    (TRANSPOSE_EXPR, Ty::Matrix(a, r, c)) => Ty::Matrix(a, c, r),
                    (_, t) => t,
                }
            }
            SINCE_EXPR | SINCE_ENTRY_EXPR => {
                // Only as a direct operand of a comparison (RC:TE4).
                let parent_ok = n.ancestors().skip(1).find(|a| a.kind() != PAREN_EXPR).is_some_and(|p| {
                    p.kind() == BIN_EXPR && matches!(binary_operator(&p), Some(LT | LTEQ | GT | GTEQ | EQ2))
                });
                let in_action = n
                    .ancestors()
                    .any(|a| matches!(a.kind(), ENTRY_ACTION | DURING_ACTION | EXIT_ACTION | TRANSITION_ACTION));
                if !parent_ok && !in_action {
                    self.problem(
                        "RC:TE4",
                        n.text_range(),
                        "a timed expression can only be compared with a number (`<`, `<=`, `>`, `>=` or `==`)".into(),
                    );
                }
                Ty::Int
            }
            SELECT_EXPR => {
                let t = operand_exprs(n).first().map(|e| self.expr(e)).unwrap_or(Ty::Error);
                let field = n
                    .children()
                    .filter(|c| c.kind() == NAME_REF)
                    .last()
                    .map(|r| (crate::defs::name_text(&r), r.text_range()));
                let Some((field, frange)) = field else { return Ty::Error };
                match &t {
                    Ty::Named(loc, rname, DefKind::Record) => {
                        let s = loc.summary(self.db);
                        match s.members.iter().find(|m| m.kind == DefKind::Field && m.name == field) {
                            Some(m) => m.ty.as_ref().map(|ty| self.lower(loc.file, ty)).unwrap_or(Ty::Error),
                            None => {
                                self.problem("LNK-01", frange, format!("record `{rname}` has no field `{field}`"));
                                Ty::Error
                            }
                        }
                    }
                    t if t.is_unknown() => Ty::Error,
                    t => {
                        self.problem(
                            "LNK-01",
                            frange,
                            format!("`.{field}` selects a field of a record, but this has type {t}"),
                        );
                        Ty::Error
                    }
                }
            }
            INDEX_EXPR => {
                let e = operand_exprs(n);
                let t = e.first().map(|x| self.expr(x)).unwrap_or(Ty::Error);
                let idx: Vec<Ty> = e.iter().skip(1).map(|x| self.expr(x)).collect();
                for (x, it) in e.iter().skip(1).zip(&idx) {
                    if !compatible(it, &Ty::Int) && !matches!(t, Ty::Function(..) | Ty::Relation(..)) {
                        self.problem(
                            "RC-EXP-14",
                            x.text_range(),
                            format!("an index must be an integer; this has type {it}"),
                        );
                    }
                }
                match t {
                    Ty::Seq(a) => *a,
                    Ty::Vector(a, _) | Ty::Matrix(a, _, _) => *a,
                    Ty::Function(_, b) | Ty::Relation(_, b) => *b,
                    Ty::Product(ts) => {
                        // Tuple access `t[k]` with a literal k (RC-EXP-01..03).
                        let k = e
                            .get(1)
                            .filter(|x| x.kind() == LITERAL)
                            .and_then(|x| x.text().to_string().trim().parse::<usize>().ok());
                        match k {
                            Some(k) if (1..=ts.len()).contains(&k) && e.len() == 2 => ts[k - 1].clone(),
                            Some(_) if e.len() == 2 => {
                                self.problem(
                                    "RC-EXP-03",
                                    e[1].text_range(),
                                    format!("tuple index out of range 1..{}", ts.len()),
                                );
                                Ty::Error
                            }
                            _ if e.len() != 2 => {
                                self.problem(
                                    "RC-EXP-01",
                                    n.text_range(),
                                    "a tuple is indexed by exactly one numeral".into(),
                                );
                                Ty::Error
                            }
                            _ => {
                                self.problem(
                                    "RC-EXP-02",
                                    e[1].text_range(),
                                    format!("a tuple index must be a numeral in 1..{}", ts.len()),
                                );
                                Ty::Error
                            }
                        }
                    }
                    _ => Ty::Error,
                }
            }
            CALL_EXPR => self.call_expr(n),
            SIM_REF_EXPR => {
                // `$e` (an event) is boolean; `$v` has v's type.
                let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { return Ty::Error };
                if let Some(suffix) = n.children().find(|c| matches!(c.kind(), SIM_SYNC_SUFFIX | SIM_INPUT_SUFFIX)) {
                    for e in operand_exprs(&suffix) {
                        self.expr(&e);
                    }
                    // `$e?x`: the event's values must fit the variable (RS-IO-07).
                    if suffix.kind() == SIM_INPUT_SUFFIX {
                        let et = self.targets.get(&q.text_range()).map(|t| self.target_type(*t));
                        let var = suffix.children().find(|c| c.kind() == QUALIFIED_NAME);
                        let vt =
                            var.as_ref().and_then(|v| self.targets.get(&v.text_range())).map(|t| self.target_type(*t));
                        if let (Some(et), Some(vt), Some(var)) = (et, vt, var) {
                            if !compatible(&et, &vt) {
                                self.problem(
                                    "RS-IO-07",
                                    var.text_range(),
                                    format!(
                                        "`{}` has type {vt} and cannot hold values of type {et}",
                                        var.text().to_string().trim()
                                    ),
                                );
                            }
                        }
                    }
                    return Ty::Bool;
                }
                match self.targets.get(&q.text_range()) {
                    Some(Target::Def(f, id)) if self.unit.defs_of(self.db, *f, *id).def(*id).kind == DefKind::Event => {
                        Ty::Bool
                    }
                    Some(Target::Member(loc, i))
                        if loc.summary(self.db).members[*i as usize].kind == DefKind::Event =>
                    {
                        Ty::Bool
                    }
                    Some(t) => self.target_type(*t),
                    None => Ty::Error,
                }
            }
            _ => Ty::Error,
        }
    }

    pub(super) fn binary(&mut self, n: &SyntaxNode) -> Ty {
        let mut e = operands(n);
        let (Some(a), Some(b)) = (e.next(), e.next()) else { return Ty::Error };
        let (a, b) = (&a, &b);
        let Some(op) = binary_operator(n) else { return Ty::Error };
        let (x, y) = (self.expr(a), self.expr(b));
        let bad = |t: &Ty| !t.is_unknown();
        match op {
            AND | OR | IMPLIES | IFF_KW => {
                self.expect_bool(&x, a, "RC-EXP-14", &format!("an operand of `{}`", op_text(op)));
                self.expect_bool(&y, b, "RC-EXP-14", &format!("an operand of `{}`", op_text(op)));
                Ty::Bool
            }
            LT | LTEQ | GT | GTEQ | EQ2 if [a, b].iter().any(|e| is_timed(&unparen(e))) => {
                for (t, s) in [(&x, a), (&y, b)] {
                    if !compatible(t, &Ty::Real) && bad(t) {
                        self.problem(
                            "RC:TE4",
                            s.text_range(),
                            format!("a timed expression is compared with a number; this has type {t}"),
                        );
                    }
                }
                Ty::Bool
            }
            EQ2 | NEQ => {
                // Sequences and sets of the same elements compare (RoboTool).
                let seq_set = |p: &Ty, q: &Ty| match (p, q) {
                    (Ty::Seq(a), Ty::Set(b)) => compatible(a, b) || compatible(b, a),
                    _ => false,
                };
                if !compatible(&x, &y) && !compatible(&y, &x) && !seq_set(&x, &y) && !seq_set(&y, &x) {
                    self.problem("RC-EXP-14", n.text_range(), format!("cannot compare {x} with {y}"));
                }
                Ty::Bool
            }
            LT | LTEQ | GT | GTEQ => {
                for (t, s) in [(&x, a), (&y, b)] {
                    if !compatible(t, &Ty::Real) && bad(t) {
                        self.problem(
                            "RC-EXP-14",
                            s.text_range(),
                            format!("`{}` compares numbers; this has type {t}", op_text(op)),
                        );
                    }
                }
                Ty::Bool
            }
            IN_KW => {
                match &y {
                    Ty::Set(el) => {
                        if !compatible(&x, el) && !compatible(el, &x) {
                            self.problem(
                                "RC-EXP-14",
                                a.text_range(),
                                format!("an element of type {x} cannot be in a set of {el}"),
                            );
                        }
                    }
                    Ty::Seq(_) | Ty::Relation(..) | Ty::Function(..) => {}
                    t if t.is_unknown() => {}
                    t => self.problem(
                        "RC-EXP-14",
                        b.text_range(),
                        format!("`in` needs a set on its right; this has type {t}"),
                    ),
                }
                Ty::Bool
            }
            PLUS | MINUS | STAR | SLASH | PERCENT => {
                if matches!(x, Ty::Vector(..) | Ty::Matrix(..)) || matches!(y, Ty::Vector(..) | Ty::Matrix(..)) {
                    return if matches!(x, Ty::Vector(..) | Ty::Matrix(..)) { x } else { y };
                }
                for (t, s) in [(&x, a), (&y, b)] {
                    if !t.is_numeric() {
                        self.problem(
                            "RC-EXP-14",
                            s.text_range(),
                            format!("`{}` needs numbers; this has type {t}", op_text(op)),
                        );
                        return Ty::Error;
                    }
                }
                if x.is_unknown() || y.is_unknown() {
                    return if op == SLASH { Ty::Real } else { Ty::Error };
                }
                let r = x.rank().max(y.rank()).unwrap_or(2);
                match op {
                    SLASH => Ty::Real,
                    MINUS if r == 0 => Ty::Int,
                    _ => [Ty::Nat, Ty::Int, Ty::Real][r as usize].clone(),
                }
            }
            CAT_KW | CARET => match (&x, &y) {
                (Ty::Str, Ty::Str) => Ty::Str,
                (Ty::Seq(p), Ty::Seq(q)) => Ty::Seq(Box::new(join(p, q))),
                (t, u) if t.is_unknown() || u.is_unknown() => Ty::Error,
                (t, u) => {
                    self.problem(
                        "RC-EXP-14",
                        n.text_range(),
                        format!("concatenation needs two sequences or two strings; found {t} and {u}"),
                    );
                    Ty::Error
                }
            },
            _ => Ty::Error,
        }
    }

    /// The arguments of the call `n` with their types (none without an
    /// argument list).
    pub(super) fn typed_args(&mut self, n: &SyntaxNode) -> Vec<(SyntaxNode, Ty)> {
        let Some(al) = n.children().find(|c| c.kind() == ARG_LIST) else { return Vec::new() };
        operands(&al)
            .map(|x| {
                let t = self.expr(&x);
                (x, t)
            })
            .collect()
    }

    pub(super) fn call_expr(&mut self, n: &SyntaxNode) -> Ty {
        let Some(callee) = &first_operand(n) else { return Ty::Error };
        let args = self.typed_args(n);
        // A function: check arity and argument types with generics.
        if callee.kind() == REF_EXPR {
            if let Some(r) = callee.children().find(|c| c.kind() == NAME_REF) {
                if let Some(Target::Item(loc)) = self.targets.get(&r.text_range()).copied() {
                    let s = loc.summary(self.db);
                    if s.kind == DefKind::Function {
                        let name = s.name.clone();
                        let params = self.function_params_of(loc);
                        let result = self.function_result_of(loc);
                        if params.len() != args.len() {
                            self.problem(
                                "RC-EXP-09",
                                n.text_range(),
                                format!("`{name}` takes {}, not {}", arguments(params.len()), args.len()),
                            );
                            return substitute(&result, &HashMap::new());
                        }
                        let mut subst = HashMap::new();
                        for (p, (_, a)) in params.iter().zip(&args) {
                            unify(p, a, &mut subst);
                        }
                        for (i, (p, (x, a))) in params.iter().zip(&args).enumerate() {
                            let p = substitute(p, &subst);
                            if !compatible(a, &p) {
                                self.problem(
                                    "RC-EXP-10",
                                    x.text_range(),
                                    format!(
                                        "argument {} of `{name}` has type {a}, expected {p}{}",
                                        i + 1,
                                        if has_open_interval(x) {
                                            " (`(a, b)` is an open interval; a pair is written `(|a, b|)`)"
                                        } else {
                                            ""
                                        }
                                    ),
                                );
                            }
                        }
                        return substitute(&result, &subst);
                    }
                }
            }
        }
        // An enumeration constructor `E::L(a, …)` (RC-EXP-06…08).
        if let Some((loc, i)) = self.literal_of(callee) {
            let s = loc.summary(self.db);
            let lit = &s.members[i as usize];
            let params: Vec<Ty> = lit
                .params
                .iter()
                .map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error))
                .collect();
            let name = lit.name.clone();
            if params.is_empty() {
                if args.is_empty() {
                    self.problem(
                        "RC-EXP-06",
                        n.text_range(),
                        format!("`{name}` takes no arguments: drop the parentheses"),
                    );
                } else {
                    self.problem(
                        "RC-EXP-07",
                        n.text_range(),
                        format!("`{name}` takes no arguments, not {}", args.len()),
                    );
                }
            } else if params.len() != args.len() {
                self.problem(
                    "RC-EXP-07",
                    n.text_range(),
                    format!("`{name}` takes {}, not {}", arguments(params.len()), args.len()),
                );
            } else {
                for (k, (p, (x, a))) in params.iter().zip(&args).enumerate() {
                    if !compatible(a, p) {
                        self.problem(
                            "RC-EXP-08",
                            x.text_range(),
                            format!("argument {} of `{name}` has type {a}, expected {p}", k + 1),
                        );
                    }
                }
            }
            return self.named(loc, DefKind::Enumeration);
        }
        let t = self.expr(callee);
        match t {
            Ty::Function(_, b) | Ty::Relation(_, b) => *b,
            Ty::Named(_, _, DefKind::Enumeration) => t,
            _ => Ty::Error,
        }
    }
}
