//! The CSPm text of the library RoboTool's generated script includes before
//! an assertion file's `csp` blocks: its tock-CSP operators (`StartBy`,
//! `EDeadline`, `TimedInterrupt`, …), its state helpers (`CRUN`, `SStop`,
//! `SHARE_WAIT`, …) and its core functions (`LSeq`, `no_zero_div`, …).
//!
//! One definition serves every back end: the CSPm bridge of the model
//! checker loads these definitions into a block's script, and the CSPm
//! export writes them out, so a block means the same in both and what it
//! means in RoboTool + FDR. Each definition is RoboTool's (the reference's
//! `csp-gen/timed/defs/core_timed_defs.csp`, `state_timed_defs.csp`,
//! `state_defs.csp` and `core_defs.csp`), laid out and commented here.
//!
//! RoboTool writes two scripts (robotool-facts RT-8): the timed one
//! includes the tock-CSP library and the timed state helpers; the untimed
//! one only the untimed state helpers (`CRUN(A)` is `RUN(A)` there) and the
//! core functions. `tock` itself is declared by the script's user (the
//! bridge's model names, the export's shared file), not here. RoboTool's
//! `model_shifting` module (its tick-tock encoding, a parameterised module
//! the CSPm engine does not evaluate) is not part of this library.

/// Which of RoboTool's two scripts a definition is in (RT-8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CspScript {
    /// Both the timed and the untimed script.
    Both,
    /// The timed script only.
    Timed,
    /// The untimed script only.
    Untimed,
}

impl CspScript {
    /// Whether a definition of this script is in the timed (`true`) or the
    /// untimed script.
    pub fn in_script(self, timed: bool) -> bool {
        match self {
            CspScript::Both => true,
            CspScript::Timed => timed,
            CspScript::Untimed => !timed,
        }
    }
}

/// One definition of the library: the names it defines and its CSPm text
/// (a whole declaration, `Timed(OneStep) { … }` included when RoboTool
/// writes it in a timed section).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CspDef {
    /// The names the text defines (its first one is the main one).
    pub names: &'static [&'static str],
    /// The script it belongs to.
    pub script: CspScript,
    /// The CSPm text (ends with a newline).
    pub text: &'static str,
}

use CspScript::{Both, Timed, Untimed};

