//! CSPm function definitions in instantiation blocks: the subset RoboTool
//! users write to give a meaning to the functions their model declares
//! without a body (`random() = 0`, `floor(x) = x`,
//! `gte(x__, y__) = em2int(x__) >= em2int(y__)`, and clauses by pattern
//! such as `em2int(Emergency_E1) = 1`). One definition per line; anything
//! outside the subset is left to FDR.

use robosim_syntax::TextRange;

/// An expression of the subset.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum CspExpr {
    /// An integer literal.
    Int(i64),
    /// `true` or `false`.
    Bool(bool),
    /// A parameter, another definition, or a constructor (`Emergency_E1`).
    Name(String),
    /// `f(a, b)`.
    Call(String, Vec<CspExpr>),
    /// `-e`.
    Neg(Box<CspExpr>),
    /// `not e`.
    Not(Box<CspExpr>),
    /// `a op b`.
    Bin(CspBinOp, Box<CspExpr>, Box<CspExpr>),
    /// `if c then a else b`.
    If(Box<CspExpr>, Box<CspExpr>, Box<CspExpr>),
}

/// A binary operator on CSPm values (also the CSPm export's).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum CspBinOp {
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
    /// `^`: sequence concatenation (written by the export, not read).
    Cat,
}

impl CspBinOp {
    /// The operators [`parse_definition`] reads.
    const READ: [CspBinOp; 13] = [
        CspBinOp::Or,
        CspBinOp::And,
        CspBinOp::Eq,
        CspBinOp::Ne,
        CspBinOp::Le,
        CspBinOp::Ge,
        CspBinOp::Lt,
        CspBinOp::Gt,
        CspBinOp::Add,
        CspBinOp::Sub,
        CspBinOp::Mul,
        CspBinOp::Div,
        CspBinOp::Mod,
    ];

    /// How it is written.
    pub fn text(self) -> &'static str {
        match self {
            CspBinOp::Add => "+",
            CspBinOp::Sub => "-",
            CspBinOp::Mul => "*",
            CspBinOp::Div => "/",
            CspBinOp::Mod => "%",
            CspBinOp::Eq => "==",
            CspBinOp::Ne => "!=",
            CspBinOp::Lt => "<",
            CspBinOp::Le => "<=",
            CspBinOp::Gt => ">",
            CspBinOp::Ge => ">=",
            CspBinOp::And => "and",
            CspBinOp::Or => "or",
            CspBinOp::Cat => "^",
        }
    }

    /// Binding strength in CSPm (higher binds tighter; `not` is 3).
    pub fn prec(self) -> u8 {
        match self {
            CspBinOp::Or => 1,
            CspBinOp::And => 2,
            CspBinOp::Eq | CspBinOp::Ne | CspBinOp::Lt | CspBinOp::Le | CspBinOp::Gt | CspBinOp::Ge => 4,
            CspBinOp::Add | CspBinOp::Sub => 5,
            CspBinOp::Mul | CspBinOp::Div | CspBinOp::Mod => 6,
            CspBinOp::Cat => 7,
        }
    }
}

/// One clause `name(p1, …, pn) = body`; the parameters are patterns: a
/// name binds the argument unless it is a constructor, a literal or a
/// constructor must match it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CspFunction {
    /// The function's name.
    pub name: String,
    /// The parameter patterns.
    pub params: Vec<CspExpr>,
    /// The body.
    pub body: CspExpr,
    /// The line.
    pub range: TextRange,
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Int(i64),
    Ident(String),
    Op(&'static str),
}

const OPS: &[&str] = &["==", "!=", "<=", ">=", "<", ">", "+", "-", "*", "/", "%", "(", ")", ",", "="];

fn lex(text: &str) -> Option<Vec<Tok>> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() {
            let start = i;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            out.push(Tok::Int(text[start..i].parse().ok()?));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'\'') {
                i += 1;
            }
            out.push(Tok::Ident(text[start..i].to_string()));
        } else {
            let op = OPS.iter().find(|op| text[i..].starts_with(**op))?;
            out.push(Tok::Op(op));
            i += op.len();
        }
    }
    Some(out)
}

/// Reads `name(p1, …) = body`, or `None` when the line is not one.
pub fn parse_definition(text: &str) -> Option<(String, Vec<CspExpr>, CspExpr)> {
    let toks = lex(text)?;
    let mut p = Parser { toks, at: 0 };
    let Some(Tok::Ident(name)) = p.next() else { return None };
    if is_keyword(&name) {
        return None;
    }
    p.expect("(")?;
    let params = p.arguments()?;
    p.expect("=")?;
    let body = p.expr(0)?;
    (p.at == p.toks.len()).then_some((name, params, body))
}

