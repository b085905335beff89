//! The invariants of docs/architecture.md that the dependency graph
//! carries, read from the crates' manifests: lower layers never use upper
//! ones, the back ends do not depend on each other, only `lsp` knows LSP,
//! and the command line goes through `ide`.

use std::collections::BTreeMap;
use std::path::Path;

/// The `[dependencies]` of every crate of the workspace, by crate folder.
fn dependencies() -> BTreeMap<String, Vec<String>> {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates");
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(&crates).expect("crates/") {
        let dir = entry.expect("a crate folder").path();
        let Ok(manifest) = std::fs::read_to_string(dir.join("Cargo.toml")) else { continue };
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        let mut deps = Vec::new();
        let mut section = "";
        for line in manifest.lines() {
            let line = line.trim();
            if line.starts_with('[') {
                section = line;
                continue;
            }
            if section == "[dependencies]" && !line.is_empty() && !line.starts_with('#') {
                let dep = line.split(['.', '=', ' ']).next().unwrap_or_default();
                deps.push(dep.to_string());
            }
        }
        out.insert(name, deps);
    }
    out
}

/// The crates of ours each crate may depend on: the layers of
/// docs/architecture.md.
const ALLOWED: &[(&str, &[&str])] = &[
    ("syntax", &[]),
    ("stdlib", &[]),
    ("test-support", &[]),
    ("cspm", &[]),
    ("fmt", &["robosim-syntax"]),
    ("hir", &["robosim-syntax", "robosim-stdlib", "robosim-cspm"]),
    ("engine", &["robosim-syntax", "robosim-hir", "robosim-cspm"]),
    ("semantics", &["robosim-syntax", "robosim-hir"]),
    ("diagram", &["robosim-syntax", "robosim-hir"]),
    (
        "ide",
        &[
            "robosim-syntax",
            "robosim-hir",
            "robosim-cspm",
            "robosim-fmt",
            "robosim-engine",
            "robosim-semantics",
            "robosim-diagram",
        ],
    ),
    ("lsp", &["robosim-ide"]),
    ("cli", &["robosim-ide", "robosim-lsp"]),
];

#[test]
fn every_crate_depends_only_on_the_layers_below_it() {
    let deps = dependencies();
    for (name, list) in &deps {
        let allowed = ALLOWED
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("crates/{name} is not in docs/architecture.md's table (add it there and here)"))
            .1;
        for d in list.iter().filter(|d| d.starts_with("robosim-")) {
            assert!(allowed.contains(&d.as_str()), "crates/{name} depends on {d}, which its layer may not use");
        }
    }
    assert!(deps.contains_key("cli") && deps.contains_key("hir"), "{deps:?}");
}

#[test]
fn only_lsp_knows_lsp_and_syntax_knows_no_salsa() {
    for (name, list) in dependencies() {
        if name != "lsp" {
            assert!(
                !list.iter().any(|d| d.contains("lsp-server") || d.contains("lsp-types")),
                "crates/{name}: {list:?}"
            );
        }
        if name == "syntax" {
            assert!(!list.iter().any(|d| d == "salsa"), "crates/syntax depends on salsa");
        }
    }
}
