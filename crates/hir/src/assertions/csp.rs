//! A line-based reader for the instantiation subset of CSPm. Comments
//! (`--`, `{- -}`) are dropped; each remaining non-blank line is one
//! [`CspLine`]. A line is read as an instantiation only if it starts a
//! top-level definition: a line inside open brackets or inside a
//! `let … within` (a local definition), and a line followed by one that
//! starts with an operator (the definition goes on), is [`CspLineKind::Other`].

use robosim_syntax::{ast, ast::AstNode, SyntaxKind::*, SyntaxNode, TextRange, TextSize};

use super::{
    child, direct_tokens, gap_after, required_name, CspBlockDecl, CspLine, CspLineKind, Instantiations, Problem, Value,
};

pub(super) fn read_csp_block(node: &SyntaxNode, inst: &mut Instantiations) -> CspBlockDecl {
    let mut problems = Vec::new();
    let timed = child(node, TIMING).and_then(|t| direct_tokens(&t).next()).is_some_and(|t| t.kind() == TIMED_KW);
    let (name, name_range) =
        required_name(node, gap_after(node, &[TIMING, CSP_KW]), "the CSP block's name", &mut problems);
    let associated = child(node, ASSOCIATED_TO)
        .map(|a| a.children().filter_map(ast::QualifiedName::cast).map(|q| q.segments()).collect())
        .unwrap_or_default();
    let mut lines = Vec::new();
    let mut text_range = None;
    let understood = match direct_tokens(node).find(|t| t.kind() == CSP_TEXT) {
        None => {
            problems.push(Problem::new(
                gap_after(node, &[NAME, ASSOCIATED_TO, CSP_KW]),
                "missing the CSP text `csp-begin … csp-end`",
            ));
            false
        }
        Some(tok) => {
            let text = tok.text();
            let start = tok.text_range().start();
            let body_start = if text.starts_with("csp-begin") { "csp-begin".len() } else { 0 };
            let terminated = text.len() >= body_start + "csp-end".len() && text.ends_with("csp-end");
            let body_end = if terminated {
                text.len() - "csp-end".len()
            } else {
                problems.push(Problem::new(tok.text_range(), "unterminated CSP block: expected `csp-end`"));
                text.len()
            };
            let body = &text[body_start..body_end];
            let offset = start + TextSize::from(body_start as u32);
            text_range = Some(TextRange::at(offset, TextSize::from(body.len() as u32)));
            read(body, offset, inst, &mut lines, &mut problems);
            terminated && lines.iter().all(|l: &CspLine| l.kind != CspLineKind::Other)
        }
    };
    CspBlockDecl {
        name,
        name_range,
        range: node.text_range(),
        timed,
        understood,
        associated,
        text_range,
        lines,
        problems,
    }
}

/// RoboTool's saturating arithmetic, without whitespace.
const STANDARD: &[&str] = &[
    "Plus(e1,e2,T)=ifmember(e1+e2,T)thene1+e2elsee1",
    "Minus(e1,e2,T)=ifmember(e1-e2,T)thene1-e2elsee1",
    "Mult(e1,e2,T)=ifmember(e1*e2,T)thene1*e2elsee1",
    "Div(e1,e2,T)=ifmember(e1/e2,T)thene1/e2elsee1",
    "Modulus(e1,e2,T)=ifmember(e1%e2,T)thene1%e2elsee1",
    "Neg(e1,T)=ifmember(-e1,T)then-e1elsee1",
];

/// A non-blank line of the block, comments blanked out.
struct Line<'a> {
    text: &'a str,
    /// Offset of `text` in the block.
    at: usize,
    /// Whether it continues a definition of the lines before (inside
    /// brackets or a `let … within`).
    continuation: bool,
}

/// Reads `body` (the text between `csp-begin` and `csp-end`, which
/// starts at `offset` in the file): fills `inst`, `lines` and `problems`.
fn read(
    body: &str,
    offset: TextSize,
    inst: &mut Instantiations,
    lines: &mut Vec<CspLine>,
    problems: &mut Vec<Problem>,
) {
    let range = |at: usize, len: usize| TextRange::at(offset + TextSize::from(at as u32), TextSize::from(len as u32));
    let masked = mask_comments(body, &mut |at, len, msg| problems.push(Problem::new(range(at, len), msg)));
    let all = split_lines(&masked);
    for (i, line) in all.iter().enumerate() {
        let r = range(line.at, line.text.len());
        let next_continues = all.get(i + 1).is_some_and(|n| starts_with_operator(n.text));
        let kind = if line.continuation || next_continues {
            CspLineKind::Other
        } else {
            classify(line.text, r, inst, problems)
        };
        lines.push(CspLine { range: r, kind });
    }
}