fn is_keyword(w: &str) -> bool {
    matches!(w, "if" | "then" | "else" | "and" | "or" | "not" | "true" | "false")
}

struct Parser {
    toks: Vec<Tok>,
    at: usize,
}

impl Parser {
    fn next(&mut self) -> Option<Tok> {
        let t = self.toks.get(self.at).cloned();
        self.at += 1;
        t
    }

    fn is(&self, s: &str) -> bool {
        match self.toks.get(self.at) {
            Some(Tok::Op(op)) => *op == s,
            Some(Tok::Ident(w)) => w == s,
            _ => false,
        }
    }

    fn eat(&mut self, s: &str) -> bool {
        let yes = self.is(s);
        if yes {
            self.at += 1;
        }
        yes
    }

    fn expect(&mut self, s: &str) -> Option<()> {
        self.eat(s).then_some(())
    }

    /// `a, b, …)` after an opening `(` (possibly none).
    fn arguments(&mut self) -> Option<Vec<CspExpr>> {
        let mut args = Vec::new();
        if self.eat(")") {
            return Some(args);
        }
        loop {
            args.push(self.expr(0)?);
            if self.eat(")") {
                return Some(args);
            }
            self.expect(",")?;
        }
    }

    /// An expression whose binary operators bind at least as tightly as
    /// `min` (0: any, and `if`).
    fn expr(&mut self, min: u8) -> Option<CspExpr> {
        if min == 0 && self.eat("if") {
            let c = self.expr(0)?;
            self.expect("then")?;
            let a = self.expr(0)?;
            self.expect("else")?;
            let b = self.expr(0)?;
            return Some(CspExpr::If(Box::new(c), Box::new(a), Box::new(b)));
        }
        let mut lhs = if min <= 3 && self.eat("not") { CspExpr::Not(Box::new(self.expr(3)?)) } else { self.unary()? };
        // Precedence climbing; operators of one level associate to the
        // left, and comparisons do not chain.
        while let Some(op) = self.operator().filter(|op| op.prec() >= min.max(1)) {
            self.at += 1;
            let rhs = self.expr(op.prec() + 1)?;
            lhs = CspExpr::Bin(op, Box::new(lhs), Box::new(rhs));
            if op.prec() == 4 && self.operator().is_some_and(|next| next.prec() == 4) {
                return None;
            }
        }
        Some(lhs)
    }

    /// The binary operator at the cursor.
    fn operator(&self) -> Option<CspBinOp> {
        CspBinOp::READ.into_iter().find(|op| self.is(op.text()))
    }

    fn unary(&mut self) -> Option<CspExpr> {
        if self.eat("-") {
            return Some(CspExpr::Neg(Box::new(self.unary()?)));
        }
        match self.next()? {
            Tok::Int(v) => Some(CspExpr::Int(v)),
            Tok::Op("(") => {
                let e = self.expr(0)?;
                self.expect(")")?;
                Some(e)
            }
            Tok::Ident(w) if w == "true" => Some(CspExpr::Bool(true)),
            Tok::Ident(w) if w == "false" => Some(CspExpr::Bool(false)),
            Tok::Ident(w) if is_keyword(&w) => None,
            Tok::Ident(w) => {
                if !self.eat("(") {
                    return Some(CspExpr::Name(w));
                }
                Some(CspExpr::Call(w, self.arguments()?))
            }
            Tok::Op(_) => None,
        }
    }
}

/// RoboTool 3's CSPm name of the model's function `name` declared in a file
/// of `package`: the package's path and the name joined by `_`
/// (`Mathematics_floor`; the name alone in the default package), as its
/// generated calls and instantiations write it (RT-2).
pub fn robotool_function_name(package: &[String], name: &str) -> String {
    package.iter().map(String::as_str).chain([name]).collect::<Vec<_>>().join("_")
}

