//! Green tree construction, in place of rowan's `GreenNodeBuilder`.
//!
//! The tree is the same, and so is what gets shared: equal tokens, and
//! equal nodes of at most three children. What differs is the lookup.
//! rowan hashes every token's text and every small node's children through
//! a general-purpose hash map. Here a token of up to 16 bytes (nearly all of
//! them) is looked up by its kind, length and bytes packed into three
//! words, and a small node by its kind and the addresses of its (already
//! shared) children: integer keys in an open-addressing table.

use std::hash::Hasher;

use rowan::{GreenNode, GreenToken, NodeOrToken};
use rustc_hash::FxHasher;

use crate::lexer::Token;
use crate::{SyntaxKind, TextRange, TextSize};

/// Whether every token of a kind has the same text: punctuation and
/// keywords, except the multi-word keywords, whose spacing varies. Such
/// tokens are shared through a slot per kind, without a table lookup.
/// Token kinds are below 256 (see `TokenSet`): `kind as usize & 255`
/// indexes these tables without a bounds check.
const FIXED_TEXT: [bool; 256] = {
    let mut t = [false; 256];
    let mut i = 0;
    while i < 256 && i < crate::kinds::ALL_KINDS.len() {
        let k = crate::kinds::ALL_KINDS[i];
        t[i] = (k.is_punct() || k.is_keyword())
            && !matches!(
                k,
                SyntaxKind::FAILURES_DIVERGENCES_MODEL_KW
                    | SyntaxKind::FAILURES_MODEL_KW
                    | SyntaxKind::TRACES_MODEL_KW
                    | SyntaxKind::TICK_TOCK_MODEL_KW
            );
        i += 1;
    }
    t
};

/// A finished child of the node being built. (In the order of
/// `NodeOrToken`'s variants, so that `into_element` keeps the tag.)
enum Child {
    /// `shared` says whether the node is in the node cache, which makes its
    /// address usable as its identity.
    Node {
        node: GreenNode,
        shared: bool,
    },
    Token(GreenToken),
}

impl Child {
    /// The address identifying a deduplicated child.
    fn id(&self) -> u64 {
        match self {
            Child::Token(t) => &**t as *const rowan::GreenTokenData as usize as u64,
            Child::Node { node, .. } => &**node as *const rowan::GreenNodeData as usize as u64,
        }
    }

    fn is_shared(&self) -> bool {
        match self {
            Child::Token(_) => true,
            Child::Node { shared, .. } => *shared,
        }
    }

    fn into_element(self) -> NodeOrToken<GreenNode, GreenToken> {
        match self {
            Child::Token(t) => NodeOrToken::Token(t),
            Child::Node { node, .. } => NodeOrToken::Node(node),
        }
    }
}

/// Open addressing with linear probing, for keys of `N` words. Keys are
/// compared as integers: no hashing or comparing of text on the hot path.
///
/// The probed array holds only 4-byte indices into a dense list of
/// entries, and is at most half full. Keeping it small matters: a table
/// that outgrows the allocator's reuse makes every parse fault in fresh
/// pages, which costs more than the lookups save.
struct Table<const N: usize, T> {
    /// Index + 1 into `entries`; 0 for a free slot. The length is a power
    /// of two.
    slots: Vec<u32>,
    entries: Vec<([u64; N], T)>,
    /// `64 - log2(slots.len())`: the index is the top bits of the hash.
    shift: u32,
}

impl<const N: usize, T: Clone> Table<N, T> {
    /// A table for about `n` entries without growing.
    fn with_capacity(n: usize) -> Table<N, T> {
        let slots = (2 * n).next_power_of_two().max(64);
        Table { slots: vec![0; slots], entries: Vec::with_capacity(n), shift: 64 - slots.trailing_zeros() }
    }

