//! Expressions (syntax.md §2.15–2.16, RoboSim §3.1/§4.9): a Pratt parser
//! over the 19 levels of §2.16, with the level restrictions of the
//! reference grammar (for example `if` only as an operand of comparisons).
//!
//! Every construct has a *level*: the loosest operator it may be an operand
//! of is the one whose level is at most that. Binary operators are left
//! associative, so an operator of level `l` takes a left operand of level
//! `>= l` and a right operand of level `> l`.

use super::{arg_list, name, name_ref, qualified_name, type_};
use crate::parser::{CompletedMarker, Parser, TokenSet};
use crate::SyntaxKind::{self, *};

const LVL_QUANT: u8 = 1;
const LVL_NOT: u8 = 6;
const LVL_THE: u8 = 8;
const LVL_LET: u8 = 9;
const LVL_IF: u8 = 10;
const LVL_TYPE_TEST: u8 = 11;
const LVL_ADD: u8 = 12;
const LVL_NEG: u8 = 15;
const LVL_ATOM: u8 = 19;

pub(crate) fn binop_level(k: SyntaxKind) -> Option<u8> {
    Some(match k {
        IFF_KW => 2,
        IMPLIES => 3,
        OR => 4,
        AND => 5,
        EQ2 | NEQ | LT | LTEQ | GT | GTEQ | IN_KW => 7,
        PLUS | MINUS => 12,
        STAR | SLASH | PERCENT => 13,
        CAT_KW | CARET => 14,
        _ => return None,
    })
}

/// A full expression.
pub(crate) fn expr(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    expr_bp(p, LVL_QUANT)
}

/// An expression of level at least `min`.
pub(crate) fn expr_bp(p: &mut Parser<'_>, min: u8) -> Option<CompletedMarker> {
    p.nested(|p| expr_bp_inner(p, min))
}

fn level_error(p: &mut Parser<'_>, what: impl std::fmt::Display) {
    p.error(format!("{what} cannot be an operand here: wrap it in parentheses"));
}

fn expr_bp_inner(p: &mut Parser<'_>, min: u8) -> Option<CompletedMarker> {
    let (mut lhs, mut level) = match p.current() {
        FORALL_KW | EXISTS_KW | EXISTS1_KW | LAMBDA_KW => {
            if min > LVL_QUANT {
                level_error(p, format_args!("a `{}` expression", p.nth_text(0)));
            }
            (quantifier(p), LVL_QUANT)
        }
        NOT_KW => {
            if min > LVL_NOT {
                level_error(p, "a `not` expression");
            }
            let m = p.start();
            p.bump(NOT_KW);
            expr_bp(p, LVL_NOT);
            (m.complete(p, PREFIX_EXPR), LVL_NOT)
        }
        THE_KW => {
            if min > LVL_THE {
                level_error(p, "a `the` expression");
            }
            let m = p.start();
            p.bump(THE_KW);
            binders(p);
            p.expect_msg(AT, "expected `@` after the binders of `the`");
            expr_bp(p, LVL_THE);
            (m.complete(p, THE_EXPR), LVL_THE)
        }
        LET_KW => {
            if min > LVL_LET {
                level_error(p, "a `let` expression");
            }
            (let_expr(p), LVL_LET)
        }
        IF_KW => {
            if min > LVL_IF {
                level_error(p, "an `if` expression");
            }
            (if_expr(p), LVL_IF)
        }
        MINUS => {
            let m = p.start();
            p.bump(MINUS);
            expr_bp(p, LVL_NEG);
            (m.complete(p, PREFIX_EXPR), LVL_NEG)
        }
        _ => (postfix_expr(p)?, LVL_ATOM),
    };
    let mut wraps = 0;
    loop {
        let k = p.current();
        if !p.depth_allows(1)
            && (matches!(k, AS_KW | IS_KW) || binop_level(k).is_some_and(|op| op >= min && level >= op))
        {
            // The chain is too long to nest further: keep the rest flat.
            flat_rest(p, min);
            break;
        }
        if wraps > 0 || binop_level(k).is_some() || matches!(k, AS_KW | IS_KW) {
            p.add_depth(1);
            wraps += 1;
        }
        if matches!(k, AS_KW | IS_KW) {
            if min > LVL_TYPE_TEST || level < LVL_ADD {
                if level == LVL_TYPE_TEST && min <= LVL_TYPE_TEST {
                    p.error(format!(
                        "only one `as`/`is` may follow an expression: parenthesise the first one before `{}`",
                        p.nth_text(0)
                    ));
                    let m = lhs.precede(p);
                    p.bump_any();
                    type_(p);
                    lhs = m.complete(p, TYPE_TEST_EXPR);
                    continue;
                }
                break;
            }
            let m = lhs.precede(p);
            p.bump_any();
            type_(p);
            lhs = m.complete(p, TYPE_TEST_EXPR);
            level = LVL_TYPE_TEST;
            continue;
        }
        let Some(op) = binop_level(k) else { break };
        if op < min || level < op {
            break;
        }
        let m = lhs.precede(p);
        p.bump_any();
        if !at_expr_start(p) {
            p.error_expected(format_args!("an expression after `{}`", k.text().unwrap_or("")));
        } else {
            expr_bp(p, op + 1);
        }
        lhs = m.complete(p, BIN_EXPR);
        level = op;
    }
    p.add_depth(-wraps);
    Some(lhs)
}

