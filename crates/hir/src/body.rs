//! Name resolution inside behaviour: expressions, statements and
//! communications (catalogue §2.18). Plain names see bound variables,
//! parameters, the context's variables and constants (RoboSim machines:
//! not their I/O variables), functions and enumeration literals; `$` names
//! see the machine's inputs and outputs; calls see the operations of
//! required and provided interfaces. A name that exists with the other
//! `$` discipline gets RS:SM6 instead of a plain "cannot resolve".

use crate::defs::name_text as text_of;
use robosim_syntax::{FileKind, SyntaxKind::*, SyntaxNode, TextRange, TextSize};
use rowan::Language as _;

use crate::defs::{file_defs, DefKind, FileDefs, Io, UseKind};
use crate::element::Unit;
use crate::index::resolve_item;
use crate::resolve::{ctx_members, enclosing, Ctx, Member, RefKind, ResolveProblem, ResolvedRef, Target};
use crate::{parse, Db, File, Workspace};

/// References inside behaviour, and their problems.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct BodyResolution {
    /// Every resolved or unresolved name.
    pub refs: Vec<ResolvedRef>,
    /// Problems (codes LNK-01, RS:SM6, RS-IO-03, RS-IO-04, RC-STMT-01, RC-STMT-06).
    pub problems: Vec<ResolveProblem>,
}

/// Resolves the names used in the behaviour of `file`.
#[salsa::tracked(returns(ref))]
pub fn body_resolution(db: &dyn Db, ws: Workspace, file: File) -> BodyResolution {
    if file.kind(db).is_assertions() {
        return BodyResolution::default();
    }
    let root = parse(db, file).syntax_node();
    let r = Body::new(db, ws, file, file_defs(db, file), None);
    r.resolve(&root, crate::walk::file_nodes(db, file))
}

/// [`body_resolution`] of one element.
pub(crate) fn resolve_body(db: &dyn Db, ws: Workspace, unit: &Unit<'_>) -> BodyResolution {
    if unit.file.kind(db).is_assertions() {
        return BodyResolution::default();
    }
    Body::new(db, ws, unit.file, unit.defs, Some(unit)).resolve(&unit.root, unit.nodes)
}

/// The kinds of node [`Body::visit`] resolves names of.
const VISITED: &[robosim_syntax::SyntaxKind] = &[
    REF_EXPR,
    SIM_REF_EXPR,
    ENUM_LITERAL_EXPR,
    ASSIGN_STMT,
    CALL_STMT,
    SIM_CALL_STMT,
    OUTPUT_COMM_STMT,
    COMM_STMT,
    SINCE_ENTRY_EXPR,
    COMM_INPUT,
];

/// The references in behaviour whose node covers `offset`: those of
/// [`body_resolution`] there, without resolving the rest of the file. A
/// hover or a jump right after a keystroke needs one name, and resolving
/// every name of a large file would make it wait.
pub fn body_refs_at(db: &dyn Db, ws: Workspace, file: File, offset: TextSize) -> Vec<ResolvedRef> {
    if file.kind(db).is_assertions() {
        return Vec::new();
    }
    // Within the element at `offset`, on its own tree: a keystroke
    // elsewhere does not put the file's definitions together again.
    if let Some((element, at)) = crate::element::element_at(db, file, offset) {
        let unit = crate::element::Unit::of_element(db, element);
        let at = TextSize::from(at);
        let mut refs = refs_around(Body::new(db, ws, file, unit.defs, Some(&unit)), &unit.root, offset - at);
        for r in &mut refs {
            r.range += at;
        }
        return refs;
    }
    refs_around(Body::new(db, ws, file, file_defs(db, file), None), &parse(db, file).syntax_node(), offset)
}

/// [`body_refs_at`] on the tree `root` and the definitions `r` reads.
fn refs_around(mut r: Body<'_>, root: &SyntaxNode, offset: TextSize) -> Vec<ResolvedRef> {
    // One name needs the members of one context, not those of the file.
    r.one_context = true;
    // Past the end (a stale position from an editor): nothing is there.
    if !root.text_range().contains_inclusive(offset) {
        return Vec::new();
    }
    // Every reference lies inside the node that resolves it, and resolving
    // a node depends on nothing visited before it: the ancestors of the
    // tokens at `offset` (both, at a boundary) give exactly the references
    // covering it. They are visited in preorder, as `body_resolution` does,
    // so that references with the same range come in the same order.
    let mut order: Vec<SyntaxNode> = Vec::new();
    for token in root.token_at_offset(offset) {
        let chain: Vec<SyntaxNode> = token.parent_ancestors().take_while(|n| !order.contains(n)).collect();
        order.extend(chain.into_iter().rev());
    }
    for n in &order {
        r.visit(n);
    }
    r.out.refs
}