/// `body` with `--` and `{- … -}` comments replaced by spaces (newlines
/// kept, so offsets stay). `{-` followed by a digit is kept as the
/// negative bound the user meant, with a problem, since FDR would read
/// a comment there.
fn mask_comments(body: &str, problem: &mut dyn FnMut(usize, usize, String)) -> String {
    let b = body.as_bytes();
    let mut out = b.to_vec();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'-' && b.get(i + 1) == Some(&b'-') {
            while i < b.len() && b[i] != b'\n' {
                out[i] = b' ';
                i += 1;
            }
        } else if b[i] == b'{' && b.get(i + 1) == Some(&b'-') {
            if b.get(i + 2).is_some_and(|c| c.is_ascii_digit()) {
                problem(i, 2, "`{-` starts a comment in CSPm: write `{ -…}` with a space for FDR".to_string());
                i += 2;
                continue;
            }
            let end = body[i + 2..].find("-}").map(|j| i + 2 + j + 2).unwrap_or(b.len());
            for (k, c) in out.iter_mut().enumerate().take(end).skip(i) {
                if b[k] != b'\n' {
                    *c = b' ';
                }
            }
            i = end;
        } else {
            i += 1;
        }
    }
    // Only whole runs of ASCII-delimited comments were blanked, so the
    // text stays valid UTF-8; be total anyway.
    String::from_utf8(out).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

fn split_lines(masked: &str) -> Vec<Line<'_>> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut brackets = 0usize;
    let mut lets = 0usize;
    for raw in masked.split('\n') {
        let start = at;
        at += raw.len() + 1;
        let text = raw.trim();
        if text.is_empty() {
            continue;
        }
        let lead = raw.len() - raw.trim_start().len();
        out.push(Line { text, at: start + lead, continuation: brackets > 0 || lets > 0 });
        for c in text.chars() {
            match c {
                '(' | '[' | '{' => brackets += 1,
                ')' | ']' | '}' => brackets = brackets.saturating_sub(1),
                _ => {}
            }
        }
        for w in text.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '\'')) {
            match w {
                "let" => lets += 1,
                "within" => lets = lets.saturating_sub(1),
                _ => {}
            }
        }
    }
    out
}

/// Whether a line continues the expression of the line before.
fn starts_with_operator(text: &str) -> bool {
    text.starts_with(|c: char| "+-*/%^.,)]}|&=<>@:;\\[?!~".contains(c))
        || ["then", "else", "within", "and", "or"].iter().any(|k| {
            text.strip_prefix(k).is_some_and(|rest| rest.is_empty() || rest.starts_with(|c: char| !is_ident(c)))
        })
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '\''
}

fn is_identifier(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && s.chars().all(is_ident)
}

fn classify(text: &str, range: TextRange, inst: &mut Instantiations, problems: &mut Vec<Problem>) -> CspLineKind {
    let squashed: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if STANDARD.contains(&squashed.as_str()) {
        return CspLineKind::Standard;
    }
    if let Some(rest) = text.strip_prefix("nametype").filter(|r| r.starts_with(char::is_whitespace)) {
        let Some((name, rhs)) = rest.split_once('=') else { return CspLineKind::Other };
        let (name, rhs) = (name.trim(), rhs.trim());
        if !is_identifier(name) || rhs.starts_with('=') {
            return CspLineKind::Other;
        }
        let rhs_squashed: String = rhs.chars().filter(|c| !c.is_whitespace()).collect();
        let base = name.strip_prefix("core_").unwrap_or(name);
        if (base == "boolean" && rhs_squashed == "Bool") || (base == "string" && rhs_squashed == "LSeq(Char,2)") {
            return CspLineKind::Standard;
        }
        return match int_range(rhs) {
            Some(Ok((lo, hi))) => {
                inst.types.push((name.to_string(), lo, hi, range));
                CspLineKind::Type
            }
            Some(Err(msg)) => {
                problems.push(Problem::new(range, format!("`nametype {name}`: {msg}")));
                CspLineKind::Other
            }
            None => CspLineKind::Other,
        };
    }
    if let Some((name, params, body)) = crate::csp_fn::parse_definition(text) {
        inst.functions.push(crate::csp_fn::CspFunction { name, params, body, range });
        return CspLineKind::Function;
    }
    if let Some((name, rhs)) = text.split_once('=') {
        let name = name.trim();
        if is_identifier(name) && !rhs.starts_with('=') {
            if let Some(v) = literal(rhs.trim()) {
                inst.constants.push((name.to_string(), v, range));
                return CspLineKind::Constant;
            }
        }
    }
    CspLineKind::Other
}

