//! Workspace-wide names. Each file contributes a position-free summary of
//! the items it declares (names, kinds, members, interface uses), so that
//! editing inside a machine body does not invalidate other files' results;
//! the workspace index maps qualified names to items; `resolve_item` finds
//! the item a (qualified) name means from a given file, with RoboTool's
//! visibility: the file's package, files without a package, imports
//! (wildcard imports also qualify relative names) and the library — all
//! within the file's project (RoboTool resolves names per Eclipse project).

use std::collections::HashMap;

use rustc_hash::FxHashMap;

use crate::defs::{DefData, DefId, DefKind, Io, TypeRef, UseKind};
use crate::{Db, File, Workspace};

/// A member of an item, without positions.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct MemberSummary {
    /// Name.
    pub name: String,
    /// Kind (event, variable, constant, clock, operation signature, …).
    pub kind: DefKind,
    /// Declared type, for typed members.
    pub ty: Option<TypeRef>,
    /// The I/O context it sits in.
    pub io: Option<Io>,
    /// For operation signatures and definitions: parameter names and types.
    pub params: Vec<(String, Option<TypeRef>)>,
    /// For references (`sref`, …): the target path.
    pub target: Vec<String>,
    /// Whether a `_broadcast` event.
    pub broadcast: bool,
}

/// A top-level item, without positions.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ItemSummary {
    /// Name.
    pub name: String,
    /// Kind.
    pub kind: DefKind,
    /// Direct members: events, variables, constants, clocks, operations,
    /// references, inline machines/controllers/platforms, fields, literals.
    pub members: Vec<MemberSummary>,
    /// `uses/provides/requires` of the item itself (and of its I/O
    /// contexts), with the path as written.
    pub uses: Vec<(UseKind, Vec<String>, Option<Io>)>,
    /// Parameters, for operations and functions.
    pub params: Vec<(String, Option<TypeRef>)>,
}

/// What a file contributes to the workspace.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct FileSummary {
    /// The package path.
    pub package: Vec<String>,
    /// Imports: path and whether wildcard.
    pub imports: Vec<(Vec<String>, bool)>,
    /// Top-level items.
    pub items: Vec<ItemSummary>,
}

/// The position-free summary of a file.
#[salsa::tracked(returns(ref))]
pub fn file_summary(db: &dyn Db, file: File) -> FileSummary {
    // Put together from the elements' summaries, which an edit elsewhere
    // does not recompute.
    let header = crate::element::file_header(db, file);
    FileSummary {
        package: header.package.clone(),
        imports: header.imports.iter().map(|i| (i.path.clone(), i.wildcard)).collect(),
        items: crate::element::element_list(db, file)
            .iter()
            .flat_map(|e| e.public(db).summary.iter().cloned())
            .collect(),
    }
}

/// The summaries of the top-level items of `defs`.
pub(crate) fn summarize(defs: &crate::defs::FileDefs) -> Vec<ItemSummary> {
    let mut out = Vec::new();
    for (id, d) in defs.children(None) {
        if d.name.is_empty() {
            continue;
        }
        let members =
            defs.children(Some(id)).filter(|(_, m)| !m.name.is_empty()).map(|(_, m)| member_summary(m)).collect();
        let uses = defs.uses_of(id).map(|u| (u.kind, u.path.clone(), u.io)).collect();
        let params = match &d.data {
            DefData::Signature { params, .. } => strip_params(params),
            _ => Vec::new(),
        };
        out.push(ItemSummary { name: d.name.clone(), kind: d.kind, members, uses, params });
    }
    out
}

fn member_summary(m: &crate::defs::Def) -> MemberSummary {
    let (ty, broadcast) = match &m.data {
        DefData::Typed { ty, broadcast, .. } => (ty.clone(), *broadcast),
        _ => (None, false),
    };
    let params = match &m.data {
        DefData::Signature { params, .. } => strip_params(params),
        // Constructor argument types of an enumeration literal.
        DefData::Literal { args } => args.iter().map(|t| (String::new(), strip_ranges(Some(t.clone())))).collect(),
        _ => Vec::new(),
    };
    let target = match &m.data {
        DefData::Reference { path, .. } => path.clone(),
        _ => Vec::new(),
    };
    MemberSummary { name: m.name.clone(), kind: m.kind, ty: strip_ranges(ty), io: m.io, params, target, broadcast }
}

/// Parameters without the ranges of their types.
fn strip_params(params: &[(String, Option<TypeRef>)]) -> Vec<(String, Option<TypeRef>)> {
    params.iter().map(|(n, t)| (n.clone(), strip_ranges(t.clone()))).collect()
}

