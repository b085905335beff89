//! The constrained design of a schedulability check (semantics.md §4):
//! the compiled design in parallel with the simulation assumptions, in two
//! profiles.
//!
//! - `robotool3` (§4.2–4.3, what RoboTool 3 generates): A1 (inputs are read
//!   from registers), A2 (each output is written to its register at once, at
//!   most once per period) and A3 (the cycle: reads, execution, quiescence
//!   until the next sample time), with the design's external events hidden,
//!   τ before `tock`, and RoboTool's timelock escape (`TLFree`).
//! - `paper2019` (§4.4, the paper's definitions): calls return (`opRet`),
//!   TA2 buffers the outputs of a cycle and writes them in order as
//!   `registerWrite.o.true.args`, then `false` for the others; TA3 admits
//!   one write per register and then exactly `p` tocks; external events stay
//!   visible and have priority over writes and `tock`. TA1 is the external
//!   choice (the internal one printed in the paper contradicts its verdict
//!   on Figure 13).
//!
//! `S is schedulable` holds iff this LTS has no deadlock.

use crate::events::{EventTable, Param};
use crate::ir::{Design, Dir, Dom, Val};
use crate::lts::{Event, Label, TAU, TICK, TOCK};
use crate::machine::{Act, Move, Offer};
use crate::pack::{Encoding, VectorLts, Vectors};

/// The state: the design's slots, then the assumptions'.
pub type State = Box<[i32]>;

/// What the design is doing as a whole.
pub(crate) const RUNNING: i32 = 0;
/// After `timelock`: only time passes (RoboTool's `TLFree` sink).
const SINK: i32 = 1;
/// After `terminate`: only time passes (`; RUN({tock})`), or ✓.
pub(crate) const DONE: i32 = 2;
/// After ✓: nothing.
pub(crate) const ENDED: i32 = 3;

/// A3's phases (and a RoboSim cycle's).
pub(crate) const READ: i32 = 0;
pub(crate) const RUN: i32 = 1;
pub(crate) const WAIT: i32 = 2;
/// `paper2019`: writing the registers of the cycle (`arg`: those left).
const WRITES: i32 = 3;

/// Which semantics (semantics.md §2): one definition for the checks and
/// the CSPm export.
pub use robosim_hir::profile::Profile;

/// The register events of a check (`registerRead.i_e.b.v`,
/// `registerWrite.o_e.args`; the paper profile's `registerRead.eU…`,
/// `registerWrite.eU.true…`, `registerWrite.eU.false`), numbered first in
/// every event table of the check, so that the two sides of a refinement
/// agree on them. Registers are matched by the platform's name for the
/// event or operation, as RoboTool does; their domains are the union of
/// the sides'.
#[derive(Debug, Clone)]
pub struct Registers {
    /// The table (only register events so far).
    pub table: EventTable,
    /// Read channel of each input, by name.
    pub reads: Vec<(String, usize)>,
    /// Write channel of each output, by name.
    pub writes: Vec<(String, usize)>,
    /// `paper2019`: the `false` write channel of each output.
    pub false_writes: Vec<(String, usize)>,
    /// The ids of all writes.
    pub write_range: (Event, Event),
    /// RoboSim: the call event of each software operation nothing defines
    /// (`opCall`, RT-19), by name: not a register.
    pub calls: Vec<(String, usize)>,
}

