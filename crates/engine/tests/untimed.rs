//! RoboChart's untimed semantics (robotool-facts RT-9) and the two
//! analyses of a plain assertion (RT-8): `wait` is SKIP, clock guards are
//! true, clock resets vanish, calls are plain events, there is no `tock`,
//! and deadlock freedom is FDR's in the failures-divergences model. Each
//! test gives the verdict of each semantics, with its counterexample.

use std::path::Path;

use robosim_engine::verify::{trace_text, verify_texts, verify_workspace, Options, Report, Semantics, Verdict};

use robosim_test_support::inputs;

/// The events and operation the machines of these tests use.
const INTERFACE: &str = "interface I { event e event f event o op() }";

/// Checks `assertions` on `model`: every report, in both semantics.
fn run(model: &str, assertions: &str) -> Vec<Report> {
    verify_texts(
        [("m.rct".to_string(), format!("{INTERFACE}\n{model}")), ("a.assertions".to_string(), assertions.into())],
        &Options::default(),
    )
}

/// Each report: name, semantics, verdict, and the counterexample's kind
/// and trace (or, unsupported, the reason).
fn outcomes(reports: &[Report]) -> Vec<(String, &'static str, Verdict, String)> {
    reports
        .iter()
        .map(|r| {
            let cex = r.counterexample.as_ref().map(|c| format!("{}: {}", c.kind, trace_text(&c.steps)));
            let reason = r.reason.clone().filter(|_| r.verdict == Verdict::Unsupported);
            (r.name.clone(), r.semantics.name(), r.verdict, cex.or(reason).unwrap_or_default())
        })
        .collect()
}

fn expect(reports: &[Report], expected: &[(&str, &str, Verdict, &str)]) {
    let want: Vec<(String, &str, Verdict, String)> =
        expected.iter().map(|(n, s, v, c)| (n.to_string(), *s, *v, c.to_string())).collect();
    assert_eq!(outcomes(reports), want, "{reports:#?}");
}

/// RT-8: a plain assertion is checked in both semantics (timed first), a
/// `timed assertion` in the timed one, an `untimed assertion` in the
/// untimed one.
#[test]
fn rt8_each_assertion_in_its_semantics() {
    let model =
        "stm M { uses I initial i state S { } transition t { from i to S } transition u { from S to S trigger e } }";
    let reports = run(
        model,
        "assertion A : M is deadlock-free
         timed assertion B : M is deadlock-free
         untimed assertion C : M is deadlock-free",
    );
    expect(
        &reports,
        &[
            ("A", "timed", Verdict::Pass, ""),
            ("A", "untimed", Verdict::Pass, ""),
            ("B", "timed", Verdict::Pass, ""),
            ("C", "untimed", Verdict::Pass, ""),
        ],
    );
    assert_eq!(reports[1].semantics, Semantics::Untimed);
}

/// RT-9: `wait(2)` is SKIP and `#C` vanishes; RT-10: refinement without
/// `tock`. Timed, `Slow` outputs `o` two time units after its start, while
/// `Fast` may output it at once or later, so `Slow` only trace-refines
/// `Fast`; untimed they are equal.
#[test]
fn rt9_wait_is_skip() {
    let model = "stm Slow { uses I clock C initial i state S { entry #C ; wait(2) ; o } final F
           transition t { from i to S } transition u { from S to F } }
         stm Fast { uses I initial i state S { entry o } final F
           transition t { from i to S } transition u { from S to F } }";
    let reports = run(
        model,
        "assertion A : Slow refines Fast in the traces model
         assertion B : Fast refines Slow in the traces model
         assertion C : Slow equals Fast",
    );
    expect(
        &reports,
        &[
            ("A", "timed", Verdict::Pass, ""),
            ("A", "untimed", Verdict::Pass, ""),
            ("B", "timed", Verdict::Fail, "trace: o.out"),
            ("B", "untimed", Verdict::Pass, ""),
            // Timed, `Slow` refuses `o` at first, where `Fast` offers it.
            ("C", "timed", Verdict::Fail, "refusal: "),
            ("C", "untimed", Verdict::Pass, ""),
        ],
    );
}

