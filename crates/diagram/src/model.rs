//! The diagram model: what a diagram shows, computed from the lowered
//! model of a file (`robosim_hir::model`), independent of any
//! layout. The language server returns it as JSON (`robosim/diagram`), the
//! command line lays it out and renders it.

use std::collections::BTreeSet;

use robosim_hir::line_index::LineIndex;
use robosim_hir::model::{self, file_model, Behaviour, Controller, DefId, Definition, Instance, Io, Item, Module};
use robosim_hir::resolve::{ctx_members, Ctx};
use robosim_hir::{Db, File, FileKind, TextRange, Workspace};
use serde::Serialize;

/// A source range: byte offsets, and the start as a 0-based line and UTF-16
/// column (LSP's convention), so that a viewer can move the cursor there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Span {
    /// Start byte offset.
    pub start: u32,
    /// End byte offset.
    pub end: u32,
    /// 0-based line of the start.
    pub line: u32,
    /// 0-based UTF-16 column of the start.
    pub character: u32,
    /// 0-based line of the end.
    pub end_line: u32,
    /// 0-based UTF-16 column of the end.
    pub end_character: u32,
}

/// What a diagram is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub enum DiagramKind {
    /// A state machine (`stm`).
    StateMachine,
    /// An operation definition (a state machine with parameters).
    Operation,
    /// A controller: its machines and operations and their connections.
    Controller,
    /// A module: its platform, controllers and their connections.
    Module,
}

impl DiagramKind {
    /// The word used in titles and file names.
    pub fn word(self) -> &'static str {
        match self {
            DiagramKind::StateMachine => "stm",
            DiagramKind::Operation => "operation",
            DiagramKind::Controller => "controller",
            DiagramKind::Module => "module",
        }
    }
}

/// One diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Diagram {
    /// What it is of.
    pub kind: DiagramKind,
    /// The element's name.
    pub name: String,
    /// Package and enclosing elements, then the name, joined with `::`.
    pub qualified_name: String,
    /// The file's path.
    pub file: String,
    /// Whether the file is RoboSim.
    pub robosim: bool,
    /// The whole declaration.
    pub range: Span,
    /// The name.
    pub name_range: Span,
    /// RoboSim inputs (`$x` read in this element), by name.
    pub inputs: Vec<String>,
    /// RoboSim outputs (`$x` written by this element), by name.
    pub outputs: Vec<String>,
    /// For machines and operations: their nodes and transitions.
    pub region: Option<Region>,
    /// For controllers and modules: the platform, controllers, machines,
    /// operations, and the element itself (`boundary`) when a connection
    /// names it.
    pub blocks: Vec<Block>,
    /// For controllers and modules: the connections.
    pub connections: Vec<Connection>,
}

/// The inside of a machine or of a composite state.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Region {
    /// States, junctions, initial and final nodes.
    pub nodes: Vec<Node>,
    /// The transitions declared at this level.
    pub transitions: Vec<Transition>,
}

impl Region {
    /// Whether there is nothing inside.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty() && self.transitions.is_empty()
    }
}

/// The kind of a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub enum NodeKind {
    /// A state (composite when its region is not empty).
    State,
    /// The initial junction.
    Initial,
    /// A junction.
    Junction,
    /// A final state.
    Final,
    /// A probabilistic junction.
    ProbabilisticJunction,
}

/// A node of a machine.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Node {
    /// Unique in the diagram: the names of the enclosing states and its
    /// own, joined with `::`.
    pub id: String,
    /// What it is.
    pub kind: NodeKind,
    /// Its name.
    pub name: String,
    /// The declaration.
    pub range: Span,
    /// The name.
    pub name_range: Span,
    /// Entry, during and exit actions, in order.
    pub actions: Vec<Action>,
    /// The nodes and transitions inside (empty for a simple state).
    pub region: Region,
}

/// An entry, during or exit action.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Action {
    /// `entry`, `during` or `exit`.
    pub kind: String,
    /// The statement, as written (whitespace collapsed).
    pub text: String,
    /// Where.
    pub range: Span,
}

/// A transition.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Transition {
    /// Unique in the diagram: the enclosing states' names and its own.
    pub id: String,
    /// Its name.
    pub name: String,
    /// The source node's id, when it resolves.
    pub source: Option<String>,
    /// The target node's id, when it resolves.
    pub target: Option<String>,
    /// The source as written.
    pub source_name: String,
    /// The target as written.
    pub target_name: String,
    /// The label, as RoboTool draws it: `trigger #C <{d} [guard] / action`
    /// (RoboSim: `exec [guard] / action`).
    pub label: String,
    /// The trigger, without `trigger`.
    pub trigger: Option<String>,
    /// RoboSim `exec`.
    pub exec: bool,
    /// `probability p`, without the keyword.
    pub probability: Option<String>,
    /// Clock resets, `#C`.
    pub resets: Vec<String>,
    /// The deadline `<{d}`.
    pub deadline: Option<String>,
    /// The guard, without `condition`.
    pub guard: Option<String>,
    /// The action, without `action`.
    pub action: Option<String>,
    /// The declaration.
    pub range: Span,
}

