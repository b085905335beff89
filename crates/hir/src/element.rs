//! Per-element results, independent of where the element sits in its file.
//!
//! A keystroke inside one machine should cost the work of that machine,
//! not of the file. The top-level elements of a file (interfaces,
//! machines, controllers, modules, …) are salsa tracked structs
//! ([`Element`]) whose identity is their kind, name and rank among
//! same-named elements of that kind, as rust-analyzer's `AstId`s are: an
//! edit elsewhere in the file leaves them, and their syntax, unchanged.
//! Name resolution, resolution in behaviour and typing run per element on
//! the element's own tree, re-rooted so that its positions start at 0
//! ([`element_problems`]); [`crate::file_diagnostics`] adds each
//! element's start back. Definition ids stay the file's (an element's
//! definitions are numbered from the count of those before it), so that
//! results name definitions as the file-level queries do.

use std::borrow::Cow;

use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange, TextSize};
use rustc_hash::FxHashMap;

use crate::defs::{file_defs, lower_element, lower_header, DefId, FileDefs};
use crate::resolve::{Ctx, Member, ResolveProblem};
use crate::walk::NodeTable;
use crate::{parse, Db, File, Workspace};

/// A top-level element's syntax, compared by identity first: the trees of
/// elements an edit did not touch are the very same nodes after an
/// incremental reparse.
#[derive(Debug, Clone)]
pub struct Green(pub rowan::GreenNode);

impl PartialEq for Green {
    fn eq(&self, other: &Green) -> bool {
        std::ptr::eq::<rowan::GreenNodeData>(&*self.0, &*other.0) || self.0 == other.0
    }
}

impl Eq for Green {}

impl std::hash::Hash for Green {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        // Cheap: equal trees have equal kinds and lengths.
        self.0.kind().hash(state);
        self.0.text_len().hash(state);
    }
}

/// A top-level element of a file (any child of the root but the package
/// and the imports), identified by its kind, its name and its rank among
/// the elements of the file with the same kind and name.
///
/// Elements are inputs, kept by [`crate::set_text`] after each change of
/// the file's text ([`sync_elements`]): an edit inside one element sets
/// that element's syntax only, at the text's durability (low for a buffer
/// being edited), and leaves the others' inputs alone, at medium
/// durability. Salsa then re-validates a result that depends only on
/// untouched elements (and on inputs of medium durability or more) without
/// walking its dependencies: the work of a keystroke follows the element
/// edited, not the file. What other elements read of an element (its
/// summary, how many definitions it has, where their ids start) is
/// published in fields of its own, set only when it changes.
#[salsa::input(debug)]
pub struct Element {
    /// The file.
    #[returns(copy)]
    pub file: File,
    /// The node kind.
    #[returns(copy)]
    pub kind: SyntaxKind,
    /// The name ("" when it has none).
    #[returns(ref)]
    pub name: String,
    /// How many elements with the same kind and name come before it.
    #[returns(copy)]
    pub nth: u32,
    /// Its syntax.
    #[returns(ref)]
    pub green: Green,
    /// The id of its first definition (the count of those before it).
    #[returns(copy)]
    pub(crate) base: u32,
    /// What other elements read of it.
    #[returns(ref)]
    pub(crate) public: Public,
}

/// What the other elements of the workspace read of an element, derived
/// from its syntax ([`public_of`]) and kept as an input ([`Element::public`])
/// so that an edit that leaves it equal does not lower their durability.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Public {
    /// How many definitions it has.
    pub count: u32,
    /// The summaries of the items it declares.
    pub summary: Vec<crate::index::ItemSummary>,
    /// Its named top-level definitions (ids from 0).
    pub tops: Vec<u32>,
    /// Its top-level definitions: kind, name and the name's range relative
    /// to its start (for DUP-01 between elements).
    pub heads: Vec<Head>,
    /// Whether it writes vector or matrix types (whose sizes a file-level
    /// rule checks).
    pub sized: bool,
}

/// A top-level definition: kind, name and the name's range relative to
/// its element's start.
pub type Head = (crate::defs::DefKind, String, TextRange);

/// [`Public`] as the element's syntax gives it.
fn public_of(db: &dyn Db, element: Element) -> Public {
    let lowered = element_lowered(db, element);
    Public {
        count: lowered.defs.len() as u32,
        summary: element_summary(db, element).clone(),
        tops: lowered.children(None).filter(|(_, d)| !d.name.is_empty()).map(|(id, _)| id.0).collect(),
        heads: lowered.children(None).map(|(_, d)| (d.kind, d.name.clone(), d.name_range)).collect(),
        sized: element_marks(db, element).1,
    }
}

