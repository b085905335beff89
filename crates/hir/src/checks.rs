//! Well-formedness rules over a file's declarations (§2 of the catalogue):
//! duplicates, required parts, machine structure, transitions, modules,
//! controllers, connections and how contexts use interfaces.

use std::collections::HashMap;

use rustc_hash::FxHashMap;

use robosim_syntax::{FileKind, TextRange};

use crate::defs::{Def, DefData, DefId, DefKind, FileDefs, Io, UseKind};
use crate::index::resolve_item;
use crate::{Db, File, Workspace};

/// What a range is relative to: rules run per element
/// ([`crate::element_rules`]), on positions from the element's start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Anchor {
    /// The start of the element whose rules found the problem.
    Here,
    /// The start of an element of the range's file (the salsa id of its
    /// [`crate::element::Element`]).
    Element(salsa::Id),
    /// The start of the file.
    File,
}

/// A range of a file, relative to an [`Anchor`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Place {
    /// The file.
    pub file: File,
    /// What `range` is relative to.
    pub anchor: Anchor,
    /// The range.
    pub range: TextRange,
}

impl Place {
    /// `range` in the element being checked, of `file`.
    pub(crate) fn here(file: File, range: TextRange) -> Place {
        Place { file, anchor: Anchor::Here, range }
    }
}

/// A rule violation before it becomes a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Problem {
    /// Rule code.
    pub code: &'static str,
    /// Where, in the file whose rules found it.
    pub range: TextRange,
    /// What `range` is relative to.
    pub anchor: Anchor,
    /// What.
    pub message: String,
    /// Other places involved.
    pub related: Vec<(Place, String)>,
}

impl Problem {
    pub(crate) fn new(code: &'static str, range: TextRange, message: impl Into<String>) -> Problem {
        Problem { code, range, anchor: Anchor::Here, message: message.into(), related: Vec::new() }
    }

    /// The same problem, its range relative to `anchor`.
    pub(crate) fn at(mut self, anchor: Anchor) -> Problem {
        self.anchor = anchor;
        self
    }

    pub(crate) fn with_related(mut self, place: Place, message: impl Into<String>) -> Problem {
        self.related.push((place, message.into()));
        self
    }

    /// Adds a related location when there is one.
    pub(crate) fn with_related_opt(self, place: Option<Place>, message: impl Into<String>) -> Problem {
        match place {
            Some(p) => self.with_related(p, message),
            None => self,
        }
    }
}

/// The declaration-level rule violations of the definitions `defs` of
/// `file` (one element's: DUP-01 between top-level definitions is
/// [`crate::element_rules::top_duplicates`]'s).
pub(crate) fn element_checks(db: &dyn Db, ws: Workspace, file: File, defs: &FileDefs) -> Vec<Problem> {
    let mut c = Checker { db, ws, file, defs, rs: file.kind(db) == FileKind::RoboSim, out: Vec::new() };
    c.duplicates();
    for (id, d) in defs.iter() {
        match d.kind {
            DefKind::StateMachine => {
                c.required_parts(id, d);
                c.node_container(id, d, true);
            }
            DefKind::Operation => {
                c.required_parts(id, d);
                c.node_container(id, d, false);
            }
            DefKind::State => {
                c.node_container(id, d, false);
                c.state_actions(id, d);
            }
            DefKind::Controller => {
                c.required_parts(id, d);
                c.controller(id, d);
                c.connections(id, d);
            }
            DefKind::Module => {
                c.required_parts(id, d);
                c.module(id, d);
                c.connections(id, d);
            }
            DefKind::Record if defs.children(Some(id)).all(|(_, f)| f.kind != DefKind::Field) => {
                c.out.push(Problem::new("RC-TYPE-01", d.name_range, format!("record `{}` has no fields", d.name)));
            }
            DefKind::Interface => c.interface(id, d),
            DefKind::Transition => c.transition(id, d),
            _ => {}
        }
    }
    c.interface_uses();
    c.out
}

