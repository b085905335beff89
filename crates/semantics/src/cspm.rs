//! A typed syntax tree for the fragment of CSPm (the machine-readable CSP
//! of FDR) that the export generates, and its pretty-printer.
//!
//! The printer never relies on the fine points of CSPm's precedence table:
//! operands of process operators are parenthesised unless they are atoms
//! (names, applications, `STOP`, `SKIP`) or prefixes and guards, and
//! `if`, `let` and replicated operators, which extend as far right as
//! possible, are parenthesised whenever something could follow them.

use crate::doc::{cat, group, nest, render, text, Doc};

/// Width of the printed files.
pub const WIDTH: usize = 100;

/// Binary operators on values: the same as those of the CSPm definitions
/// the semantic model reads from instantiation blocks.
pub use robosim_hir::csp_fn::CspBinOp as BinOp;

/// N-ary process operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProcOp {
    /// `[]`.
    ExtChoice,
    /// `|~|`.
    IntChoice,
    /// `;`.
    Seq,
    /// `|||`.
    Interleave,
    /// `/\`.
    Interrupt,
}

impl ProcOp {
    fn text(self) -> &'static str {
        match self {
            ProcOp::ExtChoice => "[]",
            ProcOp::IntChoice => "|~|",
            ProcOp::Seq => ";",
            ProcOp::Interleave => "|||",
            ProcOp::Interrupt => "/\\",
        }
    }
}

/// Replicated operators.
#[derive(Debug, Clone, PartialEq)]
pub enum ReplOp {
    /// `[] x : S @ P`.
    ExtChoice,
    /// `|~| x : S @ P`.
    IntChoice,
    /// `||| x : S @ P`.
    Interleave,
    /// `; x : <…> @ P` (over a sequence).
    Seq,
    /// `[| A |] x : S @ P`.
    Par(Box<Expr>),
}

/// One field of a prefix.
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// `.e`.
    Dot(Expr),
    /// `!e`.
    Out(Expr),
    /// `?x`.
    In(String),
    /// `?x : S`.
    InFrom(String, Expr),
}

/// A CSPm expression: values, sets and processes share one language.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)]
pub enum Expr {
    Int(i64),
    Bool(bool),
    /// An identifier, possibly qualified (`M::x`).
    Name(String),
    /// `a.b.c`.
    Dot(Vec<Expr>),
    /// `f(a, b)`.
    Call(String, Vec<Expr>),
    Not(Box<Expr>),
    Neg(Box<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    Let(Vec<Decl>, Box<Expr>),
    /// `{a, b}`.
    Set(Vec<Expr>),
    /// `{a..b}`.
    Range(Box<Expr>, Box<Expr>),
    /// `{e | x <- S, y <- T}`.
    SetComp(Box<Expr>, Vec<(String, Expr)>),
    /// `{| a, b |}`.
    Events(Vec<Expr>),
    /// `<a, b>`.
    SeqLit(Vec<Expr>),
    /// `(a, b)`.
    Tuple(Vec<Expr>),
    Stop,
    Skip,
    /// `c fields -> P`; the channel is a (possibly qualified) name.
    Prefix(String, Vec<Field>, Box<Expr>),
    /// `b & P`.
    Guard(Box<Expr>, Box<Expr>),
    /// `P op Q op …` (at least two operands).
    Nary(ProcOp, Vec<Expr>),
    /// `P [| A |] Q`.
    Par(Box<Expr>, Box<Expr>, Box<Expr>),
    /// `P [| A |> Q`.
    Exception(Box<Expr>, Box<Expr>, Box<Expr>),
    /// `P \ A`.
    Hide(Box<Expr>, Box<Expr>),
    /// `P [[ a <- b, … | x <- S, … ]]`.
    Rename(Box<Expr>, Vec<(Expr, Expr)>, Vec<(String, Expr)>),
    /// `op x : S, y : T @ P`.
    Repl(ReplOp, Vec<(String, Expr)>, Box<Expr>),
}

/// A CSPm assertion's semantic model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// `T`.
    Traces,
    /// `F`.
    Failures,
    /// `FD`.
    FailuresDivergences,
}

impl Model {
    fn text(self) -> &'static str {
        match self {
            Model::Traces => "T",
            Model::Failures => "F",
            Model::FailuresDivergences => "FD",
        }
    }
}

