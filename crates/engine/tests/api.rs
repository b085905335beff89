//! What the engine's API promises that a verification fixture
//! (`test_data/verify`, run by `fixtures.rs`) cannot state.
//!
//! The verification algorithms on small explicit LTSs with known answers
//! (CSP laws, the oracle's examples), on generated LTSs for determinism
//! across thread counts, and on infinite or very deep LTSs for budgets,
//! cancellation and stack safety; then, at the end of the file, how
//! options are read and described, budgets that depend on the clock, and
//! the numbering of the events a lowering produces.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use robosim_engine::verify::{verify_texts, AsyncBuffer, Options, Semantics, Verdict};

use robosim_engine::algo::explicit::ExplicitLts;
use robosim_engine::algo::{
    check_determinism, find_deadlock, find_divergence, find_timed_deadlock, refines, DeadlockResult, DeterminismResult,
    DivergenceResult, Path, RefinementCex, RefinementResult, SemanticModel, TimedDeadlockResult,
};
use robosim_engine::budget::{Budget, Stats, Stop};
use robosim_engine::lts::{Event, Label, Lts, FIRST_VISIBLE, TAU, TICK, TOCK};

use SemanticModel::{Failures, FailuresDivergences as FD, Traces};

const A: Event = FIRST_VISIBLE;
const B: Event = FIRST_VISIBLE + 1;
const C: Event = FIRST_VISIBLE + 2;

/// An explicit LTS over the shared alphabet a, b, c (so refinement can
/// compare event ids across LTSs).
fn lts(edges: &[(usize, &str, usize)]) -> ExplicitLts {
    ExplicitLts::with_alphabet(&["a", "b", "c"], edges)
}

fn one_thread() -> Budget {
    Budget::default().with_threads(1)
}

/// (event, state) of each step, for compact assertions.
fn steps(path: &Path<usize>) -> Vec<(Event, usize)> {
    path.steps.iter().map(|(l, s)| (l.event, *s)).collect()
}

fn cycle_steps<S: Clone>(cycle: &[(Label, S)]) -> Vec<(Event, S)> {
    cycle.iter().map(|(l, s)| (l.event, s.clone())).collect()
}

// ---------------------------------------------------------------- deadlock

#[test]
fn deadlock_shortest_path_counts_tau_and_stops_at_the_first() {
    // 0 -a-> 1 -a-> 3 -a-> 5 (dead); 0 -b-> 2 -τ-> 4 (dead); 1 -c-> 0.
    let l = lts(&[(0, "a", 1), (0, "b", 2), (1, "a", 3), (1, "c", 0), (2, "tau", 4), (3, "a", 5)]);
    let (r, stats) = find_deadlock(&l, &one_thread(), None);
    let DeadlockResult::Deadlock(path) = r else { panic!("expected a deadlock, got {r:?}") };
    assert_eq!(path.initial, 0);
    assert_eq!(steps(&path), vec![(B, 2), (TAU, 4)]);
    assert_eq!(path.trace(), vec![B]);
    // Discovered when 4 is expanded: 0..=5 (5 from 3, expanded before 4).
    assert_eq!(stats.states, 6);
    assert_eq!(stats.transitions, 6);
    assert_eq!(stats.plies, 3);
}

#[test]
fn deadlock_at_the_initial_state() {
    let l = ExplicitLts::from_edges(&[]);
    let (r, stats) = find_deadlock(&l, &one_thread(), None);
    assert_eq!(r, DeadlockResult::Deadlock(Path { initial: 0, steps: vec![] }));
    assert_eq!((stats.states, stats.transitions, stats.plies), (1, 0, 1));
}

#[test]
fn deadlock_free_with_exact_counts() {
    let l = lts(&[(0, "a", 1), (0, "b", 2), (1, "tau", 0), (1, "c", 2), (2, "tock", 2)]);
    let (r, stats) = find_deadlock(&l, &one_thread(), None);
    assert_eq!(r, DeadlockResult::Free);
    assert_eq!((stats.states, stats.transitions, stats.plies), (3, 5, 2));
}

#[test]
fn termination_is_not_a_deadlock_unless_also_reached_otherwise() {
    // a → SKIP: the state after ✓ has no transitions but terminated.
    let skip = lts(&[(0, "a", 1), (1, "tick", 2)]);
    assert_eq!(find_deadlock(&skip, &one_thread(), None).0, DeadlockResult::Free);

    // 1 is reached by ✓ first, and later by b (after it was expanded).
    let late = lts(&[(0, "tick", 1), (0, "a", 2), (2, "b", 1)]);
    let DeadlockResult::Deadlock(path) = find_deadlock(&late, &one_thread(), None).0 else {
        panic!("state 1 is reachable by a non-✓ step")
    };
    assert_eq!(steps(&path), vec![(A, 2), (B, 1)]);

    // 1 is reached by ✓ and by b from the same state (before expansion).
    let same = lts(&[(0, "tick", 1), (0, "b", 1)]);
    let DeadlockResult::Deadlock(path) = find_deadlock(&same, &one_thread(), None).0 else {
        panic!("state 1 is reachable by b")
    };
    assert_eq!(steps(&path), vec![(B, 1)]);
}

/// A generated LTS on a `w × w` grid: `a`/`b` move right/down, `c` jumps
/// back (to a state no deeper), τ transposes; with `dead`, the states on
/// anti-diagonal `dead` with `x % 5 == 2` have no transitions (many
/// deadlocks at the same depth).
struct Grid {
    w: u32,
    dead: Option<u32>,
}

impl Lts for Grid {
    type State = u64;

    fn initial(&self) -> u64 {
        0
    }

