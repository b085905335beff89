//! RoboTool's number domains (robotool-facts RT-5, RT-6), computed once in
//! hir for every back end (`robosim_hir::domains`). Each expected range is
//! worked out by hand from the facts: the model's maximal expressions,
//! evaluated with the sticky arithmetic over the base ranges `{0..2}`,
//! `{-2..2}`, `{-2..2}`.

use robosim_hir::domains::{domains_of, DomainInputs, NumRange, NumberDomains};
use robosim_hir::{load_workspace, RootDatabase, RuleSet};

/// The domains of the project of `model` (one file), or the error's text.
fn domains(model: &str, inputs: &DomainInputs) -> Result<NumberDomains, String> {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, [("m.rct".to_string(), model.to_string())], RuleSet::Paper);
    let f = ws.files(&db).iter().copied().find(|f| !f.is_library(&db)).expect("the model");
    domains_of(&db, ws, f, inputs).clone().map_err(|e| e.message)
}

fn r(lo: i64, hi: i64) -> NumRange {
    NumRange { lo, hi }
}

/// A machine with the declarations `decls` whose one transition does
/// `action`.
fn machine(decls: &str, action: &str) -> String {
    format!(
        "stm M {{ {decls}
           initial i0 state S {{ }}
           transition t {{ from i0 to S action {action} }} }}"
    )
}

fn doms(model: &str) -> ([NumRange; 3], [bool; 3]) {
    let d = domains(model, &DomainInputs::default()).expect("domains");
    (d.domains, d.widened)
}

const BASE: [NumRange; 3] = [NumRange { lo: 0, hi: 2 }, NumRange { lo: -2, hi: 2 }, NumRange { lo: -2, hi: 2 }];

#[test]
fn sticky_arithmetic_keeps_the_left_operand() {
    // `x + 3` over x in {0..2} leaves {0..2} every time: `Plus` keeps x.
    assert_eq!(doms(&machine("var x : nat", "x = x + 3")), (BASE, [false; 3]));
    // `3 + x` keeps 3: the value 3 widens `nat`, and so `int` and `real`.
    assert_eq!(doms(&machine("var x : nat", "x = 3 + x")), ([r(0, 3), r(-2, 3), r(-2, 3)], [true; 3]));
    // The operands of arithmetic widen nothing on their own: `360` in
    // `x * 360` is not a value of the model (x * 360 keeps x).
    assert_eq!(doms(&machine("var x : int", "x = x * 360")), (BASE, [false; 3]));
}

#[test]
fn a_divisor_zero_counts_as_one() {
    // RT-6: `3 / 0` is `3 / 1`, 3, not an error; 3 leaves {-2..2}, so the
    // sticky rule keeps 3 all the same: `real` widens to 3.
    assert_eq!(doms(&machine("var x : real", "x = 3 / 0")), ([r(0, 2), r(-2, 2), r(-2, 3)], [false, false, true]));
    // `2 / y` over y in {-2..2}: -1, -2, 2 (y = 0 counts as 1), 2, 1.
    assert_eq!(doms(&machine("var x : real var y : real", "x = 2 / y")), (BASE, [false; 3]));
    // The reference's `180 / av` (Alpha Algorithm): every quotient leaves
    // {-2..2} (or is 180 / 1), so 180 is kept; with `av`'s own values the
    // list is {-2..2} ∪ {180}: core_real = {-2..180}.
    assert_eq!(
        doms(&machine("const av : real var x : real", "x = 180 / av ; x = av")),
        ([r(0, 2), r(-2, 2), r(-2, 180)], [false, false, true])
    );
    // On its own too: every declared variable, constant and parameter is
    // an entry of its type's base range in RoboTool's lists (`{-2..2}`
    // for `av` and `x`: the reference's bare `{0..2}` entries are one per
    // declaration), so the least value is -2 and there is no gap.
    assert_eq!(
        doms(&machine("const av : real var x : real", "x = 180 / av")),
        ([r(0, 2), r(-2, 2), r(-2, 180)], [false, false, true])
    );
    // With no declaration of the type (an event is none), {180} leaves a
    // gap after {-2..2}: RoboTool's type is not one range, and the
    // computation asks for it.
    let events = format!("interface I {{ event e : real }}\n{}", machine("uses I", "e!(180 / 4)"));
    let err = domains(&events, &DomainInputs::default());
    assert!(err.expect_err("a gap").contains("{-2..2} ∪ {180..180}"));
}