/// Every definition, in an order that reads top-down.
pub const DEFINITIONS: &[CspDef] = &[
    // Timed sections whose events take no time by themselves.
    CspDef { names: &["OneStep"], script: Timed, text: "OneStep(_) = 0\n" },
    // A timelock: neither events nor time (STOP outside a timed section).
    CspDef { names: &["USTOP"], script: Timed, text: "USTOP = STOP\n" },
    CspDef { names: &["TSKIP"], script: Timed, text: "Timed(OneStep) {\nTSKIP = SKIP\n}\n" },
    CspDef {
        names: &["WAIT_INTERVAL"],
        script: Timed,
        text: "Timed(OneStep) {\nWAIT_INTERVAL(S__) = |~| x__ : S__ @ WAIT(x__)\n}\n",
    },
    // P must perform its first event within d time units.
    CspDef {
        names: &["StartBy"],
        script: Timed,
        text: "Timed(OneStep) {\nStartBy(P__, d__) = P__ [] (WAIT(d__); USTOP)\n}\n",
    },
    // P must terminate within d time units.
    CspDef {
        names: &["EndBy"],
        script: Timed,
        text: "Timed(OneStep) {\nEndBy(P__, d__) = P__ /\\ (WAIT(d__); USTOP)\n}\n",
    },
    CspDef { names: &["Deadline"], script: Timed, text: "Timed(OneStep) {\nDeadline(P__, d__) = EndBy(P__, d__)\n}\n" },
    // The event e within d time units, then termination.
    CspDef {
        names: &["EDeadline"],
        script: Timed,
        text: "Timed(OneStep) {\nEDeadline(e__, d__) = e__ -> SKIP [] (WAIT(d__); USTOP)\n}\n",
    },
    // P for exactly d time units (internal actions first), then termination.
    CspDef {
        names: &["TimedInterrupt"],
        script: Timed,
        text: "Timed(OneStep) {\nTimedInterrupt(P__, d__) = timed_priority(P__ /+ Events +\\ RT__(d__))\n}\n",
    },
    CspDef {
        names: &["TimeOut"],
        script: Timed,
        text: "Timed(OneStep) {\nTimeOut(P__, d__, Q__) =\n  (P__ /+ Events +\\ ((TimedInterrupt(Some__, d__); STOP); RUN(Events)))\n  [] (WAIT(d__); Q__)\n}\n",
    },
    // `TimeOut(P, 1, Q)` and `TimedInterrupt(P, 1)` for a P without an
    // initial deadline (usable in recursion).
    CspDef {
        names: &["TimeOut_1"],
        script: Timed,
        text: "TimeOut_1(P__, Q__) = (USTOP [+ {tock} +] P__) [] (tock -> Q__)\n",
    },
    CspDef {
        names: &["TimedInterrupt_1"],
        script: Timed,
        text: "TimedInterrupt_1(P__) = (USTOP [+ {tock} +] P__) /\\ (tock -> TSKIP)\n",
    },
    CspDef {
        names: &["TimedInterruptSeq"],
        script: Timed,
        text: "TimedInterruptSeq(e__, d__, Q__) =\n  let TT(n__) = if n__ < d__ then TimeOut_1(e__ -> SKIP, TT(n__ + 1)) else Q__\n  within TT(0)\n",
    },
    // CHAOS that may also let time pass, timelock or deadlock.
    CspDef {
        names: &["TCHAOS"],
        script: Timed,
        text: "TCHAOS(S__) = CHAOS(S__) /\\ (USTOP |~| tock -> TCHAOS(S__))\n",
    },
    // n time units outside timed sections, then termination at once.
    CspDef {
        names: &["wait"],
        script: Timed,
        text: "wait(n__) = if n__ > 0 then tock -> wait(n__ - 1) else SKIP\n",
    },
    CspDef {
        names: &["RT__"],
        script: Timed,
        text: "RT__(d__) = if d__ > 0 then RUN(diff(Events, {tock})) /\\ tock -> RT__(d__ - 1) else SKIP\n",
    },
    CspDef { names: &["Some__"], script: Timed, text: "Some__ = [] x__ : Events @ x__ -> SKIP\n" },
    CspDef { names: &["SKIP_ANYTIME"], script: Timed, text: "SKIP_ANYTIME = SKIP |~| tock -> SKIP_ANYTIME\n" },
    CspDef {
        names: &["clock_type_max", "clock_type_seq_max"],
        script: Timed,
        text: "clock_type_max(S__) = clock_type_seq_max(seq(S__), 0)\nclock_type_seq_max(<>, x__) = x__\nclock_type_seq_max(<elem__>^xs__, x__) =\n  if elem__ > x__ then clock_type_seq_max(xs__, elem__) else clock_type_seq_max(xs__, x__)\n",
    },
    CspDef {
        names: &["clock_type_plus"],
        script: Timed,
        text: "clock_type_plus(x__, y__, t__) = if member(x__ + y__, t__) then x__ + y__ else x__\n",
    },
    CspDef { names: &["DoClockReset"], script: Timed, text: "DoClockReset(CS__) = ||| c__ : CS__ @ c__ -> SKIP\n" },
    // RoboTool's encoding of the tick-tock model over the events `Sigma`
    // (`instance M = model_shifting(Sigma)`, then `M::TT(P)`): refusals
    // as `ref.x` events. A parameterised module: the CSPm engine reads it
    // but does not evaluate it, the export writes it for FDR.
    CspDef {
        names: &["model_shifting"],
        script: Timed,
        text: "module model_shifting(Sigma)
external prioritise
external prioritisepo
transparent sbisim
channel ref : union(Sigma, {tock, tick})
channel acc : union(Sigma, {tock, tick})
channel stab
channel tick
-- Each event has priority over its refusal.
order = { (x, ref.x) | x : union(Sigma, {tock, tick}) }
C1(P) = sbisim(prioritisepo(P ||| RUN({| ref, stab |}), union(Sigma, {| ref, tock, tick |}), order, union(Sigma, {tock, tick})))
C2(P) = C1(P) [| union(Sigma, {| ref, stab, tock, tick |}) |] Sem
Sem = ([] x : union(Sigma, {tock, tick}) @ x -> Sem) [] (ref?x -> Ref) [] (stab -> Ref)
Ref = (ref?x -> Ref) [] (stab -> Ref) [] tock -> Sem
exports
-- Refusal testing.
RT(P) = C1(P ; tick -> SKIP)
C3(P) = C2(prioritise(P, <{}, {tock}>) ; tick -> SKIP)
-- Tick-tock.
TT(P) = C3(P)
endmodule
",
    },
    // State helpers: `share__` lets other threads access shared variables.
    CspDef { names: &["share__", "timed_share__"], script: Timed, text: "channel share__, timed_share__\n" },
    CspDef { names: &["share__"], script: Untimed, text: "channel share__\n" },
    CspDef { names: &["CRUN"], script: Timed, text: "CRUN(x__) = RUN(union(x__, {tock}))\n" },
    CspDef { names: &["CRUN"], script: Untimed, text: "CRUN(x__) = RUN(x__)\n" },
    CspDef { names: &["TRUN"], script: Timed, text: "TRUN(x__) = CRUN(x__)\n" },
    CspDef { names: &["SStop"], script: Timed, text: "SStop = CRUN({| share__ |})\n" },
    CspDef { names: &["SStop"], script: Untimed, text: "SStop = RUN({share__})\n" },
    CspDef {
        names: &["share__choice"],
        script: Timed,
        text: "Timed(OneStep) {\nshare__choice(x__) = x__ [] share__ -> share__choice(x__)\n}\n",
    },
    CspDef {
        names: &["share__choice"],
        script: Untimed,
        text: "share__choice(x__) = x__ [] share__ -> share__choice(x__)\n",
    },
    CspDef {
        names: &["SHARE_WAIT"],
        script: Timed,
        text: "SHARE_WAIT(d__) = (if d__ > 0 then tock -> SHARE_WAIT(d__ - 1) else TSKIP) [] share__ -> SHARE_WAIT(d__)\n",
    },
    CspDef {
        names: &["SHARE_WAIT_INTERVAL"],
        script: Timed,
        text: "SHARE_WAIT_INTERVAL(S__) = |~| x__ : S__ @ SHARE_WAIT(x__)\n",
    },
    // Core functions: bounded sequences (`core_string` is `LSeq(Char, 2)`).
    CspDef {
        names: &["LSeq"],
        script: Both,
        text: "LSeq(X, 0) = {<>}\nLSeq(X, n) = let s = LSeq(X, n - 1) within union(s, { <x>^xs | x <- X, xs <- s })\n",
    },
    CspDef {
        names: &["ILSeq"],
        script: Both,
        text: "ILSeq(X, 0) = {<>}\nILSeq(X, n) = let s = ILSeq(X, n - 1) within union(s, { <x>^xs | x <- X, xs <- s, not elem(x, xs) })\n",
    },
    CspDef {
        names: &["calc_type_max", "calc_type_seq_max"],
        script: Both,
        text: "calc_type_max(S) = calc_type_seq_max(seq(S), 0)\ncalc_type_seq_max(<>, x__) = x__\ncalc_type_seq_max(<elem__>^xs, x__) =\n  if elem__ > x__ then calc_type_seq_max(xs, elem__) else calc_type_seq_max(xs, x__)\n",
    },
    CspDef {
        names: &["calc_type_min", "calc_type_seq_min"],
        script: Both,
        text: "calc_type_min(S) = calc_type_seq_min(seq(S), calc_type_max(S))\ncalc_type_seq_min(<>, x__) = x__\ncalc_type_seq_min(<elem__>^xs, x__) =\n  if elem__ < x__ then calc_type_seq_min(xs, elem__) else calc_type_seq_min(xs, x__)\n",
    },
    // RT-6: a divisor of 0 counts as 1.
    CspDef { names: &["no_zero_div"], script: Both, text: "no_zero_div(0) = 1\nno_zero_div(x__) = x__\n" },
    // Relations and functions as sets of pairs, over FDR's maps.
    // Every relation between s1 and s2 (every set of pairs).
    CspDef {
        names: &["Relation"],
        script: Both,
        text: "Relation(s1, s2) = Set({ (x, y) | x <- s1, y <- s2 })\n",
    },
    // Every total function from s1 to s2: the relations that a map keeps
    // whole (one pair per argument) and that cover s1.
    CspDef {
        names: &["Function"],
        script: Both,
        text: "Function(s1, s2) = { r | r <- Relation(s1, s2), set(mapToList(mapFromList(seq(r)))) == r, { x | (x, y) <- r } == s1 }\n",
    },
    CspDef { names: &["funcToSet"], script: Both, text: "funcToSet(f, s) = { (x, f(x)) | x <- s }\n" },
    CspDef { names: &["callFunc"], script: Both, text: "callFunc(f, x) = mapLookup(mapFromList(seq(f)), x)\n" },
];

