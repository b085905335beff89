//! The two back ends agree on what a model is (issue 16, item 3): for every
//! example and every model of `../shared/corpus` and `../shared/reference`,
//! the native engine's lowering ([`inspect_element`]) and the CSPm export
//! (the text `robosim csp` writes, parsed and evaluated with our CSPm
//! engine) see the same elements, the same visible events with the same
//! values, the same constants with the same values, the same bounded
//! number types and the same periods.
//!
//! Where they disagree and the export is the side that is wrong (checked
//! against RoboTool's generated CSPm and `robotool-facts.md`), the case is
//! listed in [`KNOWN`] with its reason: the test fails when a listed
//! disagreement goes away (remove it then) or a new one appears.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Duration;

use robosim_cspm::{Evaluator, Limits, Module, NoNames, Value};
use robosim_engine::lower::{inspect_element, DomainDefaults, ElementView};
use robosim_hir::cycle::Feasibility;
use robosim_hir::defs::DefKind;
use robosim_hir::index::{file_summary, ItemLoc};

use robosim_test_support::inputs;

/// Known disagreements, each checked against RoboTool's generated CSPm
/// (`reference/alpha-algorithm/csp-gen`) and `robotool-facts.md`: (kind,
/// workspace and element, what the finding says, which side is wrong and
/// why). A finding is known when its kind is the same and its place and
/// detail contain these. None today: each corpus repository's projects
/// are compared on their own (`inputs::corpus_projects`), and set values are
/// compared as sets.
const KNOWN: &[(&str, &str, &str, &str)] = &[];

/// A module being read: its full name, its first line, and the line ranges
/// of the modules nested in it.
type OpenModule = (String, usize, Vec<(usize, usize)>);

/// Whether `f` is listed in [`KNOWN`], and where.
fn known(f: &Finding) -> Option<usize> {
    KNOWN
        .iter()
        .position(|(kind, place, detail, _)| *kind == f.kind && f.place.contains(place) && f.detail.contains(detail))
}

/// A channel with more events than this is compared by its size.
const EVENT_LIMIT: u64 = 20_000;

/// The model files under `dir`, as (path, text).
fn files_under(dir: &Path) -> Vec<(String, String)> {
    let mut paths = Vec::new();
    inputs::model_files(dir, &mut paths);
    paths
        .iter()
        .filter_map(|p| Some((p.display().to_string(), String::from_utf8_lossy(&std::fs::read(p).ok()?).into_owned())))
        .collect()
}

/// One disagreement between the back ends.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Finding {
    /// What differs: `element`, `event`, `constant`, `domain`, `period`,
    /// `export`.
    kind: &'static str,
    /// The workspace and the element.
    place: String,
    /// What each side says.
    detail: String,
}

/// An element of the workspace, as the engine lowers it.
struct EngineElement {
    /// `pkg::Name`, as the export's header comment writes it.
    path: String,
    view: Result<ElementView, String>,
}

/// What the assertion files' `csp` blocks give the engine besides the
/// number types: the clocks' bound (as `verify` reads it). The number types
/// and the functions without a body are left at RoboTool's defaults (RT-5,
/// RT-2), as in the export of the models alone: a function a block defines
/// (`floor(x) = x`) would change the values of the expressions that widen
/// the number types, for the engine only.
fn defaults(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace) -> DomainDefaults {
    let mut d = DomainDefaults::default();
    for &f in ws.files(db).iter().filter(|f| f.kind(db).is_assertions()) {
        let read = robosim_hir::model::assertion_file(db, f);
        for (name, lo, hi, _) in &read.instantiations.types {
            if name == "core_clock_type" {
                d.set(name, *lo, *hi);
            }
        }
    }
    d
}

/// The elements of the workspace's model files (modules, controllers,
/// machines), each lowered on its own.
fn engine_elements(db: &robosim_hir::RootDatabase, ws: robosim_hir::Workspace) -> Vec<EngineElement> {
    let defaults = defaults(db, ws);
    let mut out = Vec::new();
    for &f in ws.files(db).iter() {
        if f.is_library(db) || f.kind(db).is_assertions() {
            continue;
        }
        let s = file_summary(db, f);
        for (i, it) in s.items.iter().enumerate() {
            if !matches!(it.kind, DefKind::Module | DefKind::Controller | DefKind::StateMachine) {
                continue;
            }
            let loc = ItemLoc { file: f, index: i as u32 };
            let mut path = s.package.clone();
            path.push(it.name.clone());
            let view = inspect_element(db, ws, loc, None, &[], &defaults).map_err(|u| u.message);
            out.push(EngineElement { path: path.join("::"), view });
            // A machine declared inside its controller is an element too
            // (checked on its own, RT-19).
            if it.kind == DefKind::Controller {
                for m in it.members.iter().filter(|m| m.kind == DefKind::StateMachine) {
                    let view = inspect_element(db, ws, loc, Some(&m.name), &[], &defaults).map_err(|u| u.message);
                    let inner = format!("{}::{}", path.join("::"), m.name);
                    out.push(EngineElement { path: inner, view });
                }
            }
        }
    }
    out
}