/// Brings the elements of `file` in line with its text (see [`Element`]):
/// elements whose syntax is unchanged are not set; the others get their
/// new syntax, at low durability for an edit of one element of a buffer
/// (`durability` LOW), at `durability` (or medium) otherwise. An element
/// edited before at low durability goes back to medium when another one
/// is edited, so that at most one element per file is of low durability.
pub(crate) fn sync_elements(db: &mut crate::RootDatabase, file: File, durability: salsa::Durability) {
    use salsa::{Durability, Setter};
    let root = parse(db, file).syntax_node();
    let header = lower_header(&root);
    if *file.header(db) != header {
        file.set_header(db).with_durability(durability.max(Durability::MEDIUM)).to(header);
    }
    // The green node of each element, in order.
    let greens: Vec<(SyntaxKind, rowan::GreenNode)> = root
        .green()
        .children()
        .filter_map(|c| c.into_node())
        .map(|n| (<robosim_syntax::RoboLang as rowan::Language>::kind_from_raw(n.kind()), n.to_owned()))
        .filter(|(k, _)| !matches!(k, PACKAGE_DECL | IMPORT))
        .collect();
    let old = file.elements(db).clone();
    // The same elements (kind, name and rank) when there are as many of
    // the same kinds and those whose syntax changed kept their names: the
    // others' names are those of their unchanged trees. This avoids
    // reading every element's name after each keystroke.
    let mut edited = Vec::new();
    let mut same_shape = old.len() == greens.len();
    for (i, (kind, green)) in greens.iter().enumerate() {
        if !same_shape {
            break;
        }
        let e = old[i];
        same_shape = e.kind(db) == *kind;
        if same_shape && !std::ptr::eq::<rowan::GreenNodeData>(&*e.green(db).0, &**green) {
            same_shape = *e.name(db) == element_name(green);
            if same_shape && e.green(db).0 != *green {
                edited.push(i);
            }
        }
    }
    let stable = durability.max(Durability::MEDIUM);
    let mut changed = Vec::new();
    let mut low = None;
    let list = if same_shape {
        // One element of a buffer edited: that element alone is of low
        // durability. Anything else (a paste over several elements, a
        // file on disk) is set at the stable durability.
        let one = durability == Durability::LOW && edited.len() == 1;
        for &i in &edited {
            let at = if one { Durability::LOW } else { stable };
            if one {
                low = Some(old[i]);
            }
            old[i].set_green(db).with_durability(at).to(Green(greens[i].1.clone()));
            changed.push(old[i]);
        }
        old
    } else {
        // The set of elements changed: reuse the inputs of those with the
        // same kind, name and rank, create the others.
        let mut by_id: FxHashMap<(SyntaxKind, String, u32), Element> =
            old.iter().map(|e| ((e.kind(db), e.name(db).clone(), e.nth(db)), *e)).collect();
        let mut list = Vec::new();
        let mut seen: FxHashMap<(SyntaxKind, String), u32> = FxHashMap::default();
        for (kind, green) in greens {
            let name = element_name(&green);
            let nth = seen.entry((kind, name.clone())).or_insert(0);
            let (green, nth) = (Green(green), std::mem::replace(nth, *nth + 1));
            let e = match by_id.remove(&(kind, name.clone(), nth)) {
                Some(e) => {
                    if *e.green(db) != green {
                        e.set_green(db).with_durability(stable).to(green);
                        changed.push(e);
                    }
                    e
                }
                None => {
                    let e =
                        Element::builder(file, kind, name, nth, green, 0, Public::default()).durability(stable).new(db);
                    changed.push(e);
                    e
                }
            };
            list.push(e);
        }
        file.set_elements(db).with_durability(stable).to(list.clone());
        list
    };
    // The element edited at low durability before, if not edited now,
    // goes back to the stable durability (its results are recomputed
    // once, and backdated).
    let hot = file.hot(db);
    if hot != low {
        if let Some(e) = hot.filter(|e| list.contains(e) && !changed.contains(e)) {
            let green = e.green(db).clone();
            e.set_green(db).with_durability(stable).to(green);
        }
        // Read by no query: low durability invalidates nothing.
        file.set_hot(db).with_durability(Durability::LOW).to(low);
    }
    // What the changed elements publish, and where every element's ids
    // start.
    let mut recount = !same_shape;
    for e in changed {
        let public = public_of(db, e);
        if *e.public(db) != public {
            recount |= e.public(db).count != public.count;
            e.set_public(db).with_durability(stable).to(public);
        }
    }
    let mut base = 0;
    for e in list.into_iter().filter(|_| recount) {
        if e.base(db) != base {
            e.set_base(db).with_durability(stable).to(base);
        }
        base += e.public(db).count;
    }
}

