//! Execution of a compiled machine over a flat state vector: what it offers
//! in a state, and the effect of each step (semantics.md §4.1).
//!
//! Deterministic internal work (assignments, clock resets, entering states,
//! exits, conditionals) runs to completion inside the step that starts it —
//! FDR's `chase` — so a machine only stops where it offers something: a
//! communication, a choice, a wait, a resting state or a junction.

use crate::ir::*;

/// Offsets of a machine's control slots from its `base`.
const LEAF: usize = 0;
const PC: usize = 1;
const WAIT: usize = 2;
const TRANS: usize = 3;
/// Time units left to finish a statement with a deadline (-1: none).
const DEADLINE: usize = 4;

/// The most internal instructions one step may run before we call it a
/// loop (a model error such a machine would be stuck in).
const MAX_INTERNAL: usize = 100_000;

/// What a machine offers to its environment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Offer {
    /// An internal step.
    Tau,
    /// An input on a channel: a required value, or any (`e?x`).
    In {
        /// Channel.
        chan: u16,
        /// The value required, if any.
        value: Option<Val>,
    },
    /// An output with its argument values.
    Out {
        /// Channel.
        chan: u16,
        /// Argument values.
        args: Vec<Val>,
    },
}

/// How to perform an offered step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Act {
    /// Take a transition from the resting configuration.
    Fire(u16),
    /// Take a transition out of the current junction.
    Junction(u16),
    /// Complete the communication at the current instruction.
    Comm,
    /// Resolve `wait([a,b])` to this many time units.
    Choose(Val),
    /// Run the pending shared-variable write.
    Exec,
    /// Complete the communication an activity (a composite state's
    /// during action, by index) is at.
    ActivityComm(u16),
    /// Resolve an activity's `wait([a,b])` to this many time units.
    ActivityChoose(u16, Val),
    /// Run an activity's pending variable write.
    ActivityExec(u16),
}

/// A step a machine can take.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Move {
    /// What the environment sees.
    pub offer: Offer,
    /// What to do.
    pub act: Act,
}

/// A step failed (modulus by zero, a model error found at run time).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepError(pub String);

/// The control slots of one thread of a machine: its main thread, or an
/// activity (a composite state's during action running alongside).
#[derive(Debug, Clone, Copy)]
struct Thread {
    pc: usize,
    wait: usize,
    deadline: usize,
    /// 0: the main thread; `k + 1`: activity `k` (its [`Pending`]).
    id: usize,
}

impl Machine {
    fn slot(&self, off: usize) -> usize {
        self.base as usize + off
    }

    fn main_thread(&self) -> Thread {
        Thread { pc: self.slot(PC), wait: self.slot(WAIT), deadline: self.slot(DEADLINE), id: 0 }
    }

    fn activity_thread(&self, k: u16) -> Thread {
        let a = &self.activities[k as usize];
        Thread {
            pc: a.pc_slot as usize,
            wait: a.wait_slot as usize,
            deadline: a.deadline_slot as usize,
            id: k as usize + 1,
        }
    }

    /// The values of the machine's control slots (its own, its activities'
    /// and its timers'): what changes when the machine moves.
    pub fn control(&self, st: &[i32]) -> Vec<i32> {
        let mut v = st[self.base as usize..(self.base + Machine::SLOTS) as usize].to_vec();
        for a in &self.activities {
            v.extend([st[a.pc_slot as usize], st[a.wait_slot as usize], st[a.deadline_slot as usize]]);
        }
        v.extend(self.timers.iter().map(|&t| st[t as usize]));
        v.extend(self.latches.iter().flatten().map(|l| st[l.flag as usize]));
        v.extend(self.pending.iter().map(|p| st[p.flag as usize]));
        v
    }

    /// The active leaf state, if any.
    pub fn leaf(&self, st: &[i32]) -> Option<u16> {
        let l = st[self.slot(LEAF)];
        (l >= 0).then_some(l as u16)
    }

    /// The instruction the machine is at.
    pub fn pc(&self, st: &[i32]) -> u32 {
        st[self.slot(PC)] as u32
    }

    /// Puts the machine in its initial configuration (before any step of
    /// the initial transition: that is its first τ).
    pub fn init(&self, st: &mut [i32]) {
        for op in &self.ops {
            st[op.ret_slot as usize] = -1;
        }
        st[self.slot(LEAF)] = -1;
        st[self.slot(PC)] = self.start_pc as i32;
        st[self.slot(WAIT)] = 0;
        st[self.slot(TRANS)] = -1;
        st[self.slot(DEADLINE)] = -1;
        for k in 0..self.activities.len() {
            self.stop_activity(st, k as u16);
        }
        for &t in &self.timers {
            st[t as usize] = -1;
        }
        for k in 0..self.pending.len() {
            self.clear_pending(st, k);
        }
    }

    /// Whether thread `id` has received a value it has not yet written.
    #[inline]
    fn has_pending(&self, st: &[i32], id: usize) -> bool {
        self.pending.get(id).is_some_and(|p| st[p.flag as usize] != 0)
    }

    fn clear_pending(&self, st: &mut [i32], id: usize) {
        if let Some(p) = self.pending.get(id) {
            st[p.flag as usize] = 0;
            st[p.value as usize] = 0;
        }
    }

    /// RT-16: the forwarding a write of `slot` starts, if it is the copy
    /// of a variable the controller provides to several machines.
    fn copy_forward(&self, slot: u16) -> Option<(u16, u16, i32)> {
        self.copy_forwards.iter().find(|&&(s, _)| s == slot).map(|&(_, f)| f)
    }

