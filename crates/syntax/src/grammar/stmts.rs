//! Statements (§2.14, RoboSim §3.1, decisions §4.1–4.2), communications
//! (§2.13) and transitions (§2.12, RoboSim §3.1).

use super::exprs::{call_exp, expr};
use super::{arg_list, member_at, name, name_ref, qualified_name, simple_name_ref, STOP};
use crate::parser::{CompletedMarker, Parser};
use crate::SyntaxKind::{self, *};

/// A statement sequence `s1; s2; …`.
pub(crate) fn stmt(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    p.nested(|p| {
        let first = timed_stmt(p)?;
        if !p.at(SEMI) {
            return Some(first);
        }
        let m = first.precede(p);
        while p.at(SEMI) {
            let semi = p.current_range();
            p.bump(SEMI);
            if at_stmt_start(p) {
                timed_stmt(p);
            } else if matches!(p.current(), R_CURLY | R_PAREN | END_KW | ELSE_KW | EOF) || p.at_ts(STOP) {
                p.error_at(semi, "`;` separates statements and cannot end them: remove this `;`");
                break;
            } else {
                p.error_expected("a statement after `;`");
                break;
            }
        }
        Some(m.complete(p, SEQ_STMT))
    })
}

/// Whether the current token can start a statement in this language.
pub(crate) fn at_stmt_start(p: &Parser<'_>) -> bool {
    match p.current() {
        IF_KW | SKIP_KW | HASH | L_PAREN | IDENT | SEND_KW | WAIT_KW => true,
        EXEC_KW | DOLLAR => p.is_robosim(),
        _ => false,
    }
}

fn timed_stmt(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let s = basic_stmt(p)?;
    if p.at(DEADLINE_OPEN) {
        let m = s.precede(p);
        deadline(p, DEADLINE);
        return Some(m.complete(p, TIMED_STMT));
    }
    Some(s)
}

fn deadline(p: &mut Parser<'_>, kind: SyntaxKind) {
    let m = p.start();
    p.bump(DEADLINE_OPEN);
    expr(p);
    p.expect_msg(R_CURLY, "expected `}` to close the deadline `<{ … }`");
    m.complete(p, kind);
}

fn basic_stmt(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let m = p.start();
    let rs = p.is_robosim();
    let kind = match p.current() {
        IF_KW => {
            p.bump(IF_KW);
            expr(p);
            p.expect_msg(THEN_KW, "expected `then` after the condition of `if`");
            stmt(p);
            if p.eat(ELSE_KW) {
                stmt(p);
            }
            p.expect_msg(END_KW, "expected `end` to close the `if` statement");
            IF_STMT
        }
        SKIP_KW => {
            p.bump(SKIP_KW);
            SKIP_STMT
        }
        WAIT_KW => {
            if rs {
                p.error("`wait` is not available in RoboSim: count cycles with a clock and `since` instead");
            }
            p.bump(WAIT_KW);
            p.expect_msg(L_PAREN, "expected `(` after `wait`");
            expr(p);
            p.expect(R_PAREN);
            WAIT_STMT
        }
        HASH => {
            clock_reset(p);
            CLOCK_RESET_STMT
        }
        L_PAREN => {
            p.bump(L_PAREN);
            stmt(p);
            p.expect_msg(R_PAREN, "expected `)` to close the parenthesised statement");
            PAR_STMT
        }
        SEND_KW => {
            if rs {
                p.error("`send` is not available in RoboSim: write outputs as `$e`, `$e!v` or `$e.v`");
            }
            p.bump(SEND_KW);
            communication(p);
            COMM_STMT
        }
        EXEC_KW if rs => {
            p.bump(EXEC_KW);
            EXEC_STMT
        }
        DOLLAR if rs => dollar_stmt(p),
        IDENT => ident_stmt(p),
        _ => {
            m.abandon(p);
            if p.at_ts(STOP)
                || matches!(p.current(), R_CURLY | R_PAREN | END_KW | ELSE_KW | EOF)
                || p.current().is_keyword()
            {
                p.error_expected("a statement");
            } else {
                p.err_and_bump(format!("expected a statement, found {}", p.found()));
            }
            return None;
        }
    };
    Some(m.complete(p, kind))
}

/// Number of tokens in the qualified name starting `start` tokens ahead.
fn qualified_len(p: &Parser<'_>, start: usize) -> (usize, usize) {
    let mut j = start + 1;
    let mut colons = 0;
    while p.nth_at(j, COLON2) && p.nth_at(j + 1, IDENT) {
        j += 2;
        colons += 1;
    }
    (j, colons)
}

fn is_target_continuation(k: SyntaxKind) -> bool {
    matches!(k, EQ | DOT | L_BRACK)
}

