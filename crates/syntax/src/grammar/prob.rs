//! The probabilistic items of `.assertions` files (syntax.md §5.3), which
//! RoboTool checks with PRISM: `const t : T`, `constants NAME : path set
//! to v, …` and `prob property NAME : formula [with constant(s) …]`. The
//! formula language (`PExpr`) has its own operators, written as ordinary
//! words (`Prob`, `Finally`, `Until`, …): they are recognised here by their
//! text and stay identifiers elsewhere (the spec advises not to reserve
//! them). The other probabilistic items (`label`, `formula`, `rewards`,
//! `defs`, `pmodules`, `prob generate path`) are still skipped.

use super::exprs::{binop_level, expr};
use super::{name, name_ref, qualified_name, type_};
use crate::parser::{CompletedMarker, Parser};
use crate::SyntaxKind::*;

/// Whether the current item is one this module parses.
pub(crate) fn at_item(p: &Parser<'_>) -> bool {
    p.at(CONST_KW)
        || (p.at(IDENT) && p.nth_text(0) == "constants")
        || (p.at(IDENT) && p.nth_text(0) == "prob" && p.nth_at(1, IDENT) && p.nth_text(1) == "property")
}

/// One item (the caller checked [`at_item`]).
pub(crate) fn item(p: &mut Parser<'_>) {
    if p.at(CONST_KW) {
        let m = p.start();
        p.bump(CONST_KW);
        let n = name(p, "property constant");
        if p.expect_msg(COLON, format_args!("expected `:` and a type after `const {}`", n.unwrap_or_default())) {
            type_(p);
        }
        m.complete(p, PROB_CONST);
    } else if p.nth_text(0) == "constants" {
        let m = p.start();
        p.bump(IDENT);
        name(p, "block of constants");
        p.expect_msg(COLON, "expected `:` and the constants' values after the block's name");
        configs(p);
        m.complete(p, PROB_CONSTANTS);
    } else {
        property(p);
    }
}

/// `prob property NAME : formula [with constant(s) (configs | NAME)]`.
fn property(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(IDENT);
    p.bump(IDENT);
    name(p, "probabilistic property");
    p.expect_msg(COLON, "expected `:` and a formula after the property's name");
    if pexpr(p).is_none() {
        p.error_expected("a formula");
    }
    if p.at(WITH_KW) && (p.nth_at(1, CONSTANT_KW) || (p.nth_at(1, IDENT) && p.nth_text(1) == "constants")) {
        let w = p.start();
        p.bump(WITH_KW);
        p.bump_any();
        // A block's name alone, or the values themselves.
        if p.at(IDENT) && !p.nth_at(1, COLON2) && !is_setter(p, 1) && !p.nth_at(1, OF_KW) {
            name_ref(p, "a block of constants");
        } else {
            configs(p);
        }
        w.complete(p, PROB_WITH_CONSTANTS);
    }
    if p.at(WITH_KW) {
        p.error("`with definitions`, `with modules` and `with cmdoptions` are not supported here");
    }
    p.eat(DOT);
    m.complete(p, PROB_PROPERTY);
}

fn is_setter(p: &Parser<'_>, n: usize) -> bool {
    matches!(p.nth(n), SET_KW | ASSIGNED_KW) || (p.nth_at(n, WITH_KW) && p.nth_at(n + 1, VALUE_KW))
}

/// `C1, C2 and C3` (also `C1, C2, and C3`).
fn configs(p: &mut Parser<'_>) {
    config(p);
    loop {
        if p.at(COMMA) && p.nth_at(1, AND_KW) {
            p.bump(COMMA);
            p.bump(AND_KW);
        } else if p.at(COMMA) || p.at(AND_KW) {
            p.bump_any();
        } else {
            break;
        }
        config(p);
    }
}

/// `[constant] path [of path] set to value`.
fn config(p: &mut Parser<'_>) {
    let m = p.start();
    p.eat(CONSTANT_KW);
    qualified_name(p, "the constant given a value");
    if p.eat(OF_KW) {
        qualified_name(p, "the element after `of`");
    }
    let s = p.start();
    match p.current() {
        SET_KW => {
            p.bump(SET_KW);
            p.expect_msg(TO_KW, "expected `to` after `set`");
        }
        ASSIGNED_KW => p.bump(ASSIGNED_KW),
        WITH_KW if p.nth_at(1, VALUE_KW) => {
            p.bump(WITH_KW);
            p.bump(VALUE_KW);
        }
        _ => p.error_expected("`set to` and a value"),
    }
    s.complete(p, SETTER);
    expr(p);
    m.complete(p, PROB_CONFIG);
}

fn word(p: &Parser<'_>, n: usize, words: &[&str]) -> bool {
    p.nth_at(n, IDENT) && words.contains(&p.nth_text(n))
}

