//! Snapshots of the lowered model (`robosim_hir::model`): a fixture with
//! every construct the back ends translate, and the examples. Refresh with
//! `UPDATE_EXPECT=1 cargo test -p robosim-hir --test model`.

use expect_test::{expect, expect_file};
use robosim_hir::model::{file_model, render};
use robosim_hir::{load_workspace, RootDatabase, RuleSet};

/// The model of each non-library file of `files`, rendered.
fn models(files: Vec<(String, String)>) -> String {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, files, RuleSet::Paper);
    let mut out = String::new();
    for &f in ws.files(&db) {
        if f.is_library(&db) || f.kind(&db).is_assertions() {
            continue;
        }
        out += &format!("# {}\n", f.path(&db));
        out += &render(&db, file_model(&db, ws, f));
    }
    out
}

fn example(dir: &str) -> String {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/");
    let mut paths: Vec<_> = std::fs::read_dir(format!("{root}{dir}"))
        .expect("example directory")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "rct" || x == "rst"))
        .collect();
    paths.sort();
    let files = paths
        .iter()
        .map(|p| {
            let name = p.strip_prefix(root).expect("under examples").display().to_string();
            (name, std::fs::read_to_string(p).expect("readable"))
        })
        .collect();
    models(files)
}

#[test]
fn fixture_with_every_construct() {
    let text = r#"
enumeration Colour { red green }
datatype Pos { x : nat y : nat }
interface I { var shared : int event ping : nat }
interface Ops { moveOp(speed : nat) }
robotic platform RP { provides Ops uses I }
stm M {
  requires Ops uses I
  const k : nat = 2
  var x : nat = k + 1, c : Colour = Colour::red, p : nat * nat, s : Set(nat)
  clock C
  event go : boolean
  initial i
  state S {
    entry x = 1 ; go!true
    during wait([1, 2))
    exit #C
    initial j
    state T {}
    transition u { from j to T }
  }
  junction J
  final F
  transition t0 { from i to S }
  transition t1 { from S to J trigger ping?x #C condition since(C) >= k /\ x in {1, 2} action if x > 0 then moveOp(x) else skip end <{3} }
  transition t2 { from J to F condition else action (p[1] = 2 ; s = union(s, {x})) }
}
operation Op(n : nat) {
  var y : int
  initial i
  final f
  transition t { from i to f action y = -n ; wait(n) }
}
controller C {
  uses I
  sref m = M
  opref op = Op
  connection m on ping to C on ping (_async)
}
module Mod {
  rref rp = RP
  cref c = C
  connection rp on ping to c on ping [mult]
}
function twice(n : nat) : nat {
  precondition n < 10
  postcondition result == 2 * n
}
stm Ranges { var r : Set(nat) = {1 to 3} initial i final f transition t { from i to f } }
"#;
    expect![[r#"
        # m.rct
        enumeration Colour {red, green}
        datatype Pos {x: nat, y: nat}
        interface I @67..116
          var shared: int
          event ping: nat
        interface Ops @117..154
          operation moveOp(speed: nat)
        platform RP @155..198
          provides Ops -> m.rct#3
          uses I -> m.rct#2
        stm M @199..789
          requires Ops -> m.rct#3
          uses I -> m.rct#2
          const k: nat = 2
          var x: nat = (k Add 1)
          var c: Colour = Colour::red
          var p: nat*nat
          var s: Set(nat)
          clock C
          event go: bool
          literals 2 1 1 1 2 1 2 0 3 1 2
          initial i @367..368
          state S @377..378
            entry x = 1; go!true
            during wait([1, 2))
            exit #C
            initial j @455..456
            state T @467..468
            transition u @487..488: j -> T
          junction J @520..521
          final F @530..531
          transition t0 @545..547: i -> S
          transition t1 @577..579: S -> J trigger ping?x #C [((since(C) Ge k) And (x In {1, 2}))] / (if (x Gt 0) then moveOp(x) else skip end) <{3}
          transition t2 @716..718: J -> F [else] / (p[1] = 2; s = union?(s, {x}))
        operation Op(n: nat) @790..906
          var y: int
          initial i @838..839
          final f @848..849
          transition t @863..864: i -> f / y = (Neg n); wait(n)
        controller C @907..1006
          uses I -> m.rct#2
          sref m = M -> m.rct#5
          opref op = Op -> m.rct#6
          connection m.ping (machine 0) -> C.ping (this) async @962..1004
        module Mod @1007..1093
          rref rp = RP -> m.rct#4
          cref c = C -> m.rct#7
          connection rp.ping (platform 0) -> c.ping (controller 0) mult @1050..1091
        function twice(n: nat): nat @1094..1181
          precondition (n Lt 10)
          postcondition (result Eq (2 Mul n))
        stm Ranges @1182..1271
          var r: Set(nat) = {1 to 3}
          literals 1 3
          initial i @1231..1232
          final f @1239..1240
          transition t @1252..1253: i -> f
    "#]]
    .assert_eq(&models(vec![("m.rct".into(), text.into())]));
}

#[test]
fn examples() {
    for dir in ["paper", "square", "lawnmower"] {
        expect_file![format!("model/{dir}.txt")].assert_eq(&example(dir));
    }
}

/// Every expression of the guards and actions of `text`'s machines, with
/// the type the type checker gives it.
fn typed_expressions(text: &str) -> String {
    use robosim_hir::model::{Expr, Item};
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, vec![("m.rct".to_string(), text.to_string())], RuleSet::Paper);
    let file = *ws.files(&db).iter().find(|f| !f.is_library(&db)).expect("the model");
    let mut out = String::new();
    let mut show = |e: &Expr| {
        let ty = e.ty.as_ref().map_or("-".to_string(), |t| t.to_string());
        out += &format!("{:?} : {ty}\n", &text[e.range]);
    };
    for (_, item) in &file_model(&db, ws, file).items {
        let Item::Machine(m) = item else { continue };
        for t in &m.region.transitions {
            if let Some(g) = t.condition.as_ref().and_then(|c| c.expr.as_ref()) {
                g.walk(&mut show);
            }
        }
    }
    out
}

#[test]
fn expression_types_come_from_the_type_checker() {
    let text = r#"
enumeration Colour { red green }
stm M {
  var x : nat, c : Colour, b : boolean, r : real
  initial i
  state S {}
  transition t0 { from i to S condition x + 1 > 2 /\ c == Colour::green \/ not b /\ r * 2.0 < x }
}
"#;
    expect![[r#"
        "x + 1 > 2 /\\ c == Colour::green \\/ not b /\\ r * 2.0 < x" : boolean
        "x + 1 > 2 /\\ c == Colour::green" : boolean
        "x + 1 > 2" : boolean
        "x + 1" : nat
        "x" : nat
        "1" : nat
        "2" : nat
        "c == Colour::green" : boolean
        "c" : Colour
        "Colour::green" : Colour
        "not b /\\ r * 2.0 < x" : boolean
        "not b" : boolean
        "b" : boolean
        "r * 2.0 < x" : boolean
        "r * 2.0" : real
        "r" : real
        "2.0" : real
        "x" : nat
    "#]]
    .assert_eq(&typed_expressions(text));
}

#[test]
fn robosim_machines_and_malformed_input() {
    let text = r#"
interface Ins { event obstacle : boolean }
interface Outs { move(v : nat) }
stm SimM {
  cycleDef cycle == 1
  input context { uses Ins }
  output context { requires Outs }
  var seen : boolean
  initial i
  state S { entry $move(1) ; exec }
  junction j
  transition t0 { from i to S }
  transition t1 { from S to j exec condition $obstacle?seen /\ seen }
  transition t2 { from j to S condition
"#;
    expect![[r#"
        # m.rst
        interface Ins @1..43
          event obstacle: bool
        interface Outs @44..76
          operation move(v: nat)
        stm SimM @77..397
          cycle Feasible(1)
          var seen: bool
          input context
            uses Ins -> m.rst#0
          output context
            requires Outs -> m.rst#1
          literals 1 1
          initial i @205..206
          state S @215..216
            entry $move(1); exec
          junction j @254..255
          transition t0 @269..271: i -> S
          transition t1 @301..303: S -> j exec [($obstacle?seen And seen)]
          transition t2 @371..373: j -> S []
    "#]]
    .assert_eq(&models(vec![("m.rst".into(), text.into())]));
}

/// Every model of `../shared/corpus` (one workspace per folder of model
/// files) lowers without a panic, each top-level element into its model.
#[test]
fn every_corpus_model_lowers() {
    use robosim_hir::defs::file_defs;
    use robosim_hir::model::Item;
    use std::path::{Path, PathBuf};
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    let is_model = |p: &Path| p.extension().is_some_and(|x| x == "rct" || x == "rst");
    let mut dirs = std::collections::BTreeSet::new();
    let mut stack = vec![root.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("the corpus").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if is_model(&p) {
                dirs.insert(d.clone());
            }
        }
    }
    let (mut machines, mut controllers, mut modules) = (0, 0, 0);
    for dir in dirs {
        let mut files: Vec<PathBuf> =
            std::fs::read_dir(&dir).expect("a folder").flatten().map(|e| e.path()).filter(|p| is_model(p)).collect();
        files.sort();
        let texts: Vec<(String, String)> = files
            .iter()
            .map(|p| {
                (p.display().to_string(), String::from_utf8_lossy(&std::fs::read(p).expect("readable")).into_owned())
            })
            .collect();
        let mut db = RootDatabase::default();
        let ws = load_workspace(&mut db, texts, RuleSet::Paper);
        for &f in ws.files(&db).iter().filter(|f| !f.is_library(&db)) {
            let model = file_model(&db, ws, f);
            let named = file_defs(&db, f).children(None).count();
            assert_eq!(model.items.len(), named, "{}", f.path(&db));
            for (_, item) in &model.items {
                match item {
                    Item::Machine(_) => machines += 1,
                    Item::Controller(_) => controllers += 1,
                    Item::Module(_) => modules += 1,
                    _ => {}
                }
            }
            render(&db, model);
        }
    }
    // The top-level elements of the corpus (machines inside controllers not counted).
    assert_eq!((machines, controllers, modules), (24, 16, 10));
}

/// What the diagrams read beyond the back ends: the package, machines
/// declared in a module, every action clause of a state in the order
/// written, and the keyword's range for a node without a name.
#[test]
fn what_the_diagrams_read() {
    use robosim_hir::model::{ActionKind, Definition, Item};
    let text = "package a::b\nstm M {\n  initial i\n  state S { exit x = 2 entry x = 1 entry x = 3 }\n  junction\n}\n\
                module Mod {\n  stm Loose { initial k }\n  rref p = P\n  sref s = M\n}\n";
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, vec![("t.rct".to_string(), text.to_string())], RuleSet::Paper);
    let f = ws.files(&db).iter().copied().find(|f| f.path(&db) == "t.rct").expect("the file");
    let m = file_model(&db, ws, f);
    assert_eq!(m.package, ["a", "b"]);
    let at = |r: robosim_hir::TextRange| &text[usize::from(r.start())..usize::from(r.end())];
    let Item::Machine(b) = &m.items[0].1 else { panic!("a machine: {:?}", m.items[0].1) };
    let s = &b.region.nodes[1];
    let clauses: Vec<(ActionKind, &str)> = s.actions.iter().map(|(k, r)| (*k, at(*r))).collect();
    assert_eq!(
        clauses,
        [(ActionKind::Exit, "exit x = 2"), (ActionKind::Entry, "entry x = 1"), (ActionKind::Entry, "entry x = 3")]
    );
    assert_eq!(s.entry.as_ref().map(|a| at(a.range)), Some("entry x = 1"));
    let j = &b.region.nodes[2];
    assert_eq!((j.name.as_str(), at(j.name_range)), ("", "junction"));
    let Item::Module(x) = &m.items[1].1 else { panic!("a module: {:?}", m.items[1].1) };
    let machines: Vec<(&str, bool)> =
        x.machines.iter().map(|i| (i.name.as_str(), matches!(i.def, Definition::Inline(_)))).collect();
    assert_eq!(machines, [("Loose", true), ("s", false)]);
    assert_eq!(x.platforms.len(), 1);
}