/// The name of an element ("" when it has none).
fn element_name(node: &rowan::GreenNodeData) -> String {
    node.children()
        .find_map(|c| c.into_node().filter(|n| n.kind() == rowan::SyntaxKind(NAME as u16)))
        .map(crate::defs::green_name_text)
        .unwrap_or_default()
}

/// The elements of `file` with their start offsets (this changes with
/// every edit before them; [`element_list`] does not).
#[salsa::tracked(returns(ref))]
pub fn file_elements(db: &dyn Db, file: File) -> Vec<(Element, u32)> {
    let root = parse(db, file).syntax_node();
    let elements = file.elements(db);
    let mut out = Vec::with_capacity(elements.len());
    let mut offset = u32::from(root.text_range().start());
    let mut next = elements.iter();
    for child in root.green().children() {
        if let rowan::NodeOrToken::Node(node) = child {
            let kind = <robosim_syntax::RoboLang as rowan::Language>::kind_from_raw(node.kind());
            if !matches!(kind, PACKAGE_DECL | IMPORT) {
                if let Some(e) = next.next() {
                    debug_assert!(e.green(db).0 == node.to_owned(), "elements not synced: use `hir::set_text`");
                    out.push((*e, offset));
                }
            }
        }
        offset += u32::from(child.text_len());
    }
    out
}

/// Where `element` starts in its file (0 if it is no longer in it): read
/// apart from [`file_elements`], so that what depends on one element's
/// position is not recomputed when an edit after it moves only others.
#[salsa::tracked(returns(copy))]
pub fn element_start(db: &dyn Db, element: Element) -> u32 {
    file_elements(db, element.file(db)).iter().find(|(e, _)| *e == element).map_or(0, |(_, at)| *at)
}

/// The elements of `file`, in order, without positions.
pub fn element_list(db: &dyn Db, file: File) -> &Vec<Element> {
    file.elements(db)
}

/// The package of `file` (as in [`file_defs`], without reading the
/// file's definitions).
pub fn file_package(db: &dyn Db, file: File) -> &[String] {
    &file.header(db).package
}

/// The package and imports of `file` (as in [`file_defs`]).
pub(crate) fn file_header(db: &dyn Db, file: File) -> &FileDefs {
    file.header(db)
}

/// The definitions of `element` numbered from 0, positions relative to
/// its start.
#[salsa::tracked(returns(ref))]
pub(crate) fn element_lowered(db: &dyn Db, element: Element) -> FileDefs {
    lower_element(&SyntaxNode::new_root(element.green(db).0.clone()))
}

/// The summaries of the items `element` declares (one, or none), from its
/// syntax (others read [`Element::public`]).
#[salsa::tracked(returns(ref))]
pub(crate) fn element_summary(db: &dyn Db, element: Element) -> Vec<crate::index::ItemSummary> {
    crate::index::summarize(element_lowered(db, element))
}

/// The id of the first definition of each element of `file` and how many
/// it has, in order: changes only when an element gains or loses
/// definitions.
#[salsa::tracked(returns(ref))]
pub(crate) fn def_bases(db: &dyn Db, file: File) -> Vec<(u32, Element, u32)> {
    element_list(db, file).iter().map(|e| (e.base(db), *e, e.public(db).count)).collect()
}

/// The definitions of `element`, with the file's ids and positions
/// relative to the element's start.
#[salsa::tracked(returns(ref))]
pub fn element_defs(db: &dyn Db, element: Element) -> FileDefs {
    element_lowered(db, element).rebased(element.base(db), file_header(db, element.file(db)))
}

/// Where the nodes the rules look for are in `element`'s tree.
#[salsa::tracked(returns(ref), no_eq)]
pub(crate) fn element_nodes(db: &dyn Db, element: Element) -> NodeTable {
    crate::walk::node_table(&SyntaxNode::new_root(element.green(db).0.clone()))
}

