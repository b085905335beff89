//! Name resolution and type checking: exact codes, ranges and messages.

use robosim_cspm::{Code, Module, NoNames};

/// (code, the text the diagnostic covers, its message) of every diagnostic.
fn diags(text: &str) -> Vec<(Code, String, String)> {
    Module::check(text, &NoNames)
        .diagnostics()
        .iter()
        .map(|d| (d.code, text[d.range].to_owned(), d.message.clone()))
        .collect()
}

#[test]
fn unresolved_and_duplicate_names() {
    let d = diags("channel c : {0..1}\nP = c?x?x -> Q\nP = STOP\nS = {y | y <- {1}, y <- {2}}");
    let got: Vec<_> = d.iter().map(|(c, t, _)| (*c, t.as_str())).collect();
    assert_eq!(got, [(Code::Duplicate, "x"), (Code::Unresolved, "Q"), (Code::Duplicate, "P"), (Code::Duplicate, "y"),]);
}

#[test]
fn type_errors_point_at_the_offending_expression() {
    let d = diags("channel a\nP = a -> 1\nQ = STOP [] {a}\nf(x) = x + 1\nR = f(true)\nS = if 1 then STOP else STOP");
    let got: Vec<_> = d.iter().map(|(c, t, m)| (*c, t.as_str(), m.as_str())).collect();
    assert_eq!(
        got,
        [
            (Code::Type, "1", "type error: expected a process, found Int"),
            (Code::Type, "{a}", "type error: expected a process, found a set of events"),
            (Code::Type, "f(true)", "type error: expected a function of 1 argument(s) returning Int, found a function of 1 argument(s) returning a value"),
            (Code::Type, "1", "type error: expected Bool, found Int"),
        ]
    );
}

#[test]
fn dotted_values_and_polymorphism_are_not_errors() {
    // Channels with data and dotted values are not modelled by the checker:
    // they never cause an error; top-level definitions are polymorphic.
    let text = "datatype T = A | B.{0..1}\nchannel c : T.Bool\nid(x) = x\nP = c.B.id(1)!id(true) -> STOP\nn = id(3) + 1\nb = id(true) and true";
    assert_eq!(diags(text), []);
}

#[test]
fn timed_only_names_and_processes_compared() {
    let d = diags("channel tock\nP = WAIT(2)\nb = STOP == STOP");
    let got: Vec<_> = d.iter().map(|(c, t, _)| (*c, t.as_str())).collect();
    assert_eq!(got, [(Code::Unresolved, "WAIT"), (Code::Type, "STOP == STOP")]);
    assert_eq!(diags("channel tock\nTimed(\\ _ @ 1) { P = WAIT(2) }"), []);
}
