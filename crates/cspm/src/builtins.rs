//! FDR's built-in names: processes (`STOP`, `SKIP`, `DIV`, `RUN`, `CHAOS`,
//! `WAIT`, `TSTOP`, `TSKIP`), operators (`prioritise`, `timed_priority`,
//! compressions, which are the identity on the semantics), sets,
//! sequences, maps and types.

use std::collections::{BTreeMap, BTreeSet};
use std::rc::Rc;

use crate::eval::{err, Evaluator, Func, R};
use crate::proc::P;
use crate::{Code, TextRange, Value};

const FUNCTIONS: &[&str] = &[
    "union",
    "inter",
    "diff",
    "Union",
    "Inter",
    "member",
    "card",
    "empty",
    "set",
    "Set",
    "seq",
    "concat",
    "head",
    "tail",
    "length",
    "null",
    "elem",
    "error",
    "show",
    "RUN",
    "CHAOS",
    "prioritise",
    "timed_priority",
    "WAIT",
    "TSTOP",
    "TSKIP",
    "productions",
    "extensions",
    "transpose",
    "dbisim",
    "sbisim",
    "wbisim",
    "diamond",
    "normal",
    "normalise",
    "normalize",
    "explicate",
    "lazyenumerate",
    "chase",
    "chase_nocache",
    "deter",
    "model_compress",
    "tau_loop_factor",
    "lazynorm",
    "prioritise_nocache",
    "loop",
    "mapFromList",
    "mapToList",
    "mapLookup",
    "mapMember",
    "mapUpdate",
    "mapUpdateMultiple",
    "mapDelete",
    "Map",
];

const CONSTANTS: &[&str] = &["STOP", "SKIP", "DIV", "Events", "Int", "Bool", "Proc", "Char", "Event", "emptyMap"];

/// Whether `name` is built in.
pub(crate) fn is_builtin(name: &str) -> bool {
    FUNCTIONS.contains(&name) || CONSTANTS.contains(&name)
}

/// The value of a built-in name, if it is one.
pub(crate) fn value(ev: &mut Evaluator, name: &str) -> Option<Value> {
    let at = TextRange::empty(0.into());
    if let Some(&f) = FUNCTIONS.iter().find(|&&f| f == name) {
        return Some(ev.func(Func::Builtin { name: f, given: Vec::new() }));
    }
    Some(match name {
        "STOP" => ev.proc_value(Rc::new(P::Stop)),
        "SKIP" => ev.proc_value(Rc::new(P::Skip)),
        "DIV" => ev.proc_value(Rc::new(P::Div)),
        "Events" => ev.all_events(at).ok()?,
        "Int" => Value::Ints,
        "Bool" => Value::set([Value::Bool(false), Value::Bool(true)]),
        "emptyMap" => Value::Map(Rc::new(BTreeMap::new())),
        _ => return None,
    })
}

fn set(v: &Value, at: TextRange) -> R<Rc<BTreeSet<Value>>> {
    match v {
        Value::Set(s) => Ok(s.clone()),
        Value::Ints => Err(err(Code::Limit, at, "the set of all integers cannot be enumerated")),
        v => Err(err(Code::Type, at, format!("expected a set, found {}", v.kind_name()))),
    }
}

fn seq(v: &Value, at: TextRange) -> R<Rc<[Value]>> {
    match v {
        Value::Seq(s) => Ok(s.clone()),
        v => Err(err(Code::Type, at, format!("expected a sequence, found {}", v.kind_name()))),
    }
}

fn map(v: &Value, at: TextRange) -> R<Rc<BTreeMap<Value, Value>>> {
    match v {
        Value::Map(m) => Ok(m.clone()),
        v => Err(err(Code::Type, at, format!("expected a map, found {}", v.kind_name()))),
    }
}

