//! RoboTool's number domains (robotool-facts RT-5), computed once for
//! every back end: `core_nat = {0..2}`, `core_int = core_real = {-2..2}`,
//! each widened to cover the values of the model's expressions of that
//! type (a `nat` expression also widens `int` and `real`, an `int` one
//! `real`), every expression evaluated with the sticky arithmetic
//! (`Plus(e1, e2, T)` keeps `e1` when the result leaves `T`; a divisor 0
//! counts as 1, RT-6) over the base ranges of its free variables and
//! constants and over its literals. The generated `instantiations.csp`
//! writes this as `union(base, {calc_type_min(U)..calc_type_max(U)})`,
//! where `calc_type_max` never goes below 0.
//!
//! Our reading of the reference output (`../shared/reference/alpha-algorithm`,
//! its `csp-gen/instantiations.csp` counted entry by entry): the lists
//! hold the model's values — values assigned, sent and waited for (the
//! reference's waits are all `floor(…)` calls, so whether a literal
//! wait counts is not shown; we count it), initial values, deadlines, the
//! arguments of every call wherever it is
//! (in a condition too: `f(-3) > i` lists `-3`) — and one entry of the
//! base range per declared variable, constant and parameter (the bare
//! `{0..2}` entries: 22 in each RoboChart list, one per `nat`
//! declaration of the project, events left out), so the least value is
//! the base's whenever the model declares one. A comparison's operands
//! and an index are no values: the one `{1}` of each list is
//! `waitOp(1)`'s argument, not `x[1]`'s index (which occurs twice, in
//! `communication.rct` and its rc2rs copy, both covered: the three
//! `card(neighs)` entries are the root's send and the copy's two), and no
//! list has an entry for `n`, `alpha`, `RC` or `MB` of the conditions
//! `n > alpha`, `since(RCC) >= RC`, `since(MBC) >= MB`. The operands of
//! arithmetic are no values either (`360` in `random() * 360 / av`
//! widens nothing). The values come from every machine and operation of
//! the project, not only the checked element (RoboTool writes one
//! `instantiations.csp` per project). Inside `core_real`'s own list the
//! arithmetic is over the base ranges; the other lists use the widened
//! `core_real` (and `core_int`) for the arithmetic of those types.
//!
//! RoboSim (`.rst` files): RoboTool writes a second file for RoboSim
//! elements (`sim/instantiations.csp`) whose lists hold the RoboChart
//! models' entries, as above, and the RoboSim models' (the RoboChart
//! elements' lists leave the RoboSim models out). Counted in the reference
//! (entry by entry: `sim/` lists against the RoboChart ones), the RoboSim
//! models add the arguments of every call — platform operations
//! (`$move(0, av)`: five `{0}`, three `av`, one `Neg(av)`, one `lv`) and
//! operations (`clone_waitOp_j_2_5_f(floor(random() * 360 / av))`: the
//! argument, and `floor`'s own argument inside it) — and nothing for
//! conditions (`since(C) == i`, `n > alpha`, `$e?x`), for outputs (the
//! three `card(neighs)` entries are the RoboChart sends; `$robots !
//! size(neighs)` adds none) or for `cycleDef cycle == 1` (the one `{1}` is
//! RoboChart's `waitOp(1)`). The other `{0..2}` and `{-2..2}` entries are
//! the declared variables, constants and parameters of each type, events
//! left out (14 more of each in the RoboSim models, 22 of each in the
//! RoboChart ones), which widen nothing. (The RoboChart lists, counted so,
//! hold no comparison operand or index either: see above.) So a RoboSim
//! model's sites are: the arguments of every call, wherever it is (each
//! evaluated on its own, not taken apart), and — as in RoboChart, with no
//! RoboSim example either way — initial and assigned values (a platform
//! variable's `$x = e` too, although it writes a register as `$e!v` does).
//!
//! The values an assertion gives constants (`with constant PI set to 45`)
//! widen nothing: RoboTool computes with these domains whatever they are.
//! What an assertion file's `Instantiations` block fixes (`nametype
//! core_real = {a..b}`, RT-7) stays as given, and its other definitions
//! (primitive types' ranges, constants, functions written in CSPm) take
//! part in the evaluation ([`DomainInputs`]).

use std::collections::{BTreeMap, BTreeSet};

use robosim_syntax::{FileKind, TextRange};

