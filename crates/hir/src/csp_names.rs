//! The model's names as RoboTool's generated CSPm spells them, so that the
//! hand-written `csp` blocks of assertion files (which use those names)
//! can be read against the model: by the native checker's CSPm bridge (a
//! block's free names) and by the editor (hover, go to definition).
//!
//! The rules, checked against RoboTool 3's output for the Alpha Algorithm
//! (`reference/alpha-algorithm/csp-gen`) and the corpus's blocks:
//!
//! - a package `A::B` is the CSPm module `A_B`; an element `M` of it is the
//!   module `A_B::M` (just `M` in the default package); an inline machine
//!   `S` of controller `C` is `…::C::S`, a reference `r` (`sref r = S`,
//!   `cref r = C`) is `…::C::r`;
//! - an event `e` of element `M` is the channel `M::e` with fields
//!   `InOut.T` (`M::e.in.v`, `M::e.out.v`; a product type is one tuple
//!   field); every element has `M::terminate`; a required operation `op` is
//!   `M::opCall` with one field per parameter; a module's platform variable
//!   `x` is `M::set_x`;
//! - RoboSim elements also have `M::registerRead.M::i_x.b.v`,
//!   `M::registerWrite.M::o_x.v` (registers are [`CspKind::Register`]) and
//!   `M::endexec`;
//! - a constant `k` of an element with path `A::B::M` is `const_A_B_M_k`;
//!   a machine's constants under a controller's reference `r` are
//!   `const_<controller path>_r_k`;
//! - the number types are `core_nat`, `core_int`, `core_real`,
//!   `core_boolean`, `core_string`, `core_clock_type`; a declared type `T`
//!   of package `A::B` is `A_B_T` (`T` in the default package) and its
//!   enumeration literals are `A_B_T_L`;
//! - generated processes `M::D__`, `M::O__`, `M::VS__`, `M::VS_O__`,
//!   `M::AS_O__` take `(id__, constants in RoboTool's order)`: a machine's
//!   own constants in declaration order; a controller's, its machines' in
//!   order; a module's, its controllers' in order;
//! - `M::sem__events` is the set of the element's visible events.
//!
//! The table is computed once per workspace ([`csp_names`]); look names up
//! with [`CspNames::get`], elements with [`CspNames::element`].

use robosim_syntax::{FileKind, TextRange};

use crate::defs::{file_defs, DefData, DefId, DefKind, TypeRef};
use crate::index::{file_summary, resolve_item, ItemLoc};
use crate::resolve::{ctx_members, Ctx, Target};
use crate::types::Ty;
use crate::{Db, File, Workspace};

/// The CSPm type (a value set) of a field, a constant or a register.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum CspType {
    /// `core_nat`.
    Nat,
    /// `core_int`.
    Int,
    /// `core_real`.
    Real,
    /// `core_boolean` (`Bool`).
    Bool,
    /// `core_string`.
    Str,
    /// `core_clock_type`.
    Clock,
    /// `InOut` (`in`, `out`): the direction field of an event.
    InOut,
    /// A declared type by its CSPm name (`main_ID`, `main_Position`): see
    /// its [`CspKind::Type`] entry for what it holds.
    Named(String),
    /// A tuple (a product type).
    Tuple(Vec<CspType>),
    /// `Set(T)`.
    Set(Box<CspType>),
    /// `Seq(T)`.
    Seq(Box<CspType>),
    /// A type RoboTool's CSPm has but this table does not describe
    /// (functions, vectors, generic parameters), as written.
    Other(String),
}

/// What a declared type holds.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum TypeDef {
    /// One of the `core_*` types (its bounds come from the instantiations).
    Core,
    /// A primitive `type T`: `{0, 1}` unless the instantiations say
    /// otherwise (RT-3).
    Primitive,
    /// An enumeration: the CSPm names of its literals, in order.
    Enumeration(Vec<String>),
    /// A record: its fields' types, in order (a tuple in CSPm).
    Record(Vec<CspType>),
}