impl Registers {
    /// The registers of the inputs and outputs of `designs`.
    pub fn new(designs: &[&Design], profile: Profile) -> Result<Registers, String> {
        let paper = profile == Profile::Paper2019;
        let too_many = |e: crate::events::TooManyEvents| format!("the channel `{}` has too many values", e.0);
        // Per register: its name, parameters, and whether it is a variable.
        let mut ins: Vec<(String, Vec<Param>, bool)> = Vec::new();
        let mut outs: Vec<(String, Vec<Param>, bool)> = Vec::new();
        // RoboSim: calls of software operations (no register).
        let mut calls: Vec<(String, Vec<Param>)> = Vec::new();
        for d in designs {
            for c in d.channels.iter().filter(|c| !c.internal) {
                if c.soft_call {
                    if !calls.iter().any(|(n, _)| *n == c.name) {
                        calls.push((c.name.clone(), c.shape.clone()));
                    }
                    continue;
                }
                let list = if c.dir == Dir::In { &mut ins } else { &mut outs };
                let disagree = || format!("the two sides disagree on the arguments of `{}`", c.name);
                match list.iter_mut().find(|(n, ..)| *n == c.name) {
                    Some((_, params, var)) => {
                        if *var != c.var {
                            return Err(format!(
                                "`{}` is a variable of the platform on one side and an event or operation on the other",
                                c.name
                            ));
                        }
                        if params.len() != c.shape.len() {
                            return Err(disagree());
                        }
                        for (p, q) in params.iter_mut().zip(&c.shape) {
                            *p = p.union(q).ok_or_else(disagree)?;
                        }
                    }
                    None => list.push((c.name.clone(), c.shape.clone(), c.var)),
                }
            }
        }
        let mut table = EventTable::default();
        let mut reads = Vec::new();
        for (name, params, var) in &ins {
            // An event's register says whether it happened; a variable's
            // always holds a value.
            let mut ps = if *var { Vec::new() } else { vec![Param::Bool] };
            ps.extend(params.iter().cloned());
            let label = if paper { format!("registerRead.{name}U") } else { format!("registerRead.i_{name}") };
            reads.push((name.clone(), table.add(label, ps).map_err(too_many)?));
        }
        let first_write = table.next_event();
        let mut writes = Vec::new();
        for (name, params, _) in &outs {
            let ps = params.clone();
            let label = if paper { format!("registerWrite.{name}U.true") } else { format!("registerWrite.o_{name}") };
            writes.push((name.clone(), table.add(label, ps).map_err(too_many)?));
        }
        let mut false_writes = Vec::new();
        if paper {
            for (name, ..) in &outs {
                false_writes.push((
                    name.clone(),
                    table.add(format!("registerWrite.{name}U.false"), Vec::new()).map_err(too_many)?,
                ));
            }
        }
        let write_range = (first_write, table.next_event());
        let mut call_groups = Vec::new();
        for (name, params) in &calls {
            call_groups.push((name.clone(), table.add(format!("{name}Call"), params.clone()).map_err(too_many)?));
        }
        Ok(Registers { table, reads, writes, false_writes, write_range, calls: call_groups })
    }

    /// The read event of input `name` (`present` is ignored for a
    /// variable's register, which has no presence flag).
    pub fn read(&self, name: &str, present: bool, value: Option<Val>) -> Option<Event> {
        let g = self.reads.iter().find(|(n, _)| n == name)?.1;
        // A variable's register carries its value alone; an event's, the
        // flag and then its value (if it has one).
        let variable = value.is_some() && self.table.group(g).params.len() == 1;
        let mut args = if variable { Vec::new() } else { vec![present as Val] };
        args.extend(value);
        Some(self.table.event(g, &args))
    }

    /// The write event of output `name`.
    pub fn write(&self, name: &str, args: &[Val]) -> Option<Event> {
        let g = self.writes.iter().find(|(n, _)| n == name)?.1;
        Some(self.table.event(g, args))
    }
}

/// The constrained design of `simulation S of M` with period `p`.
pub struct Constrained<'a> {
    design: &'a Design,
    profile: Profile,
    /// Schedulability: RoboTool's timelock escape, and time passing forever
    /// after termination. Refinement: neither; termination is ✓, and in the
    /// paper profile the external events are hidden after priority
    /// (`PConstrained \ ExternalEvents`).
    tlfree: bool,
    period: i32,
    /// Channel indices of the inputs and outputs, in order.
    inputs: Vec<u16>,
    outputs: Vec<u16>,
    /// Per design channel, what its offers need (looked up for every move).
    chans: Vec<Chan>,
    /// Per input, A3's reads of its register: the event, then the values
    /// of A1's presence flag and value slots (computed once, not per state).
    read_steps: Vec<Vec<(Event, i32, i32)>>,
    /// Event groups: register reads per input, register writes per output,
    /// the design's own (hidden) events per channel, `timelock`, `terminate`.
    read_group: Vec<usize>,
    write_group: Vec<usize>,
    /// `paper2019`: `registerWrite.o.false` per output.
    false_group: Vec<usize>,
    design_group: Vec<usize>,
    /// `paper2019`: `opRet` per channel (calls only).
    ret_group: Vec<usize>,
    /// The ids of register writes (true and false) are `writes.0..writes.1`.
    writes: (Event, Event),
    timelock: Event,
    terminate: Event,
    // Slots. In `paper2019`, `avail` holds the outputs not produced yet in
    // this cycle and `pend` the absences still to write (-1: none yet).
    mode: usize,
    a1: usize,
    avail: usize,
    pend: usize,
    k: usize,
    phase: usize,
    arg: usize,
    /// `paper2019`: the outputs produced in this cycle (their write events,
    /// in order; 0 = none), and per machine the channel of a call awaiting
    /// its return (+1; 0 = none).
    occ: usize,
    ret: usize,
    len: usize,
    /// Packing, run-time errors, event names.
    enc: Encoding,
}

