//! Lexing + parsing (+ dropping the tree) throughput. Inputs: the largest
//! file of the corpus in `../shared/corpus` (an assertion file, mostly one
//! CSP block), its largest RoboChart model, and a generated 10,000-line
//! model. Run with `cargo bench -p robosim-syntax`.

use robosim_syntax::{parse, FileKind};

// The allocator of the `robosim` binary, so that the numbers are those
// users get (a tree is one allocation per distinct node).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use generated::generated_model;
use robosim_test_support::generated;

fn main() {
    divan::main();
}

fn largest_corpus_file(only: Option<FileKind>) -> Option<(String, FileKind)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    let mut best: Option<(u64, std::path::PathBuf)> = None;
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if FileKind::from_path(&p).is_some_and(|k| only.is_none_or(|o| o == k)) {
                let len = e.metadata().map(|m| m.len()).unwrap_or(0);
                if best.as_ref().is_none_or(|(l, _)| len > *l) {
                    best = Some((len, p));
                }
            }
        }
    }
    let (_, p) = best?;
    Some((std::fs::read_to_string(&p).ok()?, FileKind::from_path(&p)?))
}

#[divan::bench]
fn generated_10k_lines(b: divan::Bencher) {
    let text = generated_model(10_000);
    b.counter(divan::counter::BytesCount::of_str(&text)).bench(|| parse(divan::black_box(&text), FileKind::RoboChart));
}

#[divan::bench]
fn largest_corpus_file_parse(b: divan::Bencher) {
    corpus_bench(b, None);
}

#[divan::bench]
fn largest_corpus_model_parse(b: divan::Bencher) {
    corpus_bench(b, Some(FileKind::RoboChart));
}

fn corpus_bench(b: divan::Bencher, only: Option<FileKind>) {
    let Some((text, kind)) = largest_corpus_file(only) else {
        eprintln!("../shared/corpus not found: skipping the corpus benchmark input");
        return;
    };
    b.counter(divan::counter::BytesCount::of_str(&text)).bench(|| parse(divan::black_box(&text), kind));
}

/// A keystroke in the middle of the generated model, as the editor sees
/// it: the new text is reparsed from the previous parse (only the edited
/// machine is parsed again; `robosim_syntax::reparse`).
#[divan::bench]
fn generated_10k_lines_keystroke_reparse(b: divan::Bencher) {
    let text = generated_model(10_000);
    let at = text[text.len() / 2..].find("exit stop()").unwrap() + text.len() / 2;
    let mut typed = text.clone();
    typed.insert(at, 'x');
    let old = parse(&text, FileKind::RoboChart);
    assert!(robosim_syntax::try_reparse(&old, &text, &typed).is_some(), "not incremental");
    b.bench(|| robosim_syntax::reparse(divan::black_box(&old), &text, divan::black_box(&typed)));
}