    fn index(&self, key: &[u64; N]) -> usize {
        // The words folded together, then multiplicative hashing (Knuth):
        // the top bits of the product depend on all bits of the fold.
        const K: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut h = key[0];
        for &w in &key[1..] {
            h = h.rotate_left(26) ^ w;
        }
        (h.wrapping_mul(K) >> self.shift) as usize
    }

    /// The value stored under `key`, or else the free slot where it goes.
    #[inline]
    fn find(&self, key: &[u64; N]) -> Result<&T, usize> {
        let mask = self.slots.len() - 1;
        let mut i = self.index(key);
        loop {
            let e = self.slots[i] as usize;
            if e == 0 {
                return Err(i);
            }
            let (k, v) = &self.entries[e - 1];
            if k == key {
                return Ok(v);
            }
            i = (i + 1) & mask;
        }
    }

    /// Stores `value` in the free `slot` that `find` gave for `key`.
    fn insert(&mut self, slot: usize, key: [u64; N], value: T) {
        debug_assert_eq!(self.slots[slot], 0);
        self.entries.push((key, value));
        self.slots[slot] = self.entries.len() as u32;
        if 2 * self.entries.len() > self.slots.len() {
            self.grow();
        }
    }

    fn grow(&mut self) {
        self.slots = vec![0; self.slots.len() * 2];
        self.shift -= 1;
        let mask = self.slots.len() - 1;
        for (n, (k, _)) in self.entries.iter().enumerate() {
            let mut i = self.index(k);
            while self.slots[i] != 0 {
                i = (i + 1) & mask;
            }
            self.slots[i] = n as u32 + 1;
        }
    }
}

/// The shared node of kind `kind` over the children from `first` on, whose
/// key is `key`: the one in `table`, or else a new one, added to it. Nodes
/// with at most three children are deduplicated (as in rowan): that covers
/// names, literals and short expressions, which repeat a lot.
#[inline(always)]
fn share<const N: usize>(
    table: &mut Table<N, GreenNode>,
    key: [u64; N],
    children: &mut Vec<Child>,
    kind: SyntaxKind,
    first: usize,
) -> GreenNode {
    match table.find(&key) {
        Ok(node) => {
            let node = node.clone();
            // `N - 1` children: popping them one by one inlines their drop,
            // which `truncate` does not.
            for _ in 1..N {
                children.pop();
            }
            debug_assert_eq!(children.len(), first);
            node
        }
        Err(slot) => {
            let node = make_node(children, kind, first);
            table.insert(slot, key, node.clone());
            node
        }
    }
}

fn make_node(children: &mut Vec<Child>, kind: SyntaxKind, first: usize) -> GreenNode {
    GreenNode::new(kind.into(), children.drain(first..).map(Child::into_element))
}

/// The bytes `src[at..at + n]` (`n` from 1 to 8) as a little-endian word.
#[inline]
pub(crate) fn word(src: &[u8], at: usize, n: usize) -> u64 {
    debug_assert!((1..=8).contains(&n));
    let rest = &src[at..];
    match rest.first_chunk::<8>() {
        // One load and a mask instead of a byte loop.
        Some(w) => u64::from_le_bytes(*w) & (u64::MAX >> (64 - 8 * n)),
        None => rest[..n].iter().rev().fold(0, |w, &b| (w << 8) | u64::from(b)),
    }
}

/// The builder's position, to go back to (see `TreeBuilder::restore`).
#[derive(Clone, Copy)]
pub(crate) struct Saved {
    children: usize,
    tok: usize,
    off: usize,
}