use crate::csp_fn::{CspBinOp, CspExpr, CspFunction};
use crate::defs::DefKind;
use crate::index::project_of;
use crate::model::{
    self, item, Behaviour, BinOp, CommPart, Definition, Expr as MExpr, ExprKind, Item, Region, Stmt, StmtKind, UnOp,
};
use crate::types::{expr_types, Ty};
use crate::{Db, File, Workspace};

/// A value of the number types.
type Val = i64;

/// An integer range `{lo..hi}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NumRange {
    /// Least value.
    pub lo: i64,
    /// Greatest value.
    pub hi: i64,
}

impl NumRange {
    /// Booleans, as numbers.
    const BOOL: NumRange = NumRange { lo: 0, hi: 1 };

    /// Whether `v` is in the range.
    pub fn contains(self, v: i64) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// The number of values.
    pub fn size(self) -> u64 {
        (self.hi as i128 - self.lo as i128 + 1).clamp(0, u64::MAX as i128) as u64
    }
}

/// RoboTool's ranges before widening: `core_nat`, `core_int`, `core_real`.
pub const BASE: [NumRange; 3] = [NumRange { lo: 0, hi: 2 }, NumRange { lo: -2, hi: 2 }, NumRange { lo: -2, hi: 2 }];

/// The names of the three number types, by rank (nat 0, int 1, real 2).
pub const NAMES: [&str; 3] = ["core_nat", "core_int", "core_real"];

/// What an assertion file's instantiations give the computation (RT-7):
/// the default for a workspace without any is [`DomainInputs::default`].
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct DomainInputs {
    /// `core_nat`, `core_int`, `core_real` as an instantiation fixes them
    /// (not widened then).
    pub fixed: [Option<NumRange>; 3],
    /// Every `nametype X = {a..b}` (the ranges of the primitive types the
    /// model declares, for `size`).
    pub types: Vec<(String, NumRange)>,
    /// Constant values (`pkg_Machine_k = v`), for functions written in CSPm.
    pub constants: Vec<(String, i64)>,
    /// Functions written in CSPm, for the model's functions without a body.
    pub functions: Vec<CspFunction>,
    /// Whether an `Instantiations` block replaces RoboTool's generated
    /// defaults (RT-7).
    pub replaced: bool,
}

/// The number types of a project.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NumberDomains {
    /// `core_nat`, `core_int`, `core_real`.
    pub domains: [NumRange; 3],
    /// Which of them the model's expressions widened (beyond [`BASE`]).
    pub widened: [bool; 3],
}

impl NumberDomains {
    /// The notes a verdict gives for the widened types (RT-5).
    pub fn notes(&self) -> Vec<String> {
        (0..3)
            .rev()
            .filter(|r| self.widened[*r])
            .map(|r| {
                let d = self.domains[r];
                format!("{} = {{{}..{}}}, widened by the model's expressions (RT-5)", NAMES[r], d.lo, d.hi)
            })
            .collect()
    }
}

/// Why the domains cannot be worked out statically: the user gives them
/// with `nametype core_X = {a..b}` in a `csp` block.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DomainError {
    /// What, as a sentence.
    pub message: String,
    /// The expression at fault, when one is.
    pub location: Option<(File, TextRange)>,
}

/// The most combinations of free values an expression is evaluated at.
const MAX_COMBINATIONS: usize = 1 << 14;

/// The numeric rank of a type: nat 0, int 1, real 2.
fn rank(t: &Ty) -> Option<usize> {
    match t {
        Ty::Nat => Some(0),
        Ty::Int => Some(1),
        Ty::Real => Some(2),
        _ => None,
    }
}

/// One maximal expression, in the file whose types say what it is.
struct Site<'a> {
    file: File,
    expr: &'a MExpr,
    /// Whether the connectives, conditionals and calls inside it are
    /// values too, and the calls' arguments inside its comparisons and
    /// indexed values (RoboChart's reading); RoboSim's sites list the
    /// nested calls' arguments as sites of their own.
    descend: bool,
}

