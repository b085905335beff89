//! The constrained design of a schedulability check (semantics.md §4.2–4.3,
//! RoboTool 3 profile): the compiled design in parallel with the
//! simulation assumptions A1 (inputs are read from registers), A2 (each
//! output is written to its register, at most once per period) and A3 (the
//! cycle: reads, execution, quiescence until the next sample time), with
//! the design's external events hidden, τ before `tock`, and RoboTool's
//! timelock escape (`TLFree`). `S is schedulable` holds iff this LTS has
//! no deadlock.

use std::sync::Mutex;

use crate::events::{EventTable, Param};
use crate::ir::{Design, Dir, Val};
use crate::lts::{Event, Label, Lts, TAU, TOCK};
use crate::machine::{Act, Move, Offer};

/// The state: the design's slots, then the assumptions'.
pub type State = Box<[i32]>;

/// What the design is doing as a whole.
const RUNNING: i32 = 0;
/// After `timelock`: only time passes (RoboTool's `TLFree` sink).
const SINK: i32 = 1;
/// After `terminate`: only time passes (`; RUN({tock})`).
const DONE: i32 = 2;

/// A3's phases.
const READ: i32 = 0;
const RUN: i32 = 1;
const WAIT: i32 = 2;

/// The constrained design of `simulation S of M` with period `p`.
pub struct Constrained<'a> {
    design: &'a Design,
    period: i32,
    /// Channel indices of the inputs and outputs, in order.
    inputs: Vec<u16>,
    outputs: Vec<u16>,
    events: EventTable,
    /// Event groups: register reads per input, register writes per output,
    /// the design's own (hidden) events per channel, `timelock`, `terminate`.
    read_group: Vec<usize>,
    write_group: Vec<usize>,
    design_group: Vec<usize>,
    timelock: Event,
    terminate: Event,
    // Slots.
    mode: usize,
    a1: usize,
    avail: usize,
    pend: usize,
    k: usize,
    phase: usize,
    arg: usize,
    len: usize,
    /// The first run-time error met (division by zero …): the search
    /// result is then inconclusive.
    error: Mutex<Option<String>>,
}

/// The design has more outputs than the engine tracks (A2's set of outputs
/// still allowed is a bit mask).
pub const MAX_OUTPUTS: usize = 30;

impl<'a> Constrained<'a> {
    /// Builds the constrained design; fails on designs too large to encode.
    pub fn new(design: &'a Design, period: u32) -> Result<Constrained<'a>, String> {
        let inputs: Vec<u16> =
            design.channels.iter().enumerate().filter(|(_, c)| c.dir == Dir::In).map(|(i, _)| i as u16).collect();
        let outputs: Vec<u16> =
            design.channels.iter().enumerate().filter(|(_, c)| c.dir == Dir::Out).map(|(i, _)| i as u16).collect();
        if outputs.len() > MAX_OUTPUTS {
            return Err(format!("the design has {} outputs; at most {MAX_OUTPUTS} are supported", outputs.len()));
        }
        if inputs.len() > MAX_OUTPUTS {
            return Err(format!("the design has {} inputs; at most {MAX_OUTPUTS} are supported", inputs.len()));
        }
        let mut events = EventTable::default();
        let too_many = |e: crate::events::TooManyEvents| format!("the channel `{}` has too many values", e.0);
        let mut read_group = Vec::new();
        let mut write_group = Vec::new();
        let mut design_group = vec![usize::MAX; design.channels.len()];
        for &i in &inputs {
            let c = &design.channels[i as usize];
            let mut params = vec![Param::Bool];
            params.extend(c.params.iter().map(|&d| Param::Num(d)));
            read_group.push(events.add(format!("registerRead.i_{}", c.name), params).map_err(too_many)?);
        }
        for &o in &outputs {
            let c = &design.channels[o as usize];
            let params = c.params.iter().map(|&d| Param::Num(d)).collect();
            write_group.push(events.add(format!("registerWrite.o_{}", c.name), params).map_err(too_many)?);
        }
        for (i, c) in design.channels.iter().enumerate() {
            let name = match (c.is_call, c.dir) {
                (true, _) => format!("{}Call", c.name),
                (false, Dir::In) => format!("{}.in", c.name),
                (false, Dir::Out) => format!("{}.out", c.name),
            };
            let params = c.params.iter().map(|&d| Param::Num(d)).collect();
            design_group[i] = events.add(name, params).map_err(too_many)?;
        }
        let g = events.add("timelock", Vec::new()).map_err(too_many)?;
        let timelock = events.event(g, &[]);
        let g = events.add("terminate", Vec::new()).map_err(too_many)?;
        let terminate = events.event(g, &[]);
        let mode = design.slots as usize;
        let a1 = mode + 1;
        let avail = a1 + 2 * inputs.len();
        Ok(Constrained {
            design,
            period: period.max(1) as i32,
            inputs,
            outputs,
            events,
            read_group,
            write_group,
            design_group,
            timelock,
            terminate,
            mode,
            a1,
            avail,
            pend: avail + 1,
            k: avail + 2,
            phase: avail + 3,
            arg: avail + 4,
            len: avail + 5,
            error: Mutex::new(None),
        })
    }

    /// The event table (register events, the design's hidden events).
    pub fn events(&self) -> &EventTable {
        &self.events
    }

    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        self.error.lock().ok().and_then(|e| e.clone())
    }