    fn successors(&self, s: &u64, out: &mut Vec<(Label, u64)>) {
        let (x, y) = ((*s >> 32) as u32, *s as u32);
        let at = |x: u32, y: u32| (u64::from(x) << 32) | u64::from(y);
        if self.dead == Some(x + y) && x % 5 == 2 {
            return;
        }
        if x + 1 < self.w {
            out.push((Label::plain(A), at(x + 1, y)));
        }
        if y + 1 < self.w {
            out.push((Label::plain(B), at(x, y + 1)));
        }
        out.push((Label { event: C, note: x }, at((x * 7 + y * 3) % (x + 1), (x * 5 + y * 11) % (y + 1))));
        if x != y {
            out.push((Label::TAU, at(y, x)));
        }
    }
}

#[test]
fn results_and_counts_do_not_depend_on_threads_or_runs() {
    let free = Grid { w: 300, dead: None };
    let dead = Grid { w: 300, dead: Some(400) };
    let mut first: Option<(DeadlockResult<u64>, Stats, DeadlockResult<u64>, Stats)> = None;
    for threads in [1, 2, 4, 2, 1, 4] {
        let budget = Budget::default().with_threads(threads);
        let (rf, sf) = find_deadlock(&free, &budget, None);
        let (rd, sd) = find_deadlock(&dead, &budget, None);
        assert_eq!(rf, DeadlockResult::Free);
        assert_eq!(sf.states, 90_000);
        let DeadlockResult::Deadlock(path) = &rd else { panic!("expected a deadlock, got {rd:?}") };
        assert_eq!(path.trace().iter().filter(|&&e| e != C).count(), 400);
        assert!(sd.states > 50_000, "{sd:?}");
        match &first {
            None => first = Some((rf, sf, rd, sd)),
            Some((rf0, sf0, rd0, sd0)) => {
                assert_eq!(&rf, rf0, "threads = {threads}");
                assert_eq!(&rd, rd0, "threads = {threads}");
                let key = |s: &Stats| (s.states, s.transitions, s.plies);
                assert_eq!(key(&sf), key(sf0), "threads = {threads}");
                assert_eq!(key(&sd), key(sd0), "threads = {threads}");
            }
        }
    }
}

// -------------------------------------------------------------- refinement

/// a → STOP ⊓ b → STOP
fn internal_ab() -> ExplicitLts {
    lts(&[(0, "tau", 1), (0, "tau", 2), (1, "a", 3), (2, "b", 4)])
}

/// a → STOP □ b → STOP
fn external_ab() -> ExplicitLts {
    lts(&[(0, "a", 1), (0, "b", 2)])
}

/// a → STOP
fn a_stop() -> ExplicitLts {
    lts(&[(0, "a", 1)])
}

fn check(spec: &ExplicitLts, imp: &ExplicitLts, model: SemanticModel) -> RefinementResult<usize> {
    let r = refines(spec, imp, model, &one_thread(), None).0;
    let r2 = refines(spec, imp, model, &Budget::default().with_threads(3), None).0;
    assert_eq!(r, r2, "thread count changed the verdict");
    r
}

#[test]
fn trace_counterexample_ends_with_the_offending_step() {
    let imp = lts(&[(0, "a", 1), (1, "b", 2)]);
    for model in [Traces, Failures, FD] {
        let RefinementResult::Fails(RefinementCex::Trace { path, event }) = check(&a_stop(), &imp, model) else {
            panic!("expected a trace counterexample in {model:?}")
        };
        assert_eq!(steps(&path), vec![(A, 1), (B, 2)]);
        assert_eq!(event, Label::plain(B));
    }
}

#[test]
fn refusal_counterexample_lists_the_minimal_acceptances() {
    // (a □ b) ⊓ (a □ b □ c) ⊓ c: minimal acceptances {a, b} and {c}.
    let spec = lts(&[
        (0, "tau", 1),
        (0, "tau", 2),
        (0, "tau", 3),
        (1, "a", 4),
        (1, "b", 4),
        (2, "a", 4),
        (2, "b", 4),
        (2, "c", 4),
        (3, "c", 4),
    ]);
    for model in [Failures, FD] {
        let r = check(&spec, &a_stop(), model);
        assert_eq!(
            r,
            RefinementResult::Fails(RefinementCex::Refusal {
                path: Path { initial: 0, steps: vec![] },
                offered: vec![A],
                acceptances: vec![vec![A, B], vec![C]],
            }),
            "{model:?}"
        );
    }
    // The traces model ignores refusals.
    assert_eq!(check(&spec, &a_stop(), Traces), RefinementResult::Holds);
}

#[test]
fn divergence_counts_only_in_the_failures_divergences_model() {
    // a → STOP, or τ into a τ-loop 2 ⇄ 3.
    let imp = lts(&[(0, "a", 1), (0, "tau", 2), (2, "tau", 3), (3, "tau", 2)]);
    let RefinementResult::Fails(RefinementCex::Divergence { path, cycle }) = check(&a_stop(), &imp, FD) else {
        panic!("expected a divergence")
    };
    assert!(path.is_empty());
    assert_eq!(cycle_steps(&cycle), vec![(TAU, 2), (TAU, 3), (TAU, 2)]);
    assert_eq!(check(&a_stop(), &imp, Failures), RefinementResult::Holds);
    assert_eq!(check(&a_stop(), &imp, Traces), RefinementResult::Holds);
}