/// The export of a workspace, evaluated.
struct ExportView<'a> {
    /// Element path → its CSPm module, from each module's header comment.
    modules: BTreeMap<String, String>,
    /// Elements the export refuses (`NOT EXPORTED: state machine P`).
    refused: BTreeSet<String>,
    /// The module's text (between `module` and `endmodule`).
    texts: BTreeMap<String, String>,
    /// The assertion scripts, by file name.
    scripts: BTreeMap<String, String>,
    eval: Evaluator<'a>,
}

/// Exports the workspace (as `robosim csp` does) and evaluates the shared
/// definitions, the instantiations and the model files.
fn export_view<'a>(
    db: &robosim_hir::RootDatabase,
    ws: robosim_hir::Workspace,
    module: &'a mut Option<Module>,
    findings: &mut Vec<Finding>,
    place: &str,
) -> ExportView<'a> {
    let ex = robosim_semantics::export_workspace(db, ws, &robosim_semantics::Options::default());
    let (mut modules, mut texts, mut scripts) = (BTreeMap::new(), BTreeMap::new(), BTreeMap::new());
    let mut refused = BTreeSet::new();
    let (mut all_modules, mut headers) = (BTreeMap::new(), Vec::new());
    let mut text = String::new();
    for f in &ex.files {
        let t = f.text();
        // `AGREE_DUMP=dir` keeps the exported files, to read a finding.
        if let Ok(dir) = std::env::var("AGREE_DUMP") {
            let _ = std::fs::write(format!("{dir}/{}_{}", place.replace('/', "_"), f.name), &t);
        }
        // The assertion scripts (they include the other files).
        if t.contains("\ninclude \"") {
            scripts.insert(f.name.clone(), t);
            continue;
        }
        let lines: Vec<&str> = t.lines().collect();
        // Every module, nested ones by their full name (`pkg::M`: RoboTool
        // puts the elements of package `pkg` inside its module, and a
        // controller's machines inside the controller's), with its text up
        // to its `endmodule`, without the modules nested in it.
        let mut stack: Vec<OpenModule> = Vec::new();
        for (i, l) in lines.iter().enumerate() {
            if let Some(name) = l.trim_start().strip_prefix("module ") {
                let full = match stack.last() {
                    Some((outer, ..)) => format!("{outer}::{}", name.trim()),
                    None => name.trim().to_string(),
                };
                stack.push((full, i, Vec::new()));
            } else if l.trim() == "endmodule" {
                if let Some((full, start, inner)) = stack.pop() {
                    let own = (start..i).filter(|k| !inner.iter().any(|(a, b)| (*a..=*b).contains(k)));
                    all_modules.insert(full, own.map(|k| lines[k]).collect::<Vec<_>>().join("\n"));
                    if let Some((.., outer)) = stack.last_mut() {
                        outer.push((start, i));
                    }
                }
            }
        }
        for l in &lines {
            let Some(header) = l.strip_prefix("-- RoboChart ").or_else(|| l.strip_prefix("-- RoboSim ")) else {
                continue;
            };
            if let Some(path) = ["state machine ", "controller ", "module "].iter().find_map(|k| header.strip_prefix(k))
            {
                headers.push(path.to_string());
            }
        }
        for l in &lines {
            if let Some(what) = l.strip_prefix("-- NOT EXPORTED: ") {
                if let Some(path) =
                    ["state machine ", "controller ", "module "].iter().find_map(|k| what.strip_prefix(k))
                {
                    refused.insert(path.to_string());
                }
            }
        }
        text.push_str(&t);
        text.push('\n');
    }
    // Each exported element's module: `A_B::M::S` for the element
    // `A::B::M::S` of package `A::B` (the package is a prefix of the path).
    for path in headers {
        let parts: Vec<&str> = path.split("::").collect();
        let flat = |ps: &[&str]| ps.join("_");
        let found = (1..parts.len())
            .map(|k| format!("{}::{}", flat(&parts[..k]), parts[k..].join("::")))
            .chain(std::iter::once(path.clone()))
            .find(|m| all_modules.contains_key(m));
        if let Some(m) = found {
            texts.insert(path.clone(), all_modules[&m].clone());
            modules.insert(path, m);
        }
    }
    let m = module.insert(Module::check(&text, &NoNames));
    for d in m.diagnostics().iter().filter(|d| d.severity == robosim_cspm::Severity::Error) {
        findings.push(Finding { kind: "export", place: place.to_string(), detail: format!("CSPm error: {d}") });
    }
    let limits = Limits { time: Duration::from_secs(20), max_set: 200_000, ..Limits::default() };
    ExportView { modules, refused, texts, scripts, eval: Evaluator::new(m, &NoNames, limits) }
}