/// RT-9: a clock guard is `true` (RoboTool's untimed script writes
/// `(true)&` for `since(MBC) >= MB`). Timed, `Timer` leaves `S` only after
/// a time unit, so it does `f` only after `tock`; untimed it may leave at
/// once and become the non-deterministic `Now`, as the Alpha Algorithm's
/// `Communication` (a1) does.
#[test]
fn rt9_clock_guards_are_true() {
    let model = "stm Timer { uses I clock C initial i state S { } state T { }
           transition t { from i to S action #C } transition e { from S to S trigger e action #C }
           transition g { from S to T condition since(C) >= 1 } transition h { from T to T trigger f } }
         stm Now { uses I initial i state S { } state T { }
           transition t { from i to S } transition e { from S to S trigger e }
           transition g { from S to T } transition h { from T to T trigger f } }";
    let reports = run(
        model,
        "assertion A : Timer refines Now in the traces model
         assertion B : Now refines Timer in the traces model
         untimed assertion C : Timer is deterministic
         untimed assertion D : T is reachable in Timer",
    );
    expect(
        &reports,
        &[
            // Timed, `Now` leaves `S` before time passes (maximal progress).
            ("A", "timed", Verdict::Fail, "trace: tock e.in"),
            ("A", "untimed", Verdict::Pass, ""),
            ("B", "timed", Verdict::Fail, "trace: f.in"),
            ("B", "untimed", Verdict::Pass, ""),
            // `e` may be refused (the τ to T) or accepted.
            ("C", "untimed", Verdict::Fail, "nondeterminism: "),
            ("D", "untimed", Verdict::Pass, "reachability: "),
        ],
    );
}

/// RT-9: what the reference does not show is refused with the reason and
/// the place, in the untimed analysis only: a clock comparison inside a
/// larger guard, `sinceEntry`, a deadline, a clock read in an action.
#[test]
fn rt9_unestablished_readings_are_unsupported() {
    let model = "stm Mixed { uses I var x : nat clock C initial i state S { } state T { }
           transition t { from i to S } transition g { from S to T condition since(C) >= 1 /\\ x == 0 } }
         stm Entry { uses I initial i state S { } state T { }
           transition t { from i to S } transition g { from S to T condition sinceEntry(S) >= 1 } }
         stm Late { uses I initial i state S { entry (o <{1}) } transition t { from i to S } }
         stm Read { uses I var x : nat clock C initial i state S { entry x = since(C) } transition t { from i to S } }";
    let reports = run(
        model,
        "untimed assertion A : Mixed is deadlock-free
         untimed assertion B : Entry is deadlock-free
         untimed assertion C : Late is deadlock-free
         untimed assertion D : Read is deadlock-free
         assertion E : Late is divergence-free",
    );
    let got = outcomes(&reports);
    let why = |k: usize| got[k].3.clone();
    assert_eq!(
        got.iter().map(|o| (o.0.as_str(), o.1, o.2)).collect::<Vec<_>>(),
        [
            ("A", "untimed", Verdict::Unsupported),
            ("B", "untimed", Verdict::Unsupported),
            ("C", "untimed", Verdict::Unsupported),
            ("D", "untimed", Verdict::Unsupported),
            ("E", "timed", Verdict::Pass),
            ("E", "untimed", Verdict::Unsupported),
        ]
    );
    assert!(
        why(0).contains("the guard of `g` combines a comparison of the clock `Mixed::C`")
            && why(0).contains("m.rct:3:"),
        "{}",
        why(0)
    );
    assert!(why(1).contains("`sinceEntry`") && why(1).contains("m.rct:5:"), "{}", why(1));
    assert!(why(2).contains("deadline `<{d}`") && why(2).contains("m.rct:6:"), "{}", why(2));
    assert!(why(3).contains("uses the clock `Read::C` outside a guard") && why(3).contains("m.rct:7:"), "{}", why(3));
    assert_eq!(why(5), why(2));
}