/// The members of every context definition of `element` (as
/// [`crate::resolve::file_members`] for a file).
#[salsa::tracked(returns(ref))]
pub(crate) fn element_members(db: &dyn Db, ws: Workspace, element: Element) -> FxHashMap<DefId, Vec<Member>> {
    let defs = element_defs(db, element);
    defs.iter()
        .filter(|(_, d)| crate::resolve::is_context_kind(d.kind))
        .map(|(id, _)| (id, crate::resolve::members_in(db, ws, element.file(db), defs, id)))
        .collect()
}

/// The problems of `element` found by name resolution, resolution in
/// behaviour and typing, each list in the order the file-level queries
/// give them, positions relative to the element's start.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ElementProblems {
    /// Declaration-level resolution ([`crate::resolve::file_resolution`]).
    pub resolution: Vec<ResolveProblem>,
    /// Resolution in behaviour ([`crate::body::body_resolution`]).
    pub body: Vec<ResolveProblem>,
    /// Typing ([`crate::types::type_checks`]).
    pub types: Vec<ResolveProblem>,
}

/// Statement deadlines (RoboSim has none: RS-STMT-02) of `element`,
/// relative to its start, and whether it writes vector or matrix types
/// (whose sizes the file-level rules check).
#[salsa::tracked(returns(ref))]
pub(crate) fn element_marks(db: &dyn Db, element: Element) -> (Vec<robosim_syntax::TextRange>, bool) {
    let root = SyntaxNode::new_root(element.green(db).0.clone());
    let table = element_nodes(db, element);
    let deadlines = table
        .nodes(&root, &[TIMED_STMT], false)
        .iter()
        .filter_map(|n| n.children().find(|c| c.kind() == DEADLINE))
        .map(|d| d.text_range())
        .collect();
    (deadlines, !table.nodes(&root, &[VECTOR_TYPE, MATRIX_TYPE], false).is_empty())
}

/// The resolution and typing problems of `element`.
#[salsa::tracked(returns(ref))]
pub fn element_problems(db: &dyn Db, ws: Workspace, element: Element) -> ElementProblems {
    let unit = Unit::of_element(db, element);
    let resolution = crate::resolve::resolve_unit(db, ws, &unit);
    let body = crate::body::resolve_body(db, ws, &unit);
    let types = crate::types::type_unit(db, ws, &unit, &resolution.refs, &body.refs);
    ElementProblems { resolution: resolution.problems, body: body.problems, types }
}

/// Everything [`crate::file_diagnostics`] reads of `element`: one result
/// per element, so that after an edit elsewhere salsa re-validates one
/// memo of it (without walking its dependencies, see [`Element`]).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ElementReport {
    /// Resolution and typing ([`element_problems`]; none in assertion
    /// files, which are checked whole).
    pub problems: ElementProblems,
    /// The cycle rules ([`crate::element_rules::element_cycles`]).
    pub cycles: Vec<crate::checks::Problem>,
    /// The other rules ([`crate::element_rules::element_rules`]).
    pub rules: crate::element_rules::ElementRules,
    /// Statement deadlines ([`element_marks`]).
    pub deadlines: Vec<TextRange>,
}

/// The problems of `element`, positions relative to its start.
#[salsa::tracked(returns(ref))]
pub fn element_report(db: &dyn Db, ws: Workspace, element: Element) -> ElementReport {
    let problems = if element.file(db).kind(db).is_assertions() {
        ElementProblems::default()
    } else {
        element_problems(db, ws, element).clone()
    };
    ElementReport {
        problems,
        cycles: crate::element_rules::element_cycles(db, ws, element).0.clone(),
        rules: crate::element_rules::element_rules(db, ws, element).clone(),
        deadlines: element_marks(db, element).0.clone(),
    }
}

/// The element of `file` around `offset` (its first or last position
/// included) and its start; `None` outside every element (the package,
/// the imports, blank space between elements) and in assertion files,
/// which are checked whole.
pub fn element_at(db: &dyn Db, file: File, offset: TextSize) -> Option<(Element, u32)> {
    if file.kind(db).is_assertions() {
        return None;
    }
    let elements = file_elements(db, file);
    let i = elements.partition_point(|(_, at)| TextSize::from(*at) <= offset).checked_sub(1)?;
    let (e, at) = elements[i];
    let end = TextSize::from(at) + e.green(db).0.text_len();
    (offset <= end).then_some((e, at))
}

/// The definitions of `element` with the file's ids and positions: what
/// requests about one place read (hover, definition), instead of putting
/// the whole file's together after each keystroke. Recomputed when an
/// edit before the element moves it.
#[salsa::tracked(returns(ref))]
pub fn placed_defs(db: &dyn Db, element: Element) -> FileDefs {
    let at = file_elements(db, element.file(db)).iter().find(|(e, _)| *e == element).map_or(0, |(_, at)| *at);
    crate::defs_shift::moved(element_defs(db, element), at.into())
}

