//! The model's names as RoboTool's generated CSPm spells them: checked
//! against RoboTool 3's own output for the Alpha Algorithm
//! (`../shared/reference/alpha-algorithm/csp-gen`, read for the expected
//! names below) and on a small RoboSim model.

use std::path::Path;

use robosim_hir::csp_names::{csp_names, CspKind, CspType, TypeDef};
use robosim_hir::{load_workspace, RootDatabase, RuleSet};

fn alpha_files() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/alpha-algorithm");
    let mut out = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "rct") {
            out.push((p.display().to_string(), std::fs::read_to_string(&p).unwrap()));
        }
    }
    out.sort();
    out
}

fn named(n: &str) -> CspType {
    CspType::Named(n.into())
}

#[test]
fn alpha_algorithm_names_match_robotool_output() {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, alpha_files(), RuleSet::Paper);
    let t = csp_names(&db, ws);
    let kind = |n: &str| t.get(n).unwrap_or_else(|| panic!("no `{n}`")).kind.clone();

    // defs/aggregation.csp: `module aggregation` / `module Movement`.
    assert_eq!(kind("aggregation"), CspKind::Module);
    assert_eq!(kind("aggregation::Movement"), CspKind::Module);
    // `channel obstacle: InOut.main_Position`, `channel moveCall: core_real.core_real`.
    assert_eq!(
        kind("aggregation::Movement::obstacle"),
        CspKind::Channel { fields: vec![CspType::InOut, named("main_Position")] }
    );
    assert_eq!(
        kind("aggregation::Movement::neighbours"),
        CspKind::Channel { fields: vec![CspType::InOut, CspType::Nat] }
    );
    assert_eq!(
        kind("aggregation::Movement::moveCall"),
        CspKind::Channel { fields: vec![CspType::Real, CspType::Real] }
    );
    assert_eq!(kind("aggregation::Movement::terminate"), CspKind::Channel { fields: vec![] });
    // model_assertions.csp: `aggregation::Movement::D__(id__, const_aggregation_Movement_lv, …)`.
    let params = [
        "id__",
        "const_aggregation_Movement_lv",
        "const_aggregation_Movement_av",
        "const_aggregation_Movement_MB",
        "const_aggregation_Movement_alpha",
    ];
    assert_eq!(kind("aggregation::Movement::D__"), CspKind::Process { params: params.map(String::from).to_vec() });
    assert!(matches!(kind("const_aggregation_Movement_alpha"), CspKind::Constant { ty: CspType::Nat, init: None }));
    // defs/Communication.csp: `channel receive: InOut.{(x0__,x1__) | x0__ <- main_ID,x1__ <- main_ID}`.
    assert_eq!(
        kind("Communication::receive"),
        CspKind::Channel { fields: vec![CspType::InOut, CspType::Tuple(vec![named("main_ID"), named("main_ID")])] }
    );
    assert_eq!(
        kind("Communication::O__"),
        CspKind::Process {
            params: ["id__", "const_Communication_id", "const_Communication_RC"].map(String::from).to_vec()
        }
    );
    // defs/main.csp: the module's platform events, and its parameters:
    // its controllers' machines' constants under the controllers' names.
    assert_eq!(kind("main::AggregationSoftware::receive"), kind("Communication::receive"));
    assert_eq!(
        kind("main::AggregationSoftware::moveCall"),
        CspKind::Channel { fields: vec![CspType::Real, CspType::Real] }
    );
    let module_params = [
        "id__",
        "const_MovementC_stm_ref0_lv",
        "const_MovementC_stm_ref0_av",
        "const_MovementC_stm_ref0_MB",
        "const_MovementC_stm_ref0_alpha",
        "const_CommunicationC_stm_ref0_id",
        "const_CommunicationC_stm_ref0_RC",
    ];
    assert_eq!(
        kind("main::AggregationSoftware::D__"),
        CspKind::Process { params: module_params.map(String::from).to_vec() }
    );
    assert_eq!(
        kind("main::AggregationSoftware::ctrl_ref0::stm_ref0::obstacle"),
        kind("aggregation::Movement::obstacle")
    );
    // defs/main_defs.csp: `datatype main_Position = main_Position_left | main_Position_right`.
    assert_eq!(
        kind("main_Position"),
        CspKind::Type(TypeDef::Enumeration(vec!["main_Position_left".into(), "main_Position_right".into()]))
    );
    assert_eq!(kind("main_Position_right"), CspKind::Literal { ty: "main_Position".into(), index: 1 });
    assert_eq!(kind("main_ID"), CspKind::Type(TypeDef::Primitive));
    assert_eq!(kind("core_clock_type"), CspKind::Type(TypeDef::Core));
    assert_eq!(kind("aggregation::Movement::sem__events"), CspKind::EventSet);
    // RoboTool-1 names (the old `b1`/`b2` blocks) are not RoboTool 3's.
    assert!(t.get("AggregationSoftware_receive").is_none());
    assert!(t.get("AggregationSoftware_O").is_none());

    // Each entry leads to its declaration.
    let decl = t.get("aggregation::Movement::obstacle").unwrap().decl.unwrap();
    assert_eq!(&decl.file.text(&db)[decl.range], "obstacle");
    let lit = t.get("main_Position_left").unwrap().decl.unwrap();
    assert_eq!(&lit.file.text(&db)[lit.range], "left");
    let el = t.element_by_path(&["aggregation".into(), "Movement".into()]).unwrap();
    assert_eq!(el.module, "aggregation::Movement");
    assert_eq!(el.constants.len(), 4);
    assert!(el.channels.contains(&"aggregation::Movement::obstacle".to_string()));
}

const ROBOSIM: &str = "package rs
interface I { event obstacle : nat }
interface O { event stop }
stm Mv {
  cycleDef cycle == 1
  input context { uses I }
  output context { uses O }
  const k : nat = 2
  initial i
  state S { }
  transition t { from i to S }
}
";

#[test]
fn robosim_registers_and_constants() {
    let mut db = RootDatabase::default();
    let ws = load_workspace(&mut db, [("m.rst".to_string(), ROBOSIM.to_string())], RuleSet::Paper);
    let t = csp_names(&db, ws);
    let kind = |n: &str| t.get(n).unwrap_or_else(|| panic!("no `{n}`")).kind.clone();
    assert_eq!(kind("rs::Mv::i_obstacle"), CspKind::Register { input: true, ty: Some(CspType::Nat) });
    assert_eq!(kind("rs::Mv::o_stop"), CspKind::Register { input: false, ty: None });
    assert!(matches!(kind("rs::Mv::registerRead"), CspKind::Channel { .. }));
    assert!(matches!(kind("rs::Mv::registerWrite"), CspKind::Channel { .. }));
    assert_eq!(kind("rs::Mv::endexec"), CspKind::Channel { fields: vec![] });
    assert_eq!(kind("const_rs_Mv_k"), CspKind::Constant { ty: CspType::Nat, init: Some("2".into()) });
    assert!(t.element("rs::Mv").is_some_and(|e| e.robosim));
}
