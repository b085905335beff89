//! Reading assertion files (`robosim_hir::assertions`).
//!
//! - Data-driven: each fixture `test_data/assertions/NAME.rsa|NAME.assertions`
//!   is read and rendered, and the rendering must match the snapshot next to
//!   it (`NAME.rsa.txt`, …). After an intended change, refresh them with
//!   `UPDATE_EXPECT=1 cargo test -p robosim-engine --test assertions` and
//!   review the diff.
//! - Every assertion file of `../shared/corpus` and of `examples/` is read:
//!   one declaration per ASSERTION node, none of kind `Other`, no problems.
//! - Every prefix of every fixture is read without panicking.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use robosim_hir::assertions::{
    read_assertions, AssertionFile, AssertionKind, CspLineKind, Override, Problem, SemanticModelName, Value,
};
use robosim_syntax::{parse, FileKind, SyntaxKind, TextRange};

/// Forms of the assertion grammar that `read_assertions` leaves as
/// `AssertionKind::Other` on complete input: none.
const UNMODELLED: &[&str] = &[];

fn fixtures() -> Vec<(PathBuf, FileKind)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/assertions");
    let mut out: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter_map(|p| FileKind::from_path(&p).filter(|k| k.is_assertions()).map(|k| (p, k)))
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(!out.is_empty(), "no fixtures in {}", dir.display());
    out
}

fn read(text: &str, kind: FileKind) -> AssertionFile {
    read_assertions(&parse(text, kind).syntax_node())
}

/// `start..end "covered text"`, the text shortened in the middle when long.
fn at(text: &str, r: TextRange) -> String {
    let (s, e) = (usize::from(r.start()), usize::from(r.end()));
    let covered = text.get(s..e).unwrap_or("<not on a char boundary>");
    let chars: Vec<char> = covered.chars().collect();
    let shown = if chars.len() > 64 {
        let head: String = chars[..40].iter().collect();
        let tail: String = chars[chars.len() - 16..].iter().collect();
        format!("{head}…{tail}")
    } else {
        covered.to_string()
    };
    format!("{s}..{e} {shown:?}")
}

fn path(p: &[String]) -> String {
    if p.is_empty() {
        "<none>".to_string()
    } else {
        p.join("::")
    }
}

fn value(v: &Value) -> String {
    match v {
        Value::Int(n) => format!("Int({n})"),
        Value::Bool(b) => format!("Bool({b})"),
        Value::Other(t) => format!("Other({t:?})"),
    }
}

fn model(m: SemanticModelName) -> String {
    format!("{m:?}")
}

fn problems(out: &mut String, text: &str, ps: &[Problem]) {
    for p in ps {
        let _ = writeln!(out, "    problem {}: {}", at(text, p.range), p.message);
    }
}