/// The rest of an operator chain that is too long to nest, as one flat
/// ERROR node (reported once).
fn flat_rest(p: &mut Parser<'_>, min: u8) {
    let m = p.start();
    p.error("this expression has too many operators in a row to be analysed; split it up");
    loop {
        let k = p.current();
        if matches!(k, AS_KW | IS_KW) {
            p.bump_any();
            type_(p);
        } else if binop_level(k).is_some_and(|op| op >= min) {
            p.bump_any();
            if at_expr_start(p) {
                postfix_expr(p);
            }
        } else {
            break;
        }
    }
    m.complete(p, ERROR);
}

/// Tokens that can start an expression.
pub(crate) fn at_expr_start(p: &Parser<'_>) -> bool {
    matches!(p.current(), FORALL_KW | EXISTS_KW | EXISTS1_KW | LAMBDA_KW | NOT_KW | THE_KW | LET_KW | IF_KW | MINUS)
        || at_atom_start(p)
}

/// Tokens that can start an atom.
pub(crate) fn at_atom_start(p: &Parser<'_>) -> bool {
    match p.current() {
        INT_NUMBER | FLOAT_NUMBER | STRING | TRUE_KW | FALSE_KW | RESULT_KW | TO_KW | FROM_KW | IDENT | L_BRACK
        | L_PAREN | SINCE_KW | SINCE_ENTRY_KW | LT | L_CURLY | L_BRACK_PIPE | INVERSE_KW | TRANSPOSE_KW
        | L_PAREN_PIPE => true,
        DOLLAR | CYCLE_KW => p.is_robosim(),
        _ => false,
    }
}

fn quantifier(p: &mut Parser<'_>) -> CompletedMarker {
    let m = p.start();
    let kind = match p.current() {
        FORALL_KW => FORALL_EXPR,
        LAMBDA_KW => LAMBDA_EXPR,
        _ => EXISTS_EXPR,
    };
    let kw = p.nth_text(0);
    p.bump_any();
    binders(p);
    p.expect_msg(AT, format_args!("expected `@` and the body of `{kw}` after its binders"));
    expr(p);
    m.complete(p, kind)
}

/// `x : T, y : U | pred`.
pub(crate) fn binders(p: &mut Parser<'_>) {
    let m = p.start();
    binder(p);
    while p.eat(COMMA) {
        binder(p);
    }
    if p.at(PIPE) {
        let s = p.start();
        p.bump(PIPE);
        expr(p);
        s.complete(p, SUCH_THAT);
    }
    m.complete(p, BINDERS);
}

fn binder(p: &mut Parser<'_>) {
    let m = p.start();
    let n = name(p, "bound variable");
    if p.expect_msg(COLON, format_args!("expected `:` and a type after the bound variable `{}`", n.unwrap_or_default()))
    {
        type_(p);
    }
    if p.at(EQ) {
        p.error("bound variables have no initialiser");
    }
    m.complete(p, BINDER);
}