/// §4.1 (RoboChart) and the identifier case of §4.2 (RoboSim).
fn ident_stmt(p: &mut Parser<'_>) -> SyntaxKind {
    let (j, colons) = qualified_len(p, 0);
    let next = p.nth(j);
    let comm = if colons > 0 {
        false
    } else {
        match next {
            L_PAREN | EQ | L_BRACK => false,
            DOT => !(p.nth_at(j + 1, IDENT) && is_target_continuation(p.nth(j + 2))),
            _ => true,
        }
    };
    if next == L_PAREN {
        qualified_name(p, "an operation name");
        arg_list(p);
        return CALL_STMT;
    }
    if comm {
        if p.is_robosim() {
            p.error(format!(
                "RoboSim has no plain communications: write an output as `${0}`, `${0}!v` or `${0}.v`, or an assignment `{0} = …`",
                p.nth_text(0).trim_start_matches('^')
            ));
        }
        communication(p);
        return COMM_STMT;
    }
    assignment(p, false)
}

/// §4.2: statements starting with `$`.
fn dollar_stmt(p: &mut Parser<'_>) -> SyntaxKind {
    if !p.nth_at(1, IDENT) {
        p.bump(DOLLAR);
        p.error_expected("a name after `$`");
        return OUTPUT_COMM_STMT;
    }
    let (j, _) = qualified_len(p, 1);
    match p.nth(j) {
        L_PAREN => {
            p.bump(DOLLAR);
            qualified_name(p, "an operation name");
            arg_list(p);
            SIM_CALL_STMT
        }
        EQ | L_BRACK => assignment(p, true),
        DOT if p.nth_at(j + 1, IDENT) && is_target_continuation(p.nth(j + 2)) => assignment(p, true),
        _ => {
            p.bump(DOLLAR);
            qualified_name(p, "an event name");
            if p.at(BANG) || p.at(DOT) {
                p.bump_any();
                call_exp(p);
            } else if p.at(QUESTION) {
                p.error("inputs `$e?x` belong in a transition condition, not in a statement");
                p.bump(QUESTION);
                qualified_name(p, "a variable");
            }
            OUTPUT_COMM_STMT
        }
    }
}

fn assignment(p: &mut Parser<'_>, dollar: bool) -> SyntaxKind {
    let t = p.start();
    if dollar {
        p.bump(DOLLAR);
    }
    let target = p.nth_text(0).trim_start_matches('^');
    qualified_name(p, "a variable");
    loop {
        match p.current() {
            DOT => {
                let f = p.start();
                p.bump(DOT);
                name_ref(p, "a field name after `.`");
                f.complete(p, FIELD_ACCESS);
            }
            L_BRACK => {
                let f = p.start();
                p.bump(L_BRACK);
                expr(p);
                while p.eat(COMMA) {
                    expr(p);
                }
                p.expect_msg(R_BRACK, "expected `]` to close the index");
                f.complete(p, INDEX_ACCESS);
            }
            _ => break,
        }
    }
    t.complete(p, ASSIGNABLE);
    if p.expect_msg(EQ, format_args!("expected `=` and a value in the assignment to `{target}`")) {
        expr(p);
    }
    ASSIGN_STMT
}

fn clock_reset(p: &mut Parser<'_>) {
    p.bump(HASH);
    name_ref(p, "a clock name after `#`");
}

/// A communication `e`, `e?x`, `e!v`, `e.v`, with an optional `[| … |]`.
pub(crate) fn communication(p: &mut Parser<'_>) {
    let m = p.start();
    name_ref(p, "an event name");
    if p.at(L_BRACK_PIPE) {
        let g = p.start();
        p.bump(L_BRACK_PIPE);
        if p.at(IDENT) && p.nth_at(1, EQ) {
            name_ref(p, "a variable");
            p.bump(EQ);
            p.expect_msg(FROM_KW, "expected `from` in the sender binding `[| x = from … |]`");
            if p.eat(PIPE) {
                expr(p);
            }
        } else if !p.at(R_BRACK_PIPE) {
            expr(p);
        }
        p.expect_msg(R_BRACK_PIPE, "expected `|]` to close the guard of the communication");
        g.complete(p, COMM_GUARD);
    }
    match p.current() {
        QUESTION => {
            let s = p.start();
            p.bump(QUESTION);
            qualified_name(p, "a variable to receive the value after `?`");
            s.complete(p, COMM_INPUT);
        }
        BANG | DOT => {
            let kind = if p.at(BANG) { COMM_OUTPUT } else { COMM_SYNC };
            let s = p.start();
            p.bump_any();
            if p.at(MINUS) {
                p.error("the value of a communication is a literal, a name or a call: parenthesise it, as in `e!(-1)`");
                super::exprs::expr_bp(p, 15);
            } else {
                call_exp(p);
            }
            s.complete(p, kind);
            if matches!(p.current(), PLUS | MINUS | STAR | SLASH | PERCENT | DOT) {
                p.error(
                    "the value of a communication is a literal, a name or a call: parenthesise it, as in `e!(x + 1)`",
                );
            }
        }
        _ => {}
    }
    m.complete(p, COMMUNICATION);
}