#[test]
fn a_nat_value_widens_int_and_real_an_int_one_real_only() {
    assert_eq!(doms(&machine("var n : nat", "n = 3")), ([r(0, 3), r(-2, 3), r(-2, 3)], [true; 3]));
    assert_eq!(doms(&machine("var i : int", "i = -7")), ([r(0, 2), r(-7, 2), r(-7, 2)], [false, true, true]));
    // A comparison's operands are no values (RoboTool's lists hold no `n`,
    // `alpha` of `n > alpha`, no `1` of `x[1]`: see the module doc); the
    // arguments of a call in it are.
    assert_eq!(
        doms("stm M { var i : int initial i0 state S { } transition t { from i0 to S condition i > -3 } }"),
        (BASE, [false; 3])
    );
    assert_eq!(
        doms(
            "function f(v : int) : int { }
             stm M { var i : int initial i0 state S { } transition t { from i0 to S condition f(-3) > i } }"
        ),
        ([r(0, 2), r(-3, 2), r(-3, 2)], [false, true, true])
    );
}

#[test]
fn an_instantiation_fixes_a_type_and_the_others_compute_with_it() {
    let fixed = DomainInputs { fixed: [None, None, Some(r(-10, 10))], ..DomainInputs::default() };
    let model = machine("var n : nat var x : real", "n = 3 ; x = 50");
    let d = domains(&model, &fixed).expect("domains");
    // `real` stays as given; the literal 50 is a `nat` value (the type
    // checker's type of the literal), so it widens `nat` and `int`.
    assert_eq!(d.domains, [r(0, 50), r(-2, 50), r(-10, 10)]);
    assert_eq!(d.widened, [true, true, false]);
    // Without it, 50 widens `real` too.
    assert_eq!(doms(&model).0, [r(0, 50), r(-2, 50), r(-2, 50)]);
    // Every type fixed: nothing is computed.
    let all = DomainInputs { fixed: [Some(r(0, 1)), Some(r(-1, 1)), Some(r(-1, 1))], ..DomainInputs::default() };
    assert_eq!(domains(&model, &all).expect("domains").domains, [r(0, 1), r(-1, 1), r(-1, 1)]);
}

#[test]
fn a_gap_in_a_stored_type_asks_for_the_range() {
    // A declared `nat` variable is an entry {0..2}: `n = 10` gives {0..10}.
    assert_eq!(doms(&machine("var n : nat", "n = 10")).0, [r(0, 10), r(-2, 10), r(-2, 10)]);
    // With only an event of the type, RoboTool's `core_nat` would be
    // {0..2} ∪ {10..10}: not one range, and values of it are communicated
    // (`real`'s gap does not matter: nothing of that type is stored or
    // communicated).
    let model = format!("interface I {{ event e : nat }}\n{}", machine("uses I", "e!10"));
    let err = domains(&model, &DomainInputs::default()).expect_err("a gap");
    assert_eq!(
        err,
        "RoboTool's `core_nat` here is {0..2} ∪ {10..10} (RT-5), not one range: give it with `nametype core_nat = \
         {a..b}` in a `csp` block of an assertion file"
    );
}

#[test]
fn the_domains_are_the_projects_not_the_elements() {
    // A second machine's value widens the first's types too.
    let model =
        format!("{}\n{}", machine("var x : nat", "x = 1"), machine("var y : int", "y = -5").replace("stm M", "stm N"));
    assert_eq!(doms(&model), ([r(0, 2), r(-5, 2), r(-5, 2)], [false, true, true]));
}

/// The domains computed for `files[at]` in a workspace of `files`.
fn domains_in(files: &[(&str, &str)], at: &str) -> Result<NumberDomains, String> {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, files.iter().map(|(p, t)| (p.to_string(), t.to_string())), RuleSet::Paper);
    let f = ws.files(&db).iter().copied().find(|f| f.path(&db) == at).expect("the file");
    domains_of(&db, ws, f, &DomainInputs::default()).clone().map_err(|e| e.message)
}

