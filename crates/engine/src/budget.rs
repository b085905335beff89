//! Resource budgets for the verification algorithms: how many states, how
//! much memory and how much time a check may use, cooperative cancellation,
//! and the statistics a check reports (progress and final).
//!
//! A check that exhausts its budget returns `Inconclusive(Stop)` with the
//! statistics reached; it never panics or runs out of memory on purpose.

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What a check may use.
#[derive(Debug, Clone)]
pub struct Budget {
    /// The most states (pairs, for refinement) the check may store.
    pub max_states: u64,
    /// The most memory, in bytes, the check's tables may take (an estimate:
    /// stored states plus table overhead; transient buffers are not counted).
    pub max_bytes: u64,
    /// The longest the check may run.
    pub timeout: Option<Duration>,
    /// Set to `true` (by any thread) to stop the check; it returns
    /// `Inconclusive(Stop::Cancelled)` within milliseconds.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Worker threads for successor generation (1 = the calling thread
    /// only). Results never depend on it.
    pub threads: usize,
}

impl Default for Budget {
    /// 50 million states, 2 GiB, no timeout, no cancellation, one thread per
    /// available core.
    fn default() -> Self {
        Budget {
            max_states: 50_000_000,
            max_bytes: 2 << 30,
            timeout: None,
            cancel: None,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        }
    }
}

impl Budget {
    /// This budget with `threads` worker threads (at least one).
    pub fn with_threads(mut self, threads: usize) -> Budget {
        self.threads = threads.max(1);
        self
    }
}

/// What a check did: reported to the progress callback while it runs and
/// returned with its result.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// States stored (for refinement: (specification node, implementation
    /// state) pairs; for determinism: normal-form nodes).
    pub states: u64,
    /// Transitions followed from explored states.
    pub transitions: u64,
    /// Breadth-first levels begun (the depth of the deepest explored state
    /// plus one).
    pub plies: u32,
    /// Wall-clock time so far.
    pub seconds: f64,
    /// Estimated memory of the check's tables, in bytes.
    pub bytes: u64,
}

/// Why a check stopped before reaching a verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The state budget ([`Budget::max_states`]) was reached.
    States,
    /// The memory budget ([`Budget::max_bytes`]) was reached.
    Memory,
    /// The time budget ([`Budget::timeout`]) ran out.
    Time,
    /// The check was cancelled through [`Budget::cancel`].
    Cancelled,
}

impl Stop {
    /// A sentence explaining the stop, with the budget's numbers.
    pub fn reason(&self, budget: &Budget) -> String {
        match self {
            Stop::States => format!("state budget of {} states reached before a verdict", budget.max_states),
            Stop::Memory => format!("memory budget of {} reached before a verdict", format_bytes(budget.max_bytes)),
            Stop::Time => match budget.timeout {
                Some(t) => format!("time budget of {:.3} s ran out before a verdict", t.as_secs_f64()),
                None => "time budget ran out before a verdict".to_string(),
            },
            Stop::Cancelled => "the check was cancelled before a verdict".to_string(),
        }
    }
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stop::States => "state budget reached before a verdict",
            Stop::Memory => "memory budget reached before a verdict",
            Stop::Time => "time budget ran out before a verdict",
            Stop::Cancelled => "the check was cancelled before a verdict",
        })
    }
}

/// `2147483648` → `2.0 GiB`; exact byte counts below 1 KiB.
fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

/// A progress callback: called from the thread that runs the check, about
/// every 100 ms and once at the end, with the statistics so far.
pub type ProgressFn<'a> = &'a (dyn Fn(&Stats) + Sync);

/// How often the progress callback is called.
const PROGRESS_PERIOD: Duration = Duration::from_millis(100);

/// Polls between two real checks of the clock and the cancellation flag:
/// small enough that a slow successor function still sees cancellation
/// within milliseconds, large enough that `Instant::now` costs nothing.
const POLL_PERIOD: u32 = 64;

/// The algorithms' view of a budget while they run: the statistics, the
/// clock, cancellation, memory accounting and progress reports. Used only
/// by the calling thread; worker threads watch a [`Halt`].
pub(crate) struct Meter<'a> {
    pub(crate) budget: &'a Budget,
    progress: Option<ProgressFn<'a>>,
    start: Instant,
    deadline: Option<Instant>,
    next_report: Instant,
    polls: u32,
    /// Bytes of the main visited table (set by it on every insertion).
    table_bytes: u64,
    /// Bytes of side tables (normal forms, divergence memos, edge lists).
    extra_bytes: u64,
    /// The statistics so far; the algorithms update states/transitions/plies.
    pub(crate) stats: Stats,
}

