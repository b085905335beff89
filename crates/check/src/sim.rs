//! A RoboSim module as an LTS (semantics.md §5, RoboTool 3 profile; the
//! paper's Rules 1–13): each cycle reads every input register (any order),
//! then runs the machines (interleaved, internal steps hidden) until every
//! one has ended its cycle with `exec` or terminated — each output written
//! at once, at most once per register per cycle — then lets `p` time units
//! pass, or terminates when every machine has. Visible: `registerRead`,
//! `registerWrite`, `tock` (and ✓).

use crate::events::EventTable;
use crate::ir::{Design, Dir};
use crate::lts::{event_name_in, Event, FirstError, Label, Lts, TAU, TICK};
use crate::machine::Offer;
use crate::pack::{initial_packed, successors_packed, Layout, Packed};
use crate::sched::{Registers, State, DONE, ENDED, READ, RUN, RUNNING, WAIT};

/// A compiled RoboSim module (or controller, or machine) with period `p`.
pub struct SimModule<'a> {
    design: &'a Design,
    period: i32,
    inputs: Vec<u16>,
    outputs: Vec<u16>,
    events: EventTable,
    read_group: Vec<usize>,
    write_group: Vec<usize>,
    terminate: Event,
    // Slots after the design's: the cycle phase and its argument (inputs
    // still to read, or time units left), outputs written this cycle, mode.
    phase: usize,
    arg: usize,
    written: usize,
    mode: usize,
    len: usize,
    layout: Layout,
    error: FirstError,
}

impl<'a> SimModule<'a> {
    /// The module with period `period`, its register events numbered by
    /// `registers`.
    pub fn new(design: &'a Design, period: u32, registers: &Registers) -> Result<SimModule<'a>, String> {
        let inputs: Vec<u16> = design
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.dir == Dir::In && !c.internal)
            .map(|(i, _)| i as u16)
            .collect();
        let outputs: Vec<u16> = design
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.dir == Dir::Out && !c.internal)
            .map(|(i, _)| i as u16)
            .collect();
        if inputs.len() > 30 || outputs.len() > 30 {
            return Err("at most 30 inputs and 30 outputs are supported".into());
        }
        let group = |list: &[(String, usize)], name: &str| {
            list.iter().find(|(n, _)| n == name).map(|(_, g)| *g).ok_or_else(|| format!("no register for `{name}`"))
        };
        let mut read_group = Vec::new();
        for &i in &inputs {
            let c = &design.channels[i as usize];
            if c.register.is_none() {
                return Err(format!("input `{}` has no register", c.name));
            }
            read_group.push(group(&registers.reads, &c.name)?);
        }
        let mut write_group = Vec::new();
        for &o in &outputs {
            write_group.push(group(&registers.writes, &design.channels[o as usize].name)?);
        }
        let mut events = registers.table.clone();
        let g = events.add("terminate", Vec::new()).map_err(|e| e.0)?;
        let terminate = events.event(g, &[]);
        let base = design.slots as usize;
        let period = period.max(1) as i32;
        let mut bounds = design.slot_bounds();
        let inputs_mask = (1i64 << inputs.len()) - 1;
        bounds.extend([(0, 2), (0, inputs_mask.max(period as i64)), (0, (1i64 << outputs.len()) - 1), (0, 3)]);
        let layout = Layout::new(&bounds);
        Ok(SimModule {
            design,
            period,
            inputs,
            outputs,
            events,
            read_group,
            write_group,
            terminate,
            phase: base,
            arg: base + 1,
            written: base + 2,
            mode: base + 3,
            len: base + 4,
            layout,
            error: FirstError::default(),
        })
    }

    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        self.error.get()
    }

    /// The next cycle: reads, or straight to execution without inputs.
    fn begin_cycle(&self, st: &mut [i32]) -> Result<(), String> {
        if self.inputs.is_empty() {
            self.begin_run(st)
        } else {
            st[self.phase] = READ;
            st[self.arg] = ((1u64 << self.inputs.len()) - 1) as i32;
            Ok(())
        }
    }

    /// After the reads: every machine resumes where its last cycle ended.
    fn begin_run(&self, st: &mut [i32]) -> Result<(), String> {
        st[self.phase] = RUN;
        st[self.written] = 0;
        for m in &self.design.machines {
            m.resume(st, &self.design.clocks).map_err(|e| e.0)?;
        }
        Ok(())
    }

    fn tock(&self, st: &mut [i32]) -> Result<(), String> {
        self.design.advance_time(st)?;
        let left = if st[self.phase] == RUN { self.period - 1 } else { st[self.arg] - 1 };
        if left <= 0 {
            self.begin_cycle(st)
        } else {
            st[self.phase] = WAIT;
            st[self.arg] = left;
            Ok(())
        }
    }

    fn successors_inner(&self, st: &State, out: &mut Vec<(Label, State)>) -> Result<(), String> {
        match st[self.phase] {
            READ => {
                for (i, &chan) in self.inputs.iter().enumerate() {
                    if st[self.arg] & (1 << i) == 0 {
                        continue;
                    }
                    let c = &self.design.channels[chan as usize];
                    let reg = c.register.unwrap_or_default() as usize;
                    let reg_lo = self.events.group(self.read_group[i]).params.get(1).map(|p| p.dom().lo);
                    for (present, v) in c.read_values(reg_lo) {
                        let mut args = vec![present];
                        args.extend(v);
                        let ev = self.events.event(self.read_group[i], &args);
                        let mut n = st.clone();
                        n[reg] = present as i32;
                        n[reg + 1] = v.filter(|_| present == 1).unwrap_or(0) as i32;
                        n[self.arg] &= !(1 << i);
                        if n[self.arg] == 0 {
                            self.begin_run(&mut n)?;
                        }
                        out.push((Label::plain(ev), n));
                    }
                }
            }
            RUN => {
                let mut moves = Vec::new();
                let mut internal = Vec::new();
                for (mi, m) in self.design.machines.iter().enumerate() {
                    moves.clear();
                    m.moves(st, &mut moves).map_err(|e| e.0)?;
                    for mv in &moves {
                        if self.design.is_internal(&mv.offer) {
                            internal.push((mi, mv.clone()));
                            continue;
                        }
                        match &mv.offer {
                            Offer::Tau => {
                                let n = self.design.after(m, st, mv.act, None)?;
                                out.push((Label::TAU, n));
                            }
                            Offer::Out { chan, args } => {
                                let Some(o) = self.outputs.iter().position(|c| c == chan) else { continue };
                                // One write per register per cycle: a second one
                                // cannot happen, and the cycle never ends.
                                if st[self.written] & (1 << o) != 0 {
                                    continue;
                                }
                                let mut n = self.design.after(m, st, mv.act, None)?;
                                n[self.written] |= 1 << o;
                                out.push((Label::plain(self.events.event(self.write_group[o], args)), n));
                            }
                            Offer::In { .. } => {
                                return Err(format!("machine `{}` waits for an input event", m.name));
                            }
                        }
                    }
                }
                for (_, _, n) in self.design.internal_steps(st, &internal)? {
                    out.push((Label::TAU, n));
                }
                // The cycle ends when every machine has ended its own.
                if self.design.machines.iter().all(|m| m.cycle_ended(st)) {
                    if self.design.machines.iter().all(|m| m.terminated(st)) {
                        let mut n = st.clone();
                        n[self.mode] = DONE;
                        out.push((Label { event: TAU, note: self.terminate }, n));
                    } else {
                        let mut n = st.clone();
                        self.tock(&mut n)?;
                        out.push((Label::TOCK, n));
                    }
                }
            }
            _ => {
                let mut n = st.clone();
                self.tock(&mut n)?;
                out.push((Label::TOCK, n));
            }
        }
        Ok(())
    }

    /// Describes the machines' control states (for counterexamples).
    pub fn describe(&self, st: &[i32]) -> Vec<(String, String)> {
        self.design.machines.iter().map(|m| (m.name.clone(), m.describe(st))).collect()
    }
}