/// The name under which a `csp` block's definition gives a call of the
/// model's function its value (RT-7), if a block defines one:
/// RoboTool 3's CSPm name (`robotool`, `Mathematics_floor`). When an
/// `Instantiations` block replaces the generated defaults (`replaced`) and
/// leaves that name undefined, RoboTool 3's script cannot load; then the
/// name as the call writes it (`floor`) is read, as the older RoboTool
/// generators whose FDR results are recorded called it (the Alpha
/// Algorithm's `floor(x) = x`) — `true` with it. Otherwise a block's `f`
/// is not the model's function: RoboTool 3's default (RT-2) holds.
pub fn block_definition<'a>(
    functions: &[CspFunction],
    robotool: Option<&'a str>,
    written: &'a str,
    replaced: bool,
) -> Option<(&'a str, bool)> {
    let defined = |n: &str| functions.iter().any(|c| c.name == n);
    match robotool {
        Some(r) if defined(r) => Some((r, false)),
        Some(r) if r != written && !replaced => None,
        _ if defined(written) => Some((written, robotool.is_some_and(|r| r != written))),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bin(op: CspBinOp, a: CspExpr, b: CspExpr) -> CspExpr {
        CspExpr::Bin(op, Box::new(a), Box::new(b))
    }
    fn name(n: &str) -> CspExpr {
        CspExpr::Name(n.into())
    }

    #[test]
    fn a_block_defines_a_function_by_robotool_s_name_first() {
        let f = |n: &str| CspFunction {
            name: n.into(),
            params: vec![],
            body: CspExpr::Int(0),
            range: TextRange::default(),
        };
        assert_eq!(robotool_function_name(&["Mathematics".into()], "floor"), "Mathematics_floor");
        assert_eq!(robotool_function_name(&[], "floor"), "floor");
        let (rt, written) = (Some("Mathematics_floor"), "floor");
        let both = [f("floor"), f("Mathematics_floor")];
        assert_eq!(block_definition(&both, rt, written, false), Some(("Mathematics_floor", false)));
        // The name the call writes: another function for RoboTool 3 …
        assert_eq!(block_definition(&[f("floor")], rt, written, false), None);
        // … read as the older generators did where RoboTool 3's script
        // cannot load.
        assert_eq!(block_definition(&[f("floor")], rt, written, true), Some(("floor", true)));
        assert_eq!(block_definition(&[f("floor")], Some("floor"), written, false), Some(("floor", false)));
        assert_eq!(block_definition(&[], rt, written, true), None);
    }

    #[test]
    fn definitions_of_the_corpus() {
        assert_eq!(parse_definition("random() = 0"), Some(("random".into(), vec![], CspExpr::Int(0))));
        assert_eq!(parse_definition("floor(x) = x "), Some(("floor".into(), vec![name("x")], name("x"))));
        assert_eq!(
            parse_definition("em2int(Emergency_E1) = 1"),
            Some(("em2int".into(), vec![name("Emergency_E1")], CspExpr::Int(1)))
        );
        let call = |x: &str| CspExpr::Call("em2int".into(), vec![name(x)]);
        assert_eq!(
            parse_definition("gte(x__,y__) = em2int(x__) >= em2int(y__)"),
            Some(("gte".into(), vec![name("x__"), name("y__")], bin(CspBinOp::Ge, call("x__"), call("y__"))))
        );
    }

    #[test]
    fn precedence_and_conditionals() {
        let (_, _, body) = parse_definition("f(a, b) = if a + b * 2 < 3 and not b == 1 then -a else a % 2").unwrap();
        assert_eq!(
            body,
            CspExpr::If(
                Box::new(bin(
                    CspBinOp::And,
                    bin(
                        CspBinOp::Lt,
                        bin(CspBinOp::Add, name("a"), bin(CspBinOp::Mul, name("b"), CspExpr::Int(2))),
                        CspExpr::Int(3)
                    ),
                    CspExpr::Not(Box::new(bin(CspBinOp::Eq, name("b"), CspExpr::Int(1)))),
                )),
                Box::new(CspExpr::Neg(Box::new(name("a")))),
                Box::new(bin(CspBinOp::Mod, name("a"), CspExpr::Int(2))),
            )
        );
    }

    #[test]
    fn what_is_not_a_definition() {
        for text in [
            "nametype core_nat = {0..5}",
            "x = 3",
            "P = a -> STOP",
            "f(x) = x -> STOP",
            "f(x) = {x}",
            "f(x) == 1",
            "if(x) = 1",
            "f(x = 1",
            "f(x) = ",
            "f(x) = 1 2",
            "f(x) = x < 1 < 2",
        ] {
            assert_eq!(parse_definition(text), None, "{text}");
        }
    }
}