struct Checker<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    file: File,
    defs: &'a FileDefs,
    rs: bool,
    out: Vec<Problem>,
}

/// Kinds that share one namespace for the duplicate rule.
pub(crate) fn dup_group(k: DefKind) -> u8 {
    match k {
        DefKind::State | DefKind::Initial | DefKind::Junction | DefKind::Final | DefKind::ProbabilisticJunction => 1,
        DefKind::Variable | DefKind::Constant => 2,
        DefKind::PrimitiveType | DefKind::Record | DefKind::Enumeration => 3,
        DefKind::Connection => 0,
        other => 10 + other as u8,
    }
}

impl<'a> Checker<'a> {
    fn duplicates(&mut self) {
        // Every definition of the file goes through these: FxHash.
        let mut seen: FxHashMap<(Option<DefId>, u8, &str), DefId> = FxHashMap::default();
        let mut reported = rustc_hash::FxHashSet::default();
        for (id, d) in self.defs.iter() {
            if d.name.is_empty() || d.kind == DefKind::Connection || d.parent.is_none() {
                continue;
            }
            let key = (d.parent, dup_group(d.kind), d.name.as_str());
            match seen.get(&key) {
                Some(&first) => {
                    let f = self.defs.def(first);
                    // Every duplicate is reported, the first one included.
                    if reported.insert(first) {
                        self.out.push(
                            Problem::new(
                                "DUP-01",
                                f.name_range,
                                format!("duplicate {} `{}`", f.kind.describe(), f.name),
                            )
                            .with_related(
                                Place::here(self.file, d.name_range),
                                format!("`{}` is declared again here", d.name),
                            ),
                        );
                    }
                    self.out.push(
                        Problem::new("DUP-01", d.name_range, format!("duplicate {} `{}`", d.kind.describe(), d.name))
                            .with_related(
                                Place::here(self.file, f.name_range),
                                format!("`{}` is first declared here", f.name),
                            ),
                    );
                }
                None => {
                    seen.insert(key, id);
                }
            }
        }
    }

    /// REQ-01 for RoboSim: `cycleDef` on modules, controllers and machines;
    /// input and output contexts on machines and operations.
    fn required_parts(&mut self, id: DefId, d: &Def) {
        if !self.rs {
            return;
        }
        let facts = self.defs.facts(id);
        let what = format!("{} `{}`", d.kind.describe(), d.name);
        if matches!(d.kind, DefKind::StateMachine | DefKind::Controller | DefKind::Module)
            && facts.cycle_defs.is_empty()
        {
            self.out.push(Problem::new(
                "REQ-01",
                d.name_range,
                format!("{what} needs a `cycleDef` (for example `cycleDef cycle == 1`)"),
            ));
        }
        if matches!(d.kind, DefKind::StateMachine | DefKind::Operation) {
            if facts.input_contexts.is_empty() {
                self.out.push(Problem::new(
                    "REQ-01",
                    d.name_range,
                    format!("{what} needs an `input context {{ … }}` (it may be empty)"),
                ));
            }
            if facts.output_contexts.is_empty() {
                self.out.push(Problem::new(
                    "REQ-01",
                    d.name_range,
                    format!("{what} needs an `output context {{ … }}` (it may be empty)"),
                ));
            }
        }
        for extra in facts.cycle_defs.iter().skip(1) {
            self.out.push(Problem::new("DUP-01", *extra, format!("{what} has more than one `cycleDef`")));
        }
    }

    fn nodes(&self, container: DefId) -> Vec<(DefId, &'a Def)> {
        let defs: &'a FileDefs = self.defs;
        defs.children(Some(container)).filter(|(_, n)| n.kind.is_node()).collect()
    }

    fn transitions(&self, container: DefId) -> Vec<(DefId, &'a crate::defs::TransitionData)> {
        let defs: &'a FileDefs = self.defs;
        defs.children(Some(container))
            .filter_map(|(id, t)| match &t.data {
                DefData::Transition(td) => Some((id, td)),
                _ => None,
            })
            .collect()
    }

