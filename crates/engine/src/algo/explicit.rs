//! A tiny explicit LTS (states are indices, transitions listed), for tests
//! and for differential checks against `semantics_oracle.py`.

use crate::lts::{Event, Label, Lts, FIRST_VISIBLE, TAU, TICK, TOCK};

/// An LTS given by its transition lists: state `s` has transitions
/// `trans[s]`; event `e` is called `names[e]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExplicitLts {
    /// The initial state.
    pub initial: usize,
    /// The transitions of each state, in order.
    pub trans: Vec<Vec<(Label, usize)>>,
    /// Event names, indexed by event (`names[0]` is τ, `[1]` ✓, `[2]` tock).
    pub names: Vec<String>,
}

/// The engine's label of a transition of an LTS our CSPm evaluator
/// compiled, its events numbered by `map` (the evaluator's event index →
/// the engine's event).
pub fn label_of_cspm(l: &robosim_cspm::Label, map: &[Event]) -> Label {
    Label::plain(match l {
        robosim_cspm::Label::Tau => TAU,
        robosim_cspm::Label::Tick => TICK,
        robosim_cspm::Label::Event(i) => map[*i as usize],
    })
}

impl ExplicitLts {
    /// The LTS our CSPm evaluator compiled: each event numbered by its
    /// position in `names` (added when new; `names` starts with τ, ✓ and
    /// `tock`, which map to the engine's [`TAU`], [`TICK`], [`TOCK`]), so
    /// that LTSs built on one `names` agree on event ids. The result's
    /// `names` is `names` as it then is.
    pub fn from_cspm(lts: &robosim_cspm::Lts, names: &mut Vec<String>) -> ExplicitLts {
        let mut id = |n: &str| -> Event {
            if n == "tock" {
                return TOCK;
            }
            match names.iter().position(|x| x == n) {
                Some(i) => i as Event,
                None => {
                    names.push(n.to_string());
                    (names.len() - 1) as Event
                }
            }
        };
        let map: Vec<Event> = lts.events.iter().map(|e| id(e)).collect();
        let trans = lts
            .transitions
            .iter()
            .map(|ts| ts.iter().map(|(l, t)| (label_of_cspm(l, &map), *t as usize)).collect())
            .collect();
        ExplicitLts { initial: lts.initial as usize, trans, names: names.clone() }
    }

    /// The LTS with initial state 0 and the edges `(from, event, to)`, where
    /// `event` is `"tau"` (or `"τ"`), `"tick"` (or `"✓"`), `"tock"` or the
    /// name of a visible event. Visible events are numbered from
    /// [`FIRST_VISIBLE`] in the order of `alphabet`, then of first use, so
    /// two LTSs built on the same alphabet agree on event ids (refinement
    /// compares ids). States are `0..=` the largest index mentioned.
    pub fn with_alphabet(alphabet: &[&str], edges: &[(usize, &str, usize)]) -> ExplicitLts {
        let mut names: Vec<String> = vec!["τ".into(), "✓".into(), "tock".into()];
        names.extend(alphabet.iter().map(|a| a.to_string()));
        let states = edges.iter().map(|&(a, _, b)| a.max(b) + 1).max().unwrap_or(1);
        let mut trans = vec![Vec::new(); states];
        for &(from, name, to) in edges {
            let event = match name {
                "tau" | "τ" => TAU,
                "tick" | "✓" => TICK,
                "tock" => TOCK,
                _ => match names[FIRST_VISIBLE as usize..].iter().position(|n| n == name) {
                    Some(i) => FIRST_VISIBLE + i as Event,
                    None => {
                        names.push(name.to_string());
                        (names.len() - 1) as Event
                    }
                },
            };
            trans[from].push((Label::plain(event), to));
        }
        ExplicitLts { initial: 0, trans, names }
    }

    /// [`ExplicitLts::with_alphabet`] with an empty alphabet: visible
    /// events numbered in order of first use.
    pub fn from_edges(edges: &[(usize, &str, usize)]) -> ExplicitLts {
        ExplicitLts::with_alphabet(&[], edges)
    }

    /// The id of the event called `name`, if the LTS knows it.
    pub fn event(&self, name: &str) -> Option<Event> {
        match name {
            "tau" => Some(TAU),
            "tick" => Some(TICK),
            _ => self.names.iter().position(|n| n == name).map(|i| i as Event),
        }
    }

    /// The number of states.
    pub fn len(&self) -> usize {
        self.trans.len()
    }

    /// Whether the LTS has no state (never, for one built from edges).
    pub fn is_empty(&self) -> bool {
        self.trans.is_empty()
    }
}

impl Lts for ExplicitLts {
    type State = usize;

    fn initial(&self) -> usize {
        self.initial
    }

    fn successors(&self, state: &usize, out: &mut Vec<(Label, usize)>) {
        if let Some(t) = self.trans.get(*state) {
            out.extend_from_slice(t);
        }
    }

    fn event_name(&self, event: Event) -> String {
        self.names.get(event as usize).cloned().unwrap_or_else(|| format!("e{event}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_from_edges() {
        let l = ExplicitLts::with_alphabet(&["b"], &[(0, "a", 1), (1, "tau", 2), (2, "b", 0), (2, "tock", 3)]);
        assert_eq!(l.len(), 4);
        assert_eq!(l.event("b"), Some(FIRST_VISIBLE));
        assert_eq!(l.event("a"), Some(FIRST_VISIBLE + 1));
        assert_eq!(l.event("tock"), Some(TOCK));
        assert_eq!(l.event_name(FIRST_VISIBLE + 1), "a");
        let mut out = Vec::new();
        l.successors(&2, &mut out);
        assert_eq!(out, vec![(Label::plain(FIRST_VISIBLE), 0), (Label::TOCK, 3)]);
        out.clear();
        l.successors(&99, &mut out);
        assert!(out.is_empty());
    }
}
