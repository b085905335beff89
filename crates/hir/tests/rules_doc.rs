//! `docs/rules.md` lists every rule of the catalogue as implemented; it is
//! generated from `codes::RULES` so the two cannot drift. Refresh with
//! `UPDATE_EXPECT=1 cargo test -p robosim-hir --test rules_doc`.

use robosim_hir::codes::RULES;

#[test]
fn rules_doc_is_current() {
    let mut s = String::from(
        "# Diagnostic codes\n\nEvery rule `robosim check` and the language server report, with its severity under the two rule sets (`--rules paper`, the default, and `--rules robotool`). Codes are those of the well-formedness catalogue; `RS:` rules are the paper's, `RC:` rules RoboChart's, and the others RoboTool's unnamed checks and our additions. This file is generated from `crates/hir/src/codes.rs` by `cargo test -p robosim-hir --test rules_doc`.\n\n| Code | paper | robotool | Rule |\n|---|---|---|---|\n",
    );
    for r in RULES {
        s.push_str(&format!("| `{}` | {} | {} | {} |\n", r.code, r.paper.as_str(), r.robotool.as_str(), r.summary));
    }
    expect_test::expect_file!["../../../docs/rules.md"].assert_eq(&s);
}