/// RT-5: the number types of the RoboChart models of `project` (as
/// [`project_of`] numbers them), given what the instantiations define;
/// with `robosim`, those of its RoboChart and RoboSim models together, as
/// RoboTool's `sim/instantiations.csp` computes them for RoboSim elements.
#[salsa::tracked(returns(ref))]
pub fn number_domains(
    db: &dyn Db,
    ws: Workspace,
    project: Option<u32>,
    inputs: DomainInputs,
    robosim: bool,
) -> Result<NumberDomains, DomainError> {
    let mut doms = [0, 1, 2].map(|r| inputs.fixed[r].unwrap_or(BASE[r]));
    let none = NumberDomains { domains: doms, widened: [false; 3] };
    if inputs.fixed.iter().all(Option::is_some) {
        return Ok(none);
    }
    let mut sites = Vec::new();
    let mut decl_types: Vec<&Ty> = Vec::new();
    // The variables, constants and parameters: each is an entry of its
    // type's base range in RoboTool's lists (so the lists' least value is
    // the base's when the model declares any).
    let mut held_types: Vec<&Ty> = Vec::new();
    for &f in ws.files(db) {
        let sim = match f.kind(db) {
            FileKind::RoboChart => false,
            FileKind::RoboSim if robosim => true,
            _ => continue,
        };
        if f.is_library(db) || project_of(db, ws, f) != project {
            continue;
        }
        for (_, item) in &model::file_model(db, ws, f).items {
            item_types(item, true, &mut decl_types);
            item_types(item, false, &mut held_types);
            match item {
                Item::Machine(b) | Item::Operation(b) => behaviour(f, b, sim, &mut sites),
                Item::Controller(c) => {
                    for inst in c.machines.iter().chain(&c.operations) {
                        if let Definition::Inline(b) = &inst.def {
                            behaviour(f, b, sim, &mut sites);
                        }
                    }
                }
                Item::Module(m) => {
                    for inst in &m.controllers {
                        if let Definition::Inline(c) = &inst.def {
                            for i in c.machines.iter().chain(&c.operations) {
                                if let Definition::Inline(b) = &i.def {
                                    behaviour(f, b, sim, &mut sites);
                                }
                            }
                        }
                    }
                }
                _ => {}
            }
        }
    }
    let mut declared = [false; 3];
    for t in &decl_types {
        mark_ranks(t, &mut declared);
    }
    // Only plain number types: a record's or a set's entry is not read here.
    let held: BTreeSet<usize> = held_types.iter().filter_map(|t| rank(t)).collect();
    let mut widened = [false; 3];
    // `real` first (over the base ranges), then `int` and `nat` with the
    // widened `real` (and `int`) for the arithmetic of those types.
    let mut arith = BASE;
    for r in [2, 1, 0] {
        if inputs.fixed[r].is_some() {
            arith[r] = doms[r];
            continue;
        }
        let mut own = arith;
        own[r] = BASE[r];
        let mut values = BTreeSet::new();
        let eval =
            |file: File| Eval { db, ws, inputs: &inputs, types: expr_types(db, ws, file), arith: &own, depth: 0 };
        for s in &sites {
            site_values(&eval(s.file), s, r, &mut values)?;
        }
        for &k in held.iter().filter(|&&k| k <= r) {
            values.extend([BASE[k].lo, BASE[k].hi]);
        }
        let max = values.iter().copied().max().unwrap_or(0).max(0);
        let min = values.iter().copied().min().unwrap_or(max).min(max);
        let base = BASE[r];
        let name = NAMES[r];
        // A gap matters only when values of the type are stored or
        // communicated (the values in it would be RoboTool's none).
        if min > base.hi + 1 && declared[r] {
            return Err(DomainError {
                message: format!(
                    "RoboTool's `{name}` here is {{{}..{}}} ∪ {{{min}..{max}}} (RT-5), not one range: \
                     give it with `nametype {name} = {{a..b}}` in a `csp` block of an assertion file",
                    base.lo, base.hi
                ),
                location: None,
            });
        }
        let w = NumRange { lo: base.lo.min(min), hi: base.hi.max(max) };
        widened[r] = w != base;
        doms[r] = w;
        arith[r] = w;
    }
    Ok(NumberDomains { domains: doms, widened })
}

/// [`number_domains`] for the project of `file`: RoboSim's (the RoboChart
/// and RoboSim models of the project) when `file` is a RoboSim file,
/// RoboChart's otherwise.
pub fn domains_of<'db>(
    db: &'db dyn Db,
    ws: Workspace,
    file: File,
    inputs: &DomainInputs,
) -> &'db Result<NumberDomains, DomainError> {
    let robosim = file.kind(db) == FileKind::RoboSim;
    number_domains(db, ws, project_of(db, ws, file), inputs.clone(), robosim)
}