/// What an assertion claims.
#[derive(Debug, Clone, PartialEq)]
pub enum AssertKind {
    /// `Spec [M= Impl`.
    Refines(Model, Expr, Expr),
    /// `P :[deadlock free [M]]`.
    DeadlockFree(Expr, Model),
    /// `P :[divergence free [M]]`.
    DivergenceFree(Expr, Model),
    /// `P :[deterministic [M]]`.
    Deterministic(Expr, Model),
}

/// `assert [not] … [:[tau priority]: A]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Assert {
    /// `assert not …`.
    pub negated: bool,
    /// The claim.
    pub kind: AssertKind,
    /// `:[tau priority]: A`.
    pub tau_priority: Option<Expr>,
}

/// A declaration.
#[derive(Debug, Clone, PartialEq)]
pub enum Decl {
    /// `-- text` (one line per line of text).
    Comment(String),
    /// An empty line.
    Blank,
    /// `include "file"`.
    Include(String),
    /// `channel a, b : T1.T2` (no type for plain events).
    Channel(Vec<String>, Vec<Expr>),
    /// `datatype T = A | B.X`.
    Datatype(String, Vec<(String, Vec<Expr>)>),
    /// `nametype T = S`.
    Nametype(String, Expr),
    /// `f(x, y) = e` (no parameters: `f = e`; one empty parameter: the
    /// function of no arguments `f() = e`).
    Def(String, Vec<String>, Expr),
    /// `module M … exports … endmodule`: private, then exported declarations.
    Module(String, Vec<Decl>, Vec<Decl>),
    /// `transparent f, g`.
    Transparent(Vec<String>),
    /// An assertion.
    Assert(Assert),
    /// Text copied verbatim (a user's `csp` block), and the process it
    /// is named after.
    Raw(String, String),
    /// `Timed(f) { … }`: a timed section (FDR inserts `tock`; the
    /// declarations are in the enclosing scope).
    Timed(String, Vec<Decl>),
}

// ---------------------------------------------------------------- helpers

/// `Name(s)`.
pub fn name(s: impl Into<String>) -> Expr {
    Expr::Name(s.into())
}

/// `f(args)`.
pub fn call(f: impl Into<String>, args: Vec<Expr>) -> Expr {
    Expr::Call(f.into(), args)
}

/// `a.b.c`, or `a` alone.
pub fn dot(mut parts: Vec<Expr>) -> Expr {
    if parts.len() == 1 {
        parts.pop().expect("one part")
    } else {
        Expr::Dot(parts)
    }
}

/// `c fields -> p`.
pub fn prefix(chan: impl Into<String>, fields: Vec<Field>, p: Expr) -> Expr {
    Expr::Prefix(chan.into(), fields, Box::new(p))
}

/// `b & p`.
pub fn guard(b: Expr, p: Expr) -> Expr {
    match b {
        Expr::Bool(true) => p,
        b => Expr::Guard(Box::new(b), Box::new(p)),
    }
}

/// `p1 op p2 op …`, flattened; one operand is returned as it is.
pub fn nary(op: ProcOp, parts: Vec<Expr>) -> Expr {
    let mut flat = Vec::new();
    for p in parts {
        match p {
            Expr::Nary(o, inner) if o == op => flat.extend(inner),
            Expr::Skip if op == ProcOp::Seq => {}
            p => flat.push(p),
        }
    }
    match flat.len() {
        0 => match op {
            ProcOp::Seq | ProcOp::Interleave => Expr::Skip,
            _ => Expr::Stop,
        },
        1 => flat.pop().expect("one operand"),
        _ => Expr::Nary(op, flat),
    }
}

/// `p1 ; p2 ; …` without the `SKIP`s.
pub fn seq(parts: Vec<Expr>) -> Expr {
    nary(ProcOp::Seq, parts)
}

/// `p1 [] p2 [] …`.
pub fn ext(parts: Vec<Expr>) -> Expr {
    nary(ProcOp::ExtChoice, parts)
}

/// `a op b`.
pub fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
    Expr::Bin(op, Box::new(a), Box::new(b))
}

/// `P [| A |] Q`.
pub fn par(p: Expr, a: Expr, q: Expr) -> Expr {
    Expr::Par(Box::new(p), Box::new(a), Box::new(q))
}

/// `P \ A`.
pub fn hide(p: Expr, a: Expr) -> Expr {
    Expr::Hide(Box::new(p), Box::new(a))
}

