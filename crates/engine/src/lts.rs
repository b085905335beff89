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

    /// The step as a counterexample shows it: a visible event by `name`, a
    /// τ with a note as the hidden event in brackets (`(opCall)`), else `τ`.
    /// `hidden` names the notes (the model's events when the step is the
    /// implementation's of a refinement).
    pub fn shown(&self, name: impl Fn(Event) -> String, hidden: impl Fn(Event) -> String) -> String {
        match (self.event, self.note) {
            (TAU, 0) => "τ".to_string(),
            (TAU, note) => format!("({})", hidden(note)),
            (event, _) => name(event),
        }
    }
}

/// A labelled transition system explored on the fly.
///
/// `successors` must be deterministic (same state ⇒ same successors in the
/// same order): counterexamples and state counts must not depend on thread
/// scheduling.
pub trait Lts: Sync {
    /// A state; small and cheap to hash.
    type State: Clone + Eq + Hash + Send + Sync + StateCodec;

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

    /// The bytes a state takes in the algorithms' visited tables: the same
    /// for every state of the LTS. The default is the initial state's
    /// [`StateCodec::width`]; models that know a tighter width override it
    /// (with [`encode`](Lts::encode) and [`decode`](Lts::decode)).
    fn state_width(&self) -> usize {
        self.initial().width()
    }

    /// Writes `state` into `row`, which is [`state_width`](Lts::state_width)
    /// bytes long. Two states are equal iff their rows are.
    fn encode(&self, state: &Self::State, row: &mut [u8]) {
        state.write(row);
    }

    /// The state stored as `row`.
    fn decode(&self, row: &[u8]) -> Self::State {
        Self::State::read(row)
    }

    /// Appends the transitions of the state stored as `row` to `out`, their
    /// targets as rows, in the order of [`successors`](Lts::successors).
    /// The default decodes, calls `successors` and encodes; models override
    /// it to skip the values in between.
    fn successor_rows(&self, row: &[u8], out: &mut Rows<Self::State>) {
        let state = self.decode(row);
        let mut scratch = std::mem::take(&mut out.scratch);
        scratch.clear();
        self.successors(&state, &mut scratch);
        out.extend_encoded(&scratch, |t, row| self.encode(t, row));
        out.scratch = scratch;
    }
}

/// A state's stored form: a fixed number of bytes (the same for all the
/// states of one LTS), compared and hashed as bytes.
pub trait StateCodec: Sized {
    /// The bytes this state's form takes.
    fn width(&self) -> usize;
    /// Writes the state into `row` (`width()` bytes, or fewer when the
    /// bytes left out are zero for every state of the LTS).
    fn write(&self, row: &mut [u8]);
    /// The state written as `row`.
    fn read(row: &[u8]) -> Self;
}

macro_rules! int_codec {
    ($($t:ty),*) => {$(
        impl StateCodec for $t {
            #[inline]
            fn width(&self) -> usize {
                std::mem::size_of::<$t>()
            }
            #[inline]
            fn write(&self, row: &mut [u8]) {
                // The full width (the usual case) is a plain store.
                match <&mut [u8; std::mem::size_of::<$t>()]>::try_from(&mut *row) {
                    Ok(full) => *full = self.to_le_bytes(),
                    Err(_) => row.copy_from_slice(&self.to_le_bytes()[..row.len()]),
                }
            }
            #[inline]
            fn read(row: &[u8]) -> Self {
                match <[u8; std::mem::size_of::<$t>()]>::try_from(row) {
                    Ok(full) => <$t>::from_le_bytes(full),
                    Err(_) => {
                        let mut b = [0u8; std::mem::size_of::<$t>()];
                        b[..row.len()].copy_from_slice(row);
                        <$t>::from_le_bytes(b)
                    }
                }
            }
        }
    )*};
}
int_codec!(u32, u64, usize);

/// Transitions whose targets are rows ([`Lts::successor_rows`]): labels,
/// and the rows back to back in one buffer (no allocation per transition).
#[derive(Debug)]
pub struct Rows<S> {
    width: usize,
    labels: Vec<Label>,
    bytes: Vec<u8>,
    /// Scratch space for successor functions that work on values.
    pub scratch: Vec<(Label, S)>,
    /// Scratch space for successor functions that work on state vectors:
    /// the successors, the source's slots and its packed words.
    pub vectors: crate::pack::Vectors,
    /// See [`Rows::vectors`].
    pub source: Box<[i32]>,
    /// See [`Rows::vectors`].
    pub words: Vec<u64>,
}

impl<S> Rows<S> {
    /// An empty buffer of rows of `width` bytes.
    pub fn new(width: usize) -> Rows<S> {
        Rows {
            width,
            labels: Vec::new(),
            bytes: Vec::new(),
            scratch: Vec::new(),
            vectors: crate::pack::Vectors::default(),
            source: Box::new([]),
            words: Vec::new(),
        }
    }

    /// The bytes of a row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// The number of transitions.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    /// Whether there is no transition.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Removes every transition (keeping the memory).
    pub fn clear(&mut self) {
        self.labels.clear();
        self.bytes.clear();
    }

    /// Keeps the first `len` transitions.
    pub fn truncate(&mut self, len: usize) {
        self.labels.truncate(len);
        self.bytes.truncate(len * self.width);
    }

    /// Appends a transition labelled `label`; its target is the returned
    /// row (zeroed), to be filled in.
    #[inline]
    pub fn push(&mut self, label: Label) -> &mut [u8] {
        self.labels.push(label);
        let at = self.bytes.len();
        Self::append_zeroed(&mut self.bytes, self.width);
        &mut self.bytes[at..]
    }

