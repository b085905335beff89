//! The CSPm grammar: declarations, expressions (processes are expressions)
//! and the statements of comprehensions. Patterns are parsed as
//! expressions, as libcspm does; lowering checks that they are patterns.
//! Operator precedence follows libcspm's grammar (lowest first): `\` `|\`,
//! `|||`, `[|A|]`/`[A||B]`/`[|A|>`, `|~|`, `[]`/`[+A+]`, `/\`, `[>`, `;`,
//! `&` and `->` (right), fields `?`/`!`/`$`, `.` (right), `or`, `and`,
//! `not`, comparisons, `+ -`, `* / %`, `#`, `^`, application and renaming.

use crate::kinds::SyntaxKind::{self, *};
use crate::parser::{Parser, MAX_DEPTH};

/// Where declarations are: FDR allows fewer kinds inside `let`, modules
/// and `Timed` sections.
#[derive(Clone, Copy, Default)]
struct Ctx {
    in_let: bool,
    in_module: bool,
    in_timed: bool,
}

pub(crate) fn source_file(p: &mut Parser) {
    p.start_root(SOURCE_FILE);
    decls(p, |_| false, Ctx::default());
    if !p.at(EOF) {
        p.error("expected a definition");
        p.start(ERROR);
        while !p.at(EOF) {
            p.bump();
        }
        p.finish_node();
    }
}

/// Declarations until `end` (or the end of the text).
fn decls(p: &mut Parser, end: fn(SyntaxKind) -> bool, ctx: Ctx) {
    while !p.at(EOF) && !end(p.current()) {
        let before = p.current_range();
        let kind = p.current();
        let banned = match kind {
            CHANNEL_KW | DATATYPE_KW | SUBTYPE_KW | NAMETYPE_KW => ctx.in_let,
            ASSERT_KW => ctx.in_let || ctx.in_module,
            PRINT_LINE => ctx.in_let || ctx.in_module || ctx.in_timed,
            MODULE_KW => ctx.in_let || ctx.in_timed,
            _ => false,
        };
        if banned {
            let place = if ctx.in_let {
                "`let`"
            } else if ctx.in_module {
                "a module"
            } else {
                "a `Timed` section"
            };
            let range = p.current_range();
            p.errors.push(crate::Diagnostic::error(
                crate::Code::Syntax,
                range,
                format!("`{}` is not allowed inside {place}", p.token_text()),
            ));
        }
        decl(p, ctx);
        if p.at(EOF) || end(p.current()) {
            break;
        }
        if !p.at_line_break() {
            p.error("expected the end of the definition (a new line)");
            p.skip_until(end);
        }
        if p.current_range() == before {
            // No progress at all: skip one token so the loop ends.
            p.start(ERROR);
            p.bump();
            p.finish_node();
        }
    }
}

fn name_list(p: &mut Parser) {
    p.start(NAME_LIST);
    p.expect(IDENT);
    while p.eat(COMMA) {
        p.expect(IDENT);
    }
    p.finish_node();
}

