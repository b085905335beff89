//! Reading the values, assertions and simulations of an assertion file.

use robosim_syntax::{ast, ast::AstNode, SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use super::{
    child, collapsed, direct_tokens, gap_after, has_token, required_name, required_path, AssertionDecl, AssertionKind,
    Override, Problem, SemanticModelName, SimulationDecl, Value,
};

// ---------------------------------------------------------------------------
// Values

/// Evaluates a value expression: literals, `-e`, `(e)`; else its text.
pub fn eval_value(expr: &SyntaxNode) -> Value {
    match expr.kind() {
        PAREN_EXPR => match expr.children().find(|c| ast::is_expr_kind(c.kind())) {
            Some(inner) if direct_tokens(expr).all(|t| matches!(t.kind(), L_PAREN | R_PAREN)) => {
                match eval_value(&inner) {
                    Value::Other(_) => Value::Other(collapsed(expr)),
                    v => v,
                }
            }
            _ => Value::Other(collapsed(expr)),
        },
        PREFIX_EXPR => {
            let ops: Vec<_> = direct_tokens(expr).collect();
            let operand = expr.children().find(|c| ast::is_expr_kind(c.kind()));
            match (ops.as_slice(), operand) {
                ([op], Some(e)) if op.kind() == MINUS => match eval_value(&e) {
                    Value::Int(n) => n.checked_neg().map(Value::Int).unwrap_or_else(|| Value::Other(collapsed(expr))),
                    _ => Value::Other(collapsed(expr)),
                },
                _ => Value::Other(collapsed(expr)),
            }
        }
        LITERAL => {
            let toks: Vec<_> = direct_tokens(expr).collect();
            match toks.as_slice() {
                [t] => match t.kind() {
                    TRUE_KW => Value::Bool(true),
                    FALSE_KW => Value::Bool(false),
                    INT_NUMBER => t.text().parse().map(Value::Int).unwrap_or_else(|_| Value::Other(t.text().into())),
                    FLOAT_NUMBER => {
                        integral_real(t.text()).map(Value::Int).unwrap_or_else(|| Value::Other(t.text().into()))
                    }
                    _ => Value::Other(t.text().into()),
                },
                _ => Value::Other(collapsed(expr)),
            }
        }
        _ => Value::Other(collapsed(expr)),
    }
}

/// `2.0` → 2, `2.50` → none.
fn integral_real(text: &str) -> Option<i64> {
    let (int, frac) = text.split_once('.')?;
    if !frac.bytes().all(|b| b == b'0') {
        return None;
    }
    int.parse().ok()
}

/// The value expression of a `with` item, its range, and a problem if missing.
fn read_value(node: &SyntaxNode, problems: &mut Vec<Problem>) -> (Value, TextRange) {
    match node.children().find(|c| ast::is_expr_kind(c.kind())) {
        Some(e) => (eval_value(&e), e.text_range()),
        None => {
            let gap =
                gap_after(node, &[SETTER, QUALIFIED_NAME, OF_KW, NAME_REF, CONSTANT_KW, PARAMETER_KW, CYCLE_DEF_KW]);
            problems.push(Problem::new(gap, "missing the value"));
            (Value::Other(String::new()), gap)
        }
    }
}

fn check_period(value: &Value, range: TextRange, problems: &mut Vec<Problem>) {
    match value {
        Value::Int(n) if *n >= 1 => {}
        Value::Other(text) if text.is_empty() => {}
        Value::Int(n) => problems.push(Problem::new(range, format!("the cycle period must be at least 1, not {n}"))),
        Value::Bool(_) | Value::Other(_) => {
            problems.push(Problem::new(range, "the cycle period must be an integer literal"))
        }
    }
}

// ---------------------------------------------------------------------------
// Assertions

pub(super) fn read_assertion(node: &SyntaxNode) -> AssertionDecl {
    let mut problems = Vec::new();
    let timed = child(node, TIMING).and_then(|t| direct_tokens(&t).next()).and_then(|t| match t.kind() {
        TIMED_KW => Some(true),
        UNTIMED_KW => Some(false),
        _ => None,
    });
    let (name, name_range) =
        required_name(node, gap_after(node, &[TIMING, ASSERTION_KW]), "the assertion's name", &mut problems);

    let (model, model_range) = match child(node, SEMANTIC_MODEL) {
        None => (SemanticModelName::Default, None),
        Some(sm) => {
            let model = direct_tokens(&sm).find_map(|t| match t.kind() {
                TRACES_MODEL_KW => Some(SemanticModelName::Traces),
                FAILURES_MODEL_KW => Some(SemanticModelName::Failures),
                FAILURES_DIVERGENCES_MODEL_KW => Some(SemanticModelName::FailuresDivergences),
                TICK_TOCK_MODEL_KW => Some(SemanticModelName::TickTock),
                _ => None,
            });
            if model.is_none() {
                problems.push(Problem::new(
                    sm.text_range(),
                    format!("unknown semantic model `{}`: the default model is used", collapsed(&sm)),
                ));
            }
            (model.unwrap_or(SemanticModelName::Default), Some(sm.text_range()))
        }
    };

    let body = child(node, ASSERTION_BODY);
    let is_clock = body.as_ref().is_some_and(|b| has_token(b, CLOCK_KW));
    let subject_gap = gap_after(node, &[TIMING, ASSERTION_KW, NAME, COLON]);
    let (subject, subject_range) = if is_clock {
        let b = body.as_ref().expect("is_clock implies a body");
        required_path(child(b, QUALIFIED_NAME), gap_after(b, &[CLOCK_KW]), "the clock", &mut problems)
    } else {
        let q = child(node, ASSERTION_SUBJECT).and_then(|s| child(&s, QUALIFIED_NAME));
        let gap =
            child(node, ASSERTION_SUBJECT).map(|s| TextRange::empty(s.text_range().start())).unwrap_or(subject_gap);
        required_path(q, gap, "the assertion's subject", &mut problems)
    };

    let (kind, negated) = match &body {
        Some(b) => read_body(b, model, &subject, subject_range, &mut problems),
        None => {
            problems
                .push(Problem::new(gap_after(node, &[ASSERTION_SUBJECT, COLON, NAME]), "missing the assertion's body"));
            (AssertionKind::Other(String::new()), false)
        }
    };

    let mut overrides = Vec::new();
    if let Some(list) = child(node, PARAM_ASSIGNMENTS) {
        for p in list.children() {
            if let Some(o) = read_override(&p, &mut problems) {
                overrides.push(o);
            }
        }
        if overrides.is_empty() {
            problems.push(Problem::new(list.text_range(), "missing the parameters after `with`"));
        }
    }

    AssertionDecl {
        name,
        name_range,
        range: node.text_range(),
        text: collapsed(node),
        subject,
        subject_range,
        negated,
        kind,
        timed,
        model,
        model_range,
        overrides,
        problems,
    }
}

fn read_body(
    body: &SyntaxNode,
    model: SemanticModelName,
    subject: &[String],
    subject_range: TextRange,
    problems: &mut Vec<Problem>,
) -> (AssertionKind, bool) {
    let toks: Vec<SyntaxKind> = direct_tokens(body).map(|t| t.kind()).collect();
    let negated = toks.contains(&NOT_KW);
    let incomplete = |problems: &mut Vec<Problem>, what: &str| {
        problems.push(Problem::new(body.text_range(), format!("incomplete assertion: {what}")));
        (AssertionKind::Other(collapsed(body)), negated)
    };
    let other = |kw: &[SyntaxKind], what: &str, problems: &mut Vec<Problem>| {
        required_path(child(body, QUALIFIED_NAME), gap_after(body, kw), what, problems)
    };
    match toks.first() {
        Some(CLOCK_KW) => {
            if !toks.contains(&INITIALISED_KW) {
                return incomplete(problems, "expected `is [not] initialised` after the clock");
            }
            let kind = AssertionKind::ClockInitialised { clock: subject.to_vec(), clock_range: subject_range };
            (kind, negated)
        }
        Some(IS_KW) => {
            let property = toks.iter().find_map(|k| match k {
                SCHEDULABLE_KW => Some(AssertionKind::Schedulable),
                DEADLOCK_FREE_KW => Some(AssertionKind::DeadlockFree),
                DIVERGENCE_FREE_KW => Some(AssertionKind::DivergenceFree),
                DETERMINISTIC_KW => Some(AssertionKind::Deterministic),
                TIMELOCK_FREE_KW => Some(AssertionKind::TimelockFree),
                _ => None,
            });
            if let Some(kind) = property {
                (kind, negated)
            } else if toks.contains(&REACHABLE_KW) {
                let (machine, machine_range) =
                    other(&[REACHABLE_KW, IN_KW], "the machine after `reachable in`", problems);
                let kind = AssertionKind::Reachable {
                    state: subject.to_vec(),
                    state_range: subject_range,
                    machine,
                    machine_range,
                };
                (kind, negated)
            } else if toks.contains(&EQUAL_KW) {
                let (other, other_range) = other(&[EQUAL_KW, TO_KW], "the element after `equal to`", problems);
                (AssertionKind::Equals { other, other_range, model }, negated)
            } else {
                incomplete(problems, "expected a property after `is`")
            }
        }
        Some(TERMINATES_KW) => (AssertionKind::Terminates, false),
        Some(DOES_KW) => {
            if toks.contains(&REFINE_KW) {
                let (other, other_range) = other(&[REFINE_KW], "the element after `does not refine`", problems);
                (AssertionKind::Refines { other, other_range, model }, true)
            } else if toks.contains(&TERMINATE_KW) {
                (AssertionKind::Terminates, true)
            } else {
                incomplete(problems, "expected `refine` or `terminate` after `does not`")
            }
        }
        Some(REFINES_KW) => {
            let (other, other_range) = other(&[REFINES_KW], "the element after `refines`", problems);
            (AssertionKind::Refines { other, other_range, model }, false)
        }
        Some(EQUALS_KW) => {
            let (other, other_range) = other(&[EQUALS_KW], "the element after `equals`", problems);
            (AssertionKind::Equals { other, other_range, model }, false)
        }
        _ => incomplete(problems, "expected `is …`, `refines`, `equals`, `does not …` or `terminates`"),
    }
}

fn read_override(p: &SyntaxNode, problems: &mut Vec<Problem>) -> Option<Override> {
    let kind = p.kind();
    if !matches!(kind, CONSTANT_PARAM | PARAMETER_PARAM | CYCLE_DEF_PARAM) {
        return None;
    }
    let (name, name_range) = match child(p, NAME_REF).and_then(ast::NameRef::cast) {
        Some(n) if !n.text().is_empty() => (n.text(), n.syntax().text_range()),
        _ if kind == CYCLE_DEF_PARAM => (String::new(), TextRange::empty(p.text_range().start())),
        _ => {
            let gap = gap_after(p, &[CONSTANT_KW, PARAMETER_KW]);
            let what = if kind == CONSTANT_PARAM { "the constant's name" } else { "the parameter's name" };
            problems.push(Problem::new(gap, format!("missing {what}")));
            (String::new(), gap)
        }
    };
    let (of, of_range) = required_path(
        child(p, QUALIFIED_NAME),
        gap_after(p, &[OF_KW, NAME_REF, CONSTANT_KW, PARAMETER_KW, CYCLE_DEF_KW]),
        "the element after `of`",
        problems,
    );
    let (value, value_range) = read_value(p, problems);
    let range = p.text_range();
    if kind == CYCLE_DEF_PARAM {
        check_period(&value, value_range, problems);
        return Some(Override::CycleDef { of, of_range, value, value_range, range });
    }
    Some(if kind == CONSTANT_PARAM {
        Override::Constant { name, name_range, of, of_range, value, value_range, range }
    } else {
        Override::Parameter { name, name_range, of, of_range, value, value_range, range }
    })
}

// ---------------------------------------------------------------------------
// Simulations

pub(super) fn read_simulation(node: &SyntaxNode) -> SimulationDecl {
    let mut problems = Vec::new();
    let (name, name_range) =
        required_name(node, gap_after(node, &[SIMULATION_KW]), "the simulation's name", &mut problems);
    let (of, of_range) = required_path(
        child(node, QUALIFIED_NAME),
        gap_after(node, &[OF_KW, NAME, SIMULATION_KW]),
        "the simulated element after `of`",
        &mut problems,
    );
    let mut cycle = None;
    let mut cycle_range = None;
    for def in node.children().filter(|c| c.kind() == CYCLE_DEF) {
        if cycle.is_some() {
            problems.push(Problem::new(def.text_range(), "a simulation has one `cycleDef`: this one is ignored"));
            continue;
        }
        cycle_range = Some(def.text_range());
        let Some(expr) = def.children().find(|c| ast::is_expr_kind(c.kind())) else {
            problems.push(Problem::new(gap_after(&def, &[CYCLE_DEF_KW]), "missing `cycle == N` after `cycleDef`"));
            cycle = Some(Value::Other(String::new()));
            continue;
        };
        let value = match cycle_equation(&expr) {
            Some(v) => {
                let value = eval_value(&v);
                check_period(&value, v.text_range(), &mut problems);
                value
            }
            None => {
                problems.push(Problem::new(expr.text_range(), "expected `cycleDef cycle == N` with an integer `N`"));
                Value::Other(collapsed(&expr))
            }
        };
        cycle = Some(value);
    }
    SimulationDecl { name, name_range, range: node.text_range(), of, of_range, cycle, cycle_range, problems }
}

/// `cycle == e`, `e == cycle`, `(…)`, `{ … }` (one element): `e`.
fn cycle_equation(expr: &SyntaxNode) -> Option<SyntaxNode> {
    let inner = |e: &SyntaxNode| -> Option<SyntaxNode> {
        let mut exprs = e.children().filter(|c| ast::is_expr_kind(c.kind()));
        let first = exprs.next()?;
        exprs.next().is_none().then_some(first)
    };
    match expr.kind() {
        PAREN_EXPR => cycle_equation(&inner(expr)?),
        SET_EXPR if !has_token(expr, COMMA) => cycle_equation(&inner(expr)?),
        BIN_EXPR if ast::binary_operator(expr) == Some(EQ2) => {
            let ops = ast::operand_exprs(expr);
            let [a, b] = ops.as_slice() else { return None };
            let is_cycle = |e: &SyntaxNode| {
                let mut e = e.clone();
                while e.kind() == PAREN_EXPR {
                    match inner(&e) {
                        Some(i) => e = i,
                        None => return false,
                    }
                }
                e.kind() == CYCLE_EXPR
            };
            if is_cycle(a) {
                Some(b.clone())
            } else if is_cycle(b) {
                Some(a.clone())
            } else {
                None
            }
        }
        _ => None,
    }
}
