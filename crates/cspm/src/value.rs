//! CSPm values. Sets are ordered sets, strings are sequences of
//! characters, dotted values (`c.1.A.2`) are flat lists whose head is a
//! channel or a datatype constructor. Functions and processes compare by
//! identity.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::rc::Rc;

/// A function or process value: compared, ordered and hashed by identity.
#[derive(Debug)]
pub struct Opaque<T> {
    pub(crate) id: u64,
    pub(crate) inner: Rc<T>,
}

impl<T> Clone for Opaque<T> {
    fn clone(&self) -> Self {
        Opaque { id: self.id, inner: self.inner.clone() }
    }
}

impl<T> PartialEq for Opaque<T> {
    fn eq(&self, o: &Self) -> bool {
        self.id == o.id
    }
}
impl<T> Eq for Opaque<T> {}
impl<T> PartialOrd for Opaque<T> {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl<T> Ord for Opaque<T> {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.id.cmp(&o.id)
    }
}
impl<T> std::hash::Hash for Opaque<T> {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.id.hash(h)
    }
}

/// A CSPm value.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Value {
    /// An integer.
    Int(i64),
    /// A boolean.
    Bool(bool),
    /// A character.
    Char(char),
    /// A tuple.
    Tuple(Rc<[Value]>),
    /// A sequence (strings are sequences of characters).
    Seq(Rc<[Value]>),
    /// A finite set.
    Set(Rc<BTreeSet<Value>>),
    /// The set of all integers (`Int`): membership only.
    Ints,
    /// A finite map (FDR's `mapFromList`, `(| k => v |)`), ordered by key.
    Map(Rc<BTreeMap<Value, Value>>),
    /// A channel or datatype constructor with no fields given.
    Ctor(Rc<str>),
    /// A dotted value: a constructor or channel and its fields, or plain
    /// values joined by `.`.
    Dot(Rc<[Value]>),
    /// A function (user-defined, lambda or built-in).
    Func(Opaque<crate::eval::Function>),
    /// A process.
    Proc(Opaque<crate::proc::P>),
}

impl Value {
    pub(crate) fn set(items: impl IntoIterator<Item = Value>) -> Value {
        Value::Set(Rc::new(items.into_iter().collect()))
    }

    pub(crate) fn kind_name(&self) -> &'static str {
        match self {
            Value::Int(_) => "an integer",
            Value::Bool(_) => "a boolean",
            Value::Char(_) => "a character",
            Value::Tuple(_) => "a tuple",
            Value::Seq(_) => "a sequence",
            Value::Set(_) | Value::Ints => "a set",
            Value::Map(_) => "a map",
            Value::Ctor(_) | Value::Dot(_) => "a dotted value",
            Value::Func(_) => "a function",
            Value::Proc(_) => "a process",
        }
    }
}

fn list(
    f: &mut fmt::Formatter<'_>,
    open: &str,
    items: impl Iterator<Item = impl fmt::Display>,
    close: &str,
) -> fmt::Result {
    f.write_str(open)?;
    for (i, v) in items.enumerate() {
        if i > 0 {
            f.write_str(", ")?;
        }
        write!(f, "{v}")?;
    }
    f.write_str(close)
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(i) => write!(f, "{i}"),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Char(c) => write!(f, "{c:?}"),
            Value::Tuple(vs) => list(f, "(", vs.iter(), ")"),
            Value::Seq(vs) if !vs.is_empty() && vs.iter().all(|v| matches!(v, Value::Char(_))) => {
                let s: String =
                    vs.iter().filter_map(|v| if let Value::Char(c) = v { Some(*c) } else { None }).collect();
                write!(f, "{s:?}")
            }
            Value::Seq(vs) => list(f, "<", vs.iter(), ">"),
            Value::Set(vs) => list(f, "{", vs.iter(), "}"),
            Value::Ints => f.write_str("Int"),
            // FDR prints `(| k => v, … |)`.
            Value::Map(m) if m.is_empty() => f.write_str("(| |)"),
            Value::Map(m) => {
                f.write_str("(| ")?;
                for (i, (k, v)) in m.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{k} => {v}")?;
                }
                f.write_str(" |)")
            }
            Value::Ctor(n) => f.write_str(n),
            Value::Dot(vs) => {
                for (i, v) in vs.iter().enumerate() {
                    if i > 0 {
                        f.write_str(".")?;
                    }
                    match v {
                        Value::Dot(_) | Value::Ctor(_) | Value::Int(_) | Value::Bool(_) | Value::Char(_) => {
                            write!(f, "{v}")?
                        }
                        _ => write!(f, "{v}")?,
                    }
                }
                Ok(())
            }
            Value::Func(_) => f.write_str("<function>"),
            Value::Proc(_) => f.write_str("<process>"),
        }
    }
}
