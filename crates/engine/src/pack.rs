//! Compact states: the slots of a state vector packed into as few bits as
//! their ranges need (semantics.md §8.6). A state of up to 128 bits is
//! stored inline; larger ones use one allocation. A value out
//! of its slot's range is an error (the check becomes inconclusive), never
//! a silently wrong state.

use crate::lts::Label;

/// A packed state.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Packed {
    /// Up to 64 bits.
    Word(u64),
    /// Up to 128 bits.
    Pair(u64, u64),
    /// More: the words (a thin pointer keeps the enum small).
    Words(Box<Box<[u64]>>),
}

impl Packed {
    /// Heap bytes used beyond the enum itself.
    pub fn heap_bytes(&self) -> usize {
        match self {
            Packed::Word(_) | Packed::Pair(..) => 0,
            Packed::Words(w) => std::mem::size_of::<Box<[u64]>>() + w.len() * 8,
        }
    }
}

/// One slot's place: word, shift, width and offset (the least value).
#[derive(Debug, Clone, Copy)]
struct Field {
    word: u32,
    /// Where the field starts in its word (0 for a field of no bits).
    shift: u32,
    bits: u32,
    /// The field's bits, unshifted.
    mask: u64,
    lo: i64,
    hi: i64,
    /// `hi - lo`: a value fits when its offset from `lo` is at most this.
    span: u64,
}

/// How to read one slot from its packed word: the part of its [`Field`]
/// that unpacking needs, in 16 bytes rather than 48, so that a state's
/// slots are read from a few cache lines.
#[derive(Debug, Clone, Copy)]
struct Slot {
    mask: u64,
    /// The field's least value, wrapped to 32 bits (a slot's value is its
    /// offset plus this, modulo 2^32, as for [`Field::lo`]).
    lo: i32,
    shift: u32,
}

impl Slot {
    /// The slot's value in its packed word `bits`.
    #[inline]
    fn read(&self, bits: u64) -> i32 {
        self.lo.wrapping_add(((bits >> self.shift) & self.mask) as i32)
    }
}

/// Packed states of up to this many words are packed and unpacked without
/// an allocation.
const SMALL_WORDS: usize = 4;

/// How the slots of a state vector are packed.
#[derive(Debug, Clone)]
pub struct Layout {
    fields: Vec<Field>,
    /// [`Layout::fields`] for unpacking.
    slots: Vec<Slot>,
    /// Per word, the end of its run of fields (fields come in word order).
    word_ends: Vec<usize>,
    words: usize,
    /// The bytes a packed state takes as a row: the words, the last one
    /// cut to the bytes its fields use (the rest is always zero).
    row_width: usize,
    /// Per word, per bit, the slot whose field holds that bit (bits of no
    /// field are always zero): which slots a changed bit belongs to.
    bit_slots: Vec<u32>,
    /// Tells this layout's unpacked states from another's (see
    /// [`Layout::unpack_row_words`]); clones share it (they are equal).
    /// Never 0, which a fresh buffer holds.
    id: u64,
}