    /// RC:STM3, RC:STM3-nested, RC:STM4, RC:IJ2, RC:J1, RC-JUNC-01.
    fn node_container(&mut self, id: DefId, d: &Def, machine: bool) {
        let nodes = self.nodes(id);
        let initials: Vec<_> = nodes.iter().filter(|(_, n)| n.kind == DefKind::Initial).collect();
        if machine {
            if initials.len() != 1 {
                let msg = if initials.is_empty() {
                    format!(
                        "state machine `{}` has no initial junction: add `initial i` and a transition from it",
                        d.name
                    )
                } else {
                    format!("state machine `{}` has {} initial junctions; it needs exactly one", d.name, initials.len())
                };
                self.out.push(Problem::new("RC:STM3", d.name_range, msg));
            }
        } else if !nodes.is_empty() && initials.len() != 1 {
            let msg = if initials.is_empty() {
                format!("{} `{}` has nodes but no initial junction", d.kind.describe(), d.name)
            } else {
                format!(
                    "{} `{}` has {} initial junctions; it needs exactly one",
                    d.kind.describe(),
                    d.name,
                    initials.len()
                )
            };
            self.out.push(Problem::new("RC:STM3-nested", d.name_range, msg));
        }
        if !nodes.is_empty() && !nodes.iter().any(|(_, n)| matches!(n.kind, DefKind::State | DefKind::Final)) {
            self.out.push(Problem::new(
                "RC:STM4",
                d.name_range,
                format!("{} `{}` has nodes but no state or final state", d.kind.describe(), d.name),
            ));
        }
        let transitions = self.transitions(id);
        let outgoing =
            |name: &str| transitions.iter().filter(|(_, t)| t.source.as_ref().is_some_and(|s| s.0 == name)).count();
        let incoming =
            |name: &str| transitions.iter().filter(|(_, t)| t.target.as_ref().is_some_and(|s| s.0 == name)).count();
        for (_, n) in &nodes {
            match n.kind {
                DefKind::Initial => {
                    let k = outgoing(&n.name);
                    if k != 1 {
                        let msg = if k == 0 {
                            format!("initial junction `{}` has no outgoing transition", n.name)
                        } else {
                            format!("initial junction `{}` has {k} outgoing transitions; it needs exactly one", n.name)
                        };
                        self.out.push(Problem::new("RC:IJ2", n.name_range, msg));
                    }
                }
                DefKind::Junction => {
                    if outgoing(&n.name) == 0 {
                        self.out.push(Problem::new(
                            "RC:J1",
                            n.name_range,
                            format!("junction `{}` has no outgoing transition", n.name),
                        ));
                    }
                    if incoming(&n.name) == 0 {
                        self.out.push(Problem::new(
                            "RC-JUNC-01",
                            n.name_range,
                            format!("junction `{}` has no incoming transition", n.name),
                        ));
                    }
                }
                _ => {}
            }
        }
    }

    /// RC:S2: at most one entry, during and exit action.
    fn state_actions(&mut self, id: DefId, d: &Def) {
        let mut seen: FxHashMap<crate::defs::ActionKind, TextRange> = FxHashMap::default();
        for (kind, range) in &self.defs.facts(id).actions {
            if let Some(first) = seen.get(kind) {
                let word = kind.keyword();
                self.out.push(
                    Problem::new("RC:S2", *range, format!("state `{}` has more than one {word} action", d.name))
                        .with_related(Place::here(self.file, *first), format!("the first {word} action")),
                );
            } else {
                seen.insert(*kind, *range);
            }
        }
    }

