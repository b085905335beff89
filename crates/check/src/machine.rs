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
}

/// A step a machine can take.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Move {
    /// What the environment sees.
    pub offer: Offer,
    /// What to do.
    pub act: Act,
}

/// A step failed (division by zero, a model error found at run time).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepError(pub String);

impl Machine {
    fn slot(&self, off: usize) -> usize {
        self.base as usize + off
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
    }

    /// Runs internal instructions from the current pc until the machine
    /// offers something. `first` allows one shared write at the start.
    pub fn settle(&self, st: &mut [i32], clocks: &[Clock], first: bool) -> Result<(), StepError> {
        self.settle_noting(st, clocks, first, &mut false)
    }

    /// [`Machine::settle`], setting `sat` when sticky arithmetic kept an
    /// operand because the result fell outside its type.
    fn settle_noting(
        &self,
        st: &mut [i32],
        clocks: &[Clock],
        mut first: bool,
        sat: &mut bool,
    ) -> Result<(), StepError> {
        for _ in 0..MAX_INTERNAL {
            let pc = st[self.slot(PC)] as usize;
            let Some(instr) = self.code.get(pc) else {
                return Err(StepError(format!("machine `{}` ran off its code", self.name)));
            };
            match instr {
                Instr::Assign { slot, expr, dom, shared } => {
                    if *shared && !first {
                        return Ok(());
                    }
                    let v = expr.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    if dom.contains(v) {
                        st[*slot as usize] = v as i32;
                    }
                    st[self.slot(PC)] += 1;
                }
                Instr::ResetClock(c) => {
                    st[*c as usize] = 0;
                    st[self.slot(PC)] += 1;
                }
                Instr::SetWait(e) => {
                    let v = e.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[self.slot(WAIT)] = v.clamp(0, i32::MAX as Val) as i32;
                    st[self.slot(PC)] += 1;
                }
                Instr::ChooseWait(lo, hi) => {
                    let a = lo.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    let b = hi.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    if a < b {
                        return Ok(());
                    }
                    // A single value (or an empty interval: no wait) is no choice.
                    st[self.slot(WAIT)] = if a == b { a.max(0) as i32 } else { 0 };
                    st[self.slot(PC)] += 1;
                }
                Instr::Wait => {
                    if st[self.slot(WAIT)] > 0 {
                        return Ok(());
                    }
                    st[self.slot(PC)] += 1;
                }
                Instr::JumpIfNot(c, target) => {
                    let v = c.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[self.slot(PC)] = if v == 0 { *target as i32 } else { pc as i32 + 1 };
                }
                Instr::Jump(target) => st[self.slot(PC)] = *target as i32,
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
                    st[body.ret_slot as usize] = pc as i32 + 1;
                    st[body.leaf_slot as usize] = st[self.slot(LEAF)];
                    st[self.slot(PC)] = body.start_pc as i32;
                }
                Instr::Deadline(e) => {
                    if st[self.slot(DEADLINE)] >= 0 {
                        return Err(StepError(format!(
                            "machine `{}`: nested statement deadlines are not supported",
                            self.name
                        )));
                    }
                    let v = e.eval(st, sat).map_err(|e| self.eval_error(e))?;
                    st[self.slot(DEADLINE)] = v.clamp(0, i32::MAX as Val) as i32;
                    st[self.slot(PC)] += 1;
                }
                Instr::EndDeadline => {
                    st[self.slot(DEADLINE)] = -1;
                    st[self.slot(PC)] += 1;
                }
                Instr::Return(op) => {
                    let body = &self.ops[*op as usize];
                    st[self.slot(LEAF)] = st[body.leaf_slot as usize];
                    st[self.slot(PC)] = st[body.ret_slot as usize];
                    st[body.ret_slot as usize] = -1;
                    st[body.leaf_slot as usize] = 0;
                }
                Instr::Enter(n) => {
                    let node = &self.nodes[*n as usize];
                    match node.kind {
                        NodeKind::State | NodeKind::Final => {
                            st[self.slot(LEAF)] = *n as i32;
                            if let Some(c) = node.since_entry {
                                st[c as usize] = 0;
                            }
                        }
                        NodeKind::Junction | NodeKind::Initial => {
                            st[self.slot(LEAF)] = node.parent.map_or(-1, i32::from);
                        }
                    }
                    st[self.slot(PC)] = node.entry_pc as i32;
                }
                Instr::BeginExits => {
                    let Some(leaf) = self.leaf(st) else {
                        return Err(StepError(format!("machine `{}` exits with no active state", self.name)));
                    };
                    st[self.slot(PC)] = self.nodes[leaf as usize].exit_pc as i32;
                }
                Instr::ExitDone(m) => {
                    let t = st[self.slot(TRANS)];
                    let Some(tr) = self.transitions.get(t.max(0) as usize).filter(|_| t >= 0) else {
                        return Err(StepError(format!("machine `{}` exits outside a transition", self.name)));
                    };
                    if tr.source == *m {
                        st[self.slot(PC)] = tr.body_pc as i32;
                    } else {
                        let Some(p) = self.nodes[*m as usize].parent else {
                            return Err(StepError(format!(
                                "machine `{}`: the source of transition `{}` is not active",
                                self.name, tr.name
                            )));
                        };
                        st[self.slot(LEAF)] = i32::from(p);
                        st[self.slot(PC)] = self.nodes[p as usize].exit_pc as i32;
                    }
                }
                Instr::Out { .. }
                | Instr::In { .. }
                | Instr::Rest
                | Instr::Junction(_)
                | Instr::Terminate
                | Instr::Exec(_)
                | Instr::ExecTransition => {
                    return Ok(());
                }
            }
            first = false;
        }
        let _ = clocks;
        Err(StepError(format!("machine `{}` loops without offering anything", self.name)))
    }

    fn eval_error(&self, e: EvalError) -> StepError {
        match e {
            EvalError::DivByZero => StepError(format!("division by zero in machine `{}`", self.name)),
            EvalError::OutOfType => {
                StepError(format!("a tuple component or set element outside its type in machine `{}`", self.name))
            }
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
        let mut sat = false;
        let mut eval = |e: &Expr| e.eval(st, &mut sat).map_err(|e| self.eval_error(e));
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
            Instr::Out { chan, args, .. } => {
                let args = args.iter().map(&mut eval).collect::<Result<_, _>>()?;
                out.push(Move { offer: Offer::Out { chan: *chan, args }, act: Act::Comm });
            }
            Instr::In { chan, value, .. } => {
                let value = value.as_ref().map(&mut eval).transpose()?;
                out.push(Move { offer: Offer::In { chan: *chan, value }, act: Act::Comm });
            }
            Instr::ChooseWait(lo, hi) => {
                let (a, b) = (eval(lo)?, eval(hi)?);
                for n in a..=b {
                    out.push(Move { offer: Offer::Tau, act: Act::Choose(n) });
                }
            }
            Instr::Assign { .. } => out.push(Move { offer: Offer::Tau, act: Act::Exec }),
            Instr::Wait | Instr::Terminate | Instr::Exec(_) | Instr::ExecTransition => {}
            _ => return Err(StepError(format!("machine `{}` stopped at an internal instruction", self.name))),
        }
        Ok(())
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
    pub fn can_tock(&self, st: &[i32]) -> bool {
        !matches!(self.code.get(self.pc(st) as usize), Some(Instr::Out { urgent: true, .. }))
            && st[self.slot(DEADLINE)] != 0
    }

    /// One time unit passes for the machine (clocks are advanced by the caller).
    pub fn tock(&self, st: &mut [i32], clocks: &[Clock]) -> Result<(), StepError> {
        if st[self.slot(DEADLINE)] > 0 {
            st[self.slot(DEADLINE)] -= 1;
        }
        if matches!(self.code.get(self.pc(st) as usize), Some(Instr::Wait)) && st[self.slot(WAIT)] > 0 {
            st[self.slot(WAIT)] -= 1;
            if st[self.slot(WAIT)] == 0 {
                st[self.slot(PC)] += 1;
                self.settle(st, clocks, true)?;
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
                if let (Some(Trigger::In { bind: Some((slot, dom)), .. }), Some(v)) = (&tr.trigger, value) {
                    if dom.contains(v) {
                        st[*slot as usize] = v as i32;
                    }
                }
                for &(var, dom, from) in &tr.binds {
                    let v = st[from as usize] as Val;
                    if dom.contains(v) {
                        st[var as usize] = v as i32;
                    }
                }
                st[self.slot(TRANS)] = i32::from(t);
                if tr.exec {
                    // The cycle ends; the rest of the transition runs in the next.
                    st[self.slot(PC)] = self.exec_transition_pc as i32;
                    return Ok(());
                }
                let Some(leaf) = self.leaf(st) else {
                    return Err(StepError(format!("machine `{}` fires with no active state", self.name)));
                };
                st[self.slot(PC)] = self.nodes[leaf as usize].exit_pc as i32;
            }
            Act::Junction(t) => {
                st[self.slot(TRANS)] = i32::from(t);
                st[self.slot(PC)] = self.transitions[t as usize].body_pc as i32;
            }
            Act::Comm => {
                if let (Some(Instr::In { bind: Some((slot, dom)), .. }), Some(v)) =
                    (self.code.get(self.pc(st) as usize), value)
                {
                    if dom.contains(v) {
                        st[*slot as usize] = v as i32;
                    }
                }
                st[self.slot(PC)] += 1;
            }
            Act::Choose(n) => {
                st[self.slot(WAIT)] = n.max(0) as i32;
                st[self.slot(PC)] += 1;
            }
            Act::Exec => {}
        }
        self.settle_noting(st, clocks, true, sat)
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