/// A box of a controller or module diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Block {
    /// The name connections use.
    pub id: String,
    /// `platform`, `controller`, `stm`, `operation` or `boundary`.
    pub kind: String,
    /// The referenced element (`Movement` for `cref mv = Movement`), if it is
    /// a reference.
    pub reference: Option<String>,
    /// The declaration.
    pub range: Span,
}

/// A connection.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Connection {
    /// The source block's id.
    pub from: String,
    /// The source's event.
    pub from_event: String,
    /// The target block's id.
    pub to: String,
    /// The target's event.
    pub to_event: String,
    /// `( _async )`.
    pub is_async: bool,
    /// `[ mult ]` (RoboChart's bidirectional connections), or two
    /// connections on the same events in opposite directions: one line with
    /// two arrowheads.
    pub bidirectional: bool,
    /// `[ mult ]`.
    pub mult: bool,
    /// `input` from the platform, `output` to it, `internal` otherwise.
    pub direction: String,
    /// The label: the event, or `e → f` when the ends' events differ.
    pub label: String,
    /// The declaration (the first one for a bidirectional pair).
    pub range: Span,
}

/// Everything needed to convert ranges.
struct Src<'a> {
    text: &'a str,
    index: LineIndex,
}

impl Src<'_> {
    fn span(&self, r: TextRange) -> Span {
        let s = self.index.line_col(self.text, r.start());
        let e = self.index.line_col(self.text, r.end());
        Span {
            start: r.start().into(),
            end: r.end().into(),
            line: s.line,
            character: s.col,
            end_line: e.line,
            end_character: e.col,
        }
    }

    /// The text of `r`, whitespace collapsed, without a leading keyword.
    fn clause(&self, r: TextRange, keyword: &str) -> String {
        let raw = self.text.get(usize::from(r.start())..usize::from(r.end())).unwrap_or("");
        let collapsed = collapse(raw);
        match collapsed.strip_prefix(keyword) {
            Some(rest) if !keyword.is_empty() && !rest.starts_with(|c: char| c.is_alphanumeric() || c == '_') => {
                rest.trim().to_string()
            }
            _ => collapsed,
        }
    }
}

/// Collapses runs of whitespace (newlines included) into one space, and drops
/// `//` comments.
pub fn collapse(s: &str) -> String {
    let mut out = String::new();
    for line in s.lines() {
        let line = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        for w in line.split_whitespace() {
            if !out.is_empty() {
                out.push(' ');
            }
            out.push_str(w);
        }
    }
    out
}

/// The diagrams of every machine, operation, controller and module declared
/// in `file`, in source order (an element before the elements declared in
/// it), from the file's lowered model ([`robosim_hir::model::file_model`]).
pub fn file_diagrams(db: &dyn Db, ws: Workspace, file: File) -> Vec<Diagram> {
    let m = file_model(db, ws, file);
    let text = file.text(db);
    let cx = Cx {
        db,
        ws,
        file,
        path: file.path(db),
        robosim: file.kind(db) == FileKind::RoboSim,
        src: Src { text, index: LineIndex::new(text) },
    };
    let mut out = Vec::new();
    for (_, item) in &m.items {
        match item {
            Item::Machine(b) => cx.behaviour(DiagramKind::StateMachine, b, &m.package, &mut out),
            Item::Operation(b) => cx.behaviour(DiagramKind::Operation, b, &m.package, &mut out),
            Item::Controller(c) => cx.controller(c, &m.package, &mut out),
            Item::Module(x) => cx.module(x, &m.package, &mut out),
            _ => {}
        }
    }
    out
}

/// What every diagram of a file shares.
struct Cx<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    path: &'a String,
    robosim: bool,
    src: Src<'a>,
}

/// A block of a controller or module diagram, before it is placed: its
/// kind, its instance, and where it is written.
type Member<'a> = (&'static str, &'a str, TextRange, Option<String>);