// ---------------------------------------------------------------- printing

/// Prints declarations, one after the other.
pub fn print_decls(decls: &[Decl]) -> String {
    let mut out = String::new();
    for d in decls {
        out.push_str(&render(&decl_doc(d), WIDTH));
        out.push('\n');
    }
    out
}

/// Prints one expression (for hovers), in `width` columns.
pub fn print_expr(e: &Expr, width: usize) -> String {
    render(&expr_doc(e), width)
}

fn hard() -> Doc {
    Doc::HardLine
}

fn line() -> Doc {
    Doc::Line
}

fn decl_doc(d: &Decl) -> Doc {
    match d {
        Decl::Comment(s) => {
            let mut parts = Vec::new();
            for (i, l) in s.lines().enumerate() {
                if i > 0 {
                    parts.push(hard());
                }
                parts.push(text(if l.is_empty() { "--".to_string() } else { format!("-- {l}") }));
            }
            if parts.is_empty() {
                parts.push(text("--"));
            }
            cat(parts)
        }
        Decl::Blank => text(""),
        Decl::Include(f) => text(format!("include \"{f}\"")),
        Decl::Channel(names, ty) => {
            let mut s = format!("channel {}", names.join(", "));
            if !ty.is_empty() {
                s.push_str(" : ");
                let parts: Vec<String> = ty.iter().map(|t| flat(&field_doc(t))).collect();
                s.push_str(&parts.join("."));
            }
            text(s)
        }
        Decl::Datatype(n, ctors) => {
            let mut parts = vec![text(format!("datatype {n} ="))];
            for (i, (c, fields)) in ctors.iter().enumerate() {
                let mut s = if i == 0 { String::new() } else { "| ".to_string() };
                s.push_str(c);
                for f in fields {
                    s.push('.');
                    s.push_str(&flat(&field_doc(f)));
                }
                parts.push(line());
                parts.push(text(s));
            }
            group(nest(2, cat(parts)))
        }
        Decl::Nametype(n, e) => {
            group(cat(vec![text(format!("nametype {n} =")), nest(2, cat(vec![line(), expr_doc(e)]))]))
        }
        Decl::Def(n, params, body) => {
            let head = if params.is_empty() { n.clone() } else { format!("{n}({})", params.join(", ")) };
            group(cat(vec![text(format!("{head} =")), nest(2, cat(vec![line(), expr_doc(body)]))]))
        }
        Decl::Module(n, private, exports) => {
            let mut parts = vec![text(format!("module {n}"))];
            for d in private {
                parts.push(hard());
                parts.push(nest(2, decl_doc(d)));
            }
            parts.push(hard());
            parts.push(text("exports"));
            for d in exports {
                parts.push(hard());
                parts.push(nest(2, decl_doc(d)));
            }
            parts.push(hard());
            parts.push(text("endmodule"));
            // Indent the inner declarations.
            cat(parts.into_iter().map(indent_decl).collect())
        }
        Decl::Transparent(names) => text(format!("transparent {}", names.join(", "))),
        Decl::Timed(f, decls) => {
            let mut parts = vec![text(format!("Timed({f}) {{"))];
            for d in decls {
                parts.push(hard());
                parts.push(nest(2, decl_doc(d)));
            }
            parts.push(hard());
            parts.push(text("}"));
            cat(parts.into_iter().map(indent_decl).collect())
        }
        Decl::Assert(a) => assert_doc(a),
        Decl::Raw(s, _) => {
            let mut parts = Vec::new();
            for (i, l) in s.lines().enumerate() {
                if i > 0 {
                    parts.push(hard());
                }
                parts.push(text(l.trim_end().to_string()));
            }
            cat(parts)
        }
    }
}

/// Inner declarations of a module are printed two columns in: the
/// `Nest(2, decl)` pieces get their first line indented here.
fn indent_decl(d: Doc) -> Doc {
    match d {
        Doc::Nest(2, inner) => cat(vec![text("  "), Doc::Nest(2, inner)]),
        d => d,
    }
}

