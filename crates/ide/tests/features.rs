//! Data-driven tests of the semantic editor features: hover, go to
//! definition and references, rename, completion, formatting and quick
//! fixes. Each `test_data/features/FEATURE/NAME.test` file holds one or
//! more model files, each introduced by a line `//- PATH`; lines `//! …`
//! before the first file are directives (`//! rename: a, b` lists the new
//! names to try). `$0` marks the cursor positions (markers are removed
//! before parsing). The output of the feature at each marker is compared
//! with `NAME.test.txt`; refresh the snapshots with
//! `UPDATE_EXPECT=1 cargo test -p robosim-ide --test features` and review
//! the diff.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use robosim_ide::{
    apply_edits, Analysis, AnalysisHost, CompletionKind, Durability, FileId, RuleSet, SourceChange, TextRange, TextSize,
};

const MARKER: &str = "$0";

struct Fixture {
    host: AnalysisHost,
    /// Path, id and text (markers removed) of each file.
    files: Vec<(String, FileId, String)>,
    /// Cursor positions: file index and offset.
    markers: Vec<(usize, TextSize)>,
    directives: Vec<(String, String)>,
}

fn load(path: &Path) -> Fixture {
    let raw = std::fs::read_to_string(path).unwrap();
    let mut directives = Vec::new();
    let mut sections: Vec<(String, String)> = Vec::new();
    for line in raw.split_inclusive('\n') {
        if let Some(p) = line.strip_prefix("//- ") {
            sections.push((p.trim().to_string(), String::new()));
        } else if let Some(last) = sections.last_mut() {
            last.1.push_str(line);
        } else if let Some(d) = line.strip_prefix("//! ") {
            let (k, v) = d.split_once(':').unwrap_or((d, ""));
            directives.push((k.trim().to_string(), v.trim().to_string()));
        }
    }
    assert!(!sections.is_empty(), "{}: no `//- PATH` file", path.display());
    let mut host = AnalysisHost::new(RuleSet::Paper);
    let mut files = Vec::new();
    let mut markers = Vec::new();
    for (i, (p, text)) in sections.into_iter().enumerate() {
        let mut out = String::new();
        let mut rest = text.as_str();
        while let Some(j) = rest.find(MARKER) {
            out.push_str(&rest[..j]);
            markers.push((i, TextSize::of(out.as_str())));
            rest = &rest[j + MARKER.len()..];
        }
        out.push_str(rest);
        let id = host.set_file(&p, out.clone(), None, Durability::LOW);
        files.push((p, id, out));
    }
    Fixture { host, files, markers, directives }
}

fn fixtures(feature: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/features").join(feature);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "test"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fixtures in {}", dir.display());
    files
}

/// Runs `render` on every fixture of `feature` and compares the output
/// with the snapshots. Returns the number of cases (markers or files).
fn check(feature: &str, render: impl Fn(&Fixture, &mut String)) {
    for path in fixtures(feature) {
        let f = load(&path);
        let mut out = String::new();
        render(&f, &mut out);
        let mut snap = path.clone().into_os_string();
        snap.push(".txt");
        expect_test::expect_file![PathBuf::from(snap)].assert_eq(&out);
    }
}

impl Fixture {
    fn analysis(&self) -> Analysis {
        self.host.analysis()
    }

    fn path_of(&self, id: FileId) -> String {
        self.analysis().file_path(id).unwrap()
    }

    fn text_of(&self, id: FileId) -> String {
        self.analysis().file_text(id).unwrap().to_string()
    }

    /// `path:line:col` of an offset (1-based), for reading snapshots.
    fn pos(&self, id: FileId, offset: TextSize) -> String {
        let text = self.text_of(id);
        let lc = self.analysis().line_index(id).unwrap().line_col(&text, offset);
        format!("{}:{}:{}", self.path_of(id), lc.line + 1, lc.col + 1)
    }

    fn range(&self, id: FileId, range: TextRange) -> String {
        let text = self.text_of(id);
        let s = &text[usize::from(range.start())..usize::from(range.end())];
        let s = if s.chars().count() > 50 {
            format!("{}…", s.chars().take(50).collect::<String>())
        } else {
            s.to_string()
        };
        format!("{} {:?}", self.pos(id, range.start()), s.replace('\n', "⏎"))
    }

    /// The line of a marker, with the marker shown.
    fn marker_line(&self, (i, offset): (usize, TextSize)) -> String {
        let text = &self.files[i].2;
        let at = usize::from(offset);
        let start = text[..at].rfind('\n').map_or(0, |j| j + 1);
        let end = text[at..].find('\n').map_or(text.len(), |j| at + j);
        format!("{}{MARKER}{}", &text[start..at], &text[at..end]).trim().to_string()
    }