    /// RC:J3, RC:TT1, RC:PJ1, RC:PJ2, RC:PT1.
    fn transition(&mut self, _id: DefId, d: &Def) {
        let DefData::Transition(t) = &d.data else { return };
        let Some(container) = d.parent else { return };
        let source = t.source.as_ref().and_then(|(name, _)| {
            self.defs.children(Some(container)).find(|(_, n)| n.kind.is_node() && &n.name == name).map(|(_, n)| n)
        });
        // An empty legacy `trigger` (a syntax error already) is no trigger.
        let trigger = t.trigger.as_ref().filter(|(_, ev)| ev.is_some()).map(|(r, _)| *r).or(t.exec);
        if let (Some(src), Some(trig)) = (source, trigger) {
            if matches!(src.kind, DefKind::Junction | DefKind::Initial | DefKind::ProbabilisticJunction) {
                let what = if self.rs { "`exec`" } else { "a trigger" };
                self.out.push(Problem::new(
                    "RC:J3",
                    trig,
                    format!(
                        "transition `{}` has {what} but leaves the {} `{}`: only transitions from states can wait",
                        d.name,
                        src.kind.describe(),
                        src.name
                    ),
                ));
            }
        }
        if let Some(deadline) = t.deadline {
            if t.trigger.is_none() && !self.rs {
                self.out.push(Problem::new(
                    "RC:TT1",
                    deadline,
                    format!("transition `{}` has a deadline but no trigger", d.name),
                ));
            }
        }
        let from_prob = source.is_some_and(|s| s.kind == DefKind::ProbabilisticJunction);
        if from_prob {
            if t.probability.is_none() {
                self.out.push(Problem::new(
                    "RC:PJ1",
                    d.name_range,
                    format!("transition `{}` leaves a probabilistic junction but has no probability", d.name),
                ));
            }
            if let Some(cond) = t.condition {
                self.out.push(Problem::new(
                    "RC:PJ2",
                    cond,
                    format!("transition `{}` leaves a probabilistic junction and cannot have a condition", d.name),
                ));
            }
        } else if let (Some(p), Some(_)) = (t.probability, source) {
            self.out.push(Problem::new(
                "RC:PT1",
                p,
                format!(
                    "only transitions leaving a probabilistic junction carry a probability (`{}` does not)",
                    d.name
                ),
            ));
        }
    }

    /// RC:C1: at least one machine.
    fn controller(&mut self, id: DefId, d: &Def) {
        let machines = self
            .defs
            .children(Some(id))
            .filter(|(_, m)| matches!(m.kind, DefKind::StateMachine | DefKind::MachineRef))
            .count();
        if machines == 0 {
            self.out.push(Problem::new("RC:C1", d.name_range, format!("controller `{}` has no state machine", d.name)));
        }
    }

    /// RC:M1, RC-MOD-01, RC-MOD-02.
    fn module(&mut self, id: DefId, d: &Def) {
        let children: Vec<_> = self.defs.children(Some(id)).collect();
        let platforms: Vec<_> =
            children.iter().filter(|(_, c)| matches!(c.kind, DefKind::Platform | DefKind::PlatformRef)).collect();
        if platforms.len() != 1 {
            let msg = if platforms.is_empty() {
                format!("module `{}` has no robotic platform: add `robotic platform P {{ … }}` or `rref p = P`", d.name)
            } else {
                format!("module `{}` has {} robotic platforms; it needs exactly one", d.name, platforms.len())
            };
            self.out.push(Problem::new("RC:M1", d.name_range, msg));
        }
        if !children.iter().any(|(_, c)| matches!(c.kind, DefKind::Controller | DefKind::ControllerRef)) {
            self.out.push(Problem::new("RC-MOD-01", d.name_range, format!("module `{}` has no controller", d.name)));
        }
        for (_, c) in &children {
            if matches!(c.kind, DefKind::StateMachine | DefKind::MachineRef) {
                self.out.push(
                    Problem::new(
                        "RC-MOD-02",
                        d.name_range,
                        format!(
                            "module `{}` contains the state machine `{}` directly: state machines belong in controllers",
                            d.name, c.name
                        ),
                    )
                    .with_related(Place::here(self.file, c.name_range), format!("`{}` is here", c.name)),
                );
            }
        }
    }