/// Adds to `out` the values of the expressions at `s` (and inside it)
/// whose type widens the domain of rank `r`.
fn site_values(ev: &Eval<'_>, s: &Site<'_>, r: usize, out: &mut BTreeSet<Val>) -> Result<(), DomainError> {
    let mut stack = vec![s.expr];
    while let Some(e) = stack.pop() {
        let ty = ev.types.get(&e.range).and_then(rank);
        if ty.is_some_and(|t| t <= r) {
            let vs = ev.values(e).ok_or_else(|| DomainError {
                message: format!(
                    "RoboTool's `{}` depends on the value of this expression, which the native checker \
                     cannot work out (RT-5): give the type with `nametype {} = {{a..b}}` in a `csp` block",
                    NAMES[r], NAMES[r]
                ),
                location: Some((s.file, e.range)),
            })?;
            out.extend(vs);
        }
        if !s.descend {
            continue;
        }
        // Into what is not arithmetic: connectives, calls, conditionals.
        // A comparison's operands and an index are no values of their own
        // (RoboTool's lists hold no `n`, `alpha` of `n > alpha`, no `1` of
        // `x[1]`: see the module doc), but the arguments of the calls in
        // them are.
        match &e.kind {
            ExprKind::Binary(op, a, b) if is_comparison(*op) => {
                for operand in [&**a, &**b] {
                    operand.walk(&mut |x| {
                        if let ExprKind::Call { args, .. } = &x.kind {
                            stack.extend(args.iter());
                        }
                    });
                }
            }
            ExprKind::Binary(op, a, b) if !is_arith(*op) => stack.extend([&**a, &**b]),
            ExprKind::Unary(UnOp::Not, a) => stack.push(a),
            ExprKind::Call { args, .. } => stack.extend(args.iter()),
            ExprKind::If(c, a, b) => stack.extend([&**c, &**a, &**b]),
            ExprKind::Index(base, _) => stack.push(base),
            ExprKind::Tuple(xs) => stack.extend(xs.iter()),
            ExprKind::Record(fs) => stack.extend(fs.iter().map(|(_, x)| x)),
            ExprKind::Interval { lo, hi, .. } => stack.extend([&**lo, &**hi]),
            _ => {}
        }
    }
    Ok(())
}

fn is_comparison(op: BinOp) -> bool {
    matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::In)
}

fn is_arith(op: BinOp) -> bool {
    matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Mod)
}

/// The sites of a machine or operation: RoboChart's maximal expressions,
/// or, with `sim`, RoboSim's (see the module doc: initial values, assigned
/// values and the arguments of every call, wherever it is; not
/// conditions, outputs (`$e!v`) or cycle definitions).
fn behaviour<'a>(file: File, b: &'a Behaviour, sim: bool, out: &mut Vec<Site<'a>>) {
    for d in &b.decls.decls {
        if let model::Decl::Vars { vars, .. } = d {
            for v in vars.iter().filter_map(|v| v.init.as_ref()) {
                match sim {
                    false => out.push(Site { file, descend: true, expr: v }),
                    true => sim_value(file, v, out),
                }
            }
        }
    }
    region_sites(file, &b.region, sim, out);
}

fn region_sites<'a>(file: File, r: &'a Region, sim: bool, out: &mut Vec<Site<'a>>) {
    let stmt = |s: &'a Stmt, out: &mut Vec<Site<'a>>| match sim {
        false => stmt_sites(file, s, out),
        true => sim_stmt_sites(file, s, out),
    };
    for n in &r.nodes {
        for a in [&n.entry, &n.during, &n.exit].into_iter().flatten() {
            if let Some(s) = &a.stmt {
                stmt(s, out);
            }
        }
        region_sites(file, &n.region, sim, out);
    }
    for t in &r.transitions {
        let condition = t.condition.as_ref().and_then(|c| c.expr.as_ref());
        let deadline = t.deadline.as_ref().and_then(|(_, d)| d.as_ref());
        for e in condition.into_iter().chain(deadline) {
            match sim {
                false => out.push(Site { file, descend: true, expr: e }),
                true => sim_calls(file, e, out),
            }
        }
        if let Some(s) = t.action.as_ref().and_then(|a| a.stmt.as_ref()) {
            stmt(s, out);
        }
    }
}

