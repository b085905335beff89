//! The names a `csp` block sees without defining them: FDR's built-ins and
//! the definitions RoboTool's generated script includes before the blocks
//! (its tock-CSP library, its core definitions and the default
//! instantiations' saturating arithmetic), each with its signature and a
//! one-line explanation for hovers and completion. The explanations are
//! ours, written from the definitions' behaviour.

/// What a library name denotes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CspLibKind {
    /// A channel (`tock`).
    Channel,
    /// A datatype constructor (`in`, `out`).
    Constructor,
    /// A process or a function returning one (`USTOP`, `StartBy`).
    Process,
    /// A function or a value.
    Function,
    /// A set of values (a type).
    Type,
}

/// Where a library name comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CspLibSource {
    /// Built into FDR.
    Fdr,
    /// Included by RoboTool's generated script.
    RoboTool,
}

/// One name of the library.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CspLibName {
    /// The name.
    pub name: &'static str,
    /// What it denotes.
    pub kind: CspLibKind,
    /// Where it comes from.
    pub source: CspLibSource,
    /// How it is called (`StartBy(P, d)`), or the name.
    pub signature: &'static str,
    /// One line: what it means.
    pub summary: &'static str,
}

use CspLibKind::{Channel as Ch, Constructor as Ctor, Function as F, Process as P, Type as T};
use CspLibSource::{Fdr, RoboTool};

macro_rules! library {
    ($($src:ident $kind:ident $name:literal $sig:literal $summary:literal;)*) => {
        /// Every library name, FDR's first.
        pub const LIBRARY: &[CspLibName] =
            &[$(CspLibName { name: $name, kind: $kind, source: $src, signature: $sig, summary: $summary }),*];
    };
}

