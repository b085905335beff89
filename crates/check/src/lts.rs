//! Labelled transition systems, generated on the fly: the interface between
//! the models (compiled RoboChart/RoboSim semantics, assumption automata)
//! and the algorithms (deadlock search, refinement, divergence).

use std::hash::Hash;

/// An event: an index into the model's event table. Three values are
/// reserved: [`TAU`], [`TICK`] (successful termination ✓) and [`TOCK`]
/// (one time unit passes); visible events are `≥ FIRST_VISIBLE`.
pub type Event = u32;

/// The internal event τ.
pub const TAU: Event = 0;
/// Successful termination ✓.
pub const TICK: Event = 1;
/// The passage of one time unit.
pub const TOCK: Event = 2;
/// The first id of a visible event other than `tock`.
pub const FIRST_VISIBLE: Event = 3;

/// A transition's label: the event the algorithms see, and a `note` the
/// model attaches to explain the step (a hidden event, a source element;
/// `0` = none). Algorithms never look at `note`; counterexamples keep it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Label {
    /// What the step is, for the semantics.
    pub event: Event,
    /// What the step was before hiding, or where it comes from; model-defined.
    pub note: u32,
}

impl Label {
    /// A τ step with no explanation.
    pub const TAU: Label = Label { event: TAU, note: 0 };
    /// A `tock` step.
    pub const TOCK: Label = Label { event: TOCK, note: 0 };

    /// A step on `event` without a note.
    pub fn plain(event: Event) -> Label {
        Label { event, note: 0 }
    }
}

/// A labelled transition system explored on the fly.
///
/// `successors` must be deterministic (same state ⇒ same successors in the
/// same order): counterexamples and state counts must not depend on thread
/// scheduling.
pub trait Lts: Sync {
    /// A state; small and cheap to hash.
    type State: Clone + Eq + Hash + Send + Sync;

    /// The initial state.
    fn initial(&self) -> Self::State;

    /// Appends the transitions of `state` to `out`. `out` may already hold
    /// other states' transitions: implementations only add to it.
    fn successors(&self, state: &Self::State, out: &mut Vec<(Label, Self::State)>);

    /// A name for `event`, for counterexamples (`tock`, `registerRead.i_obstacle.true`).
    fn event_name(&self, event: Event) -> String {
        match event {
            TAU => "τ".to_string(),
            TICK => "✓".to_string(),
            TOCK => "tock".to_string(),
            e => format!("e{e}"),
        }
    }

    /// The memory a stored `state` takes, in bytes, for the algorithms'
    /// memory budget. The default is the inline size; models whose states
    /// own heap data (vectors, boxed slices) override it to add that data.
    fn state_bytes(&self, state: &Self::State) -> usize {
        let _ = state;
        std::mem::size_of::<Self::State>()
    }
}

/// The name of `event` in `table`, with the reserved events' names.
pub fn event_name_in(table: &crate::events::EventTable, event: Event) -> String {
    match event {
        TAU => "τ".into(),
        TICK => "✓".into(),
        TOCK => "tock".into(),
        e => table.name(e).unwrap_or_else(|| format!("e{e}")),
    }
}

/// The first run-time error a model met while being explored (division by
/// zero, …): it makes the check's result inconclusive. Successor functions
/// take `&self`, so the cell is shared.
#[derive(Debug, Default)]
pub struct FirstError(std::sync::Mutex<Option<String>>);

impl FirstError {
    /// Records `msg` unless an error is already recorded.
    pub fn set(&self, msg: String) {
        if let Ok(mut e) = self.0.lock() {
            e.get_or_insert(msg);
        }
    }

    /// The recorded error.
    pub fn get(&self) -> Option<String> {
        self.0.lock().ok().and_then(|e| e.clone())
    }
}
