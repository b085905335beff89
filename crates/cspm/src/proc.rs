//! Process terms and their transitions: CSP's operational semantics (as
//! FDR implements it), one rule set per operator. Recursion is cut at
//! `Call` nodes, unfolded on demand and memoised by the evaluator, so
//! terms are finite and serve directly as LTS states.

use std::rc::Rc;

use crate::eval::{err, Evaluator, R};
use crate::{Code, TextRange};

/// A sorted set of event ids.
pub(crate) type Events = Rc<[u32]>;

fn has(set: &[u32], e: u32) -> bool {
    set.binary_search(&e).is_ok()
}

/// A transition label inside the evaluator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum L {
    Tau,
    Tick,
    Ev(u32),
}

/// A process term (opaque outside the crate). Terms share subterms
/// (`Rc`), so a term may be far larger as a tree than in memory: its hash
/// reads a bounded part of it (see the `Hash` impl); equality is
/// structural.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum P {
    Stop,
    Skip,
    /// After termination.
    Omega,
    Div,
    Prefix(u32, Rc<P>),
    Ext(Vec<Rc<P>>),
    Int(Vec<Rc<P>>),
    /// `[+A+]`: events of A are performed by every branch together.
    SyncExt(Events, Vec<Rc<P>>),
    Seq(Rc<P>, Rc<P>),
    /// `; x : s @ P(x)`: the current process, all of them, the next index.
    SeqList(Rc<P>, Rc<[Rc<P>]>, u32),
    /// `n` tocks, then the process (`n` ≥ 1).
    Tocks(u32, u32, Rc<P>),
    /// Generalised parallel (interleaving when the set is empty), n-ary.
    Par(Events, Vec<Rc<P>>),
    AlphaPar(Vec<(Events, Rc<P>)>),
    Hide(Events, Rc<P>),
    Rename(Rc<[(u32, u32)]>, Rc<P>),
    Link(Rc<[(u32, u32)]>, Rc<P>, Rc<P>),
    Interrupt(Rc<P>, Rc<P>),
    SyncInt(Events, Rc<P>, Rc<P>),
    Exception(Events, Rc<P>, Rc<P>),
    Slide(Rc<P>, Rc<P>),
    Run(Events),
    Chaos(Events),
    /// `prioritise(P, <A1, A2, …>)`; τ and ✓ rank with A1.
    Prioritise(Rc<[Events]>, Rc<P>),
    /// FDR's timed prefix: `μX. tock -> X [] (e -> tock^n -> P_e …)`.
    TimedPrefix(u32, Rc<[(u32, Rc<P>)]>),
    /// `TSTOP` (`μX. tock -> X`) and `TSKIP` (`μX. tock -> X [] SKIP`).
    TStop(u32),
    TSkip(u32),
    /// A state of an LTS the host supplied.
    External(Rc<ExternalLts>, u32),
    /// A named process or an application, unfolded on demand.
    Call(Rc<(crate::Value, Vec<crate::Value>)>),
}

/// An LTS from outside, with its event indices mapped to ours. Compared
/// by identity.
#[derive(Debug)]
pub struct ExternalLts {
    pub(crate) id: u64,
    pub(crate) lts: crate::Lts,
    pub(crate) map: Vec<u32>,
}

impl PartialEq for ExternalLts {
    fn eq(&self, o: &Self) -> bool {
        self.id == o.id
    }
}
impl Eq for ExternalLts {}
impl std::hash::Hash for ExternalLts {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.id.hash(h)
    }
}

/// The most nodes of a term its hash reads.
const HASH_NODES: usize = 128;

/// A hash of at most [`HASH_NODES`] nodes, read breadth first: the same
/// for equal terms, as `Hash` requires, and linear in the budget even for
/// a term whose shared subterms make it exponentially large as a tree (a
/// recursion through external choices of internal ones, `PRE` inside
/// every branch of `CON`). Terms that differ only deeper collide, and are
/// then told apart by equality.
impl std::hash::Hash for P {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        let mut queue = std::collections::VecDeque::from([self]);
        let mut read = 0;
        while let Some(p) = queue.pop_front() {
            read += 1;
            if read > HASH_NODES {
                break;
            }
            p.hash_node(h, &mut queue);
        }
    }
}

