//! The CSPm script a `csp` block is read in, as RoboTool's generated
//! script of the semantics checked holds it (RT-7, RT-8): the blocks of the
//! assertion's own file, in file order (`timed csp` blocks in the timed
//! script only), after the library RoboTool's script includes
//! ([`robosim_hir::csp_defs`], shared with the CSPm export: the tock-CSP
//! operators in the timed script, the state helpers and core functions in
//! both) and the sticky arithmetic when no `Instantiations` block replaces
//! the defaults (a generated default only when no block defines the name
//! itself; a library name a block defines again is FDR's error).

use robosim_cspm::{Module, NoNames, TextRange};
use robosim_hir::csp_defs;

use super::Cx;
use crate::untimed::Semantics;

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

/// The script's text, and where each block starts.
pub(crate) struct Script {
    /// The CSPm text.
    pub text: String,
    /// RoboTool's timed script (else its untimed one).
    pub timed: bool,
    /// Where the blocks start in `text` (the library comes first).
    blocks_at: usize,
    /// The library definitions included: (names, text).
    library: Vec<(&'static [&'static str], &'static str)>,
    /// (offset in `text`, offset in the assertion file, block name).
    parts: Vec<(usize, usize, String)>,
}

impl Script {
    /// The script of the assertion file of `cx`.
    pub fn of(cx: &Cx<'_>) -> Script {
        let file_text = cx.file.text(cx.db);
        let mut blocks = String::new();
        let mut parts = Vec::new();
        let timed = cx.semantics == Semantics::Timed;
        // RT-8: `timed csp` blocks exist only in the timed script.
        for b in cx.read.csp_blocks.iter().filter(|b| timed || !b.timed) {
            let Some(r) = b.text_range else { continue };
            let Some(body) = file_text.get(std::ops::Range::<usize>::from(r)) else { continue };
            parts.push((blocks.len(), usize::from(r.start()), b.name.clone()));
            blocks.push_str(body);
            blocks.push('\n');
        }
        let defined = Module::check(&blocks, &NoNames).defined_names();
        let replaced = cx.read.csp_blocks.iter().any(|b| b.name == "Instantiations");
        let mut text = String::new();
        let is_defined = |name: &str| defined.iter().any(|d| d == name);
        let mut library = Vec::new();
        // RoboTool's script includes its library files whatever the
        // blocks define (core_timed_defs.csp's `OneStep(_) = 0`): a block
        // defining one of their names again makes FDR stop on the script
        // (libcspm: "has multiple definitions"), which checking the script
        // then reports.
        for def in csp_defs::definitions(timed) {
            text.push_str(def.text);
            library.push((def.names, def.text));
        }
        for (name, def) in if replaced { &[][..] } else { DEFAULTS } {
            if !is_defined(name) {
                text.push_str(def);
                text.push('\n');
            }
        }
        let shift = text.len();
        text.push_str(&blocks);
        Script {
            text,
            timed,
            blocks_at: shift,
            library,
            parts: parts.into_iter().map(|(s, f, n)| (s + shift, f, n)).collect(),
        }
    }

    /// Whether the blocks, or a library definition they use (directly or
    /// through others), mention `word` (`Events`, `tock`): the library
    /// mentions both, whether a block uses it or not.
    pub fn mentions(&self, word: &str) -> bool {
        self.used().iter().any(|u| super::mentions(u, word))
    }

    /// The blocks' text and the library definitions they use (directly or
    /// through others).
    pub fn used(&self) -> Vec<&str> {
        let mut used = vec![&self.text[self.blocks_at..]];
        let mut left: Vec<_> = self.library.iter().collect();
        loop {
            let before = left.len();
            left.retain(|(names, text)| {
                let is_used = names.iter().any(|n| used.iter().any(|u| super::mentions(u, n)));
                if is_used {
                    used.push(text);
                }
                !is_used
            });
            if left.len() == before {
                break;
            }
        }
        used
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
