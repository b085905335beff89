//! Times the queries an edit triggers on the generated 10,000-line model,
//! one by one, to see where the language server's time goes:
//! `cargo run --release -p robosim-ide --example profile_requests` (also under
//! `perf record`).

use robosim_test_support::generated;

use std::time::Instant;

use robosim_ide::{AnalysisHost, Durability};

fn main() {
    let text = generated::generated_model(10_000);
    let mut host = AnalysisHost::default();
    let file = host.set_file("/bench/generated.rct", text.clone(), None, Durability::LOW);
    let t = Instant::now();
    let n = host.analysis().diagnostics(file).unwrap().len();
    println!("first diagnostics: {:?} ({n} diagnostics)", t.elapsed());
    let at = text.len() / 2;
    let at = text[at..].find("entry move(").map(|i| at + i).unwrap();
    for round in 0..5 {
        let mut edited = text.clone();
        edited.insert_str(at, if round % 2 == 0 { " " } else { "  " });
        let t = Instant::now();
        host.set_file("/bench/generated.rct", edited, None, Durability::LOW);
        let set = t.elapsed();
        let a = host.analysis();
        let t = Instant::now();
        let _ = a.line_index(file).unwrap();
        let li = t.elapsed();
        let t = Instant::now();
        fn count(s: &[robosim_ide::DocumentSymbol]) -> usize {
            s.iter().map(|x| 1 + count(&x.children)).sum()
        }
        let s = count(&a.document_symbols(file).unwrap());
        let sym = t.elapsed();
        let t = Instant::now();
        let n = a.diagnostics(file).unwrap().len();
        let diag = t.elapsed();
        let t = Instant::now();
        let h = a.highlight(file).unwrap().len();
        let hl = t.elapsed();
        println!("set {set:?}  line index {li:?}  symbols(+parse) {sym:?} ({s})  diagnostics {diag:?} ({n})  highlight {hl:?} ({h})");
    }
}