fn assert_doc(a: &Assert) -> Doc {
    let mut parts = vec![text(if a.negated { "assert not " } else { "assert " })];
    match &a.kind {
        AssertKind::Refines(m, spec, imp) => {
            parts.push(operand(spec, Ctx::Loose));
            parts.push(nest(2, cat(vec![line(), text(format!("[{}= ", m.text())), operand(imp, Ctx::Loose)])));
        }
        AssertKind::DeadlockFree(p, m) => {
            parts.push(operand(p, Ctx::Loose));
            parts.push(text(format!(" :[deadlock free [{}]]", m.text())));
        }
        AssertKind::DivergenceFree(p, m) => {
            parts.push(operand(p, Ctx::Loose));
            parts.push(text(format!(" :[divergence free [{}]]", m.text())));
        }
        AssertKind::Deterministic(p, m) => {
            parts.push(operand(p, Ctx::Loose));
            parts.push(text(format!(" :[deterministic [{}]]", m.text())));
        }
    }
    if let Some(t) = &a.tau_priority {
        parts.push(text(" :[tau priority]: "));
        parts.push(expr_doc(t));
    }
    group(cat(parts))
}

fn flat(d: &Doc) -> String {
    render(&group(d.clone()), usize::MAX)
}

/// How an operand is used: what it may be without parentheses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ctx {
    /// Anything (a whole right-hand side, a branch of `if`, a set element).
    Top,
    /// Operand of a process operator: atoms, prefixes and guards.
    Loose,
    /// Operand of renaming, hiding's left side: atoms only.
    Atom,
}

fn is_atom(e: &Expr) -> bool {
    match e {
        Expr::Int(n) => *n >= 0,
        Expr::Bool(_)
        | Expr::Name(_)
        | Expr::Call(..)
        | Expr::Set(_)
        | Expr::Range(..)
        | Expr::SetComp(..)
        | Expr::Events(_)
        | Expr::SeqLit(_)
        | Expr::Tuple(_)
        | Expr::Stop
        | Expr::Skip => true,
        Expr::Rename(..) => true,
        _ => false,
    }
}

/// Prefixes and guards whose body needs no parentheses can stand as
/// operands of binary process operators.
fn is_tight(e: &Expr) -> bool {
    matches!(e, Expr::Prefix(..) | Expr::Guard(..))
}

fn operand(e: &Expr, ctx: Ctx) -> Doc {
    let ok = match ctx {
        Ctx::Top => true,
        Ctx::Loose => is_atom(e) || is_tight(e),
        Ctx::Atom => is_atom(e),
    };
    if ok {
        expr_doc(e)
    } else {
        paren(expr_doc(e))
    }
}

fn paren(d: Doc) -> Doc {
    cat(vec![text("("), nest(1, d), text(")")])
}

/// A value in a field position (`c.x`, a guard, an argument of a dot).
fn field_doc(e: &Expr) -> Doc {
    if is_atom(e) {
        expr_doc(e)
    } else {
        paren(expr_doc(e))
    }
}

fn value_operand(e: &Expr, min_prec: u8) -> Doc {
    let p = match e {
        Expr::Bin(op, ..) => op.prec(),
        Expr::Not(_) => 3,
        Expr::Neg(_) => 7,
        e if is_atom(e) => 10,
        Expr::Dot(_) => 0,
        _ => 0,
    };
    if p >= min_prec {
        expr_doc(e)
    } else {
        paren(expr_doc(e))
    }
}

fn comma_list(items: &[Expr]) -> Doc {
    let mut parts = Vec::new();
    for (i, it) in items.iter().enumerate() {
        if i > 0 {
            parts.push(text(","));
            parts.push(line());
        }
        parts.push(expr_doc(it));
    }
    cat(parts)
}

/// Whether `e` prints starting with `-`: after `{` that would open an FDR
/// block comment `{- … -}`, so a space must separate them.
fn starts_with_minus(e: &Expr) -> bool {
    matches!(e, Expr::Int(n) if *n < 0) || matches!(e, Expr::Neg(_))
}

fn bracketed(open: &str, items: &[Expr], close: &str) -> Doc {
    let open = if open == "{" && items.first().is_some_and(starts_with_minus) { "{ " } else { open };
    group(cat(vec![
        text(open),
        nest(open.len(), cat(vec![Doc::SoftLine, comma_list(items)])),
        Doc::SoftLine,
        text(close),
    ]))
}