/// What a name denotes.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum CspKind {
    /// A CSPm module: a package (`A_B`) or an element (`A_B::M`).
    Module,
    /// A channel and the types of its fields, in order (`M::e`:
    /// `[InOut, T]`; `M::terminate`: `[]`; `M::opCall`: the parameters).
    Channel {
        /// The fields' types.
        fields: Vec<CspType>,
    },
    /// A RoboSim register (`M::i_x`, `M::o_x`): a value of the first field
    /// of `M::registerRead` (then a `Bool`, then the value) or of
    /// `M::registerWrite` (then the value).
    Register {
        /// An input register (read), or an output one (written).
        input: bool,
        /// The value's type (`None` for an event without a type).
        ty: Option<CspType>,
    },
    /// A constant (`const_M_k`).
    Constant {
        /// Its type.
        ty: CspType,
        /// Its initialiser in the model, as written, if any.
        init: Option<String>,
    },
    /// A type (`core_nat`, `main_ID`).
    Type(TypeDef),
    /// An enumeration literal (`main_Position_left`) of the type named
    /// `ty`, the `index`-th.
    Literal {
        /// The enumeration's CSPm name.
        ty: String,
        /// Its position among the literals.
        index: u32,
    },
    /// A generated process (`M::O__`) and its parameters' names.
    Process {
        /// `id__`, then the constants' CSPm names.
        params: Vec<String>,
    },
    /// `M::sem__events`, the set of the element's visible events.
    EventSet,
}

/// Where a name is declared in the model (for hover and go to definition).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Decl {
    /// The declaring file.
    pub file: File,
    /// The declaration's name (or, for a package, its path).
    pub range: TextRange,
}

/// One name of the table.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CspName {
    /// As CSPm writes it (`Mod::M::e`, `const_M_k`, `core_nat`).
    pub name: String,
    /// What it denotes.
    pub kind: CspKind,
    /// The model declaration it denotes (none for RoboTool's own names:
    /// `core_*`, `terminate`, `registerRead`, processes of no element …).
    pub decl: Option<Decl>,
}

/// A module, controller or machine of the model, as the table names it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CspElement {
    /// Its CSPm module path (`Control_DSkill_Move::Move`, `C::stm_ref0`).
    pub module: String,
    /// Its path as an assertion names it (`Control::DSkill::Move::Move`,
    /// `C::M`); for a reference, the controller's path and the reference.
    pub path: Vec<String>,
    /// Its kind (module, controller, machine; a reference takes the kind
    /// of what it refers to).
    pub kind: DefKind,
    /// Whether it is a RoboSim element.
    pub robosim: bool,
    /// Where it (or the reference) is declared.
    pub decl: Decl,
    /// The CSPm names of its channels (visible events).
    pub channels: Vec<String>,
    /// The CSPm names of its constants, in RoboTool's parameter order.
    pub constants: Vec<String>,
}

/// The names of a workspace's model, sorted by name.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CspNames {
    names: Vec<CspName>,
    elements: Vec<CspElement>,
}

impl CspNames {
    /// The entry for `name` as CSPm writes it.
    pub fn get(&self, name: &str) -> Option<&CspName> {
        self.names.binary_search_by(|n| n.name.as_str().cmp(name)).ok().map(|i| &self.names[i])
    }

    /// Every entry, sorted by name.
    pub fn iter(&self) -> impl Iterator<Item = &CspName> {
        self.names.iter()
    }

    /// Every element, in file and declaration order.
    pub fn elements(&self) -> &[CspElement] {
        &self.elements
    }

    /// The element whose CSPm module path is `module` (`A_B::M`).
    pub fn element(&self, module: &str) -> Option<&CspElement> {
        self.elements.iter().find(|e| e.module == module)
    }

    /// The element an assertion names with `path` (`A::B::M`, `C::M`).
    pub fn element_by_path(&self, path: &[String]) -> Option<&CspElement> {
        self.elements.iter().find(|e| e.path == path)
    }
}