    /// Whether thread `id`'s pending write (of a value received) waits for
    /// an earlier write of the same variable to be forwarded (RT-16).
    fn pending_blocked(&self, st: &[i32], id: usize) -> bool {
        if self.copy_forwards.is_empty() {
            return false;
        }
        let Some(p) = self.pending.get(id) else { return false };
        let Some(&(slot, _)) = usize::try_from(st[p.flag as usize] - 1).ok().and_then(|k| self.deferred.get(k)) else {
            return false;
        };
        self.copy_forward(slot).is_some_and(|(_, pending, _)| st[pending as usize] != 0)
    }

    /// Where a value received into `slot` goes: to the thread's pending
    /// value, written by a hidden step of its own ([`Machine::deferred`]),
    /// or at once. True if deferred.
    fn defer(&self, st: &mut [i32], id: usize, slot: u16, v: Val) -> bool {
        let Some(k) = self.deferred.iter().position(|&(s, _)| s == slot) else { return false };
        let Some(p) = self.pending.get(id) else { return false };
        st[p.flag as usize] = k as i32 + 1;
        st[p.value as usize] = v as i32;
        true
    }

    /// An activity stops (its state is left), back to its canonical values.
    fn stop_activity(&self, st: &mut [i32], k: u16) {
        let a = &self.activities[k as usize];
        // What it had read for a communication or a write is read again
        // when it starts again.
        if let Ok(pc) = usize::try_from(st[a.pc_slot as usize]) {
            self.unlatch(st, pc);
        }
        st[a.pc_slot as usize] = -1;
        st[a.wait_slot as usize] = 0;
        st[a.deadline_slot as usize] = -1;
        self.clear_pending(st, k as usize + 1);
    }

    /// The activities and timers of the states a transition from `source`
    /// leaves stop at once, innermost first (the trigger interrupts them),
    /// before any exit action runs.
    #[inline]
    fn deactivate(&self, st: &mut [i32], source: u16) {
        if !(self.activities.is_empty() && self.timers.is_empty()) {
            self.deactivate_states(st, source);
        }
    }

    #[cold]
    #[inline(never)]
    fn deactivate_states(&self, st: &mut [i32], source: u16) {
        let mut node = self.leaf(st);
        while let Some(n) = node {
            let nd = &self.nodes[n as usize];
            if let Some(t) = nd.timer {
                st[t as usize] = -1;
            }
            if let Some(k) = nd.activity {
                self.stop_activity(st, k);
            }
            if n == source {
                break;
            }
            node = nd.parent;
        }
    }

    /// Runs internal instructions from the current pc until the machine
    /// offers something. `first` allows one shared write at the start.
    pub fn settle(&self, st: &mut [i32], clocks: &[Clock], first: bool) -> Result<(), StepError> {
        self.settle_noting(st, clocks, first, &mut false)
    }

    /// [`Machine::settle`], setting `sat` when sticky arithmetic kept an
    /// operand because the result fell outside its type.
    fn settle_noting(&self, st: &mut [i32], clocks: &[Clock], first: bool, sat: &mut bool) -> Result<(), StepError> {
        // A machine with volatile instructions (`reads.rs`) has each of
        // them as a step of its own: a transition's guard, an event or the
        // start is not one (RoboTool's `get_x` and `set_x` come after them).
        let first = first && self.volatile.is_empty();
        self.run(self.main_thread(), st, clocks, first, sat)
    }

    /// RoboTool's `entered` of the simple or final state `n`, at the end of
    /// its entry action: its `sinceEntry` clock restarts, and so do those
    /// of the composite states around it entered with it (whose `entered`
    /// follows); their during actions start, innermost first, unless
    /// already running (RT-17). Whether an activity started.
    fn entered(&self, n: u16, st: &mut [i32], clocks: &[Clock], sat: &mut bool) -> Result<bool, StepError> {
        let node = &self.nodes[n as usize];
        if let Some(c) = node.since_entry {
            st[c as usize] = 0;
        }
        let mut started = false;
        let mut up = node.parent;
        while let Some(a) = up {
            let outer = &self.nodes[a as usize];
            if let (Some(c), Some(f)) = (outer.since_entry, outer.entered_flag) {
                if st[f as usize] == 1 {
                    st[c as usize] = 0;
                    st[f as usize] = 0;
                }
            }
            if let Some(k) = outer.activity {
                let act = self.activity_thread(k);
                // Started once per entry of its state: a later substate's
                // entry leaves it as it is.
                if st[act.pc] < 0 {
                    st[act.pc] = self.activities[k as usize].start_pc as i32;
                    st[act.wait] = 0;
                    st[act.deadline] = -1;
                    // Its first internal work runs now; its variable
                    // writes are steps of their own.
                    self.run(act, st, clocks, false, sat)?;
                    started = true;
                }
            }
            up = outer.parent;
        }
        Ok(started)
    }