impl SimModule<'_> {
    /// The initial state vector.
    pub fn initial_values(&self) -> State {
        let (mut st, _) = self.design.initial_state(self.len, false);
        st[self.mode] = RUNNING;
        if let Err(e) = self.begin_cycle(&mut st) {
            self.error.set(e);
        }
        st.into_boxed_slice()
    }

    fn successor_values(&self, st: &State, out: &mut Vec<(Label, State)>) {
        match st[self.mode] {
            DONE => {
                let mut n = st.clone();
                n[self.mode] = ENDED;
                out.push((Label::plain(TICK), n));
                return;
            }
            ENDED => return,
            _ => {}
        }
        let start = out.len();
        if let Err(e) = self.successors_inner(st, out) {
            self.error.set(e);
            out.truncate(start);
        }
    }

    /// The state vector of a packed state.
    pub fn values(&self, st: &Packed) -> State {
        self.layout.unpack(st)
    }
}

impl Lts for SimModule<'_> {
    type State = Packed;

    fn initial(&self) -> Packed {
        initial_packed(&self.layout, &self.error, &self.initial_values())
    }

    fn successors(&self, st: &Packed, out: &mut Vec<(Label, Packed)>) {
        successors_packed(&self.layout, &self.error, st, out, |v, next| self.successor_values(v, next));
    }

    fn event_name(&self, event: Event) -> String {
        event_name_in(&self.events, event)
    }

    fn state_bytes(&self, st: &Packed) -> usize {
        std::mem::size_of::<Packed>() + st.heap_bytes()
    }
}
