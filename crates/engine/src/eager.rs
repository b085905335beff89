//! Which waits may go on inside the `tock` step that ends them, as a
//! reduction that changes no verdict.
//!
//! RT-18 makes what a thread does after a wait a hidden step of its own,
//! so that it interleaves with the other threads' steps and guards. When
//! that step only touches what no other thread reads or writes, it commutes
//! with every other step, nothing else can disable it, and it takes no
//! choice: it is a confluent τ (Groote and van de Pol's τ-confluence). Taking
//! it at once, with the `tock`, then preserves branching bisimilarity, so
//! traces, stable failures, divergences, determinism and the states each
//! machine passes through are the same; the states skipped are unstable
//! (τ is possible) and only ever lead to the state taken.
//!
//! A wait is marked when its machine has no activity (a composite state's
//! during action is another thread of the same machine, and leaving the
//! state would disable it), it is not in a simple state's during action
//! (a transition of the state would interrupt it), and every path of
//! internal code from it to where the thread stops reads and writes only
//! the machine's own variables and clocks: no variable shared with another
//! machine or of the platform, no operation call or exit sequence (whose
//! targets are only known at run time), no activity started.

use std::collections::HashSet;

use crate::ir::{Design, Expr, Instr, Machine};

/// The most instructions followed from one wait before giving up (the
/// wait is then not marked).
const LIMIT: usize = 4096;

/// Marks, in every machine of `design`, the waits whose continuation is a
/// confluent τ ([`Machine::eager_waits`]). `shared` holds the slots of the
/// variables other machines or the platform can read or write.
pub(crate) fn mark_eager_waits(design: &mut Design, shared: &HashSet<u16>) {
    for m in &mut design.machines {
        m.eager_waits = eager_waits(m, shared);
    }
}

/// Marks, in every machine of `design`, the communications whose
/// continuation is not a confluent τ ([`Machine::paused_comms`]): what the
/// thread does after them may read or write what another thread (another
/// machine, through the shared slots; an activity of the same machine) or
/// an interrupting transition touches, so it is a hidden step of its own,
/// as in RoboTool's CSPm, where every read and write is an event.
pub(crate) fn mark_paused_comms(design: &mut Design, shared: &HashSet<u16>) {
    for m in &mut design.machines {
        m.paused_comms = paused_comms(m, shared);
    }
}

fn paused_comms(m: &Machine, shared: &HashSet<u16>) -> Vec<bool> {
    let in_during =
        |pc: usize| m.nodes.iter().filter_map(|n| n.during).any(|(s, e)| (s as usize..e as usize).contains(&pc));
    let activities = !m.activities.is_empty();
    let marks: Vec<bool> = m
        .code
        .iter()
        .enumerate()
        .map(|(pc, i)| {
            matches!(i, Instr::Out { .. } | Instr::In { .. })
                && (activities || in_during(pc) || !local_from(m, pc + 1, shared, true))
        })
        .collect();
    if marks.iter().any(|&b| b) {
        marks
    } else {
        Vec::new()
    }
}

/// Marks, in every machine of `design`, the during actions (of simple
/// states, and of composite ones: activities) that start with a hidden
/// step of their own
/// ([`Machine::paused_durings`]): RoboTool's `During = (action ; SStop) /\
/// interrupt` lets the state's transitions come before the action's first
/// event, so a clock reset there may not happen, and a read of what
/// another thread writes may see a later value. A during action whose
/// first steps (up to where the thread stops) read only what no other
/// thread writes and reset no clock starts in the step that enters the state: if a
/// transition comes first, nothing of it remains, and if not, it reads the
/// same values later (a confluent τ, as for the waits above).
pub(crate) fn mark_paused_durings(design: &mut Design, shared: &HashSet<u16>) {
    for m in &mut design.machines {
        m.paused_durings = paused_durings(m, shared);
    }
}

fn paused_durings(m: &Machine, shared: &HashSet<u16>) -> Vec<bool> {
    // With activities, the machine's own variables are another thread's
    // too: a read of one of them at the start is not confluent.
    let mut others = shared.clone();
    if !m.activities.is_empty() {
        others.extend(m.code.iter().filter_map(|i| match i {
            Instr::Assign { slot, .. } => Some(*slot),
            _ => None,
        }));
    }
    let simple = m.nodes.iter().filter_map(|n| n.during).filter(|(start, end)| start < end).map(|(s, _)| s);
    // A composite state's during action (an activity) starts after its
    // substate's entry (RT-17), and its transitions may come first too.
    let composite = m.activities.iter().map(|a| a.start_pc);
    let mut marks = vec![false; m.code.len()];
    let mut any = false;
    for start in simple.chain(composite) {
        if !local_from(m, start as usize, &others, false) {
            marks[start as usize] = true;
            any = true;
        }
    }
    if any {
        marks
    } else {
        Vec::new()
    }
}