    /// Runs thread `th`'s internal instructions until it offers something
    /// (see [`Machine::settle`]).
    fn run(
        &self,
        th: Thread,
        st: &mut [i32],
        clocks: &[Clock],
        mut first: bool,
        sat: &mut bool,
    ) -> Result<(), StepError> {
        // Most machines have no during action that starts with a step of
        // its own: one test per run, not per instruction.
        let pauses = !self.paused_durings.is_empty();
        // With volatile instructions (`reads.rs`), a step runs at most one,
        // and only when it started as a hidden step of its own.
        let marked = !self.volatile.is_empty();
        let mut fresh = first;
        // RoboTool's `set_x` after `e?x`: a step of its own.
        if self.has_pending(st, th.id) {
            if !fresh {
                return Ok(());
            }
            let p = &self.pending[th.id];
            let k = st[p.flag as usize] as usize - 1;
            let (slot, dom) = self.deferred[k];
            // RT-16: the write waits while an earlier one is forwarded.
            let forward = self.copy_forward(slot);
            if forward.is_some_and(|(_, pending, _)| st[pending as usize] != 0) {
                return Ok(());
            }
            let v = st[p.value as usize] as Val;
            if dom.contains(v) {
                st[slot as usize] = v as i32;
                if let Some((ctrl, pending, others)) = forward {
                    st[ctrl as usize] = v as i32;
                    st[pending as usize] = others;
                }
            }
            self.clear_pending(st, th.id);
            fresh = false;
            first = false;
        }
        for i in 0..MAX_INTERNAL {
            let pc = st[th.pc] as usize;
            // A during action that starts with a hidden step of its own
            // (`eager.rs`): the thread stops there, unless this step is
            // that start.
            if pauses && (i > 0 || !first) && self.paused_durings.get(pc) == Some(&true) {
                return Ok(());
            }
            let Some(instr) = self.code.get(pc) else {
                return Err(StepError(format!("machine `{}` ran off its code", self.name)));
            };
            let volatile = marked && self.volatile[pc];
            if volatile && !fresh && !matches!(instr, Instr::Out { .. } | Instr::In { .. }) {
                return Ok(());
            }
            match instr {
                Instr::Assign { slot, expr, dom, shared, forward } => {
                    let v = if marked && matches!(self.latches.get(pc), Some(Some(_))) {
                        match self.latched_assign(pc, expr, *dom, *forward, st, sat)? {
                            Some(v) => v,
                            None => return Ok(()),
                        }
                    } else {
                        if *shared && !first && !marked {
                            return Ok(());
                        }
                        // RT-16: the controller is still forwarding a write.
                        if forward.is_some_and(|(_, pending, _)| st[pending as usize] != 0) {
                            return Ok(());
                        }
                        expr.eval(st, sat).map_err(|e| self.eval_error(e))?
                    };
                    // RoboTool's CSPm writes the variable through a channel
                    // of its type: FDR stops on a value outside it.
                    if !dom.contains(v) {
                        return Err(self.eval_error(EvalError::OutOfDomain(v, *dom)));
                    }
                    st[*slot as usize] = v as i32;
                    if let Some((ctrl, pending, others)) = *forward {
                        st[ctrl as usize] = st[*slot as usize];
                        st[pending as usize] = others;
                    }
                    st[th.pc] += 1;
                }
                Instr::ResetClock(c) => {
                    st[*c as usize] = 0;
                    st[th.pc] += 1;
                }
                Instr::SetWait(e) => {
                    let v = e.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[th.wait] = v.clamp(0, i32::MAX as Val) as i32;
                    st[th.pc] += 1;
                }
                Instr::ChooseWait(lo, hi) => {
                    let a = lo.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    let b = hi.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    if a < b {
                        return Ok(());
                    }
                    // A single value (or an empty interval: no wait) is no choice.
                    st[th.wait] = if a == b { a.max(0) as i32 } else { 0 };
                    st[th.pc] += 1;
                }
                Instr::Wait => {
                    if st[th.wait] > 0 {
                        return Ok(());
                    }
                    // Passing an ended wait touches nothing another thread
                    // sees: a write right after it is still the step's first.
                    st[th.pc] += 1;
                    continue;
                }
                Instr::JumpIfNot(c, target) => {
                    let v = c.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[th.pc] = if v == 0 { *target as i32 } else { pc as i32 + 1 };
                }
                Instr::Jump(target) => st[th.pc] = *target as i32,
                Instr::CallOp { op, args } => {
                    let body = &self.ops[*op as usize];
                    if st[body.ret_slot as usize] >= 0 {
                        return Err(StepError(format!(
                            "machine `{}`: operation `{}` is called while it runs (recursion is not supported)",
                            self.name, body.name
                        )));
                    }
                    let mut values = Vec::with_capacity(args.len());
                    for a in args {
                        values.push(a.eval(st, sat).map_err(|e| self.eval_error(e))?);
                    }
                    for (&(slot, dom), v) in body.params.iter().zip(values) {
                        if dom.contains(v) {
                            st[slot as usize] = v as i32;
                        }
                    }
                    for &(slot, init) in &body.locals {
                        st[slot as usize] = init;
                    }
                    st[body.ret_slot as usize] = pc as i32 + 1;
                    st[body.leaf_slot as usize] = st[self.slot(LEAF)];
                    st[th.pc] = body.start_pc as i32;
                }
                Instr::Deadline(e) => {
                    if st[th.deadline] >= 0 {
                        return Err(StepError(format!(
                            "machine `{}`: nested statement deadlines are not supported",
                            self.name
                        )));
                    }
                    let v = e.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[th.deadline] = v.clamp(0, i32::MAX as Val) as i32;
                    st[th.pc] += 1;
                }
                Instr::EndDeadline => {
                    st[th.deadline] = -1;
                    st[th.pc] += 1;
                }
                Instr::StartTimer { slot, limits } => {
                    let mut least = i32::MAX as Val;
                    for e in limits {
                        least = least.min(e.eval(st, sat).map_err(|e| self.eval_error(e))?);
                    }
                    st[*slot as usize] = least.clamp(0, i32::MAX as Val) as i32;
                    st[th.pc] += 1;
                }
                Instr::Entered(n) => {
                    st[th.pc] += 1;
                    // Like passing an ended wait, unless an activity starts.
                    if !self.entered(*n, st, clocks, sat)? {
                        continue;
                    }
                }
                Instr::Return(op) => {
                    let body = &self.ops[*op as usize];
                    st[self.slot(LEAF)] = st[body.leaf_slot as usize];
                    st[th.pc] = st[body.ret_slot as usize];
                    st[body.ret_slot as usize] = -1;
                    st[body.leaf_slot as usize] = 0;
                }
                Instr::Enter(n) => {
                    let node = &self.nodes[*n as usize];
                    match node.kind {
                        NodeKind::State | NodeKind::Final => {
                            st[self.slot(LEAF)] = *n as i32;
                            // A composite's clock waits for its first
                            // substate's `entered` ([`Machine::entered`]).
                            if let Some(f) = node.entered_flag {
                                st[f as usize] = 1;
                            }
                        }
                        NodeKind::Junction | NodeKind::Initial => {
                            st[self.slot(LEAF)] = node.parent.map_or(-1, i32::from);
                        }
                    }
                    st[th.pc] = node.entry_pc as i32;
                }
                Instr::BeginExits => {
                    let Some(leaf) = self.leaf(st) else {
                        return Err(StepError(format!("machine `{}` exits with no active state", self.name)));
                    };
                    st[th.pc] = self.nodes[leaf as usize].exit_pc as i32;
                }
                Instr::ExitDone(m) => {
                    let t = st[self.slot(TRANS)];
                    let Some(tr) = self.transitions.get(t.max(0) as usize).filter(|_| t >= 0) else {
                        return Err(StepError(format!("machine `{}` exits outside a transition", self.name)));
                    };
                    if tr.source == *m {
                        st[th.pc] = tr.body_pc as i32;
                    } else {
                        let Some(p) = self.nodes[*m as usize].parent else {
                            return Err(StepError(format!(
                                "machine `{}`: the source of transition `{}` is not active",
                                self.name, tr.name
                            )));
                        };
                        st[self.slot(LEAF)] = i32::from(p);
                        st[th.pc] = self.nodes[p as usize].exit_pc as i32;
                    }
                }
                Instr::Out { .. } | Instr::In { .. } => {
                    if let Some(Some(l)) = self.latches.get(pc) {
                        if st[l.flag as usize] == 0 && fresh {
                            self.latch(instr, l, st, sat)?;
                        }
                    }
                    return Ok(());
                }
                Instr::Rest
                | Instr::Junction(_)
                | Instr::Terminate
                | Instr::Exec(_)
                | Instr::ExecTransition
                | Instr::ActivityEnd => {
                    return Ok(());
                }
            }
            if volatile {
                fresh = false;
            }
            first = false;
        }
        let _ = clocks;
        Err(StepError(format!("machine `{}` loops without offering anything", self.name)))
    }