/// RT-9: deadlock freedom is FDR's `:[deadlock free]` in the
/// failures-divergences model: a deadlock fails it (timed, the same state
/// is a timed deadlock, where only time passes), and so does divergence;
/// RT-19: a platform call is a plain event, which may be refused: `Call`
/// deadlocks after its calls in both.
#[test]
fn rt9_deadlock_freedom_in_the_failures_divergences_model() {
    let model = "stm Stuck { uses I initial i state S { } transition t { from i to S } }
         stm Loop { uses I var n : nat initial i junction J state S { }
           transition t { from i to J } transition a { from J to J action n = 1 } }
         stm Call { requires I initial i state S { entry op(); op() } transition t { from i to S } }
         stm Done { uses I initial i final F transition t { from i to F action o } }";
    let reports = run(
        model,
        "assertion A : Stuck is deadlock-free
         assertion B : Loop is deadlock-free
         assertion C : Call is deadlock-free
         assertion D : Done is deadlock-free
         assertion E : Done terminates",
    );
    expect(
        &reports,
        &[
            ("A", "timed", Verdict::Fail, "timed deadlock: "),
            ("A", "untimed", Verdict::Fail, "deadlock: "),
            // Hidden steps alone, forever: a divergence, which the timed
            // check (RT-10: `tock` hidden, then divergence-free) fails too.
            ("B", "timed", Verdict::Fail, "divergence: "),
            ("B", "untimed", Verdict::Fail, "divergence: "),
            ("C", "timed", Verdict::Fail, "timed deadlock: opCall opCall"),
            ("C", "untimed", Verdict::Fail, "deadlock: opCall opCall"),
            // Termination is not a deadlock.
            ("D", "timed", Verdict::Pass, ""),
            ("D", "untimed", Verdict::Pass, ""),
            ("E", "timed", Verdict::Pass, "termination: o.out ✓"),
            ("E", "untimed", Verdict::Pass, "termination: o.out ✓"),
        ],
    );
}

/// RT-10 without `tock`: `terminates` of a process that can diverge is
/// not decided (the encoding's reading of divergence is not established).
#[test]
fn rt10_terminates_with_divergence_is_not_decided() {
    let model = "stm Spin { uses I var n : nat initial i junction J final F
           transition t { from i to J } transition a { from J to J action n = 1 } transition b { from J to F } }";
    let reports = run(model, "untimed assertion A : Spin terminates");
    expect(
        &reports,
        &[(
            "A",
            "untimed",
            Verdict::Unsupported,
            "Spin can diverge: whether RoboTool's untimed encoding of termination counts a divergence against it \
             is not established, so it is not decided",
        )],
    );
}

/// RT-8: what has only a timed meaning gets no untimed analysis when the
/// assertion is plain, and an `untimed assertion` of it says why:
/// timelock freedom (time passing), the tick-tock model (`tock`).
#[test]
fn rt8_timed_only_properties() {
    let model =
        "stm M { uses I initial i state S { } transition t { from i to S } transition u { from S to S trigger e } }";
    let reports = run(
        model,
        "assertion A : M is timelock-free
         untimed assertion B : M is timelock-free
         assertion C : M refines M in the tick-tock model
         untimed assertion D : M refines M in the tick-tock model",
    );
    expect(
        &reports,
        &[
            ("A", "timed", Verdict::Pass, ""),
            (
                "B",
                "untimed",
                Verdict::Unsupported,
                "timelock freedom is about time passing: the untimed semantics has no `tock`, so it is checked \
                 timed only",
            ),
            ("C", "timed", Verdict::Pass, ""),
            (
                "D",
                "untimed",
                Verdict::Unsupported,
                "the tick-tock model is about `tock`, which the untimed semantics does not have",
            ),
        ],
    );
}