const UNTIL: &[&str] = &["Until", "until", "Release"];
const TEMPORAL: &[&str] = &["Finally", "Globally", "Next"];
const PATH_QUANT: &[&str] = &["Exists", "Forall"];

/// A formula: temporal `Until`/`Release` over the boolean levels.
pub(crate) fn pexpr(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    p.nested(|p| {
        let mut lhs = pbin(p, 1)?;
        let mut wraps = 0;
        while p.depth_allows(1) && (word(p, 0, UNTIL) || (word(p, 0, &["Weak"]) && word(p, 1, UNTIL))) {
            p.add_depth(1);
            wraps += 1;
            let m = lhs.precede(p);
            if p.nth_text(0) == "Weak" {
                p.bump(IDENT);
            }
            p.bump(IDENT);
            if pbin(p, 1).is_none() {
                p.error_expected("a formula after `Until`");
            }
            lhs = m.complete(p, PROB_UNTIL);
        }
        p.add_depth(-wraps);
        Some(lhs)
    })
}

/// Binary operators of level at least `min` (the levels of ordinary
/// expressions: `iff`, `=>`, `\/`, `/\`, comparisons, arithmetic).
fn pbin(p: &mut Parser<'_>, min: u8) -> Option<CompletedMarker> {
    let mut lhs = pprefix(p)?;
    let mut wraps = 0;
    while let Some(op) = binop_level(p.current()).filter(|op| *op >= min && p.current() != IN_KW) {
        if !p.depth_allows(1) {
            break;
        }
        p.add_depth(1);
        wraps += 1;
        let m = lhs.precede(p);
        p.bump_any();
        if p.nested(|p| pbin(p, op + 1)).is_none() {
            p.error_expected("an operand");
        }
        lhs = m.complete(p, BIN_EXPR);
    }
    p.add_depth(-wraps);
    Some(lhs)
}

fn pprefix(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    match p.current() {
        NOT_KW | MINUS => {
            let m = p.start();
            let lvl = if p.at(NOT_KW) { 6 } else { 15 };
            p.bump_any();
            if p.nested(|p| pbin(p, lvl)).is_none() {
                p.error_expected("an operand");
            }
            Some(m.complete(p, PREFIX_EXPR))
        }
        IDENT if word(p, 0, TEMPORAL) => {
            let m = p.start();
            p.bump(IDENT);
            if p.nested(|p| pbin(p, 1)).is_none() {
                p.error_expected("a formula");
            }
            Some(m.complete(p, PROB_TEMPORAL))
        }
        _ => patom(p),
    }
}

fn patom(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let m = p.start();
    match p.current() {
        INT_NUMBER | FLOAT_NUMBER | TRUE_KW | FALSE_KW => {
            p.bump_any();
            Some(m.complete(p, LITERAL))
        }
        L_PAREN => {
            p.bump(L_PAREN);
            if pexpr(p).is_none() {
                p.error_expected("a formula");
            }
            p.expect_msg(R_PAREN, "expected `)`");
            Some(m.complete(p, PAREN_EXPR))
        }
        IDENT if p.nth_text(0) == "Prob" => {
            p.bump(IDENT);
            bound(p);
            p.eat(OF_KW);
            bracketed(p);
            Some(m.complete(p, PROB_QUERY))
        }
        IDENT if word(p, 0, PATH_QUANT) => {
            p.bump(IDENT);
            bracketed(p);
            Some(m.complete(p, PROB_PATH_QUANT))
        }
        IDENT if p.nth_text(0) == "deadlock" && !p.nth_at(1, COLON2) => {
            p.bump(IDENT);
            Some(m.complete(p, PROB_DEADLOCK))
        }
        IDENT => {
            qualified_name(p, "a name");
            Some(m.complete(p, PROB_PATH))
        }
        _ => {
            m.abandon(p);
            None
        }
    }
}

/// `=?`, `min=?`, `max=?` or a comparison with a bound (`>= 0.9`).
fn bound(p: &mut Parser<'_>) {
    let m = p.start();
    if word(p, 0, &["min", "max"]) {
        p.bump(IDENT);
    }
    match p.current() {
        EQ if p.nth_at(1, QUESTION) => {
            p.bump(EQ);
            p.bump(QUESTION);
        }
        LT | LTEQ | GT | GTEQ => {
            p.bump_any();
            if patom(p).is_none() {
                p.error_expected("a probability bound");
            }
        }
        _ => p.error_expected("`=?` or a bound such as `>= 0.9` after `Prob`"),
    }
    m.complete(p, PROB_BOUND);
}

/// `[ formula ]`.
fn bracketed(p: &mut Parser<'_>) {
    if !p.expect_msg(L_BRACK, "expected `[` and a path formula") {
        return;
    }
    if pexpr(p).is_none() {
        p.error_expected("a path formula");
    }
    p.expect_msg(R_BRACK, "expected `]`");
}