/// What the assumptions need to know of a design channel, per channel.
#[derive(Debug, Clone, Copy)]
struct Chan {
    /// Its index among the platform inputs (A1's registers), if it is one.
    input: Option<usize>,
    /// Its index among the platform outputs (A2's registers), if it is one.
    output: Option<usize>,
    /// Whether it carries a value (an input's value is the register's).
    has_value: bool,
    /// Its design event without arguments (most channels have none).
    event: Event,
    /// Its output's register write without arguments, if it is an output.
    write_event: Option<Event>,
}

/// The design has more outputs than the engine tracks (A2's set of outputs
/// still allowed is a bit mask).
pub const MAX_OUTPUTS: usize = 30;

impl<'a> Constrained<'a> {
    /// Builds the constrained design; fails on designs too large to encode.
    pub fn new(design: &'a Design, period: u32, profile: Profile) -> Result<Constrained<'a>, String> {
        Constrained::with_registers(design, period, profile, None, true)
    }

    /// As [`Constrained::new`], with register events numbered by `registers`
    /// (shared with the other side of a refinement), and with or without
    /// RoboTool's timelock escape (`TLFree`: for schedulability only; the
    /// specification of a refinement is the plain constrained design, which
    /// terminates with ✓).
    pub fn with_registers(
        design: &'a Design,
        period: u32,
        profile: Profile,
        registers: Option<&Registers>,
        tlfree: bool,
    ) -> Result<Constrained<'a>, String> {
        let (inputs, outputs) = (design.platform_channels(Dir::In), design.platform_channels(Dir::Out));
        if outputs.len() > MAX_OUTPUTS {
            return Err(format!("the design has {} outputs; at most {MAX_OUTPUTS} are supported", outputs.len()));
        }
        if inputs.len() > MAX_OUTPUTS {
            return Err(format!("the design has {} inputs; at most {MAX_OUTPUTS} are supported", inputs.len()));
        }
        let too_many = |e: crate::events::TooManyEvents| format!("the channel `{}` has too many values", e.0);
        let paper = profile == Profile::Paper2019;
        let regs = match registers {
            Some(r) => r.clone(),
            None => Registers::new(&[design], profile)?,
        };
        let mut events = regs.table.clone();
        let group_of = |list: &[(String, usize)], name: &str| {
            list.iter().find(|(n, _)| n == name).map(|(_, g)| *g).ok_or_else(|| format!("no register for `{name}`"))
        };
        let mut read_group = Vec::new();
        for &i in &inputs {
            read_group.push(group_of(&regs.reads, &design.channels[i as usize].name)?);
        }
        let mut write_group = Vec::new();
        let mut false_group = Vec::new();
        for &o in &outputs {
            let name = &design.channels[o as usize].name;
            write_group.push(group_of(&regs.writes, name)?);
            if paper {
                false_group.push(group_of(&regs.false_writes, name)?);
            }
        }
        let writes = regs.write_range;
        let mut design_group = vec![usize::MAX; design.channels.len()];
        let mut ret_group = vec![usize::MAX; design.channels.len()];
        for (i, c) in design.channels.iter().enumerate() {
            // The paper names a plain event without `.in`/`.out`.
            let plain = !(c.is_call || c.internal || c.var);
            let name = if paper && plain { c.name.clone() } else { crate::design::channel_name(c) };
            let params = c.shape.clone();
            design_group[i] = events.add(name, params).map_err(too_many)?;
            if paper && c.is_call {
                ret_group[i] = events.add(format!("{}Ret", c.name), Vec::new()).map_err(too_many)?;
            }
        }
        let g = events.add("timelock", Vec::new()).map_err(too_many)?;
        let timelock = events.event(g, &[]);
        let g = events.add("terminate", Vec::new()).map_err(too_many)?;
        let terminate = events.event(g, &[]);
        let mode = design.slots as usize;
        let a1 = mode + 1;
        let avail = a1 + 2 * inputs.len();
        let occ = avail + 5;
        let ret = occ + outputs.len();
        let len = ret + design.machines.len();
        // The ranges of the assumptions' slots, after the design's.
        let mut bounds = design.slot_bounds();
        let max_event = events.next_event() as i64 + 2;
        let p = period.max(1) as i64;
        bounds.push((0, 3));
        for &i in &inputs {
            let d = design.channels[i as usize].params.first().copied().unwrap_or(Dom { lo: 0, hi: 0 });
            bounds.extend([(0, 1), (d.lo.min(0), d.hi.max(0))]);
        }
        let out_mask = (1i64 << outputs.len()) - 1;
        let in_mask = (1i64 << inputs.len()) - 1;
        bounds.extend([
            (0, out_mask),
            (-1, out_mask.max(max_event)),
            (-1, p),
            (0, 3),
            (0, in_mask.max(out_mask).max(p)),
        ]);
        bounds.extend(std::iter::repeat_n((0, max_event), outputs.len()));
        bounds.extend(std::iter::repeat_n((0, design.channels.len() as i64 + 1), design.machines.len()));
        let read_steps = inputs
            .iter()
            .zip(&read_group)
            .map(|(&chan, &g)| {
                // The register's domain (shared with the other side of a check).
                let reg_lo = events.group(g).params.get(1).map(|p| p.dom().lo);
                let steps = design.channels[chan as usize].read_values(reg_lo).map(|(present, v)| {
                    let (args, n_args) = design.channels[chan as usize].read_args(present, v);
                    let ev = events.event(g, &args[..n_args]);
                    (ev, present as i32, v.filter(|_| present == 1).unwrap_or(0) as i32)
                });
                steps.collect()
            })
            .collect();
        let chans = (0..design.channels.len())
            .map(|c| Chan {
                input: inputs.iter().position(|&i| usize::from(i) == c),
                output: outputs.iter().position(|&o| usize::from(o) == c),
                has_value: !design.channels[c].params.is_empty(),
                event: events.event(design_group[c], &[]),
                write_event: outputs
                    .iter()
                    .position(|&o| usize::from(o) == c)
                    .map(|o| events.event(write_group[o], &[])),
            })
            .collect();
        Ok(Constrained {
            chans,
            read_steps,
            design,
            profile,
            tlfree,
            period: period.max(1) as i32,
            inputs,
            outputs,
            read_group,
            write_group,
            false_group,
            design_group,
            ret_group,
            writes,
            timelock,
            terminate,
            mode,
            a1,
            avail,
            pend: avail + 1,
            k: avail + 2,
            phase: avail + 3,
            arg: avail + 4,
            occ,
            ret,
            len,
            enc: Encoding::new(&bounds, events),
        })
    }