/// RT-8: a RoboSim assertion file (.rsa) has a timed script only, even
/// about a RoboChart element.
#[test]
fn rt8_rsa_files_are_timed() {
    let model =
        "stm M { uses I initial i state S { } transition t { from i to S } transition u { from S to S trigger e } }";
    let reports = verify_texts(
        [
            ("m.rct".to_string(), format!("{INTERFACE}\n{model}")),
            ("a.rsa".to_string(), "assertion A : M is deadlock-free\nuntimed assertion B : M is deadlock-free".into()),
        ],
        &Options::default(),
    );
    expect(
        &reports,
        &[
            ("A", "timed", Verdict::Pass, ""),
            (
                "B",
                "untimed",
                Verdict::Unsupported,
                "the assertions of a RoboSim assertion file (.rsa) are checked in the timed semantics only",
            ),
        ],
    );
}

/// RT-8: a plain assertion on a plain `csp` block is checked in both
/// semantics: timed, the machine lets time pass where `STOP` cannot;
/// untimed (no `tock`), it does nothing visible, as `STOP`.
#[test]
fn rt8_csp_blocks_are_checked_in_both_semantics() {
    let model = "stm M { uses I initial i state S { } transition t { from i to S } }";
    let reports = run(
        model,
        "csp Spec csp-begin
Spec = STOP
csp-end
assertion A : M refines Spec
untimed assertion B : M refines Spec",
    );
    let got: Vec<(&str, &str, Verdict)> =
        reports.iter().map(|r| (r.name.as_str(), r.semantics.name(), r.verdict)).collect();
    assert_eq!(got, [("A", "timed", Verdict::Fail), ("A", "untimed", Verdict::Pass), ("B", "untimed", Verdict::Pass)]);
    assert_eq!(reports[2].reason.as_deref(), Some("M refines Spec"));
}

/// The reports on the Alpha Algorithm's `model.assertions` named in
/// `names`: (name, semantics, verdict, states).
fn alpha_algorithm(names: &[&str]) -> Vec<(String, &'static str, Verdict, u64)> {
    let project =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/robo-star__robochart-alpha-algorithm");
    let mut paths = Vec::new();
    inputs::model_files(&project, &mut paths);
    let files: Vec<(String, String)> =
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).unwrap())).collect();
    let mut db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&mut db, files, robosim_hir::RuleSet::Paper);
    verify_workspace(&db, ws, &Options::default(), None)
        .into_iter()
        .filter(|r| r.file.ends_with("model.assertions") && names.contains(&r.name.as_str()))
        .map(|r| (r.name, r.semantics.name(), r.verdict, r.stats.states))
        .collect()
}

/// The Alpha Algorithm (robotool-facts, "Results FDR recorded"): in both
/// the untimed and the timed analysis, a1 `Communication is
/// deterministic` is false and a2–a9 hold. Our state counts are before
/// any compression; FDR's, after its own (untimed/timed): a1 2/48, a2–a3
/// 9/1000, a4 3/39, a5–a6 8/1748, a7 3/17, a8–a9 37/392.
#[test]
fn alpha_algorithm_in_both_semantics() {
    let got = alpha_algorithm(&["a1", "a2", "a3", "a4", "a5", "a6", "a7", "a8", "a9"]);
    let expected = [
        ("a1", "timed", Verdict::Fail, 11),
        ("a1", "untimed", Verdict::Fail, 2),
        ("a2", "timed", Verdict::Pass, 102),
        ("a2", "untimed", Verdict::Pass, 50),
        ("a3", "timed", Verdict::Pass, 102),
        ("a3", "untimed", Verdict::Pass, 50),
        ("a4", "timed", Verdict::Pass, 5),
        ("a4", "untimed", Verdict::Pass, 2),
        ("a5", "timed", Verdict::Pass, 919),
        ("a5", "untimed", Verdict::Pass, 112),
        ("a6", "timed", Verdict::Pass, 919),
        ("a6", "untimed", Verdict::Pass, 112),
        ("a7", "timed", Verdict::Pass, 11),
        ("a7", "untimed", Verdict::Pass, 3),
        ("a8", "timed", Verdict::Pass, 3898),
        ("a8", "untimed", Verdict::Pass, 8700),
        ("a9", "timed", Verdict::Pass, 3898),
        ("a9", "untimed", Verdict::Pass, 8700),
    ];
    assert_eq!(got, expected.map(|(n, s, v, k)| (n.to_string(), s, v, k)).to_vec());
}
