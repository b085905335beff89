//! Text edits: what rename, formatting and quick fixes return.

use robosim_syntax::{TextRange, TextSize};

use crate::FileId;

/// Replace `range` (bytes of the current text) with `new_text`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TextEdit {
    /// The range replaced.
    pub range: TextRange,
    /// The replacement.
    pub new_text: String,
}

impl TextEdit {
    /// Inserts `text` at `at`.
    pub fn insert(at: TextSize, text: impl Into<String>) -> TextEdit {
        TextEdit { range: TextRange::empty(at), new_text: text.into() }
    }

    /// Deletes `range`.
    pub fn delete(range: TextRange) -> TextEdit {
        TextEdit { range, new_text: String::new() }
    }

    /// Replaces `range` with `text`.
    pub fn replace(range: TextRange, text: impl Into<String>) -> TextEdit {
        TextEdit { range, new_text: text.into() }
    }
}

/// The edits of one file: sorted by position, not overlapping.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct FileEdit {
    /// The file.
    pub file: FileId,
    /// Its path, as given when it was added.
    pub path: String,
    /// The edits, in increasing order of position, none overlapping.
    pub edits: Vec<TextEdit>,
}

/// Edits to one or more files, applied together.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct SourceChange {
    /// One entry per changed file, sorted by path.
    pub files: Vec<FileEdit>,
}

impl SourceChange {
    /// Whether nothing changes.
    pub fn is_empty(&self) -> bool {
        self.files.iter().all(|f| f.edits.is_empty())
    }

    /// Adds an edit of `file`; [`SourceChange::finish`] sorts them.
    pub(crate) fn push(&mut self, file: FileId, path: &str, edit: TextEdit) {
        match self.files.iter_mut().find(|f| f.file == file) {
            Some(f) => f.edits.push(edit),
            None => self.files.push(FileEdit { file, path: path.to_string(), edits: vec![edit] }),
        }
    }

    /// Sorts files and edits and drops duplicate edits.
    pub(crate) fn finish(mut self) -> SourceChange {
        self.files.sort_by(|a, b| a.path.cmp(&b.path));
        for f in &mut self.files {
            f.edits.sort_by_key(|e| (e.range.start(), e.range.end()));
            f.edits.dedup();
        }
        self.files.retain(|f| !f.edits.is_empty());
        self
    }
}

/// Applies `edits` (sorted, not overlapping, as [`FileEdit::edits`]) to
/// `text`. Edits outside the text or not on character boundaries are
/// skipped rather than panicking.
pub fn apply_edits(text: &str, edits: &[TextEdit]) -> String {
    let mut out = String::with_capacity(text.len());
    let mut at = 0usize;
    for e in edits {
        let (start, end) = (usize::from(e.range.start()), usize::from(e.range.end()));
        if start < at || end > text.len() || !text.is_char_boundary(start) || !text.is_char_boundary(end) {
            continue;
        }
        out.push_str(&text[at..start]);
        out.push_str(&e.new_text);
        at = end;
    }
    out.push_str(&text[at..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_apply_in_order_and_bad_ones_are_skipped() {
        let r = |a: u32, b: u32| TextRange::new(a.into(), b.into());
        let edits = [
            TextEdit::insert(0.into(), "$"),
            TextEdit::replace(r(2, 3), "Z"),
            TextEdit::delete(r(1, 4)),  // overlaps the previous one
            TextEdit::delete(r(5, 99)), // beyond the end
        ];
        assert_eq!(apply_edits("abcde", &edits), "$abZde");
    }
}