/// The source of [`Layout::id`]s (0 is no layout's).
static NEXT_LAYOUT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl Layout {
    /// The layout for slots with these inclusive ranges.
    pub fn new(bounds: &[(i64, i64)]) -> Layout {
        let mut fields = Vec::with_capacity(bounds.len());
        let (mut word, mut used) = (0usize, 0u32);
        for &(lo, hi) in bounds {
            let span = (hi - lo).max(0) as u64;
            let bits = 64 - span.leading_zeros();
            // Fields do not straddle words.
            if used + bits > 64 {
                word += 1;
                used = 0;
            }
            let mask = if bits == 64 { u64::MAX } else { (1u64 << bits) - 1 };
            let shift = if bits == 0 { 0 } else { used };
            fields.push(Field { word: word as u32, shift, bits, mask, lo, hi, span });
            used += bits;
        }
        let row_width = (8 * word + used.div_ceil(8) as usize).max(1);
        let word_ends = (0..=word).map(|w| fields.partition_point(|f| f.word as usize <= w)).collect();
        let slots = fields.iter().map(|f| Slot { mask: f.mask, lo: f.lo as i32, shift: f.shift }).collect();
        let mut bit_slots = vec![0u32; 64 * (word + 1)];
        for (i, f) in fields.iter().enumerate() {
            for b in f.shift..f.shift + f.bits {
                bit_slots[64 * f.word as usize + b as usize] = i as u32;
            }
        }
        let id = NEXT_LAYOUT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Layout { fields, slots, word_ends, words: word + 1, row_width, bit_slots, id }
    }

    /// The bytes of a packed state stored as a row (see [`Packed`]'s
    /// [`StateCodec`](crate::lts::StateCodec)).
    pub fn row_width(&self) -> usize {
        self.row_width
    }

    /// Zeroed words for one packed state: on the stack when they fit.
    fn scratch_words<'w>(&self, small: &'w mut [u64; SMALL_WORDS], big: &'w mut Vec<u64>) -> &'w mut [u64] {
        if self.words <= SMALL_WORDS {
            &mut small[..self.words]
        } else {
            big.resize(self.words, 0);
            big
        }
    }

    /// Packs `st` straight into `row` (zeroed, [`Layout::row_width`] bytes):
    /// the same bytes as packing and then writing the [`Packed`]. An error
    /// names the first slot out of its range.
    pub fn pack_into(&self, st: &[i32], row: &mut [u8]) -> Result<(), String> {
        let (mut small, mut big) = ([0u64; SMALL_WORDS], Vec::new());
        let words = self.scratch_words(&mut small, &mut big);
        // No early exit: the loop stays branch-free; a bad value only
        // spoils words that are thrown away.
        let mut bad = false;
        for (f, &v) in self.fields.iter().zip(st) {
            let off = (v as i64).wrapping_sub(f.lo) as u64;
            bad |= off > f.span;
            words[f.word as usize] |= off << f.shift;
        }
        if bad {
            return Err(self.out_of_range(st));
        }
        write_words(words, row);
        Ok(())
    }

    /// Packs `st` into `row` ([`Layout::row_width`] bytes) knowing that
    /// `base`, whose packed words are `base_words`, is in range: only the
    /// slots where `st` differs from `base` are repacked (a successor
    /// differs from its source in a few slots). The same bytes, and the
    /// same errors, as [`Layout::pack_into`].
    #[inline]
    pub fn pack_from(&self, base: &[i32], base_words: &[u64], st: &[i32], row: &mut [u8]) -> Result<(), String> {
        let padded = base_words.get(..SMALL_WORDS).and_then(|w| <&[u64; SMALL_WORDS]>::try_from(w).ok());
        match padded {
            // The hot path: a fixed-size copy of the words (padded, as
            // `unpack_row_words` leaves them), indexed without bounds checks.
            Some(&p) if self.words <= SMALL_WORDS => {
                let mut words = p;
                if !self.repack_changed(base, st, &mut words) {
                    return Err(self.out_of_range(st));
                }
                write_words(&words[..self.words], row);
                Ok(())
            }
            _ => self.pack_from_any(base, base_words, st, row),
        }
    }

    /// Packs each vector of `next` as [`Layout::pack_from`] does, into
    /// consecutive rows of `rows` ([`Layout::row_width`] bytes each, one
    /// per vector). Fails with the indices of the vectors out of range
    /// (their rows are left unspecified).
    pub fn pack_all(
        &self,
        base: &[i32],
        base_words: &[u64],
        next: &Vectors,
        rows: &mut [u8],
    ) -> Result<(), Vec<usize>> {
        let mut failed = Vec::new();
        let rows = rows.chunks_exact_mut(self.row_width);
        let padded = base_words.get(..SMALL_WORDS).and_then(|w| <&[u64; SMALL_WORDS]>::try_from(w).ok());
        match padded {
            // The hot path: the source's words copied as a fixed-size
            // array (padded, as `unpack_row_words` leaves them) and indexed
            // without bounds checks.
            Some(&p) if self.words <= SMALL_WORDS => {
                for (k, ((_, st), row)) in next.iter().zip(rows).enumerate() {
                    let mut words = p;
                    if self.repack_changed(base, st, &mut words) {
                        write_words(&words[..self.words], row);
                    } else {
                        failed.push(k);
                    }
                }
            }
            _ => {
                for (k, ((_, st), row)) in next.iter().zip(rows).enumerate() {
                    if self.pack_from_any(base, base_words, st, row).is_err() {
                        failed.push(k);
                    }
                }
            }
        }
        if failed.is_empty() {
            Ok(())
        } else {
            Err(failed)
        }
    }

    /// [`Layout::pack_from`] for words that do not fit `SMALL_WORDS` or
    /// come unpadded.
    #[inline(never)]
    fn pack_from_any(&self, base: &[i32], base_words: &[u64], st: &[i32], row: &mut [u8]) -> Result<(), String> {
        let mut words = base_words[..self.words].to_vec();
        if !self.repack_changed(base, st, &mut words[..]) {
            return Err(self.out_of_range(st));
        }
        write_words(&words, row);
        Ok(())
    }

    /// Repacks into `words` (of at least the layout's words) the slots
    /// where `st` differs from `base`; false if one is out of its range.
    #[inline]
    fn repack_changed<W: AsMut<[u64]> + ?Sized>(&self, base: &[i32], st: &[i32], words: &mut W) -> bool {
        let words = words.as_mut();
        // Whole blocks of slots compare at once (fixed-size arrays compare
        // without a call); most are unchanged.
        const BLOCK: usize = 8;
        let n = self.fields.len().min(st.len()).min(base.len());
        let ((a, a_rest), (b, b_rest)) = (st[..n].as_chunks::<BLOCK>(), base[..n].as_chunks::<BLOCK>());
        let (f8, f_rest) = self.fields[..n].as_chunks::<BLOCK>();
        let mut ok = true;
        for ((x, y), f) in a.iter().zip(b).zip(f8) {
            if x != y {
                for k in 0..BLOCK {
                    if x[k] != y[k] {
                        ok &= repack(&f[k], x[k], words);
                    }
                }
            }
        }
        for ((&v, &old), f) in a_rest.iter().zip(b_rest).zip(f_rest) {
            if v != old {
                ok &= repack(f, v, words);
            }
        }
        ok
    }

    /// The words of the state packed as `row`, into `words` (as many as
    /// the layout has).
    pub fn row_words(&self, row: &[u8], words: &mut Vec<u64>) {
        words.clear();
        words.resize(self.words, 0);
        read_words(row, words);
    }

    /// The slots of the state packed as `row`, into `out` (of [`Layout::len`] slots).
    pub fn unpack_row(&self, row: &[u8], out: &mut [i32]) {
        let mut words = Vec::new();
        self.unpack_row_words(row, out, &mut words);
    }

    /// [`Layout::unpack_row`], also leaving the state's packed words in
    /// `words`: as many as the layout has, then zeros up to
    /// `SMALL_WORDS` (4) if there are fewer, which lets
    /// [`Layout::pack_from`] copy them as a block, then this layout's id.
    ///
    /// When `words` ends with this layout's id already, `out` must hold
    /// the state `words` came from (as this function leaves them): then
    /// only the slots whose bits differ from that state's are read. The
    /// sources of a search come in breadth-first order, and consecutive
    /// ones differ in a few slots. (The id is kept in `words` rather than
    /// in a field of [`Rows`](crate::lts::Rows), whose size the generic
    /// search loop is sensitive to.)
    pub fn unpack_row_words(&self, row: &[u8], out: &mut [i32], words: &mut Vec<u64>) {
        let len = self.words.max(SMALL_WORDS) + 1;
        if words.len() == len && words[len - 1] == self.id && out.len() == self.len() && self.words <= SMALL_WORDS {
            self.unpack_changed(row, out, words);
            return;
        }
        // `read_words` writes every word of the layout: the padding only
        // needs zeroing when the buffer is (re)sized.
        if words.len() != len {
            words.clear();
            words.resize(len, 0);
        }
        words[len - 1] = self.id;
        read_words(row, &mut words[..self.words]);
        // Word by word, so that the word stays in a register.
        let mut at = 0;
        for (&bits, &end) in words.iter().zip(&self.word_ends) {
            // Four slots at a time: the loop's own instructions are a third
            // of the work otherwise.
            let ((s4, s_rest), (o4, o_rest)) =
                (self.slots[at..end].as_chunks::<4>(), out[at..end].as_chunks_mut::<4>());
            for (s, o) in s4.iter().zip(o4) {
                for k in 0..4 {
                    o[k] = s[k].read(bits);
                }
            }
            for (s, o) in s_rest.iter().zip(o_rest) {
                *o = s.read(bits);
            }
            at = end;
        }
    }

    /// Unpacks `row` over `out` and `words`, which hold another state of
    /// this layout (of at most `SMALL_WORDS` words), reading only the
    /// slots of the bits that differ.
    fn unpack_changed(&self, row: &[u8], out: &mut [i32], words: &mut [u64]) {
        let mut new = [0u64; SMALL_WORDS];
        read_words(row, &mut new[..self.words]);
        for (w, (old, &bits)) in words.iter_mut().zip(&new[..self.words]).enumerate() {
            let mut changed = *old ^ bits;
            *old = bits;
            let slot_of = &self.bit_slots[64 * w..64 * w + 64];
            while changed != 0 {
                let i = slot_of[changed.trailing_zeros() as usize] as usize;
                let s = &self.slots[i];
                out[i] = s.read(bits);
                changed &= !(s.mask << s.shift);
            }
        }
    }

    /// The number of slots.
    pub fn len(&self) -> usize {
        self.fields.len()
    }

    /// Whether there are no slots.
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// Packs `st`; an error names the first slot out of its range.
    pub fn pack(&self, st: &[i32]) -> Result<Packed, String> {
        // Up to two words without an allocation: the common case, and the
        // hot path of every search.
        if self.words <= 2 {
            let mut small = [0u64; 2];
            for (f, &v) in self.fields.iter().zip(st) {
                let off = (v as i64).wrapping_sub(f.lo) as u64;
                if off > f.span {
                    return Err(self.out_of_range(st));
                }
                small[f.word as usize & 1] |= off << f.shift;
            }
            return Ok(if self.words == 1 { Packed::Word(small[0]) } else { Packed::Pair(small[0], small[1]) });
        }
        let mut words = vec![0u64; self.words];
        for (f, &v) in self.fields.iter().zip(st) {
            let off = (v as i64).wrapping_sub(f.lo) as u64;
            if off > f.span {
                return Err(self.out_of_range(st));
            }
            words[f.word as usize] |= off << f.shift;
        }
        Ok(Packed::Words(Box::new(words.into_boxed_slice())))
    }

    fn out_of_range(&self, st: &[i32]) -> String {
        for (i, (f, &v)) in self.fields.iter().zip(st).enumerate() {
            let v = v as i64;
            if v < f.lo || v > f.hi {
                return format!("slot {i} holds {v}, outside {}..{} (a bound of the encoding)", f.lo, f.hi);
            }
        }
        "a state does not fit its encoding".to_string()
    }

    /// The slots of `p`.
    pub fn unpack(&self, p: &Packed) -> Box<[i32]> {
        let pair;
        let words: &[u64] = match p {
            Packed::Word(w) => std::slice::from_ref(w),
            Packed::Pair(a, b) => {
                pair = [*a, *b];
                &pair
            }
            Packed::Words(w) => w,
        };
        self.fields
            .iter()
            .map(|f| {
                let raw = if f.bits == 0 {
                    0
                } else {
                    let mask = if f.bits == 64 { u64::MAX } else { (1u64 << f.bits) - 1 };
                    (words.get(f.word as usize).copied().unwrap_or(0) >> f.shift) & mask
                };
                (f.lo + raw as i64) as i32
            })
            .collect()
    }
}