    fn fail(&self, msg: String) {
        if let Ok(mut e) = self.error.lock() {
            e.get_or_insert(msg);
        }
    }

    fn all_inputs(&self) -> i32 {
        ((1u64 << self.inputs.len()) - 1) as i32
    }

    fn all_outputs(&self) -> i32 {
        ((1u64 << self.outputs.len()) - 1) as i32
    }

    /// A3 after its read phase (or straight to `Run` without inputs).
    fn start_cycle(&self, st: &mut [i32]) {
        if self.inputs.is_empty() {
            st[self.phase] = RUN;
            st[self.arg] = 0;
        } else {
            st[self.phase] = READ;
            st[self.arg] = self.all_inputs();
        }
    }

    /// The name of the design's hidden event for a machine offer.
    fn design_event(&self, chan: u16, args: &[Val]) -> Event {
        self.events.event(self.design_group[chan as usize], args)
    }

    /// Describes the machines' control states (for counterexamples).
    pub fn describe(&self, st: &[i32]) -> Vec<(String, String)> {
        self.design.machines.iter().map(|m| (m.name.clone(), m.describe(st))).collect()
    }

    /// A3's phase, in words.
    pub fn phase(&self, st: &[i32]) -> String {
        match st[self.phase] {
            READ => "reading inputs".into(),
            RUN => "executing".into(),
            _ => format!("waiting for the next cycle ({} time units left)", st[self.arg]),
        }
    }

    /// Whether the design has terminated.
    pub fn is_done(&self, st: &[i32]) -> bool {
        st[self.mode] == DONE
    }

    /// Whether the design took the timelock escape.
    pub fn is_sink(&self, st: &[i32]) -> bool {
        st[self.mode] == SINK
    }

    /// Outputs already written in this period (A2), by platform name.
    pub fn written(&self, st: &[i32]) -> Vec<String> {
        self.outputs
            .iter()
            .enumerate()
            .filter(|(i, _)| st[self.avail] & (1 << i) == 0)
            .map(|(_, &o)| self.design.channels[o as usize].name.clone())
            .collect()
    }

    /// The design's pending moves in `st` (for explanations).
    pub fn design_moves(&self, st: &[i32]) -> Vec<(String, Move)> {
        let mut all = Vec::new();
        for m in &self.design.machines {
            let mut out = Vec::new();
            if m.moves(st, &mut out).is_ok() {
                all.extend(out.into_iter().map(|mv| (m.name.clone(), mv)));
            }
        }
        all
    }