struct Body<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    defs: &'a FileDefs,
    rs: bool,
    out: BodyResolution,
    /// Members per context, shared: a body asks for the same few contexts
    /// once per name, and cloning the lists dominated resolution.
    members_cache: rustc_hash::FxHashMap<crate::defs::DefId, std::rc::Rc<[Member]>>,
    /// Whether to compute members for the contexts asked for only, rather
    /// than read them from the whole file's (memoised) members.
    one_context: bool,
    /// The element resolved, if only one: members come from its own.
    unit: Option<&'a Unit<'a>>,
}

fn qualified(n: &SyntaxNode) -> Option<(Vec<String>, TextRange)> {
    let q = n.children().find(|c| c.kind() == QUALIFIED_NAME)?;
    // The tokens from the green tree: no cursor per token.
    let segs = q
        .green()
        .children()
        .filter_map(|e| e.into_token())
        .filter(|t| robosim_syntax::RoboLang::kind_from_raw(t.kind()) == IDENT)
        .map(|t| t.text().trim_start_matches('^').to_string())
        .collect();
    Some((segs, q.text_range()))
}

/// Names bound by an enclosing expression (quantifiers, lambda, set
/// comprehension, `the`, `let`) of `node`.
fn bound_names(node: &SyntaxNode) -> Vec<String> {
    let mut out = Vec::new();
    for a in node.ancestors().skip(1) {
        // The kinds `walk::binds` lists.
        match a.kind() {
            FORALL_EXPR | EXISTS_EXPR | LAMBDA_EXPR | THE_EXPR | SET_COMP_EXPR => {
                for b in a.children().filter(|c| c.kind() == BINDERS).flat_map(|bs| bs.children()) {
                    if b.kind() == BINDER {
                        if let Some(n) = b.children().find(|c| c.kind() == NAME) {
                            out.push(text_of(&n));
                        }
                    }
                }
            }
            LET_EXPR => {
                for d in a.children().filter(|c| c.kind() == LET_DECL) {
                    if let Some(n) = d.children().find(|c| c.kind() == NAME) {
                        out.push(text_of(&n));
                    }
                }
            }
            _ => {}
        }
    }
    out
}