/// The CSPm names of the workspace's model (see the module documentation
/// for the rules). Names declared twice (copies of a type in two files)
/// keep their first declaration.
#[salsa::tracked(returns(ref))]
pub fn csp_names(db: &dyn Db, ws: Workspace) -> CspNames {
    let mut b = Builder { db, ws, names: Vec::new(), elements: Vec::new() };
    for core in ["core_nat", "core_int", "core_real", "core_boolean", "core_string", "core_clock_type"] {
        b.push(core.to_string(), CspKind::Type(TypeDef::Core), None);
    }
    for &file in ws.files(db) {
        if file.kind(db).is_assertions() {
            continue;
        }
        b.file(file);
    }
    let mut names = b.names;
    // Stable: the first declaration of a name wins.
    names.sort_by(|a, b| a.name.cmp(&b.name));
    names.dedup_by(|a, b| a.name == b.name);
    CspNames { names, elements: b.elements }
}

/// The path and CSPm module of every element of [`csp_names`], in the
/// same order ([`CspNames::elements`]), from the elements' definitions
/// alone: without positions, channels or constants, so that after a
/// keystroke it is recomputed from memoised definitions (what a hover
/// reads to name the module of the element it exports).
#[salsa::tracked(returns(ref))]
pub fn csp_modules(db: &dyn Db, ws: Workspace) -> Vec<(Vec<String>, String)> {
    let mut out = Vec::new();
    for &file in ws.files(db) {
        // `Builder::file`: library files have no elements in the table.
        if file.kind(db).is_assertions() || file.is_library(db) {
            continue;
        }
        let package = crate::element::file_package(db, file);
        let pkg = package_prefix(package);
        for e in crate::element::element_list(db, file) {
            for (id, d) in crate::element::element_defs(db, *e).children(None) {
                if !d.name.is_empty() && matches!(d.kind, DefKind::Module | DefKind::Controller | DefKind::StateMachine)
                {
                    let mut path = package.to_vec();
                    path.push(d.name.clone());
                    modules_of(db, ws, file, id, path, joined(&pkg, &d.name, "::"), &mut out);
                }
            }
        }
    }
    out
}

/// [`Builder::element`]'s walk, for [`csp_modules`]: the element `id` of
/// `file` after its components (post-order, as the table has them).
fn modules_of(
    db: &dyn Db,
    ws: Workspace,
    file: File,
    id: DefId,
    path: Vec<String>,
    module: String,
    out: &mut Vec<(Vec<String>, String)>,
) {
    if out.len() > 10_000 || path.len() > 16 {
        return; // A reference cycle, as in `Builder::element`.
    }
    let defs = match crate::element::element_of(db, file, id) {
        Some(e) => crate::element::element_defs(db, e),
        None => file_defs(db, file),
    };
    for (cid, c) in defs.children(Some(id)) {
        if c.name.is_empty() {
            continue;
        }
        let mut cpath = path.clone();
        cpath.push(c.name.clone());
        let cmodule = format!("{module}::{}", c.name);
        match (c.kind, &c.data) {
            (DefKind::Controller | DefKind::StateMachine, _) => modules_of(db, ws, file, cid, cpath, cmodule, out),
            (DefKind::ControllerRef | DefKind::MachineRef, DefData::Reference { path: target, .. }) => {
                let accept = if c.kind == DefKind::ControllerRef {
                    (|k| k == DefKind::Controller) as fn(DefKind) -> bool
                } else {
                    |k| k == DefKind::StateMachine
                };
                let Some(loc) = resolve_item(db, ws, file, target, accept).first().copied() else { continue };
                let Some(tid) = loc.def(db) else { continue };
                modules_of(db, ws, loc.file, tid, cpath, cmodule, out);
            }
            _ => {}
        }
    }
    out.push((path, module));
}

struct Builder<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    names: Vec<CspName>,
    elements: Vec<CspElement>,
}

/// `A::B` as the prefix `A_B` (empty for the default package).
fn package_prefix(package: &[String]) -> String {
    package.join("_")
}

fn joined(prefix: &str, name: &str, sep: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}{sep}{name}")
    }
}

