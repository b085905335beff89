//! The assertion languages: `.assertions` (§5.1) and `.rsa` (§5.2).

use super::exprs::expr;
use super::{block, name, qualified_name, type_, BlockKind, Named};
use crate::parser::{Parser, TokenSet};
use crate::SyntaxKind::*;

pub(crate) const ITEM_START: TokenSet = TokenSet::new(&[
    IMPORT_KW,
    ASSERTION_KW,
    CSP_KW,
    TIMED_KW,
    UNTIMED_KW,
    DEFAULT_KW,
    INSTANTIATE_KW,
    SIMULATION_KW,
    PACKAGE_KW,
]);

/// Words that start the probabilistic sub-language (§5.3), not reserved;
/// `prob property`, `constants` and `const` are parsed (`prob.rs`), the
/// others skipped.
const PROBABILISTIC: &[&str] = &["prob", "label", "formula", "rewards", "defs", "pmodules", "constants"];

pub(crate) fn assertion_file(p: &mut Parser<'_>) {
    if p.at(PACKAGE_KW) {
        super::package_decl(p);
    }
    while !p.at_eof() {
        item(p);
    }
}

fn is_sleec(p: &Parser<'_>, n: usize) -> bool {
    p.nth_at(n, IDENT) && p.nth_text(n) == "sleec"
}

fn item(p: &mut Parser<'_>) {
    match p.current() {
        IMPORT_KW => super::import(p),
        PACKAGE_KW => {
            p.error("`package` must be the first declaration of the file");
            super::package_decl(p);
        }
        TIMED_KW | UNTIMED_KW | DEFAULT_KW => match p.nth(1) {
            ASSERTION_KW => assertion(p),
            CSP_KW => csp_block(p),
            _ if is_sleec(p, 1) => sleec(p),
            _ => {
                let m = p.start();
                p.bump_any();
                p.error_expected("`assertion` or `csp` after the timing");
                m.complete(p, ERROR);
            }
        },
        ASSERTION_KW => assertion(p),
        CSP_KW => csp_block(p),
        INSTANTIATE_KW => {
            let m = p.start();
            p.bump(INSTANTIATE_KW);
            qualified_name(p, "a primitive type after `instantiate`");
            p.expect_msg(AS_KW, "expected `as` and a type in the instantiation");
            type_(p);
            m.complete(p, TYPE_INSTANTIATION);
        }
        SIMULATION_KW => simulation(p),
        IDENT if is_sleec(p, 0) => sleec(p),
        _ if super::prob::at_item(p) => super::prob::item(p),
        IDENT if PROBABILISTIC.contains(&p.nth_text(0)) => {
            unsupported(p, "probabilistic assertions (PRISM) are not supported; this item is skipped")
        }
        _ => {
            let m = p.start();
            p.error(format!(
                "unexpected {}: expected an assertion, a `csp` block, an `import`{}",
                p.found(),
                if p.is_robosim() { " or a `simulation`" } else { " or an `instantiate`" }
            ));
            loop {
                p.bump_balanced();
                if p.at_eof() || p.at_ts(ITEM_START) || is_sleec(p, 0) || super::prob::at_item(p) {
                    break;
                }
            }
            m.complete(p, ERROR);
        }
    }
}

fn sleec(p: &mut Parser<'_>) {
    let m = p.start();
    if !p.at(IDENT) {
        p.bump_any();
    }
    p.error("SLEEC assertions (`sleec assertion …`) belong to the SLEEC-TK extension and are not supported; this item is skipped");
    p.bump_any();
    p.eat(ASSERTION_KW);
    skip_to_item(p);
    m.complete(p, UNSUPPORTED_ITEM);
}

fn unsupported(p: &mut Parser<'_>, msg: &str) {
    let m = p.start();
    p.error(msg);
    p.bump_any();
    skip_to_item(p);
    m.complete(p, UNSUPPORTED_ITEM);
}

fn skip_to_item(p: &mut Parser<'_>) {
    while !p.at_eof() && !p.at_ts(ITEM_START) && !is_sleec(p, 0) && !super::prob::at_item(p) {
        p.bump_balanced();
    }
}

