//! Types and typing (catalogue §3): the types of declarations, the type of
//! every expression, compatibility `T ≼ U`, and the typing rules of
//! statements, communications, conditions and initialisers. An ill-typed
//! subexpression gets the error type, which is compatible with everything,
//! and is reported once, at the innermost cause (RC-EXP-14).

mod expr;
mod stmt;

use std::collections::HashMap;

use rustc_hash::FxHashMap;
use std::fmt;

use robosim_syntax::ast::operand_exprs;
use robosim_syntax::{ast, FileKind, SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use crate::body::body_resolution;
use crate::defs::{file_defs, lower_type, DefData, DefKind, FileDefs, TypeRef};
use crate::element::Unit;
use crate::index::{canonical_type, file_summary, resolve_item, ItemLoc};
use crate::resolve::{file_resolution, ResolveProblem, Target};
use crate::{Db, File, Workspace};

/// A semantic type.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum Ty {
    Nat,
    Int,
    Real,
    Bool,
    Str,
    /// A declared type (`type T`, record, enumeration), by declaration.
    Named(ItemLoc, String, DefKind),
    Set(Box<Ty>),
    Seq(Box<Ty>),
    Product(Vec<Ty>),
    Function(Box<Ty>, Box<Ty>),
    Relation(Box<Ty>, Box<Ty>),
    Vector(Box<Ty>, Option<i128>),
    Matrix(Box<Ty>, Option<i128>, Option<i128>),
    /// A generic parameter `?X`.
    Var(String),
    /// The element type of `{}` and `<>`: compatible with everything.
    Any,
    /// The result of an ill-typed expression: compatible with everything,
    /// reported where it arose.
    Error,
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ty::Nat => f.write_str("nat"),
            Ty::Int => f.write_str("int"),
            Ty::Real => f.write_str("real"),
            Ty::Bool => f.write_str("boolean"),
            Ty::Str => f.write_str("string"),
            Ty::Named(_, n, _) => f.write_str(n),
            Ty::Set(t) => write!(f, "Set({t})"),
            Ty::Seq(t) => write!(f, "Seq({t})"),
            Ty::Product(ts) => {
                for (i, t) in ts.iter().enumerate() {
                    if i > 0 {
                        f.write_str(" * ")?;
                    }
                    if matches!(t, Ty::Product(_) | Ty::Function(..) | Ty::Relation(..)) {
                        write!(f, "({t})")?;
                    } else {
                        write!(f, "{t}")?;
                    }
                }
                Ok(())
            }
            Ty::Function(a, b) => write!(f, "{a} -> {b}"),
            Ty::Relation(a, b) => write!(f, "{a} <-> {b}"),
            Ty::Vector(t, n) => match n {
                Some(n) => write!(f, "vector({t}, {n})"),
                None => write!(f, "vector({t}, _)"),
            },
            Ty::Matrix(t, r, c) => write!(
                f,
                "matrix({t}, {}, {})",
                r.map_or("_".to_string(), |v| v.to_string()),
                c.map_or("_".to_string(), |v| v.to_string())
            ),
            Ty::Var(n) => write!(f, "?{n}"),
            Ty::Any => f.write_str("any"),
            Ty::Error => f.write_str("{unknown}"),
        }
    }
}

impl Ty {
    /// The first generic parameter (`?X`) the type mentions, if any.
    pub fn type_variable(&self) -> Option<&str> {
        match self {
            Ty::Var(n) => Some(n),
            Ty::Set(t) | Ty::Seq(t) | Ty::Vector(t, _) | Ty::Matrix(t, _, _) => t.type_variable(),
            Ty::Product(ts) => ts.iter().find_map(Ty::type_variable),
            Ty::Function(a, b) | Ty::Relation(a, b) => a.type_variable().or_else(|| b.type_variable()),
            _ => None,
        }
    }

    fn is_numeric(&self) -> bool {
        matches!(self, Ty::Nat | Ty::Int | Ty::Real | Ty::Error | Ty::Any | Ty::Var(_))
    }
    fn rank(&self) -> Option<u8> {
        match self {
            Ty::Nat => Some(0),
            Ty::Int => Some(1),
            Ty::Real => Some(2),
            _ => None,
        }
    }
    fn is_unknown(&self) -> bool {
        matches!(self, Ty::Error | Ty::Any | Ty::Var(_))
    }
}

