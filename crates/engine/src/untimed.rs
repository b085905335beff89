//! RoboChart's untimed semantics (robotool-facts RT-9), as a transformation
//! of a compiled [`Design`]: what RoboTool's untimed script makes of each
//! time construct, read in its generated CSPm (the Alpha Algorithm's
//! `csp-gen/` against `csp-gen/timed/`):
//!
//! - `wait(e)` and `wait([a, b])` are `SKIP` (the timed `SHARE_WAIT(e)` is
//!   simply absent), so `e` is not even evaluated;
//! - a clock reset `#C` vanishes (there are no clocks);
//! - a guard that compares a clock (`since(C) >= MB`) is `true` (the timed
//!   `(MBC>=const_…_MB)&` becomes `(true)&`);
//! - a platform operation call is a plain event (`moveCall.l.a -> SKIP`
//!   where the timed script has `EDeadline(moveCall.l.a, 0)`);
//! - there is no `tock` ([`crate::design::DesignLts::without_time`]);
//!   a during action that ends waits for its state to be left (`SStop`,
//!   which lets other threads write shared variables: `RUN({share__})`).
//!
//! What the reference does not show is refused with a reason rather than
//! guessed: deadlines `<{d}` (the untimed library defines none of
//! `Deadline`, `EndBy`, `StartBy` or `TimeOut`, so we cannot tell what the
//! generator emits), `sinceEntry(S)`, and a clock anywhere but as one side
//! of a whole guard's comparison (in `g /\ since(C) > 1`, is `since(C) > 1`
//! or the whole guard `true`?).
//!
//! The transformation keeps every instruction index (a removed instruction
//! becomes a jump to the next one), so code ranges, during-action ranges
//! and source locations stay valid.

use robosim_hir::TextRange;

use crate::ir::{Design, Expr, Instr, Machine, Trigger};

/// The semantics an assertion is checked in (RT-8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Semantics {
    /// tock-CSP: time passes in `tock` steps.
    #[default]
    Timed,
    /// RoboChart's untimed semantics (RT-9): no `tock`.
    Untimed,
}

impl Semantics {
    /// `timed`, `untimed`.
    pub fn name(self) -> &'static str {
        match self {
            Semantics::Timed => "timed",
            Semantics::Untimed => "untimed",
        }
    }
}

/// Why a design has no untimed reading we can match, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotUntimed {
    /// What, as a sentence.
    pub message: String,
    /// Where (file path and range), when known.
    pub location: Option<(String, TextRange)>,
}

/// The design in RoboChart's untimed semantics (RT-9). Explore it with
/// [`crate::design::DesignLts::without_time`].
pub fn untime(design: &Design) -> Result<Design, NotUntimed> {
    let mut d = design.clone();
    let clock_name = |slot: u16| {
        design.clocks.iter().find(|c| c.slot == slot).map_or_else(|| "a clock".to_string(), |c| c.name.clone())
    };
    let file = |k: u16| design.files.get(k as usize).cloned().unwrap_or_default();
    for m in &mut d.machines {
        for t in 0..m.transitions.len() {
            let tr = &m.transitions[t];
            let Some(guard) = &tr.guard else { continue };
            let Some(slot) = clock_in(guard) else { continue };
            let at = Some((file(tr.file), tr.range));
            if is_since_entry(design, slot) {
                return Err(NotUntimed {
                    message: format!(
                        "the guard of `{}` uses `{}`: what RoboTool's untimed semantics makes of `sinceEntry` \
                         is not established (RT-9 covers `since(C)` guards), so it is not checked untimed",
                        tr.name,
                        clock_name(slot)
                    ),
                    location: at,
                });
            }
            if !whole_clock_comparison(guard) {
                return Err(NotUntimed {
                    message: format!(
                        "the guard of `{}` combines a comparison of the clock `{}` with other conditions (or is \
                         a `condition else` next to a clock guard): RoboTool's untimed semantics makes a clock \
                         guard `true` (RT-9), but whether that is the comparison or the whole guard is not \
                         established, so it is not checked untimed",
                        tr.name,
                        clock_name(slot)
                    ),
                    location: at,
                });
            }
            // RT-9: `since(C) op e` is `true`.
            m.transitions[t].guard = None;
        }
        for tr in &m.transitions {
            let trigger_clock = match &tr.trigger {
                Some(Trigger::In { value: Some(v), .. }) => clock_in(v),
                Some(Trigger::Out { args, .. }) => args.iter().find_map(clock_in),
                _ => None,
            };
            if let Some(slot) = trigger_clock {
                return Err(NotUntimed {
                    message: format!(
                        "the trigger of `{}` uses the clock `{}`, which the untimed semantics does not have",
                        tr.name,
                        clock_name(slot)
                    ),
                    location: Some((file(tr.file), tr.range)),
                });
            }
        }
        untime_code(m, design, &clock_name)?;
    }
    Ok(d)
}

