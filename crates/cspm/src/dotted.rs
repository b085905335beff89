//! Dotted values, events and patterns: `c.1.A.2` built field by field
//! (constructors and channels know their number of fields), the complete
//! values extending a prefix (`{| c |}`, inputs), event ids, and matching
//! values against patterns (dotted patterns are aligned with the fields).

use std::collections::BTreeSet;
use std::rc::Rc;

use crate::ast::{Name, Pat};
use crate::eval::{err, Evaluator, Slot, R};
use crate::proc::P;
use crate::resolve::ExternalName;
use crate::{Code, TextRange, Value};

impl Evaluator<'_> {
    /// The constructor or channel the name `n` of a pattern denotes in the
    /// frame `env` (lexically: a module's own `c` is `M::c`), if any; a
    /// name bound to something else, or to a constructor of another name
    /// (a parameter holding an event), is a variable.
    pub(crate) fn ctor_of(&self, n: &str, env: u32) -> Option<Name> {
        match self.slot(n, env) {
            Some(Slot::Val(Value::Ctor(q)))
                if self.arity.contains_key(&q)
                    && (*q == *n || q.strip_suffix(n).is_some_and(|m| m.ends_with("::"))) =>
            {
                Some(q)
            }
            Some(_) => None,
            None if self.arity.contains_key(n)
                || matches!(self.names.lookup(n), Some(ExternalName::Value(Value::Ctor(_)))) =>
            {
                Some(n.into())
            }
            None => None,
        }
    }

    fn is_ctor(&self, n: &str) -> bool {
        matches!(n, "true" | "false") || self.ctor_of(n, self.pat_env).is_some()
    }

    /// Matches `v` against `p`, pushing the bindings.
    pub(crate) fn matches(&mut self, p: &Pat, v: &Value, binds: &mut Vec<(Name, Value)>) -> R<bool> {
        Ok(match (p, v) {
            (Pat::Wild, _) => true,
            (Pat::Name(n, _), v) if self.is_ctor(n) => match &**n {
                "true" => *v == Value::Bool(true),
                "false" => *v == Value::Bool(false),
                _ => self.ctor_of(n, self.pat_env).is_some_and(|q| *v == Value::Ctor(q)),
            },
            (Pat::Name(n, _), v) => {
                binds.push((n.clone(), v.clone()));
                true
            }
            (Pat::Int(i), Value::Int(j)) => i == j,
            (Pat::Bool(a), Value::Bool(b)) => a == b,
            (Pat::Char(a), Value::Char(b)) => a == b,
            (Pat::Str(s), Value::Seq(vs)) => {
                let cs: Vec<Value> = s.chars().map(Value::Char).collect();
                cs[..] == vs[..]
            }
            (Pat::Tuple(ps), Value::Tuple(vs)) => ps.len() == vs.len() && self.all_match(ps, vs, binds)?,
            (Pat::Seq(ps), Value::Seq(vs)) => ps.len() == vs.len() && self.all_match(ps, vs, binds)?,
            (Pat::Set(ps), Value::Set(vs)) => match (ps.first(), vs.len()) {
                (None, 0) => true,
                (Some(p), 1) => {
                    let x = vs.iter().next().cloned().unwrap_or(Value::Int(0));
                    self.matches(p, &x, binds)?
                }
                _ => false,
            },
            (Pat::Concat(a, b), Value::Seq(vs)) => {
                // One side must have a fixed length (`<x>^xs`, `xs^<x>`).
                match (fixed_len(a), fixed_len(b)) {
                    (Some(n), _) if n <= vs.len() => {
                        self.matches(a, &Value::Seq(vs[..n].into()), binds)?
                            && self.matches(b, &Value::Seq(vs[n..].into()), binds)?
                    }
                    (_, Some(n)) if n <= vs.len() => {
                        let k = vs.len() - n;
                        self.matches(a, &Value::Seq(vs[..k].into()), binds)?
                            && self.matches(b, &Value::Seq(vs[k..].into()), binds)?
                    }
                    _ => false,
                }
            }
            (Pat::Double(a, b), v) => self.matches(a, v, binds)? && self.matches(b, v, binds)?,
            (Pat::Dot(..), v) => {
                let mut ps = Vec::new();
                flatten_dot_pat(p, &mut ps);
                let vs: Vec<Value> = match v {
                    Value::Dot(vs) => vs.to_vec(),
                    v => vec![v.clone()],
                };
                self.match_dots(&ps, &vs, binds)?
            }
            _ => false,
        })
    }

    pub(crate) fn all_match(&mut self, ps: &[Pat], vs: &[Value], binds: &mut Vec<(Name, Value)>) -> R<bool> {
        for (p, v) in ps.iter().zip(vs) {
            if !self.matches(p, v, binds)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// `p1.p2.…` against the components of a dotted value. Nested
    /// constructor values are opened while patterns outnumber components
    /// (`Ccl.x.Bcl.y` against `Ccl.0.(Bcl.1)`); then each pattern takes as
    /// many components as it has parts, and the last one the rest.
    fn match_dots(&mut self, ps: &[&Pat], vs: &[Value], binds: &mut Vec<(Name, Value)>) -> R<bool> {
        let mut vs = vs.to_vec();
        let widths: Vec<usize> = ps.iter().map(|p| pat_width(p)).collect();
        let need: usize = widths.iter().sum();
        while need > vs.len() {
            let Some(i) =
                vs.iter().position(|v| matches!(v, Value::Dot(d) if matches!(d.first(), Some(Value::Ctor(_)))))
            else {
                return Ok(false);
            };
            let Value::Dot(inner) = vs[i].clone() else { return Ok(false) };
            vs.splice(i..=i, inner.iter().cloned());
        }
        let mut at = 0;
        for (i, p) in ps.iter().enumerate() {
            let take = if i + 1 == ps.len() { vs.len() - at } else { widths[i] };
            if take == 0 || at + take > vs.len() {
                return Ok(false);
            }
            let v = if take == 1 { vs[at].clone() } else { Value::Dot(vs[at..at + take].into()) };
            at += take;
            if !self.matches(p, &v, binds)? {
                return Ok(false);
            }
        }
        Ok(at == vs.len())
    }

    /// The number of fields of a constructor or channel.
    pub(crate) fn arity(&self, name: &str) -> usize {
        self.arity.get(name).copied().unwrap_or(0)
    }

    /// Whether a dotted value is a constructor/channel with all its fields.
    pub(crate) fn complete(&self, v: &Value) -> bool {
        match v {
            Value::Ctor(n) => self.arity(n) == 0,
            Value::Dot(vs) => match vs.first() {
                Some(Value::Ctor(n)) => vs.len() - 1 == self.arity(n) && vs[1..].iter().all(|x| self.complete(x)),
                _ => true,
            },
            _ => true,
        }
    }

    /// `x.y`, filling the innermost incomplete field of `x` first.
    pub(crate) fn dot(&mut self, x: Value, y: Value, at: TextRange) -> R<Value> {
        // A plain dotted `y` (`1.2`) fills fields one component at a time.
        if let Value::Dot(ys) = &y {
            if !matches!(ys.first(), Some(Value::Ctor(_))) && !self.complete(&x) {
                let mut acc = x;
                for c in ys.iter() {
                    acc = self.dot(acc, c.clone(), at)?;
                }
                return Ok(acc);
            }
        }
        if self.complete(&x) {
            let mut parts: Vec<Value> = match x {
                Value::Dot(xs) if !matches!(xs.first(), Some(Value::Ctor(_))) => xs.to_vec(),
                x => vec![x],
            };
            match y {
                Value::Dot(ys) if !matches!(ys.first(), Some(Value::Ctor(_))) => parts.extend(ys.iter().cloned()),
                y => parts.push(y),
            }
            self.check_size(parts.len(), at)?;
            return Ok(Value::Dot(parts.into()));
        }
        let mut parts: Vec<Value> = match x {
            Value::Dot(xs) => xs.to_vec(),
            x => vec![x],
        };
        let last_incomplete = parts.len() > 1 && parts.last().is_some_and(|l| !self.complete(l));
        if last_incomplete {
            let last = parts.pop().unwrap_or(Value::Int(0));
            parts.push(self.dot(last, y, at)?);
        } else {
            parts.push(y);
        }
        Ok(Value::Dot(parts.into()))
    }

    /// All complete values extending `v` (`{| c |}`, `productions`, a
    /// datatype's values): the declared values of its channel or
    /// constructor (restricted field types included) that start with `v`.
    pub(crate) fn completions(&mut self, v: Value, at: TextRange) -> R<Vec<Value>> {
        if self.complete(&v) {
            return Ok(vec![v]);
        }
        let head = match &v {
            Value::Ctor(n) => n.clone(),
            Value::Dot(d) => match d.first() {
                Some(Value::Ctor(n)) => n.clone(),
                _ => return Ok(vec![v]),
            },
            _ => return Ok(vec![v]),
        };
        let Some(fields) = self.fields.get(&head).cloned() else {
            return Err(err(
                Code::Limit,
                at,
                format!("the values of `{head}` cannot be enumerated (a field of type `Int` or a recursive type)"),
            ));
        };
        let mut prefix = Vec::new();
        flatten_value(&v, &mut prefix);
        let mut acc: Vec<Vec<Value>> = vec![vec![Value::Ctor(head)]];
        for set in fields.iter() {
            let mut next = Vec::with_capacity(acc.len() * set.len());
            for a in &acc {
                for x in set.iter() {
                    self.tick(at)?;
                    let mut t = a.clone();
                    t.push(x.clone());
                    // Prune early: the components so far must agree with `v`.
                    let mut flat = Vec::new();
                    t.iter().for_each(|c| flatten_value(c, &mut flat));
                    let n = flat.len().min(prefix.len());
                    if flat[..n] == prefix[..n] {
                        next.push(t);
                    }
                }
            }
            self.check_size(next.len(), at)?;
            acc = next;
        }
        let mut out: Vec<Value> = acc
            .into_iter()
            .filter_map(|t| {
                let mut flat = Vec::new();
                t.iter().for_each(|c| flatten_value(c, &mut flat));
                (flat.len() >= prefix.len()).then(|| if t.len() == 1 { t[0].clone() } else { Value::Dot(t.into()) })
            })
            .collect();
        out.sort();
        out.dedup();
        Ok(out)
    }

    /// The event id of a complete event value.
    pub(crate) fn event(&mut self, v: Value, at: TextRange) -> R<u32> {
        if let Some(&id) = self.event_ids.get(&v) {
            return Ok(id);
        }
        let channel = match &v {
            Value::Ctor(n) => Some(n),
            Value::Dot(vs) => match vs.first() {
                Some(Value::Ctor(n)) => Some(n),
                _ => None,
            },
            _ => None,
        };
        if !channel.is_some_and(|c| self.channels.contains(c)) || !self.complete(&v) {
            return Err(err(Code::Type, at, format!("`{v}` is not an event")));
        }
        let id = self.events.len() as u32;
        self.events.push(v.clone());
        self.event_ids.insert(v, id);
        Ok(id)
    }

    /// A process term for an external LTS: its events interned (their
    /// channels are looked up through the host's names).
    pub(crate) fn external_process(&mut self, lts: crate::Lts, at: TextRange) -> R<Rc<P>> {
        let mut map = Vec::with_capacity(lts.event_values.len());
        for v in &lts.event_values {
            let head = match v {
                Value::Ctor(n) => Some(n.clone()),
                Value::Dot(d) => match d.first() {
                    Some(Value::Ctor(n)) => Some(n.clone()),
                    _ => None,
                },
                _ => None,
            };
            if let Some(h) = head {
                if !self.channels.contains(&h) {
                    let _ = self.lookup(&h, self.global, at);
                }
            }
            map.push(self.event(v.clone(), at)?);
        }
        let ext = crate::proc::ExternalLts { id: self.fresh_id(), lts, map };
        Ok(Rc::new(P::External(Rc::new(ext), 0)))
    }

    /// Event ids of a set value.
    pub(crate) fn event_set(&mut self, v: &Value, at: TextRange) -> R<Rc<[u32]>> {
        let Value::Set(s) = v else {
            return Err(err(Code::Type, at, format!("expected a set of events, found {}", v.kind_name())));
        };
        let mut ids: Vec<u32> = s.iter().map(|e| self.event(e.clone(), at)).collect::<R<_>>()?;
        ids.sort_unstable();
        ids.dedup();
        Ok(ids.into())
    }

    /// All events of all channels (`Events`).
    pub(crate) fn all_events(&mut self, at: TextRange) -> R<Value> {
        let mut out = BTreeSet::new();
        for c in self.channels.clone() {
            out.extend(self.completions(Value::Ctor(c), at)?);
            self.check_size(out.len(), at)?;
        }
        Ok(Value::Set(Rc::new(out)))
    }
}

fn fixed_len(p: &Pat) -> Option<usize> {
    match p {
        Pat::Seq(ps) => Some(ps.len()),
        Pat::Str(s) => Some(s.chars().count()),
        Pat::Concat(a, b) => Some(fixed_len(a)? + fixed_len(b)?),
        _ => None,
    }
}

fn flatten_dot_pat<'p>(p: &'p Pat, out: &mut Vec<&'p Pat>) {
    match p {
        Pat::Dot(a, b) => {
            flatten_dot_pat(a, out);
            flatten_dot_pat(b, out);
        }
        p => out.push(p),
    }
}

/// How many dotted components a pattern needs.
pub(crate) fn pat_width(p: &Pat) -> usize {
    match p {
        Pat::Dot(a, b) => pat_width(a) + pat_width(b),
        Pat::Double(a, b) => pat_width(a).max(pat_width(b)),
        _ => 1,
    }
}

/// The number of components of a value once nested constructors are opened.
pub(crate) fn value_width(v: &Value) -> usize {
    match v {
        Value::Dot(d) => d.iter().map(value_width).sum(),
        _ => 1,
    }
}

/// The components of a value with nested constructor values opened.
pub(crate) fn flatten_value(v: &Value, out: &mut Vec<Value>) {
    match v {
        Value::Dot(d) => d.iter().for_each(|x| flatten_value(x, out)),
        v => out.push(v.clone()),
    }
}