    /// Whether a machine must act before time can pass.
    pub fn urgent_machines(&self, st: &[i32]) -> Vec<String> {
        self.design.machines.iter().filter(|m| !m.can_tock(st)).map(|m| m.name.clone()).collect()
    }

    fn tock(&self, st: &mut [i32]) -> Result<(), String> {
        if st[self.mode] == RUNNING {
            for c in &self.design.clocks {
                let v = &mut st[c.slot as usize];
                *v = (*v + 1).min(c.cap);
            }
            for m in &self.design.machines {
                m.tock(st, &self.design.clocks).map_err(|e| e.0)?;
            }
        }
        // A2: the period counter.
        let k = if st[self.k] < 0 { self.period - 1 } else { st[self.k] - 1 };
        if k <= 0 {
            st[self.avail] = self.all_outputs();
            st[self.k] = -1;
        } else {
            st[self.k] = k;
        }
        // A3: the first tock ends the execution phase.
        let left = if st[self.phase] == RUN { self.period - 1 } else { st[self.arg] - 1 };
        if left <= 0 {
            self.start_cycle(st);
        } else {
            st[self.phase] = WAIT;
            st[self.arg] = left;
        }
        Ok(())
    }

    fn successors_inner(&self, st: &State, out: &mut Vec<(Label, State)>) -> Result<(), String> {
        let start = out.len();
        let mode = st[self.mode];
        let phase = st[self.phase];
        // A3 reads the input registers, in any order.
        if phase == READ {
            for (i, &chan) in self.inputs.iter().enumerate() {
                if st[self.arg] & (1 << i) == 0 {
                    continue;
                }
                let c = &self.design.channels[chan as usize];
                let dom = c.params.first().copied();
                for present in [1, 0] {
                    // The value of an absent input is never observed: one
                    // representative stands for all.
                    let values: Vec<Option<Val>> = match dom {
                        Some(d) if present == 1 => (d.lo..=d.hi).map(Some).collect(),
                        Some(d) => vec![Some(d.lo)],
                        None => vec![None],
                    };
                    for v in values {
                        let mut args = vec![present];
                        args.extend(v);
                        let ev = self.events.event(self.read_group[i], &args);
                        let mut n = st.clone();
                        n[self.a1 + 2 * i] = present as i32;
                        n[self.a1 + 2 * i + 1] = v.unwrap_or(0) as i32;
                        n[self.arg] &= !(1 << i);
                        if n[self.arg] == 0 {
                            n[self.phase] = RUN;
                        }
                        out.push((Label::plain(ev), n));
                    }
                }
            }
        }
        // A2 writes the register of the output just produced.
        if st[self.pend] != 0 {
            let mut n = st.clone();
            n[self.pend] = 0;
            out.push((Label::plain(st[self.pend] as Event), n));
        }
        let mut design_tau = false;
        let mut design_out = false;
        let mut design_tock = true;
        if mode == RUNNING {
            let terminated = self.design.machines.iter().all(|m| m.terminated(st));
            let mut moves = Vec::new();
            for (mi, m) in self.design.machines.iter().enumerate() {
                moves.clear();
                m.moves(st, &mut moves).map_err(|e| e.0)?;
                design_tock &= m.can_tock(st);
                for mv in &moves {
                    match &mv.offer {
                        Offer::Tau => {
                            design_tau = true;
                            let mut n = st.clone();
                            m.apply(&mut n, &self.design.clocks, mv.act, None).map_err(|e| e.0)?;
                            out.push((Label::TAU, n));
                        }
                        Offer::In { chan, value } => {
                            let Some(i) = self.inputs.iter().position(|c| c == chan) else { continue };
                            // A1: only an input read as present, with its value.
                            if phase != RUN || st[self.a1 + 2 * i] == 0 {
                                continue;
                            }
                            let v = st[self.a1 + 2 * i + 1] as Val;
                            if value.is_some_and(|x| x != v) {
                                continue;
                            }
                            let has_value = !self.design.channels[*chan as usize].params.is_empty();
                            let args: Vec<Val> = if has_value { vec![v] } else { vec![] };
                            let note = self.design_event(*chan, &args);
                            let mut n = st.clone();
                            m.apply(&mut n, &self.design.clocks, mv.act, has_value.then_some(v)).map_err(|e| e.0)?;
                            n[self.a1 + 2 * i] = 0;
                            out.push((Label { event: TAU, note }, n));
                        }
                        Offer::Out { chan, args } => {
                            design_out = true;
                            let Some(o) = self.outputs.iter().position(|c| c == chan) else { continue };
                            // A2: once per period, each output immediately written.
                            if phase != RUN || st[self.pend] != 0 || st[self.k] >= 0 || st[self.avail] & (1 << o) == 0 {
                                continue;
                            }
                            let note = self.design_event(*chan, args);
                            let mut n = st.clone();
                            m.apply(&mut n, &self.design.clocks, mv.act, None).map_err(|e| e.0)?;
                            n[self.pend] = self.events.event(self.write_group[o], args) as i32;
                            n[self.avail] &= !(1 << o);
                            out.push((Label { event: TAU, note }, n));
                        }
                    }
                }
                let _ = mi;
            }
            if terminated {
                design_tau = true;
                if st[self.pend] == 0 && st[self.k] < 0 && phase == RUN {
                    let mut n = st.clone();
                    n[self.mode] = DONE;
                    out.push((Label { event: TAU, note: self.terminate }, n));
                }
            }
            // TLFree: a design that can do nothing at all — no internal step,
            // no output, not even let time pass — may signal `timelock` and
            // then only let time pass, so that input deadlines the
            // environment must meet are not blamed on scheduling.
            if !design_tau && !design_out && !design_tock {
                let mut n = st.clone();
                n[self.mode] = SINK;
                out.push((Label::plain(self.timelock), n));
            }
        }
        // Time passes when the design, A2 (no pending write) and A3 (not
        // reading) allow it, and nothing internal is possible.
        let tau_here = out[start..].iter().any(|(l, _)| l.event == TAU);
        let design_allows = match mode {
            RUNNING => design_tock,
            _ => true,
        };
        if !tau_here && design_allows && st[self.pend] == 0 && phase != READ {
            let mut n = st.clone();
            self.tock(&mut n)?;
            out.push((Label::TOCK, n));
        }
        Ok(())
    }
}

