//! A compact text form of the model, for snapshot tests and debugging.

use std::fmt::Write as _;

use super::*;
use crate::types::Ty;
use crate::Db;

/// The model of a file as indented text (ranges as `@start..end`).
pub fn render(db: &dyn Db, model: &FileModel) -> String {
    let mut p = Printer { db, out: String::new(), depth: 0 };
    for (_, item) in &model.items {
        p.item(item);
    }
    p.out
}

struct Printer<'a> {
    db: &'a dyn Db,
    out: String,
    depth: usize,
}

fn at(r: TextRange) -> String {
    format!("@{}..{}", u32::from(r.start()), u32::from(r.end()))
}

impl Printer<'_> {
    fn line(&mut self, s: impl AsRef<str>) {
        let _ = writeln!(self.out, "{}{}", "  ".repeat(self.depth), s.as_ref());
    }

    fn nested(&mut self, f: impl FnOnce(&mut Self)) {
        self.depth += 1;
        f(self);
        self.depth -= 1;
    }

    fn loc(&self, l: Option<ItemLoc>) -> String {
        match l {
            Some(l) => format!("-> {}#{}", l.file.path(self.db), l.index),
            None => "-> ?".into(),
        }
    }

    fn ty(&self, t: &Option<TyRef>) -> String {
        match t {
            Some(t) => ty_text(&t.ty),
            None => "-".into(),
        }
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Machine(b) => self.behaviour("stm", b),
            Item::Operation(b) => self.behaviour("operation", b),
            Item::Controller(c) => self.controller(c),
            Item::Module(m) => {
                self.line(format!("module {} {}", m.name, at(m.range)));
                self.nested(|p| {
                    p.cycle(&m.cycle);
                    for pl in &m.platforms {
                        match &pl.def {
                            Definition::Inline(x) => p.platform("platform", x),
                            Definition::Ref { path, target } => {
                                p.line(format!("rref {} = {} {}", pl.name, path.join("::"), p.loc(*target)))
                            }
                        }
                    }
                    for c in &m.controllers {
                        match &c.def {
                            Definition::Inline(x) => p.controller(x),
                            Definition::Ref { path, target } => {
                                p.line(format!("cref {} = {} {}", c.name, path.join("::"), p.loc(*target)))
                            }
                        }
                    }
                    for s in &m.machines {
                        match &s.def {
                            Definition::Inline(x) => p.behaviour("stm", x),
                            Definition::Ref { path, target } => {
                                p.line(format!("sref {} = {} {}", s.name, path.join("::"), p.loc(*target)))
                            }
                        }
                    }
                    p.connections(&m.connections);
                });
            }
            Item::Platform(x) => self.platform("platform", x),
            Item::Interface(x) => self.platform("interface", x),
            Item::Enumeration(n, lits) => self.line(format!("enumeration {n} {{{}}}", lits.join(", "))),
            Item::Record(n, fields) => {
                let fs: Vec<String> = fields.iter().map(|f| format!("{}: {}", f.name, self.ty(&f.ty))).collect();
                self.line(format!("datatype {n} {{{}}}", fs.join(", ")))
            }
            Item::PrimitiveType(n) => self.line(format!("type {n}")),
            Item::Function(f) => {
                let ps: Vec<String> = f.params.iter().map(|p| format!("{}: {}", p.name, self.ty(&p.ty))).collect();
                self.line(format!("function {}({}): {} {}", f.name, ps.join(", "), self.ty(&f.result), at(f.range)));
                self.nested(|p| {
                    for e in &f.preconditions {
                        p.line(format!("precondition {}", expr_text(e)));
                    }
                    for e in &f.postconditions {
                        p.line(format!("postcondition {}", expr_text(e)));
                    }
                });
            }
            Item::Other => self.line("other"),
        }
    }

    fn cycle(&mut self, c: &Option<crate::cycle::CycleInfo>) {
        if let Some(c) = c {
            match c.joint {
                Some(j) => self.line(format!("cycle {:?}, with its parts {j:?}", c.own)),
                None => self.line(format!("cycle {:?}", c.own)),
            }
        }
    }

    fn connections(&mut self, cs: &[Connection]) {
        for c in cs {
            let flags = format!("{}{}", if c.is_async { " async" } else { "" }, if c.is_mult { " mult" } else { "" });
            let end = |e: End| match e {
                End::This => "this".to_string(),
                End::Platform(i) => format!("platform {i}"),
                End::Controller(i) => format!("controller {i}"),
                End::Machine(i) => format!("machine {i}"),
                End::Unknown => "?".into(),
            };
            self.line(format!(
                "connection {}.{} ({}) -> {}.{} ({}){flags} {}",
                c.from,
                c.efrom,
                end(c.from_end),
                c.to,
                c.eto,
                end(c.to_end),
                at(c.range)
            ));
        }
    }

    fn controller(&mut self, c: &Controller) {
        self.line(format!("controller {} {}", c.name, at(c.range)));
        self.nested(|p| {
            p.cycle(&c.cycle);
            p.decls(&c.decls);
            for (what, list) in [("sref", &c.machines), ("opref", &c.operations)] {
                for m in list {
                    match &m.def {
                        Definition::Inline(b) => p.behaviour(if what == "sref" { "stm" } else { "operation" }, b),
                        Definition::Ref { path, target } => {
                            p.line(format!("{what} {} = {} {}", m.name, path.join("::"), p.loc(*target)))
                        }
                    }
                }
            }
            p.connections(&c.connections);
        });
    }

    fn platform(&mut self, what: &str, x: &Platform) {
        self.line(format!("{what} {} {}", x.name, at(x.range)));
        self.nested(|p| p.decls(&x.decls));
    }

    fn decls(&mut self, d: &Decls) {
        for u in &d.uses {
            self.line(format!("{} {} {}", u.kind.keyword(), u.path.join("::"), self.loc(u.target)));
        }
        for decl in &d.decls {
            match decl {
                Decl::Vars { is_const, vars, .. } => {
                    for v in vars {
                        let init = v.init.as_ref().map(|e| format!(" = {}", expr_text(e))).unwrap_or_default();
                        let kw = if *is_const { "const" } else { "var" };
                        self.line(format!("{kw} {}: {}{init}", v.name, self.ty(&v.ty)));
                    }
                }
                Decl::Clock { name, .. } => self.line(format!("clock {name}")),
                Decl::Event { name, ty, broadcast, .. } => {
                    let b = if *broadcast { "broadcast " } else { "" };
                    self.line(format!("{b}event {name}: {}", self.ty(ty)))
                }
                Decl::OperationSig { name, params, .. } => {
                    let ps: Vec<String> = params.iter().map(|p| format!("{}: {}", p.name, self.ty(&p.ty))).collect();
                    self.line(format!("operation {name}({})", ps.join(", ")))
                }
                Decl::Nested { kind, name, .. } => self.line(format!("{kind:?} {name}")),
            }
        }
    }

    fn behaviour(&mut self, what: &str, b: &Behaviour) {
        let ps: Vec<String> = b.params.iter().map(|p| format!("{}: {}", p.name, self.ty(&p.ty))).collect();
        let ps = if ps.is_empty() { String::new() } else { format!("({})", ps.join(", ")) };
        self.line(format!("{what} {}{ps} {}", b.name, at(b.range)));
        self.nested(|p| {
            p.cycle(&b.cycle);
            p.decls(&b.decls);
            for (io, d) in &b.contexts {
                p.line(format!("{} context", if *io == crate::defs::Io::Input { "input" } else { "output" }));
                p.nested(|p| p.decls(d));
            }
            if !b.literals.is_empty() {
                let ls: Vec<String> = b.literals.iter().map(|l| l.to_string()).collect();
                p.line(format!("literals {}", ls.join(" ")));
            }
            p.region(&b.region);
        });
    }

    fn region(&mut self, r: &Region) {
        for n in &r.nodes {
            self.line(format!("{} {} {}", format!("{:?}", n.kind).to_lowercase(), n.name, at(n.name_range)));
            self.nested(|p| {
                for (what, a) in [("entry", &n.entry), ("during", &n.during), ("exit", &n.exit)] {
                    if let Some(a) = a {
                        p.line(format!("{what} {}", a.stmt.as_ref().map(stmt_text).unwrap_or_default()));
                    }
                }
                p.region(&n.region);
            });
        }
        for t in &r.transitions {
            let node = |n: &Option<String>, i: Option<usize>| {
                format!("{}{}", n.as_deref().unwrap_or(""), if i.is_some() { "" } else { "?" })
            };
            let mut s = format!(
                "transition {} {}: {} -> {}",
                t.name,
                at(t.name_range),
                node(&t.source, t.source_node),
                node(&t.target, t.target_node)
            );
            if let Some(c) = &t.trigger {
                let _ = write!(s, " trigger {}", comm_text(c));
            }
            if t.exec {
                s.push_str(" exec");
            }
            for (c, _) in &t.resets {
                let _ = write!(s, " #{c}");
            }
            if let Some(c) = &t.condition {
                let e = if c.is_else { "else".into() } else { c.expr.as_ref().map(expr_text).unwrap_or_default() };
                let _ = write!(s, " [{e}]");
            }
            if let Some((_, d)) = &t.deadline {
                let _ = write!(s, " <{{{}}}", d.as_ref().map(expr_text).unwrap_or_default());
            }
            if let Some(a) = &t.action {
                let _ = write!(s, " / {}", a.stmt.as_ref().map(stmt_text).unwrap_or_default());
            }
            self.line(s);
        }
    }
}

