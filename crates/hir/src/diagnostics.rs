//! Diagnostics as returned values: syntax errors first, then the semantic
//! rules.

use robosim_syntax::{TextRange, TextSize};

use crate::{parse, Db, File, Workspace};

/// How serious a diagnostic is (LSP's severities).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Severity {
    /// Must be fixed: the model is not well formed.
    Error,
    /// Probably a mistake, or rejected by RoboTool.
    Warning,
    /// Worth knowing.
    Info,
    /// A suggestion.
    Hint,
}

impl Severity {
    /// `error`, `warning`, `info` or `hint`.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info => "info",
            Severity::Hint => "hint",
        }
    }
}

/// A secondary location that explains a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Related {
    /// The file of the location.
    pub file: File,
    /// The range in that file.
    pub range: TextRange,
    /// What is there.
    pub message: String,
}

/// One diagnostic on a range of a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// The file it is reported in.
    pub file: File,
    /// Where, in bytes.
    pub range: TextRange,
    /// How serious.
    pub severity: Severity,
    /// The stable code (`SYN-01`, `LNK-01`, `RS:M2`, …).
    pub code: String,
    /// What is wrong.
    pub message: String,
    /// Other locations involved.
    pub related: Vec<Related>,
}

/// Computes the rules of `file` that do not need its types, so that a second
/// thread can run them while another resolves and types the file: the
/// other's [`file_diagnostics`] then finds them done (or waits for them).
pub fn prefetch_rules(db: &dyn Db, workspace: Workspace, file: File) {
    if file.is_library(db) {
        return;
    }
    // Behaviour resolution and typing come first in `file_diagnostics`;
    // these come last, so the two threads start on different work.
    for e in crate::element::element_list(db, file) {
        crate::element_rules::element_rules(db, workspace, *e);
        crate::element_rules::element_cycles(db, workspace, *e);
    }
}

/// Every diagnostic of `file`, sorted by position.
#[salsa::tracked(returns(ref))]
pub fn file_diagnostics(db: &dyn Db, workspace: Workspace, file: File) -> Vec<Diagnostic> {
    let mut out: Vec<Diagnostic> = parse(db, file)
        .errors()
        .iter()
        .map(|e| Diagnostic {
            file,
            range: e.range,
            severity: match e.severity {
                robosim_syntax::Severity::Error => Severity::Error,
                robosim_syntax::Severity::Warning => Severity::Warning,
            },
            code: e.code().to_string(),
            message: e.message.clone(),
            related: Vec::new(),
        })
        .collect();
    if !file.is_library(db) {
        let rules = workspace.rules(db);
        let make = |code: &str, range, message: String, related: Vec<Related>| Diagnostic {
            file,
            range,
            severity: crate::codes::severity(code, rules),
            code: code.to_string(),
            message,
            related,
        };
        // One result per element: an edit elsewhere leaves it valid.
        let reports: Vec<_> = crate::element::file_elements(db, file)
            .iter()
            .map(|(e, at)| (crate::element::element_report(db, workspace, *e), *at))
            .collect();
        if file.kind(db).is_assertions() {
            let body = &crate::body::body_resolution(db, workspace, file).problems;
            let typing = crate::types::type_checks(db, workspace, file);
            let names = crate::assertion_names::assertion_name_problems(db, workspace, file);
            for p in crate::resolve::file_resolution(db, workspace, file)
                .problems
                .iter()
                .chain(body)
                .chain(typing)
                .chain(names)
            {
                out.push(make(p.code, p.range, p.message.clone(), Vec::new()));
            }
        } else {
            // Per element, positions relative to its start: an edit inside
            // one element re-runs that element's resolution and typing
            // only. Each list in the order the file-level queries give.
            let elements: Vec<_> = reports.iter().map(|(r, at)| (&r.problems, *at)).collect();
            for p in crate::resolve::import_problems(db, workspace, file) {
                out.push(make(p.code, p.range, p.message, Vec::new()));
            }
            let lists: [fn(&crate::element::ElementProblems) -> &Vec<_>; 3] =
                [|e| &e.resolution, |e| &e.body, |e| &e.types];
            for list in lists {
                for (e, at) in &elements {
                    for p in list(e) {
                        out.push(make(p.code, p.range + TextSize::from(*at), p.message.clone(), Vec::new()));
                    }
                }
            }
        }
        // The rules run per element, positions relative to the element
        // (or to another element, for related locations): each list in
        // the order the rules give it, element after element.
        let placer = crate::element_rules::Placer::new(db, file);
        let elements: Vec<_> = reports.iter().map(|(r, at)| (&r.cycles, &r.rules, *at)).collect();
        let mut push = |p: &crate::checks::Problem, at: u32| {
            let related = p
                .related
                .iter()
                .map(|(place, m)| Related {
                    file: place.file,
                    range: placer.range(place.file, place.anchor, place.range, at),
                    message: m.clone(),
                })
                .collect();
            out.push(make(p.code, placer.range(file, p.anchor, p.range, at), p.message.clone(), related));
        };
        for (cycles, _, at) in &elements {
            cycles.iter().for_each(|p| push(p, *at));
        }
        crate::element_rules::top_duplicates(db, file).iter().for_each(|p| push(p, 0));
        let lists: [fn(&crate::element_rules::ElementRules) -> &Vec<_>; 3] =
            [|r| &r.checks, |r| &r.robosim, |r| &r.more];
        for list in lists {
            for (_, rules, at) in &elements {
                list(rules).iter().for_each(|p| push(p, *at));
            }
        }
        crate::more_checks::size_checks(db, workspace, file).iter().for_each(|p| push(p, 0));
        if file.kind(db) == robosim_syntax::FileKind::RoboSim {
            // Found per element: a keystroke looks at the edited element only.
            for (r, at) in &reports {
                for d in &r.deadlines {
                    out.push(make(
                        "RS-STMT-02",
                        *d + TextSize::from(*at),
                        "statement deadlines are not part of RoboSim: count cycles with a clock instead".to_string(),
                        Vec::new(),
                    ));
                }
            }
        }
        for b in &crate::csp_blocks::csp_blocks(db, workspace, file).blocks {
            out.extend(b.problems.iter().map(|p| make(p.code, p.range, p.message.clone(), Vec::new())));
        }
    }
    out.sort_by(|a, b| (a.range.start(), a.range.end(), &a.code).cmp(&(b.range.start(), b.range.end(), &b.code)));
    out.dedup_by(|a, b| a.range == b.range && a.code == b.code && a.message == b.message);
    out
}