    /// Appends the transitions `items`, their targets written by `encode`
    /// into zeroed rows. One append for all of them: for states that are
    /// plain integers, a [`push`](Rows::push) per row would cost more than
    /// the encoding.
    #[inline]
    pub fn extend_encoded<T>(&mut self, items: &[(Label, T)], mut encode: impl FnMut(&T, &mut [u8])) {
        let at = self.bytes.len();
        self.bytes.resize(at + items.len() * self.width, 0);
        self.labels.extend(items.iter().map(|&(label, _)| label));
        // (Rows of no bytes need no encoding; `chunks_exact_mut` needs a width.)
        for ((_, t), row) in items.iter().zip(self.bytes[at..].chunks_exact_mut(self.width.max(1))) {
            encode(t, row);
        }
    }

    /// Appends the successors held in [`Rows::vectors`], in order: their
    /// labels, and as many zeroed rows, which `pack(source, words,
    /// vectors, rows)` fills (with [`Rows::source`] and [`Rows::words`]).
    /// `pack` returns the indices, in increasing order, of the successors
    /// it could not pack, which are dropped. One append for all, rather
    /// than a push per successor; the buffers are borrowed in place.
    pub fn pack_vectors(
        &mut self,
        pack: impl FnOnce(&[i32], &[u64], &crate::pack::Vectors, &mut [u8]) -> Result<(), Vec<usize>>,
    ) {
        let Rows { width, labels, bytes, vectors, source, words, .. } = self;
        let (w, start, at) = (*width, labels.len(), bytes.len());
        labels.extend_from_slice(vectors.labels());
        bytes.resize(at + vectors.len() * w, 0);
        let Err(failed) = pack(source, words, vectors, &mut bytes[at..]) else { return };
        // Rare (a successor out of its encoding): close the gaps.
        let mut to = start;
        for k in 0..vectors.len() {
            if failed.binary_search(&k).is_err() {
                labels[to] = labels[start + k];
                bytes.copy_within(at + k * w..at + (k + 1) * w, at + (to - start) * w);
                to += 1;
            }
        }
        labels.truncate(to);
        bytes.truncate(at + (to - start) * w);
    }

    /// Appends `width` zero bytes to `bytes`.
    #[inline]
    fn append_zeroed(bytes: &mut Vec<u8>, width: usize) {
        let at = bytes.len();
        if width <= 16 {
            // A fixed-size append is a store, not a call to `memset`.
            bytes.extend_from_slice(&[0u8; 16]);
            bytes.truncate(at + width);
        } else {
            bytes.resize(at + width, 0);
        }
    }

    /// The label of transition `k`.
    pub fn label(&self, k: usize) -> Label {
        self.labels[k]
    }

    /// The target row of transition `k`.
    pub fn row(&self, k: usize) -> &[u8] {
        &self.bytes[k * self.width..(k + 1) * self.width]
    }

    /// The labels of transitions `lo..hi`.
    pub fn labels(&self, lo: usize, hi: usize) -> &[Label] {
        &self.labels[lo..hi]
    }

    /// The target rows of transitions `lo..hi`, back to back.
    pub fn rows(&self, lo: usize, hi: usize) -> &[u8] {
        &self.bytes[lo * self.width..hi * self.width]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// States `0..n` on a ring, stepping by 1 and by 7, with 4-byte rows
    /// (a tighter width than `u64`'s own) when `narrow`.
    struct Ring {
        n: u64,
        narrow: bool,
    }

    impl Lts for Ring {
        type State = u64;

        fn initial(&self) -> u64 {
            0
        }

        fn successors(&self, s: &u64, out: &mut Vec<(Label, u64)>) {
            out.push((Label::plain(FIRST_VISIBLE), (s + 1) % self.n));
            if !s.is_multiple_of(3) {
                out.push((Label { event: FIRST_VISIBLE + 1, note: *s as u32 }, (s + 7) % self.n));
            }
        }

        fn state_width(&self) -> usize {
            if self.narrow {
                4
            } else {
                8
            }
        }

        fn encode(&self, s: &u64, row: &mut [u8]) {
            if self.narrow {
                row.copy_from_slice(&(*s as u32 ^ 0xdead_beef).to_le_bytes());
            } else {
                s.write(row);
            }
        }

        fn decode(&self, row: &[u8]) -> u64 {
            if self.narrow {
                u64::from(u32::read(row) ^ 0xdead_beef)
            } else {
                u64::read(row)
            }
        }
    }

    #[test]
    fn default_successor_rows_match_successors_encoded_one_by_one() {
        for narrow in [false, true] {
            let lts = Ring { n: 1000, narrow };
            let w = lts.state_width();
            let mut fast: Rows<u64> = Rows::new(w);
            let mut slow: Rows<u64> = Rows::new(w);
            let mut row = vec![0u8; w];
            for s in 0..lts.n {
                // Rows accumulate across sources, as in the engine's buffers.
                lts.encode(&s, &mut row);
                lts.successor_rows(&row, &mut fast);
                let mut succ = Vec::new();
                lts.successors(&lts.decode(&row), &mut succ);
                for (label, t) in succ {
                    lts.encode(&t, slow.push(label));
                }
            }
            assert_eq!(fast.len(), slow.len());
            assert_eq!(fast.labels(0, fast.len()), slow.labels(0, slow.len()));
            assert_eq!(fast.rows(0, fast.len()), slow.rows(0, slow.len()));
            for k in 0..fast.len() {
                assert_eq!(lts.decode(fast.row(k)), lts.decode(slow.row(k)));
            }
        }
    }
}