#[test]
fn a_divergent_specification_node_allows_anything_in_fd() {
    // Spec a → DIV; impl a → b → STOP.
    let spec = lts(&[(0, "a", 1), (1, "tau", 1)]);
    let imp = lts(&[(0, "a", 1), (1, "b", 2)]);
    assert_eq!(check(&spec, &imp, FD), RefinementResult::Holds);
    // Traces: b is not a trace of the spec.
    assert!(matches!(check(&spec, &imp, Traces), RefinementResult::Fails(RefinementCex::Trace { .. })));
    // Stable failures: DIV has no stable failure, so the stable state
    // after a refuses too much (no acceptance at all).
    assert_eq!(
        check(&spec, &imp, Failures),
        RefinementResult::Fails(RefinementCex::Refusal {
            path: Path { initial: 0, steps: vec![(Label::plain(A), 1)] },
            offered: vec![B],
            acceptances: vec![],
        })
    );
    // And a divergent implementation is fine under a divergent spec.
    let div_imp = lts(&[(0, "a", 1), (1, "tau", 2), (2, "tau", 1)]);
    assert_eq!(check(&spec, &div_imp, FD), RefinementResult::Holds);
}

#[test]
fn internal_and_external_choice_laws() {
    // a → STOP ⊓ b → STOP ⊑ a → STOP, in every model.
    for model in [Traces, Failures, FD] {
        assert_eq!(check(&internal_ab(), &a_stop(), model), RefinementResult::Holds);
    }
    // Not conversely: the internal choice can refuse a (F, FD) and do b (T).
    assert!(matches!(check(&a_stop(), &internal_ab(), Traces), RefinementResult::Fails(RefinementCex::Trace { .. })));
    for model in [Failures, FD] {
        let RefinementResult::Fails(RefinementCex::Refusal { path, offered, acceptances }) =
            check(&a_stop(), &internal_ab(), model)
        else {
            panic!("expected a refusal in {model:?}")
        };
        assert_eq!(steps(&path), vec![(TAU, 2)]);
        assert_eq!(offered, vec![B]);
        assert_eq!(acceptances, vec![vec![A]]);
    }
    // External choice refines internal choice; not conversely (F, FD),
    // though they have the same traces.
    for model in [Traces, Failures, FD] {
        assert_eq!(check(&internal_ab(), &external_ab(), model), RefinementResult::Holds);
    }
    assert_eq!(check(&external_ab(), &internal_ab(), Traces), RefinementResult::Holds);
    for model in [Failures, FD] {
        assert_eq!(
            check(&external_ab(), &internal_ab(), model),
            RefinementResult::Fails(RefinementCex::Refusal {
                path: Path { initial: 0, steps: vec![(Label::TAU, 1)] },
                offered: vec![A],
                acceptances: vec![vec![A, B]],
            })
        );
    }
}

#[test]
fn oracle_example_two_stable_states_against_stop() {
    // semantics_oracle.py `fd_refines`: the spec's stable members accept
    // {a} and {b}; STOP refuses both.
    let stop = lts(&[]);
    assert_eq!(
        check(&internal_ab(), &stop, FD),
        RefinementResult::Fails(RefinementCex::Refusal {
            path: Path { initial: 0, steps: vec![] },
            offered: vec![],
            acceptances: vec![vec![A], vec![B]],
        })
    );
    assert_eq!(check(&internal_ab(), &stop, Traces), RefinementResult::Holds);
}

#[test]
fn tock_and_tick_are_visible_events_for_refinement() {
    // Spec: tock → a → STOP. Impl: a → STOP (a before the tock).
    let spec = lts(&[(0, "tock", 1), (1, "a", 2)]);
    let imp = lts(&[(0, "a", 1)]);
    let RefinementResult::Fails(RefinementCex::Refusal { offered, acceptances, .. }) = check(&spec, &imp, FD) else {
        panic!("the impl refuses tock")
    };
    assert_eq!((offered, acceptances), (vec![A], vec![vec![TOCK]]));
    let skip = lts(&[(0, "tick", 1)]);
    let stop = lts(&[]);
    assert!(matches!(
        check(&stop, &skip, Traces),
        RefinementResult::Fails(RefinementCex::Trace { event: Label { event: TICK, .. }, .. })
    ));
    assert_eq!(check(&skip, &skip, FD), RefinementResult::Holds);
}

// ------------------------------------------------------ tick-tock model

/// An internal choice made once (`Once`: 0 -τ-> 1 or 2, each offering its
/// event and letting time pass forever) against one made again after
/// every `tock` (`Again`: back to the choosing state after each `tock`).
/// Their traces and stable failures are the same, so FD cannot tell them
/// apart; tick-tock records that `Once` refused `b` before time passed
/// and so cannot do `b` afterwards (semantics.md §7.5, simGeneric-1).
fn once_and_again() -> (ExplicitLts, ExplicitLts) {
    let once = lts(&[(0, "tau", 1), (0, "tau", 2), (1, "a", 3), (1, "tock", 1), (2, "b", 3), (2, "tock", 2)]);
    let again = lts(&[(0, "tau", 1), (0, "tau", 2), (1, "a", 3), (1, "tock", 0), (2, "b", 3), (2, "tock", 0)]);
    (once, again)
}

#[test]
fn tick_tock_tells_apart_choices_that_fd_equates() {
    use SemanticModel::TickTock;
    let (once, again) = once_and_again();
    for (spec, imp) in [(&once, &again), (&again, &once)] {
        let (r, _) = refines(spec, imp, FD, &one_thread(), None);
        assert_eq!(r, RefinementResult::Holds);
    }
    // `Again` ⊑ `Once`: every tick-tock observation of `Once` is one of `Again`.
    let (r, _) = refines(&again, &once, TickTock, &one_thread(), None);
    assert_eq!(r, RefinementResult::Holds);
    // `Once` ⋢ `Again`: after choosing `a` (refusing b), time passes, and
    // `Again` may choose `b`, refusing the `a` that `Once` must still offer.
    let (r, _) = refines(&once, &again, TickTock, &one_thread(), None);
    let RefinementResult::Fails(RefinementCex::Refusal { path, offered, acceptances }) = r else {
        panic!("expected a refusal, got {r:?}")
    };
    assert_eq!(steps(&path), vec![(TAU, 1), (TOCK, 0), (TAU, 2)]);
    assert_eq!(offered, vec![TOCK, B]);
    assert_eq!(acceptances, vec![vec![TOCK, A]]);
}