    /// The kind of the node a connection end names in `owner`.
    fn end_kind(&self, owner: DefId, name: &str) -> Option<DefKind> {
        let o = self.defs.def(owner);
        if o.kind == DefKind::Controller && o.name == name {
            return Some(DefKind::Controller);
        }
        self.defs.children(Some(owner)).find(|(_, n)| n.name == name && n.kind != DefKind::Connection).map(|(_, n)| {
            match n.kind {
                DefKind::PlatformRef => DefKind::Platform,
                DefKind::ControllerRef => DefKind::Controller,
                DefKind::MachineRef => DefKind::StateMachine,
                k => k,
            }
        })
    }

    /// RC:Cn2, RC:Cn11, RC-CONN-03, RC:M3 / RC:C6.
    fn connections(&mut self, owner: DefId, d: &Def) {
        let conns: Vec<(DefId, &crate::defs::ConnectionData, &Def)> = self
            .defs
            .children(Some(owner))
            .filter_map(|(id, c)| match &c.data {
                DefData::Connection(cd) => Some((id, cd, c)),
                _ => None,
            })
            .collect();
        let one_per_end = if d.kind == DefKind::Module { "RC:M3" } else { "RC:C6" };
        let mut used: HashMap<(String, String), TextRange> = HashMap::new();
        for (_, c, def) in &conns {
            let (Some(from), Some(to)) = (&c.from, &c.to) else { continue };
            let fk = self.end_kind(owner, &from.0);
            let tk = self.end_kind(owner, &to.0);
            if d.kind == DefKind::Module
                && (fk == Some(DefKind::Platform) || tk == Some(DefKind::Platform))
                && !c.is_async
            {
                self.out.push(Problem::new(
                    "RC:Cn2",
                    def.name_range,
                    "connections with the robotic platform must be asynchronous: add `( _async )`",
                ));
            }
            if c.is_async && fk == Some(DefKind::StateMachine) && tk == Some(DefKind::StateMachine) {
                self.out.push(Problem::new(
                    "RC:Cn11",
                    c.async_range.unwrap_or(def.name_range),
                    "asynchronous connections between two state machines have no semantics",
                ));
            }
            let self_conn = from.0 == to.0 && c.efrom.as_ref().map(|e| &e.0) == c.eto.as_ref().map(|e| &e.0);
            if self_conn && !c.is_async {
                self.out.push(Problem::new(
                    "RC-CONN-03",
                    def.name_range,
                    format!("a synchronous connection of `{}` to itself means nothing", from.0),
                ));
            }
            let mut ends = vec![(from, &c.efrom)];
            if !self_conn {
                ends.push((to, &c.eto));
            }
            for (node, event) in ends {
                let Some(event) = event else { continue };
                let key = (node.0.clone(), event.0.clone());
                match used.get(&key) {
                    Some(first) => self.out.push(
                        Problem::new(
                            one_per_end,
                            event.1,
                            format!("`{}` on `{}` is already connected", event.0, node.0),
                        )
                        .with_related(Place::here(self.file, *first), "the other connection"),
                    ),
                    None => {
                        used.insert(key, event.1);
                    }
                }
            }
        }
    }

    /// RC:I2: events and operations are not mixed.
    fn interface(&mut self, id: DefId, d: &Def) {
        let has = |k: DefKind| self.defs.children(Some(id)).any(|(_, m)| m.kind == k);
        if has(DefKind::Event) && has(DefKind::OperationSig) {
            self.out.push(Problem::new(
                "RC:I2",
                d.name_range,
                format!("interface `{}` declares both events and operations: split it into two interfaces", d.name),
            ));
        }
    }