    /// An assignment whose read and write are hidden steps of their own
    /// (`reads.rs`): on its first step it reads its value into its latch
    /// (`get_x?x`) and stops; on the next, once no earlier write of the
    /// variable is being forwarded (RT-16), it gives the value to write
    /// (`set_y`), its latch back at rest. `None`: the thread stops here.
    #[cold]
    #[inline(never)]
    fn latched_assign(
        &self,
        pc: usize,
        expr: &Expr,
        dom: Dom,
        forward: Option<(u16, u16, i32)>,
        st: &mut [i32],
        sat: &mut bool,
    ) -> Result<Option<Val>, StepError> {
        let Some(Some(l)) = self.latches.get(pc) else { return Ok(None) };
        if st[l.flag as usize] == 0 {
            let v = expr.eval(st, sat).map_err(|e| self.eval_error(e))?;
            if !dom.contains(v) {
                return Err(self.eval_error(EvalError::OutOfDomain(v, dom)));
            }
            st[l.slots[0].0 as usize] = v as i32;
            st[l.flag as usize] = 1;
            return Ok(None);
        }
        if forward.is_some_and(|(_, pending, _)| st[pending as usize] != 0) {
            return Ok(None);
        }
        let v = st[l.slots[0].0 as usize] as Val;
        self.unlatch(st, pc);
        Ok(Some(v))
    }

    /// Reads the values the communication `instr` offers into its latch.
    #[cold]
    #[inline(never)]
    fn latch(&self, instr: &Instr, l: &Latch, st: &mut [i32], sat: &mut bool) -> Result<(), StepError> {
        let exprs: Vec<&Expr> = match instr {
            Instr::Out { args, .. } => args.iter().collect(),
            Instr::In { value, .. } => value.iter().collect(),
            _ => Vec::new(),
        };
        for (e, &(slot, _)) in exprs.into_iter().zip(&l.slots) {
            let v = e.eval(st, sat).map_err(|e| self.eval_error(e))?;
            st[slot as usize] = v as i32;
        }
        st[l.flag as usize] = 1;
        Ok(())
    }

    /// The latch of the communication at `pc`, back to its resting values.
    #[inline]
    fn unlatch(&self, st: &mut [i32], pc: usize) {
        if let Some(Some(l)) = self.latches.get(pc) {
            st[l.flag as usize] = 0;
            for &(slot, _) in &l.slots {
                st[slot as usize] = 0;
            }
        }
    }