impl<'a> Body<'a> {
    fn new(db: &'a dyn Db, ws: Workspace, file: File, defs: &'a FileDefs, unit: Option<&'a Unit<'a>>) -> Body<'a> {
        Body {
            db,
            ws,
            file,
            defs,
            rs: file.kind(db) == FileKind::RoboSim,
            out: BodyResolution::default(),
            members_cache: Default::default(),
            one_context: false,
            unit,
        }
    }

    /// Resolves the names of the nodes below `root` that `table` records.
    fn resolve(mut self, root: &SyntaxNode, table: &crate::walk::NodeTable) -> BodyResolution {
        // Only the nodes `visit` resolves, from the node table: a cursor
        // for every node of a large file cost more than resolving the
        // names. Names outside binding expressions (nearly all) need no
        // cursor: their green node says everything `name_expr` reads.
        let green_ok = |k, bound: bool| k == REF_EXPR && !bound;
        for found in table.found(root, VISITED, false, green_ok) {
            match found {
                crate::walk::Found::Node(n) => self.visit(&n),
                crate::walk::Found::Green(g, range) => self.name_expr_green(&g, range.start()),
            }
        }
        self.out
    }

    /// Resolves the names `n` itself introduces (not those of its children);
    /// [`VISITED`] lists the kinds it handles.
    fn visit(&mut self, n: &SyntaxNode) {
        match n.kind() {
            REF_EXPR => self.name_expr(n),
            SIM_REF_EXPR => self.dollar_expr(n),
            ENUM_LITERAL_EXPR => self.enum_literal(n),
            ASSIGN_STMT => self.assignment(n),
            CALL_STMT => self.call(n, false),
            SIM_CALL_STMT => self.call(n, true),
            OUTPUT_COMM_STMT => self.output(n),
            COMM_STMT => self.communication(n),
            SINCE_ENTRY_EXPR => self.since_entry(n),
            COMM_INPUT => self.input_variable(n),
            _ => {}
        }
    }

    fn push(&mut self, range: TextRange, text: String, kind: RefKind, target: Option<Target>) {
        self.out.refs.push(ResolvedRef { range, text, kind, target });
    }

    fn problem(&mut self, code: &'static str, range: TextRange, message: String) {
        self.out.problems.push(ResolveProblem { code, range, message });
    }

    /// The context whose members a name at `range` sees.
    fn context(&self, range: TextRange) -> Option<crate::defs::DefId> {
        let inner = self.defs.innermost(range)?;
        enclosing(self.defs, inner, crate::resolve::MEMBER_CONTEXTS)
    }

    fn members(&mut self, ctx: crate::defs::DefId) -> std::rc::Rc<[Member]> {
        if let Some(m) = self.members_cache.get(&ctx) {
            return m.clone();
        }
        let ctx_def = Ctx::Local(self.file, ctx);
        // An element's members are memoised per element (what an edit
        // elsewhere leaves alone); a file's, for the whole file.
        let mut m = if let Some(unit) = self.unit {
            unit.members(self.db, self.ws, ctx).into_owned()
        } else if self.one_context {
            crate::resolve::compute_members(self.db, self.ws, ctx_def)
        } else {
            ctx_members(self.db, self.ws, ctx_def).into_owned()
        };
        // Parameters of operations and functions.
        for (pid, p) in self.defs.children(Some(ctx)) {
            if p.kind == DefKind::Parameter {
                m.push(Member {
                    name: p.name.clone(),
                    kind: DefKind::Parameter,
                    io: None,
                    via: None,
                    ty: None,
                    target: Target::Def(self.file, pid),
                    broadcast: false,
                    params: Vec::new(),
                });
            }
        }
        let m: std::rc::Rc<[Member]> = m.into();
        self.members_cache.insert(ctx, m.clone());
        m
    }

    /// Global names usable in expressions: functions and enumeration literals.
    fn global_value(&self, name: &str) -> Option<Target> {
        let path = [name.to_string()];
        if let Some(l) = resolve_item(self.db, self.ws, self.file, &path, |k| k == DefKind::Function).first() {
            return Some(Target::Item(*l));
        }
        // Bare enumeration literals of any visible enumeration.
        let index = crate::index::index_for(self.db, self.ws, self.file);
        let here = crate::index::file_summary(self.db, self.file);
        for (full, locs) in &index.items {
            let pkg = &full[..full.len() - 1];
            let visible = pkg == here.package.as_slice()
                || pkg.is_empty()
                || here.imports.iter().any(|(p, w)| (*w && p.as_slice() == pkg) || p.as_slice() == full.as_slice());
            if !visible {
                continue;
            }
            for l in locs {
                let s = l.summary(self.db);
                if s.kind == DefKind::Enumeration {
                    if let Some(i) = s.members.iter().position(|m| m.kind == DefKind::EnumLiteral && m.name == name) {
                        return Some(Target::Member(*l, i as u32));
                    }
                }
            }
        }
        None
    }

    fn name_expr(&mut self, n: &SyntaxNode) {
        let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = text_of(&r);
        let bound = bound_names(n).contains(&name);
        self.name(name, r.text_range(), bound);
    }

    /// [`Body::name_expr`] for a `REF_EXPR` at `offset` that no binding
    /// expression encloses, from its green node.
    fn name_expr_green(&mut self, n: &rowan::GreenNodeData, mut offset: TextSize) {
        for child in n.children() {
            let len = child.text_len();
            if let rowan::NodeOrToken::Node(c) = child {
                if robosim_syntax::RoboLang::kind_from_raw(c.kind()) == NAME_REF {
                    self.name(crate::defs::green_name_text(c), TextRange::at(offset, len), false);
                    return;
                }
            }
            offset += len;
        }
    }

    /// Resolves the name `name` at `range` of a `REF_EXPR`, `bound` by an
    /// enclosing expression or not.
    fn name(&mut self, name: String, range: TextRange, bound: bool) {
        if bound {
            self.push(range, name, RefKind::Type, None);
            return;
        }
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        let local = members.iter().find(|m| {
            m.name == name
                && matches!(m.kind, DefKind::Variable | DefKind::Constant | DefKind::Parameter)
                && (!self.rs || m.io.is_none())
        });
        if let Some(m) = local {
            let t = m.target;
            self.push(range, name, RefKind::Type, Some(t));
            return;
        }
        if let Some(t) = self.global_value(&name) {
            self.push(range, name, RefKind::Type, Some(t));
            return;
        }
        self.push(range, name.clone(), RefKind::Type, None);
        if self.rs {
            if let Some(m) = members.iter().find(|m| m.name == name && m.io.is_some()) {
                let what = io_desc(m);
                self.problem("RS:SM6", range, format!("{what} `{name}` must be written `${name}`"));
                return;
            }
        }
        if members.iter().any(|m| m.name == name && m.kind == DefKind::Event) {
            self.problem(
                "LNK-01",
                range,
                format!("`{name}` is an event: events are not values (test an input in a RoboSim condition with `${name}`, or receive a value with `{name}?x`)"),
            );
            return;
        }
        if let Some(pkg) = self.external_import() {
            self.problem("LNK-03", range, format!("`{name}` is not declared in the workspace: it may come from `{pkg}`, which no file here declares (a physical model?); load that package to check it"));
            return;
        }
        self.problem("LNK-01", range, format!("cannot resolve `{name}`: no variable, constant, parameter, function or enumeration literal of that name is in scope"));
    }

    /// An import of the file that names no package or element of the
    /// workspace: names it brings cannot be checked (RoboSim models import
    /// the packages of their physical models, written in another language).
    fn external_import(&self) -> Option<String> {
        self.defs
            .imports
            .iter()
            .find(|i| !crate::index::import_matches(self.db, self.ws, self.file, &i.path, i.wildcard))
            .map(|i| i.path.join("::"))
    }

    /// `I::op(…)`: an operation named through its interface. RoboTool falls
    /// back to the global scope for calls, where an interface's operations
    /// have qualified names; the interface is usually one the enclosing
    /// controller, module or platform provides.
    fn qualified_operation(&self, path: &[String]) -> Option<Target> {
        let (op, iface) = path.split_last()?;
        let loc = *resolve_item(self.db, self.ws, self.file, iface, |k| k == DefKind::Interface).first()?;
        let i = loc.summary(self.db).members.iter().position(|m| m.kind == DefKind::OperationSig && &m.name == op)?;
        Some(Target::Member(loc, i as u32))
    }

    fn dollar_expr(&mut self, n: &SyntaxNode) {
        let Some((path, range)) = qualified(n) else { return };
        let name = path.join("::");
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        if let Some(input) = n.children().find(|c| c.kind() == SIM_INPUT_SUFFIX) {
            self.input_with_value(n, &input, &path, &members);
        }
        let io: Vec<&Member> =
            members.iter().filter(|m| m.io.is_some() && path.len() == 1 && m.name == path[0]).collect();
        // Inputs: input variables and events of either context.
        if let Some(m) = io.iter().find(|m| {
            (m.kind == DefKind::Variable && m.io == Some(Io::Input))
                || (m.kind == DefKind::Event && m.io == Some(Io::Input))
        }) {
            let t = m.target;
            self.push(range, name, RefKind::TriggerEvent, Some(t));
            return;
        }
        if let Some(m) = io.first() {
            let t = m.target;
            self.push(range, name.clone(), RefKind::TriggerEvent, Some(t));
            if m.kind == DefKind::Event {
                self.problem(
                    "RS-IO-04",
                    range,
                    format!("`{name}` is an output event and cannot be tested: only inputs can be read"),
                );
            } else if m.kind == DefKind::Variable {
                self.problem(
                    "RS-IO-04",
                    range,
                    format!("`{name}` is an output variable and cannot be read: require it in the input context too"),
                );
            } else {
                self.problem("LNK-01", range, format!("`${name}` in an expression must be an input event or variable"));
            }
            return;
        }
        self.push(range, name.clone(), RefKind::TriggerEvent, None);
        if members.iter().any(|m| path.len() == 1 && m.name == path[0] && m.io.is_none()) {
            self.problem("RS:SM6", range, format!("`{name}` is a local name: write it without `$`"));
        } else {
            self.problem(
                "LNK-01",
                range,
                format!(
                    "cannot resolve `${name}`: no input event or variable of that name in the machine's input context"
                ),
            );
        }
    }

    /// RS-IO-07: `$e?x` reads a typed input event into a local variable, in
    /// a transition condition.
    fn input_with_value(&mut self, n: &SyntaxNode, suffix: &SyntaxNode, path: &[String], members: &[Member]) {
        let name = path.join("::");
        // The same variable bound twice in one condition.
        if let Some(cond) = n.ancestors().find(|a| a.kind() == CONDITION) {
            let var = qualified(suffix).map(|(v, _)| v.join("::"));
            let earlier = cond
                .descendants()
                .filter(|d| d.kind() == SIM_INPUT_SUFFIX && d.text_range().end() <= suffix.text_range().start())
                .filter_map(|d| qualified(&d).map(|(v, _)| v.join("::")))
                .any(|v| Some(v) == var);
            if earlier {
                if let Some((v, r)) = qualified(suffix) {
                    self.problem(
                        "RS-IO-07",
                        r,
                        format!("`{}` already receives a value in this condition", v.join("::")),
                    );
                }
            }
        }
        if !n.ancestors().any(|a| a.kind() == CONDITION) {
            self.problem(
                "RS-IO-07",
                n.text_range(),
                format!("`${name}?…` reads an input with its value: it belongs in a transition condition"),
            );
        }
        if let Some(ev) = members.iter().find(|m| m.kind == DefKind::Event && path.len() == 1 && m.name == path[0]) {
            if ev.ty.is_none() {
                self.problem("RS-IO-07", n.text_range(), format!("`{name}` carries no value: test it with `${name}`"));
            }
        }
        let Some((var, vrange)) = qualified(suffix) else { return };
        let vname = var.join("::");
        match members.iter().find(|m| {
            var.len() == 1
                && m.name == var[0]
                && matches!(m.kind, DefKind::Variable | DefKind::Constant | DefKind::Parameter)
        }) {
            Some(m) if m.kind == DefKind::Variable && m.io.is_none() => {
                let t = m.target;
                self.push(vrange, vname, RefKind::Type, Some(t));
            }
            Some(m) => {
                let t = m.target;
                self.push(vrange, vname.clone(), RefKind::Type, Some(t));
                self.problem(
                    "RS-IO-07",
                    vrange,
                    format!("`{vname}` cannot receive the value: use a local variable of the machine"),
                );
            }
            None => {
                self.push(vrange, vname.clone(), RefKind::Type, None);
                self.problem("LNK-01", vrange, format!("cannot resolve variable `{vname}` to receive the value"));
            }
        }
    }

    fn enum_literal(&mut self, n: &SyntaxNode) {
        let refs: Vec<SyntaxNode> = n.children().filter(|c| c.kind() == NAME_REF).collect();
        let (Some(e), Some(l)) = (refs.first(), refs.get(1)) else { return };
        let (ename, lname) = (text_of(e), text_of(l));
        let Some(loc) =
            resolve_item(self.db, self.ws, self.file, std::slice::from_ref(&ename), |k| k == DefKind::Enumeration)
                .first()
                .copied()
        else {
            self.push(e.text_range(), ename.clone(), RefKind::Type, None);
            self.problem("LNK-01", e.text_range(), format!("cannot resolve enumeration `{ename}`"));
            return;
        };
        self.push(e.text_range(), ename.clone(), RefKind::Type, Some(Target::Item(loc)));
        let s = loc.summary(self.db);
        match s.members.iter().position(|m| m.kind == DefKind::EnumLiteral && m.name == lname) {
            Some(i) => self.push(l.text_range(), lname, RefKind::Type, Some(Target::Member(loc, i as u32))),
            None => {
                self.push(l.text_range(), lname.clone(), RefKind::Type, None);
                self.problem("LNK-01", l.text_range(), format!("enumeration `{ename}` has no literal `{lname}`"));
            }
        }
    }

    fn assignment(&mut self, n: &SyntaxNode) {
        let Some(target) = n.children().find(|c| c.kind() == ASSIGNABLE) else { return };
        let dollar = target.children_with_tokens().any(|t| t.kind() == DOLLAR);
        let Some((path, range)) = qualified(&target) else { return };
        if path.len() != 1 {
            return;
        }
        let name = path[0].clone();
        if !dollar && bound_names(n).contains(&name) {
            return;
        }
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        if dollar {
            match members.iter().find(|m| m.name == name && m.kind == DefKind::Variable && m.io == Some(Io::Output)) {
                Some(m) => {
                    let t = m.target;
                    self.push(range, name, RefKind::Type, Some(t));
                }
                None => {
                    self.push(range, name.clone(), RefKind::Type, None);
                    if members.iter().any(|m| m.name == name && m.io.is_none()) {
                        self.problem("RS:SM6", range, format!("`{name}` is a local variable: assign it without `$`"));
                    } else {
                        self.problem("LNK-01", range, format!("cannot resolve `${name}`: no output variable of that name (require its interface in the output context)"));
                    }
                }
            }
            return;
        }
        let local = members.iter().find(|m| {
            m.name == name
                && matches!(m.kind, DefKind::Variable | DefKind::Constant | DefKind::Parameter)
                && (!self.rs || m.io.is_none())
        });
        match local {
            Some(m) => {
                let (t, kind) = (m.target, m.kind);
                self.push(range, name.clone(), RefKind::Type, Some(t));
                if kind == DefKind::Parameter {
                    self.problem("RC-STMT-01", range, format!("`{name}` is a parameter and cannot be assigned"));
                } else if kind == DefKind::Constant {
                    self.problem("RC-STMT-06", range, format!("`{name}` is a constant and cannot be assigned"));
                }
            }
            None => {
                self.push(range, name.clone(), RefKind::Type, None);
                if self.rs && members.iter().any(|m| m.name == name && m.io == Some(Io::Output)) {
                    self.problem("RS:SM6", range, format!("output variable `{name}` must be written `${name} = …`"));
                } else {
                    self.problem("LNK-01", range, format!("cannot resolve variable `{name}`"));
                }
            }
        }
    }

    fn call(&mut self, n: &SyntaxNode, dollar: bool) {
        let Some((path, range)) = qualified(n) else { return };
        let name = path.join("::");
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        let ops: Vec<&Member> = members
            .iter()
            .filter(|m| m.kind == DefKind::OperationSig && path.len() == 1 && m.name == path[0])
            .collect();
        let wanted = |m: &&&Member| {
            if dollar {
                m.io == Some(Io::Output)
            } else {
                m.io.is_none() && m.via != Some(UseKind::Uses)
            }
        };
        if let Some(m) = ops.iter().find(wanted) {
            let t = m.target;
            self.push(range, name, RefKind::Operation, Some(t));
            return;
        }
        if path.len() > 1 {
            if let Some(t) = self.qualified_operation(&path) {
                self.push(range, name, RefKind::Operation, Some(t));
                return;
            }
        }
        self.push(range, name.clone(), RefKind::Operation, None);
        if self.rs && !dollar && ops.iter().any(|m| m.io == Some(Io::Output)) {
            self.problem("RS:SM6", range, format!("`{name}` is an output operation: call it as `${name}(…)`"));
        } else if self.rs && dollar && !ops.is_empty() {
            self.problem("RS:SM6", range, format!("`{name}` is not an output operation: call it without `$`"));
        } else {
            let defined = !resolve_item(self.db, self.ws, self.file, &path, |k| k == DefKind::Operation).is_empty();
            let hint = if defined {
                " (an operation definition is called through an interface that declares its signature, required by this context)"
            } else {
                ""
            };
            self.problem("LNK-01", range, format!("cannot resolve operation `{name}`: it is not declared in an interface this context requires or provides{hint}"));
        }
    }

    fn output(&mut self, n: &SyntaxNode) {
        let Some((path, range)) = qualified(n) else { return };
        let name = path.join("::");
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        let events: Vec<&Member> =
            members.iter().filter(|m| m.kind == DefKind::Event && path.len() == 1 && m.name == path[0]).collect();
        if let Some(m) = events.iter().find(|m| m.io == Some(Io::Output)) {
            let t = m.target;
            self.push(range, name, RefKind::TriggerEvent, Some(t));
        } else if let Some(m) = events.iter().find(|m| m.io == Some(Io::Input)) {
            let t = m.target;
            self.push(range, name.clone(), RefKind::TriggerEvent, Some(t));
            self.problem(
                "RS-IO-03",
                range,
                format!("`{name}` is an input event and cannot be emitted: declare it in the output context"),
            );
        } else {
            self.push(range, name.clone(), RefKind::TriggerEvent, None);
            self.problem(
                "LNK-01",
                range,
                format!("cannot resolve output event `{name}`: no event of that name in the machine's output context"),
            );
        }
    }

    fn communication(&mut self, n: &SyntaxNode) {
        let Some(comm) = n.children().find(|c| c.kind() == COMMUNICATION) else { return };
        let Some(r) = comm.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = text_of(&r);
        let Some(ctx) = self.context(r.text_range()) else { return };
        let members = self.members(ctx);
        match members.iter().find(|m| m.kind == DefKind::Event && m.name == name) {
            Some(m) => {
                let t = m.target;
                self.push(r.text_range(), name, RefKind::TriggerEvent, Some(t));
            }
            None => {
                if self.rs {
                    return; // already a syntax error: RoboSim has no plain communications
                }
                self.push(r.text_range(), name.clone(), RefKind::TriggerEvent, None);
                self.problem("LNK-01", r.text_range(), format!("cannot resolve event `{name}`"));
            }
        }
    }

    /// The variable of `e?x`.
    fn input_variable(&mut self, n: &SyntaxNode) {
        let Some((path, range)) = qualified(n) else { return };
        if path.len() != 1 {
            return;
        }
        let name = path[0].clone();
        let Some(ctx) = self.context(range) else { return };
        let members = self.members(ctx);
        match members
            .iter()
            .find(|m| m.name == name && matches!(m.kind, DefKind::Variable | DefKind::Constant | DefKind::Parameter))
        {
            Some(m) => {
                let (t, kind) = (m.target, m.kind);
                self.push(range, name.clone(), RefKind::Type, Some(t));
                if kind == DefKind::Constant {
                    self.problem("RC-STMT-06", range, format!("`{name}` is a constant and cannot receive a value"));
                }
            }
            None => {
                self.push(range, name.clone(), RefKind::Type, None);
                self.problem("LNK-01", range, format!("cannot resolve variable `{name}` to receive the value"));
            }
        }
    }

    fn since_entry(&mut self, n: &SyntaxNode) {
        let Some((path, range)) = qualified(n) else { return };
        let Some(inner) = self.defs.innermost(range) else { return };
        let Some(owner) = enclosing(self.defs, inner, &[DefKind::StateMachine, DefKind::Operation]) else { return };
        // Any non-final state of the machine, by simple or state-qualified name.
        let found = self.defs.iter().find(|(id, d)| {
            d.kind == DefKind::State && d.name == *path.last().unwrap() && {
                let mut anc = Vec::new();
                let mut cur = d.parent;
                while let Some(c) = cur {
                    if c == owner {
                        break;
                    }
                    anc.push(self.defs.def(c).name.clone());
                    cur = self.defs.def(c).parent;
                }
                let _ = id;
                cur == Some(owner)
                    && (path.len() == 1
                        || anc.iter().rev().cloned().collect::<Vec<_>>().ends_with(&path[..path.len() - 1]))
            }
        });
        let name = path.join("::");
        match found {
            Some((id, d)) => {
                self.push(range, name.clone(), RefKind::TransitionTarget, Some(Target::Def(self.file, id)));
                // RC:TE5: inside a transition, the state is one of the
                // transition's own container.
                let in_transition =
                    n.ancestors().find(|a| a.kind() == TRANSITION).and_then(|t| self.defs.innermost(t.text_range()));
                if let Some(t) = in_transition.filter(|t| self.defs.def(*t).kind == DefKind::Transition) {
                    if self.defs.def(t).parent != d.parent {
                        self.problem(
                            "RC:TE5",
                            range,
                            format!("`{name}` is not at the level of this transition: `sinceEntry` in a transition refers to a state of the transition's own container"),
                        );
                    }
                }
            }
            None => {
                self.push(range, name.clone(), RefKind::TransitionTarget, None);
                let is_final =
                    self.defs.iter().any(|(_, d)| d.kind == DefKind::Final && d.name == *path.last().unwrap());
                if is_final {
                    self.problem(
                        "RC:TE3",
                        range,
                        format!("`{name}` is a final state: `sinceEntry` needs a state that can be left"),
                    );
                } else {
                    self.problem("LNK-01", range, format!("cannot resolve state `{name}` in this machine"));
                }
            }
        }
    }
}

fn io_desc(m: &Member) -> &'static str {
    match (m.kind, m.io) {
        (DefKind::Event, Some(Io::Input)) => "input event",
        (DefKind::Event, _) => "output event",
        (DefKind::Variable, Some(Io::Input)) => "input variable",
        (DefKind::Variable, _) => "output variable",
        (DefKind::OperationSig, _) => "output operation",
        _ => "I/O element",
    }
}