/// A CSPm integer or boolean literal, possibly negated or parenthesised.
fn literal(text: &str) -> Option<Value> {
    let text = text.trim();
    if let Some(inner) = text.strip_prefix('(').and_then(|t| t.strip_suffix(')')) {
        return literal(inner);
    }
    match text {
        "true" => return Some(Value::Bool(true)),
        "false" => return Some(Value::Bool(false)),
        _ => {}
    }
    int(text).map(Value::Int)
}

fn int(text: &str) -> Option<i64> {
    let text = text.trim();
    if let Some(rest) = text.strip_prefix('-') {
        return int(rest)?.checked_neg();
    }
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

/// `{a..b}` or a set of integers `{a, b, c}`: `Some(Ok(bounds))` when it
/// is a non-empty contiguous range, `Some(Err(why))` when it is a set of
/// integers that is not, `None` when it is something else.
fn int_range(rhs: &str) -> Option<Result<(i64, i64), String>> {
    let inner = rhs.strip_prefix('{')?.strip_suffix('}')?.trim();
    if let Some((lo, hi)) = inner.split_once("..") {
        let (lo, hi) = (int(lo)?, int(hi)?);
        return Some(if lo <= hi { Ok((lo, hi)) } else { Err(format!("the range {lo}..{hi} is empty")) });
    }
    if inner.is_empty() {
        return Some(Err("the set is empty".to_string()));
    }
    let mut values = inner.split(',').map(int).collect::<Option<Vec<_>>>()?;
    values.sort_unstable();
    values.dedup();
    let (lo, hi) = (values[0], values[values.len() - 1]);
    let contiguous = i128::from(hi) - i128::from(lo) + 1 == values.len() as i128;
    Some(if contiguous {
        Ok((lo, hi))
    } else {
        Err(format!(
            "{{{}}} is not a contiguous range of integers, which is all the native checker supports",
            values.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_sets() {
        assert_eq!(int_range("{0..3}"), Some(Ok((0, 3))));
        assert_eq!(int_range("{ -2 .. 2 }"), Some(Ok((-2, 2))));
        assert_eq!(int_range("{1, 0, 2, 2}"), Some(Ok((0, 2))));
        assert_eq!(int_range("{5}"), Some(Ok((5, 5))));
        assert!(matches!(int_range("{0, 2}"), Some(Err(_))));
        assert!(matches!(int_range("{2..1}"), Some(Err(_))));
        assert!(matches!(int_range("{}"), Some(Err(_))));
        assert_eq!(int_range("{a..b}"), None);
        assert_eq!(int_range("Bool"), None);
        assert_eq!(int_range("{0..99999999999999999999}"), None);
    }

    #[test]
    fn literals() {
        assert_eq!(literal("12"), Some(Value::Int(12)));
        assert_eq!(literal("-(3)"), None);
        assert_eq!(literal("(-3)"), Some(Value::Int(-3)));
        assert_eq!(literal("- 3"), Some(Value::Int(-3)));
        assert_eq!(literal("true"), Some(Value::Bool(true)));
        assert_eq!(literal("1.5"), None);
        assert_eq!(literal("x"), None);
        assert_eq!(literal(""), None);
    }

    #[test]
    fn comments_are_blanked_in_place() {
        let mut problems = Vec::new();
        let text = "a -- b\n{- c\nd -} e\n{-2..2}";
        let masked = mask_comments(text, &mut |at, len, msg| problems.push((at, len, msg)));
        assert_eq!(masked, "a     \n    \n     e\n{-2..2}");
        assert_eq!(problems.len(), 1);
        assert_eq!(mask_comments("{- open", &mut |_, _, _| {}), "       ");
        assert_eq!(mask_comments("é -- é\nx", &mut |_, _, _| {}), "é      \nx");
    }
}