impl ExportView<'_> {
    /// The events of `expr` (a `{| … |}` set), printed, with the module
    /// prefix `strip` removed.
    fn events(&mut self, expr: &str, strip: &str) -> Result<BTreeSet<String>, String> {
        match self.eval.eval_text(expr).map_err(|d| d.message)? {
            Value::Set(s) => Ok(s.iter().map(|v| v.to_string().replace(strip, "")).collect()),
            v => Err(format!("not a set: {v}")),
        }
    }

    /// The least and greatest value of the set `name`.
    fn range(&mut self, name: &str) -> Result<(i64, i64), String> {
        match self.eval.value(name).map_err(|d| d.message)? {
            Value::Set(s) => {
                let ints: Vec<i64> =
                    s.iter().filter_map(|v| if let Value::Int(i) = v { Some(*i) } else { None }).collect();
                match (ints.iter().min(), ints.iter().max()) {
                    (Some(lo), Some(hi)) if ints.len() == s.len() => Ok((*lo, *hi)),
                    _ => Err(format!("`{name}` is not a set of integers")),
                }
            }
            v => Err(format!("`{name}` is not a set: {v}")),
        }
    }

    /// The channels `module` exports (`entered__`, the states' entry
    /// events, `terminate`, the element's end, RoboTool's
    /// `M::terminate`, which the engine's LTS shows as ✓, and a machine's
    /// writes and updates of its required variables, `set_x` and
    /// `set_EXT_x`, which its `D__` hides and refuses, RT-16, aside).
    fn channels(&self, path: &str) -> Vec<String> {
        let Some(text) = self.texts.get(path) else { return Vec::new() };
        // The module's own `exports`, at the indentation of its `module`.
        let indent = text.len() - text.trim_start().len();
        let exports = text
            .split('\n')
            .skip_while(|l| !(l.trim() == "exports" && l.len() - l.trim_start().len() == indent))
            .collect::<Vec<_>>()
            .join("\n");
        let mut out = Vec::new();
        for l in exports.lines() {
            let Some(decl) = l.trim_start().strip_prefix("channel ") else { continue };
            let names = decl.split_once(" : ").map_or(decl, |(n, _)| n);
            let names: Vec<&str> = names.split(',').map(str::trim).collect();
            let shared = |n: &str| {
                n.strip_prefix("set_EXT_")
                    .or_else(|| n.strip_prefix("set_").filter(|v| names.contains(&format!("set_EXT_{v}").as_str())))
                    .is_some()
            };
            out.extend(
                names.iter().filter(|n| **n != "entered__" && **n != "terminate" && !shared(n)).map(|n| n.to_string()),
            );
        }
        out
    }
}

/// An event as both sides can print it: a record's constructor left out
/// (`R_rec.1.true` is the engine's tuple `1.1`), a tuple's brackets too
/// (`(1, 2)` is the engine's `1.2`), booleans as numbers, an
/// enumeration literal written as one of `known` (the engine's
/// `Side_Left` for RoboTool's `pkg_Side_Left`: the same value, see the
/// module documentation), and a set's elements in one order (the engine
/// prints a set of literals in declaration order, FDR sorted by name).
fn normalise(event: &str, known: &BTreeSet<String>) -> String {
    let parts: Vec<String> = top_level(event, '.')
        .into_iter()
        .filter(|c| !c.ends_with("_rec"))
        .map(|c| match c {
            "true" => "1".to_string(),
            "false" => "0".to_string(),
            c if c.starts_with('{') && c.ends_with('}') => {
                let inner = &c[1..c.len() - 1];
                let mut elems: Vec<String> = top_level(inner, ',')
                    .into_iter()
                    .map(str::trim)
                    .filter(|e| !e.is_empty())
                    .map(|e| normalise(e, known))
                    .collect();
                elems.sort();
                format!("{{{}}}", elems.join(", "))
            }
            // A tuple `(a, b)`, RoboTool's one field (`channel receive:
            // InOut.{(x0__,x1__) | …}`), is the engine's `a.b`.
            c if c.starts_with('(') && c.ends_with(')') => top_level(&c[1..c.len() - 1], ',')
                .into_iter()
                .map(|e| normalise(e.trim(), known))
                .collect::<Vec<_>>()
                .join("."),
            c if known.is_empty() || known.contains(c) => c.to_string(),
            c => known.iter().find(|k| c.ends_with(&format!("_{k}"))).cloned().unwrap_or_else(|| c.to_string()),
        })
        .collect();
    parts.join(".")
}