/// Type references keep their ranges in definitions, but summaries must
/// not change when text only moves.
fn strip_ranges(ty: Option<TypeRef>) -> Option<TypeRef> {
    fn strip(t: TypeRef) -> TypeRef {
        use robosim_syntax::TextRange;
        let z = TextRange::empty(0.into());
        match t {
            TypeRef::Named(p, _) => TypeRef::Named(p, z),
            TypeRef::Set(a) => TypeRef::Set(Box::new(strip(*a))),
            TypeRef::Seq(a) => TypeRef::Seq(Box::new(strip(*a))),
            TypeRef::Product(v) => TypeRef::Product(v.into_iter().map(strip).collect()),
            TypeRef::Function(a, b) => TypeRef::Function(Box::new(strip(*a)), Box::new(strip(*b))),
            TypeRef::Relation(a, b) => TypeRef::Relation(Box::new(strip(*a)), Box::new(strip(*b))),
            TypeRef::Vector(a, _) => TypeRef::Vector(Box::new(strip(*a)), z),
            TypeRef::Matrix(a, _, _) => TypeRef::Matrix(Box::new(strip(*a)), z, z),
            other => other,
        }
    }
    ty.map(strip)
}

/// An item of the workspace: the file and its index in the file's summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ItemLoc {
    /// The declaring file.
    pub file: File,
    /// Index into [`FileSummary::items`].
    pub index: u32,
}

impl ItemLoc {
    /// The item's summary.
    pub fn summary(self, db: &dyn Db) -> &ItemSummary {
        &file_summary(db, self.file).items[self.index as usize]
    }

    /// The item's definition in its file.
    pub fn def(self, db: &dyn Db) -> Option<DefId> {
        item_defs(db, self.file).get(self.index as usize).copied()
    }
}

/// The definitions of the summarised items of `file`, in order: ids only,
/// so that readers do not depend on the file's positions.
#[salsa::tracked(returns(ref))]
pub(crate) fn item_defs(db: &dyn Db, file: File) -> Vec<DefId> {
    // From the elements' lowerings (ids from 0) and where their ids start,
    // not from the file's definitions, which every keystroke changes.
    let mut out = Vec::new();
    // What the elements publish, which an edit inside one leaves alone.
    for e in crate::element::element_list(db, file) {
        let base = e.base(db);
        out.extend(e.public(db).tops.iter().map(|id| DefId(base + id)));
    }
    out
}

/// Qualified names of the whole workspace.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Index {
    /// Full path (package segments, then the item name) → items.
    pub items: HashMap<Vec<String>, Vec<ItemLoc>>,
    /// Every package path that some file declares (and its prefixes).
    pub packages: std::collections::HashSet<Vec<String>>,
}

/// The index over every file of the workspace.
#[salsa::tracked(returns(ref))]
pub fn workspace_index(db: &dyn Db, ws: Workspace) -> Index {
    index_of(db, ws.files(db).iter().copied())
}

fn index_of(db: &dyn Db, files: impl Iterator<Item = File>) -> Index {
    let mut index = Index::default();
    for file in files {
        let s = file_summary(db, file);
        for i in 0..s.package.len() {
            index.packages.insert(s.package[..=i].to_vec());
        }
        for (i, item) in s.items.iter().enumerate() {
            let mut path = s.package.clone();
            path.push(item.name.clone());
            index.items.entry(path).or_default().push(ItemLoc { file, index: i as u32 });
        }
    }
    index
}

/// The project a file belongs to: the innermost of the workspace's
/// project roots that holds it (`None` for the library and for files
/// outside every project).
pub fn project_of(db: &dyn Db, ws: Workspace, file: File) -> Option<u32> {
    if file.is_library(db) {
        return None;
    }
    let path = file.path(db);
    ws.projects(db)
        .iter()
        .enumerate()
        .filter(|(_, root)| is_under(path, root))
        .max_by_key(|(_, root)| root.len())
        .map(|(i, _)| i as u32)
}

/// Whether `path` lies in the folder `root` (either separator).
fn is_under(path: &str, root: &str) -> bool {
    let root = root.trim_end_matches(['/', '\\']);
    root.is_empty() || path.strip_prefix(root).is_some_and(|rest| rest.starts_with(['/', '\\']))
}

/// The index of the names `from` can see: its project's files and the
/// library (files outside every project see the others outside every
/// project). Without projects, the whole workspace's index.
pub fn index_for(db: &dyn Db, ws: Workspace, from: File) -> &Index {
    if ws.projects(db).is_empty() {
        return workspace_index(db, ws);
    }
    project_index(db, ws, project_of(db, ws, from))
}

