//! Expressions, statements and communications of the model, and their
//! lowering from syntax.

use robosim_syntax::ast::{self, name_text, qualified_path};
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use super::lower::Cx;
use crate::index::ItemLoc;
use crate::resolve::Target;
use crate::types::Ty;

/// An expression with its range.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Its type, as the type checker found it (none where it types no
    /// expression, as in a malformed one).
    pub ty: Option<Ty>,
    /// Its range.
    pub range: TextRange,
}

/// Unary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UnOp {
    /// `not`.
    Not,
    /// `-`.
    Neg,
    /// Another prefix operator (`#`, …).
    Other,
}

/// Binary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum BinOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    In,
    And,
    Or,
    Implies,
    Iff,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Cat,
    /// Another operator (`^`, …), or none found.
    Other,
}

impl BinOp {
    fn of(k: Option<SyntaxKind>) -> BinOp {
        match k {
            Some(EQ2) => BinOp::Eq,
            Some(NEQ) => BinOp::Ne,
            Some(LT) => BinOp::Lt,
            Some(LTEQ) => BinOp::Le,
            Some(GT) => BinOp::Gt,
            Some(GTEQ) => BinOp::Ge,
            Some(IN_KW) => BinOp::In,
            Some(AND) => BinOp::And,
            Some(OR) => BinOp::Or,
            Some(IMPLIES) => BinOp::Implies,
            Some(IFF_KW) => BinOp::Iff,
            Some(PLUS) => BinOp::Add,
            Some(MINUS) => BinOp::Sub,
            Some(STAR) => BinOp::Mul,
            Some(SLASH) => BinOp::Div,
            Some(PERCENT) => BinOp::Mod,
            Some(CAT_KW) => BinOp::Cat,
            _ => BinOp::Other,
        }
    }

    /// Whether the operator compares (`==`, `!=`, `<`, `<=`, `>`, `>=`).
    pub fn is_comparison(self) -> bool {
        matches!(self, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
    }
}

/// The kinds of expression.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ExprKind {
    /// An integer literal (none: too large for 64 bits).
    Int(Option<i64>),
    /// A real literal, as written.
    Real(String),
    /// `true`, `false`.
    Bool(bool),
    /// A name (variable, constant, parameter, bound name, function, …)
    /// and the declaration it resolves to.
    Name {
        /// The name.
        name: String,
        /// Its declaration.
        res: Option<Target>,
    },
    /// `E::l`: the enumeration as written, the literal, and the
    /// enumeration and the literal's index when they resolve.
    EnumLiteral {
        /// The enumeration's path.
        path: Vec<String>,
        /// The literal.
        literal: String,
        /// The enumeration.
        enumeration: Option<ItemLoc>,
    },
    /// RoboSim `$x`, `$e?x` and `$e.v`.
    SimRef {
        /// The input, output or variable.
        path: Vec<String>,
        /// `?x`: the variable bound and the suffix's range.
        input: Option<(Vec<String>, TextRange)>,
        /// `.v`.
        sync: Option<Box<Expr>>,
    },
    /// `since(C)`.
    Since(String),
    /// `sinceEntry(S)`.
    SinceEntry(Vec<String>),
    /// A prefix operator.
    Unary(UnOp, Box<Expr>),
    /// A binary operator.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// `if c then a else b end`.
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    /// `r.f`.
    Field(Box<Expr>, String),
    /// `x[i, …]`.
    Index(Box<Expr>, Vec<Expr>),
    /// `f(args)`: the function's name, what it resolves to, the arguments.
    Call {
        /// The function's name.
        function: String,
        /// Its declaration.
        res: Option<Target>,
        /// The arguments.
        args: Vec<Expr>,
    },
    /// `(a, b, …)`.
    Tuple(Vec<Expr>),
    /// `{a, b, …}`.
    Set(Vec<Expr>),
    /// `<a, b, …>`.
    Seq(Vec<Expr>),
    /// `(| f = v, … |)`.
    Record(Vec<(String, Expr)>),
    /// `{a to b}`.
    SetRange(Box<Expr>, Box<Expr>),
    /// `result` (in a function's postcondition).
    Result,
    /// `[lo, hi]` and its open ends.
    Interval {
        /// Lower bound.
        lo: Box<Expr>,
        /// Upper bound.
        hi: Box<Expr>,
        /// `(lo`.
        open_lo: bool,
        /// `hi)`.
        open_hi: bool,
    },
    /// A part left out (incomplete source).
    Missing,
    /// An expression the model does not describe further: its kind in
    /// words ("set comp expr", …).
    Other(String),
}

