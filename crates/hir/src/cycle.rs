//! The paper's cycle rules (catalogue §1.1, RS:M1/C1/SM1, RS:M2/C2,
//! RS-CYC-01…03): a `cycleDef` is a boolean condition on the simulation
//! period `cycle`, and the conditions of a module and its controllers, and
//! of a controller and its machines, admit a common positive period.
//!
//! Feasibility is decided exactly for the fragment of linear arithmetic in
//! one unknown with constant moduli: the formula is evaluated with exact
//! rationals and three-valued logic at every period up to a bound beyond
//! which every atom is constant or periodic.

use std::collections::HashMap;

use robosim_syntax::ast::{binary_operator, operand_exprs};
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use salsa::plumbing::AsId;

use crate::checks::{Anchor, Place, Problem};
use crate::defs::{DefData, DefId, DefKind, FileDefs};
use crate::element::{element_defs, element_list, element_of, Element};
use crate::element_rules::defs_at;
use crate::index::{resolve_item, ItemLoc};
use crate::{Db, File, Workspace};

/// An exact rational with a positive denominator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rational {
    num: i128,
    den: i128,
}

fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}

impl Rational {
    fn new(num: i128, den: i128) -> Option<Rational> {
        if den == 0 {
            return None;
        }
        let g = gcd(num, den);
        let s = if den < 0 { -1 } else { 1 };
        Some(Rational { num: s * num / g, den: s * den / g })
    }
    fn int(v: i128) -> Rational {
        Rational { num: v, den: 1 }
    }
    fn add(self, o: Rational) -> Option<Rational> {
        Rational::new(
            self.num.checked_mul(o.den)?.checked_add(o.num.checked_mul(self.den)?)?,
            self.den.checked_mul(o.den)?,
        )
    }
    fn neg(self) -> Rational {
        Rational { num: -self.num, den: self.den }
    }
    fn mul(self, o: Rational) -> Option<Rational> {
        Rational::new(self.num.checked_mul(o.num)?, self.den.checked_mul(o.den)?)
    }
    fn div(self, o: Rational) -> Option<Rational> {
        Rational::new(self.num.checked_mul(o.den)?, self.den.checked_mul(o.num)?)
    }
    fn is_int(self) -> bool {
        self.den == 1
    }
    fn cmp(self, o: Rational) -> Option<std::cmp::Ordering> {
        Some(self.num.checked_mul(o.den)?.cmp(&o.num.checked_mul(self.den)?))
    }
    fn ceil(self) -> i128 {
        if self.num >= 0 {
            (self.num + self.den - 1) / self.den
        } else {
            self.num / self.den
        }
    }
}

/// A term: linear `a·cycle + b`, or unknown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Term {
    Lin(Rational, Rational),
    /// `(p·cycle + q) % m` with integer p, q and positive integer m.
    Mod(i128, i128, i128),
    Unknown,
}

/// A formula over the period.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Formula {
    Const(bool),
    Unknown,
    Cmp(SyntaxKind, Term, Term),
    Not(Box<Formula>),
    And(Box<Formula>, Box<Formula>),
    Or(Box<Formula>, Box<Formula>),
    Implies(Box<Formula>, Box<Formula>),
    Iff(Box<Formula>, Box<Formula>),
    If(Box<Formula>, Box<Formula>, Box<Formula>),
}

/// Kleene's three-valued truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tv {
    T,
    F,
    U,
}

impl Tv {
    fn not(self) -> Tv {
        match self {
            Tv::T => Tv::F,
            Tv::F => Tv::T,
            Tv::U => Tv::U,
        }
    }
    fn and(self, o: Tv) -> Tv {
        match (self, o) {
            (Tv::F, _) | (_, Tv::F) => Tv::F,
            (Tv::T, Tv::T) => Tv::T,
            _ => Tv::U,
        }
    }
    fn or(self, o: Tv) -> Tv {
        self.not().and(o.not()).not()
    }
}

fn eval_term(t: Term, c: i128) -> Option<Rational> {
    match t {
        Term::Lin(a, b) => a.mul(Rational::int(c))?.add(b),
        Term::Mod(p, q, m) => Some(Rational::int(p.checked_mul(c)?.checked_add(q)? % m)),
        Term::Unknown => None,
    }
}

