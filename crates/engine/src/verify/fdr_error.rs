//! Run-time errors that are FDR's too: a value sent or assigned outside
//! its type. RoboTool bounds the number types by the values of the model's
//! expressions (robotool-facts RT-5), not by the values an assertion gives
//! constants, and its CSPm communicates every value on a channel of its
//! type: FDR stops there with an error, so the assertion has no verdict.
//! The report says what FDR reports and how a RoboTool user gives the
//! types (a `csp Instantiations` block in the assertion file, RT-7).

use super::Verdict;
use crate::ir::{Dom, Val, OUT_OF_DOMAIN};

/// What marks the message of a value outside its type (see
/// `Machine::eval_error`).
const OUTSIDE: &str = " is outside its type's values {";

/// The verdict and reason for the run-time error `err` of a design whose
/// number types are `domains` (`core_nat`, …).
pub(crate) fn runtime_error(err: &str, domains: &[(String, Dom)]) -> (Verdict, String) {
    match out_of_domain(err) {
        Some((v, d)) => (Verdict::Unsupported, fdr_error(err, v, d, domains)),
        None => (Verdict::Inconclusive, format!("the model met a run-time error: {err}")),
    }
}

/// The value and the type's values of an out-of-domain error.
fn out_of_domain(err: &str) -> Option<(Val, Dom)> {
    let at = err.find(OUTSIDE)?;
    let v = err[..at].rsplit(OUT_OF_DOMAIN).next()?.trim().parse().ok()?;
    let (range, _) = err[at + OUTSIDE.len()..].split_once('}')?;
    let (lo, hi) = range.split_once("..")?;
    Some((v, Dom { lo: lo.parse().ok()?, hi: hi.parse().ok()? }))
}

fn fdr_error(err: &str, v: Val, d: Dom, domains: &[(String, Dom)]) -> String {
    let shown = |d: &Dom| format!("{{{}..{}}}", d.lo, d.hi);
    let all: Vec<String> = domains.iter().map(|(n, d)| format!("{n} = {}", shown(d))).collect();
    // The number types with these values: the ones to widen (`int` and
    // `real` often share {-2..2}; widening both is safe).
    let types: Vec<&str> = domains.iter().filter(|(_, x)| *x == d).map(|(n, _)| n.as_str()).collect();
    let (which, fix) = if types.is_empty() {
        (format!("its type's values {}", shown(&d)), "give the type's values there".to_string())
    } else {
        let wide = Dom { lo: d.lo.min(v), hi: d.hi.max(v) };
        // A space after `{`: `{-` opens a CSPm comment.
        let csp = |d: &Dom| format!("{{ {}..{}}}", d.lo, d.hi);
        let lines: Vec<String> = types.iter().map(|n| format!("nametype {n} = {}", csp(&wide))).collect();
        (
            format!("{} = {}", types.join(" = "), shown(&d)),
            format!("for example `{}` (with the other types and definitions the script needs)", lines.join("; ")),
        )
    };
    format!(
        "FDR stops with an error here, so RoboTool gives no verdict: {err}. The value {v} is not in {which} \
         (RT-5: the number types are {}, widened by the values of the model's expressions, not by the values an \
         assertion gives constants). To check with this value, give the types in a `csp Instantiations \
         csp-begin … csp-end` block of the assertion file, as RoboTool users do (it replaces RoboTool's generated \
         defaults, RT-7): {fix}",
        all.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_out_of_domain_error_is_read_back() {
        let err = "the value 15 is outside its type's values {-2..2}, sent or assigned in machine `M`";
        assert_eq!(out_of_domain(err), Some((15, Dom { lo: -2, hi: 2 })));
        assert_eq!(
            out_of_domain("the value -3 is outside its type's values {0..2}, …"),
            Some((-3, Dom { lo: 0, hi: 2 }))
        );
        assert_eq!(out_of_domain("modulus by zero in machine `M`"), None);
    }
}
