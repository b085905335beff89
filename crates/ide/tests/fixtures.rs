//! Data-driven tests of the syntax-level features. Every model file in
//! `test_data/` is loaded into a workspace and its `.txt` snapshot holds
//! the output of each feature: syntax diagnostics, document symbols,
//! highlighting, folding, and selection ranges at each `$0` marker (markers
//! are removed before parsing). Semantic diagnostics are left out: they are
//! the semantic model's, tested there, and would tie these snapshots to
//! every new rule. After an intended change, refresh the snapshots with
//! `UPDATE_EXPECT=1 cargo test -p robosim-ide --test fixtures` and review
//! the diff.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use robosim_ide::{AnalysisHost, DocumentSymbol, Durability, FileKind, HlTag, RuleSet, TextRange, TextSize};

const MARKER: &str = "$0";

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| FileKind::from_path(p).is_some())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fixtures in {}", dir.display());
    files
}

/// The text without markers, and the marker offsets.
fn strip_markers(text: &str) -> (String, Vec<TextSize>) {
    let mut out = String::new();
    let mut offsets = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find(MARKER) {
        out.push_str(&rest[..i]);
        offsets.push(TextSize::of(out.as_str()));
        rest = &rest[i + MARKER.len()..];
    }
    out.push_str(rest);
    (out, offsets)
}

fn snippet(text: &str, range: TextRange) -> String {
    let s = &text[usize::from(range.start())..usize::from(range.end())];
    let mut s = s.replace('\n', "⏎");
    if s.chars().count() > 40 {
        s = s.chars().take(20).collect::<String>() + "…" + &s.chars().skip(s.chars().count() - 10).collect::<String>();
    }
    format!("{s:?}")
}

fn r(range: TextRange) -> String {
    format!("{}..{}", u32::from(range.start()), u32::from(range.end()))
}

fn render_symbols(out: &mut String, text: &str, symbols: &[DocumentSymbol], depth: usize) {
    for s in symbols {
        let detail = s.detail.as_ref().map(|d| format!(" [{d}]")).unwrap_or_default();
        let _ = writeln!(
            out,
            "{:indent$}{:?} {}{} {} name {} {}",
            "",
            s.kind,
            s.name,
            detail,
            r(s.full_range),
            r(s.selection_range),
            snippet(text, s.selection_range),
            indent = depth * 2
        );
        render_symbols(out, text, &s.children, depth + 1);
    }
}

fn render(path: &Path) -> String {
    let raw = std::fs::read_to_string(path).unwrap();
    let (text, markers) = strip_markers(&raw);
    let mut host = AnalysisHost::new(RuleSet::Paper);
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let file = host.set_file(&name, text.clone(), None, Durability::LOW);
    let analysis = host.analysis();
    let mut out = String::new();

    out.push_str("== syntax diagnostics\n");
    for d in analysis.diagnostics(file).unwrap().into_iter().filter(|d| d.code.starts_with("SYN-")) {
        let _ = writeln!(
            out,
            "{} {} {} {}: {}",
            d.severity.as_str(),
            d.code,
            r(d.range),
            snippet(&text, d.range),
            d.message
        );
    }

    out.push_str("== document symbols\n");
    render_symbols(&mut out, &text, &analysis.document_symbols(file).unwrap(), 0);

    out.push_str("== highlight\n");
    for h in analysis.highlight(file).unwrap() {
        let tag = match h.tag {
            HlTag::Symbol(k) => format!("{k:?}"),
            t => format!("{t:?}"),
        };
        let decl = if h.declaration { " decl" } else { "" };
        let _ = writeln!(out, "{} {tag}{decl} {}", r(h.range), snippet(&text, h.range));
    }

    out.push_str("== folding\n");
    for f in analysis.folding_ranges(file).unwrap() {
        let _ = writeln!(out, "{} {:?} {}", r(f.range), f.kind, snippet(&text, f.range));
    }

    if !markers.is_empty() {
        out.push_str("== selection\n");
        for (offset, ranges) in markers.iter().zip(analysis.selection_ranges(file, &markers).unwrap()) {
            let _ = writeln!(out, "at {}:", u32::from(*offset));
            for range in ranges {
                let _ = writeln!(out, "  {} {}", r(range), snippet(&text, range));
            }
        }
    }
    out
}

#[test]
fn fixtures_match_snapshots() {
    for path in fixtures() {
        let actual = render(&path);
        let mut snap = path.clone().into_os_string();
        snap.push(".txt");
        expect_test::expect_file![PathBuf::from(snap)].assert_eq(&actual);
    }
}

/// Highlight ranges must be sorted and disjoint: the LSP encoding is
/// relative and cannot express overlaps.
#[test]
fn highlight_ranges_are_sorted_and_disjoint() {
    for path in fixtures() {
        let (text, _) = strip_markers(&std::fs::read_to_string(&path).unwrap());
        let mut host = AnalysisHost::default();
        let file = host.set_file(&path.to_string_lossy(), text, None, Durability::LOW);
        let hl = host.analysis().highlight(file).unwrap();
        for pair in hl.windows(2) {
            assert!(pair[0].range.end() <= pair[1].range.start(), "{}: {:?}", path.display(), pair);
        }
    }
}