#[test]
fn tick_tock_reports_time_passing_while_refusing_too_much() {
    use SemanticModel::TickTock;
    // The specification may stop (0 -τ-> 2, a stable state refusing
    // everything, time included) or offer `a` until time passes (1), and
    // then only let time pass (4). The implementation only lets time pass:
    // its stable failures are allowed (by the stopped state, then by 4),
    // but no specification state lets time pass while refusing `a`.
    let spec = lts(&[(0, "tau", 1), (0, "tau", 2), (1, "a", 3), (1, "tock", 4), (4, "tock", 4)]);
    let imp = lts(&[(0, "tock", 0)]);
    let (r, _) = refines(&spec, &imp, Failures, &one_thread(), None);
    assert_eq!(r, RefinementResult::Holds);
    let (r, _) = refines(&spec, &imp, TickTock, &one_thread(), None);
    let RefinementResult::Fails(RefinementCex::TockRefusal { path, offered, acceptances }) = r else {
        panic!("expected a tock refusal, got {r:?}")
    };
    assert_eq!(steps(&path), vec![(TOCK, 0)]);
    assert_eq!(offered, vec![TOCK]);
    assert_eq!(acceptances, vec![vec![TOCK, A]]);
    // A process refines itself; a time-stop refines nothing that lets time pass.
    for p in [&spec, &imp] {
        assert_eq!(refines(p, p, TickTock, &one_thread(), None).0, RefinementResult::Holds);
    }
}

#[test]
fn tick_tock_ignores_tock_at_unstable_states() {
    use SemanticModel::TickTock;
    // `tock` offered beside a τ records no refusal: only the plain trace
    // must be allowed, as in the other models.
    let spec = lts(&[(0, "a", 1), (0, "tock", 0)]);
    let imp = lts(&[(0, "tau", 2), (0, "tock", 0), (2, "a", 1), (2, "tock", 0)]);
    assert_eq!(refines(&spec, &imp, TickTock, &one_thread(), None).0, RefinementResult::Holds);
}

// ------------------------------------------------ divergence, determinism

#[test]
fn mu_x_tau_x_diverges() {
    let l = lts(&[(0, "tau", 0)]);
    let (r, stats) = find_divergence(&l, &one_thread(), None);
    assert_eq!(
        r,
        DivergenceResult::Divergent { path: Path { initial: 0, steps: vec![] }, cycle: vec![(Label::TAU, 0)] }
    );
    assert_eq!(stats.states, 1);
    // After a, a τ-chain into a loop: path to the first divergent state,
    // lasso from there.
    let l = lts(&[(0, "a", 1), (1, "tau", 2), (2, "tau", 3), (3, "tau", 2), (0, "b", 4)]);
    let DivergenceResult::Divergent { path, cycle } = find_divergence(&l, &one_thread(), None).0 else {
        panic!("diverges after a")
    };
    assert_eq!(steps(&path), vec![(A, 1)]);
    assert_eq!(cycle_steps(&cycle), vec![(TAU, 2), (TAU, 3), (TAU, 2)]);
    assert_eq!(find_divergence(&external_ab(), &one_thread(), None).0, DivergenceResult::Free);
    // τ without a cycle is not divergence.
    assert_eq!(find_divergence(&internal_ab(), &one_thread(), None).0, DivergenceResult::Free);
}

#[test]
fn determinism_of_external_versus_internal_choice() {
    let (r, stats) = check_determinism(&external_ab(), &one_thread(), None);
    assert_eq!(r, DeterminismResult::Deterministic);
    assert_eq!(stats.states, 3);
    let (r, _) = check_determinism(&internal_ab(), &one_thread(), None);
    assert_eq!(
        r,
        DeterminismResult::Nondeterministic { path: Path { initial: 0, steps: vec![(Label::TAU, 1)] }, event: B }
    );
    // A τ that does not change what can be done is still deterministic.
    let l = lts(&[(0, "tau", 1), (1, "a", 2), (2, "b", 0)]);
    assert_eq!(check_determinism(&l, &one_thread(), None).0, DeterminismResult::Deterministic);
    // Divergence after a.
    let l = lts(&[(0, "a", 1), (1, "tau", 2), (2, "tau", 1)]);
    let DeterminismResult::Divergent { path, cycle } = check_determinism(&l, &one_thread(), None).0 else {
        panic!("diverges after a")
    };
    assert_eq!(steps(&path), vec![(A, 1)]);
    assert_eq!(cycle_steps(&cycle), vec![(TAU, 2), (TAU, 1)]);
    // Nondeterminism after a trace: a → (b → STOP) ⊓ (c → STOP) ...
    // written as two a-branches.
    let l = lts(&[(0, "a", 1), (0, "a", 2), (1, "b", 3), (2, "c", 3)]);
    let DeterminismResult::Nondeterministic { path, event } = check_determinism(&l, &one_thread(), None).0 else {
        panic!("a then b or c is nondeterministic")
    };
    assert_eq!((steps(&path), event), (vec![(A, 1)], C));
}

// ----------------------------------------------------------- timed deadlock

