//! Types (syntax.md §2.3): `<->` loosest, then `->`, then `*`, then
//! `vector`/`matrix`, then named, `Set(`, `Seq(`, `?X` and parenthesised.

use super::{exprs, qualified_name};
use crate::parser::{CompletedMarker, Parser};
use crate::SyntaxKind::*;

/// A full type.
pub(crate) fn type_(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    p.nested(relation_type)
}

fn relation_type(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let lhs = function_type(p)?;
    if p.at(REL_ARROW) {
        let m = lhs.precede(p);
        p.bump(REL_ARROW);
        type_(p);
        return Some(m.complete(p, RELATION_TYPE));
    }
    Some(lhs)
}

fn function_type(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let lhs = product_type(p)?;
    if p.at(ARROW) {
        let m = lhs.precede(p);
        p.bump(ARROW);
        p.nested(function_type);
        return Some(m.complete(p, FUNCTION_TYPE));
    }
    Some(lhs)
}

fn product_type(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let first = vector_type(p)?;
    if !p.at(STAR) {
        return Some(first);
    }
    let m = first.precede(p);
    while p.eat(STAR) {
        if matches!(p.current(), VECTOR_KW | MATRIX_KW) {
            p.error("only the first factor of a product may be a vector or matrix type: parenthesise it, as in `int * (vector(real, 3))`");
            vector_type(p);
        } else {
            type_ref(p);
        }
    }
    Some(m.complete(p, PRODUCT_TYPE))
}

fn vector_type(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let (kind, sizes) = match p.current() {
        VECTOR_KW => (VECTOR_TYPE, 1),
        MATRIX_KW => (MATRIX_TYPE, 2),
        _ => return type_ref(p),
    };
    let m = p.start();
    let kw = p.nth_text(0);
    p.bump_any();
    if p.expect_msg(L_PAREN, format_args!("expected `(` after `{kw}`")) {
        type_(p);
        for _ in 0..sizes {
            p.expect_msg(COMMA, format_args!("expected `,` and a size in `{kw}(…)`"));
            if exprs::at_atom_start(p) {
                let size = exprs::atom(p);
                if matches!(p.current(), PLUS | MINUS | STAR | SLASH | PERCENT) {
                    p.error("a vector or matrix size must be a literal, a name or parenthesised: write `(n + 1)`");
                    let _ = size;
                    while !matches!(p.current(), COMMA | R_PAREN | EOF) {
                        p.bump_balanced();
                    }
                }
            } else {
                p.error_expected("a size (a literal, a name or a parenthesised expression)");
            }
        }
        p.expect(R_PAREN);
    }
    Some(m.complete(p, kind))
}

fn type_ref(p: &mut Parser<'_>) -> Option<CompletedMarker> {
    let m = p.start();
    match p.current() {
        IDENT if matches!(p.nth_text(0), "Set" | "Seq") && p.nth_at(1, L_PAREN) => {
            let t = p.nth_text(0);
            let kind = if t == "Set" { SET_TYPE } else { SEQ_TYPE };
            p.error(format!("write `{t}(` without a space: `{t} (` is a type named `{t}` followed by `(`"));
            p.bump(IDENT);
            p.bump(L_PAREN);
            type_(p);
            p.expect(R_PAREN);
            Some(m.complete(p, kind))
        }
        IDENT => {
            qualified_name(p, "a type");
            Some(m.complete(p, NAMED_TYPE))
        }
        SET_OPEN | SEQ_OPEN => {
            let kind = if p.at(SET_OPEN) { SET_TYPE } else { SEQ_TYPE };
            p.bump_any();
            type_(p);
            p.expect(R_PAREN);
            Some(m.complete(p, kind))
        }
        QUESTION => {
            p.bump(QUESTION);
            if !p.eat(IDENT) {
                p.error_expected("a type variable name after `?`");
            }
            Some(m.complete(p, TYPE_VAR))
        }
        L_PAREN => {
            p.bump(L_PAREN);
            type_(p);
            p.expect(R_PAREN);
            Some(m.complete(p, PAREN_TYPE))
        }
        k if k.is_keyword() && !matches!(k, TRUE_KW | FALSE_KW) && !super::STOP.contains(k) => {
            // A reserved word used as a type name: keep it as a named type.
            let kw = p.nth_text(0).to_string();
            p.error(format!("`{kw}` is a reserved word: write `^{kw}` to use it as a type name"));
            let q = p.start();
            p.bump_any();
            q.complete(p, QUALIFIED_NAME);
            Some(m.complete(p, NAMED_TYPE))
        }
        _ => {
            m.abandon(p);
            p.error_expected("a type");
            None
        }
    }
}
