//! Diagnostics of one file, as the semantic model reports them.

use robosim_hir::{Db, File, Severity, Workspace};
use robosim_syntax::{TextRange, TextSize};

use crate::FileId;

/// A problem on a byte range of a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// Where, in bytes.
    pub range: TextRange,
    /// How serious.
    pub severity: Severity,
    /// The stable code (`SYN-01`, …).
    pub code: String,
    /// What is wrong.
    pub message: String,
    /// Other locations that explain it, possibly in other files.
    pub related: Vec<RelatedInfo>,
}

/// A secondary location of a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct RelatedInfo {
    /// The file of the location.
    pub file: FileId,
    /// Its path, as given when the file was added.
    pub path: String,
    /// The range in that file.
    pub range: TextRange,
    /// What is there.
    pub message: String,
}

impl Diagnostic {
    /// Whether this is a syntax diagnostic (`SYN-…`), recomputed with every
    /// parse, as opposed to one of the semantic rules.
    pub fn is_syntax(&self) -> bool {
        self.code.starts_with("SYN-")
    }
}

/// One change of a text: `delete` (in the text before the change) replaced
/// by `insert_len` bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Edit {
    /// The range replaced, in the text before this edit.
    pub delete: TextRange,
    /// The length of the replacement.
    pub insert_len: TextSize,
}

/// Where `range` of a text is after `edits` (in order), or `None` when an
/// edit touched it.
pub fn map_range(mut range: TextRange, edits: &[Edit]) -> Option<TextRange> {
    for e in edits {
        if range.end() <= e.delete.start() {
            continue;
        }
        if range.start() >= e.delete.end() {
            // After the edit: moved by its change in length.
            let start = u32::from(range.start()) - u32::from(e.delete.len()) + u32::from(e.insert_len);
            range = TextRange::at(start.into(), range.len());
            continue;
        }
        return None;
    }
    Some(range)
}

/// The semantic diagnostics of an older version of a file, moved along
/// with the `edits` made since (`file` is that file, for related
/// locations in it). Diagnostics whose range an edit touched are dropped.
/// This is what an editor does with markers while it waits for a check;
/// the check's own result replaces it when it arrives.
pub fn carry_over(diags: &[Diagnostic], file: FileId, edits: &[Edit]) -> Vec<Diagnostic> {
    diags
        .iter()
        .filter(|d| !d.is_syntax())
        .filter_map(|d| {
            let range = map_range(d.range, edits)?;
            let related = d
                .related
                .iter()
                .filter_map(|r| {
                    if r.file != file {
                        return Some(r.clone());
                    }
                    Some(RelatedInfo { range: map_range(r.range, edits)?, ..r.clone() })
                })
                .collect();
            Some(Diagnostic { range, related, ..d.clone() })
        })
        .collect()
}

/// Syntax diagnostics only: what a parse finds, without the semantic
/// rules, as `file_diagnostics` reports them.
pub(crate) fn syntax_diagnostics(db: &dyn Db, file: File) -> Vec<Diagnostic> {
    if file.is_library(db) {
        return Vec::new();
    }
    robosim_hir::parse(db, file)
        .errors()
        .iter()
        .map(|e| Diagnostic {
            range: e.range,
            severity: match e.severity {
                robosim_syntax::Severity::Error => Severity::Error,
                robosim_syntax::Severity::Warning => Severity::Warning,
            },
            code: e.code().to_string(),
            message: e.message.clone(),
            related: Vec::new(),
        })
        .collect()
}

pub(crate) fn diagnostics(db: &dyn Db, workspace: Workspace, file: File) -> Vec<Diagnostic> {
    // The library is ours and checked by its own tests; reporting on it
    // would only confuse users who cannot edit it.
    if file.is_library(db) {
        return Vec::new();
    }
    robosim_hir::file_diagnostics(db, workspace, file)
        .iter()
        .map(|d| Diagnostic {
            range: d.range,
            severity: d.severity,
            code: d.code.clone(),
            message: d.message.clone(),
            related: d
                .related
                .iter()
                .map(|r| RelatedInfo {
                    file: FileId(r.file),
                    path: r.file.path(db).clone(),
                    range: r.range,
                    message: r.message.clone(),
                })
                .collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(a: u32, b: u32) -> TextRange {
        TextRange::new(a.into(), b.into())
    }

    #[test]
    fn ranges_move_with_edits() {
        // Insert 3 bytes at 10, then delete 12..14.
        let edits =
            [Edit { delete: r(10, 10), insert_len: 3.into() }, Edit { delete: r(12, 14), insert_len: 0.into() }];
        assert_eq!(map_range(r(2, 5), &edits), Some(r(2, 5)));
        assert_eq!(map_range(r(5, 10), &edits), Some(r(5, 10)));
        assert_eq!(map_range(r(20, 25), &edits), Some(r(21, 26)));
        // Touched by an edit: gone.
        assert_eq!(map_range(r(9, 11), &edits), None);
        assert_eq!(map_range(r(8, 12), &edits), None);
    }
}