fn eval(f: &Formula, c: i128) -> Tv {
    match f {
        Formula::Const(b) => {
            if *b {
                Tv::T
            } else {
                Tv::F
            }
        }
        Formula::Unknown => Tv::U,
        Formula::Cmp(op, a, b) => {
            let (Some(x), Some(y)) = (eval_term(*a, c), eval_term(*b, c)) else { return Tv::U };
            let Some(ord) = x.cmp(y) else { return Tv::U };
            use std::cmp::Ordering::*;
            let r = match op {
                EQ2 => ord == Equal,
                NEQ => ord != Equal,
                LT => ord == Less,
                LTEQ => ord != Greater,
                GT => ord == Greater,
                GTEQ => ord != Less,
                _ => return Tv::U,
            };
            if r {
                Tv::T
            } else {
                Tv::F
            }
        }
        Formula::Not(a) => eval(a, c).not(),
        Formula::And(a, b) => eval(a, c).and(eval(b, c)),
        Formula::Or(a, b) => eval(a, c).or(eval(b, c)),
        Formula::Implies(a, b) => eval(a, c).not().or(eval(b, c)),
        Formula::Iff(a, b) => {
            let (x, y) = (eval(a, c), eval(b, c));
            if x == Tv::U || y == Tv::U {
                Tv::U
            } else if x == y {
                Tv::T
            } else {
                Tv::F
            }
        }
        Formula::If(k, a, b) => match eval(k, c) {
            Tv::T => eval(a, c),
            Tv::F => eval(b, c),
            Tv::U => {
                let (x, y) = (eval(a, c), eval(b, c));
                if x == y {
                    x
                } else {
                    Tv::U
                }
            }
        },
    }
}

/// Breakpoints and moduli of a formula (for the search bound).
fn bounds(f: &Formula, points: &mut Vec<Rational>, moduli: &mut Vec<i128>) {
    match f {
        Formula::Cmp(_, a, b) => {
            for t in [a, b] {
                if let Term::Mod(_, _, m) = t {
                    moduli.push(*m);
                }
            }
            if let (Term::Lin(a1, b1), Term::Lin(a2, b2)) = (a, b) {
                // (a1 - a2)·c + (b1 - b2) ⋈ 0 changes only at −(b1−b2)/(a1−a2).
                if let (Some(a), Some(b)) = (a1.add(a2.neg()), b1.add(b2.neg())) {
                    if a.num != 0 {
                        if let Some(p) = b.neg().div(a) {
                            points.push(p);
                        }
                    }
                }
            }
        }
        Formula::Not(a) => bounds(a, points, moduli),
        Formula::And(a, b) | Formula::Or(a, b) | Formula::Implies(a, b) | Formula::Iff(a, b) => {
            bounds(a, points, moduli);
            bounds(b, points, moduli);
        }
        Formula::If(k, a, b) => {
            bounds(k, points, moduli);
            bounds(a, points, moduli);
            bounds(b, points, moduli);
        }
        Formula::Const(_) | Formula::Unknown => {}
    }
}

/// The search budget: beyond it the answer is "unknown".
const BUDGET: i128 = 1_000_000;

/// The outcome of deciding a conjunction of cycle specifications.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Feasibility {
    /// Satisfied at this least positive period.
    Feasible(u64),
    /// False at every positive period.
    Infeasible,
    /// Depends on parts outside the decidable fragment, or too large.
    Unknown,
}

fn decide(conj: &[&Formula]) -> Feasibility {
    let mut points = Vec::new();
    let mut moduli = Vec::new();
    for f in conj {
        bounds(f, &mut points, &mut moduli);
    }
    let mut l: i128 = 1;
    for m in moduli {
        let g = gcd(l, m);
        l = match (l / g).checked_mul(m) {
            Some(v) if v <= BUDGET => v,
            _ => return Feasibility::Unknown,
        };
    }
    let max_p = points.iter().map(|p| p.ceil()).max().unwrap_or(0);
    let b = (max_p + 1).max(1);
    let Some(limit) = b.checked_add(l).filter(|v| *v <= BUDGET) else { return Feasibility::Unknown };
    let mut unknown = false;
    for c in 1..=limit {
        let v = conj.iter().fold(Tv::T, |acc, f| acc.and(eval(f, c)));
        match v {
            Tv::T => return Feasibility::Feasible(c as u64),
            Tv::U => unknown = true,
            Tv::F => {}
        }
    }
    if unknown {
        Feasibility::Unknown
    } else {
        Feasibility::Infeasible
    }
}

