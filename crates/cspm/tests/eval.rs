//! Evaluation and LTS compilation: values, pattern matching, and the
//! transitions of processes, including `Timed(OneStep)` sections with the
//! tock insertion of FDR's front end.

use robosim_cspm::{Code, Evaluator, Label, Limits, Lts, Module, NoNames};

fn module(text: &str) -> Module {
    let m = Module::check(text, &NoNames);
    assert!(m.is_ok(), "{:?}", m.diagnostics());
    m
}

fn value(text: &str, name: &str) -> String {
    let m = module(text);
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    ev.value(name).map(|v| v.to_string()).unwrap_or_else(|e| e.to_string())
}

fn lts(text: &str, name: &str) -> Lts {
    let m = module(text);
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    ev.lts(name).unwrap()
}

fn initials(l: &Lts, s: u32) -> Vec<String> {
    l.transitions[s as usize]
        .iter()
        .map(|(lab, _)| match lab {
            Label::Tau => "τ".to_owned(),
            Label::Tick => "✓".to_owned(),
            Label::Event(e) => l.events[*e as usize].clone(),
        })
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect()
}

#[test]
fn values_and_functions() {
    let text = "
fact(0) = 1
fact(n) = n * fact(n-1)
len(<>) = 0
len(<_>^xs) = 1 + len(xs)
datatype T = A | B.{0..1}
S = { x * 2 | x <- {0..3}, x != 1 }
Q = let f = \\ x @ x + 1 within f(41)
";
    assert_eq!(value(text, "S"), "{0, 4, 6}");
    assert_eq!(value(&format!("{text}\nr = fact(5)"), "r"), "120");
    assert_eq!(value(&format!("{text}\nr = len(<1,2,3>)"), "r"), "3");
    assert_eq!(value(text, "T"), "{A, B.0, B.1}");
    assert_eq!(value(text, "Q"), "42");
    assert_eq!(value(&format!("{text}\nr = -7 / 2 == -3 and -7 % 2 == -1"), "r"), "true");
}

#[test]
fn prefixes_choice_hiding_and_renaming() {
    let text = "
channel c : {0..2}
channel d : {0..2}.Bool
channel e : {0..2}
P = c?x:{0,1} -> d!x!true -> P
Q = (P [] c.2 -> STOP) \\ {| d |}
R = P [[ c <- e ]]
";
    let p = lts(text, "P");
    assert_eq!(p.states(), 3);
    assert_eq!(initials(&p, 0), ["c.0", "c.1"]);
    assert!(p.has_trace(&["c.1", "d.1.true", "c.0"]));
    assert!(!p.has_trace(&["c.2"]));
    let q = lts(text, "Q");
    assert!(q.has_trace(&["c.1", "c.0"]));
    // `$x`: the process, not the environment, picks the value.
    let n = lts(&format!("{text}\nN = c$x:{{0,1}} -> STOP"), "N");
    assert_eq!(initials(&n, 0), ["τ"]);
    assert_eq!(n.transitions[0].len(), 2);
    let r = lts(text, "R");
    assert!(r.has_trace(&["e.0", "d.0.true", "e.1"]));
    assert!(!r.has_trace(&["c.0"]));
}

