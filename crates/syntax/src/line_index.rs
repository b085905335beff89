//! Byte offsets ↔ (line, UTF-16 column) positions, as LSP and the JSON
//! output of `robosim check` use them.

use crate::TextSize;

/// A 0-based line and a 0-based column counted in UTF-16 code units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LineCol {
    /// 0-based line.
    pub line: u32,
    /// 0-based UTF-16 column.
    pub col: u32,
}

/// Line starts of one text, for position conversion.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineIndex {
    starts: Vec<TextSize>,
    len: TextSize,
}

impl LineIndex {
    /// Indexes `text`. Lines end at `\n`; a `\r` before it belongs to the line.
    pub fn new(text: &str) -> LineIndex {
        let mut starts = vec![TextSize::from(0)];
        for (i, b) in text.bytes().enumerate() {
            if b == b'\n' {
                starts.push(TextSize::from(i as u32 + 1));
            }
        }
        LineIndex { starts, len: TextSize::of(text) }
    }

    /// The position of byte `offset` of `text` (clamped to the text; an
    /// offset inside a character counts as its start).
    pub fn line_col(&self, text: &str, offset: TextSize) -> LineCol {
        let offset = offset.min(self.len);
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = usize::from(self.starts[line]);
        let mut end = usize::from(offset);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let col: usize = text[start..end].chars().map(char::len_utf16).sum();
        LineCol { line: line as u32, col: col as u32 }
    }

    /// The byte offset of a position, or `None` past the end of its line
    /// or of the text.
    pub fn offset(&self, text: &str, pos: LineCol) -> Option<TextSize> {
        let start = *self.starts.get(pos.line as usize)?;
        let end = self.starts.get(pos.line as usize + 1).copied().unwrap_or(self.len);
        let line = &text[usize::from(start)..usize::from(end)];
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            if units >= pos.col {
                return (units == pos.col).then(|| start + TextSize::from(i as u32));
            }
            units += c.len_utf16() as u32;
        }
        (units == pos.col).then_some(end)
    }

    /// Number of lines.
    pub fn line_count(&self) -> usize {
        self.starts.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns() {
        let text = "ab\n\u{e9}\u{1F600}x\r\ny";
        let idx = LineIndex::new(text);
        assert_eq!(idx.line_col(text, 0.into()), LineCol { line: 0, col: 0 });
        assert_eq!(idx.line_col(text, 3.into()), LineCol { line: 1, col: 0 });
        // é is 2 bytes / 1 unit, 😀 is 4 bytes / 2 units.
        assert_eq!(idx.line_col(text, 5.into()), LineCol { line: 1, col: 1 });
        assert_eq!(idx.line_col(text, 9.into()), LineCol { line: 1, col: 3 });
        assert_eq!(idx.line_col(text, 12.into()), LineCol { line: 2, col: 0 });
        assert_eq!(idx.offset(text, LineCol { line: 1, col: 3 }), Some(9.into()));
        assert_eq!(idx.offset(text, LineCol { line: 9, col: 0 }), None);
        for off in 0..=text.len() as u32 {
            if text.is_char_boundary(off as usize) {
                let lc = idx.line_col(text, off.into());
                assert_eq!(idx.offset(text, lc), Some(off.into()), "{off}");
            }
        }
    }
}
