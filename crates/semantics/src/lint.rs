//! A structural checker of the generated CSPm, since FDR is not at hand:
//!
//! - on the printed text: brackets, `module … endmodule` and
//!   `let … within` are balanced;
//! - on the syntax tree: every name is defined once in its scope; every
//!   referenced name (process, function, channel, constructor, type) is
//!   defined, bound, exported by the module it is qualified with, or one
//!   of CSPm's built-ins; every channel is declared, with a type when it
//!   carries values, and prefixes give it as many fields as it declares.
//!
//! `csp` blocks copied from assertion files are opaque: only the names
//! they define are collected.

use std::collections::{HashMap, HashSet};

use crate::cspm::{AssertKind, Decl, Expr, Field, ReplOp};
use crate::export::OutFile;

/// CSPm built-ins the export uses.
const BUILTINS: &[&str] = &[
    "STOP",
    "SKIP",
    "RUN",
    "CHAOS",
    "Events",
    "Bool",
    "Int",
    "true",
    "false",
    "union",
    "inter",
    "diff",
    "member",
    "card",
    "empty",
    "seq",
    "set",
    "head",
    "tail",
    "length",
    "null",
    "prioritise",
    "timed_priority",
    "WAIT",
    "sbisim",
    "Char",
    "Set",
    "Seq",
    "concat",
    "elem",
];

/// What a global or module-level name is.
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// A channel with its declared field types (the names of the types).
    Channel(Vec<String>),
    /// A datatype, with its constructors' field counts.
    Datatype,
    /// A constructor with its number of fields.
    Ctor(usize),
    /// A process, function, value or type name.
    Value,
    /// A module, with its exported names.
    Module,
    /// Defined by a copied `csp` block (the user's CSPm).
    Raw,
}

#[derive(Default, Debug)]
struct Scope {
    names: HashMap<String, Kind>,
}

#[derive(Default)]
struct Checker {
    problems: Vec<String>,
    global: Scope,
    modules: HashMap<String, Scope>,
    /// The names each module exports.
    exports: HashMap<String, HashSet<String>>,
    /// Datatypes whose constructors carry fields (their events have more
    /// dots than the channel declares fields).
    deep_types: HashSet<String>,
}

/// Checks the files of an export; returns the problems found (none when
/// the output is well formed). Each file that includes others is checked
/// with them, as FDR would load it.
pub fn check(files: &[OutFile]) -> Vec<String> {
    let mut problems = Vec::new();
    for f in files {
        let mut c = Checker::default();
        c.balanced(&f.name, &f.text());
        problems.extend(c.problems);
    }
    let entries: Vec<&OutFile> =
        files.iter().filter(|f| f.decls.iter().any(|d| matches!(d, Decl::Include(_)))).collect();
    let groups: Vec<Vec<&OutFile>> = if entries.is_empty() {
        vec![files.iter().collect()]
    } else {
        entries
            .iter()
            .map(|e| {
                let mut g: Vec<&OutFile> = e
                    .decls
                    .iter()
                    .filter_map(|d| match d {
                        Decl::Include(n) => files.iter().find(|f| f.name == *n),
                        _ => None,
                    })
                    .collect();
                g.push(e);
                g
            })
            .collect()
    };
    for g in groups {
        let mut c = Checker::default();
        for f in &g {
            for d in &f.decls {
                c.declare_top(&f.name, d);
            }
        }
        for f in &g {
            for d in &f.decls {
                c.check_decl(&f.name, d, None, &[]);
            }
        }
        for p in c.problems {
            if !problems.contains(&p) {
                problems.push(p);
            }
        }
    }
    problems
}

fn chan_types(ty: &[Expr]) -> Vec<String> {
    ty.iter()
        .map(|t| match t {
            Expr::Name(n) => n.clone(),
            _ => String::new(),
        })
        .collect()
}