fn decl(p: &mut Parser, ctx: Ctx) {
    match p.current() {
        CHANNEL_KW => {
            p.start(CHANNEL_DECL);
            p.bump();
            name_list(p);
            if p.eat(COLON) {
                expr_bp(p, 22);
            }
            p.finish_node();
        }
        DATATYPE_KW | SUBTYPE_KW => {
            p.start(if p.at(DATATYPE_KW) { DATATYPE_DECL } else { SUBTYPE_DECL });
            p.bump();
            p.expect(IDENT);
            p.expect(EQ);
            loop {
                p.start(DATATYPE_CLAUSE);
                p.expect(IDENT);
                if p.eat(DOT) {
                    expr_bp(p, 22);
                }
                p.finish_node();
                if !p.eat(PIPE) {
                    break;
                }
            }
            p.finish_node();
        }
        NAMETYPE_KW => {
            p.start(NAMETYPE_DECL);
            p.bump();
            p.expect(IDENT);
            p.expect(EQ);
            expr(p);
            p.finish_node();
        }
        EXTERNAL_KW | TRANSPARENT_KW => {
            p.start(if p.at(EXTERNAL_KW) { EXTERNAL_DECL } else { TRANSPARENT_DECL });
            p.bump();
            name_list(p);
            p.finish_node();
        }
        ASSERT_KW => assert_decl(p),
        MODULE_KW => {
            p.start(MODULE_DECL);
            p.bump();
            p.expect(IDENT);
            if p.at(L_PAREN) {
                if p.nth(1) == R_PAREN {
                    p.error("a module without parameters has no parentheses");
                }
                arg_list(p);
            }
            let inner = Ctx { in_module: true, ..ctx };
            decls(p, |k| matches!(k, EXPORTS_KW | ENDMODULE_KW), inner);
            if p.at(EXPORTS_KW) {
                p.start(MODULE_EXPORTS);
                p.bump();
                decls(p, |k| k == ENDMODULE_KW, inner);
                p.finish_node();
            }
            p.expect(ENDMODULE_KW);
            p.finish_node();
        }
        INSTANCE_KW => {
            p.start(INSTANCE_DECL);
            p.bump();
            p.expect(IDENT);
            p.expect(EQ);
            expr(p);
            p.finish_node();
        }
        TIMED_KW => {
            p.start(TIMED_SECTION);
            p.bump();
            if p.at(L_PAREN) {
                arg_list(p);
            }
            p.expect(L_BRACE);
            decls(p, |k| k == R_BRACE, Ctx { in_timed: true, ..ctx });
            p.expect(R_BRACE);
            p.finish_node();
        }
        INCLUDE_LINE | PRINT_LINE => {
            if p.at(INCLUDE_LINE) {
                let line = &p.token_text()["include".len()..];
                let arg = line.split("--").next().unwrap_or("").trim();
                if arg.len() < 2 || !arg.starts_with('"') || !arg.ends_with('"') {
                    p.error("expected a quoted file name after `include`");
                }
            }
            p.start(if p.at(INCLUDE_LINE) { INCLUDE_DECL } else { PRINT_DECL });
            p.bump();
            p.finish_node();
        }
        _ => {
            let cp = p.checkpoint();
            if !expr(p) {
                p.skip_until(|k| k == EQ);
            }
            if p.at(COLON2) {
                // Types (with class constraints `Eq a => …`) are kept as
                // tokens: nothing downstream reads them.
                p.start_at(cp, TYPE_ANNOTATION);
                p.bump();
                while !p.at(EOF) && !p.at(WITHIN_KW) && !p.at_line_break() {
                    p.bump();
                }
            } else {
                p.start_at(cp, DEFINITION);
                if p.expect(EQ) {
                    expr(p);
                }
            }
            p.finish_node();
        }
    }
}

fn assert_decl(p: &mut Parser) {
    p.start(ASSERT_DECL);
    p.bump();
    if p.at(NOT_KW) {
        p.bump();
    }
    expr(p);
    match p.current() {
        REFINES_T | REFINES_F | REFINES_FD | REFINES_V | REFINES_VD | REFINES_R | REFINES_RD => {
            p.bump();
            expr(p);
            while p.at(PROP_OPEN) {
                property(p);
            }
        }
        PROP_OPEN => {
            while p.at(PROP_OPEN) {
                property(p);
            }
        }
        _ => p.error("expected a refinement `[T=` / `[F=` / `[FD=` or a property `:[`"),
    }
    p.finish_node();
}

/// `:[ words [model] ]` and an optional `: expr` (a trace, a set).
fn property(p: &mut Parser) {
    p.start(ASSERT_PROPERTY);
    p.bump();
    // `]]` of `[FD]]` is one token: it closes two brackets.
    let mut depth = 1;
    loop {
        if p.at(EOF) {
            p.error("expected `]` to close the property");
            break;
        }
        match p.current() {
            L_BRACK => depth += 1,
            L_RENAME => depth += 2,
            R_BRACK => depth -= 1,
            R_RENAME => depth -= 2,
            _ => {}
        }
        p.bump();
        if depth <= 0 {
            p.hard_break_after_previous();
            break;
        }
    }
    if (!p.at_line_break() && p.eat(COLON)) || (p.at(LT) && !p.at_line_break()) {
        expr(p);
    }
    p.finish_node();
}

/// An expression at the lowest precedence. Returns whether one was found.
pub(crate) fn expr(p: &mut Parser) -> bool {
    expr_bp(p, 0)
}