    fn each_marker(&self, out: &mut String, mut f: impl FnMut(FileId, TextSize, &mut String)) {
        for &m in &self.markers {
            let id = self.files[m.0].1;
            let _ = writeln!(out, "== {} | {}", self.pos(id, m.1), self.marker_line(m));
            f(id, m.1, out);
        }
    }

    fn render_change(&self, change: &SourceChange, out: &mut String) {
        for fe in &change.files {
            let text = self.text_of(fe.file);
            let _ = writeln!(out, "--- {}", fe.path);
            out.push_str(&apply_edits(&text, &fe.edits));
            if !out.ends_with('\n') {
                out.push('\n');
            }
        }
    }
}

#[test]
fn hover() {
    check("hover", |f, out| {
        f.each_marker(out, |id, offset, out| match f.analysis().hover(id, offset).unwrap() {
            // Given the file's diagnostics, the hover is the same.
            h if h
                != f.analysis().hover_with_diagnostics(id, offset, &f.analysis().diagnostics(id).unwrap()).unwrap() =>
            {
                panic!("{}: hover_with_diagnostics differs", f.pos(id, offset))
            }
            Some(h) => {
                let _ = writeln!(out, "range {}\n{}", f.range(id, h.range), h.markdown);
            }
            None => out.push_str("(no hover)\n"),
        })
    });
}

#[test]
fn navigation() {
    check("navigation", |f, out| {
        f.each_marker(out, |id, offset, out| {
            let a = f.analysis();
            match a.goto_definition(id, offset).unwrap() {
                None => out.push_str("definition: (no name)\n"),
                Some((origin, targets)) => {
                    let _ = writeln!(out, "origin {}", f.range(id, origin));
                    if targets.is_empty() {
                        out.push_str("definition: (unresolved)\n");
                    }
                    for t in targets {
                        let _ = writeln!(out, "definition {:?} {} {}", t.kind, t.name, f.range(t.file, t.focus_range));
                    }
                }
            }
            match a.find_references(id, offset, true).unwrap() {
                None => out.push_str("references: none\n"),
                Some(refs) => {
                    for r in refs {
                        let what = if r.is_declaration { "declaration" } else { "reference" };
                        let _ = writeln!(out, "{what} {}", f.range(r.file, r.range));
                    }
                }
            }
            // Without the declaration: the same minus the first.
            let with = a.find_references(id, offset, true).unwrap().unwrap_or_default();
            let without = a.find_references(id, offset, false).unwrap().unwrap_or_default();
            assert_eq!(without.len() + usize::from(!with.is_empty()), with.len());
        })
    });
}

#[test]
fn rename() {
    check("rename", |f, out| {
        let names: Vec<String> = f
            .directives
            .iter()
            .filter(|(k, _)| k == "rename")
            .flat_map(|(_, v)| v.split(',').map(|s| s.trim().to_string()))
            .collect();
        f.each_marker(out, |id, offset, out| {
            let a = f.analysis();
            match a.prepare_rename(id, offset).unwrap() {
                Ok((range, placeholder)) => {
                    let _ = writeln!(out, "prepare: {} placeholder {placeholder:?}", f.range(id, range));
                }
                Err(e) => {
                    let _ = writeln!(out, "prepare: refused: {e}");
                }
            }
            for name in &names {
                match a.rename(id, offset, name).unwrap() {
                    Ok(change) if change.is_empty() => {
                        let _ = writeln!(out, "rename to {name:?}: no change");
                    }
                    Ok(change) => {
                        let _ = writeln!(out, "rename to {name:?}:");
                        f.render_change(&change, out);
                    }
                    Err(e) => {
                        let _ = writeln!(out, "rename to {name:?}: refused: {e}");
                    }
                }
            }
        })
    });
}

#[test]
fn completion() {
    check("completion", |f, out| {
        f.each_marker(out, |id, offset, out| {
            let items = f.analysis().completions(id, offset).unwrap();
            if items.is_empty() {
                out.push_str("(none)\n");
            }
            for c in items {
                let kind = match c.kind {
                    CompletionKind::Keyword => "keyword".to_string(),
                    CompletionKind::Symbol(k) => format!("{k:?}"),
                };
                let detail = c.detail.map(|d| format!(" — {d}")).unwrap_or_default();
                let _ = writeln!(out, "{} ({kind}){detail}", c.label);
                assert_eq!(c.range.end(), offset);
            }
        })
    });
}

