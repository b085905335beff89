//! Compilation of a process to an explicit LTS by breadth-first
//! exploration of its terms' transitions, bounded by `Limits::max_states`.

use std::rc::Rc;

use rustc_hash::FxHashMap;

use crate::eval::{err, Evaluator};
use crate::proc::{L, P};
use crate::{Code, Diagnostic, TextRange, Value};

/// A transition label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Label {
    /// An internal step.
    Tau,
    /// Successful termination (✓).
    Tick,
    /// A visible event: an index into [`Lts::events`].
    Event(u32),
}

/// An explicit labelled transition system with named events.
#[derive(Clone, Debug)]
pub struct Lts {
    /// The events, as FDR prints them (`c.1.A`), by index.
    pub events: Vec<String>,
    /// The event values, by index.
    pub event_values: Vec<Value>,
    /// The initial state (always 0).
    pub initial: u32,
    /// The transitions of each state, sorted.
    pub transitions: Vec<Vec<(Label, u32)>>,
}

impl Lts {
    /// The number of states.
    pub fn states(&self) -> usize {
        self.transitions.len()
    }

    /// The index of the event printed as `name`.
    pub fn event(&self, name: &str) -> Option<u32> {
        self.events.iter().position(|e| e == name).map(|i| i as u32)
    }

    /// Whether the visible trace `trace` (event names) is possible, with
    /// τ steps anywhere.
    pub fn has_trace(&self, trace: &[&str]) -> bool {
        let mut cur = self.tau_closure(vec![self.initial]);
        for name in trace {
            let Some(e) = self.event(name) else { return false };
            let next: Vec<u32> = cur
                .iter()
                .flat_map(|&s| {
                    self.transitions[s as usize].iter().filter(|(l, _)| *l == Label::Event(e)).map(|(_, t)| *t)
                })
                .collect();
            if next.is_empty() {
                return false;
            }
            cur = self.tau_closure(next);
        }
        true
    }

    /// The states reachable by τ steps from `states`.
    pub fn tau_closure(&self, mut states: Vec<u32>) -> Vec<u32> {
        let mut seen: std::collections::BTreeSet<u32> = states.iter().copied().collect();
        while let Some(s) = states.pop() {
            for (l, t) in &self.transitions[s as usize] {
                if *l == Label::Tau && seen.insert(*t) {
                    states.push(*t);
                }
            }
        }
        seen.into_iter().collect()
    }
}

impl Evaluator<'_> {
    /// The LTS of the process the top-level name `name` denotes.
    pub fn lts(&mut self, name: &str) -> Result<Lts, Diagnostic> {
        let v = self.value(name)?;
        self.lts_of(&v)
    }

    /// The LTS of a process value.
    pub fn lts_of(&mut self, v: &Value) -> Result<Lts, Diagnostic> {
        let at = TextRange::empty(0.into());
        let Value::Proc(p) = v else {
            return Err(err(Code::Type, at, format!("expected a process, found {}", v.kind_name())));
        };
        let mut ids: FxHashMap<Rc<P>, u32> = FxHashMap::default();
        let mut states: Vec<Rc<P>> = vec![p.inner.clone()];
        ids.insert(p.inner.clone(), 0);
        let mut transitions = Vec::new();
        let mut i = 0;
        while i < states.len() {
            self.tick(at)?;
            let s = states[i].clone();
            let mut out = Vec::new();
            for (l, t) in self.transitions(&s, at)? {
                // Calls are unfolded so that one process has one state.
                let t = if matches!(*t, P::Call(_)) { self.unfold(&t, at)? } else { t };
                let id = match ids.get(&t) {
                    Some(&id) => id,
                    None => {
                        let id = states.len() as u32;
                        if states.len() >= self.limits.max_states {
                            return Err(err(Code::Limit, at, format!("more than {} states", self.limits.max_states)));
                        }
                        ids.insert(t.clone(), id);
                        states.push(t);
                        id
                    }
                };
                let label = match l {
                    L::Tau => Label::Tau,
                    L::Tick => Label::Tick,
                    L::Ev(e) => Label::Event(e),
                };
                out.push((label, id));
            }
            out.sort_unstable();
            out.dedup();
            transitions.push(out);
            i += 1;
        }
        Ok(Lts {
            events: self.events.iter().map(|e| e.to_string()).collect(),
            event_values: self.events.clone(),
            initial: 0,
            transitions,
        })
    }
}
