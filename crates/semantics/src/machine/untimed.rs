//! What RoboChart's untimed semantics (robotool-facts RT-9) makes of the
//! time constructs, as RoboTool's untimed script writes them (the Alpha
//! Algorithm's `csp-gen/` against `csp-gen/timed/`): no `tock`, so no
//! `TimedPriority`, no time alternatives, `TStop` is `STOP`; `wait(e)` is
//! `SKIP`; clock resets vanish and clocks are gone; a guard comparing a
//! clock is `true`; platform operation calls are plain events.
//!
//! What the reference does not show is refused, for the reasons the
//! native checker gives (`robosim-engine`'s `untimed.rs`), since they are
//! about RoboTool's semantics, not about the checker: deadlines `<{d}`,
//! `sinceEntry`, and a clock anywhere but as one side of a whole guard's
//! comparison.

use super::*;

impl Gen<'_, '_> {
    /// Whether the semantics written is the timed one.
    pub(super) fn timed(&self) -> bool {
        self.ex.timed
    }

    /// The events `names`, `tock` left out when untimed.
    pub(super) fn time_events(&self, names: &[&str]) -> Vec<Expr> {
        names.iter().filter(|n| self.timed() || **n != "tock").map(|n| name(*n)).collect()
    }

    /// `TimedPriority(p)` when timed; `p` untimed.
    pub(super) fn prioritised(&self, p: Expr) -> Expr {
        if self.timed() {
            call("TimedPriority", vec![p])
        } else {
            p
        }
    }

    /// What is left when nothing more happens: time passes (`TStop`), or
    /// untimed `STOP`.
    pub(super) fn tstop(&self) -> Expr {
        if self.timed() {
            name("TStop")
        } else {
            Expr::Stop
        }
    }

    /// Adds `tock -> next` to `alts` when timed.
    pub(super) fn push_tock(&self, alts: &mut Vec<Expr>, next: Expr) {
        if self.timed() {
            alts.push(prefix("tock", vec![], next));
        }
    }

    /// The urgent event `e` (`EDeadline(e, 0)`), untimed a plain event.
    pub(super) fn urgent(&self, e: Expr) -> Expr {
        if self.timed() {
            call("EDeadline", vec![e, Expr::Int(0)])
        } else {
            plain(e)
        }
    }

    /// The event `e` whenever the environment offers it (`Delayable(e)`),
    /// untimed a plain event.
    pub(super) fn delayable(&self, e: Expr) -> Expr {
        if self.timed() {
            call("Delayable", vec![e])
        } else {
            plain(e)
        }
    }

    /// RoboTool's end of a RoboChart machine: `terminate`, its own
    /// channel, whenever the environment offers it, time passing meanwhile
    /// (`terminate -> SKIP` in a `Timed` section); untimed, `terminate ->
    /// SKIP`.
    pub(super) fn terminating(&self) -> Expr {
        self.delayable(name("terminate"))
    }

    /// Untimed: refuses a deadline `<{d}` at `range` (the native checker's
    /// reason); `true` when timed.
    pub(super) fn deadline_allowed(&mut self, range: TextRange) -> bool {
        if self.timed() {
            return true;
        }
        let what = self.what();
        self.problem(
            range,
            format!(
                "in the untimed semantics: the {what} has a deadline `<{{d}}`: RoboTool's untimed library defines no \
                 deadline operator and the reference output has none, so what its untimed semantics makes of one is \
                 not established (the timed semantics is exported)"
            ),
        );
        false
    }

    /// Untimed: refuses the read of the clock `clock` at `range`: the
    /// untimed semantics has no clocks (a whole guard comparing one is
    /// `true`, see [`Gen::untimed_guard`]).
    pub(super) fn clock_read_refused(&mut self, range: TextRange, clock: &str) {
        let what = self.what();
        self.problem(
            range,
            format!(
                "in the untimed semantics: the {what} uses the clock `{clock}` outside a guard: the untimed semantics \
                 has no clocks, and what RoboTool makes of such a use is not established (the timed semantics is \
                 exported)"
            ),
        );
    }