#[test]
fn timed_deadlock_is_a_cycle_of_forced_tocks() {
    // After a, only time passes.
    let l = lts(&[(0, "a", 1), (0, "tock", 0), (1, "tock", 1)]);
    let (r, stats) = find_timed_deadlock(&l, &one_thread(), None);
    assert_eq!(
        r,
        TimedDeadlockResult::TimedDeadlock {
            path: Path { initial: 0, steps: vec![(Label::plain(A), 1)] },
            cycle: vec![(Label::TOCK, 1)],
        }
    );
    assert_eq!(stats.states, 2);
    // Two states alternating by tock.
    let l = lts(&[(0, "a", 1), (1, "tock", 2), (2, "tock", 1)]);
    let TimedDeadlockResult::TimedDeadlock { path, cycle } = find_timed_deadlock(&l, &one_thread(), None).0 else {
        panic!("1 and 2 only let time pass")
    };
    assert_eq!(steps(&path), vec![(A, 1)]);
    assert_eq!(cycle_steps(&cycle), vec![(TOCK, 2), (TOCK, 1)]);
    // A state that can also do a, or ✓, is not stuck in time.
    for other in ["a", "tick"] {
        let l = lts(&[(0, "tock", 0), (0, other, 0)]);
        assert_eq!(find_timed_deadlock(&l, &one_thread(), None).0, TimedDeadlockResult::Free, "{other}");
    }
    // Internal steps between the tocks do not help: τ, tock, τ, tock, …
    // (RoboTool hides the prioritised tock, so this diverges).
    let l = lts(&[(0, "tau", 1), (1, "tock", 0), (1, "a", 2)]);
    assert_eq!(find_timed_deadlock(&l, &one_thread(), None).0, TimedDeadlockResult::Free, "a is offered with tock");
    let l = lts(&[(0, "tau", 1), (1, "tock", 0)]);
    let TimedDeadlockResult::TimedDeadlock { path, cycle } = find_timed_deadlock(&l, &one_thread(), None).0 else {
        panic!("only internal steps and time")
    };
    assert_eq!(steps(&path), vec![]);
    assert_eq!(cycle_steps(&cycle), vec![(TAU, 1), (TOCK, 0)]);
    // A timelock (no transition at all) is not a timed deadlock.
    let l = lts(&[(0, "tock", 1), (1, "tock", 2)]);
    assert_eq!(find_timed_deadlock(&l, &one_thread(), None).0, TimedDeadlockResult::Free);
}

// ----------------------------------------------------------------- budgets

/// An infinite binary tree: n → 2n+1 (a), 2n+2 (b); τ-free, no deadlock.
struct Tree;

impl Lts for Tree {
    type State = u64;

    fn initial(&self) -> u64 {
        0
    }

    fn successors(&self, s: &u64, out: &mut Vec<(Label, u64)>) {
        out.push((Label::plain(A), s.wrapping_mul(2).wrapping_add(1)));
        out.push((Label::plain(B), s.wrapping_mul(2).wrapping_add(2)));
    }
}

#[test]
fn state_budget_stops_every_algorithm() {
    let budget = Budget { max_states: 1000, ..Budget::default() };
    let (r, s) = find_deadlock(&Tree, &budget, None);
    assert_eq!(r, DeadlockResult::Inconclusive(Stop::States));
    assert_eq!(s.states, 1000);
    let (r, s) = find_divergence(&Tree, &budget, None);
    assert_eq!(r, DivergenceResult::Inconclusive(Stop::States));
    assert!(s.states <= 1000);
    let (r, s) = find_timed_deadlock(&Tree, &budget, None);
    assert_eq!(r, TimedDeadlockResult::Inconclusive(Stop::States));
    assert!(s.states <= 1000);
    let (r, s) = refines(&Tree, &Tree, FD, &budget, None);
    assert_eq!(r, RefinementResult::Inconclusive(Stop::States));
    assert!(s.states <= 1000);
    let (r, s) = check_determinism(&Tree, &budget, None);
    assert_eq!(r, DeterminismResult::Inconclusive(Stop::States));
    assert!(s.states <= 1000);
    assert_eq!(Stop::States.reason(&budget), "state budget of 1000 states reached before a verdict");
}

#[test]
fn memory_budget_stops_before_overshooting() {
    let budget = Budget { max_bytes: 1 << 20, ..Budget::default() };
    let (r, s) = find_deadlock(&Tree, &budget, None);
    assert_eq!(r, DeadlockResult::Inconclusive(Stop::Memory));
    assert!(s.bytes <= 1 << 20 && s.states > 10_000, "{s:?}");
    let (r, _) = refines(&Tree, &Tree, FD, &budget, None);
    assert_eq!(r, RefinementResult::Inconclusive(Stop::Memory));
}

#[test]
fn timeout_stops_the_search() {
    let budget = Budget { timeout: Some(Duration::from_millis(50)), ..Budget::default() };
    let started = Instant::now();
    let (r, s) = find_deadlock(&Tree, &budget, None);
    assert_eq!(r, DeadlockResult::Inconclusive(Stop::Time));
    assert!(started.elapsed() < Duration::from_secs(1));
    assert!(s.seconds >= 0.05);
    let (r, _) = refines(&Tree, &Tree, FD, &budget, None);
    assert_eq!(r, RefinementResult::Inconclusive(Stop::Time));
}

#[test]
fn cancellation_takes_effect_promptly() {
    for threads in [1, 2] {
        let flag = Arc::new(AtomicBool::new(false));
        let budget = Budget { cancel: Some(flag.clone()), ..Budget::default().with_threads(threads) };
        let started = Instant::now();
        let set_at = std::thread::scope(|scope| {
            let setter = scope.spawn(|| {
                std::thread::sleep(Duration::from_millis(50));
                flag.store(true, Ordering::Relaxed);
                Instant::now()
            });
            let (r, _) = find_deadlock(&Tree, &budget, None);
            assert_eq!(r, DeadlockResult::Inconclusive(Stop::Cancelled));
            let returned = Instant::now();
            let set_at = setter.join().expect("setter thread");
            returned.saturating_duration_since(set_at)
        });
        assert!(started.elapsed() < Duration::from_secs(1));
        eprintln!("threads = {threads}: returned {set_at:?} after cancellation");
    }
}