/// A selector of an assignment's target.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Selector {
    /// `.f`.
    Field(String, TextRange),
    /// `[i, …]`.
    Index(Vec<Expr>, TextRange),
}

/// The value part of a communication.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum CommPart {
    /// `e.v` (the value, none when missing).
    Sync(Option<Expr>),
    /// `e!v`.
    Output(Option<Expr>),
    /// `e?x`: the variable and the part's range.
    Input(Vec<String>, TextRange),
}

/// A communication `e`, `e?x`, `e!v`, `e.v`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Comm {
    /// The event.
    pub event: String,
    /// What the event name resolves to.
    pub res: Option<Target>,
    /// The event name's range.
    pub event_range: TextRange,
    /// `[| g |]`: its range.
    pub guard: Option<TextRange>,
    /// The value part.
    pub part: Option<CommPart>,
    /// The whole communication's range.
    pub range: TextRange,
}

/// A statement with its range.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Stmt {
    /// What it is.
    pub kind: StmtKind,
    /// Its range.
    pub range: TextRange,
    /// Its range up to its arguments or value (`$move` of `$move(lv, 0)`),
    /// where a hover shows its term.
    pub head: TextRange,
}

/// The kinds of statement.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum StmtKind {
    /// `skip`.
    Skip,
    /// `a ; b ; …`.
    Seq(Vec<Stmt>),
    /// `x(.f|[i])* = v`.
    Assign {
        /// The variable.
        target: Vec<String>,
        /// What the variable resolves to.
        res: Option<Target>,
        /// Field and index selectors.
        selectors: Vec<Selector>,
        /// The value.
        value: Expr,
    },
    /// `#C`.
    ClockReset(String),
    /// `if c then a else b end`.
    If(Expr, Box<Stmt>, Option<Box<Stmt>>),
    /// A communication.
    Comm(Comm),
    /// `op(args)`.
    Call {
        /// The operation.
        name: Vec<String>,
        /// The arguments.
        args: Vec<Expr>,
    },
    /// RoboSim `$op(args)`.
    SimCall {
        /// The operation.
        name: Vec<String>,
        /// The arguments.
        args: Vec<Expr>,
    },
    /// RoboSim `$e`, `$e!v`: the output and its value.
    Output(Vec<String>, Option<Expr>),
    /// `wait(d)`, `wait([a, b])`.
    Wait(Expr),
    /// RoboSim `exec`.
    Exec,
    /// `s <{d}`: the body and the deadline.
    Timed(Option<Box<Stmt>>, Option<Expr>),
    /// `(s)` (a parenthesised or parallel statement: its parts).
    Par(Vec<Stmt>),
    /// A statement the model does not describe further: its kind in words.
    Other(String),
}

/// A syntax kind in words, for messages.
pub(super) fn kind_words(k: SyntaxKind) -> String {
    format!("{k:?}").to_lowercase().replace('_', " ")
}