    /// The event table (register events, the design's hidden events).
    pub fn events(&self) -> &EventTable {
        &self.enc.events
    }

    /// The first run-time error met during exploration, if any.
    pub fn error(&self) -> Option<String> {
        self.enc.error.get()
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
        match args {
            // Looked up, not computed: the common case, once per move.
            [] => self.chans[chan as usize].event,
            _ => self.enc.events.event(self.design_group[chan as usize], args),
        }
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
            self.design.advance_time(st)?;
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

    /// A3 reads the input registers, in any order (A1 keeps what was read).
    fn reads(&self, st: &[i32], out: &mut Vectors) {
        if st[self.phase] != READ {
            return;
        }
        for (i, steps) in self.read_steps.iter().enumerate() {
            if st[self.arg] & (1 << i) == 0 {
                continue;
            }
            let arg = st[self.arg] & !(1 << i);
            for &(ev, present, v) in steps {
                let n = out.push_copy(st);
                n[self.a1 + 2 * i] = present;
                n[self.a1 + 2 * i + 1] = v;
                n[self.arg] = arg;
                if arg == 0 {
                    n[self.phase] = RUN;
                }
                out.set_label(Label::plain(ev));
            }
        }
    }

    /// An input the design may take now (A1): the input's index and value.
    fn input_allowed(&self, st: &[i32], chan: u16, value: Option<Val>) -> Option<(usize, Val)> {
        let i = self.chans[chan as usize].input?;
        if st[self.phase] != RUN || st[self.a1 + 2 * i] == 0 {
            return None;
        }
        let v = st[self.a1 + 2 * i + 1] as Val;
        (value.is_none_or(|x| x == v)).then_some((i, v))
    }

    /// `paper2019` TA3 on a write of output `o`: the next phase and argument.
    fn ta3_write(&self, st: &[i32], o: usize) -> Option<(i32, i32)> {
        let rem = match st[self.phase] {
            RUN => self.all_outputs() & !(1 << o),
            WRITES if st[self.arg] & (1 << o) != 0 => st[self.arg] & !(1 << o),
            _ => return None,
        };
        Some(if rem != 0 { (WRITES, rem) } else { (WAIT, self.period) })
    }

    /// `paper2019` TA2: writes of absences for the outputs in `pool`.
    fn false_writes(&self, st: &[i32], pool: i32, out: &mut Vectors) {
        for o in 0..self.outputs.len() {
            if pool & (1 << o) == 0 {
                continue;
            }
            let Some((ph, arg)) = self.ta3_write(st, o) else { continue };
            let rem = pool & !(1 << o);
            let n = out.push_copy(st);
            if rem == 0 {
                n[self.avail] = self.all_outputs();
                n[self.pend] = -1;
            } else {
                n[self.pend] = rem;
            }
            n[self.phase] = ph;
            n[self.arg] = arg;
            out.set_label(Label::plain(self.enc.events.event(self.false_group[o], &[])));
        }
    }

    fn successors_paper(&self, st: &[i32], out: &mut Vectors) -> Result<(), String> {
        let start = out.len();
        let nout = self.outputs.len();
        self.reads(st, out);
        // TA2: the outputs of the cycle in order, then the absences.
        let fm = st[self.pend];
        if fm >= 0 {
            self.false_writes(st, fm, out);
        } else if st[self.occ] != 0 {
            let head = st[self.occ] as Event;
            if let Some(o) = self.write_group.iter().position(|&g| {
                let grp = self.enc.events.group(g);
                head >= grp.base && ((head - grp.base) as u64) < grp.size
            }) {
                if let Some((ph, arg)) = self.ta3_write(st, o) {
                    let n = out.push_copy(st);
                    for j in 0..nout.saturating_sub(1) {
                        n[self.occ + j] = n[self.occ + j + 1];
                    }
                    n[self.occ + nout - 1] = 0;
                    n[self.phase] = ph;
                    n[self.arg] = arg;
                    out.set_label(Label::plain(head));
                }
            }
        } else if st[self.avail] == 0 {
            // Every output was produced and written: TA2 starts over.
            let n = out.push_copy(st);
            n[self.avail] = self.all_outputs();
            out.set_label(Label::TAU);
        } else {
            self.false_writes(st, st[self.avail], out);
        }
        let phase = st[self.phase];
        let mut design_tock = true;
        if st[self.mode] == RUNNING {
            // A buffer reused from state to state.
            let mut moves = std::mem::take(&mut out.moves);
            moves.clear();
            let mut internal = Vec::new();
            let mut returning = false;
            for (mi, m) in self.design.machines.iter().enumerate() {
                let ret = st[self.ret + mi];
                if ret != 0 {
                    // The platform returns from a call before the machine goes on.
                    returning = true;
                    design_tock = false;
                    if phase == RUN {
                        let n = out.push_copy(st);
                        n[self.ret + mi] = 0;
                        out.set_label(Label::plain(self.enc.events.event(self.ret_group[(ret - 1) as usize], &[])));
                    }
                    continue;
                }
                let from = moves.len();
                m.moves(st, &mut moves).map_err(|e| e.0)?;
                design_tock &= m.can_tock(st);
                for mv in &moves[from..] {
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
                            let Some((i, v)) = self.input_allowed(st, *chan, *value) else { continue };
                            let has_value = self.chans[*chan as usize].has_value;
                            let args: &[Val] = if has_value { &[v] } else { &[] };
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, has_value.then_some(v))?;
                            n[self.a1 + 2 * i] = 0;
                            out.set_label(Label::plain(self.design_event(*chan, args)));
                        }
                        Offer::Out { chan, args } => {
                            let Some(o) = self.chans[*chan as usize].output else { continue };
                            let len = (0..nout).take_while(|&j| st[self.occ + j] != 0).count();
                            // Order: at most one output per register per cycle is buffered.
                            if phase != RUN || fm >= 0 || len >= nout {
                                continue;
                            }
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, None)?;
                            n[self.occ + len] = self.enc.events.event(self.write_group[o], args) as i32;
                            n[self.avail] &= !(1 << o);
                            if self.design.channels[*chan as usize].is_call {
                                n[self.ret + mi] = i32::from(*chan) + 1;
                            }
                            out.set_label(Label::plain(self.design_event(*chan, args)));
                        }
                    }
                }
            }
            out.moves = moves;
            for (_, _, n) in self.design.internal_steps(st, &internal)? {
                out.push(Label::TAU, &n);
            }
            for n in self.design.forward_steps(st) {
                out.push(Label::TAU, &n);
            }
            // Termination (`end`) only at a cycle's end, before time passes.
            let terminated = !returning && self.design.machines.iter().all(|m| m.terminated(st));
            if terminated && phase == WAIT && st[self.arg] == self.period {
                let n = out.push_copy(st);
                n[self.mode] = DONE;
                out.set_label(Label { event: TAU, note: self.terminate });
            }
        }
        // TA3: exactly `p` tocks after the writes.
        if design_tock && phase == WAIT {
            let n = out.push_copy(st);
            if n[self.mode] == RUNNING {
                self.design.advance_time(n)?;
            }
            if n[self.arg] <= 1 {
                self.start_cycle(n);
            } else {
                n[self.arg] -= 1;
            }
            out.set_label(Label::TOCK);
        }
        // Priority ⟨External, {registerWrite, tock}⟩: while τ or an external
        // event is possible, no write and no tock (register reads are unranked).
        let (lo, hi) = self.writes;
        let external = out.labels()[start..]
            .iter()
            .any(|l| l.event == TAU || (l.event != TOCK && !(lo..hi).contains(&l.event) && !self.is_read(l.event)));
        if external {
            out.retain_from(start, |l| l.event != TOCK && !(lo..hi).contains(&l.event));
        }
        if !self.tlfree {
            // As the specification of a refinement: external events hidden.
            for label in &mut out.labels_mut()[start..] {
                let e = label.event;
                if e != TAU && e != TOCK && !(lo..hi).contains(&e) && !self.is_read(e) {
                    *label = Label { event: TAU, note: e };
                }
            }
        }
        Ok(())
    }

    fn is_read(&self, e: Event) -> bool {
        self.read_group.iter().any(|&g| {
            let grp = self.enc.events.group(g);
            e >= grp.base && ((e - grp.base) as u64) < grp.size
        })
    }

    fn successors_rt3(&self, st: &[i32], out: &mut Vectors) -> Result<(), String> {
        let start = out.len();
        let mode = st[self.mode];
        let phase = st[self.phase];
        if phase == READ {
            self.reads(st, out);
        }
        // A2 writes the register of the output just produced.
        if st[self.pend] != 0 {
            let n = out.push_copy(st);
            n[self.pend] = 0;
            out.set_label(Label::plain(st[self.pend] as Event));
        }
        let mut design_tau = false;
        let mut design_out = false;
        let mut design_tock = true;
        if mode == RUNNING {
            let terminated = self.design.machines.iter().all(|m| m.terminated(st));
            // A buffer reused from state to state.
            let mut moves = std::mem::take(&mut out.moves);
            moves.clear();
            let mut internal = Vec::new();
            for (mi, m) in self.design.machines.iter().enumerate() {
                // Each machine's moves after the others' (one clear per state).
                let from = moves.len();
                m.moves(st, &mut moves).map_err(|e| e.0)?;
                design_tock &= m.can_tock(st);
                for mv in &moves[from..] {
                    if self.design.is_internal(&mv.offer) {
                        internal.push((mi, mv.clone()));
                        continue;
                    }
                    match &mv.offer {
                        Offer::Tau => {
                            design_tau = true;
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, None)?;
                            out.set_label(Label::TAU);
                        }
                        // A1: inputs are taken only while executing.
                        Offer::In { .. } if phase != RUN => {}
                        Offer::In { chan, value } => {
                            let Some((i, v)) = self.input_allowed(st, *chan, *value) else { continue };
                            let has_value = self.chans[*chan as usize].has_value;
                            let args: &[Val] = if has_value { &[v] } else { &[] };
                            let note = self.design_event(*chan, args);
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, has_value.then_some(v))?;
                            n[self.a1 + 2 * i] = 0;
                            out.set_label(Label { event: TAU, note });
                        }
                        Offer::Out { chan, args } => {
                            design_out = true;
                            let Some(o) = self.chans[*chan as usize].output else { continue };
                            // A2: once per period, each output immediately written.
                            if phase != RUN || st[self.pend] != 0 || st[self.k] >= 0 || st[self.avail] & (1 << o) == 0 {
                                continue;
                            }
                            let note = self.design_event(*chan, args);
                            let n = out.push_copy(st);
                            self.design.apply(m, n, mv.act, None)?;
                            let write = match (args.as_slice(), self.chans[*chan as usize].write_event) {
                                ([], Some(e)) => e,
                                _ => self.enc.events.event(self.write_group[o], args),
                            };
                            n[self.pend] = write as i32;
                            n[self.avail] &= !(1 << o);
                            out.set_label(Label { event: TAU, note });
                        }
                    }
                }
            }
            out.moves = moves;
            for (chan, args, n) in self.design.internal_steps(st, &internal)? {
                design_tau = true;
                out.push(Label { event: TAU, note: self.design_event(chan, &args) }, &n);
            }
            for n in self.design.forward_steps(st) {
                design_tau = true;
                out.push(Label::TAU, &n);
            }
            if terminated {
                design_tau = true;
                if st[self.pend] == 0 && st[self.k] < 0 && phase == RUN {
                    let n = out.push_copy(st);
                    n[self.mode] = DONE;
                    out.set_label(Label { event: TAU, note: self.terminate });
                }
            }
            // TLFree: a design that can do nothing at all — no internal step,
            // no output, not even let time pass — may signal `timelock` and
            // then only let time pass, so that input deadlines the
            // environment must meet are not blamed on scheduling.
            if self.tlfree && !design_tau && !design_out && !design_tock {
                let n = out.push_copy(st);
                n[self.mode] = SINK;
                out.set_label(Label::plain(self.timelock));
            }
        }
        // Time passes when the design, A2 (no pending write) and A3 (not
        // reading) allow it, and nothing internal is possible.
        let tau_here = out.labels()[start..].iter().any(|l| l.event == TAU);
        let design_allows = match mode {
            RUNNING => design_tock,
            _ => true,
        };
        if !tau_here && design_allows && st[self.pend] == 0 && phase != READ {
            let n = out.push_copy(st);
            self.tock(n)?;
            out.set_label(Label::TOCK);
        }
        Ok(())
    }
}