fn stmt_sites<'a>(file: File, s: &'a Stmt, out: &mut Vec<Site<'a>>) {
    s.walk(&mut |s| match &s.kind {
        StmtKind::Assign { value, .. } => out.push(Site { file, descend: true, expr: value }),
        StmtKind::If(c, ..) => out.push(Site { file, descend: true, expr: c }),
        StmtKind::Comm(c) => {
            if let Some(CommPart::Sync(Some(v)) | CommPart::Output(Some(v))) = &c.part {
                out.push(Site { file, descend: true, expr: v });
            }
        }
        StmtKind::Call { args, .. } | StmtKind::SimCall { args, .. } => {
            out.extend(args.iter().map(|expr| Site { file, descend: true, expr }))
        }
        StmtKind::Output(_, Some(v)) | StmtKind::Wait(v) | StmtKind::Timed(_, Some(v)) => {
            out.push(Site { file, descend: true, expr: v })
        }
        _ => {}
    });
}

fn sim_stmt_sites<'a>(file: File, s: &'a Stmt, out: &mut Vec<Site<'a>>) {
    s.walk(&mut |s| match &s.kind {
        StmtKind::Assign { value, .. } => sim_value(file, value, out),
        StmtKind::Call { args, .. } | StmtKind::SimCall { args, .. } => {
            args.iter().for_each(|a| sim_value(file, a, out))
        }
        StmtKind::If(c, ..) | StmtKind::Wait(c) | StmtKind::Timed(_, Some(c)) | StmtKind::Output(_, Some(c)) => {
            sim_calls(file, c, out)
        }
        StmtKind::Comm(c) => {
            if let Some(CommPart::Sync(Some(v)) | CommPart::Output(Some(v))) = &c.part {
                sim_calls(file, v, out);
            }
        }
        _ => {}
    });
}

/// A value that is a site of its own, and the calls in it.
fn sim_value<'a>(file: File, e: &'a MExpr, out: &mut Vec<Site<'a>>) {
    out.push(Site { file, expr: e, descend: false });
    sim_calls(file, e, out);
}

/// The arguments of the calls in `e`, each a site.
fn sim_calls<'a>(file: File, e: &'a MExpr, out: &mut Vec<Site<'a>>) {
    e.walk(&mut |x| {
        if let ExprKind::Call { args, .. } = &x.kind {
            out.extend(args.iter().map(|a| Site { file, expr: a, descend: false }));
        }
    });
}

/// Evaluates expressions over every combination of their free values.
struct Eval<'c> {
    db: &'c dyn Db,
    ws: Workspace,
    inputs: &'c DomainInputs,
    types: &'c rustc_hash::FxHashMap<TextRange, Ty>,
    arith: &'c [NumRange; 3],
    /// How deep in the bodies of functions `result == e` it evaluates.
    depth: usize,
}

