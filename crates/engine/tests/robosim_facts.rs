//! RoboSim as RoboTool 3 reads it (../shared/spec/robotool-facts.md
//! RT-20 … RT-23; the generated CSPm of a RoboSim machine is in
//! ../shared/reference/alpha-algorithm/csp-gen/sim/defs/
//! pkg223_aggregation_sim_Movement.csp): the end of a cycle, what a
//! machine, a controller and a module show of it, connections between
//! machines or controllers through a memory cell, and `uses` of an
//! interface with variables.

use robosim_engine::verify::{verify_texts, Options, Report, Semantics, Verdict};

mod support;
use support::machines::expect;

/// The platform's operations and the events between machines.
const INTERFACES: &str = "interface Ops { op() op2(x : nat) }
    interface Ev { event e : nat }
    interface Cnt { var n : nat }";

/// Checks `assertions` (an `.rsa` file) on the RoboSim `model`, in the
/// timed semantics (RoboSim's own).
fn run(model: &str, assertions: &str) -> Vec<Report> {
    let reports = verify_texts(
        [("m.rst".to_string(), format!("{INTERFACES}\n{model}")), ("a.rsa".to_string(), assertions.into())],
        &Options::default(),
    );
    reports.into_iter().filter(|r| r.semantics == Semantics::Timed).collect()
}

/// M writes `op` and finishes in its first cycle; N finishes in its
/// second; M0 and N0 do the same without writing.
const ENDINGS: &str = "
    stm M { cycleDef cycle == 1 output context { requires Ops }
      initial i0 final F transition t { from i0 to F action $op() } }
    stm N { cycleDef cycle == 1 output context { requires Ops }
      initial i0 state S { } final F transition t { from i0 to S action $op() } transition u { from S to F exec } }
    stm M0 { cycleDef cycle == 1 initial i0 final F transition t { from i0 to F } }
    stm N0 { cycleDef cycle == 1 initial i0 state S { } final F transition t { from i0 to S }
      transition u { from S to F exec } }
    controller C { cycleDef cycle == 1 requires Ops sref m = M }
    controller C2 { cycleDef cycle == 1 sref a = M0 sref b = N0 }
    module Mod { cycleDef cycle == 1 robotic platform P { provides Ops } cref c = C }";

/// RT-20, RT-21: a machine on its own ends each cycle with a visible
/// `endexec`; then `terminate` if it has finished (competing with `tock`).
/// A controller shows one `endexec` per cycle, after all its machines';
/// a module hides both (its `terminate` is a hidden step before ✓).
#[test]
fn the_end_of_a_cycle_at_each_level() {
    let reports = run(
        ENDINGS,
        "assertion TM : M terminates
         assertion TN : N terminates
         assertion TC : C terminates
         assertion TC2 : C2 terminates
         assertion TMod : Mod terminates",
    );
    expect(
        &reports,
        &[
            ("TM", Verdict::Pass, "termination: registerWrite.o_op endexec terminate ✓"),
            ("TN", Verdict::Pass, "termination: registerWrite.o_op endexec tock endexec terminate ✓"),
            ("TC", Verdict::Pass, "termination: registerWrite.o_op endexec terminate ✓"),
            ("TC2", Verdict::Pass, "termination: endexec tock endexec terminate ✓"),
            ("TMod", Verdict::Pass, "termination: registerWrite.o_op (terminate) ✓"),
        ],
    );
}

/// RT-20: a finished machine keeps ending cycles (`endexec`, then
/// `terminate` or `tock`): every trace of N (finishing in cycle 2) is one
/// of M (finished in cycle 1), not the converse. M is deadlock-free in
/// RoboTool's timed reading (RT-10: `terminate` has priority over `tock`,
/// so no state lets only time pass), and not timelock-free (RT-10: its
/// urgent writes, `endexec` and `terminate` may be refused).
#[test]
fn a_finished_machine_keeps_ending_cycles() {
    let reports = run(
        ENDINGS,
        "assertion R1 : N refines M in the traces model
         assertion R2 : M refines N in the traces model
         assertion D : M is deadlock-free
         assertion T : M is timelock-free",
    );
    expect(
        &reports,
        &[
            ("R1", Verdict::Pass, ""),
            ("R2", Verdict::Fail, "trace: registerWrite.o_op endexec terminate"),
            ("D", Verdict::Pass, ""),
            ("T", Verdict::Fail, "timelock: "),
        ],
    );
}