/// A RoboSim machine with the declarations `decls` whose cycle transition
/// (guarded by `condition`) does `action`, with a platform operation
/// `move` and an output event `out` of type nat.
fn sim_machine(decls: &str, condition: &str, action: &str) -> String {
    format!(
        "interface Ops {{ move(l : real, a : real) }}
         interface Outs {{ event out : nat }}
         stm M {{ cycleDef cycle == 7 {decls}
           output context {{ requires Ops uses Outs }}
           initial i state S {{ }}
           transition t0 {{ from i to S }}
           transition t1 {{ from S to S exec condition {condition} action {action} }} }}"
    )
}

fn sim_doms(model: &str) -> ([NumRange; 3], [bool; 3]) {
    let d = domains_in(&[("m.rst", model)], "m.rst").expect("domains");
    (d.domains, d.widened)
}

/// RT-5 for RoboSim, as the reference's `sim/instantiations.csp` lists it
/// (see the `domains` module doc): conditions, outputs (`$out!9`) and the
/// cycle definition add no entry, so 7 and 9 widen nothing.
#[test]
fn robosim_conditions_outputs_and_cycles_widen_nothing() {
    let m = sim_machine("var x : nat", "x > 7", "$out!9 ; $out!(x * 9)");
    assert_eq!(sim_doms(&m), (BASE, [false; 3]));
}

/// The arguments of every call are values: a platform operation's
/// (`$move(0, 3)`), wherever the call is (`floor`'s in a condition), and,
/// as in RoboChart, assigned values.
#[test]
fn robosim_call_arguments_and_assigned_values_widen() {
    let nat3 = ([r(0, 3), r(-2, 3), r(-2, 3)], [true; 3]);
    assert_eq!(sim_doms(&sim_machine("var x : nat", "true", "$move(0, 3)")), nat3);
    assert_eq!(sim_doms(&sim_machine("var x : nat", "true", "x = 3")), nat3);
    let with_floor =
        format!("function floor(v : real) : nat {{ }}\n{}", sim_machine("var x : nat", "floor(3) > x", "x = 1"));
    assert_eq!(sim_doms(&with_floor), nat3);
    // The argument is evaluated whole, not taken apart: `x * 3` keeps x.
    assert_eq!(sim_doms(&sim_machine("var x : nat", "true", "$move(0, x * 3)")), (BASE, [false; 3]));
}

/// One computation per project: a RoboSim element's lists hold the
/// project's RoboChart models' values too, a RoboChart element's leave the
/// RoboSim models out (the reference's `instantiations.csp` has no entry of
/// its `.rst` files).
#[test]
fn robosim_lists_hold_the_robochart_models_and_not_the_other_way() {
    let rct = machine("var y : nat", "y = 3");
    let rst = sim_machine("var k : int", "true", "k = -3");
    let files = [("a.rct", rct.as_str()), ("b.rst", rst.as_str())];
    let sim = domains_in(&files, "b.rst").expect("domains");
    assert_eq!(sim.domains, [r(0, 3), r(-3, 3), r(-3, 3)]);
    let chart = domains_in(&files, "a.rct").expect("domains");
    assert_eq!(chart.domains, [r(0, 3), r(-2, 3), r(-2, 3)]);
}

/// A gap in a RoboSim list asks for the range, as in RoboChart: with no
/// `nat` variable, constant or parameter (`move`'s parameters are reals,
/// entries of `real`'s and not `nat`'s list), `$move(10, 10)` gives
/// `core_nat` {0..2} ∪ {10..10}, and the event `out : nat` communicates
/// values of it.
#[test]
fn robosim_gap_asks_for_the_range() {
    let err = domains_in(&[("m.rst", &sim_machine("", "true", "$move(10, 10)"))], "m.rst").expect_err("a gap");
    assert_eq!(
        err,
        "RoboTool's `core_nat` here is {0..2} ∪ {10..10} (RT-5), not one range: give it with `nametype core_nat = \
         {a..b}` in a `csp` block of an assertion file"
    );
}