impl<'a> Meter<'a> {
    /// Starts the clock.
    pub(crate) fn new(budget: &'a Budget, progress: Option<ProgressFn<'a>>) -> Meter<'a> {
        let start = Instant::now();
        Meter {
            budget,
            progress,
            start,
            // A timeout too large to represent is no timeout.
            deadline: budget.timeout.and_then(|t| start.checked_add(t)),
            next_report: start + PROGRESS_PERIOD,
            polls: 0,
            table_bytes: 0,
            extra_bytes: 0,
            stats: Stats::default(),
        }
    }

    /// Called once per unit of work; every [`POLL_PERIOD`] calls, checks
    /// cancellation and time and reports progress.
    #[inline]
    pub(crate) fn poll(&mut self) -> Result<(), Stop> {
        self.polls = self.polls.wrapping_add(1);
        if self.polls.is_multiple_of(POLL_PERIOD) {
            self.check()
        } else {
            Ok(())
        }
    }

    /// Checks cancellation and time now, and reports progress if due.
    pub(crate) fn check(&mut self) -> Result<(), Stop> {
        if self.cancelled() {
            return Err(Stop::Cancelled);
        }
        let now = Instant::now();
        if self.deadline.is_some_and(|d| now >= d) {
            return Err(Stop::Time);
        }
        if now >= self.next_report {
            self.next_report = now + PROGRESS_PERIOD;
            if let Some(report) = self.progress {
                self.stats.seconds = now.duration_since(self.start).as_secs_f64();
                report(&self.stats);
            }
        }
        Ok(())
    }

    fn cancelled(&self) -> bool {
        self.budget.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// Why workers stopped on their own: cancellation if the flag is set,
    /// otherwise the clock.
    pub(crate) fn halt_reason(&self) -> Stop {
        if self.cancelled() {
            Stop::Cancelled
        } else {
            Stop::Time
        }
    }

    /// The shared stop signal for worker threads.
    pub(crate) fn halt(&self) -> Halt<'a> {
        Halt { abort: AtomicBool::new(false), cancel: self.budget.cancel.as_deref(), deadline: self.deadline }
    }

    /// The main table now takes `bytes`: fails if the total is over budget.
    pub(crate) fn set_table_bytes(&mut self, bytes: u64) -> Result<(), Stop> {
        self.table_bytes = bytes;
        self.check_bytes(0)
    }

    /// Side tables grew by `bytes`: fails if the total is over budget.
    pub(crate) fn add_extra_bytes(&mut self, bytes: u64) -> Result<(), Stop> {
        self.extra_bytes = self.extra_bytes.saturating_add(bytes);
        self.check_bytes(0)
    }

    /// Fails if the memory in use plus `more` would be over budget.
    pub(crate) fn check_bytes(&mut self, more: u64) -> Result<(), Stop> {
        let total = self.table_bytes.saturating_add(self.extra_bytes);
        self.stats.bytes = total;
        if total.saturating_add(more) > self.budget.max_bytes {
            Err(Stop::Memory)
        } else {
            Ok(())
        }
    }

    /// Stops the clock, reports progress a last time and returns the
    /// statistics.
    pub(crate) fn finish(&mut self) -> Stats {
        self.stats.seconds = self.start.elapsed().as_secs_f64();
        self.stats.bytes = self.table_bytes.saturating_add(self.extra_bytes);
        if let Some(report) = self.progress {
            report(&self.stats);
        }
        self.stats
    }
}

/// The stop signal worker threads poll: set by whichever thread first sees
/// cancellation, the deadline or an error, so the others stop promptly.
pub(crate) struct Halt<'a> {
    abort: AtomicBool,
    cancel: Option<&'a AtomicBool>,
    deadline: Option<Instant>,
}

impl Halt<'_> {
    /// Asks every worker to stop.
    pub(crate) fn raise(&self) {
        self.abort.store(true, Ordering::Relaxed);
    }

    /// Whether some worker asked to stop.
    pub(crate) fn raised(&self) -> bool {
        self.abort.load(Ordering::Relaxed)
    }

    /// Checks the flags and the clock; raises the signal if it is time to
    /// stop. Returns whether to stop.
    pub(crate) fn should_stop(&self) -> bool {
        if self.raised() {
            return true;
        }
        let stop = self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
            || self.deadline.is_some_and(|d| Instant::now() >= d);
        if stop {
            self.raise();
        }
        stop
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reasons_keep_the_numbers() {
        let budget = Budget {
            max_states: 1000,
            max_bytes: 3 << 20,
            timeout: Some(Duration::from_millis(1500)),
            cancel: None,
            threads: 1,
        };
        assert_eq!(Stop::States.reason(&budget), "state budget of 1000 states reached before a verdict");
        assert_eq!(Stop::Memory.reason(&budget), "memory budget of 3.0 MiB reached before a verdict");
        assert_eq!(Stop::Time.reason(&budget), "time budget of 1.500 s ran out before a verdict");
        assert_eq!(Stop::Cancelled.to_string(), "the check was cancelled before a verdict");
        assert_eq!(format_bytes(512), "512 bytes");
        assert_eq!(format_bytes(2 << 30), "2.0 GiB");
    }

    #[test]
    fn default_budget() {
        let b = Budget::default();
        assert_eq!(b.max_states, 50_000_000);
        assert_eq!(b.max_bytes, 2 * 1024 * 1024 * 1024);
        assert!(b.threads >= 1);
        assert!(b.timeout.is_none() && b.cancel.is_none());
    }
}