/// A sends `e` (3) in its first cycle and finishes; B reads it through
/// the connection's memory cell and writes `op2` with its value.
/// `A` sends 2: RoboTool's `core_nat` here is `{0..2}` (RT-5: a RoboSim
/// output widens nothing), so a 3 would stop FDR with an error.
const CELLS: &str = "
    stm A { cycleDef cycle == 1 output context { uses Ev }
      initial i0 final F transition t { from i0 to F action $e!2 } }
    stm B { cycleDef cycle == 1 input context { uses Ev } output context { requires Ops } var x : nat
      initial i0 state W { } final F transition t { from i0 to W }
      transition a { from W to F condition $e?x action $op2(x) }
      transition b { from W to W exec condition not $e } }
    stm B2 { cycleDef cycle == 1 input context { uses Ev } output context { requires Ops }
      initial i0 state W { } state W2 { } final F transition t { from i0 to W }
      transition a { from W to W2 exec condition $e } transition b { from W to W exec condition not $e }
      transition c { from W2 to F condition $e action $op2(1) } transition d { from W2 to W2 exec condition not $e } }
    stm A2 { cycleDef cycle == 1 output context { uses Ev }
      initial i0 final F transition t { from i0 to F action $e!1; $e!2 } }
    controller C { cycleDef cycle == 1 requires Ops sref a = A sref b = B connection a on e to b on e }
    controller CA { cycleDef cycle == 1 requires Ops sref a = A sref b = B connection a on e to b on e ( _async ) }
    controller C2 { cycleDef cycle == 1 requires Ops sref a = A sref b = B2 connection a on e to b on e }
    controller CW { cycleDef cycle == 1 requires Ops sref a = A2 sref b = B connection a on e to b on e }
    controller S { cycleDef cycle == 1 uses Ev sref a = A connection a on e to S on e }
    controller R { cycleDef cycle == 1 uses Ev requires Ops sref b = B connection R on e to b on e }
    module Mod { cycleDef cycle == 1 robotic platform P { provides Ops } cref c = C }
    module ModA { cycleDef cycle == 1 robotic platform P { provides Ops } cref c = CA }
    module Mod2 { cycleDef cycle == 1 robotic platform P { provides Ops } cref c = C2 }
    module ModW { cycleDef cycle == 1 robotic platform P { provides Ops } cref c = CW }
    module Mods { cycleDef cycle == 1 robotic platform P { provides Ops } cref s = S cref r = R
      connection s on e to r on e }";

/// RT-22: what a machine sends another in cycle k, the receiver reads at
/// the start of cycle k+1 (so `op2.2` follows one `tock`), `_async` or not,
/// between machines of a controller or between controllers of a module.
#[test]
fn connections_go_through_a_memory_cell_read_one_cycle_later() {
    let reports = run(
        CELLS,
        "assertion T : Mod terminates
         assertion TA : ModA terminates
         assertion TS : Mods terminates
         assertion TC : C terminates",
    );
    expect(
        &reports,
        &[
            ("T", Verdict::Pass, "termination: tock registerWrite.o_op2.2 (terminate) ✓"),
            ("TA", Verdict::Pass, "termination: tock registerWrite.o_op2.2 (terminate) ✓"),
            ("TS", Verdict::Pass, "termination: tock registerWrite.o_op2.2 (terminate) ✓"),
            ("TC", Verdict::Pass, "termination: endexec tock registerWrite.o_op2.2 endexec terminate ✓"),
        ],
    );
}

/// RT-22: the value is erased before the receiver's next cycle executes,
/// so B2, which needs `e` in two consecutive cycles, never finishes: the
/// module then only lets time pass (nothing of it is visible), a timed
/// deadlock (RT-10). RT-20: a second write of the cell in one cycle cannot
/// happen, so A2's cycle never ends: a deadlock before termination, which
/// RoboTool's timed deadlock check (a divergence check once `tock` is
/// hidden, RT-10) does not see.
#[test]
fn a_memory_cell_holds_one_value_for_one_cycle() {
    let reports = run(
        CELLS,
        "assertion T2 : Mod2 terminates
         assertion D2 : Mod2 is deadlock-free
         assertion TW : ModW terminates
         assertion DW : ModW is deadlock-free",
    );
    expect(
        &reports,
        &[
            ("T2", Verdict::Fail, ""),
            ("D2", Verdict::Fail, "timed deadlock: tock tock"),
            ("TW", Verdict::Fail, "deadlock: "),
            ("DW", Verdict::Pass, ""),
        ],
    );
}

