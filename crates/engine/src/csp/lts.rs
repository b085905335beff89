//! The two sides of a check with CSPm as the engine's LTSs: a
//! specification compiled by the CSPm evaluator (an explicit LTS, its
//! events renumbered into the shared table), and a native model whose
//! successful termination is RoboTool's `M::terminate` then ✓.

use crate::lts::{Event, Label, Lts, StateCodec, TAU, TICK, TOCK};

use super::events::Names;

/// An explicit LTS (the specification), events already in the shared
/// numbering.
pub(crate) struct SpecLts<'a> {
    /// The transitions of each state (state 0 is initial).
    pub trans: Vec<Vec<(Label, u32)>>,
    /// Event names.
    pub names: &'a Names,
}

impl Lts for SpecLts<'_> {
    type State = u32;

    fn initial(&self) -> u32 {
        0
    }

    fn successors(&self, state: &u32, out: &mut Vec<(Label, u32)>) {
        if let Some(ts) = self.trans.get(*state as usize) {
            out.extend_from_slice(ts);
        }
    }

    fn event_name(&self, event: Event) -> String {
        self.names.name(event)
    }
}

/// A state of [`Imp`]: the model's, and whether `terminate` has just
/// happened (✓ comes next).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct ImpState<S> {
    /// The model's state.
    pub inner: S,
    /// Between `terminate` and ✓.
    pub ending: bool,
}

impl<S: StateCodec> StateCodec for ImpState<S> {
    fn width(&self) -> usize {
        self.inner.width() + 1
    }

    fn write(&self, row: &mut [u8]) {
        row[0] = u8::from(self.ending);
        self.inner.write(&mut row[1..]);
    }

    fn read(row: &[u8]) -> Self {
        ImpState { inner: S::read(&row[1..]), ending: row[0] != 0 }
    }
}

/// The native model as the CSPm side sees it: its events by their CSPm
/// names, and, for a RoboChart controller or machine, `M::terminate`
/// before ✓ (RoboTool's machine and controller processes show it; a
/// module hides it); for a RoboSim element, τ before `tock`.
pub(crate) struct Imp<'a, L: Lts> {
    /// The model.
    pub inner: &'a L,
    /// The id of `M::terminate`, when it is visible.
    pub terminate: Option<Event>,
    /// Event names.
    pub names: &'a Names,
    /// RT-10: a RoboSim element is checked as `P :[tau priority]: {tock}`
    /// (time passes only in a stable state).
    pub tau_priority: bool,
}

impl<L: Lts> Lts for Imp<'_, L> {
    type State = ImpState<L::State>;

    fn initial(&self) -> Self::State {
        ImpState { inner: self.inner.initial(), ending: false }
    }

    fn successors(&self, st: &Self::State, out: &mut Vec<(Label, Self::State)>) {
        if st.ending {
            out.push((Label::plain(TICK), ImpState { inner: st.inner.clone(), ending: false }));
            return;
        }
        let mut next = Vec::new();
        self.inner.successors(&st.inner, &mut next);
        if self.tau_priority && next.iter().any(|(l, _)| l.event == TAU) {
            next.retain(|(l, _)| l.event != TOCK);
        }
        for (l, t) in next {
            match self.terminate {
                Some(term) if l.event == TICK => {
                    out.push((Label { event: term, note: l.note }, ImpState { inner: t, ending: true }))
                }
                _ => match self.names.aliases(l.event) {
                    Some(all) => {
                        for &e in all {
                            out.push((Label { event: e, note: l.note }, ImpState { inner: t.clone(), ending: false }))
                        }
                    }
                    None => out.push((l, ImpState { inner: t, ending: false })),
                },
            }
        }
    }

    fn event_name(&self, event: Event) -> String {
        self.names.name(event)
    }

    fn state_bytes(&self, st: &Self::State) -> usize {
        self.inner.state_bytes(&st.inner) + 1
    }

    fn state_width(&self) -> usize {
        self.inner.state_width() + 1
    }

    fn encode(&self, st: &Self::State, row: &mut [u8]) {
        row[0] = u8::from(st.ending);
        self.inner.encode(&st.inner, &mut row[1..]);
    }

    fn decode(&self, row: &[u8]) -> Self::State {
        ImpState { inner: self.inner.decode(&row[1..]), ending: row[0] != 0 }
    }
}