fn let_expr(p: &mut Parser<'_>) -> CompletedMarker {
    let m = p.start();
    p.bump(LET_KW);
    loop {
        let d = p.start();
        let n = name(p, "`let` definition");
        p.expect_msg(EQ2, format_args!("expected `==` after `{}` in `let`", n.unwrap_or_default()));
        expr(p);
        d.complete(p, LET_DECL);
        if !p.eat(COMMA) {
            break;
        }
    }
    p.expect_msg(AT, "expected `@` and the body of `let` after its definitions");
    expr_bp(p, LVL_LET);
    m.complete(p, LET_EXPR)
}

fn if_expr(p: &mut Parser<'_>) -> CompletedMarker {
    let m = p.start();
    p.bump(IF_KW);
    expr(p);
    p.expect_msg(THEN_KW, "expected `then` after the condition of `if`");
    expr(p);
    p.expect_msg(ELSE_KW, "expected `else`: an `if` expression needs both branches");
    expr(p);
    p.expect_msg(END_KW, "expected `end` to close the `if` expression");
    m.complete(p, IF_EXPR)
}

/// An atom with its postfix chain: at most one call, then at most one
/// index group, then any number of field selections (§2.16, levels 16–18).
pub(crate) fn postfix_expr(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let mut lhs = atom(p)?;
    // 0 = atom, 1 = called, 2 = indexed, 3 = selected
    let mut stage = 0;
    let mut wraps = 0;
    loop {
        if matches!(p.current(), L_PAREN | L_BRACK | DOT) {
            if !p.depth_allows(1) {
                let m = p.start();
                p.error("this expression has too many selections in a row to be analysed; split it up");
                while matches!(p.current(), L_PAREN | L_BRACK) || (p.at(DOT) && p.nth_at(1, IDENT)) {
                    p.bump_balanced();
                    p.eat(IDENT);
                }
                m.complete(p, ERROR);
                break;
            }
            p.add_depth(1);
            wraps += 1;
        }
        match p.current() {
            L_PAREN => {
                if stage >= 1 {
                    p.error(match stage {
                        1 => "only one call may follow an expression: parenthesise the first call",
                        2 => "a call cannot follow indexing: parenthesise the indexed expression",
                        _ => "a call cannot follow a field selection: parenthesise the selection",
                    });
                }
                let m = lhs.precede(p);
                arg_list(p);
                lhs = m.complete(p, CALL_EXPR);
                stage = stage.max(1);
            }
            L_BRACK => {
                if stage >= 2 {
                    p.error(if stage == 2 {
                        "only one index group may follow an expression: write `a[i, j]` or parenthesise"
                    } else {
                        "indexing cannot follow a field selection: parenthesise the selection"
                    });
                }
                let m = lhs.precede(p);
                p.bump(L_BRACK);
                expr(p);
                while p.eat(COMMA) {
                    expr(p);
                }
                p.expect_msg(R_BRACK, "expected `]` to close the index");
                lhs = m.complete(p, INDEX_EXPR);
                stage = stage.max(2);
            }
            // A `.` followed by a name selects a field; otherwise it is not
            // ours (for example the full stop that ends an assertion).
            DOT if p.nth_at(1, IDENT) => {
                let m = lhs.precede(p);
                p.bump(DOT);
                name_ref(p, "a field name");
                lhs = m.complete(p, SELECT_EXPR);
                stage = 3;
            }
            _ => break,
        }
    }
    p.add_depth(-wraps);
    // Hazard 1: `s^t` is `s` followed by the escaped name `t`.
    if p.at(IDENT)
        && p.nth_text(0).starts_with('^')
        && p.prev_range().is_some_and(|r| r.end() == p.current_range().start())
    {
        let name = p.nth_text(0).trim_start_matches('^');
        p.error(format!(
            "`^{name}` reads as the escaped name `{name}`: write ` ^ {name}` with spaces (or `cat`) to concatenate"
        ));
    }
    Some(lhs)
}

/// An atom optionally followed by one argument list (the payload of
/// communications and `$` suffixes).
pub(crate) fn call_exp(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let a = atom(p)?;
    if p.at(L_PAREN) {
        let m = a.precede(p);
        arg_list(p);
        return Some(m.complete(p, CALL_EXPR));
    }
    Some(a)
}

const ATOM_RECOVERY: TokenSet =
    TokenSet::new(&[R_CURLY, R_PAREN, R_BRACK, R_BRACK_PIPE, R_PAREN_PIPE, SEMI, COMMA, AT, PIPE, EOF, COLON, EQ, DOT]);