/// Transition clause kinds, in their required order.
fn clause_rank(k: SyntaxKind, p: &Parser<'_>) -> Option<(u8, &'static str)> {
    Some(match k {
        TRIGGER_KW => (1, "the trigger"),
        EXEC_KW => (1, "`exec`"),
        PROBABILITY_KW => (1, "`probability`"),
        IDENT if p.nth_text(0) == "trigger" && p.is_robosim() => (1, "the trigger"),
        HASH => (2, "a clock reset"),
        DEADLINE_OPEN => (3, "the deadline"),
        CONDITION_KW => (4, "the condition"),
        ACTION_KW => (5, "the action"),
        _ => return None,
    })
}

/// `transition t { from a to b … }`.
pub(crate) fn transition(p: &mut Parser<'_>) {
    let m = p.start();
    p.bump(TRANSITION_KW);
    let n = name(p, "transition");
    let what = super::Named { desc: "transition", name: n };
    if !p.expect_msg(L_CURLY, format_args!("expected `{{` to open the body of {what}")) && !p.at(FROM_KW) {
        m.complete(p, TRANSITION);
        return;
    }
    if p.at(FROM_KW) {
        let s = p.start();
        p.bump(FROM_KW);
        simple_name_ref(p, format_args!("the source of {what}"));
        s.complete(p, TRANSITION_SOURCE);
    } else {
        p.error(format!("expected `from` and the source of {what}, found {}", p.found()));
    }
    if p.at(TO_KW) {
        let s = p.start();
        p.bump(TO_KW);
        simple_name_ref(p, format_args!("the target of {what}"));
        s.complete(p, TRANSITION_TARGET);
    } else {
        p.error(format!("expected `to` after the source of {what}, found {}", p.found()));
    }
    let mut last = 0u8;
    let rs = p.is_robosim();
    loop {
        let k = p.current();
        if k == R_CURLY {
            p.bump(R_CURLY);
            break;
        }
        if k == EOF {
            p.error(format!("expected `}}` to close the body of {what}"));
            break;
        }
        let Some((rank, clause)) = clause_rank(k, p) else {
            if member_at(p).is_some() {
                let range = p.prev_end();
                p.error_at(range, format!("expected `}}` to close the body of {what}"));
                break;
            }
            let e = p.start();
            p.error(format!(
                "unexpected {} in {what}: expected {}",
                p.found(),
                if rs {
                    "`exec`, `#`, `condition`, `action` or `}`"
                } else {
                    "`trigger`, `#`, `<{`, `condition`, `action` or `}`"
                }
            ));
            p.bump_balanced();
            e.complete(p, ERROR);
            continue;
        };
        if rank < last {
            p.error(format!(
                "{clause} must come earlier: the clauses of a transition are from, to, {}, clock resets, {}condition, action",
                if rs { "exec or probability" } else { "trigger or probability" },
                if rs { "" } else { "deadline, " }
            ));
        } else if rank == last && rank != 2 {
            p.error(format!("{what} already has {}", if rank == 1 { "a trigger or probability" } else { clause }));
        }
        last = last.max(rank);
        match k {
            TRIGGER_KW => trigger(p),
            IDENT => {
                let t = p.start();
                p.error("RoboSim transitions have no `trigger`: use `exec` and test inputs with `$` in the condition");
                p.bump(IDENT);
                if p.at(IDENT) {
                    communication(p);
                }
                t.complete(p, TRIGGER);
            }
            EXEC_KW => {
                let t = p.start();
                p.bump(EXEC_KW);
                t.complete(p, EXEC_TRIGGER);
            }
            PROBABILITY_KW => {
                let t = p.start();
                p.bump(PROBABILITY_KW);
                expr(p);
                t.complete(p, PROBABILITY);
            }
            HASH => {
                let t = p.start();
                clock_reset(p);
                t.complete(p, CLOCK_RESET);
            }
            DEADLINE_OPEN => {
                if rs {
                    p.error("transition deadlines are not allowed in RoboSim: count cycles with a clock instead");
                }
                deadline(p, DEADLINE);
            }
            CONDITION_KW => {
                let t = p.start();
                p.bump(CONDITION_KW);
                if p.at(ELSE_KW) {
                    let e = p.start();
                    p.bump(ELSE_KW);
                    e.complete(p, ELSE_CONDITION);
                } else {
                    expr(p);
                }
                t.complete(p, CONDITION);
            }
            _ => {
                let t = p.start();
                p.bump(ACTION_KW);
                if at_stmt_start(p) {
                    stmt(p);
                } else {
                    p.error_expected("a statement after `action`");
                }
                t.complete(p, TRANSITION_ACTION);
            }
        }
    }
    m.complete(p, TRANSITION);
}

fn trigger(p: &mut Parser<'_>) {
    let t = p.start();
    let kw = p.current_range();
    p.bump(TRIGGER_KW);
    if p.at(IDENT) {
        communication(p);
    } else if matches!(p.current(), CONDITION_KW | HASH | DEADLINE_OPEN | ACTION_KW | R_CURLY | PROBABILITY_KW) {
        // Older RoboTool versions wrote `trigger` with nothing after it.
        p.error_at(kw, "empty `trigger` (older RoboTool syntax): remove the `trigger` keyword");
    } else {
        p.error_expected("an event after `trigger`");
    }
    t.complete(p, TRIGGER);
}