/// Repacks the slot of field `f` with value `v` into `words`; false if `v`
/// is out of the field's range (then `words` are spoilt).
#[inline]
fn repack(f: &Field, v: i32, words: &mut [u64]) -> bool {
    let off = (v as i64).wrapping_sub(f.lo) as u64;
    // `words` has at least the layout's words (a power of two when it is
    // the padded array): the mask keeps the index in bounds without a check.
    let at = f.word as usize & (words.len().next_power_of_two() - 1);
    if let Some(w) = words.get_mut(at) {
        *w = (*w & !(f.mask << f.shift)) | (off << f.shift);
    }
    off <= f.span
}

/// Writes the words of a packed state into `row`, little-endian, the last
/// one cut to the row's end.
#[inline]
fn write_words(words: &[u64], row: &mut [u8]) {
    let (n, full) = (row.len(), row.len() / 8);
    if let (9..=16, [first, second, ..]) = (n, words) {
        // The common widths: two (overlapping) 8-byte stores; the loop
        // below would be a call to `memcpy`.
        let rest = n - 8;
        let tail = if rest == 8 { *second } else { (first >> (8 * rest)) | (second << (64 - 8 * rest)) };
        row[..8].copy_from_slice(&first.to_le_bytes());
        row[n - 8..].copy_from_slice(&tail.to_le_bytes());
        return;
    }
    for (c, w) in row.chunks_exact_mut(8).zip(words) {
        c.copy_from_slice(&w.to_le_bytes());
    }
    let rest = n % 8;
    let Some(&last) = words.get(full).filter(|_| rest > 0) else { return };
    if full > 0 {
        // The row's last 8 bytes in one store: the top bytes of the word
        // before, then the low `rest` bytes of the last word.
        let tail = (words[full - 1] >> (8 * rest)) | (last << (64 - 8 * rest));
        row[n - 8..].copy_from_slice(&tail.to_le_bytes());
    } else {
        for (k, b) in row.iter_mut().enumerate() {
            *b = (last >> (8 * k)) as u8;
        }
    }
}

