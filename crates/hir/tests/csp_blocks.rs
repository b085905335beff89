//! The csp blocks of assertion files through `file_diagnostics`: parse,
//! name and type errors at their exact ranges in the file; the names a
//! block sees (its file's other blocks, the model's generated names,
//! RoboTool's library) never reported.

use robosim_hir::csp_blocks::{csp_blocks, CspDefKind};
use robosim_hir::{file_diagnostics, load_workspace, RootDatabase, RuleSet, Severity};

const MODEL: &str = "\
package pkg
enumeration Colour { Red Green }
interface I { event e: nat }
stm M {
  requires I
  const k: nat
  initial i
  state S {}
  transition t { from i to S }
}
";

/// `(code, severity, text at the range)` of every csp diagnostic of the
/// assertion file `text`, checked with [`MODEL`].
fn csp_diags(text: &str, rules: RuleSet) -> Vec<(String, Severity, String)> {
    let mut db = RootDatabase::default();
    let files = vec![("m.rct".to_owned(), MODEL.to_owned()), ("a.assertions".to_owned(), text.to_owned())];
    let ws = load_workspace(&mut db, files, rules);
    let file = *ws.files(&db).iter().find(|f| f.path(&db) == "a.assertions").unwrap();
    file_diagnostics(&db, ws, file)
        .iter()
        .filter(|d| d.code.starts_with("CSP-"))
        .map(|d| (d.code.clone(), d.severity, text[d.range].to_owned()))
        .collect()
}

fn e(code: &str, at: &str) -> (String, Severity, String) {
    (code.to_owned(), Severity::Error, at.to_owned())
}

#[test]
fn errors_are_at_their_range_in_the_file() {
    let text = "\
csp Spec csp-begin
Spec = a -> Undefined
channel a
csp-end
csp Bad csp-begin
Bad = (a -> STOP
csp-end
csp Typed csp-begin
Typed = 1 + true
csp-end
";
    let got = csp_diags(text, RuleSet::Paper);
    assert_eq!(got, vec![e("CSP-N01", "Undefined"), e("CSP-P01", ""), e("CSP-T01", "true")], "{got:?}");
    // The syntax error (a missing `)`) is at the end of the block's text.
    let end = text.find("Bad = (a -> STOP\n").unwrap() + "Bad = (a -> STOP\n".len();
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, vec![("a.assertions".to_owned(), text.to_owned())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| f.path(&db) == "a.assertions").unwrap();
    let p = file_diagnostics(&db, ws, file).iter().find(|d| d.code == "CSP-P01").unwrap().range;
    assert_eq!((usize::from(p.start()), usize::from(p.end())), (end, end));
}

#[test]
fn csp_errors_are_warnings_under_robotool_rules() {
    let got = csp_diags("csp P csp-begin\nP = Undefined\ncsp-end\n", RuleSet::RoboTool);
    assert_eq!(got, vec![("CSP-N01".to_owned(), Severity::Warning, "Undefined".to_owned())]);
}

#[test]
fn a_block_sees_the_other_blocks_the_library_and_the_model() {
    let text = "\
csp Instantiations csp-begin
nametype core_nat = {0..2}
const_pkg_M_k = 1
channel go
csp-end
csp Spec csp-begin
Timed(OneStep) {
  Spec = StartBy(pkg::M::e.in?x:core_nat -> go -> SKIP, const_pkg_M_k) ; TCHAOS({tock})
  Colours = {pkg_Colour_Red, pkg_Colour_Green}
  W = EndBy(wait(2), 3) [] USTOP [] CRUN({|go, pkg::M::terminate|}) [] pkg::M::O__(0, 1)
  Q(go) = SKIP
}
csp-end
";
    assert_eq!(csp_diags(text, RuleSet::Paper), vec![]);
    // Names RoboTool does not generate are reported: the package prefix
    // is part of every name of an element or type of a package.
    let text = "csp P csp-begin\nP = M::e.in.1 -> pkg_Colour_Blue -> Colour_Red -> STOP\ncsp-end\n";
    let got = csp_diags(text, RuleSet::Paper);
    assert_eq!(got, vec![e("CSP-N01", "M::e"), e("CSP-N01", "pkg_Colour_Blue"), e("CSP-N01", "Colour_Red")]);
}

#[test]
fn block_definitions_are_listed_with_file_ranges() {
    let text = "\
csp A csp-begin
channel c, d : {0..1}
datatype T = X | Y.{0..1}
nametype N = {0..3}
f(0) = 1
f(n) = n
Timed(OneStep) { P = c?x -> STOP }
csp-end
";
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, vec![("a.assertions".to_owned(), text.to_owned())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| f.path(&db) == "a.assertions").unwrap();
    let blocks = csp_blocks(&db, ws, file);
    let defs: Vec<(String, CspDefKind, &str)> =
        blocks.blocks[0].defs.iter().map(|d| (d.name.clone(), d.kind, &text[d.name_range])).collect();
    use CspDefKind::*;
    let want = [
        ("c", Channel),
        ("d", Channel),
        ("T", Datatype),
        ("X", Constructor),
        ("Y", Constructor),
        ("N", Nametype),
        ("f", Function),
        ("P", Value),
    ];
    assert_eq!(defs, want.iter().map(|(n, k)| (n.to_string(), *k, *n)).collect::<Vec<_>>());
    assert!(blocks.blocks[0].problems.is_empty(), "{:?}", blocks.blocks[0].problems);
    let at = blocks.at((text.find("P =").unwrap() as u32).into()).unwrap();
    assert_eq!(at.name, "A");
}