library! {
    Fdr P "STOP" "STOP" "Deadlock: refuses every event (in a timed section it also refuses `tock`: a timelock).";
    Fdr P "SKIP" "SKIP" "Terminates successfully at once.";
    Fdr P "DIV" "DIV" "Diverges: performs internal actions forever.";
    Fdr P "RUN" "RUN(A)" "Offers every event of `A`, forever.";
    Fdr P "CHAOS" "CHAOS(A)" "May perform or refuse any event of `A`, forever: the most nondeterministic process over `A`.";
    Fdr P "WAIT" "WAIT(n)" "Inside a timed section: lets `n` `tock`s pass, then terminates.";
    Fdr P "TSTOP" "TSTOP" "Inside a timed section: refuses every event but lets time pass.";
    Fdr P "TSKIP" "TSKIP" "Inside a timed section: may let time pass, then terminates.";
    Fdr P "prioritise" "prioritise(P, <A1, A2, …>)" "`P` where an event of an earlier set (and τ, ✓ with the first) pre-empts those of later sets; `prioritise(P, <{}, {tock}>)` gives maximal progress.";
    Fdr P "timed_priority" "timed_priority(P)" "Inside a timed section: `P` where internal actions pre-empt `tock` (maximal progress).";
    Fdr P "dbisim" "dbisim(P)" "A compression: the same process, minimised by divergence-respecting bisimulation.";
    Fdr P "sbisim" "sbisim(P)" "A compression: the same process, minimised by strong bisimulation.";
    Fdr P "wbisim" "wbisim(P)" "A compression: the same process, minimised by weak bisimulation.";
    Fdr P "diamond" "diamond(P)" "A compression: the same process with internal actions eliminated.";
    Fdr P "normal" "normal(P)" "A compression: the same process, normalised.";
    Fdr P "explicate" "explicate(P)" "A compression: the same process, as an explicit transition system.";
    Fdr P "chase" "chase(P)" "`P` with its internal actions resolved eagerly (not a compression: may change the semantics).";
    Fdr F "union" "union(A, B)" "The union of two sets.";
    Fdr F "inter" "inter(A, B)" "The intersection of two sets.";
    Fdr F "diff" "diff(A, B)" "The elements of `A` not in `B`.";
    Fdr F "Union" "Union(S)" "The union of a set of sets.";
    Fdr F "Inter" "Inter(S)" "The intersection of a set of sets.";
    Fdr F "member" "member(x, A)" "Whether `x` is in `A`.";
    Fdr F "card" "card(A)" "The number of elements of `A`.";
    Fdr F "empty" "empty(A)" "Whether `A` has no element.";
    Fdr F "set" "set(s)" "The set of the elements of sequence `s`.";
    Fdr F "Set" "Set(A)" "Every subset of `A`.";
    Fdr F "seq" "seq(A)" "The elements of `A` as a sequence.";
    Fdr F "Seq" "Seq(A)" "Every sequence over `A`.";
    Fdr F "concat" "concat(s)" "The concatenation of a sequence of sequences.";
    Fdr F "head" "head(s)" "The first element of a non-empty sequence.";
    Fdr F "tail" "tail(s)" "A non-empty sequence without its first element.";
    Fdr F "length" "length(s)" "The number of elements of a sequence.";
    Fdr F "null" "null(s)" "Whether a sequence is empty.";
    Fdr F "elem" "elem(x, s)" "Whether `x` occurs in sequence `s`.";
    Fdr F "error" "error(msg)" "Stops the evaluation with a message.";
    Fdr F "show" "show(x)" "The text of a value.";
    Fdr T "Events" "Events" "Every event of every channel declared.";
    Fdr T "Int" "Int" "The integers.";
    Fdr T "Bool" "Bool" "`{false, true}`.";
    Fdr T "Char" "Char" "The characters.";
    Fdr T "Proc" "Proc" "The type of processes.";
    Fdr T "Event" "Event" "The type of events.";
    RoboTool Ch "tock" "tock" "The passage of one time unit (RoboTool's tock-CSP).";
    RoboTool Ch "tock'" "tock'" "A copy of `tock` RoboTool uses for its timed deadlock check.";
    RoboTool F "OneStep" "OneStep(e)" "The event function of RoboTool's timed sections: `Timed(OneStep) { … }` adds no implicit time (every event takes 0 `tock`s).";
    RoboTool P "USTOP" "USTOP" "A timelock: refuses every event and `tock` (untimed `STOP`).";
    RoboTool P "WAIT_INTERVAL" "WAIT_INTERVAL(S)" "Waits for a number of time units chosen nondeterministically from `S`, then terminates.";
    RoboTool P "StartBy" "StartBy(P, d)" "`P` must perform its first event within `d` time units (otherwise a timelock).";
    RoboTool P "EndBy" "EndBy(P, d)" "`P` must terminate within `d` time units (otherwise a timelock).";
    RoboTool P "Deadline" "Deadline(P, d)" "The same as `EndBy(P, d)`: `P` must terminate within `d` time units.";
    RoboTool P "EDeadline" "EDeadline(e, d)" "Event `e` must happen within `d` time units, then terminates.";
    RoboTool P "TimedInterrupt" "TimedInterrupt(P, d)" "Behaves as `P` for exactly `d` time units, then terminates (a strict timed interrupt).";
    RoboTool P "TimeOut" "TimeOut(P, d, Q)" "Behaves as `P` if it performs an event within `d` time units, otherwise as `Q`.";
    RoboTool P "TimeOut_1" "TimeOut_1(P, Q)" "`TimeOut(P, 1, Q)` for a `P` without an initial deadline (usable in recursion).";
    RoboTool P "TimedInterrupt_1" "TimedInterrupt_1(P)" "`TimedInterrupt(P, 1)` for a `P` without a deadline.";
    RoboTool P "TimedInterruptSeq" "TimedInterruptSeq(e, d, Q)" "Offers `e` repeatedly for `d` time units, then behaves as `Q`.";
    RoboTool P "TCHAOS" "TCHAOS(S)" "The tick-tock chaos over `S`: may perform or refuse events of `S`, let time pass, timelock or deadlock (the top of the refinement order).";
    RoboTool P "wait" "wait(n)" "Outside timed sections: performs `n` `tock`s, then terminates.";
    RoboTool P "RT__" "RT__(d)" "Offers every event but `tock` for `d` time units, then terminates (used by `TimedInterrupt`).";
    RoboTool P "Some__" "Some__" "Performs any one event, then terminates.";
    RoboTool P "SKIP_ANYTIME" "SKIP_ANYTIME" "May let time pass, and terminates at any time.";
    RoboTool P "CRUN" "CRUN(A)" "`RUN(union(A, {tock}))`: offers the events of `A` and `tock`, forever.";
    RoboTool P "TRUN" "TRUN(A)" "The same as `CRUN(A)`.";
    RoboTool P "SStop" "SStop" "A stop that still offers `share__` (and `tock`): the end of a machine's behaviour.";
    RoboTool P "share__choice" "share__choice(P)" "`P`, offering `share__` while it waits.";
    RoboTool P "SHARE_WAIT" "SHARE_WAIT(d)" "Waits `d` time units, offering `share__` meanwhile, then terminates.";
    RoboTool P "SHARE_WAIT_INTERVAL" "SHARE_WAIT_INTERVAL(S)" "`SHARE_WAIT` for a number of time units chosen nondeterministically from `S`.";
    RoboTool Ch "share__" "share__" "RoboTool's event for access to shared variables.";
    RoboTool Ch "timed_share__" "timed_share__" "RoboTool's event for access to shared variables in the timed semantics.";
    RoboTool P "DoClockReset" "DoClockReset(CS)" "Performs the clock-reset events of `CS` in any order, then terminates.";
    RoboTool F "clock_type_max" "clock_type_max(S)" "The largest element of a set of clock values (0 when empty).";
    RoboTool F "clock_type_seq_max" "clock_type_seq_max(s, x)" "The largest of `x` and the elements of `s`.";
    RoboTool F "clock_type_plus" "clock_type_plus(x, y, T)" "`x + y` if it is in `T`, else `x` (a clock that saturates).";
    RoboTool F "LSeq" "LSeq(X, n)" "The sequences over `X` of length at most `n`.";
    RoboTool F "ILSeq" "ILSeq(X, n)" "The sequences over `X` without repetition, of length at most `n`.";
    RoboTool F "Relation" "Relation(A, B)" "Every relation between `A` and `B` (a set of sets of pairs).";
    RoboTool F "Function" "Function(A, B)" "Every total function from `A` to `B` (as sets of pairs).";
    RoboTool F "funcToSet" "funcToSet(f, A)" "The pairs `(x, f(x))` for `x` in `A`.";
    RoboTool F "callFunc" "callFunc(f, x)" "Applies a function given as a set of pairs.";
    RoboTool F "calc_type_max" "calc_type_max(S)" "The largest element of a set of integers (0 when empty).";
    RoboTool F "calc_type_seq_max" "calc_type_seq_max(s, x)" "The largest of `x` and the elements of `s`.";
    RoboTool F "calc_type_min" "calc_type_min(S)" "The smallest element of a set of integers.";
    RoboTool F "calc_type_seq_min" "calc_type_seq_min(s, x)" "The smallest of `x` and the elements of `s`.";
    RoboTool F "no_zero_div" "no_zero_div(x)" "`x`, or 1 when `x` is 0 (a divisor that is never zero).";
    RoboTool F "access_" "access_(s, n)" "The `n`-th element (from 1) of sequence `s`.";
    RoboTool F "update_" "update_(s, e, n)" "Sequence `s` with its `n`-th element (from 1) replaced by `e`.";
    RoboTool F "tuple2_1" "tuple2_1(t)" "The first component of a pair.";
    RoboTool F "tuple2_2" "tuple2_2(t)" "The second component of a pair.";
    RoboTool F "tuple3_1" "tuple3_1(t)" "The first component of a triple.";
    RoboTool F "tuple3_2" "tuple3_2(t)" "The second component of a triple.";
    RoboTool F "tuple3_3" "tuple3_3(t)" "The third component of a triple.";
    RoboTool T "InOut" "InOut" "The directions of a communication: `in | out`.";
    RoboTool Ctor "in" "in" "The direction of an event the element receives (`M::e.in.v`).";
    RoboTool Ctor "out" "out" "The direction of an event the element sends (`M::e.out.v`).";
    RoboTool F "model_shifting" "instance M = model_shifting(Sigma)" "RoboTool's module encoding the tick-tock model over the events `Sigma` (`M::TT(P)`, `M::RT(P)`).";
    RoboTool F "Plus" "Plus(a, b, T)" "`a + b` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
    RoboTool F "Minus" "Minus(a, b, T)" "`a - b` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
    RoboTool F "Mult" "Mult(a, b, T)" "`a * b` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
    RoboTool F "Div" "Div(a, b, T)" "`a / b` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
    RoboTool F "Modulus" "Modulus(a, b, T)" "`a % b` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
    RoboTool F "Neg" "Neg(a, T)" "`-a` if it is in type `T`, else `a` (RoboTool's saturating arithmetic).";
}

/// The library name `name`, if it is one.
pub fn lookup(name: &str) -> Option<&'static CspLibName> {
    LIBRARY.iter().find(|l| l.name == name)
}

#[cfg(test)]
mod tests {
    #[test]
    fn names_are_unique() {
        let mut seen = std::collections::HashSet::new();
        for l in super::LIBRARY {
            assert!(seen.insert(l.name), "duplicate library name {}", l.name);
        }
    }
}