/// Reads the words of a packed state from `row` (see [`write_words`]).
fn read_words(row: &[u8], words: &mut [u64]) {
    let word = |c: &[u8]| {
        let mut b = [0u8; 8];
        b.copy_from_slice(c);
        u64::from_le_bytes(b)
    };
    let (n, full) = (row.len(), row.len() / 8);
    if let (9..=16, [first, second]) = (n, &mut *words) {
        // The common widths: two (overlapping) 8-byte loads, as in
        // `write_words`; the loop below would be a call to `memcpy`.
        *first = word(&row[..8]);
        *second = word(&row[n - 8..]) >> (64 - 8 * (n - 8));
        return;
    }
    for (c, w) in row.chunks_exact(8).zip(words.iter_mut()) {
        *w = word(c);
    }
    let Some(last) = words.get_mut(full) else { return };
    let rest = n % 8;
    *last = if rest == 0 {
        0
    } else if full > 0 {
        // The row's last 8 bytes in one load; the last word is their top
        // `rest` bytes.
        word(&row[n - 8..]) >> (64 - 8 * rest)
    } else {
        row.iter().enumerate().fold(0, |acc, (k, &b)| acc | u64::from(b) << (8 * k))
    };
}

/// Writes word `w` of a packed state into its place in `row` (the last
/// word may be cut short: its missing bytes are zero).
fn put_word(row: &mut [u8], w: usize, value: u64) {
    let len = row.len();
    let at = (8 * w).min(len);
    let dst = &mut row[at..(at + 8).min(len)];
    let n = dst.len();
    dst.copy_from_slice(&value.to_le_bytes()[..n]);
}