/// Builds one green tree over a token stream: the parser adds tokens in
/// order and closes nodes over ranges of the children added so far.
pub(crate) struct TreeBuilder<'t> {
    /// The whole text; tokens are ranges of it.
    src: &'t str,
    tokens: &'t [Token],
    /// The next token to add, and where it starts.
    tok: usize,
    off: usize,
    /// Finished children of the nodes still open, innermost last.
    children: Vec<Child>,
    /// Tokens of up to 16 bytes (nearly all), keyed by kind, length and
    /// bytes packed into words.
    short_tokens: Table<3, GreenToken>,
    /// Longer tokens, keyed by kind and length and a hash of the text; the
    /// text is compared too.
    long_tokens: Table<3, GreenToken>,
    /// Nodes of one, two and three shared children, keyed by their kind
    /// and the children's addresses. Children are kept alive by the cached
    /// node, so an address cannot be reused while its key exists.
    nodes1: Table<2, GreenNode>,
    nodes2: Table<3, GreenNode>,
    nodes3: Table<4, GreenNode>,
    /// The token of each fixed-text kind (see `FIXED_TEXT`), once seen.
    fixed: [Option<GreenToken>; 256],
    /// Recent tokens of the kinds in `is_cached`, by `cache_key`: a power
    /// of two of them, from 16 to 512 by the length of the text (setting
    /// up and dropping a large cache costs more than it saves on a small
    /// file).
    recent: Vec<(u64, Option<GreenToken>)>,
    /// `64 - log2(recent.len())`.
    recent_shift: u32,
}

/// Whether a token goes through the cache of recent tokens: whitespace,
/// names and numbers (two thirds of all tokens) of up to 7 bytes (nearly
/// all).
fn is_cached(kind: SyntaxKind, len: usize) -> bool {
    matches!(kind, SyntaxKind::WHITESPACE | SyntaxKind::IDENT | SyntaxKind::INT_NUMBER | SyntaxKind::FLOAT_NUMBER)
        && len <= 7
}

/// The size of the cache of recent tokens for a text of `len` bytes.
fn recent_len(len: usize) -> usize {
    (len / 256).next_power_of_two().clamp(16, 512)
}

/// The bytes packed into a word (`w`, never zero for these kinds), with the
/// kind in the top byte, which the packing leaves free.
fn cache_key(kind: SyntaxKind, w: u64) -> u64 {
    w | (kind as u64) << 56
}

fn recent_slot(key: u64, shift: u32) -> usize {
    (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> shift) as usize
}

