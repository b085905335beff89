//! The well-formedness rules per element, independent of where the
//! element sits in its file (as [`crate::element`] does for resolution and
//! typing).
//!
//! Each element's rules run on its own definitions ([`element_defs`]:
//! positions relative to its start), so that a keystroke inside one
//! machine re-runs that machine's rules only. Rules about a container's
//! parts in other elements (a controller's `sref` machines, a module's
//! `cref` controllers) read those elements through small position-free
//! queries (members, summaries, [`name_place`], cycle specifications,
//! usages), which salsa backdates when an edit leaves them equal: the
//! controller's rules are then not run again. Every range a problem holds
//! is a [`Place`], relative to an element's start, and
//! [`crate::file_diagnostics`] adds the starts back.

use robosim_syntax::{SyntaxNode, TextRange, TextSize};
use rustc_hash::FxHashMap;
use salsa::plumbing::AsId;

use crate::checks::{dup_group, Anchor, Place, Problem};
use crate::cycle::CycleInfo;
use crate::defs::{file_defs, DefId, DefKind, FileDefs};
use crate::element::{element_defs, element_list, element_of, file_elements, Element};
use crate::{Db, File, Workspace};

/// The rule problems of one element, each list in the order the rules of
/// the file-level modules give them.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ElementRules {
    /// Declaration-level rules (`checks`).
    pub checks: Vec<Problem>,
    /// RoboSim's rules on inputs and outputs (`robosim`).
    pub robosim: Vec<Problem>,
    /// Rules relating a container to its parts (`more_checks`).
    pub more: Vec<Problem>,
}

/// The rules of `element` but the cycle rules.
#[salsa::tracked(returns(ref))]
pub fn element_rules(db: &dyn Db, ws: Workspace, element: Element) -> ElementRules {
    let file = element.file(db);
    let defs = element_defs(db, element);
    let root = SyntaxNode::new_root(element.green(db).0.clone());
    ElementRules {
        checks: crate::checks::element_checks(db, ws, file, defs),
        robosim: crate::robosim::element_robosim(db, ws, file, defs),
        more: crate::more_checks::element_more(db, ws, file, defs, &root),
    }
}

/// The cycle rules of `element`, and what they found about each
/// container's period.
#[salsa::tracked(returns(ref))]
pub fn element_cycles(db: &dyn Db, ws: Workspace, element: Element) -> (Vec<Problem>, Vec<(DefId, CycleInfo)>) {
    crate::cycle::element_cycle_checks(db, ws, element.file(db), element_defs(db, element))
}

/// The definitions that hold `id` of `file` (its element's, positions
/// relative to the element's start) and what their positions are relative
/// to.
pub(crate) fn defs_at(db: &dyn Db, file: File, id: DefId) -> (&FileDefs, Anchor) {
    match element_of(db, file, id) {
        Some(e) => (element_defs(db, e), Anchor::Element(e.as_id())),
        None => (file_defs(db, file), Anchor::File),
    }
}

/// Where the name of the definition `id` of `file` is: changes only when
/// text before the name in its element does.
#[salsa::tracked(returns(copy))]
pub(crate) fn name_place(db: &dyn Db, file: File, id: DefId) -> Place {
    let (defs, anchor) = defs_at(db, file, id);
    Place { file, anchor, range: defs.def(id).name_range }
}

/// Where the first `input context` and `output context` of the container
/// `id` of `file` are.
#[salsa::tracked(returns(copy))]
pub(crate) fn context_places(db: &dyn Db, file: File, id: DefId) -> (Option<Place>, Option<Place>) {
    let (defs, anchor) = defs_at(db, file, id);
    let facts = defs.facts(id);
    let place = |r: Option<&TextRange>| r.map(|r| Place { file, anchor, range: *r });
    (place(facts.input_contexts.first()), place(facts.output_contexts.first()))
}

/// The uses (`uses`, `requires`, `provides`) of the context `id` of
/// `file`, with where each interface name is: for the rules on a
/// container's parts, which should not run again when an edit moves text
/// after the uses.
#[salsa::tracked(returns(ref))]
pub(crate) fn use_places(db: &dyn Db, file: File, id: DefId) -> Vec<(crate::defs::Use, Anchor)> {
    let (defs, anchor) = defs_at(db, file, id);
    defs.uses_of(id).map(|u| (u.clone(), anchor)).collect()
}

/// DUP-01 between top-level definitions of `file` (those inside an element
/// are its own rules').
#[salsa::tracked(returns(ref))]
pub(crate) fn top_duplicates(db: &dyn Db, file: File) -> Vec<Problem> {
    let mut out = Vec::new();
    let mut seen: FxHashMap<(u8, &str), (Anchor, &crate::element::Head)> = FxHashMap::default();
    let mut reported = rustc_hash::FxHashSet::default();
    for e in element_list(db, file) {
        let anchor = Anchor::Element(e.as_id());
        // Published by the element: an edit inside one leaves the others'
        // alone, and this query is re-validated without looking at them.
        for head in &e.public(db).heads {
            let (kind, name, range) = head;
            if name.is_empty() || *kind == DefKind::Connection {
                continue;
            }
            match seen.get(&(dup_group(*kind), name.as_str())) {
                Some(&(fa, first)) => {
                    let (fkind, fname, frange) = first;
                    // Every duplicate is reported, the first one included.
                    if reported.insert((fa, *frange)) {
                        out.push(
                            Problem::new("DUP-01", *frange, format!("duplicate {} `{fname}`", fkind.describe()))
                                .at(fa)
                                .with_related(
                                    Place { file, anchor, range: *range },
                                    format!("`{name}` is declared again here"),
                                ),
                        );
                    }
                    out.push(
                        Problem::new("DUP-01", *range, format!("duplicate {} `{name}`", kind.describe()))
                            .at(anchor)
                            .with_related(
                                Place { file, anchor: fa, range: *frange },
                                format!("`{fname}` is first declared here"),
                            ),
                    );
                }
                None => {
                    seen.insert((dup_group(*kind), name.as_str()), (anchor, head));
                }
            }
        }
    }
    out
}

/// The starts of the elements of `file` (for [`Placer`]).
fn starts(db: &dyn Db, file: File) -> FxHashMap<salsa::Id, u32> {
    file_elements(db, file).iter().map(|(e, at)| (e.as_id(), *at)).collect()
}

/// Puts ranges back in their files: adds the start of the element they
/// are relative to.
pub(crate) struct Placer<'a> {
    db: &'a dyn Db,
    file: File,
    starts: FxHashMap<salsa::Id, u32>,
}

impl<'a> Placer<'a> {
    /// For the problems of `file`.
    pub fn new(db: &'a dyn Db, file: File) -> Placer<'a> {
        Placer { db, file, starts: starts(db, file) }
    }

    /// `range` of `file`, relative to `anchor` (`here` for [`Anchor::Here`]).
    pub fn range(&self, file: File, anchor: Anchor, range: TextRange, here: u32) -> TextRange {
        let by = match anchor {
            Anchor::Here => here,
            Anchor::File => 0,
            Anchor::Element(id) if file == self.file => self.starts.get(&id).copied().unwrap_or(0),
            Anchor::Element(id) => starts(self.db, file).get(&id).copied().unwrap_or(0),
        };
        range + TextSize::from(by)
    }
}