fn expr_doc(e: &Expr) -> Doc {
    match e {
        Expr::Int(n) => text(n.to_string()),
        Expr::Bool(b) => text(if *b { "true" } else { "false" }),
        Expr::Name(n) => text(n.clone()),
        Expr::Dot(parts) => {
            let mut v = Vec::new();
            for (i, p) in parts.iter().enumerate() {
                if i > 0 {
                    v.push(text("."));
                }
                v.push(field_doc(p));
            }
            cat(v)
        }
        Expr::Call(f, args) => {
            group(cat(vec![text(format!("{f}(")), nest(2, cat(vec![Doc::SoftLine, comma_list(args)])), text(")")]))
        }
        Expr::Not(x) => cat(vec![text("not "), value_operand(x, 10)]),
        Expr::Neg(x) => cat(vec![text("-"), value_operand(x, 8)]),
        Expr::Bin(op, a, b) => {
            let p = op.prec();
            // Left-associative; comparisons are not associative at all.
            let left_min = if p == 4 { 5 } else { p };
            group(cat(vec![
                value_operand(a, left_min),
                text(format!(" {}", op.text())),
                nest(2, cat(vec![line(), value_operand(b, p + 1)])),
            ]))
        }
        Expr::If(c, a, b) => group(cat(vec![
            text("if "),
            expr_doc(c),
            nest(2, cat(vec![line(), text("then "), nest(5, operand(a, Ctx::Top))])),
            nest(2, cat(vec![line(), text("else "), nest(5, operand(b, Ctx::Top))])),
        ])),
        Expr::Let(decls, body) => {
            let mut parts = vec![text("let")];
            for d in decls {
                parts.push(nest(2, cat(vec![hard(), decl_doc(d)])));
            }
            parts.push(hard());
            parts.push(text("within"));
            parts.push(nest(2, cat(vec![hard(), operand(body, Ctx::Top)])));
            cat(parts)
        }
        Expr::Set(items) => bracketed("{", items, "}"),
        Expr::Range(a, b) => {
            let open = if starts_with_minus(a) { "{ " } else { "{" };
            cat(vec![text(open), expr_doc(a), text(".."), expr_doc(b), text("}")])
        }
        Expr::SetComp(e, gens) => {
            let mut g = Vec::new();
            for (i, (x, s)) in gens.iter().enumerate() {
                if i > 0 {
                    g.push(text(","));
                    g.push(line());
                }
                g.push(cat(vec![text(format!("{x} <- ")), expr_doc(s)]));
            }
            group(cat(vec![text("{"), nest(1, cat(vec![expr_doc(e), text(" |"), line(), cat(g)])), text("}")]))
        }
        Expr::Events(items) => bracketed("{| ", items, " |}"),
        Expr::SeqLit(items) => bracketed("<", items, ">"),
        Expr::Tuple(items) => bracketed("(", items, ")"),
        Expr::Stop => text("STOP"),
        Expr::Skip => text("SKIP"),
        Expr::Prefix(c, fields, body) => {
            let mut head = c.clone();
            for f in fields {
                match f {
                    Field::Dot(x) => {
                        head.push('.');
                        head.push_str(&flat(&field_doc(x)));
                    }
                    Field::Out(x) => {
                        head.push('!');
                        head.push_str(&flat(&field_doc(x)));
                    }
                    Field::In(x) => {
                        head.push('?');
                        head.push_str(x);
                    }
                    Field::InFrom(x, s) => {
                        head.push('?');
                        head.push_str(x);
                        head.push(':');
                        head.push_str(&flat(&field_doc(s)));
                    }
                }
            }
            group(cat(vec![text(format!("{head} ->")), nest(2, cat(vec![line(), body_doc(body)]))]))
        }
        Expr::Guard(b, body) => group(cat(vec![field_doc(b), text(" &"), nest(2, cat(vec![line(), body_doc(body)]))])),
        Expr::Nary(op, parts) => {
            let mut v = Vec::new();
            for (i, p) in parts.iter().enumerate() {
                if i > 0 {
                    v.push(line());
                    v.push(text(format!("{} ", op.text())));
                }
                v.push(nest(op.text().len() + 1, operand(p, Ctx::Loose)));
            }
            group(cat(v))
        }
        Expr::Par(p, a, q) => group(cat(vec![
            operand(p, Ctx::Loose),
            line(),
            text("[| "),
            expr_doc(a),
            text(" |]"),
            line(),
            operand(q, Ctx::Loose),
        ])),
        Expr::Exception(p, a, q) => group(cat(vec![
            operand(p, Ctx::Loose),
            line(),
            text("[| "),
            expr_doc(a),
            text(" |>"),
            line(),
            operand(q, Ctx::Loose),
        ])),
        Expr::Hide(p, a) => {
            group(cat(vec![operand(p, Ctx::Atom), nest(2, cat(vec![line(), text("\\ "), field_doc(a)]))]))
        }
        Expr::Rename(p, pairs, gens) => {
            let mut items = Vec::new();
            for (i, (a, b)) in pairs.iter().enumerate() {
                if i > 0 {
                    items.push(text(","));
                    items.push(line());
                }
                items.push(cat(vec![expr_doc(a), text(" <- "), expr_doc(b)]));
            }
            if !gens.is_empty() {
                items.push(text(" |"));
                for (i, (x, s)) in gens.iter().enumerate() {
                    items.push(if i == 0 { line() } else { cat(vec![text(","), line()]) });
                    items.push(cat(vec![text(format!("{x} <- ")), expr_doc(s)]));
                }
            }
            group(cat(vec![
                operand(p, Ctx::Atom),
                text(" [["),
                nest(4, cat(vec![line(), cat(items)])),
                line(),
                text("]]"),
            ]))
        }
        Expr::Repl(op, gens, body) => {
            let head = match op {
                ReplOp::ExtChoice => text("[] "),
                ReplOp::IntChoice => text("|~| "),
                ReplOp::Interleave => text("||| "),
                ReplOp::Seq => text("; "),
                ReplOp::Par(a) => cat(vec![text("[| "), expr_doc(a), text(" |] ")]),
            };
            let mut g = Vec::new();
            for (i, (x, s)) in gens.iter().enumerate() {
                if i > 0 {
                    g.push(text(", "));
                }
                g.push(cat(vec![text(format!("{x} : ")), expr_doc(s)]));
            }
            group(cat(vec![head, cat(g), text(" @"), nest(2, cat(vec![line(), operand(body, Ctx::Loose)]))]))
        }
    }
}