impl VectorLts for Constrained<'_> {
    fn encoding(&self) -> &Encoding {
        &self.enc
    }

    fn initial_values(&self) -> State {
        let mut st = self.design.initial_state(self.len, true, &self.enc.error);
        st[self.mode] = RUNNING;
        st[self.avail] = self.all_outputs();
        st[self.pend] = if self.profile == Profile::Paper2019 { -1 } else { 0 };
        st[self.k] = -1;
        self.start_cycle(&mut st);
        st.into_boxed_slice()
    }

    fn successor_values(&self, st: &[i32], out: &mut Vectors) {
        if st[self.mode] == DONE {
            // Termination is success: in a schedulability check time passes
            // forever (`; RUN({tock})`); otherwise the process ends (✓).
            if self.tlfree {
                out.push(Label::TOCK, st);
            } else {
                let n = out.push_copy(st);
                n[self.mode] = ENDED;
                out.set_label(Label::plain(TICK));
            }
            return;
        }
        if st[self.mode] == ENDED {
            return;
        }
        let start = out.len();
        let result = match self.profile {
            Profile::RoboTool3 => self.successors_rt3(st, out),
            Profile::Paper2019 => self.successors_paper(st, out),
        };
        if let Err(e) = result {
            self.enc.error.set(e);
            // Keep the search going elsewhere; the verdict becomes inconclusive.
            out.truncate(start);
            out.push(Label::TOCK, st);
        }
    }
}

/// Whether `act` started a transition (for explanations).
pub fn fired(act: Act) -> Option<u16> {
    match act {
        Act::Fire(t) | Act::Junction(t) => Some(t),
        _ => None,
    }
}