/// An atom (§2.15 `Atomic`, RoboSim §3.1).
pub(crate) fn atom(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let m = p.start();
    let kind = match p.current() {
        INT_NUMBER | FLOAT_NUMBER | STRING | TRUE_KW | FALSE_KW => {
            p.bump_any();
            LITERAL
        }
        RESULT_KW => {
            p.bump_any();
            RESULT_EXPR
        }
        FROM_KW => {
            p.bump_any();
            FROM_EXPR
        }
        TO_KW => {
            p.bump_any();
            TO_EXPR
        }
        CYCLE_KW if p.is_robosim() => {
            p.bump_any();
            CYCLE_EXPR
        }
        IDENT => match p.nth(1) {
            L_PAREN_PIPE => record_literal(p),
            COLON2 => enum_literal(p),
            _ => {
                name_ref(p, "a name");
                REF_EXPR
            }
        },
        L_BRACK => {
            p.bump(L_BRACK);
            expr(p);
            p.expect_msg(COMMA, "expected `,` in the interval `[a, b]`");
            expr(p);
            if !p.eat(R_BRACK) && !p.eat(R_PAREN) {
                p.error_expected("`]` or `)` to close the interval");
            }
            INTERVAL_EXPR
        }
        L_PAREN => {
            p.bump(L_PAREN);
            expr(p);
            if p.eat(COMMA) {
                expr(p);
                if !p.eat(R_BRACK) && !p.eat(R_PAREN) {
                    p.error_expected("`]` or `)` to close the interval");
                }
                INTERVAL_EXPR
            } else {
                p.expect_msg(R_PAREN, "expected `)` to close the parenthesis");
                PAREN_EXPR
            }
        }
        SINCE_KW => {
            p.bump(SINCE_KW);
            p.expect_msg(L_PAREN, "expected `(` and a clock after `since`");
            name_ref(p, "a clock name");
            p.expect(R_PAREN);
            SINCE_EXPR
        }
        SINCE_ENTRY_KW => {
            p.bump(SINCE_ENTRY_KW);
            p.expect_msg(L_PAREN, "expected `(` and a state after `sinceEntry`");
            qualified_name(p, "a state name");
            p.expect(R_PAREN);
            SINCE_ENTRY_EXPR
        }
        LT => {
            p.bump(LT);
            if !p.at(GT) {
                expr_bp(p, LVL_ADD);
                while p.eat(COMMA) {
                    expr_bp(p, LVL_ADD);
                }
            }
            if !p.eat(GT) {
                if matches!(p.current(), EQ2 | NEQ | LT | LTEQ | GTEQ | IN_KW | AND | OR) {
                    p.error("sequence elements cannot contain comparisons or logic: parenthesise the element, as in `<(a == b)>`");
                } else {
                    p.error_expected("`>` to close the sequence");
                }
            }
            SEQ_EXPR
        }
        L_CURLY => set_expr(p),
        L_BRACK_PIPE => {
            p.bump(L_BRACK_PIPE);
            loop {
                let row = p.start();
                expr(p);
                while p.eat(COMMA) {
                    expr(p);
                }
                row.complete(p, MATRIX_ROW);
                if !p.eat(SEMI) {
                    break;
                }
            }
            p.expect_msg(R_BRACK_PIPE, "expected `|]` to close the vector or matrix");
            MATRIX_EXPR
        }
        INVERSE_KW | TRANSPOSE_KW => {
            let kind = if p.at(INVERSE_KW) { INVERSE_EXPR } else { TRANSPOSE_EXPR };
            let kw = p.nth_text(0);
            p.bump_any();
            p.expect_msg(L_PAREN, format_args!("expected `(` after `{kw}`"));
            expr(p);
            p.expect(R_PAREN);
            kind
        }
        L_PAREN_PIPE => {
            p.bump(L_PAREN_PIPE);
            if !p.at(R_PAREN_PIPE) {
                expr(p);
                while p.eat(COMMA) {
                    expr(p);
                }
            }
            p.expect_msg(R_PAREN_PIPE, "expected `|)` to close the tuple");
            TUPLE_EXPR
        }
        DOLLAR => sim_ref(p),
        _ => {
            m.abandon(p);
            if p.at_ts(ATOM_RECOVERY) || p.current().is_keyword() {
                p.error_expected("an expression");
            } else {
                p.err_and_bump(format!("expected an expression, found {}", p.found()));
            }
            return None;
        }
    };
    Some(m.complete(p, kind))
}

