//! Lowering of the syntax tree into the abstract syntax the checker and the
//! evaluator work on: patterns become patterns, multi-clause definitions
//! are grouped, `Timed` sections mark their definitions. Malformed or
//! unsupported pieces become diagnostics here, at their ranges.

use std::rc::Rc;

use crate::kinds::SyntaxKind::{self, *};
use crate::{Code, Diagnostic, Parse, SyntaxNode, SyntaxToken, TextRange};

/// A name as written (module-qualified names keep their `::`).
pub(crate) type Name = Rc<str>;

#[derive(Debug)]
pub(crate) struct Expr {
    pub kind: ExprKind,
    pub range: TextRange,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
    Dot,
    Concat,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UnOp {
    Not,
    Neg,
    Len,
}

/// Binary process operators whose middle part is an event set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SetOp {
    GenPar,
    Exception,
    SyncExt,
    SyncInt,
}

/// Binary process operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ProcOp {
    Ext,
    Int,
    Interleave,
    Seq,
    Interrupt,
    Slide,
}

#[derive(Debug)]
pub(crate) enum RepOp {
    Ext,
    Int,
    Interleave,
    Seq,
    GenPar(Box<Expr>),
    SyncExt(Box<Expr>),
    /// `|| stmts @ [A] P`: the alphabet is evaluated with the statements' names.
    AlphaPar(Box<Expr>),
    Link(Vec<(Expr, Expr)>, Vec<Stmt>),
}

#[derive(Debug)]
pub(crate) enum Field {
    Input(Pat, Option<Expr>),
    NonDet(Pat, Option<Expr>),
    Output(Expr),
}

#[derive(Debug)]
pub(crate) enum Stmt {
    Gen(Pat, Expr),
    Pred(Expr),
}

#[derive(Debug)]
pub(crate) enum ExprKind {
    Int(i64),
    Bool(bool),
    Char(char),
    Str(Rc<str>),
    Var(Name),
    Tuple(Vec<Expr>),
    App(Box<Expr>, Vec<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    Un(UnOp, Box<Expr>),
    Set(Vec<Expr>),
    SetRange(Box<Expr>, Option<Box<Expr>>),
    /// `{e | stmts}` (and `{a..b | stmts}` as a range element).
    SetComp(Box<Expr>, Vec<Stmt>),
    Seq(Vec<Expr>),
    SeqRange(Box<Expr>, Option<Box<Expr>>),
    SeqComp(Box<Expr>, Vec<Stmt>),
    Closure(Vec<Expr>, Vec<Stmt>),
    Map(Vec<(Expr, Expr)>),
    Let(Rc<[Decl]>, Box<Expr>),
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    Lambda(Rc<[Pat]>, Rc<Expr>),
    Prefix(Box<Expr>, Vec<Field>, Box<Expr>),
    Guard(Box<Expr>, Box<Expr>),
    Proc(ProcOp, Box<Expr>, Box<Expr>),
    Hide(Box<Expr>, Box<Expr>),
    Project(Box<Expr>, Box<Expr>),
    SetProc(SetOp, Box<Expr>, Box<Expr>, Box<Expr>),
    AlphaPar(Box<Expr>, Box<Expr>, Box<Expr>, Box<Expr>),
    LinkPar(Box<Expr>, Vec<(Expr, Expr)>, Vec<Stmt>, Box<Expr>),
    Rename(Box<Expr>, Vec<(Expr, Expr)>, Vec<Stmt>),
    Replicated(RepOp, Vec<Stmt>, Box<Expr>),
    /// Something already reported (a syntax error, an unsupported form).
    Error,
}

#[derive(Debug)]
pub(crate) enum Pat {
    Wild,
    /// A name: a constructor or channel if one is in scope, else a binding.
    Name(Name, TextRange),
    Int(i64),
    Bool(bool),
    Char(char),
    Str(Rc<str>),
    Tuple(Vec<Pat>),
    Dot(Box<Pat>, Box<Pat>),
    Seq(Vec<Pat>),
    Concat(Box<Pat>, Box<Pat>),
    Set(Vec<Pat>),
    Double(Box<Pat>, Box<Pat>),
}

/// The `Timed(f)` section a definition is in.
#[derive(Debug)]
pub(crate) struct Timed {
    /// The event function; `None` means one tock per event.
    pub f: Option<Expr>,
    pub range: TextRange,
}

#[derive(Debug)]
pub(crate) struct Clause {
    pub params: Vec<Vec<Pat>>,
    pub body: Expr,
}

#[derive(Debug)]
pub(crate) enum DeclKind {
    /// `f(p)(q) = e` clauses, or `x = e` (one clause, no parameters).
    Fun(Name, Vec<Rc<Clause>>),
    PatBind(Pat, Rc<Expr>),
    Channel(Vec<(Name, TextRange)>, Option<Expr>),
    Datatype(Name, Vec<(Name, TextRange, Option<Expr>)>),
    Subtype(Name, Vec<(Name, TextRange, Option<Expr>)>),
    Nametype(Name, Expr),
    Assert,
    /// `f, g :: T`: the names annotated (the types are not read).
    Annotation(Vec<Name>),
    /// A module without parameters: its definitions (exported or not) are
    /// visible inside it and as `M::x` after it.
    Module(Name, Rc<[Decl]>),
}

#[derive(Debug)]
pub(crate) struct Decl {
    pub kind: DeclKind,
    pub range: TextRange,
    pub name_range: TextRange,
    pub timed: Option<Rc<Timed>>,
    /// From an included file: its ranges are in that file's text.
    pub foreign: bool,
}

/// A checked CSPm text: its tree, its declarations and every diagnostic
/// (syntax, names, unsupported constructs).
#[derive(Debug)]
pub struct Module {
    pub(crate) parse: Parse,
    pub(crate) decls: Rc<[Decl]>,
    pub(crate) diagnostics: Vec<Diagnostic>,
}

impl Module {
    /// Parses, lowers and resolves `text`; names it does not define are
    /// looked up in `names` (the model), then in the built-ins.
    pub fn check(text: &str, names: &dyn crate::NameLookup) -> Module {
        Module::check_with_includes(text, names, &|_| None)
    }

