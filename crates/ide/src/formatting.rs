//! Whole-document formatting with `robosim-fmt`, the formatter of
//! `robosim fmt`, in its canonical style (four spaces, 120 columns), so
//! that the editor and `robosim fmt --check` agree.

use robosim_fmt::{FormatError, Options};
use robosim_hir::{Db, File};
use robosim_syntax::{TextRange, TextSize};

use crate::edit::TextEdit;

/// The edit that formats `file`: none when it is already formatted, one
/// replacing the part that differs otherwise. A file with a syntax error is
/// not formatted: the error says where the first one is.
pub(crate) fn format(db: &dyn Db, file: File) -> Result<Vec<TextEdit>, String> {
    let text = file.text(db);
    let formatted = match robosim_fmt::format(text, file.kind(db), &Options::default()) {
        Ok(f) => f,
        Err(e @ FormatError::Syntax { .. }) => return Err(format!("not formatted: syntax error at {e}")),
        Err(e) => return Err(format!("not formatted: {e}")),
    };
    Ok(minimal_edit(text, &formatted).into_iter().collect())
}

/// One edit turning `old` into `new`: the common prefix and suffix are kept.
fn minimal_edit(old: &str, new: &str) -> Option<TextEdit> {
    if old == new {
        return None;
    }
    let mut prefix = old.bytes().zip(new.bytes()).take_while(|(a, b)| a == b).count();
    while !old.is_char_boundary(prefix) || !new.is_char_boundary(prefix) {
        prefix -= 1;
    }
    let max_suffix = old.len().min(new.len()) - prefix;
    let mut suffix = old.bytes().rev().zip(new.bytes().rev()).take(max_suffix).take_while(|(a, b)| a == b).count();
    while !old.is_char_boundary(old.len() - suffix) || !new.is_char_boundary(new.len() - suffix) {
        suffix -= 1;
    }
    let range = TextRange::new(TextSize::from(prefix as u32), TextSize::from((old.len() - suffix) as u32));
    Some(TextEdit::replace(range, &new[prefix..new.len() - suffix]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::apply_edits;

    #[test]
    fn the_edit_covers_only_what_differs() {
        for (old, new) in [
            ("a  b", "a b"),
            ("", "x\n"),
            ("x\n", ""),
            ("aa", "aaa"),
            ("été  x", "été x"),
            ("\u{e9}\u{e8}", "\u{e9}\u{e9}\u{e8}"),
        ] {
            let e = minimal_edit(old, new).unwrap();
            assert_eq!(apply_edits(old, std::slice::from_ref(&e)), new, "{old:?} → {new:?}: {e:?}");
        }
        assert_eq!(minimal_edit("same", "same"), None);
        let e = minimal_edit("a  b", "a b").unwrap();
        assert_eq!(e.range, TextRange::new(2.into(), 3.into()));
    }
}