impl Eval<'_> {
    /// The values of `e` (none when it cannot be worked out).
    fn values(&self, e: &MExpr) -> Option<BTreeSet<Val>> {
        // The free values: names and what is not computed here (tuple
        // components, fields, set sizes), each over its base range, keyed
        // by name (one value per name) or by range.
        let mut free: BTreeMap<String, NumRange> = BTreeMap::new();
        self.free(e, &mut free)?;
        let keys: Vec<(&String, &NumRange)> = free.iter().collect();
        let mut count: usize = 1;
        for (_, d) in &keys {
            count = count.checked_mul(d.size() as usize).filter(|c| *c <= MAX_COMBINATIONS)?;
        }
        let mut out = BTreeSet::new();
        let mut env: BTreeMap<String, Val> = keys.iter().map(|(k, d)| ((*k).clone(), d.lo)).collect();
        for i in 0..count {
            let mut rest = i;
            for (k, d) in &keys {
                let n = d.size() as usize;
                env.insert((*k).clone(), d.lo + (rest % n) as Val);
                rest /= n;
            }
            if let Some(v) = self.eval(e, &env) {
                out.insert(v);
            }
        }
        Some(out)
    }

    fn base_of(&self, e: &MExpr) -> Option<NumRange> {
        match self.types.get(&e.range)? {
            Ty::Bool => Some(NumRange::BOOL),
            t @ Ty::Named(_, _, DefKind::Enumeration) => Some(NumRange { lo: 0, hi: self.type_size(t)? - 1 }),
            t => rank(t).map(|r| BASE[r]),
        }
    }

    /// The key of a free value.
    fn key(e: &MExpr) -> String {
        match &e.kind {
            ExprKind::Name { name, .. } => name.clone(),
            _ => format!("@{:?}", e.range),
        }
    }

    fn free(&self, e: &MExpr, out: &mut BTreeMap<String, NumRange>) -> Option<()> {
        match &e.kind {
            ExprKind::Int(_) | ExprKind::Bool(_) | ExprKind::Real(_) | ExprKind::EnumLiteral { .. } => {}
            ExprKind::Unary(_, a) => self.free(a, out)?,
            ExprKind::Binary(_, a, b) => {
                self.free(a, out)?;
                self.free(b, out)?;
            }
            ExprKind::If(c, a, b) => {
                self.free(c, out)?;
                self.free(a, out)?;
                self.free(b, out)?;
            }
            ExprKind::Call { function, args, res } if !matches!(function.as_str(), "size" | "card") => {
                for a in args {
                    // Arguments that are not numbers only matter to CSPm
                    // definitions, which would need them: not evaluated.
                    if self.base_of(a).is_some() {
                        self.free(a, out)?;
                    } else if self.csp_defined(function, res.as_ref()).is_some() || self.body_of(res.as_ref()).is_some()
                    {
                        return None;
                    }
                }
            }
            ExprKind::Call { args, .. } => {
                // `size(s)`: from 0 to the number of values of its elements.
                let n = match args.first().and_then(|a| self.types.get(&a.range)) {
                    Some(Ty::Set(el)) => self.type_size(el)?,
                    _ => return None,
                };
                out.insert(Self::key(e), NumRange { lo: 0, hi: n });
            }
            _ => {
                out.insert(Self::key(e), self.base_of(e)?);
            }
        }
        Some(())
    }

    /// The number of values of an element type, for `size`.
    fn type_size(&self, t: &Ty) -> Option<Val> {
        Some(match t {
            Ty::Bool => 2,
            Ty::Named(loc, _, DefKind::Enumeration) => match item(self.db, self.ws, *loc)? {
                Item::Enumeration(_, lits) => lits.len() as Val,
                _ => return None,
            },
            Ty::Named(_, name, DefKind::PrimitiveType) => {
                let core = format!("core_{name}");
                match self.inputs.types.iter().rev().find(|(n, _)| n == name || *n == core) {
                    Some((_, d)) => d.size() as Val,
                    None => 2,
                }
            }
            t => BASE[rank(t)?].size() as Val,
        })
    }

    /// The function a call resolved to `res` calls, when a postcondition
    /// pins its result (a body, in RoboTool's CSPm `pkg_f(x) = e`).
    fn body_of(&self, res: Option<&crate::resolve::Target>) -> Option<(File, &'_ crate::model::Function)> {
        let Some(crate::resolve::Target::Item(loc)) = res else { return None };
        match item(self.db, self.ws, *loc)? {
            Item::Function(f) if f.pins_result() => Some((loc.file, f)),
            _ => None,
        }
    }

    /// The `csp` block definition a call of `f` (resolved to `res`) reads,
    /// by name ([`crate::csp_fn::block_definition`], as the engine reads it).
    fn csp_defined(&self, f: &str, res: Option<&crate::resolve::Target>) -> Option<String> {
        let robotool = match res {
            Some(crate::resolve::Target::Item(loc)) => Some(crate::csp_fn::robotool_function_name(
                crate::element::file_package(self.db, loc.file),
                &loc.summary(self.db).name,
            )),
            _ => None,
        };
        crate::csp_fn::block_definition(&self.inputs.functions, robotool.as_deref(), f, self.inputs.replaced)
            .map(|(n, _)| n.to_string())
    }

    /// The sticky domain of the arithmetic at `e` (its type's).
    fn dom(&self, e: &MExpr) -> NumRange {
        self.arith[self.types.get(&e.range).and_then(rank).unwrap_or(2)]
    }

    fn eval(&self, e: &MExpr, env: &BTreeMap<String, Val>) -> Option<Val> {
        let sticky = |r: Option<Val>, x: Val| r.filter(|r| self.dom(e).contains(*r)).unwrap_or(x);
        Some(match &e.kind {
            ExprKind::Int(v) => (*v)?,
            ExprKind::Bool(b) => *b as Val,
            ExprKind::Real(t) => {
                let v: f64 = t.parse().ok()?;
                (v.fract() == 0.0 && v.abs() < 1e15).then_some(v as Val)?
            }
            ExprKind::EnumLiteral { literal, enumeration, .. } => {
                match enumeration.and_then(|l| item(self.db, self.ws, l))? {
                    Item::Enumeration(_, lits) => lits.iter().position(|l| l == literal)? as Val,
                    _ => return None,
                }
            }
            // A negative literal is a number (not `Neg` of one).
            ExprKind::Unary(UnOp::Neg, a) if matches!(a.kind, ExprKind::Int(_) | ExprKind::Real(_)) => {
                self.eval(a, env)?.checked_neg()?
            }
            ExprKind::Unary(UnOp::Neg, a) => {
                let x = self.eval(a, env)?;
                sticky(x.checked_neg(), x)
            }
            ExprKind::Unary(UnOp::Not, a) => (self.eval(a, env)? == 0) as Val,
            ExprKind::Binary(op, a, b) => {
                let (x, y) = (self.eval(a, env)?, self.eval(b, env)?);
                match op {
                    BinOp::Add => sticky(x.checked_add(y), x),
                    BinOp::Sub => sticky(x.checked_sub(y), x),
                    BinOp::Mul => sticky(x.checked_mul(y), x),
                    // RT-6: `no_zero_div`.
                    BinOp::Div => sticky(x.checked_div(if y == 0 { 1 } else { y }), x),
                    // FDR stops on `x % 0`: no value.
                    BinOp::Mod => sticky(Some(x.checked_rem(y)?), x),
                    BinOp::Eq => (x == y) as Val,
                    BinOp::Ne => (x != y) as Val,
                    BinOp::Lt => (x < y) as Val,
                    BinOp::Le => (x <= y) as Val,
                    BinOp::Gt => (x > y) as Val,
                    BinOp::Ge => (x >= y) as Val,
                    BinOp::And => (x != 0 && y != 0) as Val,
                    BinOp::Or => (x != 0 || y != 0) as Val,
                    BinOp::Implies => (x == 0 || y != 0) as Val,
                    BinOp::Iff => ((x != 0) == (y != 0)) as Val,
                    _ => return None,
                }
            }
            ExprKind::If(c, a, b) => {
                if self.eval(c, env)? != 0 {
                    self.eval(a, env)?
                } else {
                    self.eval(b, env)?
                }
            }
            ExprKind::Call { function, args, res } if !matches!(function.as_str(), "size" | "card") => {
                if let Some(name) = self.csp_defined(function, res.as_ref()) {
                    let mut vs = Vec::new();
                    for a in args {
                        vs.push(self.eval(a, env)?);
                    }
                    csp_apply(&self.inputs.functions, &self.inputs.constants, &name, &vs, 0)?
                } else if let Some((file, func)) = self.body_of(res.as_ref()) {
                    // RT-2: RoboTool's `pkg_f(x) = e`, which FDR evaluates
                    // where the instantiations' sets apply it.
                    let [body] = func.result_definitions()[..] else { return None };
                    if self.depth >= 16 || args.len() != func.params.len() {
                        return None;
                    }
                    let mut bound = BTreeMap::new();
                    for (p, a) in func.params.iter().zip(args) {
                        bound.insert(p.name.clone(), self.eval(a, env)?);
                    }
                    let types = expr_types(self.db, self.ws, file);
                    Eval { types, depth: self.depth + 1, ..*self }.eval(body, &bound)?
                } else {
                    // RT-2: the default of its result type (0, `true`).
                    match self.types.get(&e.range)? {
                        Ty::Bool => 1,
                        t => {
                            rank(t)?;
                            0
                        }
                    }
                }
            }
            _ => *env.get(&Self::key(e))?,
        })
    }
}