/// Word `w` of a packed state stored in `row`.
fn get_word(row: &[u8], w: usize) -> u64 {
    let at = (8 * w).min(row.len());
    let src = &row[at..(at + 8).min(row.len())];
    let mut b = [0u8; 8];
    b[..src.len()].copy_from_slice(src);
    u64::from_le_bytes(b)
}

/// A packed state as a row: its words, little-endian, the last one cut to
/// the row's width (the layout keeps the cut bytes zero).
impl crate::lts::StateCodec for Packed {
    fn width(&self) -> usize {
        match self {
            Packed::Word(_) => 8,
            Packed::Pair(..) => 16,
            Packed::Words(w) => 8 * w.len(),
        }
    }

    fn write(&self, row: &mut [u8]) {
        match self {
            Packed::Word(a) => put_word(row, 0, *a),
            Packed::Pair(a, b) => {
                put_word(row, 0, *a);
                put_word(row, 1, *b);
            }
            Packed::Words(w) => w.iter().enumerate().for_each(|(i, &x)| put_word(row, i, x)),
        }
    }

    fn read(row: &[u8]) -> Packed {
        match row.len().div_ceil(8) {
            0 | 1 => Packed::Word(get_word(row, 0)),
            2 => Packed::Pair(get_word(row, 0), get_word(row, 1)),
            n => Packed::Words(Box::new((0..n).map(|i| get_word(row, i)).collect())),
        }
    }
}

/// Successor state vectors with their labels, back to back in one buffer:
/// a successor function appends a copy of its source and changes it in
/// place, without an allocation per successor.
#[derive(Debug, Default)]
pub struct Vectors {
    width: usize,
    labels: Vec<Label>,
    slots: Vec<i32>,
    /// Scratch space for the models' machine moves, kept between calls.
    pub(crate) moves: Vec<crate::machine::Move>,
}

impl Vectors {
    /// An empty buffer of vectors of `width` slots.
    pub fn new(width: usize) -> Vectors {
        Vectors { width, ..Vectors::default() }
    }

    /// Empties the buffer, for vectors of `width` slots.
    pub fn reset(&mut self, width: usize) {
        self.width = width;
        self.labels.clear();
        self.slots.clear();
    }

    /// The number of vectors.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Appends a copy of `st` (labelled τ until [`Vectors::set_label`]) and
    /// returns it, to be changed in place.
    // Inlined: called for nearly every successor.
    #[inline]
    pub fn push_copy(&mut self, st: &[i32]) -> &mut [i32] {
        debug_assert_eq!(st.len(), self.width);
        self.labels.push(Label::TAU);
        let at = self.slots.len();
        self.slots.extend_from_slice(st);
        &mut self.slots[at..]
    }

    /// Appends `st` with `label`.
    pub fn push(&mut self, label: Label, st: &[i32]) {
        self.push_copy(st);
        self.set_label(label);
    }

    /// Sets the label of the last vector.
    pub fn set_label(&mut self, label: Label) {
        if let Some(l) = self.labels.last_mut() {
            *l = label;
        }
    }

    /// The labels, in order.
    pub fn labels(&self) -> &[Label] {
        &self.labels
    }

    /// The labels, to be changed.
    pub fn labels_mut(&mut self) -> &mut [Label] {
        &mut self.labels
    }

    /// The vectors with their labels, in order.
    pub fn iter(&self) -> impl Iterator<Item = (Label, &[i32])> {
        // Split off the front one at a time (vectors of no slots are
        // empty slices, which `chunks_exact` cannot give).
        let (mut rest, w) = (&self.slots[..], self.width);
        let vectors = std::iter::from_fn(move || {
            let (v, tail) = rest.split_at_checked(w)?;
            rest = tail;
            Some(v)
        });
        self.labels.iter().copied().zip(vectors)
    }

    /// Vector `k`.
    pub fn get(&self, k: usize) -> &[i32] {
        &self.slots[k * self.width..(k + 1) * self.width]
    }

