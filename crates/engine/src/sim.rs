//! A RoboSim module as an LTS (semantics.md §5, RoboTool 3 profile; the
//! paper's Rules 1–13): each cycle reads every input register (any order),
//! then runs the machines (interleaved, internal steps hidden) until every
//! one has ended its cycle with `exec` or terminated — each output written
//! at once, at most once per register per cycle — then lets `p` time units
//! pass, or terminates when every machine has. Visible: `registerRead`,
//! `registerWrite`, `tock` (and ✓); a machine or a controller on its own
//! also shows `endexec` and `terminate` (robotool-facts RT-20, RT-21).

use crate::ir::{Design, Dir, Level};
use crate::lts::{Event, Label, TAU, TICK};
use crate::machine::Offer;
use crate::pack::{Encoding, VectorLts, Vectors};
use crate::sched::{Profile, Registers, State, DONE, ENDED, READ, RUN, RUNNING, WAIT};

/// `paper2019`: writing the cycle's buffered outputs (`arg`: the outputs
/// whose absence is still to be written).
const WRITES: i32 = 3;

/// A machine or controller on its own, after its visible `endexec`: `tock`
/// and, if it has finished, `terminate` (RT-20).
const ENDX: i32 = 4;

/// A compiled RoboSim module (or controller, or machine) with period `p`.
pub struct SimModule<'a> {
    design: &'a Design,
    period: i32,
    inputs: Vec<u16>,
    outputs: Vec<u16>,
    read_group: Vec<usize>,
    write_group: Vec<usize>,
    /// RT-19: the calls of software operations: (channel, event group).
    calls: Vec<(u16, usize)>,
    /// `paper2019`: `registerWrite.o.false` per output.
    false_group: Vec<usize>,
    profile: Profile,
    terminate: Event,
    /// RT-21: `endexec` and `terminate` visible (a machine or a controller
    /// on its own, RoboTool 3 profile), or hidden (a module).
    visible_end: bool,
    endexec: Event,
    // Slots after the design's: the cycle phase and its argument (inputs
    // still to read, or time units left), outputs written this cycle, mode.
    phase: usize,
    arg: usize,
    written: usize,
    mode: usize,
    /// `paper2019`: the outputs produced in the cycle, in order (their
    /// write events; 0 = none), written after the cycle's execution.
    occ: usize,
    len: usize,
    /// Packing, run-time errors, event names.
    enc: Encoding,
}