fn timing(p: &mut Parser<'_>) {
    if matches!(p.current(), TIMED_KW | UNTIMED_KW | DEFAULT_KW) {
        let m = p.start();
        p.bump_any();
        m.complete(p, TIMING);
    }
}

fn assertion(p: &mut Parser<'_>) {
    let m = p.start();
    let timed = matches!(p.current(), TIMED_KW | UNTIMED_KW | DEFAULT_KW);
    let timing_range = p.current_range();
    timing(p);
    p.bump(ASSERTION_KW);
    let n = name(p, "assertion");
    let what = Named { desc: "assertion", name: n };
    p.expect_msg(COLON, format_args!("expected `:` after the name of {what}"));
    if p.at(CLOCK_KW) {
        if timed {
            p.error_at(timing_range, "the clock-initialisation assertion takes no `timed`/`untimed`");
        }
        let b = p.start();
        p.bump(CLOCK_KW);
        qualified_name(p, "a clock after `clock`");
        p.expect_msg(IS_KW, "expected `is [not] initialised` after the clock");
        p.eat(NOT_KW);
        p.expect_msg(INITIALISED_KW, "expected `initialised`");
        b.complete(p, ASSERTION_BODY);
    } else {
        let s = p.start();
        qualified_name(
            p,
            format_args!("the subject of {what} (a module, controller, machine, operation or CSP process)"),
        );
        s.complete(p, ASSERTION_SUBJECT);
        assertion_body(p, what);
    }
    if p.at(IN_KW) {
        let sm = p.start();
        p.bump(IN_KW);
        p.expect_msg(THE_KW, "expected `the` after `in`");
        if matches!(
            p.current(),
            FAILURES_DIVERGENCES_MODEL_KW | FAILURES_MODEL_KW | TRACES_MODEL_KW | TICK_TOCK_MODEL_KW
        ) {
            p.bump_any();
        } else {
            p.error(format!(
                "expected a semantic model (`failures divergences model`, `failures model`, `traces model` or `tick-tock model`, words separated by one space), found {}",
                p.found()
            ));
            while p.at(IDENT) || p.at(MINUS) {
                p.bump_any();
            }
        }
        sm.complete(p, SEMANTIC_MODEL);
    }
    if p.at(WITH_KW) {
        param_assignments(p);
    }
    p.eat(DOT);
    m.complete(p, ASSERTION);
}

fn assertion_body(p: &mut Parser<'_>, what: Named<'_>) {
    let b = p.start();
    match p.current() {
        IS_KW => {
            p.bump(IS_KW);
            let not = p.eat(NOT_KW);
            match p.current() {
                DEADLOCK_FREE_KW | DIVERGENCE_FREE_KW | DETERMINISTIC_KW | TIMELOCK_FREE_KW => p.bump_any(),
                SCHEDULABLE_KW => p.bump_any(),
                REACHABLE_KW => {
                    p.bump(REACHABLE_KW);
                    p.expect_msg(IN_KW, "expected `in` and a machine after `reachable`");
                    qualified_name(p, "the machine in which the state is reachable");
                }
                EQUAL_KW => {
                    if !not {
                        p.error("write `is not equal to`, or `equals` for equivalence");
                    }
                    p.bump(EQUAL_KW);
                    p.expect_msg(TO_KW, "expected `to` after `equal`");
                    qualified_name(p, "the element compared with");
                }
                _ => p.error(format!(
                    "expected a property after `is`: `deadlock-free`, `divergence-free`, `deterministic`, `timelock-free`{}, `reachable in`{}; found {}",
                    if p.is_robosim() { ", `schedulable`" } else { "" },
                    if not { " or `equal to`" } else { "" },
                    p.found()
                )),
            }
        }
        TERMINATES_KW => p.bump(TERMINATES_KW),
        DOES_KW => {
            p.bump(DOES_KW);
            p.expect_msg(NOT_KW, "expected `not` after `does`");
            if p.eat(REFINE_KW) {
                qualified_name(p, "the element refined");
            } else if !p.eat(TERMINATE_KW) {
                p.error_expected("`refine` or `terminate` after `does not`");
            }
        }
        REFINES_KW | EQUALS_KW => {
            let kw = p.nth_text(0);
            p.bump_any();
            qualified_name(p, format_args!("the element after `{kw}`"));
        }
        _ => p.error(format!(
            "expected `is`, `refines`, `equals`, `does not` or `terminates` after the subject of {what}, found {}",
            p.found()
        )),
    }
    b.complete(p, ASSERTION_BODY);
}