/// RT-23: `uses` of an interface with variables declares local variables
/// of the machine (no register events), and an operation that `requires`
/// the interface updates the caller's copy.
#[test]
fn uses_of_an_interface_with_variables_declares_locals() {
    let model = "
        stm L { cycleDef cycle == 1 uses Cnt output context { requires Ops }
          initial i0 state S { } final F transition t { from i0 to S }
          transition u { from S to S exec condition n < 2 action n = n + 1 }
          transition w { from S to F condition n == 2 action $op2(n) } }
        interface IInc { Inc() }
        operation Inc() { requires Cnt initial i0 final F0 transition t { from i0 to F0 action n = n + 1 }
          input context { } output context { } }
        stm L2 { cycleDef cycle == 1 uses Cnt requires IInc output context { requires Ops }
          initial i0 state S { } final F transition t { from i0 to S }
          transition u { from S to S exec condition n < 2 action Inc() }
          transition w { from S to F condition n == 2 action $op2(n) } }
        controller C { cycleDef cycle == 1 requires Ops sref l = L2 opref op_ref0 = Inc }";
    let reports = run(
        model,
        "assertion T : L terminates
         assertion TC : C terminates",
    );
    expect(
        &reports,
        &[
            ("T", Verdict::Pass, "termination: endexec tock endexec tock registerWrite.o_op2.2 endexec terminate ✓"),
            ("TC", Verdict::Pass, "termination: endexec tock endexec tock registerWrite.o_op2.2 endexec terminate ✓"),
        ],
    );
}

/// RT-21 against a cycle-constrained design (which has no `endexec`): the
/// machine on its own is compared at a module's alphabet, and the report
/// says so.
#[test]
fn a_machine_against_a_constrained_design_hides_its_end() {
    let design = "package rc interface ROps { op() }
        stm RM { requires ROps initial i0 final F transition t { from i0 to F action op() } }";
    let rsa = "simulation PM of rc::RM { cycleDef cycle == 1 }
        assertion R : M refines PM in the traces model";
    let reports = verify_texts(
        [
            ("rc.rct".to_string(), design.to_string()),
            ("m.rst".to_string(), format!("{INTERFACES}\n{ENDINGS}")),
            ("a.rsa".to_string(), rsa.to_string()),
        ],
        &Options::default(),
    );
    let r = &reports[0];
    assert_eq!(r.verdict, Verdict::Pass, "{r:#?}");
    assert!(r.notes.iter().any(|n| n.contains("`endexec` and `terminate` are hidden")), "{:?}", r.notes);
}