    /// As [`Module::check`], with `include "file"` read through `load`
    /// (given the name as written; `None` when it cannot be read). The
    /// included definitions are in scope; their own diagnostics are not
    /// reported here (check each file on its own for them), except one
    /// at the `include` when the file has errors or cannot be read.
    pub fn check_with_includes(
        text: &str,
        names: &dyn crate::NameLookup,
        load: &dyn Fn(&str) -> Option<String>,
    ) -> Module {
        let parse = crate::parse(text);
        let mut diagnostics = parse.errors().to_vec();
        let mut lower = Lower {
            diags: Vec::new(),
            timed: None,
            load,
            depth: 0,
            foreign: false,
            stack: crate::stack::StackGuard::new(crate::stack::STATIC_PASS_STACK),
        };
        let decls = lower.decls(&parse.syntax_node());
        diagnostics.append(&mut lower.diags);
        crate::resolve::resolve(&decls, names, &mut diagnostics);
        crate::typeck::check(&decls, &mut diagnostics);
        diagnostics.sort_by_key(|d| (d.range.start(), d.range.end()));
        diagnostics.dedup();
        Module { parse, decls: decls.into(), diagnostics }
    }

    /// Every diagnostic, in text order.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }

    /// Whether there is no error (warnings allowed).
    pub fn is_ok(&self) -> bool {
        self.diagnostics.iter().all(|d| d.severity != crate::Severity::Error)
    }

    /// The syntax tree.
    pub fn parse(&self) -> &Parse {
        &self.parse
    }

    /// The names of the top-level definitions (processes, values,
    /// functions, channels, types, constructors), in text order.
    pub fn defined_names(&self) -> Vec<String> {
        let mut out = Vec::new();
        for d in self.decls.iter() {
            match &d.kind {
                DeclKind::Fun(n, _) | DeclKind::Nametype(n, _) => out.push(n.to_string()),
                DeclKind::PatBind(p, _) => crate::resolve::pat_names(p, &mut |n, _| out.push(n.to_string())),
                DeclKind::Channel(ns, _) => out.extend(ns.iter().map(|(n, _)| n.to_string())),
                DeclKind::Datatype(n, cs) | DeclKind::Subtype(n, cs) => {
                    out.push(n.to_string());
                    out.extend(cs.iter().map(|(c, _, _)| c.to_string()));
                }
                DeclKind::Module(m, inner) => {
                    let sub = Module { parse: self.parse.clone(), decls: inner.clone(), diagnostics: Vec::new() };
                    out.extend(sub.defined_names().into_iter().map(|n| format!("{m}::{n}")));
                }
                DeclKind::Assert | DeclKind::Annotation(_) => {}
            }
        }
        out
    }
}

struct Lower<'l> {
    diags: Vec<Diagnostic>,
    timed: Option<Rc<Timed>>,
    load: &'l dyn Fn(&str) -> Option<String>,
    /// Nesting of includes (a cycle stops at a bound).
    depth: u32,
    /// Lowering an included file.
    foreign: bool,
    stack: crate::stack::StackGuard,
}