/// The names a line of a copied `csp` block defines at the top level
/// (heuristically: unindented `name =`, `name(…) =`, `channel a, b`,
/// `datatype T = A | B`, `nametype T`).
pub(crate) fn raw_defined(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    if line.starts_with([' ', '\t']) {
        return out;
    }
    let l = line.split("--").next().unwrap_or("").trim();
    let is_name = |n: &str| !n.is_empty() && n.chars().all(|x| x.is_alphanumeric() || x == '_' || x == '\'');
    if let Some(rest) = l.strip_prefix("channel ") {
        for n in rest.split(':').next().unwrap_or("").split(',') {
            if is_name(n.trim()) {
                out.push(n.trim().to_string());
            }
        }
    } else if let Some(rest) = l.strip_prefix("datatype ").or_else(|| l.strip_prefix("nametype ")) {
        let n = rest.split('=').next().unwrap_or("").trim();
        if is_name(n) {
            out.push(n.to_string());
        }
        if l.starts_with("datatype") {
            if let Some(ctors) = rest.split_once('=').map(|x| x.1) {
                for c in ctors.split('|') {
                    let c = c.trim().split('.').next().unwrap_or("").trim();
                    if is_name(c) {
                        out.push(c.to_string());
                    }
                }
            }
        }
    } else if let Some(i) = l.find('=') {
        if l[i..].starts_with("==") || i == 0 || l.starts_with("assert") || l.starts_with("include") {
            return out;
        }
        let head = l[..i].trim();
        let n = head.split('(').next().unwrap_or("").trim();
        if is_name(n) {
            out.push(n.to_string());
        }
    }
    out
}

/// A name raw text defines: at the top level, or in a `module` of its own
/// (then private, or exported after `exports`).
struct RawName {
    name: String,
    module: Option<String>,
    exported: bool,
}

fn raw_names(text: &str) -> Vec<RawName> {
    // The block's least indentation is its top level.
    let indent = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with("--"))
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    let mut out = Vec::new();
    // A module's names are its own (`robosim_defs.csp`'s `model_shifting`
    // defines `C2`, which a model's controller may be called too).
    let (mut module, mut exported) = (None::<String>, false);
    for l in text.lines().map(|l| if l.len() >= indent && l.is_char_boundary(indent) { &l[indent..] } else { l }) {
        let t = l.split("--").next().unwrap_or("").trim();
        if let Some(rest) = t.strip_prefix("module ") {
            let n = rest.split(|c: char| c == '(' || c.is_whitespace()).next().unwrap_or("");
            (module, exported) = (Some(n.to_string()), false);
            continue;
        }
        match t {
            "exports" if module.is_some() => exported = true,
            "endmodule" => (module, exported) = (None, false),
            _ => out.extend(raw_defined(l).into_iter().map(|name| RawName { name, module: module.clone(), exported })),
        }
    }
    out
}

impl Checker {
    fn problem(&mut self, file: &str, msg: String) {
        let m = format!("{file}: {msg}");
        if !self.problems.contains(&m) {
            self.problems.push(m);
        }
    }