fn record_literal(p: &mut Parser<'_>) -> SyntaxKind {
    name_ref(p, "a record type");
    p.bump(L_PAREN_PIPE);
    if p.at(R_PAREN_PIPE) {
        p.error("a record literal needs at least one field `name = value`");
    } else {
        loop {
            let f = p.start();
            if p.at(IDENT) && p.nth_at(1, EQ) {
                name_ref(p, "a field name");
                p.bump(EQ);
                expr(p);
            } else {
                p.error("record literal fields are written `name = value` (for a tuple argument write `f((|a, b|))`)");
                expr(p);
            }
            f.complete(p, FIELD_VALUE);
            if !p.eat(COMMA) {
                break;
            }
        }
    }
    p.expect_msg(R_PAREN_PIPE, "expected `|)` to close the record literal");
    RECORD_LITERAL
}

fn enum_literal(p: &mut Parser<'_>) -> SyntaxKind {
    name_ref(p, "an enumeration");
    p.bump(COLON2);
    name_ref(p, "an enumeration literal after `::`");
    if p.at(COLON2) {
        p.error("an enumeration literal is exactly `Enumeration::Literal`: package-qualified names are not allowed in expressions");
        while p.at(COLON2) {
            p.bump(COLON2);
            if !p.eat(IDENT) {
                break;
            }
        }
    }
    ENUM_LITERAL_EXPR
}

fn set_expr(p: &mut Parser<'_>) -> SyntaxKind {
    p.bump(L_CURLY);
    if p.eat(R_CURLY) {
        return SET_EXPR;
    }
    if p.at(IDENT) && p.nth_at(1, COLON) {
        binders(p);
        if p.eat(AT) {
            expr(p);
        }
        p.expect_msg(R_CURLY, "expected `}` to close the set comprehension");
        return SET_COMP_EXPR;
    }
    expr(p);
    let kind = if p.eat(TO_KW) {
        expr(p);
        if p.at(COMMA) {
            p.error("a range `{a to b}` cannot be mixed with set elements");
        }
        while p.eat(COMMA) {
            expr(p);
        }
        SET_RANGE_EXPR
    } else {
        while p.eat(COMMA) {
            expr(p);
            if p.at(TO_KW) {
                p.error("a range `{a to b}` cannot be mixed with set elements");
                p.bump(TO_KW);
                expr(p);
            }
        }
        SET_EXPR
    };
    p.expect_msg(R_CURLY, "expected `}` to close the set");
    kind
}

/// `$name`, `$e.v`, `$e?x`, `$e?x : p` (§3.2, greedy suffix as §4.9).
fn sim_ref(p: &mut Parser<'_>) -> SyntaxKind {
    p.bump(DOLLAR);
    qualified_name(p, "a name after `$`");
    if p.at(DOT) && next_starts_atom(p) {
        let s = p.start();
        p.bump(DOT);
        call_exp(p);
        s.complete(p, SIM_SYNC_SUFFIX);
    } else if p.at(QUESTION) && p.nth_at(1, IDENT) {
        let s = p.start();
        p.bump(QUESTION);
        qualified_name(p, "a variable after `?`");
        if p.at(COLON) {
            p.bump(COLON);
            call_exp(p);
        }
        s.complete(p, SIM_INPUT_SUFFIX);
    }
    SIM_REF_EXPR
}

fn next_starts_atom(p: &Parser<'_>) -> bool {
    matches!(
        p.nth(1),
        INT_NUMBER
            | FLOAT_NUMBER
            | STRING
            | TRUE_KW
            | FALSE_KW
            | RESULT_KW
            | IDENT
            | L_BRACK
            | L_PAREN
            | SINCE_KW
            | SINCE_ENTRY_KW
            | LT
            | L_CURLY
            | L_BRACK_PIPE
            | INVERSE_KW
            | TRANSPOSE_KW
            | L_PAREN_PIPE
            | DOLLAR
            | CYCLE_KW
            | TO_KW
            | FROM_KW
    )
}