/// What a spec's expression is, as far as the boolean check can tell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Shape {
    Boolean,
    Number,
    Set,
    Other,
    Unknown,
}

struct Lowerer<'a> {
    consts: &'a HashMap<String, SyntaxNode>,
    /// Values given to constants from outside the model (an assertion's
    /// `with constant k of X set to v`); they win over initialisers.
    bound: &'a [(String, i64)],
    /// Every constant in scope (with or without a foldable initialiser).
    const_names: &'a std::collections::HashSet<String>,
    depth: u32,
    /// Parts outside "cycle, literals and constants" (for RS-CYC-02).
    impure: Vec<TextRange>,
}

impl Lowerer<'_> {
    fn shape(&mut self, n: &SyntaxNode) -> Shape {
        match n.kind() {
            LITERAL => match n.first_token().map(|t| t.kind()) {
                Some(TRUE_KW | FALSE_KW) => Shape::Boolean,
                Some(INT_NUMBER | FLOAT_NUMBER) => Shape::Number,
                _ => Shape::Other,
            },
            CYCLE_EXPR => Shape::Number,
            PAREN_EXPR => operand_exprs(n).first().map(|e| self.shape(e)).unwrap_or(Shape::Unknown),
            PREFIX_EXPR => {
                if n.children_with_tokens().any(|t| t.kind() == NOT_KW) {
                    Shape::Boolean
                } else {
                    Shape::Number
                }
            }
            BIN_EXPR => match binary_operator(n) {
                Some(EQ2 | NEQ | LT | LTEQ | GT | GTEQ | IN_KW | AND | OR | IMPLIES | IFF_KW) => Shape::Boolean,
                // Sequence concatenation, like a missing operator, has no numeric shape.
                Some(CAT_KW | CARET) | None => Shape::Unknown,
                Some(_) => Shape::Number,
            },
            SET_EXPR | SET_RANGE_EXPR | SET_COMP_EXPR | INTERVAL_EXPR => Shape::Set,
            SEQ_EXPR | TUPLE_EXPR | STRING => Shape::Other,
            FORALL_EXPR | EXISTS_EXPR | TYPE_TEST_EXPR => {
                if n.children_with_tokens().any(|t| t.kind() == AS_KW) {
                    Shape::Unknown
                } else {
                    Shape::Boolean
                }
            }
            IF_EXPR => operand_exprs(n).get(1).map(|e| self.shape(e)).unwrap_or(Shape::Unknown),
            REF_EXPR => {
                let name = crate::defs::name_text(n);
                match self.consts.get(&name).cloned() {
                    Some(init) if self.depth < 16 => {
                        self.depth += 1;
                        let s = self.shape(&init);
                        self.depth -= 1;
                        s
                    }
                    _ => Shape::Unknown,
                }
            }
            _ => Shape::Unknown,
        }
    }

    fn formula(&mut self, n: &SyntaxNode) -> Formula {
        match n.kind() {
            PAREN_EXPR => operand_exprs(n).first().map(|e| self.formula(e)).unwrap_or(Formula::Unknown),
            LITERAL => match n.first_token().map(|t| t.kind()) {
                Some(TRUE_KW) => Formula::Const(true),
                Some(FALSE_KW) => Formula::Const(false),
                _ => Formula::Unknown,
            },
            PREFIX_EXPR if n.children_with_tokens().any(|t| t.kind() == NOT_KW) => {
                Formula::Not(Box::new(operand_exprs(n).first().map(|e| self.formula(e)).unwrap_or(Formula::Unknown)))
            }
            IF_EXPR => {
                let e = operand_exprs(n);
                if e.len() != 3 {
                    return Formula::Unknown;
                }
                Formula::If(Box::new(self.formula(&e[0])), Box::new(self.formula(&e[1])), Box::new(self.formula(&e[2])))
            }
            BIN_EXPR => {
                let e = operand_exprs(n);
                let (Some(a), Some(b)) = (e.first(), e.get(1)) else { return Formula::Unknown };
                match binary_operator(n) {
                    Some(AND) => Formula::And(Box::new(self.formula(a)), Box::new(self.formula(b))),
                    Some(OR) => Formula::Or(Box::new(self.formula(a)), Box::new(self.formula(b))),
                    Some(IMPLIES) => Formula::Implies(Box::new(self.formula(a)), Box::new(self.formula(b))),
                    Some(IFF_KW) => Formula::Iff(Box::new(self.formula(a)), Box::new(self.formula(b))),
                    Some(op @ (EQ2 | NEQ | LT | LTEQ | GT | GTEQ)) => {
                        let (x, y) = (self.term(a), self.term(b));
                        if x == Term::Unknown || y == Term::Unknown {
                            Formula::Unknown
                        } else {
                            Formula::Cmp(op, x, y)
                        }
                    }
                    Some(IN_KW) => self.membership(a, b),
                    _ => Formula::Unknown,
                }
            }
            REF_EXPR => {
                let name = crate::defs::name_text(n);
                match self.consts.get(&name).cloned() {
                    Some(init) if self.depth < 16 => {
                        self.depth += 1;
                        let f = self.formula(&init);
                        self.depth -= 1;
                        f
                    }
                    _ => {
                        if !self.const_names.contains(&name) {
                            self.impure.push(n.text_range());
                        }
                        Formula::Unknown
                    }
                }
            }
            _ => {
                self.mark_impure(n);
                Formula::Unknown
            }
        }
    }

    fn membership(&mut self, x: &SyntaxNode, set: &SyntaxNode) -> Formula {
        let t = self.term(x);
        if t == Term::Unknown {
            return Formula::Unknown;
        }
        let e = operand_exprs(set);
        match set.kind() {
            SET_EXPR => e
                .iter()
                .map(|k| match self.term(k) {
                    Term::Unknown => Formula::Unknown,
                    k => Formula::Cmp(EQ2, t, k),
                })
                .reduce(|a, b| Formula::Or(Box::new(a), Box::new(b)))
                .unwrap_or(Formula::Const(false)),
            SET_RANGE_EXPR | INTERVAL_EXPR if e.len() == 2 => {
                let (lo, hi) = (self.term(&e[0]), self.term(&e[1]));
                if lo == Term::Unknown || hi == Term::Unknown {
                    return Formula::Unknown;
                }
                let text = set.text().to_string();
                let text = text.trim();
                let (lo_op, hi_op) = if set.kind() == SET_RANGE_EXPR {
                    (GTEQ, LTEQ)
                } else {
                    (if text.starts_with('(') { GT } else { GTEQ }, if text.ends_with(')') { LT } else { LTEQ })
                };
                Formula::And(Box::new(Formula::Cmp(lo_op, t, lo)), Box::new(Formula::Cmp(hi_op, t, hi)))
            }
            _ => Formula::Unknown,
        }
    }

    fn mark_impure(&mut self, n: &SyntaxNode) {
        let is_const =
            n.kind() == REF_EXPR && self.const_names.contains(n.text().to_string().trim().trim_start_matches('^'));
        if matches!(n.kind(), SIM_REF_EXPR | SINCE_EXPR | SINCE_ENTRY_EXPR | REF_EXPR | CALL_EXPR) && !is_const {
            self.impure.push(n.text_range());
        }
    }

    fn term(&mut self, n: &SyntaxNode) -> Term {
        match n.kind() {
            CYCLE_EXPR => Term::Lin(Rational::int(1), Rational::int(0)),
            LITERAL => {
                let text = n.text().to_string();
                let text = text.trim();
                match text.split_once('.') {
                    Some((i, f)) => {
                        let den = 10i128.checked_pow(f.len() as u32);
                        match (format!("{i}{f}").parse::<i128>().ok(), den) {
                            (Some(num), Some(den)) => {
                                Rational::new(num, den).map(|r| Term::Lin(Rational::int(0), r)).unwrap_or(Term::Unknown)
                            }
                            _ => Term::Unknown,
                        }
                    }
                    None => text
                        .parse::<i128>()
                        .map(|v| Term::Lin(Rational::int(0), Rational::int(v)))
                        .unwrap_or(Term::Unknown),
                }
            }
            PAREN_EXPR => operand_exprs(n).first().map(|e| self.term(e)).unwrap_or(Term::Unknown),
            PREFIX_EXPR => match operand_exprs(n).first().map(|e| self.term(e)) {
                Some(Term::Lin(a, b)) => Term::Lin(a.neg(), b.neg()),
                _ => Term::Unknown,
            },
            REF_EXPR => {
                let name = crate::defs::name_text(n);
                if let Some((_, v)) = self.bound.iter().find(|(k, _)| *k == name) {
                    return Term::Lin(Rational::int(0), Rational::int(i128::from(*v)));
                }
                match self.consts.get(&name).cloned() {
                    Some(init) if self.depth < 16 => {
                        self.depth += 1;
                        let t = self.term(&init);
                        self.depth -= 1;
                        t
                    }
                    _ => {
                        if !self.const_names.contains(&name) {
                            self.impure.push(n.text_range());
                        }
                        Term::Unknown
                    }
                }
            }
            BIN_EXPR => {
                let e = operand_exprs(n);
                let (Some(a), Some(b)) = (e.first(), e.get(1)) else { return Term::Unknown };
                let (x, y) = (self.term(a), self.term(b));
                let (Term::Lin(a1, b1), Term::Lin(a2, b2)) = (x, y) else { return Term::Unknown };
                let zero = Rational::int(0);
                let r = match binary_operator(n) {
                    Some(PLUS) => a1.add(a2).zip(b1.add(b2)),
                    Some(MINUS) => a1.add(a2.neg()).zip(b1.add(b2.neg())),
                    Some(STAR) if a2 == zero => a1.mul(b2).zip(b1.mul(b2)),
                    Some(STAR) if a1 == zero => a2.mul(b1).zip(b2.mul(b1)),
                    Some(SLASH) if a2 == zero && b2 != zero => a1.div(b2).zip(b1.div(b2)),
                    Some(PERCENT) if a2 == zero && b2.is_int() && b2.num > 0 && a1.is_int() && b1.is_int() => {
                        return Term::Mod(a1.num, b1.num, b2.num);
                    }
                    _ => None,
                };
                r.map(|(a, b)| Term::Lin(a, b)).unwrap_or(Term::Unknown)
            }
            _ => {
                self.mark_impure(n);
                Term::Unknown
            }
        }
    }
}