/// The timed reports of the `.rsa` files in a workspace of the model and
/// `.rsa` files of `subs` (folders of the reference output), as `(file
/// name, verdict, reason up to its location)`, sorted.
fn reference_rsa_reports(subs: &[&str]) -> Vec<(String, Verdict, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/alpha-algorithm");
    let mut files = Vec::new();
    for sub in subs {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            let p = e.unwrap().path();
            let kind = robosim_syntax::FileKind::from_path(&p);
            if p.is_file() && kind.is_some_and(|k| k != robosim_syntax::FileKind::Assertions) {
                files.push((p.display().to_string(), std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    files.sort();
    let db = robosim_hir::RootDatabase::default();
    let ws = robosim_hir::load_workspace(&db, files, robosim_hir::RuleSet::Paper);
    let mut got: Vec<(String, Verdict, String)> =
        robosim_engine::verify::verify_workspace(&db, ws, &Options::default(), None)
            .into_iter()
            .filter(|r| r.semantics == Semantics::Timed)
            .map(|r| {
                let file = r.file.rsplit('/').next().unwrap_or_default().to_string();
                // The reason up to its source location (a path).
                let reason = r.reason.unwrap_or_default();
                let reason = reason.split(" (/").next().unwrap_or_default().to_string();
                (format!("{file} {}", r.name), r.verdict, reason)
            })
            .collect();
    got.sort_by(|a, b| a.0.cmp(&b.0));
    got
}

/// The RoboSim assertions of the reference output (RoboTool's rc2rs
/// transformation of the Alpha Algorithm, `rc2rs/*.rsa`; FDR recorded no
/// results for them) with the `rc2rs` folder alone as the workspace: its
/// RoboChart models import `main` and `Mathematics`, which live at the
/// project's root, so `main::ID` and `floor` do not resolve. RoboTool's
/// RoboSim script bounds the number types with the values of the
/// project's RoboChart models too (`sim/instantiations.csp`, RT-5), among
/// them `robots ! size(neighs)` over `Set(main::ID)`: no assertion can be
/// checked without them, and each says why (CommunicationC's A2, decided
/// before RoboSim's domains were RoboTool's, is refused too).
#[test]
fn reference_robosim_assertions_without_their_project() {
    let got = reference_rsa_reports(&["rc2rs", "rc2rs/robochart", "rc2rs/robosim"]);
    let domain = "RoboTool's `core_real` depends on the value of this expression, which the native checker \
                  cannot work out (RT-5): give the type with `nametype core_real = {a..b}` in a `csp` block";
    let want: Vec<(String, Verdict, String)> = ["communicationC.rsa", "main.rsa", "movementC.rsa"]
        .iter()
        .flat_map(|f| ["A1", "A2", "A3", "A4"].map(|a| (format!("{f} {a}"), Verdict::Unsupported, domain.to_string())))
        .collect();
    assert_eq!(got, want);
}

/// The same assertions in their project (the reference folder, whose
/// `.project` is at its root, as RoboTool read it): the number types are
/// `sim/instantiations.csp`'s, `{0..2}`, `{-2..2}`, `{-2..180}` (RT-5), on
/// both sides of each refinement (RoboTool's RoboSim script includes that
/// one file for the `simulation`'s RoboChart design too).
///
/// CommunicationC's A2 fails, as RoboTool's encoding must (RT-10: a
/// divergence once `tock` is hidden): with `id = 0` (RT-1) and
/// `receiveF` true, a read `receive` of `(0, 0)` enables `t2` (Receive to
/// Receive, no `exec`) again and again within the cycle — primitive `ID`
/// is `{0, 1}` (RT-3), so this does not rest on the number domains.
///
/// MovementC's A2–A4 changed when the RoboSim types became RoboTool's:
/// with every literal of the project widening them (`{0..360}`), A2 ran
/// out of memory and A3/A4 failed on values (`registerRead.i_neighbours.
/// true.3`) the RoboChart side's `{0..2}` did not have — a mismatch
/// RoboTool's one `core_nat` cannot have.
#[test]
fn reference_robosim_assertions_in_their_project() {
    let got = reference_rsa_reports(&["", "rc2rs", "rc2rs/robochart", "rc2rs/robosim"]);
    let several = "receiving into `n`, which the controller provides to several machines, is not supported yet";
    let diverges = |m: &str| {
        format!(
            "{m} can run hidden steps forever without time passing (a divergence, which RoboTool's timed \
             deadlock check fails too)"
        )
    };
    let (no, pass, fail) = (Verdict::Unsupported, Verdict::Pass, Verdict::Fail);
    let expected = [
        ("communicationC.rsa A1", pass, "CommunicationC can be scheduled in cycles of period 1".to_string()),
        ("communicationC.rsa A2", fail, diverges("pkg223__sim::CommunicationC")),
        (
            "communicationC.rsa A3",
            fail,
            "refinement fails: the implementation refuses every event the specification must offer: one of \
             {registerWrite.o_broadcast.0}"
                .to_string(),
        ),
        (
            "communicationC.rsa A4",
            fail,
            "refinement fails: the implementation can perform registerWrite.o_broadcast.0 where the specification \
             cannot"
                .to_string(),
        ),
        ("main.rsa A1", no, several.to_string()),
        ("main.rsa A2", fail, diverges("pkg223_main_sim::AggregationSoftware")),
        ("main.rsa A3", no, several.to_string()),
        ("main.rsa A4", no, several.to_string()),
        ("movementC.rsa A1", fail, "MovementC cannot be scheduled in cycles of period 1".to_string()),
        ("movementC.rsa A2", pass, "pkg223__sim::MovementC never reaches a state where only time passes".to_string()),
        (
            "movementC.rsa A3",
            fail,
            "refinement fails: the implementation can perform tock where the specification cannot".to_string(),
        ),
        ("movementC.rsa A4", pass, "NormalFormMovementC refines pkg223__sim::MovementC".to_string()),
    ];
    let want: Vec<(String, Verdict, String)> =
        expected.iter().map(|(n, v, r)| (n.to_string(), *v, r.clone())).collect();
    assert_eq!(got, want);
}