/// The definitions of `file` that hold `id`, with the file's positions:
/// those of the element declaring it ([`placed_defs`]), or the whole
/// file's for an assertion file.
pub fn defs_holding(db: &dyn Db, file: File, id: DefId) -> &FileDefs {
    match element_of(db, file, id).filter(|_| !file.kind(db).is_assertions()) {
        Some(e) => placed_defs(db, e),
        None => file_defs(db, file),
    }
}

/// The definitions of `file` that may contain `range`, with the file's
/// positions: those of the element around it, or the whole file's for an
/// assertion file (outside every element: none, only the package and
/// imports).
pub fn defs_around(db: &dyn Db, file: File, range: TextRange) -> &FileDefs {
    if file.kind(db).is_assertions() {
        return file_defs(db, file);
    }
    match element_at(db, file, range.start()) {
        Some((e, _)) => placed_defs(db, e),
        None => file_header(db, file),
    }
}

/// The declaration-level references of `element` (resolution's, positions
/// from its start), for requests about a place in it.
#[salsa::tracked(returns(ref))]
pub(crate) fn element_refs(db: &dyn Db, ws: Workspace, element: Element) -> Vec<crate::resolve::ResolvedRef> {
    crate::resolve::resolve_unit(db, ws, &Unit::of_element(db, element)).refs
}

/// The element of `file` that declares `id` (from the ids alone, so that
/// asking does not depend on the element's positions).
pub fn element_of(db: &dyn Db, file: File, id: DefId) -> Option<Element> {
    let bases = def_bases(db, file);
    let i = bases.partition_point(|(b, _, _)| *b <= id.0).checked_sub(1)?;
    let (base, e, count) = bases[i];
    (id.0 < base + count).then_some(e)
}

/// What resolution and typing work on: a whole file, or one element of it
/// re-rooted (positions relative to its start, the file's definition ids).
pub(crate) struct Unit<'a> {
    /// The file.
    pub file: File,
    /// Its definitions (an element's only, for an element).
    pub defs: &'a FileDefs,
    /// The root of the tree.
    pub root: SyntaxNode,
    /// The nodes the queries look for.
    pub nodes: &'a NodeTable,
    /// The element, for an element.
    pub element: Option<Element>,
}

impl<'a> Unit<'a> {
    /// The whole of `file`.
    pub fn of_file(db: &'a dyn Db, file: File) -> Unit<'a> {
        Unit {
            file,
            defs: file_defs(db, file),
            root: parse(db, file).syntax_node(),
            nodes: crate::walk::file_nodes(db, file),
            element: None,
        }
    }

    /// One element.
    pub fn of_element(db: &'a dyn Db, element: Element) -> Unit<'a> {
        Unit {
            file: element.file(db),
            defs: element_defs(db, element),
            root: SyntaxNode::new_root(element.green(db).0.clone()),
            nodes: element_nodes(db, element),
            element: Some(element),
        }
    }

    /// The definitions that hold `id` of `file`: this unit's when it holds
    /// it, another element's of the same file (read without the file's
    /// positions), or those of another file.
    pub fn defs_of(&self, db: &'a dyn Db, file: File, id: DefId) -> &'a FileDefs {
        if file != self.file || self.element.is_none() {
            return file_defs(db, file);
        }
        if self.defs.holds(id) {
            return self.defs;
        }
        match element_of(db, file, id) {
            Some(e) => element_defs(db, e),
            None => file_defs(db, file),
        }
    }

    /// The members of the context `id` of this unit.
    pub fn members(&self, db: &'a dyn Db, ws: Workspace, id: DefId) -> Cow<'a, [Member]> {
        match self.element {
            Some(e) if self.defs.holds(id) => match element_members(db, ws, e).get(&id) {
                Some(m) => Cow::Borrowed(m),
                None => Cow::Owned(crate::resolve::members_in(db, ws, self.file, self.defs, id)),
            },
            _ => crate::resolve::ctx_members(db, ws, Ctx::Local(self.file, id)),
        }
    }

    /// [`crate::resolve::node_ctx`] for a definition of this unit.
    pub fn node_ctx(&self, db: &'a dyn Db, ws: Workspace, id: DefId) -> Option<Ctx> {
        crate::resolve::node_ctx_in(db, ws, self.file, self.defs_of(db, self.file, id), id)
    }
}