/// `t ≼ u`: a value of type `t` may be used where `u` is expected.
pub fn compatible(t: &Ty, u: &Ty) -> bool {
    if t.is_unknown() || u.is_unknown() {
        return true;
    }
    match (t, u) {
        (a, b) if a == b => true,
        (a, b) if a.rank().is_some() && b.rank().is_some() => a.rank() <= b.rank(),
        (Ty::Named(a, _, _), Ty::Named(b, _, _)) => a == b,
        (Ty::Set(a), Ty::Set(b)) | (Ty::Seq(a), Ty::Seq(b)) => compatible(a, b),
        (Ty::Product(a), Ty::Product(b)) => a.len() == b.len() && a.iter().zip(b).all(|(x, y)| compatible(x, y)),
        // Functions are relations; RoboTool also lets a relation stand where
        // a function is expected (its library relies on it).
        (Ty::Function(a1, b1), Ty::Function(a2, b2))
        | (Ty::Function(a1, b1), Ty::Relation(a2, b2))
        | (Ty::Relation(a1, b1), Ty::Function(a2, b2))
        | (Ty::Relation(a1, b1), Ty::Relation(a2, b2)) => compatible(a1, a2) && compatible(b1, b2),
        (Ty::Relation(a, b), Ty::Set(s)) | (Ty::Function(a, b), Ty::Set(s)) => {
            compatible(&Ty::Product(vec![(**a).clone(), (**b).clone()]), s)
        }
        (Ty::Set(s), Ty::Relation(a, b)) | (Ty::Set(s), Ty::Function(a, b)) => {
            compatible(s, &Ty::Product(vec![(**a).clone(), (**b).clone()]))
        }
        // A sequence is a set of (index, element) pairs (RoboTool).
        (Ty::Seq(e), Ty::Set(s)) => compatible(&Ty::Product(vec![Ty::Nat, (**e).clone()]), s),
        (Ty::Seq(e), Ty::Relation(a, b)) | (Ty::Seq(e), Ty::Function(a, b)) => {
            compatible(&Ty::Nat, a) && compatible(e, b)
        }
        (Ty::Vector(a, n), Ty::Vector(b, m)) => compatible(a, b) && (n.is_none() || m.is_none() || n == m),
        (Ty::Matrix(a, r1, c1), Ty::Matrix(b, r2, c2)) => {
            compatible(a, b) && (r1.is_none() || r2.is_none() || r1 == r2) && (c1.is_none() || c2.is_none() || c1 == c2)
        }
        (Ty::Vector(a, Some(n)), Ty::Product(ts)) | (Ty::Product(ts), Ty::Vector(a, Some(n))) => {
            ts.len() as i128 == *n && ts.iter().all(|t| compatible(t, a) || compatible(a, t))
        }
        // A vector holds the same values as a one-row matrix (RoboTool
        // assigns one to the other, and a vector literal to a matrix).
        (Ty::Vector(a, n), Ty::Matrix(b, r, c)) | (Ty::Matrix(a, r, c), Ty::Vector(b, n)) => {
            compatible(a, b) && r.is_none_or(|r| r == 1) && (n.is_none() || c.is_none() || n == c)
        }
        // A function of one parameter has a one-tuple domain.
        (Ty::Product(v), t) if v.len() == 1 => compatible(&v[0], t),
        (t, Ty::Product(v)) if v.len() == 1 => compatible(t, &v[0]),
        _ => false,
    }
}

/// Whether `e` contains an open interval `(a, b)`, which readers take for
/// a pair.
fn has_open_interval(e: &SyntaxNode) -> bool {
    e.descendants().any(|d| {
        d.kind() == INTERVAL_EXPR
            && d.first_token().is_some_and(|t| t.kind() == L_PAREN)
            && d.last_token().is_some_and(|t| t.kind() == R_PAREN)
    })
}