fn eager_waits(m: &Machine, shared: &HashSet<u16>) -> Vec<bool> {
    if !m.activities.is_empty() {
        return Vec::new();
    }
    let in_during =
        |pc: usize| m.nodes.iter().filter_map(|n| n.during).any(|(s, e)| (s as usize..e as usize).contains(&pc));
    let marks: Vec<bool> = m
        .code
        .iter()
        .enumerate()
        .map(|(pc, i)| matches!(i, Instr::Wait) && !in_during(pc) && local_from(m, pc + 1, shared, true))
        .collect();
    if marks.iter().any(|&b| b) {
        marks
    } else {
        Vec::new()
    }
}

/// Whether every path of internal code from `start` to a stopping point
/// touches only the machine's own data (`resets`: counting a clock reset
/// as such).
fn local_from(m: &Machine, start: usize, shared: &HashSet<u16>, resets: bool) -> bool {
    let reads = |e: &Expr| !reads_shared(e, shared);
    let mut todo = vec![start];
    let mut seen = HashSet::new();
    while let Some(pc) = todo.pop() {
        if !seen.insert(pc) {
            continue;
        }
        if seen.len() > LIMIT {
            return false;
        }
        let Some(instr) = m.code.get(pc) else { return false };
        let next = match instr {
            Instr::Assign { slot, expr, shared: s, .. } => {
                if *s || shared.contains(slot) || !reads(expr) {
                    return false;
                }
                vec![pc + 1]
            }
            Instr::ResetClock(_) if !resets => return false,
            Instr::ResetClock(_) | Instr::EndDeadline => vec![pc + 1],
            Instr::SetWait(e) | Instr::Deadline(e) => {
                if !reads(e) {
                    return false;
                }
                vec![pc + 1]
            }
            Instr::ChooseWait(a, b) => {
                if !(reads(a) && reads(b)) {
                    return false;
                }
                vec![pc + 1]
            }
            Instr::StartTimer { limits, .. } => {
                if !limits.iter().all(reads) {
                    return false;
                }
                vec![pc + 1]
            }
            // A wait of length 0 is passed at once.
            Instr::Wait => vec![pc + 1],
            Instr::JumpIfNot(c, target) => {
                if !reads(c) {
                    return false;
                }
                vec![pc + 1, *target as usize]
            }
            Instr::Jump(target) => vec![*target as usize],
            Instr::Enter(n) => match m.nodes.get(*n as usize) {
                Some(node) => vec![node.entry_pc as usize],
                None => return false,
            },
            // Where these continue is only known at run time.
            Instr::CallOp { .. } | Instr::Return(_) | Instr::BeginExits | Instr::ExitDone(_) => return false,
            // Starts an activity, or resets a clock.
            Instr::Entered(n) => {
                let mut up = Some(*n);
                while let Some(a) = up {
                    let node = &m.nodes[a as usize];
                    if node.activity.is_some() || (!resets && node.since_entry.is_some()) {
                        return false;
                    }
                    up = node.parent;
                }
                vec![pc + 1]
            }
            // The thread stops: what it offers there is a step of its own.
            Instr::Out { .. }
            | Instr::In { .. }
            | Instr::Rest
            | Instr::Junction(_)
            | Instr::Terminate
            | Instr::Exec(_)
            | Instr::ExecTransition
            | Instr::ActivityEnd => Vec::new(),
        };
        todo.extend(next);
    }
    true
}

/// Whether `e` reads one of the `shared` slots.
fn reads_shared(e: &Expr, shared: &HashSet<u16>) -> bool {
    match e {
        Expr::Const(_) | Expr::Clock(_) => false,
        Expr::Slot(s) => shared.contains(s),
        Expr::Neg(a, _) | Expr::Not(a) | Expr::Proj(a, ..) | Expr::Elem(a, _) | Expr::Card(a) | Expr::Checked(a, _) => {
            reads_shared(a, shared)
        }
        Expr::Arith(_, a, b, _) | Expr::Cmp(_, a, b) | Expr::Log(_, a, b) | Expr::Set(_, a, b) => {
            reads_shared(a, shared) || reads_shared(b, shared)
        }
        Expr::If(c, a, b) => reads_shared(c, shared) || reads_shared(a, shared) || reads_shared(b, shared),
        Expr::Tuple(parts) => parts.iter().any(|(p, _)| reads_shared(p, shared)),
        Expr::Seq(_, args, _) => args.iter().any(|p| reads_shared(p, shared)),
    }
}