fn exprs_of(n: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> {
    n.children().filter(|c| ast::is_expr_kind(c.kind()))
}

fn stmts_of(n: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> {
    n.children().filter(|c| ast::is_stmt_kind(c.kind()))
}

fn name_ref_text(n: &SyntaxNode) -> String {
    n.children().find(|c| c.kind() == NAME_REF).map(|c| name_text(&c)).unwrap_or_default()
}

impl Cx<'_> {
    fn boxed(&mut self, e: Option<SyntaxNode>, at: TextRange) -> Box<Expr> {
        Box::new(self.opt_expr(e, at))
    }

    /// The expression `e`, or a [`ExprKind::Missing`] at `at`.
    pub(super) fn opt_expr(&mut self, e: Option<SyntaxNode>, at: TextRange) -> Expr {
        match e {
            Some(e) => self.expr(&e),
            None => Expr { kind: ExprKind::Missing, ty: None, range: at },
        }
    }

    /// Lowers an expression (parentheses are dropped: the tree keeps the
    /// grouping).
    pub(super) fn expr(&mut self, e: &SyntaxNode) -> Expr {
        let range = e.text_range();
        let kind = match e.kind() {
            PAREN_EXPR => match exprs_of(e).next() {
                Some(inner) => return self.expr(&inner),
                None => ExprKind::Missing,
            },
            LITERAL => match e.first_token().map(|t| (t.kind(), t.text().to_string())) {
                Some((INT_NUMBER, t)) => ExprKind::Int(t.parse().ok()),
                Some((TRUE_KW, _)) => ExprKind::Bool(true),
                Some((FALSE_KW, _)) => ExprKind::Bool(false),
                Some((FLOAT_NUMBER, t)) => ExprKind::Real(t),
                _ => ExprKind::Other("literal".into()),
            },
            REF_EXPR => {
                let name = name_text(e);
                ExprKind::Name { res: self.target_at(e), name }
            }
            ENUM_LITERAL_EXPR => {
                let mut parts: Vec<String> =
                    e.children().filter(|c| c.kind() == NAME_REF).map(|c| name_text(&c)).collect();
                match parts.pop() {
                    Some(literal) => {
                        let enumeration = super::lower::resolve(
                            self.db,
                            self.ws,
                            self.file,
                            &parts,
                            crate::defs::DefKind::Enumeration,
                        );
                        ExprKind::EnumLiteral { path: parts, literal, enumeration }
                    }
                    None => ExprKind::Missing,
                }
            }
            SIM_REF_EXPR => {
                let input =
                    e.children().find(|c| c.kind() == SIM_INPUT_SUFFIX).map(|s| (qualified_path(&s), s.text_range()));
                let sync = e
                    .children()
                    .find(|c| c.kind() == SIM_SYNC_SUFFIX)
                    .map(|s| self.boxed(exprs_of(&s).next(), s.text_range()));
                ExprKind::SimRef { path: qualified_path(e), input, sync }
            }
            SINCE_EXPR => ExprKind::Since(name_ref_text(e)),
            SINCE_ENTRY_EXPR => ExprKind::SinceEntry(qualified_path(e)),
            PREFIX_EXPR => {
                let op = match e.first_token().map(|t| t.kind()) {
                    Some(NOT_KW) => UnOp::Not,
                    Some(MINUS) => UnOp::Neg,
                    _ => UnOp::Other,
                };
                ExprKind::Unary(op, self.boxed(exprs_of(e).next(), range))
            }
            BIN_EXPR => {
                let ops: Vec<SyntaxNode> = exprs_of(e).collect();
                match ops.as_slice() {
                    [a, b] => {
                        let op = BinOp::of(ast::binary_operator(e));
                        ExprKind::Binary(op, Box::new(self.expr(a)), Box::new(self.expr(b)))
                    }
                    _ => ExprKind::Missing,
                }
            }
            IF_EXPR => {
                let mut parts = exprs_of(e);
                let (c, a, b) = (parts.next(), parts.next(), parts.next());
                if b.is_none() {
                    ExprKind::Missing
                } else {
                    ExprKind::If(self.boxed(c, range), self.boxed(a, range), self.boxed(b, range))
                }
            }
            SELECT_EXPR => {
                let base = exprs_of(e).next();
                let field = e.children().filter(|c| c.kind() == NAME_REF).last().map(|n| name_text(&n));
                match (base, field) {
                    (Some(b), Some(f)) => ExprKind::Field(Box::new(self.expr(&b)), f),
                    _ => ExprKind::Missing,
                }
            }
            INDEX_EXPR => {
                let mut parts = exprs_of(e);
                match parts.next() {
                    Some(base) => {
                        let base = Box::new(self.expr(&base));
                        let ix = parts.map(|x| self.expr(&x)).collect();
                        ExprKind::Index(base, ix)
                    }
                    None => ExprKind::Missing,
                }
            }
            CALL_EXPR => {
                let f = e.children().find(|c| c.kind() == REF_EXPR);
                let function = f.as_ref().map(name_text).unwrap_or_default();
                let res = f.as_ref().and_then(|f| self.target_at(f));
                let args = self.args(e);
                ExprKind::Call { function, res, args }
            }
            TUPLE_EXPR => ExprKind::Tuple(exprs_of(e).map(|x| self.expr(&x)).collect()),
            SET_EXPR => ExprKind::Set(exprs_of(e).map(|x| self.expr(&x)).collect()),
            SEQ_EXPR => ExprKind::Seq(exprs_of(e).map(|x| self.expr(&x)).collect()),
            RECORD_LITERAL => ExprKind::Record(
                e.children()
                    .filter(|f| f.kind() == FIELD_VALUE)
                    .map(|f| (name_ref_text(&f), self.opt_expr(exprs_of(&f).next(), f.text_range())))
                    .collect(),
            ),
            SET_RANGE_EXPR => {
                let mut parts = exprs_of(e);
                let (lo, hi) = (parts.next(), parts.next());
                ExprKind::SetRange(self.boxed(lo, range), self.boxed(hi, range))
            }
            RESULT_EXPR => ExprKind::Result,
            INTERVAL_EXPR => {
                let mut parts = exprs_of(e);
                let (lo, hi) = (parts.next(), parts.next());
                if hi.is_none() {
                    ExprKind::Missing
                } else {
                    ExprKind::Interval {
                        lo: self.boxed(lo, range),
                        hi: self.boxed(hi, range),
                        open_lo: e.first_token().is_some_and(|t| t.kind() == L_PAREN),
                        open_hi: e.last_token().is_some_and(|t| t.kind() == R_PAREN),
                    }
                }
            }
            k => ExprKind::Other(kind_words(k)),
        };
        Expr { kind, ty: self.types.get(&range).cloned(), range }
    }

    /// The arguments of a call (`ARG_LIST` child of `n`).
    fn args(&mut self, n: &SyntaxNode) -> Vec<Expr> {
        match n.children().find(|c| c.kind() == ARG_LIST) {
            Some(a) => exprs_of(&a).map(|x| self.expr(&x)).collect(),
            None => Vec::new(),
        }
    }

    /// The communication `comm`.
    pub(super) fn comm(&mut self, comm: &SyntaxNode) -> Comm {
        let event_node = comm.children().find(|n| n.kind() == NAME_REF);
        let event = event_node.as_ref().map(name_text).unwrap_or_default();
        let res = event_node.as_ref().and_then(|n| self.target_at(n));
        let guard = comm.children().find(|c| c.kind() == COMM_GUARD).map(|g| g.text_range());
        let part = comm.children().find_map(|p| match p.kind() {
            COMM_SYNC => Some(CommPart::Sync(exprs_of(&p).next().map(|e| self.expr(&e)))),
            COMM_OUTPUT => Some(CommPart::Output(exprs_of(&p).next().map(|e| self.expr(&e)))),
            COMM_INPUT => Some(CommPart::Input(qualified_path(&p), p.text_range())),
            _ => None,
        });
        let event_range = event_node.as_ref().map_or(comm.text_range(), |n| n.text_range());
        Comm { event, res, event_range, guard, part, range: comm.text_range() }
    }

    /// The statement of an action clause (its first statement child).
    pub(super) fn action(&mut self, a: &SyntaxNode) -> super::Action {
        super::Action { stmt: stmts_of(a).next().map(|s| self.stmt(&s)), range: a.text_range() }
    }

    /// Lowers a statement.
    pub(super) fn stmt(&mut self, s: &SyntaxNode) -> Stmt {
        let range = s.text_range();
        let kind = match s.kind() {
            SEQ_STMT => StmtKind::Seq(stmts_of(s).map(|c| self.stmt(&c)).collect()),
            SKIP_STMT => StmtKind::Skip,
            ASSIGN_STMT => {
                let a = s.children().find(|c| c.kind() == ASSIGNABLE);
                let target = a.as_ref().map(qualified_path).unwrap_or_default();
                let res = a
                    .as_ref()
                    .and_then(|a| a.children().find(|c| c.kind() == QUALIFIED_NAME))
                    .and_then(|q| self.target_at(&q));
                let selectors = a
                    .iter()
                    .flat_map(|a| a.children())
                    .filter_map(|c| match c.kind() {
                        FIELD_ACCESS => Some(Selector::Field(name_ref_text(&c), c.text_range())),
                        INDEX_ACCESS => {
                            Some(Selector::Index(exprs_of(&c).map(|x| self.expr(&x)).collect(), c.text_range()))
                        }
                        _ => None,
                    })
                    .collect();
                let value = self.opt_expr(exprs_of(s).next(), range);
                StmtKind::Assign { target, res, selectors, value }
            }
            CLOCK_RESET_STMT => StmtKind::ClockReset(name_ref_text(s)),
            IF_STMT => {
                let cond = self.opt_expr(exprs_of(s).next(), range);
                let mut branches = stmts_of(s);
                let then =
                    branches.next().map(|t| self.stmt(&t)).unwrap_or(Stmt { kind: StmtKind::Skip, range, head: range });
                let els = branches.next().map(|e| Box::new(self.stmt(&e)));
                StmtKind::If(cond, Box::new(then), els)
            }
            COMM_STMT => match s.children().find(|c| c.kind() == COMMUNICATION) {
                Some(c) => StmtKind::Comm(self.comm(&c)),
                None => StmtKind::Other("incomplete communication".into()),
            },
            CALL_STMT => StmtKind::Call { name: qualified_path(s), args: self.args(s) },
            SIM_CALL_STMT => StmtKind::SimCall { name: qualified_path(s), args: self.args(s) },
            OUTPUT_COMM_STMT => StmtKind::Output(qualified_path(s), exprs_of(s).next().map(|e| self.expr(&e))),
            WAIT_STMT => StmtKind::Wait(self.opt_expr(exprs_of(s).next(), range)),
            EXEC_STMT => StmtKind::Exec,
            TIMED_STMT => {
                let body = stmts_of(s).next().map(|b| Box::new(self.stmt(&b)));
                let limit = s
                    .children()
                    .find(|c| c.kind() == DEADLINE)
                    .and_then(|d| exprs_of(&d).next())
                    .map(|e| self.expr(&e));
                StmtKind::Timed(body, limit)
            }
            PAR_STMT => StmtKind::Par(stmts_of(s).map(|c| self.stmt(&c)).collect()),
            k => StmtKind::Other(kind_words(k)),
        };
        let end = s
            .children()
            .find(|c| c.kind() == ARG_LIST || ast::is_expr_kind(c.kind()))
            .map_or(range.end(), |c| c.text_range().start());
        Stmt { kind, range, head: TextRange::new(range.start(), end.max(range.start())) }
    }
}

impl Expr {
    /// Calls `f` on this expression and every subexpression, parents first.
    pub fn walk<'a>(&'a self, f: &mut impl FnMut(&'a Expr)) {
        f(self);
        let mut go = |e: &'a Expr| e.walk(f);
        match &self.kind {
            ExprKind::SimRef { sync: Some(x), .. } | ExprKind::Unary(_, x) | ExprKind::Field(x, _) => go(x),
            ExprKind::Binary(_, a, b) | ExprKind::Interval { lo: a, hi: b, .. } | ExprKind::SetRange(a, b) => {
                go(a);
                go(b);
            }
            ExprKind::If(c, a, b) => {
                go(c);
                go(a);
                go(b);
            }
            ExprKind::Index(b, xs) => {
                go(b);
                xs.iter().for_each(go);
            }
            ExprKind::Call { args: xs, .. } | ExprKind::Tuple(xs) | ExprKind::Set(xs) | ExprKind::Seq(xs) => {
                xs.iter().for_each(go)
            }
            ExprKind::Record(fs) => fs.iter().for_each(|(_, x)| go(x)),
            _ => {}
        }
    }
}

impl Stmt {
    /// Calls `f` on this statement and every statement inside, parents first.
    pub fn walk<'a>(&'a self, f: &mut impl FnMut(&'a Stmt)) {
        f(self);
        match &self.kind {
            StmtKind::Seq(ss) | StmtKind::Par(ss) => ss.iter().for_each(|s| s.walk(f)),
            StmtKind::If(_, a, b) => {
                a.walk(f);
                if let Some(b) = b {
                    b.walk(f);
                }
            }
            StmtKind::Timed(Some(b), _) => b.walk(f),
            _ => {}
        }
    }
}