/// One container's cycle specification.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Spec {
    file: File,
    /// What `range` and `impure` are relative to.
    anchor: Anchor,
    /// The expression's range.
    range: TextRange,
    formula: Formula,
    shape: Shape,
    impure: Vec<TextRange>,
}

/// The cycle specification of a definition (its first `cycleDef`), from
/// its element's specifications: unchanged by edits that leave the
/// element's `cycleDef`s alone.
fn spec_of(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> Option<Spec> {
    let e = element_of(db, file, id)?;
    element_specs(db, ws, e).iter().find(|(d, _)| *d == id).map(|(_, s)| s.clone())
}

/// The cycle specifications of the modules, controllers and machines of
/// `element`, positions relative to its start.
#[salsa::tracked(returns(ref))]
pub(crate) fn element_specs(db: &dyn Db, ws: Workspace, element: Element) -> Vec<(DefId, Spec)> {
    let (file, defs) = (element.file(db), element_defs(db, element));
    let root = SyntaxNode::new_root(element.green(db).0.clone());
    let anchor = Anchor::Element(element.as_id());
    defs.iter()
        .filter(|(_, d)| matches!(d.kind, DefKind::Module | DefKind::Controller | DefKind::StateMachine))
        .filter_map(|(id, _)| Some((id, spec_in(db, ws, file, defs, &root, anchor, id, &[])?)))
        .collect()
}

/// [`spec_of`], with constants bound to values from outside the model.
fn spec_bound(db: &dyn Db, ws: Workspace, file: File, id: DefId, bound: &[(String, i64)]) -> Option<Spec> {
    let e = element_of(db, file, id)?;
    let root = SyntaxNode::new_root(e.green(db).0.clone());
    spec_in(db, ws, file, element_defs(db, e), &root, Anchor::Element(e.as_id()), id, bound)
}

/// The specification of `id`, read from `defs` and the tree `root` their
/// positions are in.
#[allow(clippy::too_many_arguments)]
fn spec_in(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    defs: &FileDefs,
    root: &SyntaxNode,
    anchor: Anchor,
    id: DefId,
    bound: &[(String, i64)],
) -> Option<Spec> {
    let range = *defs.facts(id).cycle_defs.first()?;
    let node = expr_at(root, range)?;
    // Constants of the container with initialisers fold into the formula.
    let mut consts = HashMap::new();
    for (_, c) in defs.children(Some(id)) {
        if let (DefKind::Constant, DefData::Typed { init: Some(init), .. }) = (c.kind, &c.data) {
            if let Some(n) = expr_at(root, *init) {
                consts.insert(c.name.clone(), n);
            }
        }
    }
    let const_names: std::collections::HashSet<String> =
        crate::resolve::ctx_members(db, ws, crate::resolve::Ctx::Local(file, id))
            .iter()
            .filter(|m| m.kind == DefKind::Constant)
            .map(|m| m.name.clone())
            .collect();
    let mut l = Lowerer { consts: &consts, bound, const_names: &const_names, depth: 0, impure: Vec::new() };
    let shape = l.shape(&node);
    let formula = if shape == Shape::Boolean { l.formula(&node) } else { Formula::Unknown };
    Some(Spec { file, anchor, range, formula, shape, impure: l.impure })
}

/// The expression node with exactly `range`.
fn expr_at(root: &SyntaxNode, range: TextRange) -> Option<SyntaxNode> {
    let el = root.covering_element(range);
    let start = match el {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    start.ancestors().find(|n| n.text_range() == range && robosim_syntax::ast::is_expr_kind(n.kind()))
}

/// What is known about a container's period, for hovers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CycleInfo {
    /// The least admissible period of the container's own specification.
    pub own: Feasibility,
    /// The least admissible period shared with its sub-components (module:
    /// its controllers; controller: its machines).
    pub joint: Option<Feasibility>,
}

/// What the cycle rules found about the period of every RoboSim
/// container of `file` (put together from its elements').
#[salsa::tracked(returns(ref))]
pub fn cycle_infos(db: &dyn Db, ws: Workspace, file: File) -> Vec<(DefId, CycleInfo)> {
    element_list(db, file)
        .iter()
        .flat_map(|e| crate::element_rules::element_cycles(db, ws, *e).1.iter().copied())
        .collect()
}

/// The cycle rules of the RoboSim containers of `defs` (one element of
/// `file`), positions relative to the element's start.
pub(crate) fn element_cycle_checks(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    defs: &FileDefs,
) -> (Vec<Problem>, Vec<(DefId, CycleInfo)>) {
    let mut problems = Vec::new();
    let mut infos = Vec::new();
    if file.kind(db) != robosim_syntax::FileKind::RoboSim {
        return (problems, infos);
    }
    for (id, d) in defs.iter() {
        let code = match d.kind {
            DefKind::Module => "RS:M1",
            DefKind::Controller => "RS:C1",
            DefKind::StateMachine => "RS:SM1",
            _ => continue,
        };
        let Some(spec) = spec_of(db, ws, file, id) else { continue };
        let what = format!("{} `{}`", d.kind.describe(), d.name);
        match spec.shape {
            Shape::Number | Shape::Set | Shape::Other => {
                let got = match spec.shape {
                    Shape::Number => "a number",
                    Shape::Set => "a set",
                    _ => "not a condition",
                };
                problems.push(Problem::new(
                    code,
                    spec.range,
                    format!(
                        "the cycleDef of {what} must be a boolean condition on `cycle`, such as `cycle == 1`; this is {got}"
                    ),
                ));
                continue;
            }
            Shape::Boolean | Shape::Unknown => {}
        }
        for r in &spec.impure {
            problems.push(Problem::new(
                "RS-CYC-02",
                *r,
                "a cycle specification may mention only `cycle`, literals and constants: the period is fixed before the simulation starts",
            ));
        }
        let own = decide(&[&spec.formula]);
        if own == Feasibility::Infeasible {
            problems.push(Problem::new(
                "RS-CYC-01",
                spec.range,
                format!("the cycleDef of {what} admits no positive period"),
            ));
        }
        // The components whose specifications must agree with this one.
        let parts: Vec<(String, TextRange, Option<Spec>)> = match d.kind {
            DefKind::Module => components(db, ws, file, id, &[DefKind::Controller], DefKind::ControllerRef),
            DefKind::Controller => components(db, ws, file, id, &[DefKind::StateMachine], DefKind::MachineRef),
            _ => Vec::new(),
        };
        let joint = if parts.is_empty() {
            None
        } else if parts.iter().any(|(_, _, s)| s.as_ref().is_none_or(|s| s.shape != Shape::Boolean)) {
            // A missing or ill-typed part is reported on its own. A part
            // that contradicts itself (RS-CYC-01) still makes the conjunction
            // the paper's rule speaks of unsatisfiable: that is C2/M2 here.
            None
        } else {
            let all: Vec<&Formula> = std::iter::once(&spec.formula)
                .chain(parts.iter().filter_map(|(_, _, s)| s.as_ref().map(|s| &s.formula)))
                .collect();
            let verdict = decide(&all);
            match verdict {
                Feasibility::Infeasible => {
                    // A minimal infeasible subset: drop parts while it stays infeasible.
                    let mut keep: Vec<usize> = (0..parts.len()).collect();
                    let mut i = 0;
                    while i < keep.len() {
                        let trial: Vec<usize> = keep.iter().copied().filter(|k| *k != keep[i]).collect();
                        let f: Vec<&Formula> = std::iter::once(&spec.formula)
                            .chain(trial.iter().filter_map(|k| parts[*k].2.as_ref().map(|s| &s.formula)))
                            .collect();
                        if decide(&f) == Feasibility::Infeasible {
                            keep = trial;
                        } else {
                            i += 1;
                        }
                    }
                    let (rule, sub) =
                        if d.kind == DefKind::Module { ("RS:M2", "controllers") } else { ("RS:C2", "machines") };
                    let mut related = Vec::new();
                    for k in &keep {
                        let (name, via, s) = &parts[*k];
                        if let Some(s) = s {
                            related.push((
                                Place { file: s.file, anchor: s.anchor, range: s.range },
                                format!("the cycleDef of `{name}`"),
                            ));
                        }
                        if via != &TextRange::empty(0.into()) {
                            related.push((Place::here(file, *via), format!("`{name}` is part of {what} here")));
                        }
                    }
                    if keep.is_empty() {
                        // The element's own contradiction is the whole story: one
                        // diagnostic (the rule's) instead of RS-CYC-01 as well.
                        problems.retain(|p| !(p.code == "RS-CYC-01" && p.range == spec.range));
                    }
                    problems.push(Problem {
                        code: rule,
                        range: spec.range,
                        anchor: Anchor::Here,
                        message: if keep.is_empty() {
                            format!("the cycleDef of {what} admits no positive period, so none agrees with its {sub}")
                        } else {
                            format!(
                                "no positive period satisfies the cycleDef of {what} together with those of its {sub}"
                            )
                        },
                        related,
                    });
                }
                Feasibility::Unknown => problems.push(Problem::new(
                    "RS-CYC-03",
                    spec.range,
                    format!("whether the cycle specifications of {what} and its components agree could not be decided"),
                )),
                Feasibility::Feasible(_) => {}
            }
            Some(verdict)
        };
        infos.push((id, CycleInfo { own, joint }));
    }
    (problems, infos)
}

/// The cycle specifications of a container's components: inline ones and
/// those reached through references (with the reference's range).
fn components(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    owner: DefId,
    inline: &[DefKind],
    reference: DefKind,
) -> Vec<(String, TextRange, Option<Spec>)> {
    component_defs(db, ws, file, owner, inline, reference)
        .into_iter()
        .map(|(name, via, file, def)| (name, via, spec_of(db, ws, file, def)))
        .collect()
}

/// A container's components (inline, or through a reference whose range
/// is given), each once, with where it is declared.
fn component_defs(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    owner: DefId,
    inline: &[DefKind],
    reference: DefKind,
) -> Vec<(String, TextRange, File, DefId)> {
    let defs = defs_at(db, file, owner).0;
    let mut out = Vec::new();
    let mut seen: Vec<(File, DefId)> = Vec::new();
    for (cid, c) in defs.children(Some(owner)) {
        if inline.contains(&c.kind) {
            if !seen.contains(&(file, cid)) {
                seen.push((file, cid));
                out.push((c.name.clone(), c.name_range, file, cid));
            }
        } else if c.kind == reference {
            let DefData::Reference { path, .. } = &c.data else { continue };
            let accept: fn(DefKind) -> bool = if inline[0] == DefKind::Controller {
                |k| k == DefKind::Controller
            } else {
                |k| k == DefKind::StateMachine
            };
            let Some(loc): Option<ItemLoc> = resolve_item(db, ws, file, path, accept).first().copied() else {
                continue;
            };
            let Some(def) = loc.def(db) else { continue };
            if loc.file.kind(db) != robosim_syntax::FileKind::RoboSim || seen.contains(&(loc.file, def)) {
                continue;
            }
            seen.push((loc.file, def));
            out.push((path.join("::"), c.name_range, loc.file, def));
        }
    }
    out
}

/// The period a RoboSim module, controller or machine is simulated with:
/// the least positive period that satisfies its own `cycleDef` and those
/// of every component below it (a module's controllers and their machines,
/// a controller's machines), as RoboTool's generator chooses it. `bound`
/// gives constants values from outside the model (an assertion's `with
/// constant k of X set to v`, as (the name of `X`'s declaration, `k`,
/// `v`)). `None` when nothing in the hierarchy has a `cycleDef`.
///
/// This is the one place a period is chosen: the native checker and the
/// CSPm export both ask here, so `cycle > 2` means period 3 for both.
pub fn simulation_period(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    def: DefId,
    bound: &[(String, String, i64)],
) -> Option<Feasibility> {
    let mut specs = Vec::new();
    let mut todo = vec![(file, def)];
    let mut seen = Vec::new();
    while let Some((file, def)) = todo.pop() {
        if seen.contains(&(file, def)) {
            continue;
        }
        seen.push((file, def));
        // A value binds the constant of the element it names only, as the
        // lowering reads it (`with constant K of M` is not another
        // element's `K`).
        let name = &defs_at(db, file, def).0.def(def).name;
        let own: Vec<(String, i64)> =
            bound.iter().filter(|(of, _, _)| of == name).map(|(_, k, v)| (k.clone(), *v)).collect();
        specs.extend(spec_bound(db, ws, file, def, &own));
        let below = match defs_at(db, file, def).0.def(def).kind {
            DefKind::Module => component_defs(db, ws, file, def, &[DefKind::Controller], DefKind::ControllerRef),
            DefKind::Controller => component_defs(db, ws, file, def, &[DefKind::StateMachine], DefKind::MachineRef),
            _ => Vec::new(),
        };
        todo.extend(below.into_iter().map(|(_, _, f, d)| (f, d)));
    }
    if specs.is_empty() {
        return None;
    }
    if specs.iter().any(|s| s.shape != Shape::Boolean) {
        return Some(Feasibility::Unknown);
    }
    Some(decide(&specs.iter().map(|s| &s.formula).collect::<Vec<_>>()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lin(a: i128, b: i128) -> Term {
        Term::Lin(Rational::int(a), Rational::int(b))
    }

    #[test]
    fn worked_example_of_the_catalogue() {
        // module `cycle % 4 == 0`, controller `cycle < 4`: infeasible over
        // the positive naturals (c = 0 would satisfy both).
        let m = Formula::Cmp(EQ2, Term::Mod(1, 0, 4), lin(0, 0));
        let c = Formula::Cmp(LT, lin(1, 0), lin(0, 4));
        assert_eq!(decide(&[&m, &c]), Feasibility::Infeasible);
        let c2 = Formula::Cmp(LTEQ, lin(1, 0), lin(0, 4));
        assert_eq!(decide(&[&m, &c2]), Feasibility::Feasible(4));
    }

    #[test]
    fn unknown_never_becomes_false() {
        let u = Formula::Unknown;
        let c = Formula::Cmp(EQ2, lin(1, 0), lin(0, 1));
        assert_eq!(decide(&[&u, &c]), Feasibility::Unknown);
        let f = Formula::Cmp(EQ2, lin(1, 0), lin(0, 0));
        assert_eq!(decide(&[&u, &f]), Feasibility::Infeasible);
    }
}