impl Cx<'_> {
    /// A diagram with no contents yet; `scope` is the package and the
    /// enclosing elements' names.
    fn diagram(
        &self,
        kind: DiagramKind,
        name: &str,
        scope: &[String],
        range: TextRange,
        name_range: TextRange,
        def: Option<DefId>,
    ) -> Diagram {
        let (inputs, outputs) = match def {
            Some(id) if self.robosim => io_names(self.db, self.ws, self.file, id),
            _ => (Vec::new(), Vec::new()),
        };
        let mut qualified = scope.to_vec();
        qualified.push(name.to_string());
        Diagram {
            kind,
            name: name.to_string(),
            qualified_name: qualified.join("::"),
            file: self.path.clone(),
            robosim: self.robosim,
            range: self.src.span(range),
            name_range: self.src.span(name_range),
            inputs,
            outputs,
            region: None,
            blocks: Vec::new(),
            connections: Vec::new(),
        }
    }

    fn behaviour(&self, kind: DiagramKind, b: &Behaviour, scope: &[String], out: &mut Vec<Diagram>) {
        let mut d = self.diagram(kind, &b.name, scope, b.range, b.name_range, b.def);
        d.region = Some(region(&self.src, &b.region, ""));
        out.push(d);
    }

    fn controller(&self, c: &Controller, scope: &[String], out: &mut Vec<Diagram>) {
        let mut d = self.diagram(DiagramKind::Controller, &c.name, scope, c.range, c.name_range, c.def);
        let mut members: Vec<Member<'_>> = Vec::new();
        members.extend(c.machines.iter().map(|i| member("stm", i)));
        members.extend(c.operations.iter().map(|i| member("operation", i)));
        members.sort_by_key(|m| m.2.start());
        (d.blocks, d.connections) = structure(&self.src, &members, &c.connections, &c.name, c.name_range);
        out.push(d);
        // The elements declared inside, in the order written.
        let inner = child_scope(scope, &c.name);
        let mut nested: Vec<(DiagramKind, &Behaviour)> = Vec::new();
        nested.extend(c.machines.iter().filter_map(inline).map(|b| (DiagramKind::StateMachine, b)));
        nested.extend(c.operations.iter().filter_map(inline).map(|b| (DiagramKind::Operation, b)));
        nested.sort_by_key(|(_, b)| b.range.start());
        for (kind, b) in nested {
            self.behaviour(kind, b, &inner, out);
        }
    }

    fn module(&self, x: &Module, scope: &[String], out: &mut Vec<Diagram>) {
        let mut d = self.diagram(DiagramKind::Module, &x.name, scope, x.range, x.name_range, x.def);
        let mut members: Vec<Member<'_>> = Vec::new();
        members.extend(x.platforms.iter().map(|i| member("platform", i)));
        members.extend(x.controllers.iter().map(|i| member("controller", i)));
        members.extend(x.machines.iter().map(|i| member("stm", i)));
        members.sort_by_key(|m| m.2.start());
        (d.blocks, d.connections) = structure(&self.src, &members, &x.connections, &x.name, x.name_range);
        out.push(d);
        let inner = child_scope(scope, &x.name);
        enum Inner<'a> {
            Controller(&'a Controller),
            Machine(&'a Behaviour),
        }
        let mut nested: Vec<(TextRange, Inner<'_>)> = Vec::new();
        nested.extend(x.controllers.iter().filter_map(inline).map(|c| (c.range, Inner::Controller(c))));
        nested.extend(x.machines.iter().filter_map(inline).map(|b| (b.range, Inner::Machine(b))));
        nested.sort_by_key(|(r, _)| r.start());
        for (_, n) in nested {
            match n {
                Inner::Controller(c) => self.controller(c, &inner, out),
                Inner::Machine(b) => self.behaviour(DiagramKind::StateMachine, b, &inner, out),
            }
        }
    }
}

fn child_scope(scope: &[String], name: &str) -> Vec<String> {
    let mut s = scope.to_vec();
    s.push(name.to_string());
    s
}

/// The element an instance declares inline (none for a reference).
fn inline<T>(i: &Instance<T>) -> Option<&T> {
    match &i.def {
        Definition::Inline(t) => Some(t),
        Definition::Ref { .. } => None,
    }
}

fn member<'a, T>(kind: &'static str, i: &'a Instance<T>) -> Member<'a> {
    let reference = match &i.def {
        Definition::Ref { path, .. } => Some(path.join("::")),
        Definition::Inline(_) => None,
    };
    (kind, &i.name, i.range, reference)
}

/// The RoboSim inputs and outputs visible in a machine or operation (those
/// of the enclosing element for controllers and modules).
fn io_names(db: &dyn Db, ws: Workspace, file: File, id: DefId) -> (Vec<String>, Vec<String>) {
    let mut inputs = BTreeSet::new();
    let mut outputs = BTreeSet::new();
    for m in ctx_members(db, ws, Ctx::Local(file, id)).iter() {
        match m.io {
            Some(Io::Input) => inputs.insert(m.name.clone()),
            Some(Io::Output) => outputs.insert(m.name.clone()),
            None => false,
        };
    }
    (inputs.into_iter().collect(), outputs.into_iter().collect())
}

fn node_kind(k: model::NodeKind) -> NodeKind {
    match k {
        model::NodeKind::State => NodeKind::State,
        model::NodeKind::Initial => NodeKind::Initial,
        model::NodeKind::Junction => NodeKind::Junction,
        model::NodeKind::Final => NodeKind::Final,
        model::NodeKind::Probabilistic => NodeKind::ProbabilisticJunction,
    }
}

fn join_id(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}::{name}")
    }
}