/// `text` split at the occurrences of `sep` outside brackets.
fn top_level(text: &str, sep: char) -> Vec<&str> {
    let (mut out, mut depth, mut start) = (Vec::new(), 0i32, 0);
    for (i, c) in text.char_indices() {
        match c {
            '{' | '(' | '<' => depth += 1,
            '}' | ')' | '>' => depth -= 1,
            c if c == sep && depth == 0 => {
                out.push(&text[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    out.push(&text[start..]);
    out
}

/// The components of an event, those inside its sets and tuples too.
fn atoms(event: &str) -> Vec<String> {
    top_level(event, '.')
        .into_iter()
        .flat_map(|c| {
            let c = c.trim();
            match c.strip_prefix(['{', '(', '<']).and_then(|r| r.strip_suffix(['}', ')', '>'])) {
                Some(inner) => top_level(inner, ',').into_iter().flat_map(atoms).collect(),
                None => vec![c.to_string()],
            }
        })
        .collect()
}

/// Compares the events of each element.
fn compare_events(ex: &mut ExportView<'_>, place: &str, e: &EngineElement, v: &ElementView, out: &mut Vec<Finding>) {
    let module = &ex.modules[&e.path].clone();
    let strip = format!("{module}::");
    let here = format!("{place} {}", e.path);
    if !v.robosim {
        // The export's channels are the engine's, direction aside.
        let engine: BTreeSet<String> =
            v.events.iter().map(|ev| ev.label.split('.').next().unwrap_or_default().to_string()).collect();
        let export: BTreeSet<String> = ex.channels(&e.path).into_iter().collect();
        if engine != export {
            out.push(Finding {
                kind: "alphabet",
                place: here.clone(),
                detail: format!("engine {engine:?}, export {export:?}"),
            });
        }
    }
    for ev in &v.events {
        // RoboSim's registers are global; its call events (`opCall`, RT-19)
        // are the machine module's channels, as RoboChart's events.
        let register = v.robosim && ev.label.starts_with("register");
        let expr = if register { format!("{{| {} |}}", ev.label) } else { format!("{{| {module}::{} |}}", ev.label) };
        let export = match ex.events(&expr, &strip) {
            Ok(s) => s,
            Err(why) => {
                out.push(Finding {
                    kind: "event",
                    place: here.clone(),
                    detail: format!("{}: export: {why}", ev.label),
                });
                continue;
            }
        };
        match ev.events(EVENT_LIMIT) {
            Some(engine) => {
                let engine: BTreeSet<String> = engine.iter().map(|e| normalise(e, &BTreeSet::new())).collect();
                let parts: BTreeSet<String> = engine.iter().flat_map(|e| atoms(e)).collect();
                let export: BTreeSet<String> = export.iter().map(|e| normalise(e, &parts)).collect();
                if engine != export {
                    let only_engine: Vec<_> = engine.difference(&export).take(4).collect();
                    let only_export: Vec<_> = export.difference(&engine).take(4).collect();
                    out.push(Finding {
                        kind: "event",
                        place: here.clone(),
                        detail: format!(
                            "{}: {} vs {} values; engine only {only_engine:?}; export only {only_export:?}",
                            ev.label,
                            engine.len(),
                            export.len()
                        ),
                    });
                }
            }
            None => {
                let n: u64 = ev.fields.iter().map(|p| p.dom().size().max(1)).product();
                if n != export.len() as u64 {
                    out.push(Finding {
                        kind: "event",
                        place: here.clone(),
                        detail: format!("{}: {n} vs {} values", ev.label, export.len()),
                    });
                }
            }
        }
    }
}

/// The parameters of the process `name` as `module` defines it
/// (`D__(id__, cycle, PI, lv)`).
fn params(text: &str, name: &str) -> Vec<String> {
    let Some(line) = text.lines().find(|l| l.trim_start().starts_with(&format!("{name}("))) else { return Vec::new() };
    let rest = &line.trim_start()[name.len() + 1..];
    let close = rest.find(')').unwrap_or(0);
    rest[..close].split(',').map(|p| p.trim().to_string()).filter(|p| !p.is_empty()).collect()
}

/// The arguments of the first call `callee(…)` in `text`, split at the
/// top-level commas.
fn call_args(text: &str, callee: &str) -> Option<Vec<String>> {
    let at = text.find(&format!("{callee}("))? + callee.len() + 1;
    let (mut depth, mut args, mut cur) = (0i32, Vec::new(), String::new());
    for c in text[at..].chars() {
        match c {
            '(' | '{' | '<' => depth += 1,
            ')' if depth == 0 => {
                args.push(cur.trim().to_string());
                return Some(args);
            }
            ')' | '}' | '>' => depth -= 1,
            ',' if depth == 0 => {
                args.push(std::mem::take(&mut cur).trim().to_string());
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    None
}

/// Compares the constants: the engine's (instance path, value) against
/// the parameters the export's `D__` takes, each valued by the
/// instantiations (`const_<path>_<k>`), by constant name.
fn compare_constants(ex: &mut ExportView<'_>, here: &str, e: &EngineElement, v: &ElementView, out: &mut Vec<Finding>) {
    let mut ps = params(&ex.texts[&e.path], "D__");
    let skip = if v.robosim { 2 } else { 1 };
    ps.drain(..skip.min(ps.len()));
    let short = |q: &str| q.rsplit("::").next().unwrap_or(q).to_string();
    // By constant name: the values each side uses, printed (the engine's
    // default as its note prints it: `true`, `Mode_Idle`), and whether the
    // engine took RoboTool's default (RT-1).
    let mut engine: BTreeMap<String, (Vec<String>, bool)> = BTreeMap::new();
    for (q, _, shown) in &v.constants {
        let note = v.defaults.iter().find_map(|d| d.strip_prefix(&format!("constant {q} = "))?.strip_suffix(" (RT-1)"));
        let entry = engine.entry(short(q)).or_default();
        entry.0.push(comparable(note.unwrap_or(shown)).replace("true", "1").replace("false", "0"));
        entry.1 |= note.is_some();
    }
    let names: BTreeSet<String> = engine.keys().cloned().collect();
    let mut export: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for p in &ps {
        let (k, global) = match p.strip_prefix("const_") {
            // The longest constant name of the engine's that ends it.
            Some(rest) => {
                let k = names
                    .iter()
                    .filter(|k| rest == k.as_str() || rest.ends_with(&format!("_{k}")))
                    .max_by_key(|k| k.len());
                (k.cloned().unwrap_or_else(|| rest.to_string()), p.clone())
            }
            None => (p.clone(), format!("const_{}_{p}", e.path.replace("::", "_"))),
        };
        let value = match ex.eval.value(&global) {
            Ok(Value::Bool(b)) => (b as i64).to_string(),
            // A record (`R_rec.0.0`) by its fields, as `comparable` writes
            // the engine's.
            Ok(other) => normalise(&other.to_string(), &BTreeSet::new()),
            Err(d) => format!("error: {}", d.message),
        };
        export.entry(k).or_default().push(value);
    }
    for name in names.iter().chain(export.keys()).collect::<BTreeSet<_>>() {
        let (mut e, default) = engine.get(name).cloned().unwrap_or_default();
        let mut x = export.get(name).cloned().unwrap_or_default();
        // The export passes one value per constant it names, the engine
        // has one per machine instance: the same values either way.
        for vs in [&mut e, &mut x] {
            vs.sort();
            vs.dedup();
        }
        // An enumeration literal: RoboTool's `pkg_Mode_Idle` is `Mode_Idle`,
        // also inside a sequence (`<pkg_Mode_Idle>`).
        let literal = |a: &str, b: &str| a == b || b.ends_with(&format!("_{a}"));
        let value = |a: &str, b: &str| match (seq_elems(a), seq_elems(b)) {
            (Some(xs), Some(ys)) => xs.len() == ys.len() && xs.iter().zip(&ys).all(|(x, y)| literal(x, y)),
            _ => literal(a, b),
        };
        let same = e.len() == x.len() && e.iter().zip(&x).all(|(a, b)| value(a, b));
        if !same {
            let default = if default { " (RT-1 default)" } else { "" };
            out.push(Finding {
                kind: "constant",
                place: here.to_string(),
                detail: format!("{name}: engine {e:?}{default}, export {x:?}"),
            });
        }
    }
}

/// The elements of a sequence value `<a, b>`, as printed.
fn seq_elems(v: &str) -> Option<Vec<String>> {
    let inner = v.strip_prefix('<')?.strip_suffix('>')?;
    Some(top_level(inner, ',').into_iter().map(|e| e.trim().to_string()).filter(|e| !e.is_empty()).collect())
}

/// A constant's value as the engine writes it, comparable with the
/// export's: a record `(| x = 0, y = 1 |)` by its fields, `0.1`, as
/// `normalise` writes RoboTool's `R_rec.0.1`.
fn comparable(shown: &str) -> String {
    match shown.strip_prefix("(|").and_then(|r| r.strip_suffix("|)")) {
        Some(fields) => {
            fields.split(',').map(|f| f.split_once('=').map_or(f, |(_, v)| v).trim()).collect::<Vec<_>>().join(".")
        }
        None => shown.to_string(),
    }
}

/// Compares the bounded number types.
fn compare_domains(ex: &mut ExportView<'_>, here: &str, v: &ElementView, out: &mut Vec<Finding>) {
    for (name, dom) in &v.domains {
        let export = ex.range(name);
        if export != Ok((dom.lo, dom.hi)) {
            out.push(Finding {
                kind: "domain",
                place: here.to_string(),
                detail: format!("{name}: engine {{{}..{}}}, export {export:?}", dom.lo, dom.hi),
            });
        }
    }
}

/// The assertion file that makes the export write each RoboSim element's
/// period (`M::D__(0, period, …)`): one deadlock check per element.
fn period_assertions(elements: &[EngineElement]) -> String {
    let mut s = String::new();
    for (i, e) in elements.iter().enumerate() {
        if e.view.as_ref().is_ok_and(|v| v.robosim) {
            s.push_str(&format!("assertion agree_{i} : {} is deadlock-free\n", e.path));
        }
    }
    s
}

/// Compares the period of RoboSim element number `i`.
fn compare_period(
    ex: &mut ExportView<'_>,
    here: &str,
    i: usize,
    e: &EngineElement,
    v: &ElementView,
    out: &mut Vec<Finding>,
) {
    let module = ex.modules[&e.path].clone();
    let script = ex.scripts.get("agree_assertions.csp").cloned().unwrap_or_default();
    let marker = format!("-- assertion agree_{i} :");
    let export = match script.split_once(&marker).map(|(_, rest)| rest.split("\n\n").next().unwrap_or_default()) {
        None => Err("no assertion".to_string()),
        // Refused for want of a period: what the engine says too.
        Some(a) if a.contains("NOT EXPORTED: no positive period satisfies") => Err("infeasible".to_string()),
        Some(a) if a.contains("NOT EXPORTED") => {
            Err(a.lines().find(|l| l.contains("NOT EXPORTED")).unwrap_or(a).to_string())
        }
        Some(a) => match call_args(a, &format!("{module}::D__")).and_then(|args| args.get(1).cloned()) {
            None => Err(format!("no call of {module}::D__ in {a}")),
            Some(arg) => match ex.eval.eval_text(&arg) {
                Ok(Value::Int(p)) => Ok(p),
                other => Err(format!("{other:?}")),
            },
        },
    };
    let engine = match v.period {
        Some(Feasibility::Feasible(p)) => Ok(p as i64),
        Some(Feasibility::Infeasible) => Err("infeasible".to_string()),
        ref other => Err(format!("{other:?}")),
    };
    if engine != export {
        out.push(Finding {
            kind: "period",
            place: here.to_string(),
            detail: format!("engine {engine:?}, export {export:?}"),
        });
    }
}

/// What one workspace gave.
#[derive(Default)]
struct Tally {
    findings: Vec<Finding>,
    /// Elements compared in full.
    compared: usize,
    /// Elements the engine refuses (with a reason), the export refuses,
    /// and machines inside a controller that only the export lists.
    engine_refused: usize,
    export_refused: usize,
    /// Controllers declared inside a module (and their machines), which
    /// the engine lowers only as part of the module.
    inline: usize,
    periods: usize,
}

/// Runs the comparison on one workspace.
fn agree(place: &str, files: Vec<(String, String)>) -> Tally {
    let mut t = Tally::default();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files.clone(), robosim_hir::RuleSet::Paper);
    let elements = engine_elements(&db, ws);
    // The export of the same files and of one assertion per RoboSim
    // element (which widens nothing: it sets no constant).
    // The assertion files are left out: their constant values and `csp`
    // blocks would bound the types for every element in the export, but
    // only for their own checks in the engine.
    let mut with_periods: Vec<(String, String)> =
        files.iter().filter(|(p, _)| !(p.ends_with(".rsa") || p.ends_with(".assertions"))).cloned().collect();
    with_periods.push(("agree.rsa".to_string(), period_assertions(&elements)));
    let mut db2 = robosim_hir::RootDatabase::default();
    let ws2 = robosim_hir::load_workspace(&mut db2, with_periods, robosim_hir::RuleSet::Paper);
    let mut module = None;
    let mut ex = export_view(&db2, ws2, &mut module, &mut t.findings, place);
    // The same elements: exported or refused with a reason.
    let engine: BTreeSet<&str> = elements.iter().map(|e| e.path.as_str()).collect();
    let export: BTreeSet<&str> = ex.modules.keys().chain(ex.refused.iter()).map(String::as_str).collect();
    for p in engine.symmetric_difference(&export) {
        // A controller declared inside a module (and its machines) is
        // lowered by the engine as part of the module only: assertions
        // cannot name it on its own (robosim_hir::target).
        let (parent, _) = p.rsplit_once("::").unwrap_or_default();
        let grandparent = parent.rsplit_once("::").map_or("", |(g, _)| g);
        if !engine.contains(p) && (engine.contains(parent) || engine.contains(grandparent)) {
            t.inline += 1;
            println!("inside its module for the engine: {place} {p}");
            continue;
        }
        let side = if engine.contains(p) { "only the engine" } else { "only the export" };
        t.findings.push(Finding { kind: "element", place: format!("{place} {p}"), detail: format!("seen by {side}") });
    }
    t.export_refused = ex.refused.len();
    for (i, e) in elements.iter().enumerate() {
        let v = match &e.view {
            Ok(v) => v,
            Err(why) => {
                t.engine_refused += 1;
                println!("engine refuses {place} {}: {why}", e.path);
                continue;
            }
        };
        if !ex.modules.contains_key(&e.path) {
            continue;
        }
        t.compared += 1;
        let here = format!("{place} {}", e.path);
        compare_events(&mut ex, place, e, v, &mut t.findings);
        compare_constants(&mut ex, &here, e, v, &mut t.findings);
        compare_domains(&mut ex, &here, v, &mut t.findings);
        if v.robosim {
            t.periods += 1;
            compare_period(&mut ex, &here, i, e, v, &mut t.findings);
        }
    }
    t
}

/// The workspaces: each example, each corpus project, the reference.
fn workspaces() -> Vec<(String, Vec<(String, String)>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let shared = root.join("../shared");
    let mut dirs: Vec<PathBuf> = Vec::new();
    for parent in [root.join("examples"), shared.join("corpus")] {
        let mut ds: Vec<PathBuf> = std::fs::read_dir(&parent)
            .unwrap_or_else(|e| panic!("{}: {e}", parent.display()))
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .collect();
        ds.sort();
        // Each RoboTool project on its own (a corpus repository may hold
        // several, with the same qualified names: MANIFEST.md).
        dirs.extend(ds.iter().flat_map(|d| inputs::corpus_projects(d)));
    }
    dirs.push(shared.join("reference/alpha-algorithm"));
    let shared = shared.join("corpus");
    dirs.into_iter()
        .map(|d| {
            let name = match d.strip_prefix(&shared) {
                Ok(rel) => rel.display().to_string(),
                Err(_) => d.file_name().unwrap().to_string_lossy().into_owned(),
            };
            (name, files_under(&d))
        })
        .collect()
}

#[test]
fn the_engine_and_the_export_agree() {
    let mut all = Vec::new();
    let (mut compared, mut engine_refused, mut export_refused, mut inline, mut periods, mut spaces) =
        (0, 0, 0, 0, 0, 0);
    for (name, files) in workspaces() {
        let t = agree(&name, files);
        spaces += 1;
        compared += t.compared;
        engine_refused += t.engine_refused;
        export_refused += t.export_refused;
        inline += t.inline;
        periods += t.periods;
        all.extend(t.findings);
    }
    let kinds = agree("kinds", vec![("kinds.rct".to_string(), KINDS.to_string())]);
    assert_eq!(kinds.compared, 3, "{:#?}", kinds.findings);
    compared += kinds.compared;
    all.extend(kinds.findings);
    let mut used = vec![false; KNOWN.len()];
    let mut unknown = Vec::new();
    for f in &all {
        match known(f) {
            Some(i) => used[i] = true,
            None => unknown.push(f),
        }
        println!("{:9} {}: {}", f.kind, f.place, f.detail);
    }
    println!(
        "{spaces} workspaces: {compared} elements compared ({periods} periods), {engine_refused} refused by the \
         engine, {export_refused} by the export, {inline} inside their module; {} known disagreements",
        all.len()
    );
    assert!(unknown.is_empty(), "the back ends disagree: {unknown:#?}");
    let stale: Vec<_> = KNOWN.iter().zip(&used).filter(|(_, u)| !**u).map(|(k, _)| k).collect();
    assert!(stale.is_empty(), "known disagreements no longer seen (remove them from KNOWN): {stale:#?}");
    assert!(compared >= 25 && periods >= 6, "{compared} elements, {periods} periods compared");
}

/// A RoboSim module `Mod` around a controller and a machine with the given
/// cycleDefs (`None`: `cycle >= 1`, which admits every period), as in
/// `periods.rs`, whose verdicts follow from the period chosen.
fn cycle_model(module: Option<&str>, controller: Option<&str>, machine: Option<&str>) -> String {
    let cd = |c: Option<&str>| format!("cycleDef {}", c.unwrap_or("cycle >= 1"));
    format!(
        "interface I {{ event i }} interface O {{ op() }}
         stm M {{ {m} input context {{ uses I }} output context {{ requires O }}
           initial i0 state S {{ }} transition t {{ from i0 to S }}
           transition u {{ from S to S exec condition $i action $op() }}
           transition w {{ from S to S exec condition not $i }} }}
         controller C {{ {c} uses I requires O sref m = M
           connection C on i to m on i ( _async ) }}
         module Mod {{ {d} robotic platform P {{ uses I provides O }} cref c = C
           connection P on i to c on i ( _async ) }}\n",
        m = cd(machine),
        c = cd(controller),
        d = cd(module),
    )
}

/// The cycleDefs of a module, its controller and its machine, and the
/// period they give (`None`: no period is feasible).
type CycleCase<'a> = (Option<&'a str>, Option<&'a str>, Option<&'a str>, Option<u64>);

/// The cycle cases of issue 16: each back end takes the least period the
/// cycleDefs of the module, its controller and its machine all admit
/// (`periods.rs` checks the verdicts that follow from it), and refuses a
/// model whose cycleDefs admit none.
#[test]
fn the_back_ends_choose_the_same_period() {
    let gt = Some("cycle > 2");
    let cases: [CycleCase; 7] = [
        (gt, gt, gt, Some(3)),
        (Some("cycle >= 2"), Some("cycle >= 2"), Some("cycle >= 2"), Some(2)),
        (Some("cycle < 5"), Some("cycle < 5"), Some("cycle < 5"), Some(1)),
        (Some("cycle >= 2"), Some("cycle < 5"), Some("cycle % 3 == 0"), Some(3)),
        (Some("cycle >= 2 /\\ cycle < 5 /\\ cycle % 3 == 0"), None, None, Some(3)),
        (None, None, Some("cycle > 3"), Some(4)),
        (Some("cycle >= 3"), None, Some("cycle < 2"), None),
    ];
    for (m, c, s, expected) in cases {
        let text = cycle_model(m, c, s);
        let t = agree("cycles", vec![("m.rst".to_string(), text.clone())]);
        let case = format!("module {m:?}, controller {c:?}, machine {s:?}");
        assert!(t.findings.is_empty(), "{case}: {:#?}", t.findings);
        assert_eq!((t.compared, t.periods), (3, 3), "{case}");
        // The period both sides agreed on is the expected one.
        let mut db = robosim_hir::RootDatabase::default();
        let ws = robosim_hir::load_workspace(&mut db, [("m.rst".to_string(), text)], robosim_hir::RuleSet::Paper);
        let module = engine_elements(&db, ws).into_iter().find(|e| e.path == "Mod").expect("the module");
        let period = module.view.expect("lowered").period;
        match expected {
            Some(p) => assert_eq!(period, Some(Feasibility::Feasible(p)), "{case}"),
            None => assert_eq!(period, Some(Feasibility::Infeasible), "{case}"),
        }
    }
}

/// One model with a constant of each kind and no value, a packaged
/// enumeration, a record, a product and platform operations: the kinds of
/// values the corpus has few of. It is compared
/// with the corpus, in [`the_engine_and_the_export_agree`].
const KINDS: &str = "package kinds
    enumeration Mode { Idle Busy }
    datatype Pos { x : nat y : int }
    interface I { event go : Mode event at : Pos event pair : nat * boolean event ping }
    interface Ops { turn(m : Mode) stop() }
    stm M { uses I requires Ops const k : nat const b : boolean const m : Mode
      var n : nat var v : Mode var q : Pos var r : nat * boolean
      initial i state S { }
      transition t { from i to S }
      transition u { from S to S trigger go?v action turn(v) ; n = n + 3 }
      transition w { from S to S trigger at?q condition b /\\ k == 0 action stop() }
      transition p { from S to S trigger pair?r action ping } }
    controller C { uses I requires Ops sref s = M
      connection C on go to s on go ( _async )
      connection C on at to s on at ( _async )
      connection C on pair to s on pair ( _async )
      connection s on ping to C on ping }
    robotic platform P { uses I provides Ops }
    module Mod { rref p = P cref c = C
      connection p on go to c on go ( _async )
      connection p on at to c on at ( _async )
      connection p on pair to c on pair ( _async )
      connection c on ping to p on ping ( _async ) }\n";
