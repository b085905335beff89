//! The diagram model: what a diagram shows, computed from the semantic
//! model (per-file declarations and name resolution), independent of any
//! layout. The language server returns it as JSON (`robosim/diagram`), the
//! command line lays it out and renders it.

use std::collections::{BTreeSet, HashMap};

use robosim_hir::defs::{file_defs, ConnectionData, DefData, DefId, DefKind, FileDefs, Io};
use robosim_hir::line_index::LineIndex;
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
/// in `file`, in source order.
pub fn file_diagrams(db: &dyn Db, ws: Workspace, file: File) -> Vec<Diagram> {
    let defs = file_defs(db, file);
    let text = file.text(db);
    let src = Src { text, index: LineIndex::new(text) };
    let robosim = file.kind(db) == FileKind::RoboSim;
    let mut out = Vec::new();
    for (id, d) in defs.iter() {
        let kind = match d.kind {
            DefKind::StateMachine => DiagramKind::StateMachine,
            DefKind::Operation => DiagramKind::Operation,
            DefKind::Controller => DiagramKind::Controller,
            DefKind::Module => DiagramKind::Module,
            _ => continue,
        };
        let mut qualified: Vec<String> = defs.package.clone();
        qualified.extend(defs.local_path(id));
        let (inputs, outputs) = if robosim { io_names(db, ws, file, id) } else { (Vec::new(), Vec::new()) };
        let mut diagram = Diagram {
            kind,
            name: d.name.clone(),
            qualified_name: qualified.join("::"),
            file: file.path(db).clone(),
            robosim,
            range: src.span(d.range),
            name_range: src.span(d.name_range),
            inputs,
            outputs,
            region: None,
            blocks: Vec::new(),
            connections: Vec::new(),
        };
        match kind {
            DiagramKind::StateMachine | DiagramKind::Operation => {
                diagram.region = Some(region(defs, &src, id, ""));
            }
            DiagramKind::Controller | DiagramKind::Module => {
                let (blocks, connections) = structure(defs, &src, id);
                diagram.blocks = blocks;
                diagram.connections = connections;
            }
        }
        out.push(diagram);
    }
    out
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

fn node_kind(k: DefKind) -> Option<NodeKind> {
    Some(match k {
        DefKind::State => NodeKind::State,
        DefKind::Initial => NodeKind::Initial,
        DefKind::Junction => NodeKind::Junction,
        DefKind::Final => NodeKind::Final,
        DefKind::ProbabilisticJunction => NodeKind::ProbabilisticJunction,
        _ => return None,
    })
}

fn join_id(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}::{name}")
    }
}

/// The nodes and transitions directly inside `owner` (a machine, operation
/// or state); `prefix` is the owner's node id ("" for the machine).
fn region(defs: &FileDefs, src: &Src<'_>, owner: DefId, prefix: &str) -> Region {
    let mut r = Region::default();
    let mut by_name: HashMap<&str, String> = HashMap::new();
    let mut unnamed = 0;
    for (id, d) in defs.children(Some(owner)) {
        let Some(kind) = node_kind(d.kind) else { continue };
        let name = if d.name.is_empty() {
            unnamed += 1;
            format!("#{unnamed}")
        } else {
            d.name.clone()
        };
        let node_id = join_id(prefix, &name);
        by_name.entry(&d.name).or_insert_with(|| node_id.clone());
        let actions = defs
            .facts(id)
            .actions
            .iter()
            .map(|(k, range)| {
                let kw = k.keyword();
                Action { kind: kw.to_string(), text: src.clause(*range, kw), range: src.span(*range) }
            })
            .collect();
        let inner = if kind == NodeKind::State { region(defs, src, id, &node_id) } else { Region::default() };
        r.nodes.push(Node {
            id: node_id,
            kind,
            name,
            range: src.span(d.range),
            name_range: src.span(d.name_range),
            actions,
            region: inner,
        });
    }
    let mut unnamed_t = 0;
    for (_, d) in defs.children(Some(owner)) {
        let (DefKind::Transition, DefData::Transition(t)) = (d.kind, &d.data) else { continue };
        let name = if d.name.is_empty() {
            unnamed_t += 1;
            format!("#t{unnamed_t}")
        } else {
            d.name.clone()
        };
        let end = |e: &Option<(String, TextRange)>| -> (Option<String>, String) {
            match e {
                Some((n, _)) => (by_name.get(n.as_str()).cloned(), n.clone()),
                None => (None, String::new()),
            }
        };
        let (source, source_name) = end(&t.source);
        let (target, target_name) = end(&t.target);
        let trigger = t.trigger.as_ref().map(|(r, _)| src.clause(*r, "trigger")).filter(|s| !s.is_empty());
        let probability = t.probability.map(|r| src.clause(r, "probability"));
        let resets: Vec<String> = t.resets.iter().map(|(n, _)| format!("#{n}")).collect();
        let deadline = t.deadline.map(|r| src.clause(r, ""));
        let guard = t.condition.map(|r| src.clause(r, "condition"));
        let action = t.action.map(|r| src.clause(r, "action"));
        let exec = t.exec.is_some();
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
            range: src.span(d.range),
        });
    }
    r
}

/// The blocks and connections of a controller or module.
fn structure(defs: &FileDefs, src: &Src<'_>, owner: DefId) -> (Vec<Block>, Vec<Connection>) {
    let me = defs.def(owner);
    let mut blocks = Vec::new();
    for (_, d) in defs.children(Some(owner)) {
        let (kind, reference) = match (d.kind, &d.data) {
            (DefKind::Platform, _) => ("platform", None),
            (DefKind::Controller, _) => ("controller", None),
            (DefKind::StateMachine, _) => ("stm", None),
            (DefKind::Operation, _) => ("operation", None),
            (DefKind::PlatformRef, data) => ("platform", ref_path(data)),
            (DefKind::ControllerRef, data) => ("controller", ref_path(data)),
            (DefKind::MachineRef, data) => ("stm", ref_path(data)),
            (DefKind::OperationRef, data) => ("operation", ref_path(data)),
            _ => continue,
        };
        if d.name.is_empty() {
            continue;
        }
        blocks.push(Block { id: d.name.clone(), kind: kind.to_string(), reference, range: src.span(d.range) });
    }
    let raw: Vec<(&ConnectionData, TextRange)> = defs
        .children(Some(owner))
        .filter_map(|(_, d)| match &d.data {
            DefData::Connection(c) => Some((c, d.range)),
            _ => None,
        })
        .collect();
    let name = |e: &Option<(String, TextRange)>| e.as_ref().map(|(n, _)| n.clone()).unwrap_or_default();
    let mut connections: Vec<Connection> = Vec::new();
    for (c, range) in raw {
        let (from, from_event, to, to_event) = (name(&c.from), name(&c.efrom), name(&c.to), name(&c.eto));
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
            range: src.span(range),
        });
    }
    // The element itself, when connections name it (its boundary).
    let named = |n: &str| connections.iter().any(|c| c.from == n || c.to == n);
    if !me.name.is_empty() && !blocks.iter().any(|b| b.id == me.name) && named(&me.name) {
        blocks.insert(
            0,
            Block { id: me.name.clone(), kind: "boundary".into(), reference: None, range: src.span(me.name_range) },
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
        blocks.push(Block { id: n, kind: "unresolved".into(), reference: None, range: src.span(me.name_range) });
    }
    (blocks, connections)
}

fn ref_path(data: &DefData) -> Option<String> {
    match data {
        DefData::Reference { path, .. } => Some(path.join("::")),
        _ => None,
    }
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
