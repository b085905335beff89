//! Diagnostics of a check run, rendered for people (codespan-reporting) and
//! for machines (the JSON contract in the README).

use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity as CsSeverity};
use codespan_reporting::files::SimpleFiles;
use codespan_reporting::term::termcolor::{ColorChoice, StandardStream};
use codespan_reporting::term::{self, Styles, StylesWriter};
use robosim_ide::TextRange;
use serde_json::{json, Value};

use crate::workspace::Workspace;

pub use robosim_ide::Severity;

/// A secondary location that explains a diagnostic.
#[derive(Debug, Clone)]
pub struct Related {
    pub file: usize,
    pub range: TextRange,
    pub message: String,
}

#[derive(Debug, Clone)]
pub struct Diagnostic {
    pub file: usize,
    pub range: TextRange,
    pub severity: Severity,
    pub code: String,
    pub message: String,
    pub related: Vec<Related>,
}

fn json_range(ws: &Workspace, file: usize, range: TextRange) -> Value {
    let f = &ws.files[file];
    let s = f.line_index.line_col(&f.text, range.start());
    let e = f.line_index.line_col(&f.text, range.end());
    json!({
        "start": { "line": s.line, "character": s.col },
        "end": { "line": e.line, "character": e.col },
    })
}

/// The JSON report: `{"files": N, "diagnostics": [...]}`.
pub fn to_json(ws: &Workspace, diags: &[Diagnostic]) -> Value {
    let list: Vec<Value> = diags
        .iter()
        .map(|d| {
            json!({
                "file": ws.files[d.file].path,
                "range": json_range(ws, d.file, d.range),
                "severity": d.severity.as_str(),
                "code": d.code,
                "message": d.message,
                "related": d.related.iter().map(|r| json!({
                    "file": ws.files[r.file].path,
                    "range": json_range(ws, r.file, r.range),
                    "message": r.message,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({ "files": ws.user_files, "diagnostics": list })
}

/// Renders every diagnostic with source excerpts, then a summary line.
pub fn render_human(ws: &Workspace, diags: &[Diagnostic], color: bool) -> std::io::Result<()> {
    let mut files = SimpleFiles::new();
    for f in &ws.files {
        files.add(f.path.clone(), &*f.text);
    }
    let stream = StandardStream::stdout(if color { ColorChoice::Always } else { ColorChoice::Never });
    let mut lock = stream.lock();
    let styles = Styles::default();
    let mut writer = StylesWriter::new(&mut lock, &styles);
    let config = term::Config::default();
    for d in diags {
        let severity = match d.severity {
            Severity::Error => CsSeverity::Error,
            Severity::Warning => CsSeverity::Warning,
            Severity::Info => CsSeverity::Note,
            Severity::Hint => CsSeverity::Help,
        };
        let mut labels = vec![Label::primary(d.file, d.range).with_message(short_label(&d.message))];
        for r in &d.related {
            labels.push(Label::secondary(r.file, r.range).with_message(r.message.clone()));
        }
        let cs =
            CsDiagnostic::new(severity).with_code(d.code.clone()).with_message(d.message.clone()).with_labels(labels);
        term::emit_to_write_style(&mut writer, &config, &files, &cs).map_err(std::io::Error::other)?;
    }
    let errors = diags.iter().filter(|d| d.severity == Severity::Error).count();
    let warnings = diags.iter().filter(|d| d.severity == Severity::Warning).count();
    use std::io::Write;
    writeln!(
        writer,
        "checked {} file{}: {} error{}, {} warning{}",
        ws.user_files,
        plural(ws.user_files),
        errors,
        plural(errors),
        warnings,
        plural(warnings)
    )
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// The part of a message before its first colon, as the label under the
/// excerpt (the full message is the diagnostic's title).
fn short_label(message: &str) -> String {
    match message.split_once(": ") {
        Some((head, _)) if head.len() < message.len() => head.to_string(),
        _ => String::new(),
    }
}