/// A function defined in CSPm applied to numbers (plain CSPm arithmetic).
fn csp_apply(fs: &[CspFunction], consts: &[(String, Val)], name: &str, args: &[Val], depth: usize) -> Option<Val> {
    if depth > 16 {
        return None;
    }
    'clauses: for c in fs.iter().filter(|c| c.name == name && c.params.len() == args.len()) {
        let mut env = BTreeMap::new();
        for (p, a) in c.params.iter().zip(args) {
            match p {
                CspExpr::Name(n) if n.contains('_') => return None, // a constructor
                CspExpr::Name(n) => {
                    env.insert(n.clone(), *a);
                }
                CspExpr::Int(v) if v == a => {}
                CspExpr::Bool(b) if (*b as Val) == *a => {}
                CspExpr::Int(_) | CspExpr::Bool(_) => continue 'clauses,
                _ => return None,
            }
        }
        return csp_eval(fs, consts, &c.body, &env, depth);
    }
    None
}

fn csp_eval(
    fs: &[CspFunction],
    consts: &[(String, Val)],
    e: &CspExpr,
    env: &BTreeMap<String, Val>,
    depth: usize,
) -> Option<Val> {
    let go = |x: &CspExpr| csp_eval(fs, consts, x, env, depth);
    Some(match e {
        CspExpr::Int(v) => *v,
        CspExpr::Bool(b) => *b as Val,
        CspExpr::Name(n) => match env.get(n) {
            Some(v) => *v,
            None => match consts.iter().find(|(c, _)| c == n) {
                Some((_, v)) => *v,
                None => csp_apply(fs, consts, n, &[], depth + 1)?,
            },
        },
        CspExpr::Call(f, xs) => {
            let mut vs = Vec::new();
            for x in xs {
                vs.push(go(x)?);
            }
            csp_apply(fs, consts, f, &vs, depth + 1)?
        }
        CspExpr::Neg(x) => go(x)?.checked_neg()?,
        CspExpr::Not(x) => (go(x)? == 0) as Val,
        CspExpr::Bin(op, a, b) => {
            let (x, y) = (go(a)?, go(b)?);
            match op {
                CspBinOp::Add => x.checked_add(y)?,
                CspBinOp::Sub => x.checked_sub(y)?,
                CspBinOp::Mul => x.checked_mul(y)?,
                CspBinOp::Div => x.checked_div(y)?,
                CspBinOp::Mod => x.checked_rem(y)?,
                CspBinOp::Eq => (x == y) as Val,
                CspBinOp::Ne => (x != y) as Val,
                CspBinOp::Lt => (x < y) as Val,
                CspBinOp::Le => (x <= y) as Val,
                CspBinOp::Gt => (x > y) as Val,
                CspBinOp::Ge => (x >= y) as Val,
                CspBinOp::And => (x != 0 && y != 0) as Val,
                CspBinOp::Or => (x != 0 || y != 0) as Val,
                CspBinOp::Cat => return None,
            }
        }
        CspExpr::If(c, a, b) => {
            if go(c)? != 0 {
                go(a)?
            } else {
                go(b)?
            }
        }
    })
}