/// The body of a prefix or guard: parenthesised unless an atom, a prefix
/// or a guard (whose own body is then checked the same way).
fn body_doc(e: &Expr) -> Doc {
    operand(e, Ctx::Loose)
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_negative_first_element_does_not_open_an_fdr_comment() {
        use super::*;
        let range = Expr::Range(Box::new(Expr::Int(-2)), Box::new(Expr::Int(3)));
        assert_eq!(print_expr(&range, 100), "{ -2..3}");
        assert_eq!(print_expr(&Expr::Set(vec![Expr::Int(-1), Expr::Int(2)]), 100), "{ -1, 2}");
        assert_eq!(print_expr(&Expr::Range(Box::new(Expr::Int(0)), Box::new(Expr::Int(3))), 100), "{0..3}");
    }

    use super::*;

    #[test]
    fn prints_with_parentheses_where_needed() {
        let p = prefix(
            "a",
            vec![Field::Dot(Expr::Int(1)), Field::In("x".into())],
            ext(vec![prefix("b", vec![Field::Out(bin(BinOp::Add, name("x"), Expr::Int(1)))], Expr::Skip), Expr::Stop]),
        );
        assert_eq!(print_expr(&p, 100), "a.1?x -> (b!(x + 1) -> SKIP [] STOP)");
        let h = hide(seq(vec![name("P"), name("Q")]), Expr::Events(vec![name("c")]));
        assert_eq!(print_expr(&h, 100), "(P ; Q) \\ {| c |}");
        let i = ext(vec![Expr::If(Box::new(name("b")), Box::new(Expr::Skip), Box::new(Expr::Stop)), name("P")]);
        assert_eq!(print_expr(&i, 100), "(if b then SKIP else STOP) [] P");
        let neg = dot(vec![name("c"), Expr::Int(-1)]);
        assert_eq!(print_expr(&neg, 100), "c.(-1)");
        let arith = bin(BinOp::Sub, name("a"), bin(BinOp::Sub, name("b"), name("c")));
        assert_eq!(print_expr(&arith, 100), "a - (b - c)");
    }

    #[test]
    fn breaks_long_choices() {
        let alts: Vec<Expr> =
            (0..6).map(|i| prefix(format!("event_number_{i}"), vec![], name(format!("Process_{i}")))).collect();
        let s = print_expr(&ext(alts), 60);
        assert!(s.lines().count() == 6, "{s}");
        assert!(s.lines().nth(1).unwrap().starts_with("[] event_number_1 ->"), "{s}");
    }
}