fn nodes(n: &SyntaxNode) -> Vec<SyntaxNode> {
    n.children().filter(|c| c.kind() != ERROR).collect()
}

fn tokens(n: &SyntaxNode) -> impl Iterator<Item = SyntaxToken> {
    n.children_with_tokens().filter_map(|e| e.into_token()).filter(|t| !t.kind().is_trivia())
}

fn has_token(n: &SyntaxNode, kind: SyntaxKind) -> bool {
    tokens(n).any(|t| t.kind() == kind)
}

fn first_token(n: &SyntaxNode) -> Option<SyntaxKind> {
    tokens(n).next().map(|t| t.kind())
}

impl Lower<'_> {
    fn err(&mut self, code: Code, range: TextRange, msg: impl Into<String>) {
        self.diags.push(Diagnostic::error(code, range, msg));
    }

    fn decls(&mut self, parent: &SyntaxNode) -> Vec<Decl> {
        let mut out: Vec<Decl> = Vec::new();
        for n in nodes(parent) {
            self.decl(&n, &mut out);
        }
        out
    }

    fn decl(&mut self, n: &SyntaxNode, out: &mut Vec<Decl>) {
        let range = n.text_range();
        let timed = self.timed.clone();
        let foreign = self.foreign;
        let push = |out: &mut Vec<Decl>, kind, name_range| {
            out.push(Decl { kind, range, name_range, timed: timed.clone(), foreign })
        };
        match n.kind() {
            DEFINITION => {
                let kids = nodes(n);
                let (Some(lhs), Some(rhs)) = (kids.first(), kids.get(1)) else { return };
                let body = self.expr(rhs);
                // `f(p)(q) = e`: peel the argument lists off a name.
                let mut params = Vec::new();
                let mut head = lhs.clone();
                while head.kind() == CALL_EXPR {
                    let k = nodes(&head);
                    let (Some(f), Some(args)) = (k.first(), k.get(1)) else { return };
                    params.push(nodes(args).iter().map(|a| self.pat(a)).collect());
                    head = f.clone();
                }
                params.reverse();
                if head.kind() == NAME_REF && (!params.is_empty() || lhs.kind() == NAME_REF) {
                    let name: Name = head.text().to_string().into();
                    let clause = Rc::new(Clause { params, body });
                    if let Some(Decl { kind: DeclKind::Fun(prev, clauses), range: r, .. }) = out.last_mut() {
                        if *prev == name && !clauses.is_empty() && !clauses[0].params.is_empty() {
                            clauses.push(clause);
                            *r = r.cover(range);
                            return;
                        }
                    }
                    push(out, DeclKind::Fun(name, vec![clause]), head.text_range());
                } else if !params.is_empty() {
                    self.err(
                        Code::BadPattern,
                        head.text_range(),
                        "a function definition needs a name before its arguments",
                    );
                } else {
                    let pat = self.pat(lhs);
                    push(out, DeclKind::PatBind(pat, Rc::new(body)), lhs.text_range());
                }
            }
            TYPE_ANNOTATION => {
                let names = nodes(n)
                    .first()
                    .map(|l| {
                        l.descendants_with_tokens()
                            .filter_map(|e| e.into_token())
                            .filter(|t| t.kind() == IDENT)
                            .map(|t| Name::from(t.text()))
                            .collect()
                    })
                    .unwrap_or_default();
                push(out, DeclKind::Annotation(names), range);
            }
            EXTERNAL_DECL | TRANSPARENT_DECL | PRINT_DECL => {}
            ASSERT_DECL => push(out, DeclKind::Assert, range),
            CHANNEL_DECL => {
                let names = self.name_list(n);
                let ty = nodes(n).iter().find(|c| c.kind() != NAME_LIST).map(|c| self.expr(c));
                let nr = names.first().map_or(range, |x| x.1);
                push(out, DeclKind::Channel(names, ty), nr);
            }
            DATATYPE_DECL | SUBTYPE_DECL => {
                let Some(name) = tokens(n).find(|t| t.kind() == IDENT) else { return };
                let mut clauses = Vec::new();
                for c in nodes(n).iter().filter(|c| c.kind() == DATATYPE_CLAUSE) {
                    let Some(t) = tokens(c).find(|t| t.kind() == IDENT) else { continue };
                    let fields = nodes(c).first().map(|e| self.expr(e));
                    clauses.push((t.text().into(), t.text_range(), fields));
                }
                let nm: Name = name.text().into();
                let kind = if n.kind() == DATATYPE_DECL {
                    DeclKind::Datatype(nm, clauses)
                } else {
                    DeclKind::Subtype(nm, clauses)
                };
                push(out, kind, name.text_range());
            }
            NAMETYPE_DECL => {
                let Some(name) = tokens(n).find(|t| t.kind() == IDENT) else { return };
                let Some(e) = nodes(n).first().map(|e| self.expr(e)) else { return };
                push(out, DeclKind::Nametype(name.text().into(), e), name.text_range());
            }
            TIMED_SECTION => {
                let f = nodes(n).into_iter().find(|c| c.kind() == ARG_LIST).and_then(|a| {
                    let args = nodes(&a);
                    if args.len() != 1 {
                        self.err(Code::Syntax, a.text_range(), "`Timed` takes one argument, the event function");
                    }
                    args.first().map(|e| self.expr(e))
                });
                let saved = self.timed.replace(Rc::new(Timed { f, range }));
                for d in nodes(n).iter().filter(|c| c.kind() != ARG_LIST) {
                    self.decl(d, out);
                }
                self.timed = saved;
            }
            MODULE_DECL if !nodes(n).iter().any(|c| c.kind() == ARG_LIST) => {
                let Some(name) = tokens(n).find(|t| t.kind() == IDENT) else { return };
                let mut inner = Vec::new();
                for c in nodes(n) {
                    if c.kind() == MODULE_EXPORTS {
                        for e in nodes(&c) {
                            self.decl(&e, &mut inner);
                        }
                    } else {
                        self.decl(&c, &mut inner);
                    }
                }
                push(out, DeclKind::Module(name.text().into(), inner.into()), name.text_range());
            }
            INCLUDE_DECL => {
                let Some(t) = tokens(n).next() else { return };
                let line = &t.text()["include".len()..];
                let file = line.split("--").next().unwrap_or("").trim().trim_matches('"').to_owned();
                let loaded = if self.depth < 16 { (self.load)(&file) } else { None };
                let Some(inner_text) = loaded else {
                    self.err(Code::Unresolved, t.text_range(), format!("cannot read the included file `{file}`"));
                    return;
                };
                let inner = crate::parse(&inner_text);
                if !inner.errors().is_empty() && !self.foreign {
                    self.err(Code::Syntax, t.text_range(), format!("the included file `{file}` has syntax errors"));
                }
                let saved = (self.foreign, std::mem::take(&mut self.diags));
                self.foreign = true;
                self.depth += 1;
                for d in nodes(&inner.syntax_node()) {
                    self.decl(&d, out);
                }
                self.depth -= 1;
                self.foreign = saved.0;
                self.diags = saved.1;
            }
            MODULE_DECL | INSTANCE_DECL => {
                let what = match n.kind() {
                    MODULE_DECL => "modules",
                    INSTANCE_DECL => "module instances",
                    _ => "`include`",
                };
                let at = tokens(n).next().map_or(range, |t| t.text_range());
                self.diags.push(Diagnostic {
                    code: Code::Unsupported,
                    severity: crate::Severity::Warning,
                    range: at,
                    message: format!("{what} are parsed but not evaluated: their definitions are not visible"),
                });
            }
            _ => {}
        }
    }

    fn name_list(&mut self, n: &SyntaxNode) -> Vec<(Name, TextRange)> {
        nodes(n)
            .iter()
            .filter(|c| c.kind() == NAME_LIST)
            .flat_map(|l| {
                tokens(l).filter(|t| t.kind() == IDENT).map(|t| (t.text().into(), t.text_range())).collect::<Vec<_>>()
            })
            .collect()
    }

    fn exprs(&mut self, n: &SyntaxNode) -> Vec<Expr> {
        nodes(n).iter().map(|c| self.expr(c)).collect()
    }

    fn stmts(&mut self, n: Option<&SyntaxNode>) -> Vec<Stmt> {
        let Some(n) = n else { return Vec::new() };
        nodes(n)
            .iter()
            .map(|s| {
                let k = nodes(s);
                match (s.kind(), k.first(), k.get(1)) {
                    (GENERATOR, Some(p), Some(e)) => Stmt::Gen(self.pat(p), self.expr(e)),
                    (_, Some(e), _) => Stmt::Pred(self.expr(e)),
                    _ => Stmt::Pred(Expr { kind: ExprKind::Error, range: s.text_range() }),
                }
            })
            .collect()
    }

    fn boxed(&mut self, n: Option<&SyntaxNode>, at: TextRange) -> Box<Expr> {
        Box::new(match n {
            Some(n) => self.expr(n),
            None => Expr { kind: ExprKind::Error, range: at },
        })
    }

    pub(crate) fn expr(&mut self, n: &SyntaxNode) -> Expr {
        let range = n.text_range();
        if self.stack.exceeded() {
            self.err(Code::Limit, range, "expression nested too deeply");
            return Expr { kind: ExprKind::Error, range };
        }
        let kids = nodes(n);
        let k0 = kids.first();
        let k1 = kids.get(1);
        let k2 = kids.get(2);
        let kind = match n.kind() {
            LITERAL => match tokens(n).next() {
                Some(t) => self.literal(&t),
                None => ExprKind::Error,
            },
            NAME_REF => ExprKind::Var(n.text().to_string().into()),
            WILDCARD => {
                self.err(Code::BadPattern, range, "`_` is a pattern, not a value");
                ExprKind::Error
            }
            PAREN_EXPR => return k0.map_or(Expr { kind: ExprKind::Error, range }, |e| self.expr(e)),
            TUPLE_EXPR => ExprKind::Tuple(self.exprs(n)),
            CALL_EXPR => {
                let f = self.boxed(k0, range);
                let args = k1.map(|a| self.exprs(a)).unwrap_or_default();
                ExprKind::App(f, args)
            }
            UNARY_EXPR => {
                let op = match first_token(n) {
                    Some(NOT_KW) => UnOp::Not,
                    Some(MINUS) => UnOp::Neg,
                    _ => UnOp::Len,
                };
                ExprKind::Un(op, self.boxed(k0, range))
            }
            BIN_EXPR => {
                let op = tokens(n).next().map(|t| t.kind());
                let a = self.boxed(k0, range);
                let b = self.boxed(k1, range);
                let bin_op = match op {
                    Some(PLUS) => Some(BinOp::Add),
                    Some(MINUS) => Some(BinOp::Sub),
                    Some(STAR) => Some(BinOp::Mul),
                    Some(SLASH) => Some(BinOp::Div),
                    Some(PERCENT) => Some(BinOp::Mod),
                    Some(EQ2) => Some(BinOp::Eq),
                    Some(NEQ) => Some(BinOp::Ne),
                    Some(LT) => Some(BinOp::Lt),
                    Some(LTEQ) => Some(BinOp::Le),
                    Some(GT) => Some(BinOp::Gt),
                    Some(GTEQ) => Some(BinOp::Ge),
                    Some(AND_KW) => Some(BinOp::And),
                    Some(OR_KW) => Some(BinOp::Or),
                    Some(DOT) => Some(BinOp::Dot),
                    Some(CARET) => Some(BinOp::Concat),
                    _ => None,
                };
                if let Some(o) = bin_op {
                    return Expr { kind: ExprKind::Bin(o, a, b), range };
                }
                match op {
                    Some(EXT_CHOICE) => ExprKind::Proc(ProcOp::Ext, a, b),
                    Some(INT_CHOICE) => ExprKind::Proc(ProcOp::Int, a, b),
                    Some(INTERLEAVE) => ExprKind::Proc(ProcOp::Interleave, a, b),
                    Some(SEMI) => ExprKind::Proc(ProcOp::Seq, a, b),
                    Some(INTERRUPT) => ExprKind::Proc(ProcOp::Interrupt, a, b),
                    Some(SLIDE) => ExprKind::Proc(ProcOp::Slide, a, b),
                    Some(BACKSLASH) => ExprKind::Hide(a, b),
                    Some(PROJECT) => ExprKind::Project(a, b),
                    _ => {
                        let at = tokens(n).next().map_or(range, |t| t.text_range());
                        self.err(Code::Unsupported, at, "this operator is only allowed in type annotations");
                        ExprKind::Error
                    }
                }
            }
            SET_EXPR => ExprKind::Set(self.exprs(n)),
            SEQ_EXPR => ExprKind::Seq(self.exprs(n)),
            SET_RANGE | SEQ_RANGE => {
                let a = self.boxed(k0, range);
                let b = k1.map(|e| Box::new(self.expr(e)));
                if n.kind() == SET_RANGE {
                    ExprKind::SetRange(a, b)
                } else {
                    ExprKind::SeqRange(a, b)
                }
            }
            SET_COMPREHENSION | SEQ_COMPREHENSION => {
                let stmts = self.stmts(kids.last());
                let elems: Vec<_> = kids[..kids.len().saturating_sub(1)].iter().map(|e| self.expr(e)).collect();
                let seq = n.kind() == SEQ_COMPREHENSION;
                let elem = if has_token(n, DOT2) {
                    let mut it = elems.into_iter();
                    let a = Box::new(it.next().unwrap_or(Expr { kind: ExprKind::Error, range }));
                    let b = it.next().map(Box::new);
                    let kind = if seq { ExprKind::SeqRange(a, b) } else { ExprKind::SetRange(a, b) };
                    Expr { kind, range }
                } else if elems.len() == 1 {
                    elems.into_iter().next().unwrap_or(Expr { kind: ExprKind::Error, range })
                } else {
                    // `{a, b | x <- S}`: every element for every binding,
                    // as `Union({{a, b} | x <- S})` (`concat` for sequences).
                    let kind = if seq { ExprKind::Seq(elems) } else { ExprKind::Set(elems) };
                    let e = Expr { kind, range };
                    let kind =
                        if seq { ExprKind::SeqComp(Box::new(e), stmts) } else { ExprKind::SetComp(Box::new(e), stmts) };
                    let f = Expr { kind: ExprKind::Var((if seq { "concat" } else { "Union" }).into()), range };
                    return Expr { kind: ExprKind::App(Box::new(f), vec![Expr { kind, range }]), range };
                };
                if seq {
                    ExprKind::SeqComp(Box::new(elem), stmts)
                } else {
                    ExprKind::SetComp(Box::new(elem), stmts)
                }
            }
            CLOSURE_EXPR => ExprKind::Closure(self.exprs(n), Vec::new()),
            CLOSURE_COMPREHENSION => {
                let stmts = self.stmts(kids.last());
                let elems = kids[..kids.len().saturating_sub(1)].iter().map(|e| self.expr(e)).collect();
                ExprKind::Closure(elems, stmts)
            }
            MAP_EXPR => {
                let es = self.exprs(n);
                let mut it = es.into_iter();
                let mut pairs = Vec::new();
                while let (Some(a), Some(b)) = (it.next(), it.next()) {
                    pairs.push((a, b));
                }
                ExprKind::Map(pairs)
            }
            LET_EXPR => {
                let body = kids.iter().rev().find(|c| {
                    !matches!(
                        c.kind(),
                        DEFINITION
                            | TYPE_ANNOTATION
                            | TIMED_SECTION
                            | CHANNEL_DECL
                            | DATATYPE_DECL
                            | NAMETYPE_DECL
                            | SUBTYPE_DECL
                            | EXTERNAL_DECL
                            | TRANSPARENT_DECL
                            | ASSERT_DECL
                            | PRINT_DECL
                            | MODULE_DECL
                    )
                });
                let mut decls = Vec::new();
                for d in kids.iter().filter(|c| Some(*c) != body) {
                    self.decl(d, &mut decls);
                }
                ExprKind::Let(decls.into(), self.boxed(body, range))
            }
            IF_EXPR => ExprKind::If(self.boxed(k0, range), self.boxed(k1, range), self.boxed(k2, range)),
            LAMBDA_EXPR => {
                let pats: Vec<Pat> = kids[..kids.len().saturating_sub(1)].iter().map(|p| self.pat(p)).collect();
                let body = self.boxed(kids.last(), range);
                ExprKind::Lambda(pats.into(), Rc::from(body))
            }
            PREFIX_EXPR => {
                let ev = self.boxed(k0, range);
                let mut fields = Vec::new();
                for f in kids.iter().filter(|c| matches!(c.kind(), INPUT_FIELD | NONDET_FIELD | OUTPUT_FIELD)) {
                    let fk = nodes(f);
                    fields.push(match f.kind() {
                        OUTPUT_FIELD => Field::Output(*self.boxed(fk.first(), f.text_range())),
                        kind => {
                            let p = fk.first().map_or(Pat::Wild, |p| self.pat(p));
                            let s = fk.get(1).map(|s| self.expr(s));
                            if kind == INPUT_FIELD {
                                Field::Input(p, s)
                            } else {
                                Field::NonDet(p, s)
                            }
                        }
                    });
                }
                let body =
                    kids.iter().skip(1).rfind(|c| !matches!(c.kind(), INPUT_FIELD | NONDET_FIELD | OUTPUT_FIELD));
                ExprKind::Prefix(ev, fields, self.boxed(body, range))
            }
            GUARD_EXPR => ExprKind::Guard(self.boxed(k0, range), self.boxed(k1, range)),
            GEN_PARALLEL | EXCEPTION | SYNC_EXT_CHOICE | SYNC_INTERRUPT => {
                let op = match n.kind() {
                    GEN_PARALLEL => SetOp::GenPar,
                    EXCEPTION => SetOp::Exception,
                    SYNC_EXT_CHOICE => SetOp::SyncExt,
                    _ => SetOp::SyncInt,
                };
                ExprKind::SetProc(op, self.boxed(k0, range), self.boxed(k1, range), self.boxed(k2, range))
            }
            ALPHA_PARALLEL => {
                let k3 = kids.get(3);
                ExprKind::AlphaPar(
                    self.boxed(k0, range),
                    self.boxed(k1, range),
                    self.boxed(k2, range),
                    self.boxed(k3, range),
                )
            }
            LINK_PARALLEL => {
                let links = self.links(&kids);
                let stmts = self.stmts(kids.iter().find(|c| c.kind() == STMT_LIST));
                let rhs = kids.iter().skip(1).rfind(|c| !matches!(c.kind(), LINK | STMT_LIST));
                ExprKind::LinkPar(self.boxed(k0, range), links, stmts, self.boxed(rhs, range))
            }
            RENAME_EXPR => {
                let pairs = kids
                    .iter()
                    .filter(|c| c.kind() == RENAME_PAIR)
                    .map(|c| {
                        let k = nodes(c);
                        (*self.boxed(k.first(), c.text_range()), *self.boxed(k.get(1), c.text_range()))
                    })
                    .collect();
                let stmts = self.stmts(kids.iter().find(|c| c.kind() == STMT_LIST));
                ExprKind::Rename(self.boxed(k0, range), pairs, stmts)
            }
            REPLICATED_EXPR => self.replicated(n, &kids, range),
            DOUBLE_PATTERN => {
                self.err(Code::BadPattern, range, "`@@` is only allowed in patterns");
                ExprKind::Error
            }
            _ => ExprKind::Error,
        };
        Expr { kind, range }
    }

    fn links(&mut self, kids: &[SyntaxNode]) -> Vec<(Expr, Expr)> {
        kids.iter()
            .filter(|c| c.kind() == LINK)
            .map(|c| {
                let k = nodes(c);
                (*self.boxed(k.first(), c.text_range()), *self.boxed(k.get(1), c.text_range()))
            })
            .collect()
    }

    fn replicated(&mut self, n: &SyntaxNode, kids: &[SyntaxNode], range: TextRange) -> ExprKind {
        let Some(stmt_pos) = kids.iter().rposition(|c| c.kind() == STMT_LIST) else { return ExprKind::Error };
        let stmts_node = kids[stmt_pos].clone();
        let op_token = first_token(n);
        let before: Vec<_> = kids[..stmt_pos].to_vec();
        let after: Vec<_> = kids[stmt_pos + 1..].to_vec();
        let op = match op_token {
            Some(EXT_CHOICE) => RepOp::Ext,
            Some(INT_CHOICE) => RepOp::Int,
            Some(INTERLEAVE) => RepOp::Interleave,
            Some(SEMI) => RepOp::Seq,
            Some(L_PAR) => RepOp::GenPar(self.boxed(before.first(), range)),
            Some(LSYNC_EXT) => RepOp::SyncExt(self.boxed(before.first(), range)),
            Some(PARALLEL) => RepOp::AlphaPar(self.boxed(after.first(), range)),
            Some(L_BRACK) => {
                let links = self.links(&before);
                let s = self.stmts(before.iter().find(|c| c.kind() == STMT_LIST));
                RepOp::Link(links, s)
            }
            _ => return ExprKind::Error,
        };
        let stmts = self.stmts(Some(&stmts_node));
        let body = self.boxed(after.last(), range);
        ExprKind::Replicated(op, stmts, body)
    }

    fn literal(&mut self, t: &SyntaxToken) -> ExprKind {
        let text = t.text();
        match t.kind() {
            INT => match text.parse() {
                Ok(v) => ExprKind::Int(v),
                Err(_) => {
                    self.err(Code::Syntax, t.text_range(), "integer literal too large");
                    ExprKind::Error
                }
            },
            TRUE_KW => ExprKind::Bool(true),
            FALSE_KW => ExprKind::Bool(false),
            STRING => ExprKind::Str(unescape(&text[1..text.len() - 1]).into()),
            CHAR => {
                let s = unescape(&text[1..text.len().saturating_sub(1).max(1)]);
                let mut cs = s.chars();
                match (cs.next(), cs.next()) {
                    (Some(c), None) => ExprKind::Char(c),
                    _ => {
                        self.err(Code::Syntax, t.text_range(), "a character literal holds one character");
                        ExprKind::Error
                    }
                }
            }
            _ => ExprKind::Error,
        }
    }

    pub(crate) fn pat(&mut self, n: &SyntaxNode) -> Pat {
        if self.stack.exceeded() {
            self.err(Code::Limit, n.text_range(), "pattern nested too deeply");
            return Pat::Wild;
        }
        let kids = nodes(n);
        let bad = |s: &mut Self| {
            s.err(Code::BadPattern, n.text_range(), format!("`{}` is not a pattern", n.text()));
            Pat::Wild
        };
        match n.kind() {
            WILDCARD => Pat::Wild,
            NAME_REF => Pat::Name(n.text().to_string().into(), n.text_range()),
            PAREN_EXPR => kids.first().map_or(Pat::Wild, |k| self.pat(k)),
            TUPLE_EXPR => Pat::Tuple(kids.iter().map(|k| self.pat(k)).collect()),
            SEQ_EXPR => Pat::Seq(kids.iter().map(|k| self.pat(k)).collect()),
            SET_EXPR if kids.len() <= 1 => Pat::Set(kids.iter().map(|k| self.pat(k)).collect()),
            LITERAL => match tokens(n).next().map(|t| self.literal(&t)) {
                Some(ExprKind::Int(v)) => Pat::Int(v),
                Some(ExprKind::Bool(b)) => Pat::Bool(b),
                Some(ExprKind::Char(c)) => Pat::Char(c),
                Some(ExprKind::Str(s)) => Pat::Str(s),
                _ => Pat::Wild,
            },
            UNARY_EXPR if first_token(n) == Some(MINUS) => match kids.first().map(|k| self.pat(k)) {
                Some(Pat::Int(v)) => Pat::Int(-v),
                _ => bad(self),
            },
            BIN_EXPR if has_token(n, DOT) || has_token(n, CARET) => {
                let (Some(a), Some(b)) = (kids.first(), kids.get(1)) else { return Pat::Wild };
                let (a, b) = (Box::new(self.pat(a)), Box::new(self.pat(b)));
                if has_token(n, DOT) {
                    Pat::Dot(a, b)
                } else {
                    Pat::Concat(a, b)
                }
            }
            DOUBLE_PATTERN => {
                let (Some(a), Some(b)) = (kids.first(), kids.get(1)) else { return Pat::Wild };
                Pat::Double(Box::new(self.pat(a)), Box::new(self.pat(b)))
            }
            ERROR => Pat::Wild,
            _ => bad(self),
        }
    }
}

fn unescape(s: &str) -> String {
    let mut out = String::new();
    let mut cs = s.chars();
    while let Some(c) = cs.next() {
        if c == '\\' {
            match cs.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some('r') => out.push('\r'),
                Some(o) => out.push(o),
                None => {}
            }
        } else {
            out.push(c);
        }
    }
    out
}