/// Binding powers of the infix operators: (left, right).
fn infix(kind: SyntaxKind, gt_closes: bool) -> Option<(u8, u8)> {
    Some(match kind {
        AT2 => (1, 2),
        YIELD | YIELD_STAR => (3, 2),
        // The set of `P \ A op Q` ends before the process operator:
        // `(P \ A) op Q`, as libcspm re-associates it.
        BACKSLASH | PROJECT => (2, 22),
        INTERLEAVE => (4, 5),
        L_PAR | L_BRACK => (6, 7),
        INT_CHOICE => (8, 9),
        EXT_CHOICE | LSYNC_EXT => (10, 11),
        INTERRUPT | LSYNC_INT => (12, 13),
        SLIDE => (14, 15),
        SEMI => (16, 17),
        AMP | ARROW => (19, 18),
        QUESTION | BANG | DOLLAR => (20, 21),
        DOT => (25, 24),
        OR_KW => (28, 29),
        AND_KW => (30, 31),
        EQ2 | NEQ | LT | LTEQ | GTEQ => (34, 35),
        GT if !gt_closes => (34, 35),
        PLUS | MINUS => (36, 37),
        STAR | SLASH | PERCENT => (38, 39),
        CARET => (42, 43),
        L_PAREN | L_RENAME => (50, 51),
        _ => return None,
    })
}

pub(crate) fn expr_bp(p: &mut Parser, min_bp: u8) -> bool {
    if p.depth >= MAX_DEPTH || p.stack.exceeded() {
        p.error("expression nested too deeply");
        p.skip_until(|_| false);
        return false;
    }
    p.depth += 1;
    let ok = expr_bp_inner(p, min_bp);
    p.depth -= 1;
    ok
}

fn expr_bp_inner(p: &mut Parser, min_bp: u8) -> bool {
    let cp = p.checkpoint();
    if !prefix_expr(p) {
        return false;
    }
    // Each operator applied here nests the tree one level deeper (`a + b
    // + c` is `(a + b) + c`): counted with the recursion depth, so that the
    // whole tree stays shallow enough to walk recursively.
    let depth_before = p.depth;
    loop {
        if p.at_line_break() {
            break;
        }
        let op = p.current();
        let Some((lbp, rbp)) = infix(op, p.gt_closes) else { break };
        if lbp < min_bp {
            break;
        }
        if p.depth >= MAX_DEPTH || p.stack.exceeded() {
            p.error("expression nested too deeply (split it into definitions)");
            p.skip_until(|_| false);
            break;
        }
        p.depth += 1;
        match op {
            L_PAREN => {
                p.start_at(cp, CALL_EXPR);
                arg_list(p);
            }
            L_RENAME => {
                p.start_at(cp, RENAME_EXPR);
                p.bump();
                if !p.at(R_RENAME) {
                    loop {
                        p.start(RENAME_PAIR);
                        expr(p);
                        p.expect(DRAWN);
                        expr(p);
                        p.finish_node();
                        if !p.eat(COMMA) {
                            break;
                        }
                    }
                    if p.eat(PIPE) {
                        stmts(p);
                    }
                }
                p.expect(R_RENAME);
            }
            QUESTION | BANG | DOLLAR => {
                p.start_at(cp, PREFIX_EXPR);
                while matches!(p.current(), QUESTION | BANG | DOLLAR) {
                    field(p);
                }
                p.expect(ARROW);
                expr_bp(p, 18);
            }
            ARROW => {
                p.start_at(cp, PREFIX_EXPR);
                p.bump();
                expr_bp(p, rbp);
            }
            AMP => {
                p.start_at(cp, GUARD_EXPR);
                p.bump();
                expr_bp(p, rbp);
            }
            AT2 => {
                p.start_at(cp, DOUBLE_PATTERN);
                p.bump();
                expr_bp(p, rbp);
            }
            L_PAR => {
                let saved = std::mem::replace(&mut p.gt_closes, false);
                p.bump();
                expr(p);
                let kind = if p.eat(EXC_CLOSE) {
                    EXCEPTION
                } else {
                    p.expect(R_PAR);
                    GEN_PARALLEL
                };
                p.gt_closes = saved;
                p.start_at(cp, kind);
                expr_bp(p, rbp);
            }
            L_BRACK => {
                let saved = std::mem::replace(&mut p.gt_closes, false);
                p.bump();
                let kind = bracket_operator(p);
                p.gt_closes = saved;
                p.start_at(cp, kind);
                expr_bp(p, rbp);
            }
            LSYNC_EXT | LSYNC_INT => {
                let saved = std::mem::replace(&mut p.gt_closes, false);
                p.bump();
                expr(p);
                p.expect(if op == LSYNC_EXT { RSYNC_EXT } else { RSYNC_INT });
                p.gt_closes = saved;
                p.start_at(cp, if op == LSYNC_EXT { SYNC_EXT_CHOICE } else { SYNC_INTERRUPT });
                expr_bp(p, rbp);
            }
            _ => {
                p.start_at(cp, BIN_EXPR);
                p.bump();
                if !expr_bp(p, rbp) {
                    p.error("expected an expression");
                }
            }
        }
        p.finish_node();
        if matches!(op, EQ2 | NEQ | LT | GT | LTEQ | GTEQ) && matches!(infix(p.current(), p.gt_closes), Some((34, _))) {
            p.error("comparisons do not chain: add parentheses");
        }
    }
    p.depth = depth_before;
    true
}