/// At most 16 events of a set, and its size.
fn hash_events<H: std::hash::Hasher>(set: &[u32], h: &mut H) {
    use std::hash::Hash;
    set.len().hash(h);
    set.iter().take(16).for_each(|e| e.hash(h));
}

impl P {
    /// Hashes this node's own data and queues its subterms.
    fn hash_node<'a, H: std::hash::Hasher>(&'a self, h: &mut H, queue: &mut std::collections::VecDeque<&'a P>) {
        use std::hash::Hash;
        std::mem::discriminant(self).hash(h);
        match self {
            P::Stop | P::Skip | P::Omega | P::Div => {}
            P::Prefix(e, q) => {
                e.hash(h);
                queue.push_back(q);
            }
            P::Ext(ps) | P::Int(ps) => {
                ps.len().hash(h);
                queue.extend(ps.iter().map(|q| &**q));
            }
            P::SyncExt(a, ps) | P::Par(a, ps) => {
                hash_events(a, h);
                ps.len().hash(h);
                queue.extend(ps.iter().map(|q| &**q));
            }
            P::Seq(a, b) | P::Interrupt(a, b) | P::Slide(a, b) => queue.extend([&**a, &**b]),
            P::SeqList(q, list, i) => {
                (list.len(), i).hash(h);
                queue.push_back(q);
            }
            P::Tocks(t, n, q) => {
                (t, n).hash(h);
                queue.push_back(q);
            }
            P::AlphaPar(ps) => {
                ps.len().hash(h);
                for (a, q) in ps {
                    hash_events(a, h);
                    queue.push_back(q);
                }
            }
            P::Hide(a, q) => {
                hash_events(a, h);
                queue.push_back(q);
            }
            P::Rename(map, q) => {
                map.len().hash(h);
                queue.push_back(q);
            }
            P::Link(map, a, b) => {
                map.len().hash(h);
                queue.extend([&**a, &**b]);
            }
            P::SyncInt(e, a, b) | P::Exception(e, a, b) => {
                hash_events(e, h);
                queue.extend([&**a, &**b]);
            }
            P::Run(a) | P::Chaos(a) => hash_events(a, h),
            P::Prioritise(levels, q) => {
                levels.len().hash(h);
                queue.push_back(q);
            }
            P::TimedPrefix(t, branches) => {
                (t, branches.len()).hash(h);
                for (e, q) in branches.iter() {
                    e.hash(h);
                    queue.push_back(q);
                }
            }
            P::TStop(t) | P::TSkip(t) => t.hash(h),
            P::External(lts, s) => (lts.id, s).hash(h),
            P::Call(key) => key.hash(h),
        }
    }

    /// `n` tocks then `p` (kept as one node: no deep terms).
    pub(crate) fn tocks(tock: u32, n: i64, p: Rc<P>) -> Rc<P> {
        match u32::try_from(n) {
            Ok(0) | Err(_) if n <= 0 => p,
            Ok(n) => Rc::new(P::Tocks(tock, n, p)),
            Err(_) => Rc::new(P::Tocks(tock, u32::MAX, p)),
        }
    }
}