#[test]
fn formatting() {
    check("formatting", |f, out| {
        for (path, id, text) in &f.files {
            let _ = writeln!(out, "== {path}");
            match f.analysis().format(*id).unwrap() {
                Ok(edits) if edits.is_empty() => out.push_str("(already formatted)\n"),
                Ok(edits) => {
                    let result = apply_edits(text, &edits);
                    let _ = writeln!(out, "{} edit(s)", edits.len());
                    out.push_str(&result);
                    // Formatting the result again changes nothing.
                    let mut host = AnalysisHost::default();
                    let again = host.set_file(path, result, None, Durability::LOW);
                    assert_eq!(host.analysis().format(again).unwrap(), Ok(Vec::new()), "{path}: not idempotent");
                }
                Err(e) => {
                    let _ = writeln!(out, "error: {e}");
                }
            }
        }
    });
}

#[test]
fn code_actions() {
    check("actions", |f, out| {
        for (path, id, text) in &f.files {
            let a = f.analysis();
            let all = TextRange::up_to(TextSize::of(text.as_str()));
            for action in a.code_actions(*id, all).unwrap() {
                let d = &action.diagnostic;
                let _ = writeln!(out, "== {path}: {} {} {}", d.code, f.range(*id, d.range), d.message);
                let _ = writeln!(out, "action: {}", action.title);
                f.render_change(&action.change, out);
                // The fix removes the diagnostic it is for.
                let mut host = AnalysisHost::new(RuleSet::Paper);
                for (p, _, t) in &f.files {
                    let fe = action.change.files.iter().find(|fe| &fe.path == p);
                    let t = fe.map(|fe| apply_edits(t, &fe.edits)).unwrap_or_else(|| t.clone());
                    host.set_file(p, t, None, Durability::LOW);
                }
                let after = host.file_id(path).unwrap();
                let remaining = host.analysis().diagnostics(after).unwrap();
                let same = |r: &&robosim_ide::Diagnostic| r.code == d.code && r.message == d.message;
                let before = a.diagnostics(*id).unwrap().iter().filter(same).count();
                let still = remaining.iter().filter(same).count() >= before;
                let _ = writeln!(
                    out,
                    "after: {}",
                    if remaining.is_empty() {
                        "no diagnostics".to_string()
                    } else {
                        remaining.iter().map(|r| format!("{} {}", r.code, r.message)).collect::<Vec<_>>().join("; ")
                    }
                );
                assert!(!still, "{path}: `{}` did not fix {} {}", action.title, d.code, d.message);
            }
        }
    });
}

/// Every feature at every offset of every fixture, and at the end of every
/// prefix of them (text being typed): answers or nothing, never a panic.
#[test]
fn every_feature_at_every_offset() {
    let mut texts: Vec<(String, String)> = Vec::new();
    for feature in ["hover", "navigation", "rename", "completion", "formatting", "actions"] {
        for path in fixtures(feature) {
            let f = load(&path);
            for (p, _, t) in &f.files {
                texts.push((p.clone(), t.clone()));
            }
        }
    }
    for (path, text) in &texts {
        let mut host = AnalysisHost::default();
        let id = host.set_file(path, text.clone(), None, Durability::LOW);
        let a = host.analysis();
        let len = text.len() as u32;
        for o in (0..=len + 2).filter(|o| text.is_char_boundary((*o).min(len) as usize)) {
            let offset = TextSize::from(o);
            a.hover(id, offset).unwrap();
            a.goto_definition(id, offset).unwrap();
            a.find_references(id, offset, true).unwrap();
            let _ = a.prepare_rename(id, offset).unwrap();
            let _ = a.rename(id, offset, "renamed").unwrap();
            a.completions(id, offset).unwrap();
            a.code_actions(id, TextRange::empty(offset.min(TextSize::from(len)))).unwrap();
        }
        let _ = a.format(id).unwrap();
        // Changing an input waits for every snapshot to be dropped.
        drop(a);
        // Being typed: completion at the end of each prefix.
        for cut in (0..text.len()).step_by(7).filter(|c| text.is_char_boundary(*c)) {
            let prefix = &text[..cut];
            let id = host.set_file(path, prefix.to_string(), None, Durability::LOW);
            let a = host.analysis();
            a.completions(id, TextSize::of(prefix)).unwrap();
            a.hover(id, TextSize::of(prefix)).unwrap();
            for assist in a.code_actions(id, TextRange::up_to(TextSize::of(prefix))).unwrap() {
                for fe in &assist.change.files {
                    if fe.file == id {
                        let _ = apply_edits(prefix, &fe.edits);
                    }
                }
            }
        }
    }
}
