//! A RoboSim module as an LTS (semantics.md §5, RoboTool 3 profile; the
//! paper's Rules 1–13): each cycle reads every input register (any order),
//! then runs the machines (interleaved, internal steps hidden) until every
//! one has ended its cycle with `exec` or terminated — each output written
//! at once, at most once per register per cycle — then lets `p` time units
//! pass, or terminates when every machine has. Visible: `registerRead`,
//! `registerWrite`, `tock` (and ✓).

use std::sync::Mutex;

use crate::events::EventTable;
use crate::ir::{Design, Dir, Val};
use crate::lts::{Event, Label, Lts, TAU, TICK, TOCK};
use crate::machine::Offer;
use crate::sched::{Registers, State};

const READ: i32 = 0;
const RUN: i32 = 1;
const WAIT: i32 = 2;

const RUNNING: i32 = 0;
const DONE: i32 = 1;
const ENDED: i32 = 2;

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
    error: Mutex<Option<String>>,
}

impl<'a> SimModule<'a> {
    /// The module with period `period`, its register events numbered by
    /// `registers`.
    pub fn new(design: &'a Design, period: u32, registers: &Registers) -> Result<SimModule<'a>, String> {
        let inputs: Vec<u16> =
            design.channels.iter().enumerate().filter(|(_, c)| c.dir == Dir::In).map(|(i, _)| i as u16).collect();
        let outputs: Vec<u16> =
            design.channels.iter().enumerate().filter(|(_, c)| c.dir == Dir::Out).map(|(i, _)| i as u16).collect();
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
        Ok(SimModule {
            design,
            period: period.max(1) as i32,
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
            error: Mutex::new(None),
        })
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
        for c in &self.design.clocks {
            let v = &mut st[c.slot as usize];
            *v = (*v + 1).min(c.cap);
        }
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
                    for present in [1, 0] {
                        let values: Vec<Option<Val>> = match c.params.first() {
                            Some(d) if present == 1 => (d.lo..=d.hi).map(Some).collect(),
                            Some(d) => vec![Some(reg_lo.unwrap_or(d.lo))],
                            None => vec![None],
                        };
                        for v in values {
                            let mut args = vec![present];
                            args.extend(v);
                            let ev = self.events.event(self.read_group[i], &args);
                            let mut n = st.clone();
                            n[reg] = present as i32;
                            n[reg + 1] = v.unwrap_or(0) as i32;
                            n[self.arg] &= !(1 << i);
                            if n[self.arg] == 0 {
                                self.begin_run(&mut n)?;
                            }
                            out.push((Label::plain(ev), n));
                        }
                    }
                }
            }
            RUN => {
                let mut moves = Vec::new();
                for m in &self.design.machines {
                    moves.clear();
                    m.moves(st, &mut moves).map_err(|e| e.0)?;
                    for mv in &moves {
                        match &mv.offer {
                            Offer::Tau => {
                                let mut n = st.clone();
                                m.apply(&mut n, &self.design.clocks, mv.act, None).map_err(|e| e.0)?;
                                out.push((Label::TAU, n));
                            }
                            Offer::Out { chan, args } => {
                                let Some(o) = self.outputs.iter().position(|c| c == chan) else { continue };
                                // One write per register per cycle: a second one
                                // cannot happen, and the cycle never ends.
                                if st[self.written] & (1 << o) != 0 {
                                    continue;
                                }
                                let mut n = st.clone();
                                m.apply(&mut n, &self.design.clocks, mv.act, None).map_err(|e| e.0)?;
                                n[self.written] |= 1 << o;
                                out.push((Label::plain(self.events.event(self.write_group[o], args)), n));
                            }
                            Offer::In { .. } => {
                                return Err(format!("machine `{}` waits for an input event", m.name));
                            }
                        }
                    }
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

impl Lts for SimModule<'_> {
    type State = State;

    fn initial(&self) -> State {
        let mut st = vec![0i32; self.len];
        for v in &self.design.vars {
            st[v.slot as usize] = v.init as i32;
        }
        for m in &self.design.machines {
            m.init_cycle(&mut st);
        }
        st[self.mode] = RUNNING;
        if let Err(e) = self.begin_cycle(&mut st) {
            self.fail(e);
        }
        st.into_boxed_slice()
    }

    fn successors(&self, st: &State, out: &mut Vec<(Label, State)>) {
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
            self.fail(e);
            out.truncate(start);
        }
    }

    fn event_name(&self, event: Event) -> String {
        match event {
            TAU => "τ".into(),
            TICK => "✓".into(),
            TOCK => "tock".into(),
            e => self.events.name(e).unwrap_or_else(|| format!("e{e}")),
        }
    }

    fn state_bytes(&self, st: &State) -> usize {
        std::mem::size_of::<State>() + std::mem::size_of_val(&st[..])
    }
}