impl Evaluator<'_> {
    /// The body of a call (memoised), chasing calls to calls.
    pub(crate) fn unfold(&mut self, p: &Rc<P>, at: TextRange) -> R<Rc<P>> {
        let mut cur = p.clone();
        for _ in 0..1000 {
            let P::Call(key) = &*cur else { return Ok(cur) };
            if let Some(body) = self.calls.get(&**key) {
                cur = body.clone();
                continue;
            }
            let body = self.call_body(key, at)?;
            self.calls.insert((**key).clone(), body.clone());
            cur = body;
        }
        Err(err(Code::Runtime, at, "unguarded recursion: a process is defined as itself"))
    }

    /// The transitions of a term.
    pub(crate) fn transitions(&mut self, p: &Rc<P>, at: TextRange) -> R<Vec<(L, Rc<P>)>> {
        self.enter(at)?;
        let r = self.transitions_inner(p, at);
        self.depth -= 1;
        r
    }

    fn transitions_inner(&mut self, p: &Rc<P>, at: TextRange) -> R<Vec<(L, Rc<P>)>> {
        let omega = || Rc::new(P::Omega);
        let mut out = Vec::new();
        match &**p {
            P::Stop | P::Omega => {}
            P::Skip => out.push((L::Tick, omega())),
            P::Div => out.push((L::Tau, p.clone())),
            P::Prefix(e, q) => out.push((L::Ev(*e), q.clone())),
            P::Call(_) => {
                let q = self.unfold(p, at)?;
                return self.transitions(&q, at);
            }
            P::Ext(ps) => {
                for (i, q) in ps.iter().enumerate() {
                    for (l, q2) in self.transitions(q, at)? {
                        match l {
                            L::Tau => {
                                let mut ps2 = ps.clone();
                                ps2[i] = q2;
                                out.push((L::Tau, Rc::new(P::Ext(ps2))));
                            }
                            l => out.push((l, q2)),
                        }
                    }
                }
            }
            P::Int(ps) => out.extend(ps.iter().map(|q| (L::Tau, q.clone()))),
            P::SyncExt(a, ps) => {
                let all: Vec<_> = ps.iter().map(|q| self.transitions(q, at)).collect::<R<_>>()?;
                for (i, ts) in all.iter().enumerate() {
                    for (l, q2) in ts {
                        match l {
                            L::Tau => {
                                let mut ps2 = ps.clone();
                                ps2[i] = q2.clone();
                                out.push((L::Tau, Rc::new(P::SyncExt(a.clone(), ps2))));
                            }
                            L::Ev(e) if has(a, *e) => {}
                            l => out.push((*l, q2.clone())),
                        }
                    }
                }
                for e in a.iter() {
                    for succ in sync_all(&all, *e) {
                        out.push((L::Ev(*e), Rc::new(P::SyncExt(a.clone(), succ))));
                    }
                }
            }
            P::Seq(a, b) => {
                for (l, a2) in self.transitions(a, at)? {
                    match l {
                        L::Tick => out.push((L::Tau, b.clone())),
                        l => out.push((l, Rc::new(P::Seq(a2, b.clone())))),
                    }
                }
            }
            P::Par(a, ps) => {
                let all: Vec<_> = ps.iter().map(|q| self.transitions(q, at)).collect::<R<_>>()?;
                if ps.iter().all(|q| matches!(**q, P::Omega)) {
                    out.push((L::Tick, omega()));
                }
                for (i, ts) in all.iter().enumerate() {
                    for (l, q2) in ts {
                        let l2 = match l {
                            L::Ev(e) if has(a, *e) => continue,
                            L::Tick => L::Tau,
                            l => *l,
                        };
                        let mut ps2 = ps.clone();
                        ps2[i] = q2.clone();
                        out.push((l2, Rc::new(P::Par(a.clone(), ps2))));
                    }
                }
                for e in a.iter() {
                    for succ in sync_all(&all, *e) {
                        out.push((L::Ev(*e), Rc::new(P::Par(a.clone(), succ))));
                    }
                }
            }
            P::AlphaPar(cs) => {
                let all: Vec<_> = cs.iter().map(|(_, q)| self.transitions(q, at)).collect::<R<_>>()?;
                if cs.iter().all(|(_, q)| matches!(**q, P::Omega)) {
                    out.push((L::Tick, omega()));
                }
                let mut events: Vec<u32> = Vec::new();
                for (i, ts) in all.iter().enumerate() {
                    for (l, q2) in ts {
                        match l {
                            L::Ev(e) => events.push(*e),
                            L::Tau | L::Tick => {
                                let mut cs2 = cs.clone();
                                cs2[i].1 = q2.clone();
                                // τ, and ✓ of one component (which then waits as Ω), are τ.
                                out.push((L::Tau, Rc::new(P::AlphaPar(cs2))));
                            }
                        }
                    }
                }
                events.sort_unstable();
                events.dedup();
                for e in events {
                    // Every component whose alphabet has `e` takes part.
                    let idx: Vec<usize> = (0..cs.len()).filter(|&i| has(&cs[i].0, e)).collect();
                    let sub: Vec<Vec<(L, Rc<P>)>> = idx.iter().map(|&i| all[i].clone()).collect();
                    for succ in sync_all(&sub, e) {
                        let mut cs2 = cs.clone();
                        for (k, &i) in idx.iter().enumerate() {
                            cs2[i].1 = succ[k].clone();
                        }
                        out.push((L::Ev(e), Rc::new(P::AlphaPar(cs2))));
                    }
                }
            }
            P::Hide(a, q) => {
                for (l, q2) in self.transitions(q, at)? {
                    let l = match l {
                        L::Ev(e) if has(a, e) => L::Tau,
                        l => l,
                    };
                    let next = if l == L::Tick { q2 } else { Rc::new(P::Hide(a.clone(), q2)) };
                    out.push((l, next));
                }
            }
            P::Rename(rel, q) => {
                for (l, q2) in self.transitions(q, at)? {
                    let next = Rc::new(P::Rename(rel.clone(), q2.clone()));
                    match l {
                        L::Ev(e) => {
                            let targets: Vec<u32> = rel.iter().filter(|(a, _)| *a == e).map(|(_, b)| *b).collect();
                            if targets.is_empty() {
                                out.push((l, next));
                            } else {
                                out.extend(targets.into_iter().map(|b| (L::Ev(b), next.clone())));
                            }
                        }
                        L::Tick => out.push((L::Tick, q2)),
                        L::Tau => out.push((L::Tau, next)),
                    }
                }
            }
            P::Link(map, a, b) => {
                let ta = self.transitions(a, at)?;
                let tb = self.transitions(b, at)?;
                let left = |e: u32| map.iter().any(|(x, _)| *x == e);
                let right = |e: u32| map.iter().any(|(_, y)| *y == e);
                if matches!(**a, P::Omega) && matches!(**b, P::Omega) {
                    out.push((L::Tick, omega()));
                }
                for (l, a2) in &ta {
                    match l {
                        L::Ev(e) if left(*e) => {
                            for (l2, b2) in &tb {
                                if let L::Ev(f) = l2 {
                                    if map.contains(&(*e, *f)) {
                                        out.push((L::Tau, Rc::new(P::Link(map.clone(), a2.clone(), b2.clone()))));
                                    }
                                }
                            }
                        }
                        l => out.push((
                            if *l == L::Tick { L::Tau } else { *l },
                            Rc::new(P::Link(map.clone(), a2.clone(), b.clone())),
                        )),
                    }
                }
                for (l, b2) in tb {
                    if matches!(l, L::Ev(e) if right(e)) {
                        continue;
                    }
                    out.push((if l == L::Tick { L::Tau } else { l }, Rc::new(P::Link(map.clone(), a.clone(), b2))));
                }
            }
            P::SeqList(cur, all, next) => {
                for (l, c2) in self.transitions(cur, at)? {
                    match (l, all.get(*next as usize)) {
                        (L::Tick, Some(n)) => out.push((L::Tau, Rc::new(P::SeqList(n.clone(), all.clone(), next + 1)))),
                        (L::Tick, None) => out.push((L::Tick, c2)),
                        (l, _) => out.push((l, Rc::new(P::SeqList(c2, all.clone(), *next)))),
                    }
                }
            }
            P::External(ext, s) => {
                for (l, t) in ext.lts.transitions.get(*s as usize).into_iter().flatten() {
                    let l = match l {
                        crate::Label::Tau => L::Tau,
                        crate::Label::Tick => L::Tick,
                        crate::Label::Event(e) => match ext.map.get(*e as usize) {
                            Some(&id) => L::Ev(id),
                            None => {
                                return Err(err(Code::Runtime, at, "an external LTS uses an event it does not list"))
                            }
                        },
                    };
                    let next = if l == L::Tick { Rc::new(P::Omega) } else { Rc::new(P::External(ext.clone(), *t)) };
                    out.push((l, next));
                }
            }
            P::Tocks(tock, n, q) => {
                let next = if *n <= 1 { q.clone() } else { Rc::new(P::Tocks(*tock, n - 1, q.clone())) };
                out.push((L::Ev(*tock), next));
            }
            P::Interrupt(a, b) => {
                for (l, a2) in self.transitions(a, at)? {
                    match l {
                        L::Tick => out.push((L::Tick, a2)),
                        l => out.push((l, Rc::new(P::Interrupt(a2, b.clone())))),
                    }
                }
                for (l, b2) in self.transitions(b, at)? {
                    match l {
                        L::Tau => out.push((L::Tau, Rc::new(P::Interrupt(a.clone(), b2)))),
                        l => out.push((l, b2)),
                    }
                }
            }
            P::SyncInt(s, a, b) => {
                let ta = self.transitions(a, at)?;
                let tb = self.transitions(b, at)?;
                for (l, a2) in &ta {
                    match l {
                        L::Tick => out.push((L::Tick, a2.clone())),
                        L::Ev(e) if has(s, *e) => {
                            for (l2, b2) in &tb {
                                if l2 == l {
                                    out.push((*l, Rc::new(P::SyncInt(s.clone(), a2.clone(), b2.clone()))));
                                }
                            }
                        }
                        l => out.push((*l, Rc::new(P::SyncInt(s.clone(), a2.clone(), b.clone())))),
                    }
                }
                for (l, b2) in tb {
                    match l {
                        L::Tau => out.push((L::Tau, Rc::new(P::SyncInt(s.clone(), a.clone(), b2)))),
                        L::Ev(e) if has(s, e) => {}
                        l => out.push((l, b2)),
                    }
                }
            }
            P::Exception(s, a, b) => {
                for (l, a2) in self.transitions(a, at)? {
                    match l {
                        L::Ev(e) if has(s, e) => out.push((l, b.clone())),
                        L::Tick => out.push((L::Tick, a2)),
                        l => out.push((l, Rc::new(P::Exception(s.clone(), a2, b.clone())))),
                    }
                }
            }
            P::Slide(a, b) => {
                for (l, a2) in self.transitions(a, at)? {
                    match l {
                        L::Tau => out.push((L::Tau, Rc::new(P::Slide(a2, b.clone())))),
                        l => out.push((l, a2)),
                    }
                }
                out.push((L::Tau, b.clone()));
            }
            P::Run(a) => out.extend(a.iter().map(|e| (L::Ev(*e), p.clone()))),
            P::Chaos(a) => {
                out.push((L::Tau, Rc::new(P::Stop)));
                out.extend(a.iter().map(|e| (L::Ev(*e), p.clone())));
            }
            P::Prioritise(levels, q) => {
                let ts = self.transitions(q, at)?;
                let level = |l: &L| match l {
                    L::Tau | L::Tick => Some(0),
                    L::Ev(e) => levels.iter().position(|s| has(s, *e)),
                };
                let best = ts.iter().filter_map(|(l, _)| level(l)).min();
                for (l, q2) in ts {
                    let keep = match (level(&l), best) {
                        (Some(k), Some(b)) => k <= b || k == 0,
                        _ => true,
                    };
                    if keep {
                        let next = if l == L::Tick { q2 } else { Rc::new(P::Prioritise(levels.clone(), q2)) };
                        out.push((l, next));
                    }
                }
            }
            P::TimedPrefix(tock, branches) => {
                out.push((L::Ev(*tock), p.clone()));
                out.extend(branches.iter().map(|(e, q)| (L::Ev(*e), q.clone())));
            }
            P::TStop(tock) => out.push((L::Ev(*tock), p.clone())),
            P::TSkip(tock) => {
                out.push((L::Ev(*tock), p.clone()));
                out.push((L::Tick, omega()));
            }
        }
        Ok(out)
    }
}

/// Every way all components perform `e` together (the product of their
/// `e`-successors).
fn sync_all(all: &[Vec<(L, Rc<P>)>], e: u32) -> Vec<Vec<Rc<P>>> {
    let mut acc: Vec<Vec<Rc<P>>> = vec![Vec::new()];
    for ts in all {
        let succ: Vec<&Rc<P>> = ts.iter().filter(|(l, _)| *l == L::Ev(e)).map(|(_, q)| q).collect();
        if succ.is_empty() {
            return Vec::new();
        }
        let mut next = Vec::with_capacity(acc.len() * succ.len());
        for a in &acc {
            for q in &succ {
                let mut v = a.clone();
                v.push((*q).clone());
                next.push(v);
            }
        }
        acc = next;
    }
    if all.is_empty() {
        return Vec::new();
    }
    acc
}