fn at_param_start(p: &Parser<'_>, n: usize) -> bool {
    matches!(p.nth(n), CONSTANT_KW | PARAMETER_KW | CYCLE_DEF_KW)
}

/// `with A`, `with A and B`, `with A, B and C`, `with A, B, and C`.
fn param_assignments(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(WITH_KW);
    param(p);
    let mut count = 1;
    let mut saw_and = false;
    loop {
        let sep = p.current_range();
        let is_and = if p.at(COMMA) && at_param_start(p, 1) {
            p.bump(COMMA);
            false
        } else if p.at(COMMA) && p.nth_at(1, AND_KW) {
            p.bump(COMMA);
            p.bump(AND_KW);
            true
        } else if p.at(AND_KW) {
            p.bump(AND_KW);
            true
        } else {
            break;
        };
        if saw_and {
            p.error_at(sep, "only the last parameter is introduced by `and`: write `A, B and C`");
        }
        saw_and |= is_and;
        param(p);
        count += 1;
    }
    if count >= 2 && !saw_and {
        p.error("`and` is required before the last parameter: write `A and B` or `A, B and C`");
    }
    m.complete(p, PARAM_ASSIGNMENTS);
}

fn param(p: &mut Parser<'_>) {
    let m = p.start();
    let kind = match p.current() {
        CONSTANT_KW => {
            p.bump(CONSTANT_KW);
            super::name_ref(p, "a constant name after `constant`");
            CONSTANT_PARAM
        }
        PARAMETER_KW => {
            p.bump(PARAMETER_KW);
            super::name_ref(p, "a parameter name after `parameter`");
            PARAMETER_PARAM
        }
        CYCLE_DEF_KW => {
            p.bump(CYCLE_DEF_KW);
            CYCLE_DEF_PARAM
        }
        _ => {
            m.abandon(p);
            p.error_expected(if p.is_robosim() {
                "`constant`, `parameter` or `cycleDef`"
            } else {
                "`constant` or `parameter`"
            });
            return;
        }
    };
    p.expect_msg(OF_KW, "expected `of` and the element that declares it");
    qualified_name(p, "the element after `of`");
    let s = p.start();
    match p.current() {
        ASSIGNED_KW => p.bump(ASSIGNED_KW),
        SET_KW => {
            p.bump(SET_KW);
            p.expect_msg(TO_KW, "expected `to` after `set`");
        }
        WITH_KW => {
            p.bump(WITH_KW);
            p.expect_msg(VALUE_KW, "expected `value` after `with`");
        }
        _ => p.error_expected("`set to`, `assigned` or `with value`"),
    }
    s.complete(p, SETTER);
    expr(p);
    m.complete(p, kind);
}

fn csp_block(p: &mut Parser<'_>) {
    let m = p.start();
    timing(p);
    p.bump(CSP_KW);
    name(p, "CSP process");
    if p.at(ASSOCIATED_KW) {
        let a = p.start();
        p.bump(ASSOCIATED_KW);
        p.expect_msg(TO_KW, "expected `to` after `associated`");
        qualified_name(p, "an element after `associated to`");
        while p.eat(COMMA) {
            qualified_name(p, "an element");
        }
        a.complete(p, ASSOCIATED_TO);
    }
    p.expect_msg(CSP_TEXT, "expected the CSP text `csp-begin … csp-end`");
    m.complete(p, CSP_BLOCK);
}

fn simulation(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(SIMULATION_KW);
    let n = name(p, "simulation");
    p.expect_msg(OF_KW, "expected `of` and the simulated element after the simulation's name");
    qualified_name(p, "the simulated module, controller or machine");
    let what = Named { desc: "simulation", name: n };
    p.blocks.push(super::Block { kind: BlockKind::File, what: Named { desc: "file", name: None } });
    block(p, BlockKind::Simulation, what);
    p.blocks.pop();
    m.complete(p, SIMULATION);
}