    fn eval_error(&self, e: EvalError) -> StepError {
        match e {
            EvalError::DivByZero => StepError(format!("modulus by zero in machine `{}`", self.name)),
            EvalError::OutOfType => {
                StepError(format!("a tuple component or set element outside its type in machine `{}`", self.name))
            }
            EvalError::OutOfDomain(v, d) => StepError(format!(
                "{}{v} is outside its type's values {{{}..{}}}, sent or assigned in machine `{}`",
                crate::ir::OUT_OF_DOMAIN,
                d.lo,
                d.hi,
                self.name
            )),
            EvalError::SeqTooLong(max) => StepError(format!(
                "machine `{}` makes a sequence longer than {max} elements, the longest the native checker holds \
                 (RoboChart's sequences are unbounded: no verdict is given rather than one that ignores the longer \
                 sequences)",
                self.name
            )),
            EvalError::EmptySeq(f) => StepError(format!(
                "machine `{}` takes `{f}` of the empty sequence (an error in CSPm too: FDR stops there)",
                self.name
            )),
        }
    }

    fn guard(&self, st: &[i32], g: &Option<Expr>) -> Result<bool, StepError> {
        let mut sat = false;
        match g {
            None => Ok(true),
            Some(e) => Ok(e.eval(st, &mut sat).map_err(|e| self.eval_error(e))? != 0),
        }
    }

    /// The steps the machine offers (time aside: see [`Machine::can_tock`]).
    // Inlined: called for every machine in every state of a search.
    #[inline(always)]
    pub fn moves(&self, st: &[i32], out: &mut Vec<Move>) -> Result<(), StepError> {
        let pc = self.pc(st) as usize;
        if self.in_during(st) {
            self.transition_moves(st, out)?;
        }
        // A value received and not yet written: writing it comes first
        // (a during action's can be pre-empted, as above).
        if !self.pending.is_empty() && self.has_pending(st, 0) {
            if !self.pending_blocked(st, 0) {
                out.push(Move { offer: Offer::Tau, act: Act::Exec });
            }
            if !self.activities.is_empty() {
                self.activity_moves(st, out)?;
            }
            return Ok(());
        }
        let Some(instr) = self.code.get(pc) else {
            return Err(StepError(format!("machine `{}` ran off its code", self.name)));
        };
        match instr {
            Instr::Rest => self.transition_moves(st, out)?,
            Instr::Junction(j) => {
                for &t in &self.nodes[*j as usize].out {
                    if self.guard(st, &self.transitions[t as usize].guard)? {
                        out.push(Move { offer: Offer::Tau, act: Act::Junction(t) });
                    }
                }
            }
            Instr::Terminate | Instr::Exec(_) | Instr::ExecTransition => {}
            _ => {
                let waited = st[self.slot(WAIT)] == 0;
                if !self.thread_offers(pc, instr, st, out, waited, Act::Comm, Act::Choose, Act::Exec)? {
                    return Err(StepError(format!("machine `{}` stopped at an internal instruction", self.name)));
                }
            }
        }
        if !self.activities.is_empty() {
            self.activity_moves(st, out)?;
        }
        Ok(())
    }

    /// The steps of the running activities (out of line: most machines
    /// have none, and `moves` is inlined into the search).
    #[cold]
    #[inline(never)]
    fn activity_moves(&self, st: &[i32], out: &mut Vec<Move>) -> Result<(), StepError> {
        for (k, a) in self.activities.iter().enumerate() {
            let k = k as u16;
            let pc = st[a.pc_slot as usize];
            if pc < 0 {
                continue;
            }
            if self.has_pending(st, k as usize + 1) {
                if !self.pending_blocked(st, k as usize + 1) {
                    out.push(Move { offer: Offer::Tau, act: Act::ActivityExec(k) });
                }
                continue;
            }
            let ok = match self.code.get(pc as usize) {
                Some(Instr::ActivityEnd) => true,
                Some(instr) => self.thread_offers(
                    pc as usize,
                    instr,
                    st,
                    out,
                    st[a.wait_slot as usize] == 0,
                    Act::ActivityComm(k),
                    |n| Act::ActivityChoose(k, n),
                    Act::ActivityExec(k),
                )?,
                None => false,
            };
            if !ok {
                return Err(StepError(format!(
                    "machine `{}`: the during action of `{}` stopped at an internal instruction",
                    self.name, self.nodes[a.state as usize].name
                )));
            }
        }
        Ok(())
    }