/// When `t` is a wider number than `u` (`int` for `nat`, `real` for `int`
/// or `nat`, also inside sets, sequences, products, vectors and matrices):
/// the values of `t` that `u` cannot hold.
fn narrowing(t: &Ty, u: &Ty) -> Option<&'static str> {
    match (t, u) {
        (Ty::Int, Ty::Nat) => Some("a negative value"),
        (Ty::Real, Ty::Int) => Some("a fractional value"),
        (Ty::Real, Ty::Nat) => Some("a negative or fractional value"),
        (Ty::Set(a), Ty::Set(b))
        | (Ty::Seq(a), Ty::Seq(b))
        | (Ty::Vector(a, _), Ty::Vector(b, _))
        | (Ty::Matrix(a, ..), Ty::Matrix(b, ..)) => narrowing(a, b),
        (Ty::Product(a), Ty::Product(b)) if a.len() == b.len() => {
            let mut risk = None;
            for (x, y) in a.iter().zip(b) {
                if !compatible(x, y) {
                    risk = Some(narrowing(x, y)?);
                }
            }
            risk
        }
        _ => None,
    }
}

/// The more general of two comparable types.
fn join(a: &Ty, b: &Ty) -> Ty {
    if a.is_unknown() {
        return b.clone();
    }
    if b.is_unknown() {
        return a.clone();
    }
    if compatible(a, b) {
        b.clone()
    } else {
        a.clone()
    }
}

/// Lowers a syntactic type in the scope of `file`.
pub fn lower(db: &dyn Db, ws: Workspace, file: File, t: &TypeRef) -> Ty {
    lower_by(t, &|path| named_type(db, ws, file, path))
}

/// Lowers `t`, asking `named` for the type a name denotes.
fn lower_by(t: &TypeRef, named: &impl Fn(&[String]) -> Ty) -> Ty {
    match t {
        TypeRef::Named(path, _) => named(path),
        TypeRef::Set(a) => Ty::Set(Box::new(lower_by(a, named))),
        TypeRef::Seq(a) => Ty::Seq(Box::new(lower_by(a, named))),
        TypeRef::Var(n) => Ty::Var(n.clone()),
        TypeRef::Product(v) => Ty::Product(v.iter().map(|t| lower_by(t, named)).collect()),
        TypeRef::Function(a, b) => Ty::Function(Box::new(lower_by(a, named)), Box::new(lower_by(b, named))),
        TypeRef::Relation(a, b) => Ty::Relation(Box::new(lower_by(a, named)), Box::new(lower_by(b, named))),
        TypeRef::Vector(a, _) => Ty::Vector(Box::new(lower_by(a, named)), None),
        TypeRef::Matrix(a, _, _) => Ty::Matrix(Box::new(lower_by(a, named)), None, None),
        TypeRef::Missing => Ty::Error,
    }
}