    /// Keeps the first `len` vectors.
    pub fn truncate(&mut self, len: usize) {
        self.labels.truncate(len);
        self.slots.truncate(len * self.width);
    }

    /// Keeps, among the vectors from `start` on, those whose label `keep`
    /// holds of, in order.
    pub fn retain_from(&mut self, start: usize, keep: impl Fn(Label) -> bool) {
        let w = self.width;
        let mut to = start;
        for k in start..self.labels.len() {
            if keep(self.labels[k]) {
                if to != k {
                    self.labels[to] = self.labels[k];
                    self.slots.copy_within(k * w..(k + 1) * w, to * w);
                }
                to += 1;
            }
        }
        self.truncate(to);
    }
}

/// What a state-vector model needs to be explored packed: the layout of
/// its states, the cell for run-time errors, and its events' names.
#[derive(Debug)]
pub struct Encoding {
    /// How states are packed.
    pub layout: Layout,
    /// The first run-time error met while exploring.
    pub error: crate::lts::FirstError,
    /// The names of events.
    pub events: crate::events::EventTable,
}

impl Encoding {
    /// The encoding of states with these slot ranges and events.
    pub fn new(bounds: &[(i64, i64)], events: crate::events::EventTable) -> Encoding {
        Encoding { layout: Layout::new(bounds), error: crate::lts::FirstError::default(), events }
    }
}

/// A transition system whose successor function works on state vectors
/// and whose states are stored packed: implementing this gives the [`Lts`]
/// (pack on the way out, unpack on the way in, errors recorded).
///
/// [`Lts`]: crate::lts::Lts
pub trait VectorLts: Sync {
    /// How states are packed, where errors go, how events are named.
    fn encoding(&self) -> &Encoding;
    /// The initial state vector.
    fn initial_values(&self) -> Box<[i32]>;
    /// Appends the transitions of a state vector to `out`.
    fn successor_values(&self, st: &[i32], out: &mut Vectors);

    /// The state vector of a packed state.
    fn values(&self, st: &Packed) -> Box<[i32]> {
        self.encoding().layout.unpack(st)
    }
}

impl<T: VectorLts> crate::lts::Lts for T {
    type State = Packed;

    fn initial(&self) -> Packed {
        let e = self.encoding();
        initial_packed(&e.layout, &e.error, &self.initial_values())
    }

    fn successors(&self, st: &Packed, out: &mut Vec<(crate::lts::Label, Packed)>) {
        let e = self.encoding();
        successors_packed(&e.layout, &e.error, st, out, |v, next| self.successor_values(v, next));
    }

    fn event_name(&self, event: crate::lts::Event) -> String {
        crate::lts::event_name_in(&self.encoding().events, event)
    }

    fn state_bytes(&self, st: &Packed) -> usize {
        std::mem::size_of::<Packed>() + st.heap_bytes()
    }

    fn state_width(&self) -> usize {
        self.encoding().layout.row_width()
    }

    fn successor_rows(&self, row: &[u8], out: &mut crate::lts::Rows<Packed>) {
        let e = self.encoding();
        if out.source.len() != e.layout.len() {
            out.source = vec![0; e.layout.len()].into_boxed_slice();
        }
        e.layout.unpack_row_words(row, &mut out.source, &mut out.words);
        out.vectors.reset(e.layout.len());
        self.successor_values(&out.source, &mut out.vectors);
        out.pack_vectors(|source, words, next, rows| {
            let packed = e.layout.pack_all(source, words, next, rows);
            if let Err(failed) = &packed {
                e.error.set(e.layout.out_of_range(next.get(failed[0])));
            }
            packed
        });
    }
}

/// The packed side of an LTS whose successor function works on unpacked
/// state vectors: unpack, run `succ`, pack the successors. A successor that
/// does not fit its encoding is dropped and `error` records why (the
/// check's result is then inconclusive).
pub fn successors_packed(
    layout: &Layout,
    error: &crate::lts::FirstError,
    st: &Packed,
    out: &mut Vec<(crate::lts::Label, Packed)>,
    succ: impl FnOnce(&[i32], &mut Vectors),
) {
    let vals = layout.unpack(st);
    let mut next = Vectors::new(vals.len());
    succ(&vals, &mut next);
    for (k, &label) in next.labels().iter().enumerate() {
        match layout.pack(next.get(k)) {
            Ok(p) => out.push((label, p)),
            Err(e) => error.set(e),
        }
    }
}