impl<'t> TreeBuilder<'t> {
    pub(crate) fn new(src: &'t str, tokens: &'t [Token]) -> TreeBuilder<'t> {
        TreeBuilder {
            src,
            tokens,
            tok: 0,
            off: 0,
            children: Vec::with_capacity(256),
            // Sized from what models have: one distinct token per 36 to 56
            // bytes, one distinct small node per 19 to 28.
            short_tokens: Table::with_capacity(src.len() / 32),
            long_tokens: Table::with_capacity(16),
            nodes1: Table::with_capacity(src.len() / 32),
            nodes2: Table::with_capacity(src.len() / 64),
            nodes3: Table::with_capacity(src.len() / 64),
            fixed: [const { None }; 256],
            recent: vec![(0, None); recent_len(src.len())],
            recent_shift: 64 - recent_len(src.len()).trailing_zeros(),
        }
    }

    /// Where the children of a node started now would begin.
    pub(crate) fn checkpoint(&self) -> usize {
        self.children.len()
    }

    pub(crate) fn save(&self) -> Saved {
        Saved { children: self.children.len(), tok: self.tok, off: self.off }
    }

    /// Goes back to `saved`, which must be at or before the last checkpoint
    /// still in use, dropping the tokens added since.
    pub(crate) fn restore(&mut self, saved: Saved) {
        self.children.truncate(saved.children);
        self.tok = saved.tok;
        self.off = saved.off;
    }

    /// Adds the trivia in front of the next token.
    pub(crate) fn trivia(&mut self) {
        while let Some(t) = self.tokens.get(self.tok) {
            if !t.kind.is_trivia() {
                break;
            }
            self.add(*t);
        }
    }

    /// Adds the next non-trivia token, and the trivia in front of it.
    pub(crate) fn token(&mut self) {
        self.trivia();
        if let Some(t) = self.tokens.get(self.tok) {
            self.add(*t);
        }
    }

    /// The range of the last non-trivia token added (`None` before the
    /// first): only trivia can follow it.
    pub(crate) fn range_behind(&self) -> Option<TextRange> {
        let mut end = TextSize::from(self.off as u32);
        for t in self.tokens[..self.tok].iter().rev() {
            if !t.kind.is_trivia() {
                return Some(TextRange::new(end - t.len, end));
            }
            end -= t.len;
        }
        None
    }

    /// The range of the `n`-th non-trivia token from the next one to add
    /// (`None` past the end).
    pub(crate) fn range_ahead(&self, mut n: usize) -> Option<TextRange> {
        let mut off = TextSize::from(self.off as u32);
        for t in &self.tokens[self.tok..] {
            if !t.kind.is_trivia() {
                if n == 0 {
                    return Some(TextRange::at(off, t.len));
                }
                n -= 1;
            }
            off += t.len;
        }
        None
    }

    /// Adds all tokens that are left.
    pub(crate) fn rest(&mut self) {
        while let Some(t) = self.tokens.get(self.tok) {
            self.add(*t);
        }
    }

    #[inline]
    fn add(&mut self, t: Token) {
        let (kind, start, len) = (t.kind, self.off, u32::from(t.len) as usize);
        self.tok += 1;
        self.off += len;
        if FIXED_TEXT[kind as usize & 255] {
            let token = match &self.fixed[kind as usize & 255] {
                Some(token) => token.clone(),
                None => self.new_fixed(kind, start, len),
            };
            debug_assert_eq!(Some(token.text()), kind.text());
            self.children.push(Child::Token(token));
            return;
        }
        if is_cached(kind, len) {
            // Whitespace has only a few distinct texts, and names and
            // numbers repeat close to each other: a direct-mapped cache in
            // front of the table saves most lookups.
            let k = cache_key(kind, word(self.src.as_bytes(), start, len));
            if let (key, Some(token)) = &self.recent[recent_slot(k, self.recent_shift)] {
                if *key == k {
                    let token = token.clone();
                    self.children.push(Child::Token(token));
                    return;
                }
            }
        }
        self.add_hashed(kind, start, len);
    }

    /// `add` through the token tables. Kept out of `add` so that its fast
    /// paths need no registers saved.
    #[inline(never)]
    fn add_hashed(&mut self, kind: SyntaxKind, start: usize, len: usize) {
        let bytes = self.src.as_bytes();
        let head = kind as u64 | (len as u64) << 16;
        let key = match len {
            1..=8 => [head, word(bytes, start, len), 0],
            9..=16 => [head, word(bytes, start, 8), word(bytes, start + 8, len - 8)],
            _ => return self.add_long(kind, start, len),
        };
        let token = self.short_token(key, kind, start, len);
        if is_cached(kind, len) {
            let k = cache_key(kind, key[1]);
            self.recent[recent_slot(k, self.recent_shift)] = (k, Some(token.clone()));
        }
        self.children.push(Child::Token(token));
    }

    #[inline(always)]
    fn short_token(&mut self, key: [u64; 3], kind: SyntaxKind, start: usize, len: usize) -> GreenToken {
        match self.short_tokens.find(&key) {
            Ok(token) => token.clone(),
            Err(slot) => self.new_short(slot, key, kind, start, len),
        }
    }

    #[cold]
    #[inline(never)]
    fn new_short(&mut self, slot: usize, key: [u64; 3], kind: SyntaxKind, start: usize, len: usize) -> GreenToken {
        let token = GreenToken::new(kind.into(), &self.src[start..start + len]);
        self.short_tokens.insert(slot, key, token.clone());
        token
    }

    #[cold]
    #[inline(never)]
    fn new_fixed(&mut self, kind: SyntaxKind, start: usize, len: usize) -> GreenToken {
        let token = GreenToken::new(kind.into(), &self.src[start..start + len]);
        self.fixed[kind as usize & 255] = Some(token.clone());
        token
    }

    /// Comments, strings and long names: rare enough that hashing the text
    /// is fine. Two texts with the same hash are not shared.
    #[cold]
    #[inline(never)]
    fn add_long(&mut self, kind: SyntaxKind, start: usize, len: usize) {
        let text = &self.src[start..start + len];
        let mut h = FxHasher::default();
        h.write(text.as_bytes());
        let key = [kind as u64 | (len as u64) << 16, h.finish(), 0];
        let token = match self.long_tokens.find(&key) {
            Ok(token) if token.text() == text => token.clone(),
            Ok(_) => GreenToken::new(kind.into(), text),
            Err(slot) => {
                let token = GreenToken::new(kind.into(), text);
                self.long_tokens.insert(slot, key, token.clone());
                token
            }
        };
        self.children.push(Child::Token(token));
    }

    /// Makes the children from `first` on into one node of kind `kind`.
    pub(crate) fn finish_node(&mut self, kind: SyntaxKind, first: usize) {
        let k = kind as u64;
        let children = &mut self.children;
        // Each number of children has its own table, so that the keys of
        // the most common nodes, those of one child, are only two words.
        let shared = match &children[first..] {
            [a] if a.is_shared() => Some(share(&mut self.nodes1, [k, a.id()], children, kind, first)),
            [a, b] if a.is_shared() && b.is_shared() => {
                Some(share(&mut self.nodes2, [k, a.id(), b.id()], children, kind, first))
            }
            [a, b, c] if a.is_shared() && b.is_shared() && c.is_shared() => {
                Some(share(&mut self.nodes3, [k, a.id(), b.id(), c.id()], children, kind, first))
            }
            _ => None,
        };
        let child = match shared {
            Some(node) => Child::Node { node, shared: true },
            None => Child::Node { node: make_node(children, kind, first), shared: false },
        };
        children.push(child);
    }

    /// The root. Normally the parser has closed it over everything;
    /// after a grammar bug (a marker never completed) whatever is left
    /// is wrapped in one more `root` node, so that no text is lost.
    pub(crate) fn finish(mut self, root: SyntaxKind) -> GreenNode {
        self.rest();
        if self.children.len() != 1 || !matches!(self.children[0], Child::Node { .. }) {
            debug_assert!(false, "unbalanced tree");
            self.finish_node(root, 0);
        }
        match self.children.pop() {
            Some(Child::Node { node, .. }) => node,
            _ => unreachable!("a root node was just made"),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{parse, FileKind};

    #[test]
    fn words_pack_every_length_and_the_end_of_the_text() {
        let src = b"abcdefghij";
        assert_eq!(super::word(src, 0, 1), u64::from(b'a'));
        assert_eq!(super::word(src, 0, 8), u64::from_le_bytes(*b"abcdefgh"));
        // Fewer than eight bytes left: the byte loop.
        assert_eq!(super::word(src, 7, 3), u64::from_le_bytes(*b"hij\0\0\0\0\0"));
    }

    #[test]
    fn equal_tokens_are_shared_and_different_ones_are_not() {
        // Names that differ only after 8 or 16 bytes, long names, and one
        // at the very end of the text.
        let text = "const abcdefgh1, abcdefgh2, abcdefghijklmnop1, abcdefghijklmnop2 : int \
                    const averyveryverylongname_x, averyveryverylongname_y, averyveryverylongname_x : int\n\
                    const abcdefgh1 : int abcdefgh2";
        let parse = parse(text, FileKind::RoboChart);
        let root = parse.syntax_node();
        assert_eq!(root.text().to_string(), text);
        let idents: Vec<_> = root
            .descendants_with_tokens()
            .filter_map(|e| e.into_token())
            .filter(|t| t.kind() == crate::SyntaxKind::IDENT)
            .collect();
        for a in &idents {
            for b in &idents {
                let same = std::ptr::eq(a.green(), b.green());
                assert_eq!(same, a.text() == b.text(), "{} / {}", a.text(), b.text());
            }
        }
    }
}