/// The definitions of the timed (`true`) or untimed script, in order.
pub fn definitions(timed: bool) -> impl Iterator<Item = &'static CspDef> {
    DEFINITIONS.iter().filter(move |d| d.script.in_script(timed))
}

/// Whether `name` is defined by the library of the timed (`true`) or the
/// untimed script.
pub fn defines(name: &str, timed: bool) -> bool {
    definitions(timed).any(|d| d.names.contains(&name))
}

/// The opening of RoboTool's timed sections.
const TIMED_OPEN: &str = "Timed(OneStep) {\n";

/// The whole library of the timed (`true`) or untimed script, as CSPm
/// (consecutive timed definitions in one `Timed(OneStep)` section).
pub fn text(timed: bool) -> String {
    let mut out = String::new();
    let mut open = false;
    for d in definitions(timed) {
        match d.text.strip_prefix(TIMED_OPEN).and_then(|t| t.strip_suffix("}\n")) {
            Some(inner) => {
                if !open {
                    out.push_str(TIMED_OPEN);
                    open = true;
                }
                out.push_str(inner);
            }
            None => {
                if open {
                    out.push_str("}\n");
                    open = false;
                }
                out.push_str(d.text);
            }
        }
    }
    if open {
        out.push_str("}\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each script defines each name once.
    #[test]
    fn names_are_unique_per_script() {
        for timed in [true, false] {
            let mut seen = std::collections::HashSet::new();
            for d in definitions(timed) {
                for n in d.names {
                    assert!(seen.insert(*n), "{n} defined twice (timed: {timed})");
                }
            }
        }
    }

    /// The library is valid CSPm for the language crate (with `tock`
    /// declared, as its users do), and its timed definitions are gathered
    /// in sections.
    #[test]
    fn the_library_is_valid_cspm() {
        for timed in [true, false] {
            let text = format!("channel tock\n{}", super::text(timed));
            let m = robosim_cspm::Module::check(&text, &robosim_cspm::NoNames);
            let errors: Vec<_> =
                m.diagnostics().iter().filter(|d| d.severity == robosim_cspm::Severity::Error).collect();
            assert!(errors.is_empty(), "timed: {timed}: {errors:?}");
        }
        assert_eq!(super::text(true).matches("Timed(OneStep)").count(), 2);
        assert_eq!(super::text(false).matches("Timed(OneStep)").count(), 0);
    }

    /// The value of `expr` with the library of both scripts loaded.
    fn value(expr: &str) -> Vec<String> {
        [true, false]
            .map(|timed| {
                let text = format!("channel tock\n{}\nr = {expr}\n", super::text(timed));
                let m = robosim_cspm::Module::check(&text, &robosim_cspm::NoNames);
                let mut ev = robosim_cspm::Evaluator::new(&m, &robosim_cspm::NoNames, Default::default());
                ev.value("r").map(|v| v.to_string()).unwrap_or_else(|e| e.to_string())
            })
            .to_vec()
    }

    /// RoboTool's relations and functions as sets of pairs (its
    /// `core_defs.csp`): every relation, every total function, a function
    /// applied and tabulated.
    #[test]
    fn relations_and_functions() {
        let both = |s: &str| vec![s.to_string(), s.to_string()];
        assert_eq!(value("Relation({0}, {1, 2})"), both("{{}, {(0, 1)}, {(0, 1), (0, 2)}, {(0, 2)}}"));
        assert_eq!(value("card(Relation({0, 1}, {0, 1}))"), both("16"));
        // Total functions only: one pair per argument, every argument.
        assert_eq!(value("Function({0, 1}, {5})"), both("{{(0, 5), (1, 5)}}"));
        assert_eq!(value("card(Function({0, 1}, {0, 1, 2}))"), both("9"));
        assert_eq!(value("Function({}, {1})"), both("{{}}"));
        assert_eq!(value("callFunc({(0, 1), (1, 0)}, 1)"), both("0"));
        assert_eq!(value("funcToSet(\\ x @ x * 2, {1, 2})"), both("{(1, 2), (2, 4)}"));
        // Outside its domain, FDR's `mapLookup` error.
        assert!(
            value("callFunc({(0, 1)}, 2)")[0].contains("not in the map's domain"),
            "{:?}",
            value("callFunc({(0, 1)}, 2)")
        );
    }
}