/// The root of a project that declares the package or item `path`, for
/// messages when another project cannot see it.
pub fn project_declaring(db: &dyn Db, ws: Workspace, path: &[String]) -> Option<String> {
    if ws.projects(db).is_empty() {
        return None;
    }
    ws.files(db).iter().find_map(|&f| {
        let p = project_of(db, ws, f)?;
        let s = file_summary(db, f);
        let declares = s.package.starts_with(path)
            || s.items.iter().any(|i| {
                s.package.len() + 1 == path.len() && path.starts_with(&s.package) && i.name == path[path.len() - 1]
            });
        declares.then(|| ws.projects(db)[p as usize].clone())
    })
}

/// The index over one project's files and the library.
#[salsa::tracked(returns(ref))]
fn project_index(db: &dyn Db, ws: Workspace, project: Option<u32>) -> Index {
    let files = ws.files(db).iter().copied().filter(|&f| f.is_library(db) || project_of(db, ws, f) == project);
    index_of(db, files)
}

/// Which items a reference may denote.
pub type KindFilter = fn(DefKind) -> bool;

/// The items that `path`, written in `from`, may denote (best first).
/// Only items whose kind passes `accept` are considered.
pub fn resolve_item(db: &dyn Db, ws: Workspace, from: File, path: &[String], accept: KindFilter) -> Vec<ItemLoc> {
    if path.is_empty() {
        return Vec::new();
    }
    let found = resolve_in_scope(db, ws, from, path, accept);
    if found.is_empty() && path.len() == 1 && from.kind(db) == robosim_syntax::FileKind::RoboSim {
        return unique_copy(db, ws, from, &path[0], accept).into_iter().collect();
    }
    found
}

/// The item a simple name written in a RoboSim file denotes when no import
/// brings it into scope: RoboTool's RoboChart-to-RoboSim output writes
/// plain names of interfaces it copied into other packages (`uses
/// SensingHw` in a package that imports neither copy), and RoboTool
/// resolves them. We accept such a name only when every declaration of it
/// in the workspace is the same (a copy, compared like [`type_copies`]),
/// so the choice cannot matter; [`resolve_in_scope`] tells the resolver to
/// warn (LNK-02).
pub fn unique_copy(db: &dyn Db, ws: Workspace, from: File, name: &str, accept: KindFilter) -> Option<ItemLoc> {
    let index = index_for(db, ws, from);
    let mut all: Vec<ItemLoc> = index
        .items
        .iter()
        .filter(|(full, _)| full.last().is_some_and(|n| n == name))
        .flat_map(|(_, locs)| locs.iter().copied())
        .filter(|l| accept(l.summary(db).kind))
        .collect();
    all.sort_by(|a, b| (a.file.path(db), a.index).cmp(&(b.file.path(db), b.index)));
    let first = *all.first()?;
    // Signature parameters keep their type ranges in summaries.
    let params = |ps: &[(String, Option<TypeRef>)]| -> Vec<(String, Option<TypeRef>)> {
        ps.iter().map(|(n, t)| (n.clone(), strip_ranges(t.clone()))).collect()
    };
    let key = |l: &ItemLoc| {
        let s = l.summary(db);
        let members: Vec<MemberSummary> =
            s.members.iter().map(|m| MemberSummary { params: params(&m.params), ..m.clone() }).collect();
        (s.kind, members, s.uses.clone(), params(&s.params))
    };
    let k = key(&first);
    all.iter().all(|l| key(l) == k).then_some(first)
}

/// The items that `path`, written in `from`, denotes through the file's
/// package, files without a package, its imports and the library (best
/// first); [`resolve_item`] adds RoboTool's fallback for RoboSim files.
pub fn resolve_in_scope(db: &dyn Db, ws: Workspace, from: File, path: &[String], accept: KindFilter) -> Vec<ItemLoc> {
    if path.is_empty() {
        return Vec::new();
    }
    // Simple names, by far the most common, come from the file's scope.
    if path.len() == 1 {
        if let Some(levels) = file_scope(db, ws, from).get(&path[0]) {
            for level in levels {
                let found: Vec<ItemLoc> = level.iter().copied().filter(|l| accept(l.summary(db).kind)).collect();
                if !found.is_empty() {
                    return found;
                }
            }
        }
        return Vec::new();
    }
    let index = index_for(db, ws, from);
    let here = file_summary(db, from);
    let lookup = |full: &[String]| -> Vec<ItemLoc> {
        index
            .items
            .get(full)
            .map(|v| v.iter().copied().filter(|l| accept(l.summary(db).kind)).collect())
            .unwrap_or_default()
    };
    let mut candidates: Vec<Vec<String>> = Vec::new();
    // Relative to the file's own package.
    candidates.push(here.package.iter().chain(path).cloned().collect());
    // Absolute.
    if !here.package.is_empty() {
        candidates.push(path.to_vec());
    }
    for (imp, wildcard) in &here.imports {
        if *wildcard {
            // `import P::*`: P's items by simple name, and names relative to P.
            candidates.push(imp.iter().chain(path).cloned().collect());
        } else if imp.last() == path.first() {
            // `import P::x` makes `x` (and `x::…`) visible.
            candidates.push(imp.iter().chain(&path[1..]).cloned().collect());
        }
    }
    // The library's core types and the RoboSim core are always visible.
    candidates.push(["core".to_string()].iter().chain(path).cloned().collect());
    candidates.push(["robosim__core".to_string()].iter().chain(path).cloned().collect());
    for c in candidates {
        let found = lookup(&c);
        if !found.is_empty() {
            return found;
        }
    }
    Vec::new()
}