impl Lts for Constrained<'_> {
    type State = State;

    fn initial(&self) -> State {
        let mut st = vec![0i32; self.len];
        for v in &self.design.vars {
            st[v.slot as usize] = v.init as i32;
        }
        for m in &self.design.machines {
            m.init(&mut st);
            if let Err(e) = m.settle(&mut st, &self.design.clocks, true) {
                self.fail(e.0);
            }
        }
        st[self.mode] = RUNNING;
        st[self.avail] = self.all_outputs();
        st[self.pend] = 0;
        st[self.k] = -1;
        self.start_cycle(&mut st);
        st.into_boxed_slice()
    }

    fn successors(&self, st: &State, out: &mut Vec<(Label, State)>) {
        if st[self.mode] == DONE {
            // Termination is success: time passes forever.
            out.push((Label::TOCK, st.clone()));
            return;
        }
        let start = out.len();
        if let Err(e) = self.successors_inner(st, out) {
            self.fail(e);
            // Keep the search going elsewhere; the verdict becomes inconclusive.
            out.truncate(start);
            out.push((Label::TOCK, st.clone()));
        }
    }

    fn event_name(&self, event: Event) -> String {
        match event {
            TAU => "τ".into(),
            TOCK => "tock".into(),
            e => self.events.name(e).unwrap_or_else(|| format!("e{e}")),
        }
    }

    fn state_bytes(&self, st: &State) -> usize {
        std::mem::size_of::<State>() + std::mem::size_of_val(&st[..])
    }
}

/// Whether `act` started a transition (for explanations).
pub fn fired(act: Act) -> Option<u16> {
    match act {
        Act::Fire(t) | Act::Junction(t) => Some(t),
        _ => None,
    }
}