/// A type in words.
pub(super) fn ty_text(t: &Ty) -> String {
    match t {
        Ty::Named(_, n, _) => n.clone(),
        Ty::Set(a) => format!("Set({})", ty_text(a)),
        Ty::Seq(a) => format!("Seq({})", ty_text(a)),
        Ty::Product(v) => v.iter().map(ty_text).collect::<Vec<_>>().join("*"),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn res_mark(res: &Option<crate::resolve::Target>) -> &'static str {
    if res.is_some() {
        ""
    } else {
        "?"
    }
}

fn list(xs: &[Expr]) -> String {
    xs.iter().map(expr_text).collect::<Vec<_>>().join(", ")
}

/// An expression, fully parenthesised; an unresolved name is marked `?`.
pub(super) fn expr_text(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Int(v) => v.map_or("<large>".into(), |v| v.to_string()),
        ExprKind::Real(t) => t.clone(),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Name { name, res } => format!("{name}{}", res_mark(res)),
        ExprKind::EnumLiteral { path, literal, enumeration } => {
            format!("{}{}::{literal}", path.join("::"), if enumeration.is_some() { "" } else { "?" })
        }
        ExprKind::SimRef { path, input, sync } => {
            let mut s = format!("${}", path.join("::"));
            if let Some((v, _)) = input {
                let _ = write!(s, "?{}", v.join("::"));
            }
            if let Some(v) = sync {
                let _ = write!(s, ".{}", expr_text(v));
            }
            s
        }
        ExprKind::Since(c) => format!("since({c})"),
        ExprKind::SinceEntry(s) => format!("sinceEntry({})", s.join("::")),
        ExprKind::Unary(op, x) => format!("({op:?} {})", expr_text(x)),
        ExprKind::Binary(op, a, b) => format!("({} {op:?} {})", expr_text(a), expr_text(b)),
        ExprKind::If(c, a, b) => format!("(if {} then {} else {})", expr_text(c), expr_text(a), expr_text(b)),
        ExprKind::Field(b, f) => format!("{}.{f}", expr_text(b)),
        ExprKind::Index(b, ix) => format!("{}[{}]", expr_text(b), list(ix)),
        ExprKind::Call { function, res, args } => format!("{function}{}({})", res_mark(res), list(args)),
        ExprKind::Tuple(xs) => format!("({})", list(xs)),
        ExprKind::Set(xs) => format!("{{{}}}", list(xs)),
        ExprKind::Seq(xs) => format!("<{}>", list(xs)),
        ExprKind::Record(fs) => {
            let fs: Vec<String> = fs.iter().map(|(n, x)| format!("{n} = {}", expr_text(x))).collect();
            format!("(|{}|)", fs.join(", "))
        }
        ExprKind::Interval { lo, hi, open_lo, open_hi } => format!(
            "{}{}, {}{}",
            if *open_lo { "(" } else { "[" },
            expr_text(lo),
            expr_text(hi),
            if *open_hi { ")" } else { "]" }
        ),
        ExprKind::SetRange(a, b) => format!("{{{} to {}}}", expr_text(a), expr_text(b)),
        ExprKind::Result => "result".into(),
        ExprKind::Missing => "<missing>".into(),
        ExprKind::Other(k) => format!("<{k}>"),
    }
}

