//! Types and typing (catalogue §3): the types of declarations, the type of
//! every expression, compatibility `T ≼ U`, and the typing rules of
//! statements, communications, conditions and initialisers. An ill-typed
//! subexpression gets the error type, which is compatible with everything,
//! and is reported once, at the innermost cause (RC-EXP-14).

use std::collections::HashMap;

use rustc_hash::FxHashMap;
use std::fmt;

use robosim_syntax::ast::{binary_operator, operand_exprs};
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
    let targets = decl.iter().chain(body).filter_map(|r| Some((r.range, r.target?))).collect();
    let unit = Unit::of_file(db, file);
    let mut t = Typer {
        db,
        ws,
        file,
        unit: &unit,
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
                    let params: Vec<Ty> = s
                        .params
                        .iter()
                        .map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error))
                        .collect();
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

    fn expr_type(&mut self, n: &SyntaxNode) -> Ty {
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
            SET_EXPR => {
                let mut el = Ty::Any;
                for e in operand_exprs(n) {
                    let t = self.expr(&e);
                    el = join(&el, &t);
                }
                Ty::Set(Box::new(el))
            }
            SEQ_EXPR => {
                let mut el = Ty::Any;
                for e in operand_exprs(n) {
                    let t = self.expr(&e);
                    el = join(&el, &t);
                }
                Ty::Seq(Box::new(el))
            }
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

    fn binary(&mut self, n: &SyntaxNode) -> Ty {
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
    fn typed_args(&mut self, n: &SyntaxNode) -> Vec<(SyntaxNode, Ty)> {
        let Some(al) = n.children().find(|c| c.kind() == ARG_LIST) else { return Vec::new() };
        operands(&al)
            .map(|x| {
                let t = self.expr(&x);
                (x, t)
            })
            .collect()
    }

    fn call_expr(&mut self, n: &SyntaxNode) -> Ty {
        let Some(callee) = &first_operand(n) else { return Ty::Error };
        let args = self.typed_args(n);
        // A function: check arity and argument types with generics.
        if callee.kind() == REF_EXPR {
            if let Some(r) = callee.children().find(|c| c.kind() == NAME_REF) {
                if let Some(Target::Item(loc)) = self.targets.get(&r.text_range()).copied() {
                    let s = loc.summary(self.db);
                    if s.kind == DefKind::Function {
                        let name = s.name.clone();
                        let params: Vec<Ty> = s
                            .params
                            .iter()
                            .map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error))
                            .collect();
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

    /// The enumeration literal an expression names (`E::L` or a bare `L`).
    fn literal_of(&self, e: &SyntaxNode) -> Option<(ItemLoc, u32)> {
        let r = match e.kind() {
            ENUM_LITERAL_EXPR => e.children().filter(|c| c.kind() == NAME_REF).nth(1)?,
            REF_EXPR => e.children().find(|c| c.kind() == NAME_REF)?,
            _ => return None,
        };
        self.literal_named(&r)
    }

    /// The enumeration literal the name reference `r` denotes.
    fn literal_named(&self, r: &SyntaxNode) -> Option<(ItemLoc, u32)> {
        match self.targets.get(&r.text_range())? {
            Target::Member(loc, i) if loc.summary(self.db).members[*i as usize].kind == DefKind::EnumLiteral => {
                Some((*loc, *i))
            }
            _ => None,
        }
    }

    /// RC-EXP-05: a literal that takes arguments is not used bare.
    fn bare_literal(&mut self, e: &SyntaxNode) {
        let Some((loc, i)) = self.literal_of(e) else { return };
        self.bare_literal_at(e, loc, i);
    }

    /// [`Typer::bare_literal`] for a `REF_EXPR` `e` whose name is `r`.
    fn bare_literal_named(&mut self, e: &SyntaxNode, r: &SyntaxNode) {
        let Some((loc, i)) = self.literal_named(r) else { return };
        self.bare_literal_at(e, loc, i);
    }

    fn bare_literal_at(&mut self, e: &SyntaxNode, loc: ItemLoc, i: u32) {
        let is_callee = e.parent().is_some_and(|p| p.kind() == CALL_EXPR && first_operand(&p).as_ref() == Some(e));
        let lit = &loc.summary(self.db).members[i as usize];
        if !is_callee && !lit.params.is_empty() {
            let msg = format!("`{}` expects {}", lit.name, arguments(lit.params.len()));
            self.problem("RC-EXP-05", e.text_range(), msg);
        }
    }

    fn initialiser(&mut self, n: &SyntaxNode) {
        let Some(init) = first_operand(n) else { return };
        let Some(ty) = n.children().find(|c| ast::is_type_kind(c.kind())) else { return };
        let declared = self.lower(self.file, &lower_type(&ty));
        let t = self.expr(&init);
        if !compatible(&t, &declared) {
            let name = n.children().find(|c| c.kind() == NAME).map(|x| x.text().to_string()).unwrap_or_default();
            self.problem(
                "RC-VAR-01",
                init.text_range(),
                format!("`{}` has type {declared}, but its initial value has type {t}", name.trim()),
            );
        }
    }

    fn assignment(&mut self, n: &SyntaxNode) {
        let Some(target) = n.children().find(|c| c.kind() == ASSIGNABLE) else { return };
        let Some(value) = first_operand(n) else { return };
        let Some(q) = target.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let mut ty = match self.targets.get(&q.text_range()) {
            Some(t) => self.target_type(*t),
            None => {
                let name = crate::defs::name_text(&q);
                self.env.iter().rev().find(|(x, _)| *x == name).map(|(_, t)| t.clone()).unwrap_or(Ty::Error)
            }
        };
        // Follow `.f` and `[i]` selectors.
        for s in target.children() {
            ty = match (s.kind(), &ty) {
                (FIELD_ACCESS, Ty::Named(loc, rname, DefKind::Record)) => {
                    let fref = s.children().find(|c| c.kind() == NAME_REF);
                    let f = fref.as_ref().map(crate::defs::name_text).unwrap_or_default();
                    let field =
                        loc.summary(self.db).members.iter().find(|m| m.kind == DefKind::Field && m.name == f).cloned();
                    match field {
                        Some(m) => m.ty.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error),
                        None => {
                            if let Some(r) = fref {
                                self.problem("LNK-01", r.text_range(), format!("record `{rname}` has no field `{f}`"));
                            }
                            Ty::Error
                        }
                    }
                }
                (INDEX_ACCESS, Ty::Seq(a)) | (INDEX_ACCESS, Ty::Vector(a, _)) | (INDEX_ACCESS, Ty::Matrix(a, _, _)) => {
                    (**a).clone()
                }
                (INDEX_ACCESS, Ty::Function(_, b)) | (INDEX_ACCESS, Ty::Relation(_, b)) => (**b).clone(),
                (FIELD_ACCESS | INDEX_ACCESS, _) => Ty::Error,
                _ => ty,
            };
            for e in operands(&s) {
                self.expr(&e);
            }
        }
        let t = self.expr(&value);
        if !compatible(&t, &ty) {
            self.problem(
                "RC-STMT-02",
                target.text_range(),
                format!("`{}` has type {ty}, but the value has type {t}", target.text().to_string().trim()),
            );
        }
    }

    fn call_stmt(&mut self, n: &SyntaxNode) {
        let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let args = self.typed_args(n);
        let params: Vec<Ty> = match self.targets.get(&q.text_range()) {
            Some(Target::Def(f, id)) => match &self.unit.defs_of(self.db, *f, *id).def(*id).data {
                DefData::Signature { params, .. } => {
                    params.iter().map(|(_, t)| t.as_ref().map(|t| self.lower(*f, t)).unwrap_or(Ty::Error)).collect()
                }
                _ => return,
            },
            Some(Target::Member(loc, i)) => {
                let m = &loc.summary(self.db).members[*i as usize];
                m.params.iter().map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error)).collect()
            }
            _ => return,
        };
        // Only messages need the name: read it then.
        let name = || q.text().to_string().trim().to_string();
        if params.len() != args.len() {
            self.problem(
                "RC-STMT-05",
                n.text_range(),
                format!("operation `{}` takes {}, not {}", name(), arguments(params.len()), args.len()),
            );
            return;
        }
        for (i, (p, (x, a))) in params.iter().zip(&args).enumerate() {
            if compatible(a, p) {
                continue;
            }
            match narrowing(a, p) {
                // RoboTool accepts a wider numeric argument (it compares the
                // parameter's type with the argument's); the call still means
                // something, but the value may not fit.
                Some(risk) => self.problem(
                    "RC-STMT-05-narrow",
                    x.text_range(),
                    format!(
                        "argument {} of `{}` has type {a} where {p} is expected: {risk} would be wrong at run time",
                        i + 1,
                        name()
                    ),
                ),
                None => self.problem(
                    "RC-STMT-05",
                    x.text_range(),
                    format!("argument {} of `{}` has type {a}, expected {p}", i + 1, name()),
                ),
            }
        }
    }

    fn event_type(&self, r: &SyntaxNode) -> Option<Option<Ty>> {
        let t = self.targets.get(&r.text_range())?;
        Some(match t {
            Target::Def(f, id) => match &self.unit.defs_of(self.db, *f, *id).def(*id).data {
                DefData::Typed { ty, .. } => ty.as_ref().map(|t| self.lower(*f, t)),
                _ => None,
            },
            Target::Member(loc, i) => {
                loc.summary(self.db).members[*i as usize].ty.as_ref().map(|t| self.lower(loc.file, t))
            }
            Target::Item(_) => None,
        })
    }

    fn communication(&mut self, n: &SyntaxNode) {
        let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = crate::defs::name_text(&r);
        let Some(ety) = self.event_type(&r) else { return };
        let payload = n.children().find(|c| matches!(c.kind(), COMM_INPUT | COMM_OUTPUT | COMM_SYNC));
        match (payload, ety) {
            (None, Some(t)) => self.problem(
                "RC:Tg2",
                r.text_range(),
                format!("`{name}` carries a value of type {t}: receive it (`{name}?x`) or send one (`{name}!v`)"),
            ),
            (Some(p), None) => self.problem(
                "RC:Tg5",
                r.text_range(),
                format!("`{name}` carries no value, so `{}` is not possible", p.text().to_string().trim()),
            ),
            (Some(p), Some(et)) => match p.kind() {
                COMM_INPUT => {
                    if let Some(q) = p.children().find(|c| c.kind() == QUALIFIED_NAME) {
                        let vt = self.targets.get(&q.text_range()).map(|t| self.target_type(*t)).unwrap_or(Ty::Error);
                        if !compatible(&et, &vt) {
                            self.problem(
                                "RC-COMM-01",
                                q.text_range(),
                                format!(
                                    "`{}` has type {vt} and cannot hold values of `{name}`, of type {et}",
                                    q.text().to_string().trim()
                                ),
                            );
                        }
                    }
                }
                _ => {
                    if let Some(v) = &first_operand(&p) {
                        let vt = self.expr(v);
                        if !compatible(&vt, &et) {
                            let code = if p.kind() == COMM_OUTPUT { "RC-COMM-02" } else { "RC-COMM-03" };
                            self.problem(
                                code,
                                v.text_range(),
                                format!("`{name}` carries {et}, but the value has type {vt}"),
                            );
                        }
                    }
                }
            },
            (None, None) => {}
        }
    }

    fn output_comm(&mut self, n: &SyntaxNode) {
        let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let Some(ety) = self.event_type(&q) else { return };
        let name = q.text().to_string().trim().to_string();
        match (first_operand(n).as_ref(), ety) {
            (None, Some(t)) => self.problem(
                "RS-IO-06",
                q.text_range(),
                format!("`{name}` carries a value of type {t}: write `${name}!v`"),
            ),
            (Some(v), None) => {
                self.problem("RS-IO-06", v.text_range(), format!("`{name}` carries no value: write `${name}`"))
            }
            (Some(v), Some(et)) => {
                let vt = self.expr(v);
                if !compatible(&vt, &et) {
                    self.problem(
                        "RS-IO-06",
                        v.text_range(),
                        format!("`{name}` carries {et}, but the value has type {vt}"),
                    );
                }
            }
            (None, None) => {}
        }
    }

    fn probability(&mut self, n: &SyntaxNode) {
        let Some(e) = first_operand(n) else { return };
        let t = self.expr(&e);
        if !compatible(&t, &Ty::Real) {
            self.problem("RC:PT2", e.text_range(), format!("a probability is a number in [0, 1]; this has type {t}"));
            return;
        }
        // A literal, or a constant whose initialiser is a literal.
        let literal = match e.kind() {
            LITERAL => Some(e.text().to_string()),
            REF_EXPR => e
                .children()
                .find(|c| c.kind() == NAME_REF)
                .and_then(|r| self.targets.get(&r.text_range()).copied())
                .and_then(|t| crate::nav::declaration(self.db, t))
                .and_then(|d| match &file_defs(self.db, d.file).def(d.def).data {
                    DefData::Typed { init: Some(init), .. } => Some(d.file.text(self.db)[*init].to_string()),
                    _ => None,
                }),
            _ => None,
        };
        if let Some(text) = literal {
            if let Ok(v) = text.trim().parse::<f64>() {
                if !(0.0..=1.0).contains(&v) {
                    self.problem("RC:PT2", e.text_range(), "a probability must lie in [0, 1]".into());
                }
            }
        }
    }
}

/// `1 argument`, `2 arguments`, … for arity messages.
fn arguments(n: usize) -> String {
    format!("{n} argument{}", if n == 1 { "" } else { "s" })
}