/// Marks the numeric types `t` stores (in products and sets too).
fn mark_ranks(t: &Ty, out: &mut [bool; 3]) {
    match t {
        Ty::Product(ts) => ts.iter().for_each(|t| mark_ranks(t, out)),
        Ty::Set(t) | Ty::Seq(t) | Ty::Vector(t, _) | Ty::Matrix(t, ..) => mark_ranks(t, out),
        t => {
            if let Some(r) = rank(t) {
                out[r] = true;
            }
        }
    }
}

/// The types of what an item declares: variables, constants, events
/// (with `events`), parameters (of its behaviours, interfaces,
/// controllers, platforms).
fn item_types<'a>(item: &'a Item, events: bool, out: &mut Vec<&'a Ty>) {
    fn decls<'a>(d: &'a model::Decls, events: bool, out: &mut Vec<&'a Ty>) {
        for d in &d.decls {
            match d {
                model::Decl::Vars { vars, .. } => out.extend(vars.iter().filter_map(|v| v.ty.as_ref()).map(|t| &t.ty)),
                model::Decl::Event { ty: Some(t), .. } if events => out.push(&t.ty),
                model::Decl::OperationSig { params, .. } => {
                    out.extend(params.iter().filter_map(|p| p.ty.as_ref()).map(|t| &t.ty))
                }
                _ => {}
            }
        }
    }
    fn behaviour<'a>(b: &'a Behaviour, events: bool, out: &mut Vec<&'a Ty>) {
        decls(&b.decls, events, out);
        out.extend(b.params.iter().filter_map(|p| p.ty.as_ref()).map(|t| &t.ty));
    }
    fn controller<'a>(c: &'a model::Controller, events: bool, out: &mut Vec<&'a Ty>) {
        decls(&c.decls, events, out);
        for i in c.machines.iter().chain(&c.operations) {
            if let Definition::Inline(b) = &i.def {
                behaviour(b, events, out);
            }
        }
    }
    match item {
        Item::Machine(b) | Item::Operation(b) => behaviour(b, events, out),
        Item::Controller(c) => controller(c, events, out),
        Item::Interface(p) | Item::Platform(p) => decls(&p.decls, events, out),
        Item::Module(m) => {
            for c in &m.controllers {
                if let Definition::Inline(c) = &c.def {
                    controller(c, events, out);
                }
            }
            for p in &m.platforms {
                if let Definition::Inline(p) = &p.def {
                    decls(&p.decls, events, out);
                }
            }
        }
        Item::Record(_, fields) if events => out.extend(fields.iter().filter_map(|f| f.ty.as_ref()).map(|t| &t.ty)),
        _ => {}
    }
}