/// The packed initial state (a state that does not fit is recorded as an
/// error and replaced by the all-least one).
pub fn initial_packed(layout: &Layout, error: &crate::lts::FirstError, st: &[i32]) -> Packed {
    layout.pack(st).unwrap_or_else(|e| {
        error.set(e);
        Packed::Word(0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lts::{Lts, Rows, StateCodec};

    /// A counter machine over slots of assorted widths: each step bumps
    /// one slot, some past its range (those successors are dropped).
    struct Counters(Encoding);

    impl VectorLts for Counters {
        fn encoding(&self) -> &Encoding {
            &self.0
        }

        fn initial_values(&self) -> Box<[i32]> {
            self.0.layout.fields.iter().map(|f| f.lo as i32).collect()
        }

        fn successor_values(&self, st: &[i32], out: &mut Vectors) {
            for i in 0..st.len() {
                let n = out.push_copy(st);
                n[i] = n[i].wrapping_add(1 + (i as i32 % 3));
                out.set_label(Label::plain(crate::lts::FIRST_VISIBLE + i as u32));
            }
            out.push(Label::TAU, st);
        }
    }

    #[test]
    fn vectors_iterate_in_order_even_without_slots() {
        for width in [0, 1, 3] {
            let mut v = Vectors::new(width);
            for k in 0..4 {
                let st: Vec<i32> = (0..width as i32).map(|i| 10 * k + i).collect();
                v.push(Label::plain(k as u32), &st);
            }
            let all: Vec<(Label, Vec<i32>)> = v.iter().map(|(l, s)| (l, s.to_vec())).collect();
            let by_index: Vec<(Label, Vec<i32>)> = (0..v.len()).map(|k| (v.labels()[k], v.get(k).to_vec())).collect();
            assert_eq!((all.len(), &all), (4, &by_index));
        }
    }

    #[test]
    fn successor_rows_match_successors_packed_one_by_one() {
        let bounds: Vec<Vec<(i64, i64)>> = vec![
            vec![(0, 3), (-2, 5), (0, 1), (0, 40)],
            (0..42).map(|i| (-(i % 3), 2 + i % 5)).collect(),
            vec![(0, i32::MAX as i64), (0, 1000), (0, 9), (-1, 1), (0, i32::MAX as i64)],
            // More words than are packed on the stack.
            [(i32::MIN as i64, i32::MAX as i64); 10].into_iter().chain([(0, 0)]).collect(),
        ];
        for b in bounds {
            let lts = Counters(Encoding::new(&b, crate::events::EventTable::default()));
            let w = lts.state_width();
            let mut fast: Rows<Packed> = Rows::new(w);
            let mut slow = Vec::new();
            // A breadth-first walk over the first states, with the rows
            // of every source appended to the same buffer.
            let mut queue = vec![lts.initial()];
            let mut k = 0;
            while k < queue.len() && k < 200 {
                let mut row = vec![0u8; w];
                lts.encode(&queue[k], &mut row);
                lts.successor_rows(&row, &mut fast);
                let before = slow.len();
                lts.successors(&queue[k], &mut slow);
                queue.extend(slow[before..].iter().map(|(_, p)| p.clone()));
                k += 1;
            }
            assert_eq!(fast.len(), slow.len());
            for (j, (label, p)) in slow.iter().enumerate() {
                let mut row = vec![0u8; w];
                p.write(&mut row);
                assert_eq!((fast.label(j), fast.row(j)), (*label, &row[..]), "transition {j}");
            }
            // Some successors were out of range and dropped, in both.
            assert!(lts.0.error.get().is_some());
        }
    }

    #[test]
    fn rows_shared_by_two_layouts_unpack_each_source_in_full() {
        // Same number of slots, different packing: a source unpacked by one
        // layout is no base for the other's changed slots.
        let a = Counters(Encoding::new(&[(0, 3), (-2, 5), (0, 1), (0, 40)], crate::events::EventTable::default()));
        let b = Counters(Encoding::new(&[(0, 40), (0, 1), (-2, 5), (0, 3)], crate::events::EventTable::default()));
        let w = a.state_width().max(b.state_width());
        let mut shared: Rows<Packed> = Rows::new(w);
        for (k, lts) in [&a, &b, &b, &a, &a, &b].into_iter().enumerate() {
            let st: Vec<i32> =
                lts.0.layout.fields.iter().map(|f| (f.lo + k as i64 % (f.span as i64 + 1)) as i32).collect();
            let mut row = vec![0u8; lts.state_width()];
            lts.0.layout.pack_into(&st, &mut row).unwrap();
            shared.clear();
            lts.successor_rows(&row, &mut shared);
            let mut slow = Vec::new();
            lts.successors(&lts.0.layout.pack(&st).unwrap(), &mut slow);
            assert_eq!(shared.len(), slow.len());
            assert_eq!(&*shared.source, &st[..], "source {k}");
        }
    }

    #[test]
    fn round_trip_and_bounds() {
        let layout = Layout::new(&[(-1, 5), (0, 1), (0, 0), (-3, 3), (i32::MIN as i64, i32::MAX as i64)]);
        for st in [[-1, 0, 0, -3, i32::MIN], [5, 1, 0, 3, i32::MAX], [2, 1, 0, 0, -7]] {
            let p = layout.pack(&st).unwrap();
            assert_eq!(&*layout.unpack(&p), &st);
        }
        assert!(layout.pack(&[6, 0, 0, 0, 0]).is_err());
        assert!(layout.pack(&[0, 0, 1, 0, 0]).is_err());
        // 3 + 1 + 0 + 3 bits, then a 32-bit slot: one word.
        assert!(matches!(layout.pack(&[0, 0, 0, 0, 0]).unwrap(), Packed::Word(_)));
        let two = Layout::new(&[(0, i32::MAX as i64); 3]);
        let p = two.pack(&[1, 2, 3]).unwrap();
        assert!(matches!(p, Packed::Pair(..)));
        assert_eq!(&*two.unpack(&p), &[1, 2, 3]);
        let wide = Layout::new(&[(0, i32::MAX as i64); 5]);
        let p = wide.pack(&[1, 2, 3, 4, 5]).unwrap();
        assert!(matches!(p, Packed::Words(_)));
        assert_eq!(&*wide.unpack(&p), &[1, 2, 3, 4, 5]);
        assert_eq!(std::mem::size_of::<Packed>(), 24);
    }

    #[test]
    fn rows_are_the_packed_words_cut_short() {
        use crate::lts::StateCodec;
        let layouts = [
            Layout::new(&[(-1, 5), (0, 1), (0, 0), (-3, 3)]),
            Layout::new(&[(0, i32::MAX as i64), (0, i32::MAX as i64), (0, 1000)]),
            Layout::new(&[(i32::MIN as i64, i32::MAX as i64); 5]),
            Layout::new(&[(0, 0)]),
            // Rows of one word, of two full words, and of a word and a part.
            Layout::new(&[(0, i32::MAX as i64); 2]),
            Layout::new(&[(0, i32::MAX as i64); 4]),
            Layout::new(&[(0, i32::MAX as i64), (0, i32::MAX as i64), (-7, i32::MAX as i64), (0, 255)]),
        ];
        assert_eq!(layouts.iter().map(Layout::row_width).collect::<Vec<_>>(), [1, 10, 20, 1, 8, 16, 13]);
        for layout in &layouts {
            for seed in 0..20i64 {
                let st: Vec<i32> = layout
                    .fields
                    .iter()
                    .map(|f| (f.lo + (seed * 7919 + f.shift as i64).rem_euclid(f.span as i64 + 1)) as i32)
                    .collect();
                let p = layout.pack(&st).unwrap();
                let mut row = vec![0u8; layout.row_width()];
                layout.pack_into(&st, &mut row).unwrap();
                let mut written = vec![0u8; layout.row_width()];
                p.write(&mut written);
                assert_eq!(row, written);
                assert_eq!(Packed::read(&row), p);
                let mut back = vec![0; layout.len()];
                layout.unpack_row(&row, &mut back);
                assert_eq!(back, st);
                // Repacking from another state gives the same bytes.
                let base: Vec<i32> = layout.fields.iter().map(|f| f.lo as i32).collect();
                let mut base_words = Vec::new();
                let mut base_row = vec![0u8; layout.row_width()];
                layout.pack_into(&base, &mut base_row).unwrap();
                layout.row_words(&base_row, &mut base_words);
                let mut again = vec![0u8; layout.row_width()];
                layout.pack_from(&base, &base_words, &st, &mut again).unwrap();
                assert_eq!(again, row);
                // The same from the words unpacking leaves (padded).
                let (mut padded, mut vals) = (Vec::new(), vec![0; layout.len()]);
                layout.unpack_row_words(&base_row, &mut vals, &mut padded);
                assert_eq!((&vals, &padded[..base_words.len()]), (&base, &base_words[..]));
                let mut from_padded = vec![0u8; layout.row_width()];
                layout.pack_from(&base, &padded, &st, &mut from_padded).unwrap();
                assert_eq!(from_padded, row);
                layout
                    .pack_from(
                        &st,
                        &{
                            let mut w = Vec::new();
                            layout.row_words(&row, &mut w);
                            w
                        },
                        &base,
                        &mut again,
                    )
                    .unwrap();
                assert_eq!(again, base_row);
                let mut wrong = st.clone();
                wrong[0] = (layout.fields[0].hi + 1) as i32;
                if layout.fields[0].hi < i32::MAX as i64 {
                    assert!(layout.pack_from(&st, &base_words, &wrong, &mut again).is_err());
                }
            }
        }
        let mut row = [0u8; 1];
        assert!(layouts[0].pack_into(&[6, 0, 0, 0], &mut row).is_err());
    }
}
