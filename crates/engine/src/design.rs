//! A RoboChart module, controller or machine on its own, as an LTS: its
//! external events visible (`e.in.v`, `e.out.v`, `opCall.args`), internal
//! steps hidden, τ before `tock` (semantics.md §4.1). This is what
//! RoboChart assertions about a design (`deadlock-free`, `divergence-free`,
//! `timelock-free`, `deterministic`, `reachable`) are about.

use crate::events::{EventTable, Param};
use crate::ir::{Design, Dir, Level, Val};
use crate::lts::{Event, Label, Lts, TAU, TICK};
use crate::machine::Offer;
use crate::pack::{Encoding, VectorLts, Vectors};
use crate::sched::State;

/// The design as an LTS.
pub struct DesignLts<'a> {
    design: &'a Design,
    /// Event channel of each design channel.
    group: Vec<usize>,
    /// Slot: 0 running, 1 terminated (✓ done).
    ended: usize,
    len: usize,
    /// Packing, run-time errors, event names.
    enc: Encoding,
    /// RT-9: no `tock` (RoboChart's untimed semantics, see the fixtures `untimed_*`).
    untimed: bool,
    /// RT-11: a RoboSim operation on its own: the slot saying it is
    /// between the `endexec` and the `startexec` of an `exec`, and those
    /// two events.
    exec: Option<(usize, Event, Event)>,
}

/// The printed name of a design channel's events.
pub(crate) fn channel_name(c: &crate::ir::Channel) -> String {
    match (c.is_call, c.dir) {
        // RoboSim: an output of the output context (a RoboSim operation on
        // its own writes its register: `registerWrite.o_move.l.a`).
        _ if c.register_write => format!("registerWrite.o_{}", c.name),
        (true, _) => format!("{}Call", c.name),
        _ if c.internal => c.name.clone(),
        _ if c.var => format!("set_{}", c.name),
        (false, Dir::In) => format!("{}.in", c.name),
        (false, Dir::Out) => format!("{}.out", c.name),
    }
}

/// The events of several designs in one table, matched by name (for a
/// refinement between two designs): a channel's domains are the union of
/// the designs'.
pub fn shared_events(designs: &[&Design]) -> Result<EventTable, String> {
    let mut channels: Vec<(String, Vec<Param>)> = Vec::new();
    for d in designs {
        for c in &d.channels {
            let name = channel_name(c);
            let disagree = || format!("the two sides disagree on the values of `{name}`");
            match channels.iter_mut().find(|(n, _)| *n == name) {
                Some((_, params)) if params.len() == c.shape.len() => {
                    for (p, q) in params.iter_mut().zip(&c.shape) {
                        *p = p.union(q).ok_or_else(disagree)?;
                    }
                }
                Some(_) => return Err(disagree()),
                None => channels.push((name, c.shape.clone())),
            }
        }
    }
    let mut events = EventTable::default();
    for (name, params) in channels {
        events.add(name, params).map_err(|e| format!("the channel `{}` has too many values", e.0))?;
    }
    Ok(events)
}