/// The nodes and transitions of a region of the model; `prefix` is the
/// owner's node id ("" for the machine).
fn region(src: &Src<'_>, m: &model::Region, prefix: &str) -> Region {
    let mut r = Region::default();
    let mut unnamed = 0;
    for n in &m.nodes {
        let kind = node_kind(n.kind);
        let name = if n.name.is_empty() {
            unnamed += 1;
            format!("#{unnamed}")
        } else {
            n.name.clone()
        };
        let node_id = join_id(prefix, &name);
        let actions = n
            .actions
            .iter()
            .map(|(k, range)| {
                let kw = k.keyword();
                Action { kind: kw.to_string(), text: src.clause(*range, kw), range: src.span(*range) }
            })
            .collect();
        let inner = if kind == NodeKind::State { region(src, &n.region, &node_id) } else { Region::default() };
        r.nodes.push(Node {
            id: node_id,
            kind,
            name,
            range: src.span(n.range),
            name_range: src.span(n.name_range),
            actions,
            region: inner,
        });
    }
    let mut unnamed_t = 0;
    for t in &m.transitions {
        let name = if t.name.is_empty() {
            unnamed_t += 1;
            format!("#t{unnamed_t}")
        } else {
            t.name.clone()
        };
        // Transitions name nodes of their own region (the first of a name).
        let end = |name: &Option<String>, node: Option<usize>| -> (Option<String>, String) {
            (node.and_then(|i| r.nodes.get(i)).map(|n| n.id.clone()), name.clone().unwrap_or_default())
        };
        let (source, source_name) = end(&t.source, t.source_node);
        let (target, target_name) = end(&t.target, t.target_node);
        let trigger = t.trigger_range.map(|r| src.clause(r, "trigger")).filter(|s| !s.is_empty());
        let probability = t.probability.map(|r| src.clause(r, "probability"));
        let resets: Vec<String> = t.resets.iter().map(|(n, _)| format!("#{n}")).collect();
        let deadline = t.deadline.as_ref().map(|(r, _)| src.clause(*r, ""));
        let guard = t.condition.as_ref().map(|c| src.clause(c.range, "condition"));
        let action = t.action.as_ref().map(|a| src.clause(a.range, "action"));
        let exec = t.exec;
        let mut parts: Vec<String> = Vec::new();
        if let Some(tr) = &trigger {
            parts.push(tr.clone());
        }
        if exec {
            parts.push("exec".into());
        }
        if let Some(p) = &probability {
            parts.push(format!("{{{p}}}"));
        }
        parts.extend(resets.iter().cloned());
        if let Some(d) = &deadline {
            parts.push(d.clone());
        }
        if let Some(g) = &guard {
            parts.push(format!("[{g}]"));
        }
        if let Some(a) = &action {
            parts.push(format!("/ {a}"));
        }
        r.transitions.push(Transition {
            id: join_id(prefix, &name),
            name,
            source,
            target,
            source_name,
            target_name,
            label: parts.join(" "),
            trigger,
            exec,
            probability,
            resets,
            deadline,
            guard,
            action,
            range: src.span(t.range),
        });
    }
    r
}