/// The pairs `(k, v)` of a sequence of 2-tuples, in order.
fn pairs(v: &Value, at: TextRange) -> R<Vec<(Value, Value)>> {
    seq(v, at)?
        .iter()
        .map(|t| match t {
            Value::Tuple(p) if p.len() == 2 => Ok((p[0].clone(), p[1].clone())),
            t => Err(err(Code::Type, at, format!("expected a pair `(key, value)`, found {}", t.kind_name()))),
        })
        .collect()
}

fn proc(v: &Value, at: TextRange) -> R<Rc<P>> {
    match v {
        Value::Proc(p) => Ok(p.inner.clone()),
        v => Err(err(Code::Type, at, format!("expected a process, found {}", v.kind_name()))),
    }
}

/// Whether every key of `a` is a key of `b` with a value `<=` its value
/// there (libcspm's order on maps: `M.isSubmapOfBy` with `compareValues`).
pub(crate) fn submap(a: &BTreeMap<Value, Value>, b: &BTreeMap<Value, Value>) -> bool {
    a.iter().all(|(k, v)| b.get(k).is_some_and(|w| value_le(v, w)))
}

/// libcspm's partial order on values (`compareValues` giving LT or EQ):
/// numbers, characters, booleans and tuples (lexicographically) by value,
/// sets by inclusion, sequences by prefix, maps as submaps; anything else
/// only when equal.
fn value_le(v: &Value, w: &Value) -> bool {
    match (v, w) {
        _ if v == w => true,
        (Value::Int(_), Value::Int(_))
        | (Value::Char(_), Value::Char(_))
        | (Value::Bool(_), Value::Bool(_))
        | (Value::Tuple(_), Value::Tuple(_)) => v <= w,
        (Value::Set(x), Value::Set(y)) => x.is_subset(y),
        (Value::Seq(x), Value::Seq(y)) => y.starts_with(x),
        (Value::Map(x), Value::Map(y)) => submap(x, y),
        _ => false,
    }
}