impl<'a> DesignLts<'a> {
    /// The design this LTS runs: its slots come first in every state.
    pub fn design(&self) -> &'a Design {
        self.design
    }

    /// The design's LTS.
    pub fn new(design: &'a Design) -> Result<DesignLts<'a>, String> {
        DesignLts::with_events(design, &shared_events(&[design])?)
    }

    /// The design's LTS, its events numbered by `events` (see
    /// [`shared_events`]).
    pub fn with_events(design: &'a Design, events: &EventTable) -> Result<DesignLts<'a>, String> {
        let mut events = events.clone();
        let mut group = Vec::new();
        for c in &design.channels {
            let name = channel_name(c);
            group.push(events.find(&name).ok_or_else(|| format!("no events for `{name}`"))?);
        }
        let ended = design.slots as usize;
        let mut bounds = design.slot_bounds();
        bounds.push((0, 1));
        let mut len = ended + 1;
        let mut exec = None;
        if design.level == Level::Operation {
            let too_many = |e: crate::events::TooManyEvents| format!("the channel `{}` has too many values", e.0);
            let g = events.add("endexec", Vec::new()).map_err(too_many)?;
            let endexec = events.event(g, &[]);
            let g = events.add("startexec", Vec::new()).map_err(too_many)?;
            let startexec = events.event(g, &[]);
            bounds.push((0, 1));
            exec = Some((len, endexec, startexec));
            len += 1;
        }
        Ok(DesignLts { design, group, ended, len, enc: Encoding::new(&bounds, events), untimed: false, exec })
    }

    /// The same LTS without `tock`: time never passes (RT-9). For a design
    /// made untimed by [`crate::untimed::untime`], whose waits are gone.
    pub fn without_time(mut self) -> Self {
        self.untimed = true;
        self
    }

    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        self.enc.error.get()
    }

    /// RT-11: a RoboSim operation on its own, as RoboTool's `OP_…::O__`
    /// (e.g. the reference's
    /// `csp-gen/sim/defs/pkg223_aggregation_sim_clone_waitOp_j_2_3_f.csp`):
    /// an `exec` statement is `endexec -> startexec -> …` inside a timed
    /// section with no cycle around it, so time may pass before `endexec`
    /// and between the two (nothing hidden competes there, and τ has
    /// priority over `tock` only); after `startexec` the operation goes on
    /// where it stopped. `None` when `st` is not at an `exec`.
    fn exec_steps(&self, st: &[i32], out: &mut Vectors) -> Result<Option<()>, String> {
        let Some((slot, endexec, startexec)) = self.exec else { return Ok(None) };
        let m = &self.design.machines[0];
        let at_exec = st[slot] == 1 || (m.cycle_ended(st) && !m.terminated(st));
        if !at_exec {
            return Ok(None);
        }
        let n = out.push_copy(st);
        if st[slot] == 1 {
            n[slot] = 0;
            m.resume(n, &self.design.clocks).map_err(|e| e.0)?;
            out.set_label(Label::plain(startexec));
        } else {
            n[slot] = 1;
            out.set_label(Label::plain(endexec));
        }
        let n = out.push_copy(st);
        self.design.advance_time(n)?;
        out.set_label(Label::TOCK);
        Ok(Some(()))
    }

    fn successors_inner(&self, st: &[i32], out: &mut Vectors) -> Result<(), String> {
        if self.exec_steps(st, out)?.is_some() {
            return Ok(());
        }
        let start = out.len();
        let mut can_tock = true;
        // A buffer reused from state to state.
        let mut moves = std::mem::take(&mut out.moves);
        moves.clear();
        let mut internal = Vec::new();
        for (mi, m) in self.design.machines.iter().enumerate() {
            moves.clear();
            m.moves(st, &mut moves).map_err(|e| e.0)?;
            can_tock &= m.can_tock(st);
            for mv in &moves {
                if self.design.is_internal(&mv.offer) {
                    internal.push((mi, mv.clone()));
                    continue;
                }
                match &mv.offer {
                    Offer::Tau => {
                        let n = out.push_copy(st);
                        self.design.apply(m, n, mv.act, None)?;
                        out.set_label(Label::TAU);
                    }
                    Offer::In { chan, value } => {
                        let c = &self.design.channels[*chan as usize];
                        let values: Vec<Option<Val>> = match (c.params.first(), value) {
                            (_, Some(v)) => vec![Some(*v)],
                            (Some(d), None) => (d.lo..=d.hi).map(Some).collect(),
                            (None, None) => vec![None],
                        };
                        for v in values {
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, v)?;
                            let ev =
                                self.enc.events.event(self.group[*chan as usize], &v.into_iter().collect::<Vec<_>>());
                            out.set_label(Label::plain(ev));
                        }
                    }
                    Offer::Out { chan, args } => {
                        let n = out.push_copy(st);
                        self.design.apply(m, n, mv.act, None)?;
                        out.set_label(Label::plain(self.enc.events.event(self.group[*chan as usize], args)));
                    }
                }
            }
        }
        // Communications between machines are hidden.
        out.moves = moves;
        for (chan, args, n) in self.design.internal_steps(st, &internal)? {
            out.push(Label { event: TAU, note: self.enc.events.event(self.group[chan as usize], &args) }, &n);
        }
        for n in self.design.forward_steps(st) {
            out.push(Label::TAU, &n);
        }
        if self.design.machines.iter().all(|m| m.terminated(st)) {
            let n = out.push_copy(st);
            n[self.ended] = 1;
            out.set_label(Label::plain(TICK));
            // A module hides its controllers' `terminate`: a τ, which comes
            // before `tock` (RoboTool's `(… [| {|terminate|} |> SKIP) \
            // {|terminate|}` under `prioritise`, timed/defs/main_*.csp), so
            // a finished module ends at once. A machine or a controller
            // offers its visible `terminate` while time passes.
            if self.design.level == Level::Module {
                can_tock = false;
            }
        }
        // Maximal progress: time passes only when nothing internal can happen.
        let tau = out.labels()[start..].iter().any(|l| l.event == TAU);
        if can_tock && !tau && !self.untimed {
            let n = out.push_copy(st);
            self.design.advance_time(n)?;
            out.set_label(Label::TOCK);
        }
        Ok(())
    }
}