/// After `[` in operator position: `[A || B]` or `[a <-> b, … | stmts]`.
fn bracket_operator(p: &mut Parser) -> SyntaxKind {
    let cp = p.checkpoint();
    expr(p);
    if p.eat(PARALLEL) {
        expr(p);
        p.expect(R_BRACK);
        return ALPHA_PARALLEL;
    }
    p.start_at(cp, LINK);
    p.expect(TIE);
    expr(p);
    p.finish_node();
    while p.eat(COMMA) {
        p.start(LINK);
        expr(p);
        p.expect(TIE);
        expr(p);
        p.finish_node();
    }
    if p.eat(PIPE) {
        stmts(p);
    }
    p.expect(R_BRACK);
    LINK_PARALLEL
}

/// `?p`, `?p:S`, `$p:S` or `!e` of a prefix.
fn field(p: &mut Parser) {
    let kind = match p.current() {
        QUESTION => INPUT_FIELD,
        DOLLAR => NONDET_FIELD,
        _ => OUTPUT_FIELD,
    };
    p.start(kind);
    p.bump();
    if !expr_bp(p, 22) {
        p.error("expected a pattern or an expression");
    }
    if kind != OUTPUT_FIELD && p.eat(COLON) {
        expr_bp(p, 22);
    }
    p.finish_node();
}

pub(crate) fn arg_list(p: &mut Parser) {
    let saved = std::mem::replace(&mut p.gt_closes, false);
    p.start(ARG_LIST);
    p.bump();
    if !p.at(R_PAREN) {
        loop {
            expr(p);
            if !p.eat(COMMA) {
                break;
            }
        }
    }
    p.expect(R_PAREN);
    p.finish_node();
    p.gt_closes = saved;
}

/// Generators `p <- e` / `p : e` and predicates, comma-separated.
fn stmts(p: &mut Parser) {
    p.start(STMT_LIST);
    loop {
        let cp = p.checkpoint();
        expr(p);
        if p.at(DRAWN) || p.at(COLON) {
            p.start_at(cp, GENERATOR);
            p.bump();
            expr(p);
        } else {
            p.start_at(cp, PREDICATE);
        }
        p.finish_node();
        if !p.eat(COMMA) {
            break;
        }
    }
    p.finish_node();
}

fn prefix_expr(p: &mut Parser) -> bool {
    match p.current() {
        LET_KW => {
            p.start(LET_EXPR);
            p.bump();
            let saved = std::mem::replace(&mut p.gt_closes, false);
            decls(p, |k| k == WITHIN_KW, Ctx { in_let: true, in_module: false, in_timed: false });
            p.gt_closes = saved;
            p.expect(WITHIN_KW);
            expr(p);
        }
        IF_KW => {
            p.start(IF_EXPR);
            p.bump();
            expr(p);
            p.expect(THEN_KW);
            expr(p);
            p.expect(ELSE_KW);
            expr(p);
        }
        BACKSLASH => {
            p.start(LAMBDA_EXPR);
            p.bump();
            loop {
                expr_bp(p, 22);
                if !p.eat(COMMA) {
                    break;
                }
            }
            p.expect(AT);
            expr(p);
        }
        EXT_CHOICE | INT_CHOICE | INTERLEAVE | SEMI | PARALLEL | L_PAR | L_BRACK | LSYNC_EXT => {
            p.start(REPLICATED_EXPR);
            let op = p.current();
            let saved = std::mem::replace(&mut p.gt_closes, false);
            p.bump();
            match op {
                L_PAR => {
                    expr(p);
                    p.expect(R_PAR);
                }
                LSYNC_EXT => {
                    expr(p);
                    p.expect(RSYNC_EXT);
                }
                L_BRACK => {
                    let kind = bracket_operator(p);
                    if kind != LINK_PARALLEL {
                        p.error("expected a linked parallel `[a <-> b]` before `@`");
                    }
                }
                _ => {}
            }
            stmts(p);
            p.expect(AT);
            if op == PARALLEL {
                p.expect(L_BRACK);
                expr(p);
                p.expect(R_BRACK);
            }
            p.gt_closes = saved;
            expr(p);
        }
        NOT_KW | MINUS | HASH => {
            let bp = if p.at(NOT_KW) { 32 } else { 40 };
            p.start(UNARY_EXPR);
            p.bump();
            if !expr_bp(p, bp) {
                p.error("expected an expression");
            }
        }
        _ => return primary(p),
    }
    p.finish_node();
    true
}