    fn balanced(&mut self, file: &str, text: &str) {
        let mut stack: Vec<(char, usize)> = Vec::new();
        let (mut modules, mut lets) = (0i64, 0i64);
        for (ln, line) in text.lines().enumerate() {
            let code = line.split("--").next().unwrap_or("");
            let b = code.as_bytes();
            let mut i = 0;
            while i < b.len() {
                let rest = &code[i..];
                if rest.starts_with("[T=") || rest.starts_with("[F=") {
                    i += 3;
                    continue;
                }
                if rest.starts_with("[FD=") {
                    i += 4;
                    continue;
                }
                if rest.starts_with("|>") {
                    match stack.pop() {
                        Some(('[', _)) => {}
                        _ => self.problem(file, format!("line {}: `|>` does not close a `[|`", ln + 1)),
                    }
                    i += 2;
                    continue;
                }
                match b[i] as char {
                    c @ ('(' | '[' | '{') => stack.push((c, ln + 1)),
                    c @ (')' | ']' | '}') => {
                        let want = match c {
                            ')' => '(',
                            ']' => '[',
                            _ => '{',
                        };
                        match stack.pop() {
                            Some((o, _)) if o == want => {}
                            _ => self.problem(file, format!("line {}: unbalanced `{c}`", ln + 1)),
                        }
                    }
                    _ => {}
                }
                i += 1;
            }
            for w in code.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                match w {
                    "module" => modules += 1,
                    "endmodule" => modules -= 1,
                    "let" => lets += 1,
                    "within" => lets -= 1,
                    _ => {}
                }
            }
        }
        if let Some((c, l)) = stack.pop() {
            self.problem(file, format!("line {l}: `{c}` is never closed"));
        }
        if modules != 0 {
            self.problem(file, "`module` and `endmodule` do not match".into());
        }
        if lets != 0 {
            self.problem(file, "`let` and `within` do not match".into());
        }
    }

    fn define(&mut self, file: &str, module: Option<&str>, n: &str, k: Kind) {
        let scope = match module {
            Some(m) => self.modules.entry(m.to_string()).or_default(),
            None => &mut self.global,
        };
        if let Some(old) = scope.names.get(n) {
            // Copied `csp` blocks may define a name twice (clauses of a
            // function by patterns, or the user's own clashes): not ours.
            if *old == Kind::Raw && k == Kind::Raw {
                return;
            }
            let where_ = module.map(|m| format!(" in module {m}")).unwrap_or_default();
            let msg = format!("`{n}` is defined twice{where_}");
            self.problem(file, msg);
            return;
        }
        scope.names.insert(n.to_string(), k);
    }

    fn declare(&mut self, file: &str, d: &Decl, module: Option<&str>) {
        match d {
            Decl::Channel(names, ty) => {
                for n in names {
                    self.define(file, module, n, Kind::Channel(chan_types(ty)));
                }
            }
            Decl::Datatype(n, ctors) => {
                self.define(file, module, n, Kind::Datatype);
                if ctors.iter().any(|(_, f)| !f.is_empty()) {
                    self.deep_types.insert(n.clone());
                    if let Some(m) = module {
                        self.deep_types.insert(format!("{m}::{n}"));
                    }
                }
                for (c, f) in ctors {
                    self.define(file, module, c, Kind::Ctor(f.len()));
                }
            }
            Decl::Nametype(n, _) | Decl::Def(n, _, _) => self.define(file, module, n, Kind::Value),
            Decl::Module(n, private, exports) => {
                self.define(file, None, n, Kind::Module);
                for d in private.iter().chain(exports) {
                    self.declare(file, d, Some(n));
                }
                let mut names = HashSet::new();
                for d in exports {
                    match d {
                        Decl::Channel(ns, _) => names.extend(ns.iter().cloned()),
                        Decl::Datatype(x, ctors) => {
                            names.insert(x.clone());
                            names.extend(ctors.iter().map(|(c, _)| c.clone()));
                        }
                        Decl::Nametype(x, _) | Decl::Def(x, _, _) => {
                            names.insert(x.clone());
                        }
                        _ => {}
                    }
                }
                self.exports.insert(n.clone(), names);
            }
            Decl::Timed(_, decls) => {
                for d in decls {
                    self.declare(file, d, module);
                }
            }
            Decl::Raw(t, block) => {
                if !block.is_empty() {
                    self.define(file, module, block, Kind::Raw);
                }
                for r in raw_names(t) {
                    match (&r.module, module) {
                        (None, _) => self.define(file, module, &r.name, Kind::Raw),
                        (Some(m), outer) => {
                            let m = outer.map_or_else(|| m.clone(), |o| format!("{o}::{m}"));
                            self.define(file, Some(&m), &r.name, Kind::Raw);
                            if r.exported {
                                self.exports.entry(m).or_default().insert(r.name);
                            }
                        }
                    }
                }
            }
            _ => {}
        }
    }

    fn declare_top(&mut self, file: &str, d: &Decl) {
        self.declare(file, d, None);
    }

    /// Looks a name up: bound locals, the module's names, global names,
    /// qualified exports, built-ins.
    fn lookup(&self, n: &str, module: Option<&str>, bound: &[String]) -> Option<Kind> {
        if bound.iter().any(|b| b == n) {
            return Some(Kind::Value);
        }
        // `A_B::M::x`: the name `x` of module `A_B::M`.
        if let Some((m, x)) = n.rsplit_once("::") {
            if !self.exports.get(m)?.contains(x) {
                return None;
            }
            return self.modules.get(m)?.names.get(x).cloned();
        }
        if let Some(m) = module {
            if let Some(k) = self.modules.get(m).and_then(|s| s.names.get(n)) {
                return Some(k.clone());
            }
        }
        if let Some(k) = self.global.names.get(n) {
            return Some(k.clone());
        }
        BUILTINS.contains(&n).then_some(Kind::Value)
    }

    fn check_decl(&mut self, file: &str, d: &Decl, module: Option<&str>, bound: &[String]) {
        match d {
            Decl::Channel(_, ty) => {
                for t in ty {
                    self.check_expr(file, t, module, bound);
                }
            }
            Decl::Datatype(_, ctors) => {
                for (_, f) in ctors {
                    for t in f {
                        self.check_expr(file, t, module, bound);
                    }
                }
            }
            Decl::Nametype(_, e) => self.check_expr(file, e, module, bound),
            Decl::Def(_, params, e) => {
                let mut b = bound.to_vec();
                // A parameter may be a pattern (`R_rec.x1__.x2__`, `(a, b)`):
                // each of its names is bound.
                for p in params {
                    b.extend(
                        p.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '\''))
                            .filter(|w| !w.is_empty())
                            .map(String::from),
                    );
                }
                self.check_expr(file, e, module, &b);
            }
            Decl::Module(n, private, exports) => {
                for d in private.iter().chain(exports) {
                    self.check_decl(file, d, Some(n), bound);
                }
            }
            Decl::Timed(f, decls) => {
                self.check_expr(file, &Expr::Name(f.clone()), module, bound);
                for d in decls {
                    self.check_decl(file, d, module, bound);
                }
            }
            Decl::Assert(a) => {
                let es: Vec<&Expr> = match &a.kind {
                    AssertKind::Refines(_, x, y) => vec![x, y],
                    AssertKind::DeadlockFree(x, _)
                    | AssertKind::DivergenceFree(x, _)
                    | AssertKind::Deterministic(x, _) => {
                        vec![x]
                    }
                };
                for e in es.into_iter().chain(a.tau_priority.as_ref()) {
                    self.check_expr(file, e, module, bound);
                }
            }
            _ => {}
        }
    }

    fn check_name(&mut self, file: &str, n: &str, module: Option<&str>, bound: &[String]) -> Option<Kind> {
        let k = self.lookup(n, module, bound);
        if k.is_none() {
            let where_ = module.map(|m| format!(" (in module {m})")).unwrap_or_default();
            self.problem(file, format!("`{n}` is not defined{where_}"));
        }
        k
    }

    /// Checks an event (channel and fields) used in a prefix (`complete`)
    /// or as a (partial) event value.
    fn check_event(
        &mut self,
        file: &str,
        chan: &str,
        nfields: usize,
        complete: bool,
        module: Option<&str>,
        bound: &[String],
    ) {
        match self.check_name(file, chan, module, bound) {
            Some(Kind::Channel(types)) => {
                let deep = types.iter().any(|t| {
                    t.is_empty()
                        || t == "?"
                        || self.deep_types.contains(t)
                        || module.is_some_and(|m| self.deep_types.contains(&format!("{m}::{t}")))
                });
                if deep {
                    return;
                }
                let ok = if complete { nfields == types.len() } else { nfields <= types.len() };
                if !ok {
                    self.problem(
                        file,
                        format!("`{chan}` is declared with {} fields, used with {nfields}", types.len()),
                    );
                }
            }
            Some(Kind::Value) | None => {}
            Some(k) => {
                let what = match k {
                    Kind::Datatype => "datatype",
                    Kind::Ctor(_) => "constructor",
                    Kind::Module => "module",
                    _ => "name of another kind",
                };
                self.problem(file, format!("`{chan}` is used as a channel but is a {what}"))
            }
        }
    }

    fn check_expr(&mut self, file: &str, e: &Expr, module: Option<&str>, bound: &[String]) {
        match e {
            Expr::Int(_) | Expr::Bool(_) | Expr::Stop | Expr::Skip => {}
            Expr::Name(n) => {
                self.check_name(file, n, module, bound);
            }
            Expr::Dot(parts) => {
                if let Some(Expr::Name(head)) = parts.first() {
                    if let Some(Kind::Channel(_)) = self.lookup(head, module, bound) {
                        self.check_event(file, head, parts.len() - 1, false, module, bound);
                        for p in &parts[1..] {
                            self.check_expr(file, p, module, bound);
                        }
                        return;
                    }
                }
                for p in parts {
                    self.check_expr(file, p, module, bound);
                }
            }
            Expr::Call(f, args) => {
                self.check_name(file, f, module, bound);
                for a in args {
                    self.check_expr(file, a, module, bound);
                }
            }
            Expr::Not(x) | Expr::Neg(x) => self.check_expr(file, x, module, bound),
            Expr::Bin(_, a, b) | Expr::Range(a, b) | Expr::Guard(a, b) | Expr::Hide(a, b) => {
                self.check_expr(file, a, module, bound);
                self.check_expr(file, b, module, bound);
            }
            Expr::If(a, b, c) | Expr::Par(a, b, c) | Expr::Exception(a, b, c) => {
                for x in [a, b, c] {
                    self.check_expr(file, x, module, bound);
                }
            }
            Expr::Let(decls, body) => {
                let mut b = bound.to_vec();
                let mut seen = HashSet::new();
                for d in decls {
                    if let Decl::Def(n, _, _) = d {
                        if !seen.insert(n.clone()) {
                            self.problem(file, format!("`{n}` is defined twice in a `let`"));
                        }
                        b.push(n.clone());
                    }
                }
                for d in decls {
                    self.check_decl(file, d, module, &b);
                }
                self.check_expr(file, body, module, &b);
            }
            Expr::Set(items)
            | Expr::Events(items)
            | Expr::SeqLit(items)
            | Expr::Tuple(items)
            | Expr::Nary(_, items) => {
                for i in items {
                    self.check_expr(file, i, module, bound);
                }
            }
            Expr::Prefix(c, fields, body) => {
                self.check_event(file, c, fields.len(), true, module, bound);
                let mut b = bound.to_vec();
                for f in fields {
                    match f {
                        Field::Dot(x) | Field::Out(x) => self.check_expr(file, x, module, &b),
                        Field::In(x) => b.push(x.clone()),
                        Field::InFrom(x, s) => {
                            self.check_expr(file, s, module, &b);
                            b.push(x.clone());
                        }
                    }
                }
                self.check_expr(file, body, module, &b);
            }
            Expr::Rename(p, pairs, gens) => {
                self.check_expr(file, p, module, bound);
                let mut b = bound.to_vec();
                for (x, s) in gens {
                    self.check_expr(file, s, module, &b);
                    b.push(x.clone());
                }
                for (x, y) in pairs {
                    self.check_expr(file, x, module, &b);
                    self.check_expr(file, y, module, &b);
                }
            }
            Expr::SetComp(e, gens) => {
                let mut b = bound.to_vec();
                for (x, s) in gens {
                    self.check_expr(file, s, module, &b);
                    b.push(x.clone());
                }
                self.check_expr(file, e, module, &b);
            }
            Expr::Repl(op, gens, body) => {
                if let ReplOp::Par(a) = op {
                    self.check_expr(file, a, module, bound);
                }
                let mut b = bound.to_vec();
                for (x, s) in gens {
                    self.check_expr(file, s, module, &b);
                    b.push(x.clone());
                }
                self.check_expr(file, body, module, &b);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cspm::{name, prefix};

    fn file(decls: Vec<Decl>) -> OutFile {
        OutFile { name: "t.csp".into(), title: "t".into(), decls }
    }

    #[test]
    fn finds_undefined_and_duplicate_names_and_wrong_arity() {
        let f = file(vec![
            Decl::Channel(vec!["a".into()], vec![name("Bool")]),
            Decl::Def("P".into(), vec![], prefix("a", vec![], name("Q"))),
            Decl::Def("P".into(), vec![], Expr::Stop),
        ]);
        let p = check(&[f]);
        assert!(p.iter().any(|m| m.contains("`Q` is not defined")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("`P` is defined twice")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("declared with 1 fields, used with 0")), "{p:?}");
    }

    #[test]
    fn accepts_bound_names_and_module_exports() {
        let f = file(vec![
            Decl::Module(
                "M".into(),
                vec![Decl::Channel(vec!["c".into()], vec![name("Bool")])],
                vec![Decl::Def("D__".into(), vec!["x".into()], prefix("c", vec![Field::In("y".into())], name("SKIP")))],
            ),
            Decl::Def("Q".into(), vec![], Expr::Call("M::D__".into(), vec![Expr::Int(1)])),
        ]);
        assert_eq!(check(&[f]), Vec::<String>::new());
        let bad = file(vec![Decl::Def("Q".into(), vec![], Expr::Call("M::c".into(), vec![]))]);
        assert!(!check(&[bad]).is_empty());
    }

    #[test]
    fn a_raw_module_s_names_are_its_own() {
        // As `robosim_defs.csp`'s `model_shifting`: its private `C2` is
        // not the model's controller `C2`; its exports are qualified.
        let raw = "module model_shifting(Sigma)\nC2(P) = P\nexports\nTT(P) = C2(P)\nendmodule\n";
        let f = file(vec![
            Decl::Raw(raw.into(), String::new()),
            Decl::Module("C2".into(), vec![], vec![Decl::Def("D__".into(), vec![], Expr::Stop)]),
            Decl::Def("Q".into(), vec![], Expr::Call("model_shifting::TT".into(), vec![Expr::Stop])),
        ]);
        assert_eq!(check(&[f]), Vec::<String>::new());
        let private = file(vec![
            Decl::Raw(raw.into(), String::new()),
            Decl::Def("Q".into(), vec![], Expr::Call("model_shifting::C2".into(), vec![Expr::Stop])),
        ]);
        let p = check(&[private]);
        assert!(p.iter().any(|m| m.contains("model_shifting::C2")), "{p:?}");
    }
}