/// A readable rendering of everything `read_assertions` returns.
fn render(text: &str, file: &AssertionFile) -> String {
    let mut out = String::new();
    for s in &file.simulations {
        let _ = writeln!(out, "simulation {:?} {}", s.name, at(text, s.name_range));
        let _ = writeln!(out, "    range {}", at(text, s.range));
        let _ = writeln!(out, "    of {} {}", path(&s.of), at(text, s.of_range));
        match (&s.cycle, s.cycle_range) {
            (Some(c), Some(r)) => {
                let _ = writeln!(out, "    cycle {} {}", value(c), at(text, r));
            }
            (c, r) => {
                let _ = writeln!(out, "    cycle {c:?} {r:?}");
            }
        }
        problems(&mut out, text, &s.problems);
    }
    for a in &file.assertions {
        let _ = writeln!(out, "assertion {:?} {}", a.name, at(text, a.name_range));
        let _ = writeln!(out, "    range {}", at(text, a.range));
        let _ = writeln!(out, "    text {:?}", a.text);
        let _ = writeln!(out, "    subject {} {}", path(&a.subject), at(text, a.subject_range));
        let _ = writeln!(
            out,
            "    negated {} timed {:?} model {}{}",
            a.negated,
            a.timed,
            model(a.model),
            a.model_range.map(|r| format!(" {}", at(text, r))).unwrap_or_default()
        );
        let kind = match &a.kind {
            AssertionKind::Refines { other, other_range, model: m }
            | AssertionKind::Equals { other, other_range, model: m } => {
                format!("{} {} {} in {}", a.kind.label(), path(other), at(text, *other_range), model(*m))
            }
            AssertionKind::Reachable { state, state_range, machine, machine_range } => format!(
                "reachable state {} {} machine {} {}",
                path(state),
                at(text, *state_range),
                path(machine),
                at(text, *machine_range)
            ),
            AssertionKind::ClockInitialised { clock, clock_range } => {
                format!("clock-initialised {} {}", path(clock), at(text, *clock_range))
            }
            AssertionKind::Other(t) => format!("other {t:?}"),
            k => k.label().to_string(),
        };
        let _ = writeln!(out, "    kind {kind}");
        for o in &a.overrides {
            match o {
                Override::Constant { name, name_range, of, of_range, value: v, value_range, range }
                | Override::Parameter { name, name_range, of, of_range, value: v, value_range, range } => {
                    let what = if matches!(o, Override::Constant { .. }) { "constant" } else { "parameter" };
                    let _ = writeln!(out, "    {what} {name:?} {}", at(text, *name_range));
                    let _ = writeln!(out, "        of {} {}", path(of), at(text, *of_range));
                    let _ = writeln!(out, "        value {} {}", value(v), at(text, *value_range));
                    let _ = writeln!(out, "        range {}", at(text, *range));
                }
                Override::CycleDef { of, of_range, value: v, value_range, range } => {
                    let _ = writeln!(out, "    cycleDef of {} {}", path(of), at(text, *of_range));
                    let _ = writeln!(out, "        value {} {}", value(v), at(text, *value_range));
                    let _ = writeln!(out, "        range {}", at(text, *range));
                }
            }
        }
        problems(&mut out, text, &a.problems);
    }
    for b in &file.csp_blocks {
        let _ = writeln!(out, "csp {:?} {}", b.name, at(text, b.name_range));
        let _ = writeln!(out, "    range {}", at(text, b.range));
        let assoc: Vec<_> = b.associated.iter().map(|p| path(p)).collect();
        let _ = writeln!(out, "    timed {} understood {} associated {:?}", b.timed, b.understood, assoc);
        if let Some(r) = b.text_range {
            let _ = writeln!(out, "    text {}", at(text, r));
        }
        for l in &b.lines {
            let kind = match l.kind {
                CspLineKind::Type => "type",
                CspLineKind::Constant => "constant",
                CspLineKind::Function => "function",
                CspLineKind::Standard => "standard",
                CspLineKind::Other => "other",
            };
            let _ = writeln!(out, "    {kind:<8} {}", at(text, l.range));
        }
        problems(&mut out, text, &b.problems);
    }
    let inst = &file.instantiations;
    for (name, lo, hi, r) in &inst.types {
        let _ = writeln!(out, "nametype {name} = {lo}..{hi} {}", at(text, *r));
    }
    for (name, v, r) in &inst.constants {
        let _ = writeln!(out, "constant {name} = {} {}", value(v), at(text, *r));
    }
    for f in &inst.functions {
        let _ = writeln!(out, "function {}{:?} = {:?} {}", f.name, f.params, f.body, at(text, f.range));
    }
    for t in &inst.type_instantiations {
        let _ = writeln!(out, "instantiate {} as {:?} {}", path(&t.primitive), t.ty, at(text, t.range));
    }
    for s in &file.skipped {
        let _ = writeln!(out, "skipped {}: {}", at(text, s.range), s.message);
    }
    out
}

#[test]
fn fixtures_match_snapshots() {
    for (p, kind) in fixtures() {
        let text = std::fs::read_to_string(&p).unwrap();
        let rendered = render(&text, &read(&text, kind));
        let mut snap = p.clone().into_os_string();
        snap.push(".txt");
        expect_test::expect_file![PathBuf::from(snap)].assert_eq(&rendered);
    }
}

#[test]
fn every_prefix_of_every_fixture_is_read_without_panicking() {
    for (p, kind) in fixtures() {
        let text = std::fs::read_to_string(&p).unwrap();
        for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
            let prefix = &text[..end];
            let file = read(prefix, kind);
            let nodes = count_assertion_nodes(prefix, kind);
            assert_eq!(file.assertions.len(), nodes, "{}: prefix of {end} bytes", p.display());
            for r in all_ranges(&file) {
                assert!(usize::from(r.end()) <= prefix.len(), "{}: prefix of {end} bytes: range {r:?}", p.display());
            }
        }
    }
}