/// The simple names visible in a file, each with its candidate items in
/// priority order (one inner list per lookup level of [`resolve_item`]);
/// every simple name of the file is looked up here, hence the fast hash.
#[salsa::tracked(returns(ref))]
pub fn file_scope(db: &dyn Db, ws: Workspace, file: File) -> FxHashMap<String, Vec<Vec<ItemLoc>>> {
    /// Where a level finds a simple name.
    enum Level<'a> {
        /// Items of this package.
        Package(&'a [String]),
        /// Exactly the item `import P::x` names.
        Item(&'a [String]),
    }
    let index = index_for(db, ws, file);
    let here = file_summary(db, file);
    let mut levels: Vec<Level<'_>> = vec![Level::Package(&here.package)];
    if !here.package.is_empty() {
        levels.push(Level::Package(&[]));
    }
    for (imp, wildcard) in &here.imports {
        levels.push(if *wildcard { Level::Package(imp) } else { Level::Item(imp) });
    }
    let core = ["core".to_string()];
    let robosim_core = ["robosim__core".to_string()];
    levels.push(Level::Package(&core));
    levels.push(Level::Package(&robosim_core));
    let mut out: FxHashMap<String, Vec<Vec<ItemLoc>>> = FxHashMap::default();
    for (full, locs) in &index.items {
        let Some((name, pkg)) = full.split_last() else { continue };
        for (i, level) in levels.iter().enumerate() {
            let hit = match level {
                Level::Package(p) => *p == pkg,
                Level::Item(imp) => *imp == full.as_slice(),
            };
            if hit {
                let entry = out.entry(name.clone()).or_insert_with(|| vec![Vec::new(); levels.len()]);
                entry[i].extend(locs.iter().copied());
            }
        }
    }
    out
}

/// Whether an import, written in `from`, names an existing package or
/// item of its project.
pub fn import_matches(db: &dyn Db, ws: Workspace, from: File, path: &[String], wildcard: bool) -> bool {
    let index = index_for(db, ws, from);
    if wildcard {
        // `import P::*` names a package, or an item whose members it opens.
        index.packages.contains(path) || index.items.contains_key(path)
    } else {
        index.items.contains_key(path) || index.packages.contains(path)
    }
}

/// Type identity across packages. RoboTool compares declared types by kind
/// and simple name, and its RoboChart-to-RoboSim output relies on it: the
/// generated package redeclares `type ID` and `enumeration Position {…}`
/// and connects events typed with the copies to events typed with the
/// originals. We go half way: declarations of the same kind and simple
/// name with identical members (a copy) are one type, represented by the
/// first of them in path order; same-named declarations that differ stay
/// distinct (RoboTool's name-only comparison would mix them up).
#[salsa::tracked(returns(ref))]
pub fn type_copies(db: &dyn Db, ws: Workspace) -> FxHashMap<ItemLoc, ItemLoc> {
    let index = workspace_index(db, ws);
    // (project, name, kind, members) → the declarations with them, and
    // their paths: copies are one type within a project only.
    type Shape<'a> = (Option<u32>, &'a str, DefKind, &'a [MemberSummary]);
    let mut groups: HashMap<Shape<'_>, Vec<(&str, ItemLoc)>> = HashMap::new();
    for locs in index.items.values() {
        for &loc in locs {
            let s = loc.summary(db);
            if s.kind.is_type() {
                groups
                    .entry((project_of(db, ws, loc.file), s.name.as_str(), s.kind, s.members.as_slice()))
                    .or_default()
                    .push((loc.file.path(db), loc));
            }
        }
    }
    let mut out = FxHashMap::default();
    for mut same in groups.into_values().filter(|g| g.len() > 1) {
        same.sort_by(|a, b| (a.0, a.1.index).cmp(&(b.0, b.1.index)));
        let first = same[0].1;
        for (_, loc) in &same[1..] {
            out.insert(*loc, first);
        }
    }
    out
}

/// The representative of the type declared at `loc` (see [`type_copies`]).
pub fn canonical_type(db: &dyn Db, ws: Workspace, loc: ItemLoc) -> ItemLoc {
    type_copies(db, ws).get(&loc).copied().unwrap_or(loc)
}