    /// The rules on how contexts use, provide and require interfaces.
    fn interface_uses(&mut self) {
        for u in &self.defs.uses {
            let owner = self.defs.def(u.owner);
            let Some(loc) =
                resolve_item(self.db, self.ws, self.file, &u.path, |k| k == DefKind::Interface).first().copied()
            else {
                continue;
            };
            let s = loc.summary(self.db);
            let has = |k: DefKind| s.members.iter().any(|m| m.kind == k);
            let (events, ops, vars, clocks) =
                (has(DefKind::Event), has(DefKind::OperationSig), has(DefKind::Variable), has(DefKind::Clock));
            let iname = u.path.join("::");
            let owner_desc = format!("{} `{}`", owner.kind.describe(), owner.name);
            let mut push = |code: &'static str, msg: String| self.out.push(Problem::new(code, u.range, msg));
            match (owner.kind, u.kind, u.io) {
                // RoboSim I/O contexts.
                (_, UseKind::Uses, Some(io)) => {
                    if vars {
                        push(
                            "RS:SM3",
                            format!(
                                "variables of `{iname}` would be local: only required variables can be {}s; write `requires {iname}`",
                                if io == Io::Input { "input" } else { "output" }
                            ),
                        );
                    }
                    if ops {
                        push(
                            "RC:I2-uses",
                            format!("cannot use `{iname}`: it declares operations (require it in the output context)"),
                        );
                    }
                    if io == Io::Input && clocks {
                        push(
                            "RS-IO-02",
                            format!("interfaces used in an input context declare only events; `{iname}` has clocks"),
                        );
                    }
                }
                (_, UseKind::Requires, Some(io)) => {
                    if events {
                        push(
                            "RC:I1-req",
                            format!("cannot require `{iname}`: it declares events (use `uses` for events)"),
                        );
                    }
                    if io == Io::Input && ops {
                        push("RS:SM2", format!("inputs are only events and variables: `{iname}` declares operations; require it in the output context"));
                    }
                }
                (_, UseKind::Provides, Some(_)) => {}
                (kind, UseKind::Provides, None) => {
                    match kind {
                        DefKind::Controller => push(
                            "RC:C2",
                            format!(
                                "{owner_desc} cannot provide `{iname}`: controllers only use and require interfaces"
                            ),
                        ),
                        DefKind::StateMachine => push(
                            "RC:STM1",
                            format!(
                                "{owner_desc} cannot provide `{iname}`: state machines only use and require interfaces"
                            ),
                        ),
                        DefKind::Operation => push("RC:O1:STM1", format!("{owner_desc} cannot provide `{iname}`")),
                        _ => {}
                    }
                    if events {
                        push(
                            "RC:I1-prov",
                            format!("cannot provide `{iname}`: it declares events (use `uses` for events)"),
                        );
                    }
                    if clocks {
                        push("RC-IFC-01", format!("cannot provide `{iname}`: it declares clocks"));
                    }
                }
                (kind, UseKind::Requires, None) => {
                    if kind == DefKind::Platform {
                        push(
                            "RC:RP1",
                            format!("{owner_desc} cannot require `{iname}`: platforms provide and use interfaces"),
                        );
                    }
                    if events {
                        push(
                            "RC:I1-req",
                            format!("cannot require `{iname}`: it declares events (use `uses` for events)"),
                        );
                    }
                    if clocks {
                        match kind {
                            DefKind::Controller => {
                                push("RC:C11", format!("{owner_desc} cannot require `{iname}`: it declares clocks"))
                            }
                            DefKind::StateMachine => {
                                push("RC:STM7", format!("{owner_desc} cannot require `{iname}`: it declares clocks"))
                            }
                            _ => {}
                        }
                    }
                }
                (kind, UseKind::Uses, None) => {
                    if ops {
                        push(
                            "RC:I2-uses",
                            format!("cannot use `{iname}`: it declares operations (require or provide it instead)"),
                        );
                    }
                    if clocks {
                        match kind {
                            DefKind::Platform => {
                                push("RC:RP2", format!("{owner_desc} cannot use `{iname}`: it declares clocks"))
                            }
                            DefKind::Controller => {
                                push("RC:C10", format!("{owner_desc} cannot use `{iname}`: it declares clocks"))
                            }
                            _ => {}
                        }
                    }
                }
            }
        }
    }
}