impl<'a> SimModule<'a> {
    /// The design this LTS runs: its slots come first in every state.
    pub fn design(&self) -> &'a Design {
        self.design
    }

    /// The module with period `period`, its register events numbered by
    /// `registers`.
    pub fn new(design: &'a Design, period: u32, registers: &Registers) -> Result<SimModule<'a>, String> {
        SimModule::with_profile(design, period, registers, Profile::RoboTool3)
    }

    /// As [`SimModule::new`], in either profile: RoboTool 3 writes each
    /// output at once; the paper (Rules 4 and 12) buffers the outputs of a
    /// cycle and writes them when every machine has ended it, in order as
    /// `registerWrite.o.true.args`, then `registerWrite.o.false` for the
    /// outputs not produced.
    pub fn with_profile(
        design: &'a Design,
        period: u32,
        registers: &Registers,
        profile: Profile,
    ) -> Result<SimModule<'a>, String> {
        let (inputs, mut outputs) = (design.platform_channels(Dir::In), design.platform_channels(Dir::Out));
        // RT-19: a call of a software operation is an event, not a register.
        let mut calls = Vec::new();
        for &o in outputs.iter().filter(|&&o| design.channels[o as usize].soft_call) {
            let name = &design.channels[o as usize].name;
            let g = registers.calls.iter().find(|(n, _)| n == name).map(|(_, g)| *g);
            calls.push((o, g.ok_or_else(|| format!("no call event for `{name}`"))?));
        }
        outputs.retain(|&o| !design.channels[o as usize].soft_call);
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
        let mut false_group = Vec::new();
        for &o in &outputs {
            let name = &design.channels[o as usize].name;
            write_group.push(group(&registers.writes, name)?);
            if profile == Profile::Paper2019 {
                false_group.push(group(&registers.false_writes, name)?);
            }
        }
        let mut events = registers.table.clone();
        let g = events.add("terminate", Vec::new()).map_err(|e| e.0)?;
        let terminate = events.event(g, &[]);
        let g = events.add("endexec", Vec::new()).map_err(|e| e.0)?;
        let endexec = events.event(g, &[]);
        let visible_end = profile == Profile::RoboTool3 && design.level != Level::Module;
        let base = design.slots as usize;
        let period = period.max(1) as i32;
        let mut bounds = design.slot_bounds();
        let inputs_mask = (1i64 << inputs.len()) - 1;
        let nout = outputs.len();
        let out_mask = (1i64 << nout) - 1;
        bounds.extend([(0, ENDX as i64), (0, inputs_mask.max(out_mask).max(period as i64)), (0, out_mask), (0, 3)]);
        let max_event = events.next_event() as i64;
        bounds.extend(std::iter::repeat_n((0, max_event), outputs.len()));
        Ok(SimModule {
            design,
            period,
            inputs,
            outputs,
            read_group,
            write_group,
            calls,
            false_group,
            profile,
            terminate,
            visible_end,
            endexec,
            phase: base,
            arg: base + 1,
            written: base + 2,
            mode: base + 3,
            occ: base + 4,
            len: base + 4 + nout,
            enc: Encoding::new(&bounds, events),
        })
    }

    /// The module reading (`endexec` and `terminate` hidden) whatever the
    /// element is: for a refinement against a cycle-constrained design,
    /// whose process has no `endexec`.
    pub fn hiding_end(mut self) -> Self {
        self.visible_end = false;
        self
    }

    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        self.enc.error.get()
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
        // RT-22: what was written into a connection's memory cell last cycle
        // is read now, and the cell erased.
        for c in &self.design.channels {
            if let (Some(cell), Some(reg)) = (c.cell, c.register) {
                let (cell, reg) = (cell as usize, reg as usize);
                st[reg] = st[cell];
                st[reg + 1] = st[cell + 1];
                st[cell] = 0;
                st[cell + 1] = 0;
            }
        }
        for m in &self.design.machines {
            m.resume(st, &self.design.clocks).map_err(|e| e.0)?;
        }
        Ok(())
    }

    fn tock(&self, st: &mut [i32]) -> Result<(), String> {
        self.design.advance_time(st)?;
        let left = if matches!(st[self.phase], RUN | ENDX) { self.period - 1 } else { st[self.arg] - 1 };
        if left <= 0 {
            self.begin_cycle(st)
        } else {
            st[self.phase] = WAIT;
            st[self.arg] = left;
            Ok(())
        }
    }

    fn successors_inner(&self, st: &[i32], out: &mut Vectors) -> Result<(), String> {
        match st[self.phase] {
            READ => {
                for (i, &chan) in self.inputs.iter().enumerate() {
                    if st[self.arg] & (1 << i) == 0 {
                        continue;
                    }
                    let c = &self.design.channels[chan as usize];
                    let reg = c.register.unwrap_or_default() as usize;
                    let value_param = usize::from(!c.var);
                    let reg_lo = self.enc.events.group(self.read_group[i]).params.get(value_param).map(|p| p.dom().lo);
                    for (present, v) in c.read_values(reg_lo) {
                        let (args, n_args) = c.read_args(present, v);
                        let ev = self.enc.events.event(self.read_group[i], &args[..n_args]);
                        let n = out.push_copy(st);
                        if c.var {
                            n[reg] = v.unwrap_or(0) as i32;
                        } else {
                            n[reg] = present as i32;
                            n[reg + 1] = v.filter(|_| present == 1).unwrap_or(0) as i32;
                        }
                        n[self.arg] &= !(1 << i);
                        if n[self.arg] == 0 {
                            self.begin_run(n)?;
                        }
                        out.set_label(Label::plain(ev));
                    }
                }
            }
            RUN => {
                // A buffer reused from state to state.
                let mut moves = std::mem::take(&mut out.moves);
                moves.clear();
                let mut internal = Vec::new();
                for (mi, m) in self.design.machines.iter().enumerate() {
                    moves.clear();
                    m.moves(st, &mut moves).map_err(|e| e.0)?;
                    for mv in &moves {
                        if let Offer::Out { chan, args } = &mv.offer {
                            if let Some(cell) = self.design.channels[*chan as usize].cell {
                                // RT-22: into the connection's memory cell, a
                                // hidden step; like any output, at most once
                                // per cycle (RT-20), else the cycle cannot end.
                                let cell = cell as usize;
                                if st[cell] != 0 {
                                    continue;
                                }
                                let n = out.push_copy(st);
                                self.design.apply(m, n, mv.act, None)?;
                                n[cell] = 1;
                                n[cell + 1] = args.first().map_or(0, |&v| v as i32);
                                out.set_label(Label::TAU);
                                continue;
                            }
                        }
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
                            Offer::Out { chan, args } => {
                                if let Some(&(_, g)) = self.calls.iter().find(|(c, _)| c == chan) {
                                    // RT-19: an urgent visible event, as often as called.
                                    let call = self.enc.events.event(g, args);
                                    let n = out.push_copy(st);
                                    self.design.apply(m, n, mv.act, None)?;
                                    out.set_label(Label::plain(call));
                                    continue;
                                }
                                let Some(o) = self.outputs.iter().position(|c| c == chan) else { continue };
                                let write = self.enc.events.event(self.write_group[o], args);
                                if self.profile == Profile::Paper2019 {
                                    // Rule 12: into the buffer (as many outputs as
                                    // there are registers), written at the cycle's end.
                                    let nout = self.outputs.len();
                                    let len = (0..nout).take_while(|&j| st[self.occ + j] != 0).count();
                                    if len >= nout {
                                        continue;
                                    }
                                    let n = out.push_copy(st);
                                    self.design.apply(m, n, mv.act, None)?;
                                    n[self.occ + len] = write as i32;
                                    n[self.written] |= 1 << o;
                                    out.set_label(Label::TAU);
                                    continue;
                                }
                                // One write per register per cycle: a second one
                                // cannot happen, and the cycle never ends.
                                if st[self.written] & (1 << o) != 0 {
                                    continue;
                                }
                                let n = out.push_copy(st);
                                self.design.apply(m, n, mv.act, None)?;
                                n[self.written] |= 1 << o;
                                out.set_label(Label::plain(write));
                            }
                            Offer::In { .. } => {
                                return Err(format!("machine `{}` waits for an input event", m.name));
                            }
                        }
                    }
                }
                out.moves = moves;
                for (_, _, n) in self.design.internal_steps(st, &internal)? {
                    out.push(Label::TAU, &n);
                }
                // The cycle ends when every machine has ended its own.
                if self.design.machines.iter().all(|m| m.cycle_ended(st)) {
                    if self.profile == Profile::Paper2019 {
                        // Rule 4: then the buffered outputs are written.
                        let n = out.push_copy(st);
                        n[self.phase] = WRITES;
                        n[self.arg] = ((1i64 << self.outputs.len()) - 1) as i32 & !st[self.written];
                        out.set_label(Label::TAU);
                    } else {
                        self.end_cycle(st, out)?;
                    }
                }
            }
            ENDX => {
                // RT-20: `TimeOut_1(terminate -> SKIP, WAIT(cycle-1); Cycle)`:
                // `terminate` only if every machine has finished, and it
                // competes with `tock` (both visible, no priority).
                if self.design.machines.iter().all(|m| m.terminated(st)) {
                    let n = out.push_copy(st);
                    n[self.mode] = DONE;
                    out.set_label(Label::plain(self.terminate));
                }
                let n = out.push_copy(st);
                self.tock(n)?;
                out.set_label(Label::TOCK);
            }
            WRITES => {
                let nout = self.outputs.len();
                if nout > 0 && st[self.occ] != 0 {
                    let n = out.push_copy(st);
                    for j in 0..nout - 1 {
                        n[self.occ + j] = n[self.occ + j + 1];
                    }
                    n[self.occ + nout - 1] = 0;
                    out.set_label(Label::plain(st[self.occ] as Event));
                } else if st[self.arg] != 0 {
                    for o in (0..nout).filter(|o| st[self.arg] & (1 << o) != 0) {
                        let n = out.push_copy(st);
                        n[self.arg] &= !(1 << o);
                        out.set_label(Label::plain(self.enc.events.event(self.false_group[o], &[])));
                    }
                } else {
                    self.end_cycle(st, out)?;
                }
            }
            _ => {
                let n = out.push_copy(st);
                self.tock(n)?;
                out.set_label(Label::TOCK);
            }
        }
        Ok(())
    }

    /// The end of a cycle: termination when every machine has terminated,
    /// else time passes until the next.
    fn end_cycle(&self, st: &[i32], out: &mut Vectors) -> Result<(), String> {
        let n = out.push_copy(st);
        if self.visible_end {
            // RT-21: a machine's (a controller's: after all its machines')
            // `endexec` is visible.
            n[self.phase] = ENDX;
            out.set_label(Label::plain(self.endexec));
            return Ok(());
        }
        if self.design.machines.iter().all(|m| m.terminated(st)) {
            n[self.mode] = DONE;
            out.set_label(Label { event: TAU, note: self.terminate });
        } else {
            self.tock(n)?;
            out.set_label(Label::TOCK);
        }
        Ok(())
    }

    /// Describes the machines' control states (for counterexamples).
    pub fn describe(&self, st: &[i32]) -> Vec<(String, String)> {
        self.design.machines.iter().map(|m| (m.name.clone(), m.describe(st))).collect()
    }
}

impl VectorLts for SimModule<'_> {
    fn encoding(&self) -> &Encoding {
        &self.enc
    }

    fn initial_values(&self) -> State {
        let mut st = self.design.initial_state(self.len, false, &self.enc.error);
        st[self.mode] = RUNNING;
        if let Err(e) = self.begin_cycle(&mut st) {
            self.enc.error.set(e);
        }
        st.into_boxed_slice()
    }

    fn successor_values(&self, st: &[i32], out: &mut Vectors) {
        match st[self.mode] {
            DONE => {
                let n = out.push_copy(st);
                n[self.mode] = ENDED;
                out.set_label(Label::plain(TICK));
                return;
            }
            ENDED => return,
            _ => {}
        }
        let start = out.len();
        if let Err(e) = self.successors_inner(st, out) {
            self.enc.error.set(e);
            out.truncate(start);
        }
    }
}