/// Removes waits and clock resets from `m`'s code, makes calls plain, and
/// refuses what has no established untimed reading.
fn untime_code(m: &mut Machine, design: &Design, clock_name: &dyn Fn(u16) -> String) -> Result<(), NotUntimed> {
    let name = m.name.clone();
    let at = |m: &Machine, pc: usize| {
        let file = m.code_files.get(pc).and_then(|&f| design.files.get(f as usize)).cloned().unwrap_or_default();
        m.code_ranges.get(pc).map(|&r| (file, r))
    };
    for pc in 0..m.code.len() {
        let skip = Instr::Jump(pc as u32 + 1);
        match &m.code[pc] {
            // RT-9: `wait(e)` is SKIP; `#C` vanishes.
            Instr::SetWait(_) | Instr::ChooseWait(..) | Instr::Wait | Instr::ResetClock(_) => m.code[pc] = skip,
            Instr::Deadline(_) | Instr::StartTimer { .. } => {
                return Err(NotUntimed {
                    message: format!(
                        "machine `{name}` has a deadline `<{{d}}`: RoboTool's untimed library defines no deadline \
                         operator and the reference output has none, so what its untimed semantics makes of one is \
                         not established; it is not checked untimed (check it timed)"
                    ),
                    location: at(m, pc),
                });
            }
            instr => {
                if let Some(slot) = instr_clock(instr) {
                    return Err(NotUntimed {
                        message: format!(
                            "machine `{name}` uses the clock `{}` outside a guard: the untimed semantics has no \
                             clocks, and what RoboTool makes of such a use is not established",
                            clock_name(slot)
                        ),
                        location: at(m, pc),
                    });
                }
            }
        }
        // RT-9, RT-19: a platform operation call is a plain event.
        if let Instr::Out { urgent, .. } = &mut m.code[pc] {
            *urgent = false;
        }
    }
    Ok(())
}

/// Whether the clock in `slot` is a state's `sinceEntry`.
fn is_since_entry(design: &Design, slot: u16) -> bool {
    design.machines.iter().any(|m| m.nodes.iter().any(|n| n.since_entry == Some(slot)))
}

/// A guard that is, as a whole, one comparison with a clock on one side
/// and no clock on the other.
fn whole_clock_comparison(e: &Expr) -> bool {
    match e {
        Expr::Cmp(_, a, b) => clock_in(a).is_some() != clock_in(b).is_some(),
        _ => false,
    }
}

/// The first clock `e` reads, if any.
fn clock_in(e: &Expr) -> Option<u16> {
    match e {
        Expr::Clock(s) => Some(*s),
        Expr::Const(_) | Expr::Slot(_) => None,
        Expr::Neg(a, _) | Expr::Not(a) | Expr::Proj(a, ..) | Expr::Elem(a, _) | Expr::Card(a) | Expr::Checked(a, _) => {
            clock_in(a)
        }
        Expr::Arith(_, a, b, _) | Expr::Cmp(_, a, b) | Expr::Log(_, a, b) | Expr::Set(_, a, b) => {
            clock_in(a).or_else(|| clock_in(b))
        }
        Expr::If(c, a, b) => clock_in(c).or_else(|| clock_in(a)).or_else(|| clock_in(b)),
        Expr::Tuple(parts) => parts.iter().find_map(|(e, _)| clock_in(e)),
        Expr::Seq(_, args, _) => args.iter().find_map(clock_in),
    }
}

/// The first clock an instruction reads (waits and resets aside).
fn instr_clock(i: &Instr) -> Option<u16> {
    match i {
        Instr::Assign { expr, .. } => clock_in(expr),
        Instr::Out { args, .. } | Instr::CallOp { args, .. } => args.iter().find_map(clock_in),
        Instr::In { value, .. } => value.as_ref().and_then(clock_in),
        Instr::JumpIfNot(c, _) => clock_in(c),
        _ => None,
    }
}