    /// Untimed, the guard `g` of transition `t` when it reads a clock:
    /// `Some(Some(true))` for a whole comparison of a clock with a
    /// clock-free value (RT-9: RoboTool's `(true)&`), `Some(None)` after a
    /// problem; `None` when `g` reads no clock or the semantics is timed.
    pub(super) fn untimed_guard(&mut self, t: usize, g: &m::Expr) -> Option<Option<Expr>> {
        if self.timed() || !has_clock(g) {
            return None;
        }
        let tname = self.trans[t].m.name.clone();
        let range = g.range;
        if has_since_entry(g) {
            self.problem(
                range,
                format!(
                    "in the untimed semantics: the guard of `{tname}` uses `sinceEntry`: what RoboTool's untimed \
                     semantics makes of it is not established (RT-9 covers `since(C)` guards)"
                ),
            );
            return Some(None);
        }
        match &g.kind {
            m::ExprKind::Binary(op, a, b)
                if matches!(
                    op,
                    m::BinOp::Eq | m::BinOp::Ne | m::BinOp::Lt | m::BinOp::Le | m::BinOp::Gt | m::BinOp::Ge
                ) && has_clock(a) != has_clock(b) =>
            {
                Some(Some(Expr::Bool(true)))
            }
            _ => {
                self.problem(
                    range,
                    format!(
                        "in the untimed semantics: the guard of `{tname}` combines a comparison of a clock with other \
                         conditions: RoboTool's untimed semantics makes a clock guard `true` (RT-9), but whether that \
                         is the comparison or the whole guard is not established"
                    ),
                );
                Some(None)
            }
        }
    }

    /// Untimed: refuses `condition else` next to a guard of transition `u`
    /// that reads a clock (`true` when allowed).
    pub(super) fn else_allowed(&mut self, t: usize, u: usize) -> bool {
        let reads_clock = self.trans[u].m.condition.as_ref().and_then(|c| c.expr.as_ref()).is_some_and(has_clock);
        if self.timed() || !reads_clock {
            return true;
        }
        let (tname, uname) = (self.trans[t].m.name.clone(), self.trans[u].m.name.clone());
        self.problem(
            self.trans[t].m.name_range,
            format!(
                "in the untimed semantics: `{tname}` is a `condition else` next to the clock guard of `{uname}`: \
                 RoboTool's untimed semantics makes a clock guard `true` (RT-9), but what it makes of the `else` \
                 is not established"
            ),
        );
        false
    }
}

/// `e -> SKIP` for the event expression `e` (`opCall.1`).
fn plain(e: Expr) -> Expr {
    match e {
        Expr::Dot(parts) if matches!(parts.first(), Some(Expr::Name(_))) => match parts.split_first() {
            Some((Expr::Name(head), rest)) => {
                prefix(head.clone(), rest.iter().cloned().map(Field::Dot).collect(), Expr::Skip)
            }
            _ => prefix(crate::cspm::print_expr(&Expr::Dot(parts), usize::MAX), vec![], Expr::Skip),
        },
        Expr::Name(n) => prefix(n, vec![], Expr::Skip),
        // Event expressions are channels applied to values; print anything
        // else whole.
        e => prefix(crate::cspm::print_expr(&e, usize::MAX), vec![], Expr::Skip),
    }
}

/// Whether `e` reads a clock (`since(C)`, `sinceEntry(S)`).
fn has_clock(e: &m::Expr) -> bool {
    let mut found = false;
    e.walk(&mut |x| found |= matches!(x.kind, m::ExprKind::Since(_) | m::ExprKind::SinceEntry(_)));
    found
}

/// Whether `e` reads `sinceEntry(S)`.
fn has_since_entry(e: &m::Expr) -> bool {
    let mut found = false;
    e.walk(&mut |x| found |= matches!(x.kind, m::ExprKind::SinceEntry(_)));
    found
}