/// The type a (qualified) type name written in `file` denotes.
fn named_type(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Ty {
    let Some(loc) = resolve_item(db, ws, file, path, DefKind::is_type).first().copied() else {
        return Ty::Error;
    };
    let s = loc.summary(db);
    if file_summary(db, loc.file).package == ["core"] && s.kind == DefKind::PrimitiveType {
        return match s.name.as_str() {
            "nat" => Ty::Nat,
            "int" => Ty::Int,
            "real" => Ty::Real,
            "boolean" => Ty::Bool,
            "string" => Ty::Str,
            _ => Ty::Named(canonical_type(db, ws, loc), s.name.clone(), s.kind),
        };
    }
    Ty::Named(canonical_type(db, ws, loc), s.name.clone(), s.kind)
}

/// Instantiates generic parameters by matching a parameter type against an
/// argument type.
fn unify(param: &Ty, arg: &Ty, subst: &mut HashMap<String, Ty>) {
    match (param, arg) {
        (Ty::Var(n), a) if !a.is_unknown() => {
            let e = subst.entry(n.clone()).or_insert_with(|| a.clone());
            *e = join(e, a);
        }
        (Ty::Var(_), _) => {}
        (Ty::Set(p), Ty::Set(a)) | (Ty::Seq(p), Ty::Seq(a)) => unify(p, a, subst),
        (Ty::Set(p), Ty::Seq(a)) => unify(p, &Ty::Product(vec![Ty::Nat, (**a).clone()]), subst),
        (Ty::Product(ps), Ty::Product(xs)) if ps.len() == xs.len() => {
            for (p, x) in ps.iter().zip(xs) {
                unify(p, x, subst);
            }
        }
        (Ty::Function(p1, p2), Ty::Function(a1, a2))
        | (Ty::Relation(p1, p2), Ty::Relation(a1, a2))
        | (Ty::Relation(p1, p2), Ty::Function(a1, a2)) => {
            unify(p1, a1, subst);
            unify(p2, a2, subst);
        }
        (Ty::Relation(p1, p2), Ty::Set(s)) => {
            if let Ty::Product(v) = &**s {
                if v.len() == 2 {
                    unify(p1, &v[0], subst);
                    unify(p2, &v[1], subst);
                }
            }
        }
        (Ty::Relation(p1, p2), Ty::Seq(e)) | (Ty::Function(p1, p2), Ty::Seq(e)) => {
            unify(p1, &Ty::Nat, subst);
            unify(p2, e, subst);
        }
        _ => {}
    }
}

fn substitute(t: &Ty, subst: &HashMap<String, Ty>) -> Ty {
    match t {
        Ty::Var(n) => subst.get(n).cloned().unwrap_or(Ty::Any),
        Ty::Set(a) => Ty::Set(Box::new(substitute(a, subst))),
        Ty::Seq(a) => Ty::Seq(Box::new(substitute(a, subst))),
        Ty::Product(v) => Ty::Product(v.iter().map(|t| substitute(t, subst)).collect()),
        Ty::Function(a, b) => Ty::Function(Box::new(substitute(a, subst)), Box::new(substitute(b, subst))),
        Ty::Relation(a, b) => Ty::Relation(Box::new(substitute(a, subst)), Box::new(substitute(b, subst))),
        Ty::Vector(a, n) => Ty::Vector(Box::new(substitute(a, subst)), *n),
        Ty::Matrix(a, r, c) => Ty::Matrix(Box::new(substitute(a, subst)), *r, *c),
        other => other.clone(),
    }
}

/// The type problems of a file.
#[salsa::tracked(returns(ref))]
pub fn type_checks(db: &dyn Db, ws: Workspace, file: File) -> Vec<ResolveProblem> {
    if file.kind(db).is_assertions() {
        return Vec::new();
    }
    let (decl, body) = (&file_resolution(db, ws, file).refs, &body_resolution(db, ws, file).refs);
    type_unit(db, ws, &Unit::of_file(db, file), decl, body)
}

/// [`type_checks`] of a unit (a file or one element), with its resolved
/// names.
pub(crate) fn type_unit(
    db: &dyn Db,
    ws: Workspace,
    unit: &Unit<'_>,
    decl: &[crate::resolve::ResolvedRef],
    body: &[crate::resolve::ResolvedRef],
) -> Vec<ResolveProblem> {
    let file = unit.file;
    if file.kind(db).is_assertions() {
        return Vec::new();
    }
    let mut targets: FxHashMap<TextRange, Target> =
        FxHashMap::with_capacity_and_hasher(decl.len() + body.len(), Default::default());
    for r in decl.iter().chain(body) {
        if let Some(t) = r.target {
            targets.insert(r.range, t);
        }
    }
    let mut t = Typer {
        db,
        ws,
        file,
        unit,
        defs: unit.defs,
        rs: file.kind(db) == FileKind::RoboSim,
        targets,
        type_cache: Default::default(),
        named_cache: Default::default(),
        env: Vec::new(),
        out: Vec::new(),
        result: None,
        recorded: None,
    };
    t.walk(&unit.root);
    t.out
}

/// The type of every expression of `file` that the type checker types,
/// by the expression's range (for the lowered model, [`crate::model`]).
#[salsa::tracked(returns(ref))]
pub fn expr_types(db: &dyn Db, ws: Workspace, file: File) -> FxHashMap<TextRange, Ty> {
    if file.kind(db).is_assertions() {
        return FxHashMap::default();
    }
    let (decl, body) = (&file_resolution(db, ws, file).refs, &body_resolution(db, ws, file).refs);
    unit_types(db, ws, &Unit::of_file(db, file), decl, body)
}

/// [`expr_types`] of a unit (a file or one element), with its resolved
/// names.
pub(crate) fn unit_types(
    db: &dyn Db,
    ws: Workspace,
    unit: &Unit<'_>,
    decl: &[crate::resolve::ResolvedRef],
    body: &[crate::resolve::ResolvedRef],
) -> FxHashMap<TextRange, Ty> {
    let file = unit.file;
    if file.kind(db).is_assertions() {
        return FxHashMap::default();
    }
    let targets = decl.iter().chain(body).filter_map(|r| Some((r.range, r.target?))).collect();
    let mut t = Typer {
        db,
        ws,
        file,
        unit,
        defs: unit.defs,
        rs: file.kind(db) == FileKind::RoboSim,
        targets,
        type_cache: Default::default(),
        named_cache: Default::default(),
        env: Vec::new(),
        out: Vec::new(),
        result: None,
        recorded: Some(FxHashMap::default()),
    };
    t.walk(&unit.root);
    t.recorded.unwrap_or_default()
}

struct Typer<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    /// The file or element typed.
    unit: &'a Unit<'a>,
    defs: &'a FileDefs,
    rs: bool,
    /// Every resolved name of the file by range (tens of thousands in a
    /// large file: a fast hash matters).
    targets: FxHashMap<TextRange, Target>,
    type_cache: std::cell::RefCell<FxHashMap<Target, Ty>>,
    /// Type names lowered so far, per file they are written in: the same
    /// few names (`nat`, `real`) are written on every declaration, and
    /// resolving one goes through the workspace's scopes.
    named_cache: std::cell::RefCell<FxHashMap<File, FxHashMap<Vec<String>, Ty>>>,
    env: Vec<(String, Ty)>,
    out: Vec<ResolveProblem>,
    /// The result type inside a function's postcondition.
    result: Option<Ty>,
    /// The types of the expressions typed so far, when asked for
    /// ([`expr_types`]).
    recorded: Option<FxHashMap<TextRange, Ty>>,
}

