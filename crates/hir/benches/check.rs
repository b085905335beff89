//! `check` of the whole of `../shared/corpus` from scratch: parse, resolve
//! and run every rule on all 82 model files (one workspace per project
//! folder, plus the bundled library each time), and the re-check after an
//! edit inside one machine. Run with `cargo bench -p robosim-hir`.

use std::path::{Path, PathBuf};

use robosim_hir::{file_diagnostics, load_workspace, File, RootDatabase, RuleSet};
use robosim_syntax::FileKind;

fn main() {
    divan::main();
}

fn projects() -> Vec<Vec<(String, String)>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    let mut dirs: std::collections::BTreeMap<PathBuf, Vec<(String, String)>> = Default::default();
    let mut stack = vec![root.clone()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else { continue };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if FileKind::from_path(&p).is_some() {
                let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
                dirs.entry(d.clone()).or_default().push((p.to_string_lossy().into_owned(), text));
            }
        }
    }
    dirs.into_values().collect()
}

fn check(db: &mut RootDatabase, files: &[(String, String)]) -> usize {
    let ws = load_workspace(db, files.iter().cloned(), RuleSet::Paper);
    ws.files(db).iter().filter(|f| !f.is_library(db)).map(|f| file_diagnostics(db, ws, *f).len()).sum()
}

#[divan::bench]
fn check_whole_corpus(b: divan::Bencher) {
    let ps = projects();
    if ps.is_empty() {
        eprintln!("../shared/corpus not found");
        return;
    }
    b.bench(|| {
        let mut db = RootDatabase::default();
        ps.iter().map(|p| check(&mut db, p)).sum::<usize>()
    });
}

#[divan::bench]
fn recheck_after_edit_in_largest_project(b: divan::Bencher) {
    let ps = projects();
    let Some(p) = ps.iter().max_by_key(|p| p.iter().map(|(_, t)| t.len()).sum::<usize>()) else { return };
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, p.iter().cloned(), RuleSet::Paper);
    let user: Vec<File> = ws.files(&db).iter().copied().filter(|f| !f.is_library(&db)).collect();
    let target = *user.iter().max_by_key(|f| f.text(&db).len()).unwrap();
    let original = target.text(&db).clone();
    let mut flip = false;
    b.bench_local(move || {
        flip = !flip;
        // Insert or remove a blank line inside the file (positions shift).
        let text = if flip { original.replacen('\n', "\n\n", 1) } else { original.clone() };
        robosim_hir::set_text(&mut db, target, text, None, robosim_hir::Durability::LOW);
        user.iter().map(|f| file_diagnostics(&db, ws, *f).len()).sum::<usize>()
    });
}