impl VectorLts for DesignLts<'_> {
    fn encoding(&self) -> &Encoding {
        &self.enc
    }

    fn initial_values(&self) -> State {
        self.design.initial_state(self.len, true, &self.enc.error).into_boxed_slice()
    }

    fn successor_values(&self, st: &[i32], out: &mut Vectors) {
        if st[self.ended] != 0 {
            return;
        }
        let start = out.len();
        if let Err(e) = self.successors_inner(st, out) {
            self.enc.error.set(e);
            out.truncate(start);
        }
    }
}

/// `lts` with the states satisfying `target` made final (no transitions)
/// and every other state kept live, so that a deadlock search finds the
/// shortest path to a target state.
pub struct Reach<'a, L: Lts> {
    /// The LTS searched.
    pub lts: &'a L,
    /// The states sought.
    pub target: &'a (dyn Fn(&L::State) -> bool + Sync),
}

impl<L: Lts> Lts for Reach<'_, L> {
    type State = L::State;

    fn initial(&self) -> L::State {
        self.lts.initial()
    }

    fn successors(&self, st: &L::State, out: &mut Vec<(Label, L::State)>) {
        if (self.target)(st) {
            return;
        }
        let start = out.len();
        self.lts.successors(st, out);
        if out.len() == start {
            // A dead end of the LTS is not a target.
            out.push((Label::TOCK, st.clone()));
        }
    }

    fn event_name(&self, event: Event) -> String {
        self.lts.event_name(event)
    }

    fn state_bytes(&self, st: &L::State) -> usize {
        self.lts.state_bytes(st)
    }

    fn state_width(&self) -> usize {
        self.lts.state_width()
    }

    fn encode(&self, st: &L::State, row: &mut [u8]) {
        self.lts.encode(st, row);
    }

    fn decode(&self, row: &[u8]) -> L::State {
        self.lts.decode(row)
    }
}

/// Reachability ([`Design::state_nodes`], [`Design::in_nodes`]) reads the
/// design alone, so every LTS built on it (plain, RoboSim cycles, the
/// simulation constraints) answers it the same way.
impl Design {
    /// The states the path `path` of a reachability assertion names, as
    /// (machine, node) pairs, read by hir's one reading of state paths
    /// ([`robosim_hir::target::match_state`], which the checker's LNK-01
    /// uses too). An error when the path names no state, or several (a
    /// verdict on the wrong state would be wrong).
    pub fn state_nodes(&self, path: &[String]) -> Result<Vec<(usize, u16)>, String> {
        use robosim_hir::target::{match_state, MachineStates, StateMatch, StateNode};
        let written = path.join("::");
        let machines: Vec<MachineStates> = self
            .machines
            .iter()
            .map(|m| MachineStates {
                instance: m.name.clone(),
                decl: m.decl_name.clone(),
                nodes: m
                    .nodes
                    .iter()
                    .map(|n| StateNode { name: n.name.clone(), parent: n.parent.map(usize::from), own: n.op.is_none() })
                    .collect(),
            })
            .collect();
        let pairs = |found: Vec<(usize, usize)>| found.into_iter().map(|(mi, ni)| (mi, ni as u16)).collect();
        match match_state(path, &machines) {
            StateMatch::None => Err(format!("`{written}` names no state of the machines checked")),
            StateMatch::Found(found) => Ok(pairs(found)),
            StateMatch::Several(found) => {
                let names: Vec<&str> = found.iter().map(|&(mi, _)| self.machines[mi].name.as_str()).collect();
                Err(format!(
                    "`{written}` names a state of several machines ({}): qualify it with the machine's name",
                    names.join(", ")
                ))
            }
        }
    }

    /// Whether a machine of the design, in the state `st` (whose first
    /// slots are the design's, in every LTS built on it), has entered (and
    /// not left) one of the states `nodes` ([`Design::state_nodes`]), or a state inside.
    pub fn in_nodes(&self, st: &[i32], nodes: &[(usize, u16)]) -> bool {
        nodes.iter().any(|&(mi, target)| {
            let m = &self.machines[mi];
            // RoboTool's reachability looks for the state's `entered`, after
            // its entry action; a composite's follows its first substate's
            // (timed/defs: `VS__` keeps `entered` visible). So the active
            // simple or final state must be past its entry action.
            let Some(leaf) = m.leaf(st) else { return false };
            let entry = &m.nodes[leaf as usize];
            let Some(entered_pc) = entry.entered_pc else { return false };
            if (entry.entry_pc..=entered_pc).contains(&m.pc(st)) {
                return false;
            }
            let mut node = Some(leaf);
            while let Some(n) = node {
                if n == target {
                    return true;
                }
                node = m.nodes[n as usize].parent;
            }
            false
        })
    }
}