fn op_text(k: SyntaxKind) -> &'static str {
    k.text().unwrap_or("?")
}

/// The kinds of node [`Typer::walk`] checks.
const TYPED_POSITIONS: &[SyntaxKind] = &[
    CONDITION,
    PRECONDITION,
    POSTCONDITION,
    VARIABLE,
    ASSIGN_STMT,
    IF_STMT,
    WAIT_STMT,
    CALL_STMT,
    SIM_CALL_STMT,
    COMMUNICATION,
    OUTPUT_COMM_STMT,
    PROBABILITY,
    ENTRY_ACTION,
    DURING_ACTION,
    EXIT_ACTION,
    TRANSITION_ACTION,
];

/// The first operand of `n`: `operand_exprs(n).first()` without
/// collecting the others (typing asks for operands of every expression).
fn first_operand(n: &SyntaxNode) -> Option<SyntaxNode> {
    n.children().find(|c| ast::is_expr_kind(c.kind()))
}

/// The operands of `n`, as `operand_exprs` lists them, without a vector.
fn operands(n: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> {
    n.children().filter(|c| ast::is_expr_kind(c.kind()))
}

fn unparen(n: &SyntaxNode) -> SyntaxNode {
    let mut n = n.clone();
    while n.kind() == PAREN_EXPR {
        match first_operand(&n) {
            Some(inner) => n = inner,
            None => break,
        }
    }
    n
}

fn is_timed(n: &SyntaxNode) -> bool {
    matches!(n.kind(), SINCE_EXPR | SINCE_ENTRY_EXPR)
}

impl Typer<'_> {
    /// [`lower`], with the type names memoised.
    fn lower(&self, file: File, t: &TypeRef) -> Ty {
        lower_by(t, &|path| {
            if let Some(ty) = self.named_cache.borrow().get(&file).and_then(|m| m.get(path)) {
                return ty.clone();
            }
            let ty = named_type(self.db, self.ws, file, path);
            self.named_cache.borrow_mut().entry(file).or_default().insert(path.to_vec(), ty.clone());
            ty
        })
    }

    /// The type declared at `loc` (one type for identical copies).
    fn named(&self, loc: ItemLoc, kind: DefKind) -> Ty {
        Ty::Named(canonical_type(self.db, self.ws, loc), loc.summary(self.db).name.clone(), kind)
    }

    fn problem(&mut self, code: &'static str, range: TextRange, message: String) {
        self.out.push(ResolveProblem { code, range, message });
    }

    /// Walks the tree; typed positions are checked where they occur.
    fn walk(&mut self, root: &SyntaxNode) {
        let table = self.unit.nodes;
        // No typed position lies inside an expression or a type, and `expr`
        // walks the expressions it types itself.
        let positions = table.nodes(root, TYPED_POSITIONS, true);
        // Timed expressions, in order, for the actions that contain them.
        let timed = table.nodes(root, &[SINCE_EXPR, SINCE_ENTRY_EXPR], false);
        for n in positions {
            match n.kind() {
                CONDITION => {
                    if let Some(e) = &first_operand(&n) {
                        let t = self.expr(e);
                        self.expect_bool(
                            &t,
                            e,
                            if self.rs { "RS-TRANS-01" } else { "RC-TRANS-01" },
                            "a transition condition",
                        );
                    }
                }
                PRECONDITION | POSTCONDITION => {
                    self.result = self.function_result(&n);
                    if let Some(e) = &first_operand(&n) {
                        let t = self.expr(e);
                        self.expect_bool(&t, e, "RC-EXP-13", "a pre- or postcondition");
                    }
                    self.result = None;
                }
                VARIABLE => self.initialiser(&n),
                ASSIGN_STMT => self.assignment(&n),
                IF_STMT => {
                    if let Some(e) = &first_operand(&n) {
                        let t = self.expr(e);
                        self.expect_bool(&t, e, "RC-STMT-03", "the condition of `if`");
                    }
                }
                WAIT_STMT => {
                    if let Some(e) = &first_operand(&n) {
                        let t = self.expr(e);
                        let ok = compatible(&t, &Ty::Int) || compatible(&t, &Ty::Set(Box::new(Ty::Int)));
                        if !ok {
                            self.problem(
                                "RC-STMT-04",
                                e.text_range(),
                                format!("`wait` needs an integer or a set of integers; this has type {t}"),
                            );
                        }
                    }
                }
                CALL_STMT | SIM_CALL_STMT => self.call_stmt(&n),
                COMMUNICATION => self.communication(&n),
                OUTPUT_COMM_STMT => self.output_comm(&n),
                PROBABILITY => self.probability(&n),
                ENTRY_ACTION | DURING_ACTION | EXIT_ACTION | TRANSITION_ACTION => {
                    // The timed descendants of the action, in preorder.
                    let range = n.text_range();
                    let first = timed.partition_point(|t| t.text_range().start() < range.start());
                    let inside = timed[first..]
                        .iter()
                        .take_while(|t| t.text_range().start() <= range.end())
                        .filter(|t| t.ancestors().any(|a| a == n));
                    for t in inside {
                        self.problem(
                            "RC:TE1",
                            t.text_range(),
                            "`since` and `sinceEntry` are not allowed in actions: use them in transition conditions"
                                .into(),
                        );
                    }
                }
                _ => {}
            }
        }
    }

    fn function_result(&self, n: &SyntaxNode) -> Option<Ty> {
        let inner = self.defs.innermost(n.text_range())?;
        let d = self.defs.def(inner);
        match (&d.kind, &d.data) {
            (DefKind::Function, DefData::Signature { result: Some(r), .. }) => Some(self.lower(self.file, r)),
            _ => None,
        }
    }

    fn expect_bool(&mut self, t: &Ty, e: &SyntaxNode, code: &'static str, what: &str) {
        if !compatible(t, &Ty::Bool) {
            self.problem(code, e.text_range(), format!("{what} must be boolean; this expression has type {t}"));
        }
    }

    /// The declared type of a resolved name, lowered once per name: a file
    /// names the same few variables many times, and lowering resolves the
    /// type's name each time.
    fn target_type(&self, t: Target) -> Ty {
        if let Some(ty) = self.type_cache.borrow().get(&t) {
            return ty.clone();
        }
        let ty = self.lower_target_type(t);
        self.type_cache.borrow_mut().insert(t, ty.clone());
        ty
    }

    fn lower_target_type(&self, t: Target) -> Ty {
        match t {
            Target::Def(f, id) => {
                let d = self.unit.defs_of(self.db, f, id).def(id);
                match (&d.kind, &d.data) {
                    (
                        DefKind::Variable | DefKind::Constant | DefKind::Parameter | DefKind::Field | DefKind::Event,
                        DefData::Typed { ty, .. },
                    ) => ty.as_ref().map(|t| self.lower(f, t)).unwrap_or(Ty::Error),
                    _ => Ty::Error,
                }
            }
            Target::Member(loc, i) => {
                let s = loc.summary(self.db);
                let m = &s.members[i as usize];
                match m.kind {
                    DefKind::EnumLiteral => self.named(loc, DefKind::Enumeration),
                    _ => m.ty.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error),
                }
            }
            Target::Item(loc) => {
                let s = loc.summary(self.db);
                if s.kind == DefKind::Function {
                    let params = self.function_params_of(loc);
                    let result = self.function_result_of(loc);
                    if params.is_empty() {
                        return result;
                    }
                    return Ty::Function(Box::new(Ty::Product(params)), Box::new(result));
                }
                Ty::Error
            }
        }
    }

    /// The parameter types of the function `loc`.
    fn function_params_of(&self, loc: ItemLoc) -> Vec<Ty> {
        let s = loc.summary(self.db);
        s.params.iter().map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error)).collect()
    }

    fn function_result_of(&self, loc: ItemLoc) -> Ty {
        let Some(def) = loc.def(self.db) else { return Ty::Error };
        match &file_defs(self.db, loc.file).def(def).data {
            DefData::Signature { result: Some(r), .. } => self.lower(loc.file, r),
            _ => Ty::Error,
        }
    }

    /// The type of the name reference `r`.
    fn name_type(&self, r: &SyntaxNode) -> Ty {
        // Bound names are rare: read the name only when some are in scope.
        if !self.env.is_empty() {
            let name = crate::defs::name_text(r);
            if let Some((_, t)) = self.env.iter().rev().find(|(x, _)| *x == name) {
                return t.clone();
            }
        }
        match self.targets.get(&r.text_range()) {
            Some(t) => self.target_type(*t),
            None => Ty::Error,
        }
    }

    fn bind(&mut self, n: &SyntaxNode) -> usize {
        let before = self.env.len();
        for bs in n.children().filter(|c| c.kind() == BINDERS) {
            for b in bs.children().filter(|c| c.kind() == BINDER) {
                let name = b.children().find(|c| c.kind() == NAME).map(|x| crate::defs::name_text(&x));
                let ty = b
                    .children()
                    .find(|c| ast::is_type_kind(c.kind()))
                    .map(|t| self.lower(self.file, &lower_type(&t)))
                    .unwrap_or(Ty::Error);
                if let Some(name) = name {
                    self.env.push((name, ty));
                }
            }
        }
        before
    }

    fn binder_types(&self, n: &SyntaxNode, from: usize) -> Vec<Ty> {
        let _ = n;
        self.env[from..].iter().map(|(_, t)| t.clone()).collect()
    }

    fn such_that(&mut self, n: &SyntaxNode) {
        if let Some(st) =
            n.children().filter(|c| c.kind() == BINDERS).flat_map(|b| b.children()).find(|c| c.kind() == SUCH_THAT)
        {
            if let Some(e) = operand_exprs(&st).first() {
                let t = self.expr(e);
                self.expect_bool(&t, e, "RC-EXP-14", "the predicate of a binder");
            }
        }
    }

    /// The type of an expression; reports the innermost ill-typed part.
    fn expr(&mut self, n: &SyntaxNode) -> Ty {
        let t = self.expr_type(n);
        if let Some(r) = &mut self.recorded {
            r.insert(n.text_range(), t.clone());
        }
        t
    }
}

/// `1 argument`, `2 arguments`, … for arity messages.
fn arguments(n: usize) -> String {
    format!("{n} argument{}", if n == 1 { "" } else { "s" })
}