fn comm_text(c: &Comm) -> String {
    let mut s = format!("{}{}", c.event, res_mark(&c.res));
    if c.guard.is_some() {
        s.push_str("[|…|]");
    }
    match &c.part {
        Some(CommPart::Sync(v)) => s += &format!(".{}", v.as_ref().map(expr_text).unwrap_or_default()),
        Some(CommPart::Output(v)) => s += &format!("!{}", v.as_ref().map(expr_text).unwrap_or_default()),
        Some(CommPart::Input(v, _)) => s += &format!("?{}", v.join("::")),
        None => {}
    }
    s
}

/// A statement on one line.
pub(super) fn stmt_text(s: &Stmt) -> String {
    match &s.kind {
        StmtKind::Skip => "skip".into(),
        StmtKind::Seq(ss) => ss.iter().map(stmt_text).collect::<Vec<_>>().join("; "),
        StmtKind::Assign { target, res, selectors, value } => {
            let mut t = format!("{}{}", target.join("::"), res_mark(res));
            for sel in selectors {
                match sel {
                    Selector::Field(f, _) => t += &format!(".{f}"),
                    Selector::Index(ix, _) => t += &format!("[{}]", list(ix)),
                }
            }
            format!("{t} = {}", expr_text(value))
        }
        StmtKind::ClockReset(c) => format!("#{c}"),
        StmtKind::If(c, a, b) => match b {
            Some(b) => format!("if {} then {} else {} end", expr_text(c), stmt_text(a), stmt_text(b)),
            None => format!("if {} then {} end", expr_text(c), stmt_text(a)),
        },
        StmtKind::Comm(c) => comm_text(c),
        StmtKind::Call { name, args } => format!("{}({})", name.join("::"), list(args)),
        StmtKind::SimCall { name, args } => format!("${}({})", name.join("::"), list(args)),
        StmtKind::Output(n, v) => match v {
            Some(v) => format!("${}!{}", n.join("::"), expr_text(v)),
            None => format!("${}", n.join("::")),
        },
        StmtKind::Wait(e) => format!("wait({})", expr_text(e)),
        StmtKind::Exec => "exec".into(),
        StmtKind::Timed(b, d) => format!(
            "({}) <{{{}}}",
            b.as_deref().map(stmt_text).unwrap_or_default(),
            d.as_ref().map(expr_text).unwrap_or_default()
        ),
        StmtKind::Par(ss) => format!("({})", ss.iter().map(stmt_text).collect::<Vec<_>>().join(" || ")),
        StmtKind::Other(k) => format!("<{k}>"),
    }
}