fn primary(p: &mut Parser) -> bool {
    match p.current() {
        INT | STRING | CHAR | TRUE_KW | FALSE_KW => {
            p.start(LITERAL);
            p.bump();
        }
        UNDERSCORE => {
            p.start(WILDCARD);
            p.bump();
        }
        IDENT => {
            p.start(NAME_REF);
            p.bump();
            // `M::x`: module-qualified names are written without spaces.
            while p.at(COLON2) && p.adjacent() && p.nth(1) == IDENT {
                p.bump();
                if !p.adjacent() {
                    p.error("expected a name right after `::`");
                }
                p.bump();
            }
        }
        L_PAREN => {
            let saved = std::mem::replace(&mut p.gt_closes, false);
            let cp = p.checkpoint();
            p.bump();
            let mut n = 0;
            if !p.at(R_PAREN) {
                loop {
                    expr(p);
                    n += 1;
                    if !p.eat(COMMA) {
                        break;
                    }
                }
            }
            p.expect(R_PAREN);
            p.start_at(cp, if n == 1 { PAREN_EXPR } else { TUPLE_EXPR });
            p.gt_closes = saved;
        }
        L_BRACE => collection(p, L_BRACE, R_BRACE, false),
        L_PIPE_BRACE => collection(p, L_PIPE_BRACE, R_PIPE_BRACE, false),
        LT => collection(p, LT, GT, true),
        L_MAP => {
            p.start(MAP_EXPR);
            let saved = std::mem::replace(&mut p.gt_closes, false);
            p.bump();
            if !p.at(R_MAP) {
                loop {
                    expr_bp(p, 4);
                    p.expect(YIELD);
                    expr(p);
                    if !p.eat(COMMA) {
                        break;
                    }
                }
            }
            p.expect(R_MAP);
            p.gt_closes = saved;
        }
        _ => {
            p.error("expected an expression");
            // Keep closers and definition boundaries for the callers.
            if !matches!(
                p.current(),
                R_PAREN
                    | R_BRACE
                    | R_BRACK
                    | R_PIPE_BRACE
                    | R_RENAME
                    | R_PAR
                    | GT
                    | EQ
                    | WITHIN_KW
                    | THEN_KW
                    | ELSE_KW
                    | COMMA
                    | EOF
                    | AT
                    | PIPE
                    | ENDMODULE_KW
                    | EXPORTS_KW
            ) && !p.at_line_break()
            {
                p.start(ERROR);
                p.bump();
                p.finish_node();
            }
            return false;
        }
    }
    p.finish_node();
    true
}

/// `{…}`, `{|…|}` and `<…>`: enumerations, ranges and comprehensions.
fn collection(p: &mut Parser, open: SyntaxKind, close: SyntaxKind, seq: bool) {
    let saved = std::mem::replace(&mut p.gt_closes, seq);
    let cp = p.checkpoint();
    p.bump();
    let mut kind = match open {
        L_BRACE => SET_EXPR,
        L_PIPE_BRACE => CLOSURE_EXPR,
        _ => SEQ_EXPR,
    };
    if !p.at(close) {
        expr(p);
        if open != L_PIPE_BRACE && p.eat(DOT2) {
            kind = if seq { SEQ_RANGE } else { SET_RANGE };
            if !p.at(close) && !p.at(PIPE) {
                expr(p);
            }
        } else {
            while p.eat(COMMA) {
                expr(p);
            }
        }
        if p.eat(PIPE) {
            kind = match kind {
                SET_EXPR | SET_RANGE => SET_COMPREHENSION,
                CLOSURE_EXPR => CLOSURE_COMPREHENSION,
                _ => SEQ_COMPREHENSION,
            };
            stmts(p);
        }
    }
    p.gt_closes = saved;
    p.expect(close);
    p.start_at(cp, kind);
}