impl Builder<'_> {
    fn push(&mut self, name: String, kind: CspKind, decl: Option<Decl>) {
        self.names.push(CspName { name, kind, decl });
    }

    fn file(&mut self, file: File) {
        let db = self.db;
        let defs = file_defs(db, file);
        let pkg = package_prefix(&defs.package);
        if !pkg.is_empty() && !file.is_library(db) {
            let range = defs.package_range.unwrap_or_default();
            self.push(pkg.clone(), CspKind::Module, Some(Decl { file, range }));
        }
        for (id, d) in defs.children(None) {
            if d.name.is_empty() {
                continue;
            }
            let decl = Some(Decl { file, range: d.name_range });
            match d.kind {
                DefKind::PrimitiveType if defs.package != ["core"] => {
                    self.push(joined(&pkg, &d.name, "_"), CspKind::Type(TypeDef::Primitive), decl)
                }
                DefKind::Enumeration => {
                    let ty = joined(&pkg, &d.name, "_");
                    let mut literals = Vec::new();
                    for (_, l) in defs.children(Some(id)).filter(|(_, l)| l.kind == DefKind::EnumLiteral) {
                        let lit = format!("{ty}_{}", l.name);
                        let kind = CspKind::Literal { ty: ty.clone(), index: literals.len() as u32 };
                        self.push(lit.clone(), kind, Some(Decl { file, range: l.name_range }));
                        literals.push(lit);
                    }
                    self.push(ty, CspKind::Type(TypeDef::Enumeration(literals)), decl);
                }
                DefKind::Record => {
                    let fields = defs
                        .children(Some(id))
                        .filter(|(_, f)| f.kind == DefKind::Field)
                        .map(|(_, f)| match &f.data {
                            DefData::Typed { ty: Some(t), .. } => self.ty(file, t),
                            _ => CspType::Other(String::new()),
                        })
                        .collect();
                    self.push(joined(&pkg, &d.name, "_"), CspKind::Type(TypeDef::Record(fields)), decl)
                }
                DefKind::Module | DefKind::Controller | DefKind::StateMachine if !file.is_library(db) => {
                    let mut path = defs.package.clone();
                    path.push(d.name.clone());
                    let module = joined(&pkg, &d.name, "::");
                    let owner = joined(&pkg, &d.name, "_");
                    self.element(file, id, d.kind, path, module, owner, Decl { file, range: d.name_range });
                }
                _ => {}
            }
        }
    }

    /// Adds the element `id` of `file` (or the one a reference leads to)
    /// under the CSPm module `module`; `owner` prefixes its constants.
    /// Returns its constants, in RoboTool's order.
    #[allow(clippy::too_many_arguments)]
    fn element(
        &mut self,
        file: File,
        id: DefId,
        kind: DefKind,
        path: Vec<String>,
        module: String,
        owner: String,
        decl: Decl,
    ) -> Vec<String> {
        let db = self.db;
        if self.elements.len() > 10_000 || path.len() > 16 {
            return Vec::new(); // A reference cycle: the model reports it.
        }
        let robosim = file.kind(db) == FileKind::RoboSim;
        self.push(module.clone(), CspKind::Module, Some(decl));
        let defs = file_defs(db, file);
        let mut channels = Vec::new();
        let mut constants = Vec::new();
        let mut registers = Vec::new();
        // A module's events are its platform's.
        // (context, whether it is a robotic platform: the operations it
        // provides are the module's calls).
        let mut contexts = vec![(Ctx::Local(file, id), false)];
        if kind == DefKind::Module {
            for (rid, r) in defs.children(Some(id)) {
                match (r.kind, &r.data) {
                    (DefKind::Platform, _) => contexts.push((Ctx::Local(file, rid), true)),
                    (DefKind::PlatformRef, DefData::Reference { path, .. }) => {
                        if let Some(loc) = resolve_item(db, self.ws, file, path, |k| k == DefKind::Platform).first() {
                            contexts.push((Ctx::Item(*loc), true));
                        }
                    }
                    _ => {}
                }
            }
        }
        for (ctx, platform) in contexts {
            for m in ctx_members(db, self.ws, ctx).iter() {
                let Some((mfile, mdecl)) = target_decl(db, m.target) else { continue };
                let ty = m.ty.as_ref().map(|t| self.ty(mfile, t));
                match m.kind {
                    DefKind::Event => {
                        let name = format!("{module}::{}", m.name);
                        let fields = std::iter::once(CspType::InOut).chain(ty.clone()).collect();
                        if !channels.contains(&name) {
                            self.push(name.clone(), CspKind::Channel { fields }, Some(mdecl));
                            channels.push(name);
                        }
                        if let (true, Some(io)) = (robosim, m.io) {
                            registers.push((m.name.clone(), io, ty, mdecl));
                        }
                    }
                    DefKind::Variable if kind == DefKind::Module => {
                        let name = format!("{module}::set_{}", m.name);
                        self.push(name.clone(), CspKind::Channel { fields: ty.into_iter().collect() }, Some(mdecl));
                        channels.push(name);
                    }
                    DefKind::Variable if robosim && m.io.is_some() => {
                        registers.push((m.name.clone(), m.io.unwrap_or(crate::defs::Io::Input), ty, mdecl));
                    }
                    DefKind::Constant if kind == DefKind::StateMachine => {
                        let name = format!("const_{owner}_{}", m.name);
                        let init = member_init(db, m.target);
                        let ty = ty.unwrap_or(CspType::Other(String::new()));
                        self.push(name.clone(), CspKind::Constant { ty, init }, Some(mdecl));
                        constants.push(name);
                    }
                    DefKind::OperationSig if platform || m.via != Some(crate::defs::UseKind::Provides) => {
                        let name = format!("{module}::{}Call", m.name);
                        let fields = sig_params(db, m.target).iter().map(|t| self.ty(mfile, t)).collect();
                        if !channels.contains(&name) {
                            self.push(name.clone(), CspKind::Channel { fields }, Some(mdecl));
                            channels.push(name);
                        }
                        if robosim && m.io.is_some() {
                            registers.push((m.name.clone(), crate::defs::Io::Output, None, mdecl));
                        }
                    }
                    _ => {}
                }
            }
        }
        // Inline components and references, in declaration order: their
        // constants are this element's parameters too.
        for (cid, c) in defs.children(Some(id)) {
            if c.name.is_empty() {
                continue;
            }
            let cdecl = Decl { file, range: c.name_range };
            let mut cpath = path.clone();
            cpath.push(c.name.clone());
            let cmodule = format!("{module}::{}", c.name);
            let cowner = format!("{owner}_{}", c.name);
            match (c.kind, &c.data) {
                (DefKind::Controller | DefKind::StateMachine, _) => {
                    constants.extend(self.element(file, cid, c.kind, cpath, cmodule, cowner, cdecl));
                }
                (DefKind::ControllerRef | DefKind::MachineRef, DefData::Reference { path: target, .. }) => {
                    let want =
                        if c.kind == DefKind::ControllerRef { DefKind::Controller } else { DefKind::StateMachine };
                    let accept = if want == DefKind::Controller {
                        (|k| k == DefKind::Controller) as fn(DefKind) -> bool
                    } else {
                        |k| k == DefKind::StateMachine
                    };
                    let Some(loc) = resolve_item(db, self.ws, file, target, accept).first().copied() else { continue };
                    let Some(tid) = loc.def(db) else { continue };
                    // A controller's constants are named after the
                    // controller itself (`const_MovementC_stm_ref0_lv`),
                    // whichever module refers to it.
                    let towner = if want == DefKind::Controller {
                        let tpkg = package_prefix(&file_summary(db, loc.file).package);
                        joined(&tpkg, &loc.summary(db).name, "_")
                    } else {
                        cowner
                    };
                    constants.extend(self.element(loc.file, tid, want, cpath, cmodule, towner, cdecl));
                }
                _ => {}
            }
        }
        let terminate = format!("{module}::terminate");
        self.push(terminate.clone(), CspKind::Channel { fields: Vec::new() }, None);
        channels.push(terminate);
        if robosim {
            for (name, io, ty, rdecl) in registers {
                let input = io == crate::defs::Io::Input;
                let reg = format!("{module}::{}_{name}", if input { "i" } else { "o" });
                self.push(reg, CspKind::Register { input, ty }, Some(rdecl));
            }
            for (ch, fields) in [
                (
                    "registerRead",
                    vec![CspType::Other("register".into()), CspType::Bool, CspType::Other("value".into())],
                ),
                ("registerWrite", vec![CspType::Other("register".into()), CspType::Other("value".into())]),
                ("endexec", Vec::new()),
            ] {
                let name = format!("{module}::{ch}");
                self.push(name.clone(), CspKind::Channel { fields }, None);
                channels.push(name);
            }
        }
        let mut params = vec!["id__".to_string()];
        params.extend(constants.iter().cloned());
        for p in ["D__", "O__", "VS__", "VS_O__", "AS_O__"] {
            self.push(format!("{module}::{p}"), CspKind::Process { params: params.clone() }, Some(decl));
        }
        self.push(format!("{module}::sem__events"), CspKind::EventSet, Some(decl));
        self.elements.push(CspElement { module, path, kind, robosim, decl, channels, constants: constants.clone() });
        constants
    }

    /// The CSPm type of `t`, written in `file`.
    fn ty(&self, file: File, t: &TypeRef) -> CspType {
        self.of(&crate::types::lower(self.db, self.ws, file, t))
    }

    fn of(&self, t: &Ty) -> CspType {
        match t {
            Ty::Nat => CspType::Nat,
            Ty::Int => CspType::Int,
            Ty::Real => CspType::Real,
            Ty::Bool => CspType::Bool,
            Ty::Str => CspType::Str,
            Ty::Named(loc, name, _) => {
                let pkg = package_prefix(&file_summary(self.db, loc.file).package);
                if pkg == "core" {
                    return CspType::Named(format!("core_{name}"));
                }
                CspType::Named(joined(&pkg, name, "_"))
            }
            Ty::Product(ts) => CspType::Tuple(ts.iter().map(|t| self.of(t)).collect()),
            Ty::Set(a) => CspType::Set(Box::new(self.of(a))),
            Ty::Seq(a) => CspType::Seq(Box::new(self.of(a))),
            other => CspType::Other(other.to_string()),
        }
    }
}

