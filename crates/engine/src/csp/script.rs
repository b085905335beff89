//! The CSPm script a `csp` block is read in, as RoboTool's generated
//! script holds it (RT-7): the blocks of the assertion's own file, in file
//! order, after the library definitions RoboTool's script includes and
//! blocks use (`LSeq` for `core_string`, the sticky arithmetic when no
//! `Instantiations` block replaces the defaults), each written here from
//! its meaning and added only when no block defines the name itself.

use robosim_cspm::{Module, NoNames, TextRange};

use super::Cx;

/// Library definitions: (name, CSPm text).
const LIBRARY: &[(&str, &str)] = &[
    // Sequences of at most `n` elements of `X` (`core_string` is `LSeq(Char, 2)`).
    ("LSeq", "LSeq(X, n) = if n <= 0 then {<>} else union({<>}, { <x>^s | x <- X, s <- LSeq(X, n - 1) })"),
    // The same without repeated elements.
    (
        "ILSeq",
        "ILSeq(X, n) = if n <= 0 then {<>} else union({<>}, { <x>^s | x <- X, s <- ILSeq(diff(X, {x}), n - 1) })",
    ),
    // RT-6: a divisor of 0 counts as 1.
    ("no_zero_div", "no_zero_div(x) = if x == 0 then 1 else x"),
];

/// RT-5's sticky arithmetic, part of the generated defaults that an
/// `Instantiations` block replaces: a result outside `T` keeps the left
/// operand.
const DEFAULTS: &[(&str, &str)] = &[
    ("Plus", "Plus(a, b, T) = if member(a + b, T) then a + b else a"),
    ("Minus", "Minus(a, b, T) = if member(a - b, T) then a - b else a"),
    ("Mult", "Mult(a, b, T) = if member(a * b, T) then a * b else a"),
    ("Div", "Div(a, b, T) = if member(a / b, T) then a / b else a"),
    ("Modulus", "Modulus(a, b, T) = if member(a % b, T) then a % b else a"),
    ("Neg", "Neg(a, T) = if member(-a, T) then -a else a"),
];

/// RoboTool's tock-CSP library names, which this bridge does not define
/// (their exact definitions are RoboTool's): an unresolved one is said to
/// be unsupported, not unknown.
pub(crate) const TOCK_LIBRARY: &[&str] = &[
    "StartBy",
    "EndBy",
    "Deadline",
    "EDeadline",
    "TimedInterrupt",
    "CRUN",
    "TRUN",
    "USTOP",
    "TCHAOS",
    "SHARE_WAIT",
    "wait",
];

/// The script's text, and where each block starts.
pub(crate) struct Script {
    /// The CSPm text.
    pub text: String,
    /// (offset in `text`, offset in the assertion file, block name).
    parts: Vec<(usize, usize, String)>,
}

impl Script {
    /// The script of the assertion file of `cx`.
    pub fn of(cx: &Cx<'_>) -> Script {
        let file_text = cx.file.text(cx.db);
        let mut blocks = String::new();
        let mut parts = Vec::new();
        for b in &cx.read.csp_blocks {
            let Some(r) = b.text_range else { continue };
            let Some(body) = file_text.get(std::ops::Range::<usize>::from(r)) else { continue };
            parts.push((blocks.len(), usize::from(r.start()), b.name.clone()));
            blocks.push_str(body);
            blocks.push('\n');
        }
        let defined = Module::check(&blocks, &NoNames).defined_names();
        let replaced = cx.read.csp_blocks.iter().any(|b| b.name == "Instantiations");
        let mut text = String::new();
        for (name, def) in LIBRARY.iter().chain(if replaced { &[][..] } else { DEFAULTS }) {
            if !defined.iter().any(|d| d == name) {
                text.push_str(def);
                text.push('\n');
            }
        }
        let shift = text.len();
        text.push_str(&blocks);
        Script { text, parts: parts.into_iter().map(|(s, f, n)| (s + shift, f, n)).collect() }
    }

    /// Where `range` of the script is: `in `csp` block `B` at line N` (a
    /// line of the assertion file), or RoboTool's library.
    pub fn locate(&self, cx: &Cx<'_>, range: TextRange) -> String {
        let at = usize::from(range.start());
        let Some((start, in_file, name)) = self.parts.iter().rev().find(|(s, ..)| *s <= at) else {
            return "in the library definitions RoboTool's script includes".into();
        };
        let offset = in_file + (at - start);
        let file_text = cx.file.text(cx.db);
        let line = file_text.get(..offset).map_or(0, |t| t.matches('\n').count()) + 1;
        format!("in `csp` block `{name}` at line {line}")
    }
}
