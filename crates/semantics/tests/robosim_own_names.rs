//! A `csp` block written against RoboTool's generated names for RoboSim
//! (each element's module declares its own `terminate`, `endexec`,
//! `registerRead : RegisterDataInput` and `registerWrite :
//! RegisterDataOutput`, the reference's
//! `csp-gen/sim/defs/pkg223_aggregation_sim_Movement.csp`) names the
//! export's events: the script lints clean, and each assertion's verdict,
//! evaluated with our CSPm evaluator, is RoboTool's (robotool-facts RT-20,
//! RT-21). RoboTool has no RoboSim controller or module in the reference:
//! theirs follow its RoboChart pattern (their own names, their
//! components' renamed into them).

mod support;
use robosim_semantics::lint;
use support::{export_files, load, text, trace_refines};

/// M reads `x` (every cycle, RT-20), writes `op` and finishes in its
/// first cycle; C and Mod contain it.
const MODEL: &str = "interface Ops { op() }
interface E { event x : nat }
stm M { cycleDef cycle == 1 input context { uses E } output context { requires Ops }
  initial i0 final F transition t { from i0 to F action $op() } }
controller C { cycleDef cycle == 1 uses E requires Ops sref m = M }
module Mod { cycleDef cycle == 1 robotic platform P { provides Ops uses E } cref c = C }";

/// Each block is one trace (then ✓); `S refines X` holds iff X can do
/// it and terminate (`X::D__ [T= S`).
const ASSERTIONS: &str = "
csp SpecM csp-begin
SpecM = M::registerRead.M::i_x.true.2 -> M::registerWrite.M::o_op -> M::endexec -> M::terminate -> SKIP
csp-end
csp LateM csp-begin
LateM = M::registerRead.M::i_x.true.2 -> M::endexec -> M::registerWrite.M::o_op -> SKIP
csp-end
csp SpecC csp-begin
SpecC = C::registerRead.C::i_x.false.0 -> C::registerWrite.C::o_op -> C::endexec -> C::terminate -> SKIP
csp-end
csp InnerC csp-begin
InnerC = C::registerRead.C::i_x.false.0 -> C::registerWrite.C::o_op -> M::endexec -> SKIP
csp-end
csp SpecMod csp-begin
SpecMod = Mod::registerRead.Mod::i_x.true.1 -> Mod::registerWrite.Mod::o_op -> SKIP
csp-end
csp EndMod csp-begin
EndMod = Mod::registerRead.Mod::i_x.true.1 -> Mod::registerWrite.Mod::o_op -> Mod::endexec -> SKIP
csp-end
assertion AM : SpecM refines M in the traces model
assertion LM : LateM refines M in the traces model
assertion AC : SpecC refines C in the traces model
assertion IC : InnerC refines C in the traces model
assertion AMod : SpecMod refines Mod in the traces model
assertion EMod : EndMod refines Mod in the traces model
";

#[test]
fn a_csp_block_names_robotools_per_element_robosim_events() {
    let e = export_files(vec![("m.rst".into(), MODEL.into()), ("a.rsa".into(), ASSERTIONS.into())]);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings.iter().map(|w| &w.message).collect::<Vec<_>>());
    assert!(lint::check(&e.files).is_empty(), "{:#?}", lint::check(&e.files));
    let model = text(&e, "m.csp");
    // RoboTool's declarations, in the machine's module.
    assert!(
        model.contains(
            "  channel terminate, endexec\n  datatype RegisterDataInput = i_x.Bool.core_nat\n  channel registerRead : \
             RegisterDataInput\n  datatype RegisterDataOutput = o_op\n  channel registerWrite : RegisterDataOutput\n"
        ),
        "{model}"
    );
    let (m, errors) = load(&e.files, "a_assertions.csp");
    assert!(errors.is_empty(), "{errors:#?}");
    let script = text(&e, "a_assertions.csp");
    let verdict = |name: &str, process: &str| {
        let line = format!("assert {process}::D__(0, 1) [T= {name} :[tau priority]: {{tock}}");
        assert!(script.contains(&line), "no `{line}` in\n{script}");
        trace_refines(&m, name, &format!("{process}::D__(0, 1)"))
    };
    // RT-20: the input is read at the start of the cycle (its presence
    // flag and value), the output written in it, then the machine on its
    // own shows its `endexec` and, finished, its `terminate` (RT-21).
    assert!(verdict("SpecM", "M"));
    // RT-20: writes happen before the cycle ends (`endexec`); a finished
    // machine writes nothing in later cycles.
    assert!(!verdict("LateM", "M"));
    // RT-21: a controller shows its own `endexec` (after its machines')
    // and its `terminate`.
    assert!(verdict("SpecC", "C"));
    // RT-21: the machines' `endexec` are hidden in the controller.
    assert!(!verdict("InnerC", "C"));
    // RT-21: a module shows its register reads and writes only; its end
    // is a hidden `terminate`, then ✓.
    assert!(verdict("SpecMod", "Mod"));
    // RT-21: a module hides `endexec`.
    assert!(!verdict("EndMod", "Mod"));
}