/// The blocks and connections of a controller or module: `members` its
/// instances in the order written, `name` and `name_range` its own.
fn structure(
    src: &Src<'_>,
    members: &[Member<'_>],
    raw: &[model::Connection],
    name: &str,
    name_range: TextRange,
) -> (Vec<Block>, Vec<Connection>) {
    let mut blocks = Vec::new();
    for (kind, id, range, reference) in members {
        if id.is_empty() {
            continue;
        }
        blocks.push(Block {
            id: id.to_string(),
            kind: kind.to_string(),
            reference: reference.clone(),
            range: src.span(*range),
        });
    }
    let mut connections: Vec<Connection> = Vec::new();
    for c in raw {
        let (from, from_event, to, to_event) = (c.from.clone(), c.efrom.clone(), c.to.clone(), c.eto.clone());
        // The reverse of an earlier connection on the same events: one
        // bidirectional line.
        if let Some(prev) = connections.iter_mut().find(|p| {
            !p.bidirectional
                && p.from == to
                && p.to == from
                && p.from_event == to_event
                && p.to_event == from_event
                && p.is_async == c.is_async
        }) {
            prev.bidirectional = true;
            continue;
        }
        let kind_of = |n: &str| blocks.iter().find(|b| b.id == n).map(|b| b.kind.as_str());
        let direction = if kind_of(&from) == Some("platform") {
            "input"
        } else if kind_of(&to) == Some("platform") {
            "output"
        } else {
            "internal"
        };
        let label = if from_event == to_event || to_event.is_empty() {
            from_event.clone()
        } else {
            format!("{from_event} → {to_event}")
        };
        connections.push(Connection {
            from,
            from_event,
            to,
            to_event,
            is_async: c.is_async,
            bidirectional: c.is_mult,
            mult: c.is_mult,
            direction: direction.to_string(),
            label,
            range: src.span(c.range),
        });
    }
    // The element itself, when connections name it (its boundary).
    let named = |n: &str| connections.iter().any(|c| c.from == n || c.to == n);
    if !name.is_empty() && !blocks.iter().any(|b| b.id == name) && named(name) {
        blocks.insert(
            0,
            Block { id: name.to_string(), kind: "boundary".into(), reference: None, range: src.span(name_range) },
        );
    }
    // Ends that name nothing still get a box, so that every connection is drawn.
    let mut missing: Vec<String> = Vec::new();
    for c in &connections {
        for n in [&c.from, &c.to] {
            if !blocks.iter().any(|b| &b.id == n) && !missing.contains(n) {
                missing.push(n.clone());
            }
        }
    }
    for n in missing {
        blocks.push(Block { id: n, kind: "unresolved".into(), reference: None, range: src.span(name_range) });
    }
    (blocks, connections)
}

/// A compact, stable text form of a diagram for snapshot tests: one line
/// per node, transition, block and connection, with nesting by indentation.
pub fn dump(d: &Diagram) -> String {
    let mut out = format!("{} {} ({})\n", d.kind.word(), d.qualified_name, d.file);
    if !d.inputs.is_empty() || !d.outputs.is_empty() {
        out.push_str(&format!("  inputs: {}; outputs: {}\n", d.inputs.join(", "), d.outputs.join(", ")));
    }
    if let Some(r) = &d.region {
        dump_region(r, 1, &mut out);
    }
    for b in &d.blocks {
        out.push_str(&format!(
            "  {} {}{}\n",
            b.kind,
            b.id,
            b.reference.as_ref().map(|r| format!(" = {r}")).unwrap_or_default()
        ));
    }
    for c in &d.connections {
        let arrow = if c.bidirectional { "<->" } else { "->" };
        let mut flags = vec![c.direction.clone()];
        if c.is_async {
            flags.push("async".into());
        }
        if c.mult {
            flags.push("mult".into());
        }
        out.push_str(&format!(
            "  connection {}.{} {arrow} {}.{} [{}] \"{}\"\n",
            c.from,
            c.from_event,
            c.to,
            c.to_event,
            flags.join(", "),
            c.label
        ));
    }
    out
}

fn dump_region(r: &Region, depth: usize, out: &mut String) {
    let pad = "  ".repeat(depth);
    for n in &r.nodes {
        let kind = match n.kind {
            NodeKind::State if !n.region.is_empty() => "composite state",
            NodeKind::State => "state",
            NodeKind::Initial => "initial",
            NodeKind::Junction => "junction",
            NodeKind::Final => "final",
            NodeKind::ProbabilisticJunction => "probabilistic junction",
        };
        out.push_str(&format!("{pad}{kind} {} @{}:{}\n", n.id, n.name_range.line + 1, n.name_range.character + 1));
        for a in &n.actions {
            out.push_str(&format!("{pad}  {} {}\n", a.kind, a.text));
        }
        dump_region(&n.region, depth + 1, out);
    }
    for t in &r.transitions {
        let end = |id: &Option<String>, name: &str| id.clone().unwrap_or_else(|| format!("?{name}"));
        out.push_str(&format!(
            "{pad}transition {}: {} -> {} \"{}\"\n",
            t.id,
            end(&t.source, &t.source_name),
            end(&t.target, &t.target_name),
            t.label
        ));
    }
}