/// Applies a built-in function.
pub(crate) fn call(ev: &mut Evaluator, name: &'static str, args: Vec<Value>, at: TextRange) -> R<Value> {
    let arity = match name {
        "union" | "inter" | "diff" | "member" | "elem" | "prioritise" | "prioritise_nocache" => 2,
        "mapLookup" | "mapMember" | "mapUpdateMultiple" | "mapDelete" | "Map" => 2,
        "mapUpdate" => 3,
        _ => 1,
    };
    if args.len() != arity {
        return Err(err(Code::Type, at, format!("`{name}` takes {arity} argument(s), not {}", args.len())));
    }
    let a = &args[0];
    Ok(match name {
        "union" | "inter" | "diff" => {
            if let (Value::Ints, _) | (_, Value::Ints) = (a, &args[1]) {
                return match (name, a, &args[1]) {
                    ("union", _, _) => Ok(Value::Ints),
                    ("inter", Value::Ints, s) | ("inter", s, Value::Ints) => Ok(s.clone()),
                    _ => Err(err(Code::Limit, at, "the set of all integers cannot be enumerated")),
                };
            }
            let (x, y) = (set(a, at)?, set(&args[1], at)?);
            let r: BTreeSet<Value> = match name {
                "union" => x.union(&y).cloned().collect(),
                "inter" => x.intersection(&y).cloned().collect(),
                _ => x.difference(&y).cloned().collect(),
            };
            ev.check_size(r.len(), at)?;
            Value::Set(Rc::new(r))
        }
        "Union" => {
            let mut r = BTreeSet::new();
            for s in set(a, at)?.iter() {
                r.extend(set(s, at)?.iter().cloned());
                ev.check_size(r.len(), at)?;
            }
            Value::Set(Rc::new(r))
        }
        "Inter" => {
            let mut it = set(a, at)?.iter().cloned().collect::<Vec<_>>().into_iter();
            let Some(first) = it.next() else { return Err(err(Code::Runtime, at, "Inter of an empty set")) };
            let mut r = (*set(&first, at)?).clone();
            for s in it {
                let s = set(&s, at)?;
                r.retain(|x| s.contains(x));
            }
            Value::Set(Rc::new(r))
        }
        "member" => match &args[1] {
            Value::Ints => Value::Bool(matches!(a, Value::Int(_))),
            s => Value::Bool(set(s, at)?.contains(a)),
        },
        "card" => Value::Int(set(a, at)?.len() as i64),
        "empty" => Value::Bool(set(a, at)?.is_empty()),
        "set" => Value::set(seq(a, at)?.iter().cloned()),
        "seq" => Value::Seq(set(a, at)?.iter().cloned().collect()),
        "Set" => {
            let s = set(a, at)?;
            if s.len() > 16 || (1usize << s.len()) > ev.limits.max_set {
                return Err(err(Code::Limit, at, "the powerset is too large"));
            }
            let items: Vec<Value> = s.iter().cloned().collect();
            let subsets = (0..1usize << items.len())
                .map(|m| Value::set(items.iter().enumerate().filter(|(i, _)| m >> i & 1 == 1).map(|(_, v)| v.clone())));
            Value::set(subsets)
        }
        "concat" => {
            let mut out = Vec::new();
            for s in seq(a, at)?.iter() {
                out.extend(seq(s, at)?.iter().cloned());
                ev.check_size(out.len(), at)?;
            }
            Value::Seq(out.into())
        }
        "head" => seq(a, at)?.first().cloned().ok_or_else(|| err(Code::Runtime, at, "head of an empty sequence"))?,
        "tail" => {
            let s = seq(a, at)?;
            if s.is_empty() {
                return Err(err(Code::Runtime, at, "tail of an empty sequence"));
            }
            Value::Seq(s[1..].into())
        }
        "length" => Value::Int(seq(a, at)?.len() as i64),
        "null" => Value::Bool(seq(a, at)?.is_empty()),
        "elem" => Value::Bool(seq(&args[1], at)?.contains(a)),
        "error" => return Err(err(Code::Runtime, at, format!("error({a})"))),
        "show" => Value::Seq(a.to_string().chars().map(Value::Char).collect()),
        "RUN" | "CHAOS" => {
            let s = ev.event_set(a, at)?;
            let p = if name == "RUN" { P::Run(s) } else { P::Chaos(s) };
            ev.proc_value(Rc::new(p))
        }
        "loop" => {
            // `loop(P) = P ; loop(P)`: a sequence whose second part is itself.
            let p = proc(a, at)?;
            let key = (ev.value("loop")?, args.clone());
            let call = Rc::new(P::Call(Rc::new(key.clone())));
            let body = Rc::new(P::Seq(p, call.clone()));
            ev.calls.insert(key, body.clone());
            ev.proc_value(body)
        }
        "prioritise" | "prioritise_nocache" | "timed_priority" if ev.limits.traces_only => {
            return Err(err(
                Code::Unsupported,
                at,
                format!("`{name}` in a compilation up to traces (priority depends on more than traces)"),
            ))
        }
        "prioritise" | "prioritise_nocache" => {
            let p = proc(a, at)?;
            let levels: Vec<_> = seq(&args[1], at)?.iter().map(|s| ev.event_set(s, at)).collect::<R<_>>()?;
            ev.proc_value(Rc::new(P::Prioritise(levels.into(), p)))
        }
        "timed_priority" => {
            let p = proc(a, at)?;
            let tock =
                ev.value("tock").map_err(|_| err(Code::Unresolved, at, "`timed_priority` needs a channel `tock`"))?;
            let t = ev.event(tock, at)?;
            ev.proc_value(Rc::new(P::Prioritise(vec![Rc::from([]), Rc::from([t])].into(), p)))
        }
        "TSTOP" | "TSKIP" => {
            let t = ev.event(a.clone(), at)?;
            ev.proc_value(Rc::new(if name == "TSTOP" { P::TStop(t) } else { P::TSkip(t) }))
        }
        "WAIT" => {
            let Value::Int(n) = a else { return Err(err(Code::Type, at, "WAIT takes a number of time units")) };
            let tock = ev.value("tock").map_err(|_| err(Code::Unresolved, at, "`WAIT` needs a channel `tock`"))?;
            let t = ev.event(tock, at)?;
            let p = P::tocks(t, *n, Rc::new(P::TSkip(t)));
            ev.proc_value(p)
        }
        "productions" => Value::set(ev.completions(a.clone(), at)?),
        "extensions" => {
            let skip = match a {
                Value::Dot(x) => x.len(),
                _ => 1,
            };
            let mut out = Vec::new();
            for v in ev.completions(a.clone(), at)? {
                out.push(match v {
                    Value::Dot(y) if y.len() > skip + 1 => Value::Dot(y[skip..].into()),
                    Value::Dot(y) if y.len() == skip + 1 => y[skip].clone(),
                    _ => continue,
                });
            }
            Value::set(out)
        }
        "transpose" => Value::set(set(a, at)?.iter().filter_map(|t| match t {
            Value::Tuple(p) if p.len() == 2 => Some(Value::Tuple(vec![p[1].clone(), p[0].clone()].into())),
            _ => None,
        })),
        // Maps, as libcspm's `BuiltInFunctions.hs` defines them.
        // `mapFromList`: a later pair for the same key wins (Haskell's
        // `Map.fromList`).
        "mapFromList" => Value::Map(Rc::new(pairs(a, at)?.into_iter().collect())),
        // In ascending order of keys.
        "mapToList" => {
            Value::Seq(map(a, at)?.iter().map(|(k, v)| Value::Tuple(vec![k.clone(), v.clone()].into())).collect())
        }
        "mapLookup" => map(a, at)?.get(&args[1]).cloned().ok_or_else(|| {
            err(Code::Runtime, at, format!("mapLookup: the key {} is not in the map's domain", args[1]))
        })?,
        "mapMember" => Value::Bool(map(a, at)?.contains_key(&args[1])),
        "mapUpdate" => {
            let mut m = (*map(a, at)?).clone();
            m.insert(args[1].clone(), args[2].clone());
            Value::Map(Rc::new(m))
        }
        // A `foldr` of inserts: for a key given twice the first pair wins.
        "mapUpdateMultiple" => {
            let mut m = (*map(a, at)?).clone();
            for (k, v) in pairs(&args[1], at)?.into_iter().rev() {
                m.insert(k, v);
            }
            Value::Map(Rc::new(m))
        }
        "mapDelete" => {
            let mut m = (*map(a, at)?).clone();
            m.remove(&args[1]);
            Value::Map(Rc::new(m))
        }
        // Every map whose domain is a subset of `ks` and whose values are
        // in `vs`: (|vs| + 1)^|ks| of them.
        "Map" => {
            let (ks, vs) = (set(a, at)?, set(&args[1], at)?);
            let count = u32::try_from(ks.len())
                .ok()
                .and_then(|n| (vs.len() + 1).checked_pow(n))
                .filter(|&c| c <= ev.limits.max_set)
                .ok_or_else(|| err(Code::Limit, at, "the set of maps is too large"))?;
            let mut maps: Vec<BTreeMap<Value, Value>> = Vec::with_capacity(count);
            maps.push(BTreeMap::new());
            for k in ks.iter() {
                let mut next = Vec::with_capacity(maps.len() * (vs.len() + 1));
                for m in &maps {
                    next.push(m.clone());
                    for v in vs.iter() {
                        let mut with = m.clone();
                        with.insert(k.clone(), v.clone());
                        next.push(with);
                    }
                }
                maps = next;
            }
            Value::set(maps.into_iter().map(|m| Value::Map(Rc::new(m))))
        }
        // Compressions and FDR's other semantics-preserving operators.
        _ => {
            proc(a, at)?;
            a.clone()
        }
    })
}
