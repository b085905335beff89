//! RT-12: an asynchronous connection between two controllers of a module
//! is RoboTool's one-place buffer that overwrites, as RoboTool generates
//! it (`Buffer0` of `reference/alpha-algorithm/csp-gen/timed/defs/
//! main_AggregationSoftware.csp`):
//!
//! ```text
//! Buffer0(<v>) = S::e.out?x -> Buffer0(<x>) [] R::f.in!v -> Buffer0(<>)
//! Buffer0(<>)  = S::e.out?x -> Buffer0(<x>)
//! ```
//!
//! in parallel with the controllers on both whole channels (so the sender
//! never blocks, an unread value is lost when the next one arrives, and
//! the other direction of each channel is refused), both hidden; the
//! container's `TimedPriority` gives the hidden transfers priority over
//! `tock`, as RoboTool's `prioritise(…, <…, {tock}>)` does. RoboTool's
//! buffer is in a `Timed` section, where it lets time pass in every
//! state; ours leaves `tock` out of its synchronisation, which is the
//! same.

use std::collections::BTreeMap;

use robosim_hir::{File, TextRange};

use crate::cspm::{ext, name, prefix, Decl, Expr, Field};
use crate::export::Chan;
use crate::machine::Problem;

/// An asynchronous link between two components: (sender's instance and
/// event, receiver's, the connection's range).
pub(super) type AsyncLink = ((usize, Chan), (usize, Chan), TextRange);

/// Why the links `links` of a container (of `file`) cannot be exported,
/// given how many connections name each (instance, event) end: an end
/// that another connection names too would be renamed or synchronised
/// elsewhere, and RoboTool's text for that is not known.
pub(super) fn check_ends(
    file: File,
    links: &[AsyncLink],
    uses: &BTreeMap<(usize, String), usize>,
    problems: &mut Vec<Problem>,
) {
    for ((i, ca), (j, cb), range) in links {
        for (x, ch) in [(i, ca), (j, cb)] {
            if uses.get(&(*x, ch.model.clone())).copied().unwrap_or(0) > 1 {
                problems.push((
                    file,
                    *range,
                    format!(
                        "the event `{}` has an asynchronous connection and another one: RoboTool's buffer is \
                         known for an event connected once only (RT-12)",
                        ch.model
                    ),
                ));
            }
        }
    }
}

/// The `k`th buffer (from 1), between the channels `sender` and
/// `receiver` (qualified CSPm names) carrying `values`; `out` and `inp`
/// name `InOut`'s constructors. Returns its declarations (private to the
/// container's module) and the process to compose.
pub(super) fn buffer(
    k: usize,
    sender: &str,
    receiver: &str,
    values: &[Expr],
    out: Expr,
    inp: Expr,
) -> (Vec<Decl>, Expr) {
    let empty = format!("Buffer{k}__");
    let full = format!("Buffer{k}Full__");
    let vars = |p: &str| (0..values.len()).map(|n| format!("{p}{n}__")).collect::<Vec<_>>();
    let (xs, ys) = (vars("x"), vars("y"));
    let call_full = |vs: &[String]| {
        if vs.is_empty() {
            name(full.clone())
        } else {
            crate::cspm::call(full.clone(), vs.iter().map(|v| name(v.clone())).collect())
        }
    };
    let send = |vs: &[String]| {
        let mut fields = vec![Field::Dot(out.clone())];
        fields.extend(vs.iter().map(|v| Field::In(v.clone())));
        prefix(sender, fields, call_full(vs))
    };
    let mut take = vec![Field::Dot(inp)];
    take.extend(xs.iter().map(|v| Field::Out(name(v.clone()))));
    let decls = vec![
        Decl::Comment(format!(
            "RT-12: the asynchronous connection {sender} → {receiver}, RoboTool's one-place buffer that \
             overwrites:\n{empty} holds no value, {full} one."
        )),
        Decl::Def(empty.clone(), vec![], send(&xs)),
        Decl::Def(full.clone(), xs.clone(), ext(vec![send(&ys), prefix(receiver, take, name(empty.clone()))])),
    ];
    (decls, name(empty))
}