    /// What a thread (the main one or an activity) stopped at `instr`
    /// offers: a communication (`comm`), the choice of a wait (`choose`),
    /// a variable write (`exec`), going on after a wait that has ended
    /// (`waited`: also `exec`), or nothing while it waits. False when it
    /// should not have stopped there.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn thread_offers(
        &self,
        pc: usize,
        instr: &Instr,
        st: &[i32],
        out: &mut Vec<Move>,
        waited: bool,
        comm: Act,
        choose: impl Fn(Val) -> Act,
        exec: Act,
    ) -> Result<bool, StepError> {
        let mut sat = false;
        let mut eval = |e: &Expr| e.eval(st, &mut sat).map_err(|e| self.eval_error(e));
        let latch = match self.latches.get(pc) {
            Some(Some(l)) => Some(l),
            _ => None,
        };
        match instr {
            // Not read yet: reading is a hidden step of its own.
            Instr::Out { .. } | Instr::In { .. } if latch.is_some_and(|l| st[l.flag as usize] == 0) => {
                out.push(Move { offer: Offer::Tau, act: exec })
            }
            Instr::Out { chan, args, .. } => {
                let args = match latch {
                    Some(l) => l.slots.iter().map(|&(s, _)| st[s as usize] as Val).collect(),
                    None => args.iter().map(&mut eval).collect::<Result<_, _>>()?,
                };
                out.push(Move { offer: Offer::Out { chan: *chan, args }, act: comm });
            }
            Instr::In { chan, value, .. } => {
                let value = match latch {
                    Some(l) => l.slots.first().map(|&(s, _)| st[s as usize] as Val),
                    None => value.as_ref().map(&mut eval).transpose()?,
                };
                out.push(Move { offer: Offer::In { chan: *chan, value }, act: comm });
            }
            Instr::ChooseWait(lo, hi) => {
                let (a, b) = (eval(lo)?, eval(hi)?);
                for n in a..=b {
                    out.push(Move { offer: Offer::Tau, act: choose(n) });
                }
            }
            // RT-16: a write waits while an earlier one is being forwarded
            // (its read, when a step of its own, need not).
            Instr::Assign { forward: Some((_, pending, _)), .. }
                if st[*pending as usize] != 0 && latch.is_none_or(|l| st[l.flag as usize] != 0) => {}
            Instr::Assign { .. } => out.push(Move { offer: Offer::Tau, act: exec }),
            // RT-18: what follows a wait that ended at a `tock` is a hidden
            // step of its own, interleaving freely with the other threads'
            // (and their guards); τ has priority over `tock` only.
            Instr::Wait if waited => out.push(Move { offer: Offer::Tau, act: exec }),
            Instr::Wait => {}
            // Stopped after a communication ([`Machine::paused_comms`]) or
            // before a during action ([`Machine::paused_durings`]): going
            // on is a hidden step.
            Instr::JumpIfNot(..)
            | Instr::Jump(_)
            | Instr::ResetClock(_)
            | Instr::SetWait(_)
            | Instr::Deadline(_)
            | Instr::EndDeadline
            | Instr::StartTimer { .. }
            | Instr::Enter(_)
            | Instr::CallOp { .. }
            | Instr::Return(_)
            | Instr::BeginExits
            | Instr::ExitDone(_)
            | Instr::Entered(_)
                if !(self.paused_comms.is_empty() && self.paused_durings.is_empty() && self.volatile.is_empty()) =>
            {
                out.push(Move { offer: Offer::Tau, act: exec })
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Transitions of the leaf and of every enclosing state, with no
    /// priority between levels.
    // Inlined into `moves` (the call cost a fifth of it).
    #[inline(always)]
    fn transition_moves(&self, st: &[i32], out: &mut Vec<Move>) -> Result<(), StepError> {
        let mut sat = false;
        let mut eval = |e: &Expr| e.eval(st, &mut sat).map_err(|e| self.eval_error(e));
        let mut node = self.leaf(st);
        while let Some(n) = node {
            for &t in &self.nodes[n as usize].out {
                let tr = &self.transitions[t as usize];
                if !self.guard(st, &tr.guard)? {
                    continue;
                }
                let offer = match &tr.trigger {
                    None => Offer::Tau,
                    Some(Trigger::In { chan, value, .. }) => {
                        Offer::In { chan: *chan, value: value.as_ref().map(&mut eval).transpose()? }
                    }
                    Some(Trigger::Out { chan, args }) => {
                        Offer::Out { chan: *chan, args: args.iter().map(&mut eval).collect::<Result<_, _>>()? }
                    }
                };
                out.push(Move { offer, act: Act::Fire(t) });
            }
            node = self.nodes[n as usize].parent;
        }
        Ok(())
    }

    /// Whether the machine is running the during action of its active
    /// state (which its transitions may interrupt).
    fn in_during(&self, st: &[i32]) -> bool {
        let pc = self.pc(st);
        self.leaf(st).and_then(|l| self.nodes[l as usize].during).is_some_and(|(start, end)| (start..end).contains(&pc))
    }

    /// Whether time may pass: everywhere except before an urgent call and
    /// when a deadline has run out.
    #[inline]
    pub fn can_tock(&self, st: &[i32]) -> bool {
        let main = !self.urgent_at(st[self.slot(PC)]) && st[self.slot(DEADLINE)] != 0;
        // Most machines have neither timers nor activities.
        if self.timers.is_empty() && self.activities.is_empty() {
            return main;
        }
        main && self.threads_can_tock(st)
    }

    /// Whether the instruction at `pc` is an urgent call.
    #[inline]
    fn urgent_at(&self, pc: i32) -> bool {
        matches!(self.code.get(pc as usize), Some(Instr::Out { urgent: true, .. }))
    }

    /// [`Machine::can_tock`] for the timers and activities.
    #[cold]
    #[inline(never)]
    fn threads_can_tock(&self, st: &[i32]) -> bool {
        self.timers.iter().all(|&t| st[t as usize] != 0)
            && self.activities.iter().all(|a| {
                let pc = st[a.pc_slot as usize];
                pc < 0 || (!self.urgent_at(pc) && st[a.deadline_slot as usize] != 0)
            })
    }

    /// Why the machine cannot let time pass in `st`, one sentence per
    /// reason (empty when it can): for explanations of timelocks.
    pub fn tock_blockers(&self, st: &[i32]) -> Vec<String> {
        let mut why = Vec::new();
        if self.urgent_at(st[self.slot(PC)]) {
            why.push(format!(
                "{}: a platform operation call, update of a platform variable or register write cannot wait",
                self.name
            ));
        }
        if st[self.slot(DEADLINE)] == 0 {
            why.push(format!("{}: the deadline of a statement `<{{…}}` has run out", self.name));
        }
        for node in &self.nodes {
            if node.timer.is_some_and(|t| st[t as usize] == 0) {
                let names: Vec<String> =
                    node.out.iter().map(|&t| &self.transitions[t as usize].name).map(|t| format!("`{t}`")).collect();
                why.push(format!("{}: the deadline of {} from {} has run out", self.name, names.join(", "), node.name));
            }
        }
        for a in &self.activities {
            let pc = st[a.pc_slot as usize];
            if pc >= 0 && (self.urgent_at(pc) || st[a.deadline_slot as usize] == 0) {
                why.push(format!(
                    "{}: the during action of {} cannot wait (an urgent call or a deadline that has run out)",
                    self.name, self.nodes[a.state as usize].name
                ));
            }
        }
        why
    }

    /// One time unit passes for the machine (clocks are advanced by the caller).
    pub fn tock(&self, st: &mut [i32], clocks: &[Clock]) -> Result<(), StepError> {
        if self.timers.is_empty() && self.activities.is_empty() {
            return self.tock_thread(self.main_thread(), st, clocks);
        }
        for &t in &self.timers {
            if st[t as usize] > 0 {
                st[t as usize] -= 1;
            }
        }
        for k in 0..self.activities.len() {
            let th = self.activity_thread(k as u16);
            if st[th.pc] >= 0 {
                self.tock_thread(th, st, clocks)?;
            }
        }
        self.tock_thread(self.main_thread(), st, clocks)
    }

    /// One time unit passes for one thread: its deadline budget and wait
    /// counter count down. A wait that ends does not let the thread go on
    /// here: that is a hidden step of its own after the `tock` (RT-18), so
    /// that it interleaves with the other threads' steps and guards —
    /// unless going on touches nothing another thread sees, which changes
    /// no verdict (`eager.rs`).
    fn tock_thread(&self, th: Thread, st: &mut [i32], clocks: &[Clock]) -> Result<(), StepError> {
        if st[th.deadline] > 0 {
            st[th.deadline] -= 1;
        }
        let pc = st[th.pc] as usize;
        if matches!(self.code.get(pc), Some(Instr::Wait)) && st[th.wait] > 0 {
            st[th.wait] -= 1;
            if st[th.wait] == 0 && self.eager_waits.get(pc) == Some(&true) {
                st[th.pc] += 1;
                self.run(th, st, clocks, false, &mut false)?;
            }
        }
        Ok(())
    }

    /// Whether the machine has terminated.
    pub fn terminated(&self, st: &[i32]) -> bool {
        matches!(self.code.get(self.pc(st) as usize), Some(Instr::Terminate))
    }

    /// RoboSim: the machine starts in its first cycle's wait.
    pub fn init_cycle(&self, st: &mut [i32]) {
        self.init(st);
        st[self.slot(PC)] = self.first_cycle_pc as i32;
    }

    /// RoboSim: whether the machine has ended its cycle (at an `exec`, or
    /// terminated).
    pub fn cycle_ended(&self, st: &[i32]) -> bool {
        matches!(self.code.get(self.pc(st) as usize), Some(Instr::Exec(_) | Instr::ExecTransition | Instr::Terminate))
    }

    /// RoboSim: a new cycle starts (after the reads): the machine resumes
    /// where its last cycle ended.
    pub fn resume(&self, st: &mut [i32], clocks: &[Clock]) -> Result<(), StepError> {
        match self.code.get(self.pc(st) as usize) {
            Some(Instr::Exec(target)) => st[self.slot(PC)] = *target as i32,
            Some(Instr::ExecTransition) => {
                let Some(leaf) = self.leaf(st) else {
                    return Err(StepError(format!("machine `{}` resumes with no active state", self.name)));
                };
                st[self.slot(PC)] = self.nodes[leaf as usize].exit_pc as i32;
            }
            _ => return Ok(()),
        }
        self.settle(st, clocks, true)
    }

    /// Performs `act`; `value` is the value received by an input.
    pub fn apply(&self, st: &mut [i32], clocks: &[Clock], act: Act, value: Option<Val>) -> Result<(), StepError> {
        self.apply_noting(st, clocks, act, value, &mut false)
    }

    /// [`Machine::apply`], setting `sat` when the step's arithmetic
    /// saturated (for the note on counterexamples that depend on it).
    pub fn apply_noting(
        &self,
        st: &mut [i32],
        clocks: &[Clock],
        act: Act,
        value: Option<Val>,
        sat: &mut bool,
    ) -> Result<(), StepError> {
        match act {
            Act::Fire(t) => {
                let tr = &self.transitions[t as usize];
                // A during action's pending write is pre-empted with it.
                self.clear_pending(st, 0);
                let mut deferred = false;
                if let (Some(Trigger::In { bind: Some((slot, dom)), .. }), Some(v)) = (&tr.trigger, value) {
                    deferred = self.defer(st, 0, *slot, v);
                    if !deferred && dom.contains(v) {
                        st[*slot as usize] = v as i32;
                    }
                }
                bind_inputs(st, tr);
                st[self.slot(TRANS)] = i32::from(t);
                self.deactivate(st, tr.source);
                if tr.exec {
                    // The cycle ends; the rest of the transition runs in the next.
                    st[self.slot(PC)] = self.exec_transition_pc as i32;
                    return Ok(());
                }
                let Some(leaf) = self.leaf(st) else {
                    return Err(StepError(format!("machine `{}` fires with no active state", self.name)));
                };
                st[self.slot(PC)] = self.nodes[leaf as usize].exit_pc as i32;
                if deferred {
                    // The write is the next step (`moves`), then the exits.
                    return Ok(());
                }
            }
            Act::Junction(t) => {
                let tr = &self.transitions[t as usize];
                bind_inputs(st, tr);
                st[self.slot(TRANS)] = i32::from(t);
                st[self.slot(PC)] = tr.body_pc as i32;
            }
            Act::Comm | Act::Choose(_) | Act::Exec => {
                return self.step(self.main_thread(), st, clocks, act, value, sat)
            }
            Act::ActivityComm(k) | Act::ActivityChoose(k, _) | Act::ActivityExec(k) => {
                return self.step(self.activity_thread(k), st, clocks, act, value, sat)
            }
        }
        self.settle_noting(st, clocks, true, sat)
    }

    /// A step of thread `th` at the instruction it stopped at: the
    /// communication completes (storing a value received), the wait's
    /// length is chosen, or the pending write runs; then the thread goes on.
    #[inline]
    fn step(
        &self,
        th: Thread,
        st: &mut [i32],
        clocks: &[Clock],
        act: Act,
        value: Option<Val>,
        sat: &mut bool,
    ) -> Result<(), StepError> {
        match act {
            Act::Comm | Act::ActivityComm(_) => {
                let pc = st[th.pc] as u32;
                self.receive(st, th.id, pc, value, sat)?;
                self.unlatch(st, pc as usize);
                st[th.pc] += 1;
                if self.has_pending(st, th.id) {
                    return Ok(());
                }
                // RT-16/18: what follows is a hidden step of its own (the
                // thread offers it as a τ where it stopped).
                if self.paused_comms.get(pc as usize) == Some(&true) {
                    return Ok(());
                }
            }
            Act::Choose(n) | Act::ActivityChoose(_, n) => {
                st[th.wait] = n.max(0) as i32;
                st[th.pc] += 1;
            }
            _ => {}
        }
        // Only the pending write itself runs a shared write at once: after
        // an event, a write that follows is a hidden step of its own in
        // RoboTool's CSPm (`set_x`), and another thread, or a transition
        // interrupting a during action, may come in between.
        let first = matches!(act, Act::Exec | Act::ActivityExec(_));
        self.run(th, st, clocks, first, sat)
    }

    /// An input `e?x` at `pc` stores the value received, and the update of
    /// a platform variable the value sent (when in its type).
    #[inline]
    fn receive(&self, st: &mut [i32], id: usize, pc: u32, value: Option<Val>, sat: &mut bool) -> Result<(), StepError> {
        match (self.code.get(pc as usize), value) {
            (Some(Instr::In { bind: Some((slot, dom)), .. }), Some(v)) if dom.contains(v) => {
                let deferred = self.defer(st, id, *slot, v);
                if !deferred {
                    st[*slot as usize] = v as i32;
                }
            }
            (Some(Instr::Out { args, store: Some((slot, dom)), .. }), _) => {
                let v = match (self.latches.get(pc as usize), args.first()) {
                    (Some(Some(l)), _) => match l.slots.first() {
                        Some(&(s, _)) => st[s as usize] as Val,
                        None => return Ok(()),
                    },
                    (_, Some(e)) => e.eval(st, sat).map_err(|e| self.eval_error(e))?,
                    (_, None) => return Ok(()),
                };
                if dom.contains(v) {
                    st[*slot as usize] = v as i32;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// A description of the machine's control state, for counterexamples.
    pub fn describe(&self, st: &[i32]) -> String {
        let pc = self.pc(st) as usize;
        let at = |n: u16| self.nodes[n as usize].name.clone();
        match self.code.get(pc) {
            Some(Instr::Terminate) => "terminated".into(),
            Some(Instr::Exec(_)) => format!(
                "waiting for the next cycle (exec){}",
                self.leaf(st).map(|l| format!(" in {}", at(l))).unwrap_or_default()
            ),
            Some(Instr::ExecTransition) => format!(
                "taking {} in the next cycle (exec)",
                self.transitions.get(st[self.slot(TRANS)].max(0) as usize).map_or("?", |t| t.name.as_str())
            ),
            Some(Instr::Junction(j)) => format!("at junction {}", at(*j)),
            Some(Instr::Wait) => format!(
                "waiting ({} left){}",
                st[self.slot(WAIT)],
                self.leaf(st).map(|l| format!(" in {}", at(l))).unwrap_or_default()
            ),
            Some(Instr::Rest) => self.leaf(st).map(at).unwrap_or_default(),
            _ => match self.leaf(st) {
                Some(l) => format!("in {}", at(l)),
                None => "starting".into(),
            },
        }
    }
}

/// RoboSim `$e?x` in a transition's guard: `x` takes the input's value when
/// the transition is taken (from a state or from a junction).
#[inline]
fn bind_inputs(st: &mut [i32], tr: &Transition) {
    for &(var, dom, from) in &tr.binds {
        let v = st[from as usize] as Val;
        if dom.contains(v) {
            st[var as usize] = v as i32;
        }
    }
}