#[test]
fn progress_is_reported_periodically_and_at_the_end() {
    let calls = AtomicUsize::new(0);
    let last = std::sync::Mutex::new(Stats::default());
    let report = |s: &Stats| {
        calls.fetch_add(1, Ordering::Relaxed);
        *last.lock().expect("lock") = *s;
    };
    // Reports come about every 100 ms from the searching thread; on a
    // loaded machine it may be descheduled, so only the order of magnitude
    // is asserted: at least one report before the final one, and not one
    // per state.
    let budget = Budget { timeout: Some(Duration::from_millis(1000)), ..Budget::default() };
    let (r, stats) = find_deadlock(&Tree, &budget, Some(&report));
    assert_eq!(r, DeadlockResult::Inconclusive(Stop::Time));
    let n = calls.load(Ordering::Relaxed);
    assert!((2..=15).contains(&n), "{n} progress calls");
    assert_eq!(*last.lock().expect("lock"), stats);
}

// ------------------------------------------------------------- deep chains

/// A chain 0 → 1 → … → n of `event` steps; state n has a `last` step to
/// itself, or nothing.
struct Chain {
    n: u32,
    event: Event,
    last: Option<Event>,
}

impl Lts for Chain {
    type State = u32;

    fn initial(&self) -> u32 {
        0
    }

    fn successors(&self, s: &u32, out: &mut Vec<(Label, u32)>) {
        if *s < self.n {
            out.push((Label::plain(self.event), s + 1));
        } else if let Some(e) = self.last {
            out.push((Label::plain(e), *s));
        }
    }
}

const DEEP: u32 = 1_000_000;

// One test per algorithm, so the harness runs them side by side.

#[test]
fn deep_chain_deadlock() {
    let visible = Chain { n: DEEP, event: A, last: None };
    let DeadlockResult::Deadlock(path) = find_deadlock(&visible, &one_thread(), None).0 else {
        panic!("the chain ends in STOP")
    };
    assert_eq!((path.len(), *path.last()), (DEEP as usize, DEEP));
}

#[test]
fn deep_chain_divergence() {
    let taus = Chain { n: DEEP, event: TAU, last: Some(TAU) };
    let DivergenceResult::Divergent { path, cycle } = find_divergence(&taus, &one_thread(), None).0 else {
        panic!("the τ-chain ends in a τ-loop")
    };
    assert!(path.is_empty());
    assert_eq!(cycle.len(), DEEP as usize + 1);
    assert_eq!(cycle.last(), Some(&(Label::TAU, DEEP)));
}

#[test]
fn deep_chain_timed_deadlock() {
    let tocks = Chain { n: DEEP, event: TOCK, last: Some(TOCK) };
    let TimedDeadlockResult::TimedDeadlock { path, cycle } = find_timed_deadlock(&tocks, &one_thread(), None).0 else {
        panic!("only time passes")
    };
    // Every state is on the way to the loop, but only the last is on it.
    assert_eq!((path.len(), cycle_steps(&cycle)), (DEEP as usize, vec![(TOCK, DEEP)]));
}

#[test]
fn deep_chain_refinement_through_a_deep_tau_graph() {
    // A τ-chain into STOP refines STOP: the divergence test walks the
    // whole τ-chain.
    let tau_stop = Chain { n: DEEP, event: TAU, last: None };
    let (r, s) = refines(&lts(&[]), &tau_stop, FD, &one_thread(), None);
    assert_eq!(r, RefinementResult::Holds);
    assert_eq!(s.states, u64::from(DEEP) + 1);
}

#[test]
fn deep_chain_refinement_against_a_deep_spec() {
    // Every spec state is its own normal-form node.
    let visible = Chain { n: DEEP, event: A, last: None };
    let (r, s) = refines(&visible, &visible, FD, &one_thread(), None);
    assert_eq!(r, RefinementResult::Holds);
    assert_eq!(s.states, u64::from(DEEP) + 1);
}

#[test]
fn deep_chain_determinism() {
    let visible = Chain { n: DEEP, event: A, last: None };
    let (r, s) = check_determinism(&visible, &one_thread(), None);
    assert_eq!(r, DeterminismResult::Deterministic);
    assert_eq!(s.states, u64::from(DEEP) + 1);
    // One node holding the whole τ-chain, divergent at its end.
    let taus = Chain { n: DEEP, event: TAU, last: Some(TAU) };
    let (r, _) = check_determinism(&taus, &one_thread(), None);
    let DeterminismResult::Divergent { path, cycle } = r else { panic!("the τ-chain diverges") };
    assert!(path.is_empty());
    assert_eq!(cycle.len(), DEEP as usize + 1);
}

// ------------------------------------------- differential: the oracle's BFS

/// A tiny deterministic pseudo-random generator (xorshift).
struct Rng(u64);

impl Rng {
    fn next(&mut self, bound: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % bound
    }
}

fn random_lts(rng: &mut Rng, states: usize) -> ExplicitLts {
    let names = ["tau", "a", "b"];
    let mut edges = Vec::new();
    for s in 0..states {
        for _ in 0..rng.next(3) {
            edges.push((s, names[rng.next(3) as usize], rng.next(states as u64) as usize));
        }
    }
    let mut l = lts(&edges);
    l.trans.resize(states, Vec::new());
    l
}

