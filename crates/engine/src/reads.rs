//! Reads of what another thread may change, as RoboTool's CSPm makes them
//! (RT-16, RT-18).
//!
//! In RoboTool's CSPm a statement reads each variable it uses by a hidden
//! event of its own (`get_x?x`) just before it runs, and what it offers
//! then carries the values read: `get_speed?speed -> reportCall.speed`
//! offers the call with the value read, however the variable changes while
//! the call waits. Between a guard's read and the action's, other threads
//! (another machine, the controller forwarding a write to this machine's
//! copy, a composite state's during action) may write the variable.
//!
//! So an instruction that reads or writes what another thread writes or
//! reads is *volatile*: the thread stops before it, and running it is a
//! hidden step of its own, unless that step started with nothing else
//! another thread sees ([`Machine::volatile`]). A communication that
//! carries such values *latches* them: they are read in that step, into
//! slots of their own, and the communication offers those until it
//! happens ([`Machine::latches`]).
//!
//! An assignment that reads what another thread writes, to a variable
//! another thread reads, latches its value the same way: RoboTool reads
//! (`get_x?x`) and writes (`set_y!(x + 1)`) by two hidden steps, and
//! another thread may read the old `y` in between.
//!
//! A value received into a variable another thread reads is written by a
//! hidden step of its own after the communication, as RoboTool's
//! `e?x -> set_x!x` ([`Machine::deferred`]): another thread may read the
//! old value after the event.
//!
//! What only the thread itself reads and writes runs as before: another
//! thread cannot tell when it happened (a confluent τ, as in `eager.rs`).
//! Clocks need neither: only time changes them, and actions cannot read
//! them (RC:TE1), so a value offered never waits across a `tock`.

use std::collections::HashSet;

use crate::ir::{Design, Dom, Expr, Instr, Latch, Machine, Pending, Trigger};

/// Marks, in every machine of `design`, the volatile instructions and the
/// communications that latch their values, taking latch slots from `slot`.
/// `shared` holds the slots other machines or the platform read or write.
pub(crate) fn mark_reads(design: &mut Design, shared: &HashSet<u16>, slot: &mut u16) {
    let params: Vec<Vec<Dom>> = design.channels.iter().map(|c| c.params.clone()).collect();
    for m in &mut design.machines {
        mark_machine(m, shared, &params, slot);
    }
}

fn mark_machine(m: &mut Machine, shared: &HashSet<u16>, params: &[Vec<Dom>], slot: &mut u16) {
    // A composite state's during action is another thread of the machine:
    // then every variable and clock of the machine is another thread's too.
    let threads = !m.activities.is_empty();
    let volatile = |e: &Expr| reads(e, &|s| threads || shared.contains(&s));
    let mut marks = vec![false; m.code.len()];
    let mut latches: Vec<Option<Latch>> = vec![None; m.code.len()];
    for (pc, instr) in m.code.iter().enumerate() {
        let (vol, latch) = match instr {
            // `y = x + 1` is `get_x?x -> set_y!(x + 1)`: when another
            // thread may write `x` and see `y`, the read and the write are
            // hidden steps of their own, and the value read is latched
            // between them.
            Instr::Assign { slot: s, expr, shared: written, dom, .. } => {
                let (read, write) = (volatile(expr), *written || threads || shared.contains(s));
                (read || write, (read && write).then(|| vec![Some(*dom)]))
            }
            Instr::JumpIfNot(e, _) | Instr::SetWait(e) | Instr::Deadline(e) => (volatile(e), None),
            Instr::ChooseWait(a, b) => (volatile(a) || volatile(b), None),
            Instr::StartTimer { limits, .. } => (limits.iter().any(volatile), None),
            Instr::CallOp { args, .. } => (args.iter().any(volatile), None),
            Instr::Out { chan, args, .. } => {
                let vol = args.iter().any(volatile);
                let doms = params.get(*chan as usize).filter(|p| p.len() == args.len());
                (vol, vol.then(|| (0..args.len()).map(|k| doms.map(|d| d[k])).collect::<Vec<_>>()))
            }
            Instr::In { chan, value: Some(v), .. } => {
                let vol = volatile(v);
                let dom = params.get(*chan as usize).filter(|p| p.len() == 1).map(|p| p[0]);
                (vol, vol.then(|| vec![dom]))
            }
            _ => (false, None),
        };
        marks[pc] = vol;
        if let Some(doms) = latch {
            let flag = *slot;
            *slot += 1;
            let slots = doms
                .into_iter()
                .map(|d| {
                    let s = *slot;
                    *slot += 1;
                    (s, d)
                })
                .collect();
            latches[pc] = Some(Latch { flag, slots });
        }
    }
    m.volatile = if marks.iter().any(|&b| b) { marks } else { Vec::new() };
    m.latches = if latches.iter().any(Option::is_some) { latches } else { Vec::new() };
    // What a value received goes to, where another thread reads it.
    let statements = m.code.iter().filter_map(|i| match i {
        Instr::In { bind: Some(b), .. } => Some(*b),
        _ => None,
    });
    let triggers = m.transitions.iter().filter_map(|t| match &t.trigger {
        Some(Trigger::In { bind: Some(b), .. }) => Some(*b),
        _ => None,
    });
    let mut deferred: Vec<(u16, Dom)> = Vec::new();
    for (s, d) in statements.chain(triggers) {
        if (threads || shared.contains(&s)) && !deferred.iter().any(|&(t, _)| t == s) {
            deferred.push((s, d));
        }
    }
    if !deferred.is_empty() {
        m.pending = (0..=m.activities.len())
            .map(|_| {
                let p = Pending { flag: *slot, value: *slot + 1 };
                *slot += 2;
                p
            })
            .collect();
    }
    m.deferred = deferred;
}

/// Whether `e` reads a slot for which `slot` holds.
fn reads(e: &Expr, slot: &dyn Fn(u16) -> bool) -> bool {
    let r = |a: &Expr| reads(a, slot);
    match e {
        Expr::Const(_) | Expr::Clock(_) => false,
        Expr::Slot(s) => slot(*s),
        Expr::Neg(a, _) | Expr::Not(a) | Expr::Proj(a, ..) | Expr::Elem(a, _) | Expr::Card(a) | Expr::Checked(a, _) => {
            r(a)
        }
        Expr::Arith(_, a, b, _) | Expr::Cmp(_, a, b) | Expr::Log(_, a, b) | Expr::Set(_, a, b) => r(a) || r(b),
        Expr::If(c, a, b) => r(c) || r(a) || r(b),
        Expr::Tuple(parts) => parts.iter().any(|(p, _)| r(p)),
        Expr::Seq(_, args, _) => args.iter().any(r),
    }
}