#[test]
fn parallel_interleaving_and_termination() {
    let text = "
channel a, b, c
P = a -> b -> SKIP
Q = b -> c -> SKIP
S = P [| {b} |] Q
I = (a -> SKIP) ||| (c -> SKIP)
X = (a -> STOP) [| {a} |> (c -> SKIP)
";
    let s = lts(text, "S");
    assert!(s.has_trace(&["a", "b", "c"]));
    assert!(!s.has_trace(&["b"]));
    let i = lts(text, "I");
    assert!(i.has_trace(&["c", "a"]));
    // Both sides terminate, then the whole does: ✓ after two τs.
    let ticks = i.transitions.iter().flatten().filter(|(l, _)| *l == Label::Tick).count();
    assert_eq!(ticks, 1);
    assert!(lts(text, "X").has_trace(&["a", "c"]));
}

#[test]
fn timed_sections_insert_tocks_as_fdr_does() {
    let text = "
channel tock, a, b
OneStep(_) = 1
Timed(OneStep) {
  P = a -> b -> STOP
}
";
    let p = lts(text, "P");
    // μX. tock -> X [] a -> tock -> (μY. tock -> Y [] b -> tock -> TSTOP)
    assert_eq!(initials(&p, 0), ["a", "tock"]);
    assert!(p.has_trace(&["tock", "tock", "a", "tock", "tock", "b", "tock", "tock"]));
    assert!(!p.has_trace(&["a", "b"]));
    assert_eq!(p.states(), 5);
}

#[test]
fn timed_external_choice_synchronises_on_tock() {
    let text = "
channel tock, a, b
OneStep(_) = 1
Timed(OneStep) {
  P = (a -> STOP) [] (WAIT(2); b -> STOP)
}
";
    let p = lts(text, "P");
    assert!(p.has_trace(&["tock", "a"]));
    assert!(p.has_trace(&["tock", "tock", "b"]));
    assert!(!p.has_trace(&["b"]));
}

#[test]
fn bounds_and_errors_are_diagnostics() {
    let text = "channel c : {0..3}\nP(n) = c.0 -> P(n+1)\nR = P(0)\nZ = 1/0\nU = head(<>)";
    let m = module(text);
    let limits = Limits { max_states: 100, ..Limits::default() };
    let mut ev = Evaluator::new(&m, &NoNames, limits);
    assert_eq!(ev.lts("R").unwrap_err().code, Code::Limit);
    let z = ev.value("Z").unwrap_err();
    assert_eq!((z.code, &text[z.range]), (Code::Runtime, "1/0"));
    assert_eq!(ev.value("U").unwrap_err().code, Code::Runtime);
    // Cancellation stops an evaluation that would otherwise run long.
    let cancel = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let limits = Limits { cancel: Some(cancel), ..Limits::default() };
    let mut ev = Evaluator::new(&m, &NoNames, limits);
    assert_eq!(ev.lts("R").unwrap_err().code, Code::Cancelled);
    // Runaway recursion is a depth limit, not a stack overflow.
    let deep = module(
        "f(n) = f(n+1) + 1
x = f(0)",
    );
    let mut ev = Evaluator::new(&deep, &NoNames, Limits::default());
    assert_eq!(ev.value("x").unwrap_err().code, Code::Limit);
    let bad = Module::check("P = a -> Q\n", &NoNames);
    let codes: Vec<_> = bad.diagnostics().iter().map(|d| (d.code, u32::from(d.range.start()))).collect();
    assert_eq!(codes, [(Code::Unresolved, 4), (Code::Unresolved, 9)]);
}

/// Names declared in different modules are different: two modules' `c`
/// (of different types) and `T` (with the same constructors) do not
/// share their values, a module's constructor is matched by its short name
/// inside the module, and a top-level function's parameter named like a
/// module's channel is a variable (as in the CSPm RoboTool and our export
/// generate: a `TIDS` and an event `e` per machine, `Delayable(e)`).
#[test]
fn modules_keep_their_names_apart() {
    let text = "
F(e) = e -> SKIP
module A
  exports
  datatype T = t0 | t1
  channel c : T
  channel e
  first(t0) = true
  first(_) = false
  P = c?x -> (if first(x) then e -> STOP else STOP)
  H = (c?x -> STOP) \\ {| c |}
endmodule
module B
  exports
  datatype T = t0
  channel c : T.{0, 1}
  channel e
  P = [] x : T @ c.x?y -> F(e)
  Ts = T
endmodule
";
    let a = lts(text, "A::P");
    assert_eq!(initials(&a, 0), ["A::c.A::t0", "A::c.A::t1"]);
    assert!(a.has_trace(&["A::c.A::t0", "A::e"]));
    assert!(!a.has_trace(&["A::c.A::t1", "A::e"]));
    let b = lts(text, "B::P");
    assert_eq!(initials(&b, 0), ["B::c.B::t0.0", "B::c.B::t0.1"]);
    assert!(b.has_trace(&["B::c.B::t0.1", "B::e"]));
    // A's hiding hides A's `c` only, all of it.
    let h = lts(text, "A::H");
    assert_eq!(initials(&h, 0), ["τ"]);
    let m = Module::check(text, &NoNames);
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    assert_eq!(ev.value("B::Ts").unwrap().to_string(), "{B::t0}");
}

#[test]
fn modules_includes_and_nested_inputs() {
    let text = "
module M
  X = {0, 1}
exports
  channel c : X
  P = c?x -> P
endmodule
datatype R = i_x.Bool
channel rr : R
Q = M::P
S = rr.i_x?b -> (if b then STOP else SKIP)
";
    // FDR prints a module's channel with its module.
    let q = lts(text, "Q");
    assert_eq!(initials(&q, 0), ["M::c.0", "M::c.1"]);
    let s = lts(text, "S");
    assert_eq!(initials(&s, 0), ["rr.i_x.false", "rr.i_x.true"]);
    let load = |f: &str| (f == "defs.csp").then(|| "channel d : {7}\nD = d.7 -> STOP".to_owned());
    let m = Module::check_with_includes("include \"defs.csp\"\nT = D ; SKIP", &NoNames, &load);
    assert!(m.is_ok(), "{:?}", m.diagnostics());
    let mut ev = Evaluator::new(&m, &NoNames, Limits::default());
    assert!(ev.lts("T").unwrap().has_trace(&["d.7"]));
    let missing = Module::check_with_includes("include \"nope.csp\"\n", &NoNames, &load);
    let d = &missing.diagnostics()[0];
    assert_eq!((d.code, d.message.as_str()), (Code::Unresolved, "cannot read the included file `nope.csp`"));
}

/// A host (the model) supplying a channel, a constant and a process family.
struct Host;

impl robosim_cspm::NameLookup for Host {
    fn lookup(&self, name: &str) -> Option<robosim_cspm::ExternalName> {
        use robosim_cspm::{ExternalName, Value};
        match name {
            "M::e" => Some(ExternalName::Channel(vec![vec![Value::Int(0), Value::Int(1)]])),
            "const_M_k" => Some(ExternalName::Value(Value::Int(1))),
            "M::O__" => Some(ExternalName::Process {
                arity: 1,
                build: std::rc::Rc::new(|args: &[Value]| {
                    let Value::Int(k) = args[0] else { return Err("expected an integer".to_owned()) };
                    let e = Value::Dot(vec![Value::Ctor("M::e".into()), Value::Int(k)].into());
                    // One state looping on `M::e.k`.
                    Ok(Lts {
                        events: vec![format!("M::e.{k}")],
                        event_values: vec![e],
                        initial: 0,
                        transitions: vec![vec![(Label::Event(0), 0)]],
                    })
                }),
            }),
            _ => None,
        }
    }
}

#[test]
fn names_and_processes_from_the_host() {
    let text = "Spec = M::O__(const_M_k) [[ M::e.1 <- M::e.0 ]]\nBad = M::O__(true)";
    let m = Module::check(text, &Host);
    assert!(m.is_ok(), "{:?}", m.diagnostics());
    let mut ev = Evaluator::new(&m, &Host, Limits::default());
    let l = ev.lts("Spec").unwrap();
    assert!(l.has_trace(&["M::e.0", "M::e.0"]));
    assert!(!l.has_trace(&["M::e.1"]));
    let e = ev.lts("Bad").unwrap_err();
    assert_eq!((e.code, e.message.as_str()), (Code::Runtime, "`M::O__`: expected an integer"));
}

/// RoboTool's names for a module `Mv` with events `go` and `done` of type
/// `InOut` (`in`/`out`) and `speed` carrying a number.
struct Robo;

impl robosim_cspm::NameLookup for Robo {
    fn lookup(&self, name: &str) -> Option<robosim_cspm::ExternalName> {
        use robosim_cspm::{ExternalName, Value};
        let inout = || vec![Value::Ctor("in".into()), Value::Ctor("out".into())];
        match name {
            "Mv::go" | "Mv::done" => Some(ExternalName::Channel(vec![inout()])),
            "Mv::speed" => Some(ExternalName::Channel(vec![inout(), vec![Value::Int(0), Value::Int(1)]])),
            "in" | "out" => Some(ExternalName::Value(Value::Ctor(name.into()))),
            _ => None,
        }
    }
}

#[test]
fn a_contract_over_model_events() {
    // The shape of the corpus's EBDS properties: `let PRE … within`.
    let text = "
All = {| Mv::go, Mv::done, Mv::speed |}
Spec = let
    PRE = |~| ev : diff(All, {Mv::go.in}) @ ev -> PRE
          |~| Mv::go.in -> CON
    CON = |~| ev : {| Mv::speed.out |} @ ev -> CON
          |~| Mv::done.out -> POS
    POS = CHAOS(All)
  within PRE
Last = Mv::speed.in?x -> (if x == 1 then Mv::done.out -> STOP else STOP)
";
    let m = Module::check(text, &Robo);
    assert!(m.is_ok(), "{:?}", m.diagnostics());
    let mut ev = Evaluator::new(&m, &Robo, Limits::default());
    let l = ev.lts("Spec").unwrap();
    assert!(l.has_trace(&["Mv::done.in", "Mv::go.in", "Mv::speed.out.1", "Mv::done.out", "Mv::go.out"]));
    assert!(!l.has_trace(&["Mv::go.in", "Mv::go.in"]));
    let last = ev.lts("Last").unwrap();
    assert!(last.has_trace(&["Mv::speed.in.1", "Mv::done.out"]));
    assert!(!last.has_trace(&["Mv::speed.in.0", "Mv::done.out"]));
}

/// FDR's maps, as libcspm defines them: `mapFromList` keeps the last pair
/// of a key, `mapUpdateMultiple` the first (a `foldr` of inserts),
/// `mapToList` is ordered by key, `Map(K, V)` is every partial map, maps
/// are ordered as submaps, and a missing key is an error.
#[test]
fn maps() {
    let text = "
m = mapFromList(<(2, 20), (1, 10), (2, 21)>)
u = mapUpdateMultiple(m, <(3, 30), (3, 31)>)
";
    let v = |e: &str| value(&format!("{text}\nr = {e}"), "r");
    assert_eq!(v("m"), "(| 1 => 10, 2 => 21 |)");
    assert_eq!(v("mapToList(m)"), "<(1, 10), (2, 21)>");
    assert_eq!(v("mapLookup(u, 3)"), "30");
    assert_eq!(v("mapMember(m, 1) and not mapMember(mapDelete(m, 1), 1)"), "true");
    assert_eq!(v("mapToList(mapUpdate(emptyMap, 0, true))"), "<(0, true)>");
    assert_eq!(v("(| 0 => 1, 0 => 2 |) == mapFromList(<(0, 2)>)"), "true");
    assert_eq!(v("card(Map({0, 1}, {0, 1}))"), "9");
    assert_eq!(v("Map({0}, {5})"), "{(| |), (| 0 => 5 |)}");
    assert_eq!(v("mapFromList(<(1, 0)>) < mapFromList(<(1, 1)>)"), "true");
    assert_eq!(v("(| 1 => 0 |) <= (| 1 => 0, 2 => 0 |) and not (| 1 => 1 |) <= (| 1 => 0 |)"), "true");
    assert!(v("mapLookup(m, 3)").contains("not in the map's domain"), "{}", v("mapLookup(m, 3)"));
}