/// `semantics_oracle.py`'s `fd_refines`, transcribed: the verdict kind and
/// the visible trace of the counterexample.
fn oracle_fd_refines(spec: &ExplicitLts, imp: &ExplicitLts) -> Option<(&'static str, Vec<Event>)> {
    use std::collections::{BTreeSet, HashMap, VecDeque};
    fn divergent(t: &ExplicitLts) -> BTreeSet<usize> {
        let mut cand: BTreeSet<usize> = (0..t.len()).collect();
        loop {
            let drop: Vec<usize> = cand
                .iter()
                .copied()
                .filter(|&i| !t.trans[i].iter().any(|(l, j)| l.event == TAU && cand.contains(j)))
                .collect();
            if drop.is_empty() {
                return cand;
            }
            for i in drop {
                cand.remove(&i);
            }
        }
    }
    fn closure(t: &ExplicitLts, seed: BTreeSet<usize>) -> BTreeSet<usize> {
        let mut seen = seed.clone();
        let mut stack: Vec<usize> = seed.into_iter().collect();
        while let Some(s) = stack.pop() {
            for (l, u) in &t.trans[s] {
                if l.event == TAU && seen.insert(*u) {
                    stack.push(*u);
                }
            }
        }
        seen
    }
    type Pair = (BTreeSet<usize>, usize);
    let (sdiv, idiv) = (divergent(spec), divergent(imp));
    let start: Pair = (closure(spec, BTreeSet::from([0])), 0);
    let mut parent: HashMap<Pair, Option<(Pair, Event)>> = HashMap::from([(start.clone(), None)]);
    let mut queue = VecDeque::from([start]);
    let trace = |parent: &HashMap<Pair, Option<(Pair, Event)>>, mut x: Pair| {
        let mut tr = Vec::new();
        while let Some(Some((p, e))) = parent.get(&x) {
            if *e != TAU {
                tr.push(*e);
            }
            x = p.clone();
        }
        tr.reverse();
        tr
    };
    while let Some((n, i)) = queue.pop_front() {
        if n.iter().any(|s| sdiv.contains(s)) {
            continue;
        }
        if idiv.contains(&i) {
            return Some(("divergence", trace(&parent, (n, i))));
        }
        if !imp.trans[i].iter().any(|(l, _)| l.event == TAU) {
            let offered: BTreeSet<Event> = imp.trans[i].iter().map(|(l, _)| l.event).collect();
            let ok = n
                .iter()
                .filter(|&&s| !spec.trans[s].iter().any(|(l, _)| l.event == TAU))
                .any(|&s| spec.trans[s].iter().all(|(l, _)| offered.contains(&l.event)));
            if !ok {
                return Some(("refusal", trace(&parent, (n, i))));
            }
        }
        for (l, j) in &imp.trans[i] {
            let n2 = if l.event == TAU {
                n.clone()
            } else {
                let seed: BTreeSet<usize> = n
                    .iter()
                    .flat_map(|&s| spec.trans[s].iter())
                    .filter(|(m, _)| m.event == l.event)
                    .map(|&(_, t)| t)
                    .collect();
                if seed.is_empty() {
                    let mut tr = trace(&parent, (n, i));
                    tr.push(l.event);
                    return Some(("trace", tr));
                }
                closure(spec, seed)
            };
            let key = (n2, *j);
            if !parent.contains_key(&key) {
                parent.insert(key.clone(), Some(((n.clone(), i), l.event)));
                queue.push_back(key);
            }
        }
    }
    None
}

#[test]
fn fd_refinement_agrees_with_the_oracle_on_random_ltss() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut kinds = std::collections::BTreeMap::new();
    for _ in 0..2000 {
        let (n, m) = (1 + rng.next(4) as usize, 1 + rng.next(5) as usize);
        let spec = random_lts(&mut rng, n);
        let imp = random_lts(&mut rng, m);
        let expected = oracle_fd_refines(&spec, &imp);
        let got = match check(&spec, &imp, FD) {
            RefinementResult::Holds => None,
            RefinementResult::Fails(RefinementCex::Trace { path, .. }) => Some(("trace", path.trace())),
            RefinementResult::Fails(RefinementCex::Refusal { path, .. }) => Some(("refusal", path.trace())),
            RefinementResult::Fails(RefinementCex::Divergence { path, cycle }) => {
                assert!(!cycle.is_empty() && cycle.iter().all(|(l, _)| l.event == TAU));
                Some(("divergence", path.trace()))
            }
            RefinementResult::Fails(c @ RefinementCex::TockRefusal { .. }) => panic!("not in FD: {c:?}"),
            RefinementResult::Inconclusive(stop) => panic!("{stop}"),
        };
        assert_eq!(got, expected, "spec {spec:?}\nimpl {imp:?}");
        *kinds.entry(got.map_or("holds", |g| g.0)).or_insert(0) += 1;
    }
    // The sample exercises every verdict.
    assert_eq!(kinds.len(), 4, "{kinds:?}");
}

/// `semantics_oracle.py`'s `deadlock_bfs`: states discovered and the trace.
fn oracle_deadlock(l: &ExplicitLts) -> (usize, Option<Vec<Event>>) {
    use std::collections::{HashMap, VecDeque};
    let mut parent: HashMap<usize, Option<(usize, Event)>> = HashMap::from([(0, None)]);
    let mut queue = VecDeque::from([0]);
    while let Some(s) = queue.pop_front() {
        if l.trans[s].is_empty() {
            let mut tr = Vec::new();
            let mut at = s;
            while let Some(Some((p, e))) = parent.get(&at) {
                if *e != TAU {
                    tr.push(*e);
                }
                at = *p;
            }
            tr.reverse();
            return (parent.len(), Some(tr));
        }
        for (lab, t) in &l.trans[s] {
            if !parent.contains_key(t) {
                parent.insert(*t, Some((s, lab.event)));
                queue.push_back(*t);
            }
        }
    }
    (parent.len(), None)
}