/// The file and name range of a member's declaration.
fn target_decl(db: &dyn Db, t: Target) -> Option<(File, Decl)> {
    let (file, id) = target_def(db, t)?;
    let range = file_defs(db, file).def(id).name_range;
    Some((file, Decl { file, range }))
}

/// The definition a member target denotes.
fn target_def(db: &dyn Db, t: Target) -> Option<(File, DefId)> {
    match t {
        Target::Def(file, id) => Some((file, id)),
        Target::Item(loc) => Some((loc.file, loc.def(db)?)),
        Target::Member(loc, i) => {
            let item = loc.def(db)?;
            let defs = file_defs(db, loc.file);
            let (id, _) = defs.children(Some(item)).filter(|(_, d)| !d.name.is_empty()).nth(i as usize)?;
            Some((loc.file, id))
        }
    }
}

/// A constant's initialiser, as written.
fn member_init(db: &dyn Db, t: Target) -> Option<String> {
    let (file, id) = target_def(db, t)?;
    match &file_defs(db, file).def(id).data {
        DefData::Typed { init: Some(r), .. } => {
            Some(file.text(db).get(std::ops::Range::<usize>::from(*r))?.trim().to_string())
        }
        _ => None,
    }
}

/// The parameter types of an operation signature.
fn sig_params(db: &dyn Db, t: Target) -> Vec<TypeRef> {
    let Some((file, id)) = target_def(db, t) else { return Vec::new() };
    match &file_defs(db, file).def(id).data {
        DefData::Signature { params, .. } => {
            params.iter().map(|(_, t)| t.clone().unwrap_or(TypeRef::Missing)).collect()
        }
        _ => Vec::new(),
    }
}

/// The CSPm module path of a top-level item (`A_B::M`, `M` in the default
/// package), for callers that start from the index.
pub fn item_module(db: &dyn Db, loc: ItemLoc) -> String {
    let pkg = package_prefix(&file_summary(db, loc.file).package);
    joined(&pkg, &loc.summary(db).name, "::")
}