#[test]
fn queries() {
    let text = "simulation S of M { cycleDef cycle == 2 }\n\
                assertion A : S is schedulable with cycleDef of S set to 3\n\
                csp Instantiations csp-begin\nnametype core_nat = {0..2}\nnametype nat = {0..3}\nconst_M_k = 4\ncsp-end\n";
    let file = read(text, FileKind::SimAssertions);
    assert_eq!(file.simulation("S").and_then(|s| s.cycle.clone()), Some(Value::Int(2)));
    assert_eq!(file.assertion("A").map(|a| a.kind.label()), Some("schedulable"));
    assert_eq!(file.assertion("A").map(|a| a.overrides[0].range()).map(|r| &text[r]), Some("cycleDef of S set to 3"));
    assert_eq!(file.instantiations.type_bounds("nat"), Some((0, 3)));
    assert_eq!(file.instantiations.type_bounds("int"), None);
    assert_eq!(file.instantiations.constant("const_M_k"), Some(&Value::Int(4)));
    let (_, _, _, r) = &file.instantiations.types[0];
    assert_eq!(file.csp_block_containing(*r).map(|b| b.name.as_str()), Some("Instantiations"));
    assert!(file.csp_block("Instantiations").is_some_and(|b| b.understood && !b.timed));
    assert_eq!(file.problems().count(), 0);
}

fn count_assertion_nodes(text: &str, kind: FileKind) -> usize {
    parse(text, kind).syntax_node().descendants().filter(|n| n.kind() == SyntaxKind::ASSERTION).count()
}

fn all_ranges(file: &AssertionFile) -> Vec<TextRange> {
    let mut out = Vec::new();
    for s in &file.simulations {
        out.extend([s.name_range, s.range, s.of_range]);
        out.extend(s.cycle_range);
    }
    for a in &file.assertions {
        out.extend([a.name_range, a.range, a.subject_range]);
        out.extend(a.model_range);
        out.extend(a.overrides.iter().map(Override::range));
    }
    for b in &file.csp_blocks {
        out.extend([b.name_range, b.range]);
        out.extend(b.text_range);
        out.extend(b.lines.iter().map(|l| l.range));
    }
    out.extend(file.problems().map(|p| p.range));
    out
}

fn assertion_files(dir: &Path, out: &mut Vec<(PathBuf, FileKind)>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            assertion_files(&p, out);
        } else if let Some(kind) = FileKind::from_path(&p).filter(|k| k.is_assertions()) {
            out.push((p, kind));
        }
    }
}

#[test]
fn corpus_and_examples_are_read_completely() {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let corpus = manifest.join("../../../shared/corpus");
    let examples = manifest.join("../../examples");
    assert!(corpus.is_dir(), "the corpus must be at {} (../shared beside the project)", corpus.display());
    assert!(examples.is_dir(), "examples/ must be at {}", examples.display());
    let mut files = Vec::new();
    assertion_files(&corpus, &mut files);
    let from_corpus = files.len();
    assertion_files(&examples, &mut files);
    assert!(from_corpus >= 13, "expected the corpus's 13 `.assertions` files, found {from_corpus}");
    assert!(files.len() > from_corpus, "no assertion files under examples/");

    let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
    let (mut sims, mut blocks, mut understood, mut skipped) = (0, 0, 0, 0);
    let mut failures = Vec::new();
    for (p, kind) in &files {
        let bytes = std::fs::read(p).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let file = read(&text, *kind);
        let shown = p.display();
        let nodes = count_assertion_nodes(&text, *kind);
        if file.assertions.len() != nodes {
            failures.push(format!("{shown}: {} assertions read for {nodes} ASSERTION nodes", file.assertions.len()));
        }
        for a in &file.assertions {
            let negated = if a.negated { "not " } else { "" };
            let model = match &a.kind {
                AssertionKind::Refines { model, .. } | AssertionKind::Equals { model, .. } => format!(" [{model:?}]"),
                _ => String::new(),
            };
            *kinds.entry(format!("{negated}{}{model}", a.kind.label())).or_default() += 1;
            if let AssertionKind::Other(t) = &a.kind {
                if !UNMODELLED.iter().any(|form| a.text.contains(form)) {
                    failures.push(format!("{shown}: assertion {} not modelled: {t:?} in {:?}", a.name, a.text));
                }
            }
            for pr in &a.problems {
                failures.push(format!("{shown}: assertion {}: {}", a.name, pr.message));
            }
        }
        for s in &file.simulations {
            sims += 1;
            for pr in &s.problems {
                failures.push(format!("{shown}: simulation {}: {}", s.name, pr.message));
            }
        }
        blocks += file.csp_blocks.len();
        understood += file.csp_blocks.iter().filter(|b| b.understood).count();
        skipped += file.skipped.len();
    }
    println!("{} assertion files ({from_corpus} in the corpus)", files.len());
    println!("assertions per kind:");
    for (k, n) in &kinds {
        println!("  {n:>4}  {k}");
    }
    println!("{sims} simulations, {blocks} csp blocks ({understood} understood), {skipped} skipped items");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