#[test]
fn deadlock_search_agrees_with_the_oracle_on_random_ltss() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for _ in 0..2000 {
        let n = 1 + rng.next(12) as usize;
        let l = random_lts(&mut rng, n);
        let (count, trace) = oracle_deadlock(&l);
        let (r, stats) = find_deadlock(&l, &one_thread(), None);
        let got = match r {
            DeadlockResult::Free => None,
            DeadlockResult::Deadlock(path) => Some(path.trace()),
            DeadlockResult::Inconclusive(stop) => panic!("{stop}"),
        };
        assert_eq!((stats.states as usize, got), (count, trace), "{l:?}");
    }
}

// ----------------------------------------------------- options and lowering

fn buffer(text: &str) -> AsyncBuffer {
    AsyncBuffer::parse(text).expect("a buffer")
}

/// `--async-buffer` (robotool-facts.md RT-12): a size from 1 to 8 and an
/// optional policy; nothing else.
#[test]
fn buffer_assumptions_are_read_strictly() {
    assert_eq!(AsyncBuffer::parse("3"), Ok(AsyncBuffer { size: 3, overwrite: true }));
    assert_eq!(AsyncBuffer::parse("2:block"), Ok(AsyncBuffer { size: 2, overwrite: false }));
    for bad in ["0", "9:overwrite", "x", "1:drop", ""] {
        assert!(AsyncBuffer::parse(bad).is_err(), "{bad}");
    }
}

/// The note every report under a buffer assumption carries says whether it
/// is RoboTool's own buffer or one the user assumed.
#[test]
fn buffer_assumptions_are_described() {
    assert!(buffer("1:overwrite").describe().contains(
        "buffer 1 value; when full, a new value replaces the oldest (RoboTool's buffer between controllers, RT-12)"
    ));
    assert!(buffer("2:block").describe().ends_with(
        "when full, the sender waits (assumed with `--async-buffer`; RoboTool's buffer between controllers is `1:overwrite`)"
    ));
}

/// A check whose time is up before it starts is inconclusive (or, on a
/// machine fast enough to finish before the first look at the clock,
/// decided); never a wrong verdict. (A spent state budget is the fixture
/// `reasons_spent_state_budget`.)
#[test]
fn a_spent_timeout_is_inconclusive() {
    let design = "interface I { event i op() }
        stm M { uses I requires I const k : nat initial i0 state S { entry op(); wait(1) }
          transition t { from i0 to S } transition u { from S to S } }
        controller C { uses I requires I sref m = M connection C on i to m on i }
        module Mod { robotic platform P { uses I provides I } cref c = C connection P on i to c on i }";
    let rsa = "simulation S of Mod { cycleDef cycle == 1 }
        assertion A : S is schedulable with constant k of M set to 1 .";
    let mut opts = Options::default();
    opts.budget.timeout = Some(Duration::ZERO);
    let reports =
        verify_texts([("m.rct".to_string(), design.to_string()), ("a.rsa".to_string(), rsa.to_string())], &opts);
    let r = reports.iter().find(|r| r.semantics == Semantics::Timed).expect("the timed report");
    assert!(matches!(r.verdict, Verdict::Inconclusive | Verdict::Pass), "{:?}", r.verdict);
}

/// A RoboSim module reading the platform's `level` every cycle and raising
/// `alarm` at 2, its machine's input context extended with an event.
const WATCHER: &str = "package pi
    interface Pings { event ping : nat }
    interface Lvl { var level : nat }
    interface Out { var alarm : boolean }
    stm Watch {
      cycleDef cycle == 1
      input context { requires Lvl uses Pings }
      output context { requires Out }
      initial i
      state S { }
      transition t0 { from i to S }
      transition hi { from S to S exec condition $level >= 2 action $alarm = true }
      transition lo { from S to S exec condition $level < 2 }
    }
    controller C { cycleDef cycle == 1 requires Lvl requires Out sref w = Watch }
    module M { cycleDef cycle == 1 robotic platform P { provides Lvl provides Out } cref c = C }";

/// The register events a check numbers: a variable's read carries its value
/// alone, an event's its presence flag (and value); writes carry the value.
#[test]
fn register_events_of_variables() {
    use robosim_engine::lower::{lower_design, DomainDefaults};
    use robosim_engine::sched::Registers;
    let text = WATCHER.to_string();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, [("w.rst".to_string(), text)], robosim_hir::RuleSet::Paper);
    let file = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model file");
    let path = ["pi".to_string(), "Watch".to_string()];
    let loc = robosim_hir::index::resolve_item(&db, ws, file, &path, |_| true)[0];
    let design = lower_design(&db, ws, loc, &[], &DomainDefaults::default()).expect("supported");
    let regs = Registers::new(&[&design], robosim_engine::verify::Profile::RoboTool3).expect("registers");
    let name = |e| regs.table.name(e).expect("a register event");
    assert_eq!(name(regs.read("level", true, Some(2)).expect("level")), "registerRead.i_level.2");
    assert_eq!(name(regs.read("ping", true, Some(1)).expect("ping")), "registerRead.i_ping.true.1");
    assert_eq!(name(regs.read("ping", false, Some(0)).expect("ping")), "registerRead.i_ping.false.0");
    assert_eq!(name(regs.write("alarm", &[1]).expect("alarm")), "registerWrite.o_alarm.true");
}
