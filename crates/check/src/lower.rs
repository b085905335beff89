//! Lowering of a resolved RoboChart module, controller or machine into the
//! compiled [`Design`]: machines as instruction lists, variables and clocks as
//! slots of a flat state vector, types as bounded ranges (semantics.md §3),
//! events and platform operations as channels to the platform.
//!
//! What the engine cannot interpret yet is refused with a reason and a
//! source location ([`Unsupported`]) instead of being approximated: a wrong
//! verdict is worse than none.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use robosim_hir::defs::{file_defs, DefKind};
use robosim_hir::index::{resolve_item, ItemLoc};
use robosim_hir::{parse, Db, File, Workspace};
use robosim_syntax::ast::{self, name_text as ident_text, qualified_path as path_of};
use robosim_syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange};

use crate::events::{tuple_size, Param};
use crate::ir::*;
use robosim_hir::csp_fn::{CspBinOp, CspExpr, CspFunction};

/// The largest tuple type (number of tuples): its encoding must fit a slot.
const MAX_TUPLES: u64 = 1 << 30;

/// The largest element type of a set: a set is a bitmask in one slot.
const MAX_SET_ELEMENTS: u64 = 31;

/// A type as the lowering sees it. Every value is one slot: a product is
/// its components in mixed radix (first component most significant, so
/// that the codes count tuples in CSPm's order and one event parameter
/// carries a tuple: the event table prints the components as fields); a
/// finite set is a bitmask over its element type's codes.
#[derive(Debug, Clone, PartialEq)]
enum Ty {
    /// Numbers, booleans, enumerations.
    Num(Dom),
    /// `A * B * …` of numeric components.
    Tuple(Vec<Dom>),
    /// A record of numeric fields (names, domains): encoded as the tuple
    /// of its fields in declaration order.
    Record(Vec<String>, Vec<Dom>),
    /// `Set(T)` of a type with at most [`MAX_SET_ELEMENTS`] values.
    Set(Box<Ty>),
}

impl Ty {
    /// The slot's range.
    fn dom(&self) -> Dom {
        match self {
            Ty::Num(d) => *d,
            Ty::Tuple(ds) | Ty::Record(_, ds) => Dom { lo: 0, hi: tuple_size(ds) as Val - 1 },
            Ty::Set(el) => Dom { lo: 0, hi: (1 << el.dom().size()) - 1 },
        }
    }

    /// The value of a variable declared without one: the least value of
    /// each number (0 when in range), the empty set.
    fn default_value(&self) -> Val {
        let num = |d: Dom| d.lo.max(0).min(d.hi);
        match self {
            Ty::Num(d) => num(*d),
            Ty::Tuple(ds) | Ty::Record(_, ds) => ds.iter().fold(0, |code, d| code * d.size() as Val + (num(*d) - d.lo)),
            Ty::Set(_) => 0,
        }
    }

    /// How an event parameter of this type is named.
    fn param(&self) -> Param {
        match self {
            Ty::Tuple(ds) | Ty::Record(_, ds) => Param::Tuple(ds.clone()),
            t => Param::Num(t.dom()),
        }
    }

    /// Whether values of the type are plain numbers.
    fn is_num(&self) -> bool {
        matches!(self, Ty::Num(_))
    }
}

/// Why a model cannot be checked natively.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unsupported {
    /// What is not supported, as a sentence.
    pub message: String,
    /// Where (file path and range), when known.
    pub location: Option<(String, TextRange)>,
}

/// A value given to a constant by an assertion (`with constant k of M set to v`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConstValue {
    /// The constant's name.
    pub name: String,
    /// The element it belongs to, as written.
    pub of: Vec<String>,
    /// The value.
    pub value: Val,
}

/// The bounded primitive types (RoboTool's `core_nat`, `core_int`,
/// `core_real`) before widening.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DomainDefaults {
    /// `core_nat`.
    pub nat: Dom,
    /// `core_int`.
    pub int: Dom,
    /// `core_real` (reals are integers).
    pub real: Dom,
    /// Greatest clock value (`core_clock_type`).
    pub clock_max: i32,
    /// Whether the user fixed `nat`, `int`, `real` (no widening then).
    pub fixed: [bool; 3],
    /// Every `nametype X = {a..b}` of the instantiations (for primitive
    /// types the model declares, such as `type ID`).
    pub types: Vec<(String, Dom)>,
    /// Constant values of the instantiations (`pkg_Machine_k = v`,
    /// `Machine_k = v`), used for constants given no other value.
    pub constants: Vec<(String, Val)>,
    /// Functions defined in CSPm by the instantiations, for the model's
    /// functions declared without a body.
    pub functions: Vec<CspFunction>,
    /// The buffer assumed for asynchronous connections between machines
    /// or controllers (none: RoboTool's, [`AsyncBuffer::ROBOTOOL`]).
    pub async_buffer: Option<AsyncBuffer>,
}

impl Default for DomainDefaults {
    fn default() -> Self {
        DomainDefaults {
            nat: Dom { lo: 0, hi: 2 },
            int: Dom { lo: -2, hi: 2 },
            real: Dom { lo: -2, hi: 2 },
            clock_max: 10,
            fixed: [false; 3],
            types: Vec::new(),
            constants: Vec::new(),
            functions: Vec::new(),
            async_buffer: None,
        }
    }
}

impl DomainDefaults {
    /// Applies `nametype core_X = {a..b}` instantiations.
    pub fn set(&mut self, name: &str, lo: Val, hi: Val) {
        let d = Dom { lo, hi };
        self.types.push((name.to_string(), d));
        match name.trim_start_matches("core_") {
            "nat" => (self.nat, self.fixed[0]) = (d, true),
            "int" => (self.int, self.fixed[1]) = (d, true),
            "real" => (self.real, self.fixed[2]) = (d, true),
            "clock_type" => self.clock_max = hi as i32,
            _ => {}
        }
    }
}

/// Compiles the RoboChart module, controller or machine `loc`.
pub fn lower_design(
    db: &dyn Db,
    ws: Workspace,
    loc: ItemLoc,
    consts: &[ConstValue],
    defaults: &DomainDefaults,
) -> Result<Design, Unsupported> {
    lower_element(db, ws, loc, None, consts, defaults)
}

/// Compiles the RoboChart module, controller or machine `loc`, or with
/// `inner`, the machine of that name declared inside the controller `loc`
/// (on its own: the controller's operations are call events, RT-19).
pub fn lower_element(
    db: &dyn Db,
    ws: Workspace,
    loc: ItemLoc,
    inner: Option<&str>,
    consts: &[ConstValue],
    defaults: &DomainDefaults,
) -> Result<Design, Unsupported> {
    let robosim = loc.file.kind(db) == robosim_hir::FileKind::RoboSim;
    let mut cx = Cx {
        db,
        ws,
        consts,
        defaults: defaults.clone(),
        design: None,
        files: Vec::new(),
        robosim,
        shared_vars: HashMap::new(),
        copies: BTreeMap::new(),
        platform_vars: BTreeSet::new(),
        machine_count: 0,
        lone: false,
        bidirectional: BTreeSet::new(),
    };
    cx.lower(loc, inner)
}

struct Cx<'a> {
    db: &'a dyn Db,
    ws: Workspace,
    consts: &'a [ConstValue],
    defaults: DomainDefaults,
    design: Option<Design>,
    files: Vec<File>,
    /// Whether the element is a RoboSim one (`$` references, `exec`).
    robosim: bool,
    /// Variables shared by the machines (required through interfaces).
    shared_vars: HashMap<String, (u16, Dom)>,
    /// RT-16: each machine's copy of a variable its controller provides
    /// (by variable: machine index and copy slot).
    copies: BTreeMap<String, Vec<(usize, u16)>>,
    /// Variables of the robotic platform (by name).
    platform_vars: BTreeSet<String>,
    /// How many machines the design has.
    machine_count: usize,
    /// Whether the design is one machine on its own (every event faces the
    /// environment).
    lone: bool,
    /// The platform's events connected both ways (`[ mult ]`).
    bidirectional: BTreeSet<String>,
}

/// One machine to compile: its declaration and where it sits.
struct Instance {
    /// Controller reference (or controller) name; "" for a lone machine.
    ctrl: String,
    /// Machine reference name.
    name: String,
    /// The machine's own declared name (for `constant … of`).
    decl_name: String,
    file: File,
    node: SyntaxNode,
    /// Operations its controller defines (or references): name, file, body.
    ops: Vec<(String, File, SyntaxNode)>,
}

/// A connection end: (node name, event name).
type End = (String, String);

/// An asynchronous connection: where it is declared, and its two ends.
type AsyncLink = (File, TextRange, End, End);

/// Where a machine's event leads: the channel's name, the direction from
/// the machine's side, and whether it is internal (to another machine).
struct Link {
    name: String,
    dir: Dir,
    internal: bool,
    /// Through an asynchronous connection (then internal).
    buffered: bool,
    /// Connected to nothing: hidden by the controller (RT-15; then internal).
    hidden: bool,
    /// How many machines receive it (internal synchronous links, RT-14).
    receivers: u8,
}

fn node_of(db: &dyn Db, loc: ItemLoc) -> Option<(File, SyntaxNode)> {
    let id = loc.def(db)?;
    let def = file_defs(db, loc.file).def(id);
    let root = parse(db, loc.file).syntax_node();
    let node = match root.covering_element(def.range) {
        robosim_syntax::SyntaxElement::Node(n) => n,
        robosim_syntax::SyntaxElement::Token(t) => t.parent()?,
    };
    node.ancestors().find(|n| n.kind() == def.syntax && n.text_range() == def.range).map(|n| (loc.file, n))
}

fn name_of(n: &SyntaxNode) -> String {
    n.children()
        .find(|c| c.kind() == NAME)
        .map(|c| c.text().to_string().trim_start_matches('^').to_string())
        .unwrap_or_default()
}

impl Cx<'_> {
    fn file_index(&mut self, f: File) -> u16 {
        if let Some(i) = self.files.iter().position(|&g| g == f) {
            return i as u16;
        }
        self.files.push(f);
        (self.files.len() - 1) as u16
    }

    fn unsupported(&self, file: File, range: TextRange, message: impl Into<String>) -> Unsupported {
        Unsupported { message: message.into(), location: Some((file.path(self.db).clone(), range)) }
    }

    fn resolve(&self, from: File, path: &[String], accept: fn(DefKind) -> bool) -> Option<(File, SyntaxNode)> {
        let loc = resolve_item(self.db, self.ws, from, path, accept).into_iter().next()?;
        node_of(self.db, loc)
    }

    /// Records the variables a robotic platform declares or provides.
    fn platform_variables(&mut self, file: File, platform: &SyntaxNode) {
        for n in self.with_interfaces(file, platform) {
            for v in n.children().filter(|c| c.kind() == VARIABLE_LIST).flat_map(|l| l.children()) {
                if v.kind() == VARIABLE {
                    self.platform_vars.insert(name_of(&v));
                }
            }
        }
    }

    /// The events a RoboSim machine's input context declares, itself or
    /// through the interfaces it uses.
    fn input_context_events(&self, file: File, machine: &SyntaxNode) -> Vec<String> {
        let contexts = machine.children().filter(|c| c.kind() == INPUT_CONTEXT);
        let sources = contexts.flat_map(|ctx| self.with_interfaces(file, &ctx));
        sources
            .flat_map(|n| n.children().filter(|c| c.kind() == EVENT).map(|e| name_of(&e)).collect::<Vec<_>>())
            .collect()
    }

    /// `node` and the interfaces it uses, provides or requires (those that
    /// resolve): where its declarations are.
    fn with_interfaces(&self, file: File, node: &SyntaxNode) -> Vec<SyntaxNode> {
        let mut sources = vec![node.clone()];
        for u in node.children().filter(|c| c.kind() == INTERFACE_USE) {
            sources.extend(self.resolve(file, &path_of(&u), |k| k == DefKind::Interface).map(|(_, n)| n));
        }
        sources
    }

    /// A connection with the platform marked `[ mult ]` carries its event
    /// both ways: `e.in` and `e.out` are channels of their own.
    fn note_bidirectional(&mut self, connection: &SyntaxNode, platform_event: &str) {
        if connection.children().any(|n| n.kind() == MULT_FLAG) {
            self.bidirectional.insert(platform_event.to_string());
        }
    }

    fn lower(&mut self, loc: ItemLoc, inner: Option<&str>) -> Result<Design, Unsupported> {
        let (file, node) = node_of(self.db, loc).ok_or_else(|| Unsupported {
            message: "the element to verify could not be found".into(),
            location: None,
        })?;
        if let Some(m) = inner {
            return self.inner_machine(file, &node, m);
        }
        let top_name = name_of(&node);
        let mut instances = Vec::new();
        // Links between connection ends, and which ends belong to the platform
        // (with the direction seen from the software).
        let mut links: Vec<(End, End)> = Vec::new();
        let mut platform: HashMap<End, Dir> = HashMap::new();
        let mut async_links: Vec<AsyncLink> = Vec::new();
        match node.kind() {
            MODULE => {
                let mut platform_names = BTreeSet::new();
                for c in node.children() {
                    match c.kind() {
                        ROBOTIC_PLATFORM => {
                            platform_names.insert(name_of(&c));
                            self.platform_variables(file, &c);
                        }
                        PLATFORM_REF => {
                            platform_names.insert(name_of(&c));
                            if let Some((pf, pn)) = self.resolve(file, &path_of(&c), |k| k == DefKind::Platform) {
                                self.platform_variables(pf, &pn);
                            }
                        }
                        CONTROLLER_REF => {
                            let target = path_of(&c);
                            let (cf, cn) =
                                self.resolve(file, &target, |k| k == DefKind::Controller).ok_or_else(|| {
                                    self.unsupported(
                                        file,
                                        c.text_range(),
                                        "the referenced controller could not be resolved",
                                    )
                                })?;
                            self.controller(&name_of(&c), cf, &cn, &mut instances, &mut links, &mut async_links)?;
                        }
                        CONTROLLER => {
                            let n = name_of(&c);
                            self.controller(&n, file, &c, &mut instances, &mut links, &mut async_links)?;
                        }
                        _ => {}
                    }
                }
                for c in node.children().filter(|c| c.kind() == CONNECTION) {
                    let (a, b, is_async) = ends(&c);
                    if platform_names.contains(&a.0) {
                        platform.insert(a.clone(), Dir::In);
                        self.note_bidirectional(&c, &a.1);
                    } else if platform_names.contains(&b.0) {
                        platform.insert(b.clone(), Dir::Out);
                        self.note_bidirectional(&c, &b.1);
                    } else if is_async {
                        async_links.push((file, c.text_range(), a.clone(), b.clone()));
                    }
                    links.push((a, b));
                }
            }
            CONTROLLER => {
                self.controller(&top_name, file, &node, &mut instances, &mut links, &mut async_links)?;
                // The controller's own events face the platform.
                for c in node.children().filter(|c| c.kind() == CONNECTION) {
                    let (a, b, _) = ends(&c);
                    if a.0 == top_name {
                        platform.insert((top_name.clone(), a.1.clone()), Dir::In);
                        self.note_bidirectional(&c, &a.1);
                    }
                    if b.0 == top_name {
                        platform.insert((top_name.clone(), b.1.clone()), Dir::Out);
                        self.note_bidirectional(&c, &b.1);
                    }
                }
                // Inside `controller`, its own name is the controller end.
                links =
                    links.into_iter().map(|(a, b)| (rename_ctrl(a, &top_name), rename_ctrl(b, &top_name))).collect();
                platform = platform.into_iter().map(|(e, d)| (rename_ctrl(e, &top_name), d)).collect();
            }
            STATE_MACHINE => {
                instances.push(Instance {
                    ctrl: String::new(),
                    name: top_name.clone(),
                    decl_name: top_name.clone(),
                    file,
                    node: node.clone(),
                    ops: Vec::new(),
                });
            }
            _ => {
                return Err(self.unsupported(
                    file,
                    node.text_range(),
                    "only RoboChart modules, controllers and state machines can be checked",
                ))
            }
        }
        if let Some((f, r, ..)) = async_links.first() {
            if self.robosim {
                return Err(self.unsupported(
                    *f,
                    *r,
                    "asynchronous connections between RoboSim controllers or machines are not supported yet",
                ));
            }
        }
        let async_ends: BTreeSet<End> = async_links.into_iter().flat_map(|(_, _, a, b)| [a, b]).collect();
        self.build(&top_name, node.kind(), instances, &links, &platform, &async_ends)
    }

    /// The machine `name` declared inside the controller `ctrl`, on its own
    /// (every event faces the environment). The controller's operations
    /// are undefined for it: calls of them are urgent visible call events
    /// (`opCall`), as for platform operations (RT-19).
    fn inner_machine(&mut self, file: File, ctrl: &SyntaxNode, name: &str) -> Result<Design, Unsupported> {
        let (mut instances, mut links, mut async_links) = (Vec::new(), Vec::new(), Vec::new());
        self.controller(&name_of(ctrl), file, ctrl, &mut instances, &mut links, &mut async_links)?;
        let mut inst = instances
            .into_iter()
            .find(|i| i.node.parent().as_ref() == Some(ctrl) && i.node.kind() == STATE_MACHINE && i.name == name)
            .ok_or_else(|| {
                self.unsupported(file, ctrl.text_range(), format!("the controller declares no state machine `{name}`"))
            })?;
        inst.ctrl = String::new();
        inst.ops.clear();
        self.build(name, STATE_MACHINE, vec![inst], &[], &HashMap::new(), &BTreeSet::new())
    }

    /// Collects the machines of a controller (referenced or inline) and its
    /// connections, with ends named `ctrl.machine` for machines and `ctrl`
    /// for the controller itself.
    fn controller(
        &mut self,
        cref: &str,
        file: File,
        node: &SyntaxNode,
        instances: &mut Vec<Instance>,
        links: &mut Vec<(End, End)>,
        async_links: &mut Vec<AsyncLink>,
    ) -> Result<(), Unsupported> {
        let ctrl_name = name_of(node);
        let mut machines = BTreeSet::new();
        let mut ops: Vec<(String, File, SyntaxNode)> = Vec::new();
        for c in node.children() {
            match c.kind() {
                STATE_MACHINE_REF => {
                    let target = path_of(&c);
                    let (mf, mn) = self.resolve(file, &target, |k| k == DefKind::StateMachine).ok_or_else(|| {
                        self.unsupported(file, c.text_range(), "the referenced state machine could not be resolved")
                    })?;
                    let decl_name = name_of(&mn);
                    machines.insert(name_of(&c));
                    instances.push(Instance {
                        ctrl: cref.to_string(),
                        name: name_of(&c),
                        decl_name,
                        file: mf,
                        node: mn,
                        ops: Vec::new(),
                    });
                }
                STATE_MACHINE => {
                    machines.insert(name_of(&c));
                    instances.push(Instance {
                        ctrl: cref.to_string(),
                        name: name_of(&c),
                        decl_name: name_of(&c),
                        file,
                        node: c.clone(),
                        ops: Vec::new(),
                    });
                }
                OPERATION_DEF => ops.push((name_of(&c), file, c.clone())),
                OPERATION_REF => {
                    let target = path_of(&c);
                    let (of, on) = self.resolve(file, &target, |k| k == DefKind::Operation).ok_or_else(|| {
                        self.unsupported(file, c.text_range(), "the referenced operation could not be resolved")
                    })?;
                    ops.push((name_of(&c), of, on));
                }
                _ => {}
            }
        }
        // The controller's operations serve every one of its machines.
        for inst in instances.iter_mut().filter(|i| i.ctrl == cref) {
            inst.ops = ops.clone();
        }
        for c in node.children().filter(|c| c.kind() == CONNECTION) {
            let (a, b, is_async) = ends(&c);
            let qualify = |e: End| -> End {
                if machines.contains(&e.0) {
                    (format!("{cref}.{}", e.0), e.1)
                } else if e.0 == ctrl_name {
                    (cref.to_string(), e.1)
                } else {
                    e
                }
            };
            let (a, b) = (qualify(a), qualify(b));
            if is_async && a.0.contains('.') && b.0.contains('.') {
                async_links.push((file, c.text_range(), a.clone(), b.clone()));
            }
            links.push((a, b));
        }
        Ok(())
    }

    fn build(
        &mut self,
        top_name: &str,
        top_kind: SyntaxKind,
        instances: Vec<Instance>,
        links: &[(End, End)],
        platform: &HashMap<End, Dir>,
        async_ends: &BTreeSet<End>,
    ) -> Result<Design, Unsupported> {
        // Literals of every machine widen the numeric domains (as RoboTool's
        // generator does), and so do the constants' values.
        let mut lits: Vec<Val> = Vec::new();
        for inst in &instances {
            for t in inst.node.descendants_with_tokens().filter_map(|e| e.into_token()) {
                if t.kind() == INT_NUMBER {
                    if let Ok(v) = t.text().parse::<Val>() {
                        lits.push(v);
                    }
                }
            }
        }
        lits.extend(self.consts.iter().map(|c| c.value));
        let widen = |d: Dom, fixed: bool, nat: bool| -> Dom {
            if fixed {
                return d;
            }
            let mut d = d;
            for &v in &lits {
                if nat && v < 0 {
                    continue;
                }
                d.lo = d.lo.min(v);
                d.hi = d.hi.max(v);
            }
            d
        };
        let f = self.defaults.fixed;
        self.defaults.nat = widen(self.defaults.nat, f[0], true);
        self.defaults.int = widen(self.defaults.int, f[1], false);
        self.defaults.real = widen(self.defaults.real, f[2], false);
        self.design = Some(Design {
            name: top_name.to_string(),
            machines: Vec::new(),
            channels: Vec::new(),
            vars: Vec::new(),
            clocks: Vec::new(),
            slots: 0,
            files: Vec::new(),
            domains: vec![
                ("core_nat".into(), self.defaults.nat),
                ("core_int".into(), self.defaults.int),
                ("core_real".into(), self.defaults.real),
            ],
            constants: Vec::new(),
            defaults: Vec::new(),
            forwards: Vec::new(),
        });
        // Union-find over connection ends: a machine event is external when
        // its class contains a platform end.
        let mut classes: Vec<BTreeSet<End>> = Vec::new();
        for (a, b) in links {
            let ia = classes.iter().position(|c| c.contains(a));
            let ib = classes.iter().position(|c| c.contains(b));
            match (ia, ib) {
                (Some(i), Some(j)) if i != j => {
                    let (lo, hi) = (i.min(j), i.max(j));
                    let moved = classes.remove(hi);
                    classes[lo].extend(moved);
                }
                (Some(_), Some(_)) => {}
                (Some(i), None) => {
                    classes[i].insert(b.clone());
                }
                (None, Some(j)) => {
                    classes[j].insert(a.clone());
                }
                (None, None) => classes.push([a.clone(), b.clone()].into_iter().collect()),
            }
        }
        // Which machine ends send (the `from` side of a connection) and
        // which receive.
        let mut sends: HashMap<&End, bool> = HashMap::new();
        for (a, b) in links {
            if a.0.contains('.') {
                sends.insert(a, true);
            }
            if b.0.contains('.') {
                sends.insert(b, false);
            }
        }
        // `receives`: whether the machine ever receives the event (for one
        // connected to nothing, which has no connection to say); none when
        // it never communicates on it.
        let robosim = self.robosim;
        let external = |machine_end: &End, receives: Option<bool>| -> Result<Option<Link>, String> {
            let Some(class) = classes.iter().find(|c| c.contains(machine_end)) else {
                // RT-15: an event connected to nothing is hidden by the
                // controller (a RoboSim machine's is refused where used);
                // one the machine never uses needs no channel.
                let Some(receives) = receives.filter(|_| !robosim) else {
                    return Ok(None);
                };
                let name = format!("{}.{}", machine_end.0, machine_end.1);
                let dir = if receives { Dir::In } else { Dir::Out };
                return Ok(Some(Link { name, dir, internal: true, buffered: false, hidden: true, receivers: 1 }));
            };
            let plat: Vec<(&End, &Dir)> = class.iter().filter_map(|e| platform.get(e).map(|d| (e, d))).collect();
            if let Some((e, d)) = plat.first() {
                return Ok(Some(Link {
                    name: e.1.clone(),
                    dir: **d,
                    internal: false,
                    buffered: false,
                    hidden: false,
                    receivers: 1,
                }));
            }
            // Between machines: a synchronous communication from the one
            // sender to every receiver at once (RT-14: a multi-way
            // synchronisation when there are several), hidden in the design.
            let ends: Vec<&End> = class.iter().filter(|e| e.0.contains('.')).collect();
            let senders: Vec<&&End> = ends.iter().filter(|e| sends.get(**e) == Some(&true)).collect();
            if ends.len() == 1 {
                return Err(format!(
                    "event `{}` reaches its controller's boundary, but the controller's event is connected to \
                     nothing in the module: not supported yet (whether RoboTool hides it is not pinned down)",
                    machine_end.1
                ));
            }
            if senders.len() != 1 {
                return Err(format!(
                    "event `{}` connects {} machine ends of which {} send; only one sender is supported",
                    machine_end.1,
                    ends.len(),
                    senders.len()
                ));
            }
            let dir = if sends.get(machine_end) == Some(&true) { Dir::Out } else { Dir::In };
            let name = format!("{}.{}", senders[0].0, senders[0].1);
            let buffered = class.iter().any(|e| async_ends.contains(e));
            let receivers = u8::try_from(ends.len() - 1)
                .map_err(|_| format!("event `{}` has too many receivers", machine_end.1))?;
            if buffered && receivers > 1 {
                return Err(format!(
                    "event `{}` is sent asynchronously to {receivers} receivers: not supported yet",
                    machine_end.1
                ));
            }
            Ok(Some(Link { name, dir, internal: true, buffered, hidden: false, receivers }))
        };
        let lone = top_kind == STATE_MACHINE;
        self.lone = lone;
        self.machine_count = instances.len();
        let mut slot: u16 = 0;
        for inst in &instances {
            let end: End = (format!("{}.{}", inst.ctrl, inst.name), String::new());
            // A machine on its own: every event faces the environment, as an
            // input if the machine ever receives it (a RoboSim machine: if
            // its input context declares it), else as an output.
            let mut received = received_events(&inst.node);
            if self.robosim {
                received.extend(self.input_context_events(inst.file, &inst.node));
            }
            let mut used = communicated_events(&inst.node);
            used.extend(inst.ops.iter().flat_map(|(_, _, body)| communicated_events(body)));
            let m = self.machine(inst, &mut slot, |ev: &str| {
                if lone {
                    let dir = if received.iter().any(|r| r == ev) { Dir::In } else { Dir::Out };
                    return Ok(Some(Link {
                        name: ev.to_string(),
                        dir,
                        internal: false,
                        buffered: false,
                        hidden: false,
                        receivers: 1,
                    }));
                }
                let mut e = end.clone();
                e.1 = ev.to_string();
                let uses = used.iter().any(|u| u == ev);
                external(&e, uses.then(|| received.iter().any(|r| r == ev)))
            })?;
            self.design.as_mut().expect("design").machines.push(m);
        }
        let mut design = self.design.take().expect("design");
        let mut shared: std::collections::HashSet<u16> = self.shared_vars.values().map(|&(s, _)| s).collect();
        self.forwards(&mut design, &mut slot, &mut shared)?;
        crate::eager::mark_eager_waits(&mut design, &shared);
        design.slots = slot;
        design.files = self.files.iter().map(|f| f.path(self.db).clone()).collect();
        Ok(design)
    }

    /// RT-16: the forwarding of each variable a controller provides to
    /// several machines: a slot of the machines still to update, and each
    /// machine's writes marked with it. Receiving into such a variable is
    /// refused (the write would be part of the communication).
    fn forwards(
        &mut self,
        design: &mut Design,
        slot: &mut u16,
        shared: &mut std::collections::HashSet<u16>,
    ) -> Result<(), Unsupported> {
        for (name, copies) in std::mem::take(&mut self.copies) {
            let Some(&(ctrl, _)) = self.shared_vars.get(&name) else { continue };
            let pending = *slot;
            *slot += 1;
            shared.extend(copies.iter().map(|&(_, c)| c));
            shared.insert(pending);
            let all = (1i32 << copies.len()) - 1;
            for (k, &(mi, copy)) in copies.iter().enumerate() {
                let m = &mut design.machines[mi];
                let binds = m.transitions.iter().filter_map(|t| match &t.trigger {
                    Some(Trigger::In { bind: Some((s, _)), .. }) if *s == copy => Some(t.range),
                    _ => None,
                });
                let stmts = m.code.iter().zip(&m.code_ranges).filter_map(|(i, r)| match i {
                    Instr::In { bind: Some((s, _)), .. } if *s == copy => Some(*r),
                    _ => None,
                });
                if let Some(r) = binds.chain(stmts).next() {
                    let file = self.files[m.file as usize];
                    return Err(self.unsupported(
                        file,
                        r,
                        format!(
                            "receiving into `{name}`, which the controller provides to several machines, is not \
                             supported yet"
                        ),
                    ));
                }
                for i in &mut m.code {
                    if let Instr::Assign { slot: s, forward, .. } = i {
                        if *s == copy {
                            *forward = Some((ctrl, pending, all & !(1 << k)));
                        }
                    }
                }
            }
            design.forwards.push(crate::ir::Forward {
                ctrl,
                pending,
                copies: copies.iter().map(|&(_, c)| c).collect(),
            });
        }
        Ok(())
    }

    /// Compiles one machine. `external(e)` says which platform channel (and
    /// direction) the machine's event `e` is connected to.
    fn machine(
        &mut self,
        inst: &Instance,
        slot: &mut u16,
        external: impl Fn(&str) -> Result<Option<Link>, String>,
    ) -> Result<Machine, Unsupported> {
        let file = inst.file;
        let file_ix = self.file_index(file);
        let base = *slot;
        *slot += Machine::SLOTS;
        let mut mc = MachineCx {
            cx: self,
            file,
            inst_prefix: if inst.ctrl.is_empty() { inst.name.clone() } else { format!("{}::{}", inst.ctrl, inst.name) },
            names: HashMap::new(),
            op_names: HashMap::new(),
            nodes: Vec::new(),
            node_syntax: Vec::new(),
            transitions: Vec::new(),
            code: Vec::new(),
            slot,
            decl_name: inst.decl_name.clone(),
            at: inst.node.text_range(),
            code_ranges: Vec::new(),
            code_files: Vec::new(),
            file_ix,
            clock_caps: HashMap::new(),
            binds: Vec::new(),
            else_transitions: Vec::new(),
            op_defs: inst.ops.clone(),
            ops: Vec::new(),
            op_of_def: HashMap::new(),
            pending_ops: Vec::new(),
            cur_op: None,
            types: HashMap::new(),
            sends: HashMap::new(),
            activities: Vec::new(),
            timers: Vec::new(),
            deadlines: Vec::new(),
        };
        mc.declarations(&inst.node, &external)?;
        mc.collect_nodes(&inst.node, None)?;
        mc.compile(&inst.node)?;
        let start_pc = mc.region_start(&inst.node, None)?;
        mc.operation_bodies(&external)?;
        let first_cycle_pc = mc.code.len() as u32;
        mc.emit(Instr::Exec(start_pc));
        let exec_transition_pc = mc.code.len() as u32;
        mc.emit(Instr::ExecTransition);
        let caps = std::mem::take(&mut mc.clock_caps);
        if !mc.activities.is_empty() {
            // An activity runs alongside the rest of the machine: every
            // variable write is a step of its own, so that each thread can
            // observe the other's writes in any order (as for variables
            // shared between machines).
            for i in &mut mc.code {
                if let Instr::Assign { shared, .. } = i {
                    *shared = true;
                }
            }
        }
        let m = Machine {
            name: mc.inst_prefix.clone(),
            nodes: mc.nodes,
            transitions: mc.transitions,
            code: mc.code,
            code_ranges: mc.code_ranges,
            code_files: mc.code_files,
            start_pc,
            first_cycle_pc,
            exec_transition_pc,
            ops: std::mem::take(&mut mc.ops),
            activities: std::mem::take(&mut mc.activities),
            timers: std::mem::take(&mut mc.timers),
            eager_waits: Vec::new(),
            base,
            file: file_ix,
        };
        // Clocks saturate one above the greatest value they are compared with.
        let clock_max = self.defaults.clock_max;
        let design = self.design.as_mut().expect("design");
        for c in design.clocks.iter_mut() {
            if let Some(&cap) = caps.get(&c.slot) {
                c.cap = if cap < 0 { clock_max + 1 } else { cap.min(clock_max) + 1 };
            }
        }
        Ok(m)
    }
}

fn rename_ctrl(e: End, top: &str) -> End {
    if e.0 == top {
        (top.to_string(), e.1)
    } else if !e.0.contains('.') && !e.0.is_empty() {
        (format!("{top}.{}", e.0), e.1)
    } else {
        e
    }
}

/// The events a machine receives: triggers, `e?x` and `e.v` statements.
fn received_events(machine: &SyntaxNode) -> Vec<String> {
    machine
        .descendants()
        .filter(|n| n.kind() == COMMUNICATION)
        .filter(|c| {
            c.parent().is_some_and(|p| p.kind() == TRIGGER)
                || c.children().any(|p| matches!(p.kind(), COMM_INPUT | COMM_SYNC))
        })
        .filter_map(|c| c.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)))
        .collect()
}

/// The events a machine (or an operation) communicates on, in any way.
fn communicated_events(node: &SyntaxNode) -> Vec<String> {
    node.descendants()
        .filter(|n| n.kind() == COMMUNICATION)
        .filter_map(|c| c.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)))
        .collect()
}

/// The events a machine sends a value on (`e!v`).
fn sent_events(machine: &SyntaxNode) -> Vec<String> {
    machine
        .descendants()
        .filter(|n| n.kind() == COMMUNICATION && n.children().any(|p| p.kind() == COMM_OUTPUT))
        .filter_map(|c| c.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)))
        .collect()
}

/// A connection's ends and whether it is asynchronous.
fn ends(c: &SyntaxNode) -> (End, End, bool) {
    let refs: Vec<String> = c.children().filter(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)).collect();
    let get = |i: usize| refs.get(i).cloned().unwrap_or_default();
    let is_async = c.children().any(|n| n.kind() == ASYNC_FLAG);
    ((get(0), get(1)), (get(2), get(3)), is_async)
}

/// What a simple name means inside a machine.
#[derive(Debug, Clone)]
enum Name {
    Var {
        slot: u16,
        dom: Dom,
        shared: bool,
        /// A platform variable: the channel of its updates (an assignment
        /// is an output on it).
        update: Option<u16>,
    },
    Const(Val),
    Clock(u16),
    Event {
        chan: Option<(u16, Dir)>,
        ty: Option<Dom>,
    },
    Op {
        params: Vec<Dom>,
        chan: u16,
    },
    /// An operation defined in the model: its index in the machine's
    /// operations.
    Defined(u16),
}

struct MachineCx<'a, 'b> {
    cx: &'a mut Cx<'b>,
    file: File,
    inst_prefix: String,
    names: HashMap<String, Name>,
    /// Operations, apart from `names`: an event and an operation may share
    /// a name, and the syntax says which is meant (a call or not).
    op_names: HashMap<String, Name>,
    nodes: Vec<Node>,
    node_syntax: Vec<SyntaxNode>,
    transitions: Vec<Transition>,
    code: Vec<Instr>,
    slot: &'a mut u16,
    decl_name: String,
    /// The source range of the code being emitted, and per instruction.
    at: TextRange,
    code_ranges: Vec<TextRange>,
    /// The file of the code being emitted (index into the design's
    /// files), and per instruction.
    file_ix: u16,
    code_files: Vec<u16>,
    /// `$e?x` bindings met while lowering a guard.
    binds: Vec<(u16, Dom, u16)>,
    /// Transitions with `condition else`, to complete.
    else_transitions: Vec<u16>,
    /// Operations the controller defines, and those compiled into the
    /// machine (by index into `op_defs`), with bodies still to compile.
    op_defs: Vec<(String, File, SyntaxNode)>,
    ops: Vec<Operation>,
    op_of_def: HashMap<usize, u16>,
    pending_ops: Vec<(u16, usize)>,
    /// The operation whose body is being compiled.
    cur_op: Option<u16>,
    /// Greatest static value each clock slot is compared with (-1: unknown).
    clock_caps: HashMap<u16, i32>,
    /// The types of the variables, constants and events in scope whose
    /// values are not plain numbers (tuples, sets).
    types: HashMap<String, Ty>,
    /// The events a lone machine, or one connected both ways to the
    /// platform, both receives and sends: the channel of their outputs.
    sends: HashMap<String, u16>,
    /// The during actions of composite states, and the deadline timers of
    /// states, so far.
    activities: Vec<Activity>,
    timers: Vec<u16>,
    /// The deadlines `<{d}` of the transitions compiled so far, by source.
    deadlines: Vec<(u16, Expr)>,
}

impl MachineCx<'_, '_> {
    /// The variable or constant named `n` (at `e`) as an expression.
    fn value_of(&self, e: &SyntaxNode, n: &str) -> Result<Expr, Unsupported> {
        match self.names.get(n) {
            Some(Name::Var { slot, .. }) => Ok(Expr::Slot(*slot)),
            Some(Name::Const(v)) => Ok(Expr::Const(*v)),
            _ => Err(self.err(e.text_range(), format!("`{n}` is not a variable or constant"))),
        }
    }

    fn err(&self, range: TextRange, msg: impl Into<String>) -> Unsupported {
        self.cx.unsupported(self.file, range, msg)
    }

    /// Records the type of `name`, which a declaration binds.
    fn bind_ty(&mut self, name: &str, ty: &Ty) {
        if ty.is_num() {
            self.types.remove(name);
        } else {
            self.types.insert(name.to_string(), ty.clone());
        }
    }

    fn emit(&mut self, i: Instr) {
        self.code.push(i);
        self.code_ranges.push(self.at);
        self.code_files.push(self.file_ix);
    }

    fn design(&mut self) -> &mut Design {
        self.cx.design.as_mut().expect("design")
    }

    fn new_slot(&mut self) -> u16 {
        let s = *self.slot;
        *self.slot += 1;
        s
    }

    /// A type whose values are plain numbers (parameters of operations).
    fn ty(&self, file: File, node: Option<&SyntaxNode>, at: TextRange) -> Result<Dom, Unsupported> {
        match self.ty_of(file, node, at)? {
            Ty::Num(d) => Ok(d),
            _ => Err(self.cx.unsupported(
                file,
                node.map_or(at, |n| n.text_range()),
                "product and set types are supported for variables, constants and events (not parameters) yet",
            )),
        }
    }

    /// A type: numbers, products of them, finite sets.
    fn ty_of(&self, file: File, node: Option<&SyntaxNode>, at: TextRange) -> Result<Ty, Unsupported> {
        let Some(node) = node else {
            return Err(self.err(at, "an untyped declaration cannot be checked"));
        };
        let range = node.text_range();
        match node.kind() {
            PRODUCT_TYPE => {
                let mut comps = Vec::new();
                for c in node.children().filter(|c| ast::is_type_kind(c.kind())) {
                    match self.ty_of(file, Some(&c), at)? {
                        Ty::Num(d) => comps.push(d),
                        _ => {
                            return Err(self.cx.unsupported(
                                file,
                                c.text_range(),
                                "tuples whose components are tuples or sets are not supported yet",
                            ))
                        }
                    }
                }
                self.small_product(file, node, &comps)?;
                return Ok(Ty::Tuple(comps));
            }
            SET_TYPE => {
                let inner = node.children().find(|c| ast::is_type_kind(c.kind()));
                let el = self.ty_of(file, inner.as_ref(), range)?;
                let n = el.dom().size();
                if matches!(el, Ty::Set(_)) || n > MAX_SET_ELEMENTS {
                    return Err(self.cx.unsupported(
                        file,
                        range,
                        format!(
                            "the set type `{}` is not supported: sets are checked over types with at most {MAX_SET_ELEMENTS} values, and its elements have {n}",
                            node.text()
                        ),
                    ));
                }
                return Ok(Ty::Set(Box::new(el)));
            }
            _ => {}
        }
        let path = if node.kind() == NAMED_TYPE { path_of(node) } else { Vec::new() };
        let last = path.last().map(String::as_str).unwrap_or("");
        let d = &self.cx.defaults;
        match last {
            "boolean" => return Ok(Ty::Num(Dom::BOOL)),
            "nat" => return Ok(Ty::Num(d.nat)),
            "int" => return Ok(Ty::Num(d.int)),
            "real" => return Ok(Ty::Num(d.real)),
            _ => {}
        }
        if !path.is_empty() {
            // A primitive type the model declares (`type ID`) takes the range
            // an instantiation gives it (`nametype ID = {0..1}`).
            if self.cx.resolve(file, &path, |k| k == DefKind::PrimitiveType).is_some() {
                let name = last.to_string();
                let core = format!("core_{name}");
                return match d.types.iter().rev().find(|(n, _)| *n == name || *n == core) {
                    Some((_, dom)) => Ok(Ty::Num(*dom)),
                    None => Err(self.cx.unsupported(
                        file,
                        node.text_range(),
                        format!("the type `{name}` has no range: give it one with `nametype {name} = {{a..b}}` in a `csp` block of an assertion file"),
                    )),
                };
            }
            if let Some((_, en)) = self.cx.resolve(file, &path, |k| k == DefKind::Enumeration) {
                let n = en.children().filter(|c| c.kind() == ENUM_LITERAL).count() as Val;
                return Ok(Ty::Num(Dom { lo: 0, hi: (n - 1).max(0) }));
            }
            if let Some((rf, rec)) = self.cx.resolve(file, &path, |k| k == DefKind::Record) {
                let (mut names, mut doms) = (Vec::new(), Vec::new());
                for f in rec.children().filter(|c| c.kind() == FIELD) {
                    let t = f.children().find(|t| ast::is_type_kind(t.kind()));
                    match self.ty_of(rf, t.as_ref(), f.text_range())? {
                        Ty::Num(d) => doms.push(d),
                        _ => {
                            return Err(self.cx.unsupported(
                                rf,
                                f.text_range(),
                                "records whose fields are records, tuples or sets are not supported yet",
                            ))
                        }
                    }
                    names.push(name_of(&f));
                }
                self.small_product(file, node, &doms)?;
                return Ok(Ty::Record(names, doms));
            }
        }
        Err(self.cx.unsupported(
            file,
            node.text_range(),
            format!(
                "the type `{}` is not supported by the native checker (booleans, numbers, enumerations, their products and small finite sets are)",
                node.text()
            ),
        ))
    }

    /// A product type (tuple or record) `node` of components `doms` is
    /// small enough to be one slot.
    fn small_product(&self, file: File, node: &SyntaxNode, doms: &[Dom]) -> Result<(), Unsupported> {
        let n = tuple_size(doms);
        if n > MAX_TUPLES {
            return Err(self.cx.unsupported(
                file,
                node.text_range(),
                format!("the type `{}` has {n} values: too many to check natively", node.text()),
            ));
        }
        Ok(())
    }

    /// How event values of the type `node` are named when they are not
    /// numbers: booleans, and enumerations (RoboTool's CSPm constructors
    /// `Enum_Literal`).
    fn param_of(&self, file: File, node: Option<&SyntaxNode>) -> Option<Param> {
        let node = node.filter(|n| n.kind() == NAMED_TYPE)?;
        let path = path_of(node);
        if path.last().is_some_and(|l| l == "boolean") {
            return Some(Param::Bool);
        }
        let (_, en) = self.cx.resolve(file, &path, |k| k == DefKind::Enumeration)?;
        let ty = name_of(&en);
        Some(Param::Named(
            en.children().filter(|c| c.kind() == ENUM_LITERAL).map(|l| format!("{ty}_{}", name_of(&l))).collect(),
        ))
    }

    /// The default of the type `node` (`ty` lowered): RoboTool's, true for
    /// booleans (RT-1, RT-4), otherwise the least value of each number
    /// (0 when in range), the first literal, the empty set.
    fn default_of(&self, file: File, node: Option<&SyntaxNode>, ty: &Ty) -> Val {
        match self.param_of(file, node) {
            Some(Param::Bool) => 1,
            _ => ty.default_value(),
        }
    }

    /// The initial value of a variable declared without one (RT-4): the
    /// type's default; a boolean's `true` is recorded as a default the
    /// verdict rests on, since a modeller may expect `false`.
    fn uninitialised(&mut self, q: &str, file: File, node: Option<&SyntaxNode>, ty: &Ty) -> Val {
        let v = self.default_of(file, node, ty);
        if matches!(self.param_of(file, node), Some(Param::Bool)) {
            self.design().defaults.push(format!("variable {q} starts true (RT-4)"));
        }
        v
    }

    /// A value of the type `node` as the modeller writes it.
    fn value_text(&self, file: File, node: Option<&SyntaxNode>, v: Val) -> String {
        match self.param_of(file, node) {
            Some(Param::Bool) => (v != 0).to_string(),
            Some(Param::Named(names)) => names.get(v as usize).cloned().unwrap_or_else(|| v.to_string()),
            _ => v.to_string(),
        }
    }

    /// The value an assertion gives the constant `name`, else the one an
    /// instantiation block gives it (RoboTool's `pkg_Machine_name` or
    /// `Machine_name`).
    fn const_value(&self, name: &str) -> Option<Val> {
        let given = self
            .cx
            .consts
            .iter()
            .find(|c| c.name == name && c.of.last().is_some_and(|o| *o == self.decl_name))
            .map(|c| c.value);
        given.or_else(|| {
            let package = robosim_hir::index::file_summary(self.cx.db, self.file).package.join("_");
            let short = format!("{}_{name}", self.decl_name);
            let long = format!("{package}_{short}");
            let candidates = [long, short, format!("const_{}_{name}", self.decl_name)];
            self.cx.defaults.constants.iter().find(|(n, _)| candidates.contains(n)).map(|(_, v)| *v)
        })
    }

    /// Variables, constants, clocks, events and operations of the machine
    /// and of the interfaces it uses, provides or requires.
    fn declarations(
        &mut self,
        node: &SyntaxNode,
        external: &impl Fn(&str) -> Result<Option<Link>, String>,
    ) -> Result<(), Unsupported> {
        let file = self.file;
        // Each source of declarations: its file, its node, whether it is an
        // interface, and the I/O context it comes through (RoboSim).
        let mut sources: Vec<(File, SyntaxNode, bool, Option<Dir>)> = vec![(file, node.clone(), false, None)];
        // RoboSim declares its inputs and outputs in I/O contexts.
        let contexts: Vec<(SyntaxNode, Option<Dir>)> = node
            .children()
            .filter_map(|c| match c.kind() {
                INPUT_CONTEXT => Some((c, Some(Dir::In))),
                OUTPUT_CONTEXT => Some((c, Some(Dir::Out))),
                _ => None,
            })
            .collect();
        sources.extend(contexts.iter().map(|(c, d)| (file, c.clone(), false, *d)));
        let uses: Vec<(SyntaxNode, Option<Dir>)> = std::iter::once((node.clone(), None))
            .chain(contexts)
            .flat_map(|(n, d)| n.children().filter(|c| c.kind() == INTERFACE_USE).map(move |u| (u, d)))
            .collect();
        for (u, context) in uses {
            let path = path_of(&u);
            let (f, n) = self
                .cx
                .resolve(file, &path, |k| k == DefKind::Interface)
                .ok_or_else(|| self.err(u.text_range(), "the interface could not be resolved"))?;
            sources.push((f, n, true, context));
        }
        for (f, n, from_interface, context) in sources {
            for c in n.children() {
                match c.kind() {
                    VARIABLE_LIST => {
                        let is_const = c.children_with_tokens().any(|t| t.kind() == CONST_KW);
                        for v in c.children().filter(|v| v.kind() == VARIABLE) {
                            let name = name_of(&v);
                            let tnode = v.children().find(|t| ast::is_type_kind(t.kind()));
                            let ty = self.ty_of(f, tnode.as_ref(), v.text_range())?;
                            let dom = ty.dom();
                            let init = v.children().find(|e| ast::is_expr_kind(e.kind()));
                            self.bind_ty(&name, &ty);
                            if is_const {
                                let q = format!("{}::{name}", self.inst_prefix);
                                let value = match self.const_value(&name) {
                                    Some(v) => v,
                                    None => match init
                                        .as_ref()
                                        .map(|e| self.typed(e, &ty))
                                        .transpose()?
                                        .and_then(|e| e.constant())
                                    {
                                        Some(v) => v,
                                        None => {
                                            // RT-1: RoboTool writes the type's default.
                                            let v = self.default_of(f, tnode.as_ref(), &ty);
                                            let shown = self.value_text(f, tnode.as_ref(), v);
                                            self.design().defaults.push(format!("constant {q} = {shown} (RT-1)"));
                                            v
                                        }
                                    },
                                };
                                self.design().constants.push((q, value));
                                self.names.insert(name, Name::Const(value));
                            } else {
                                if from_interface {
                                    // A variable the machine requires: shared
                                    // by every machine of the design.
                                    let shape = self.param_of(f, tnode.as_ref()).unwrap_or_else(|| ty.param());
                                    self.shared_variable(&c, &name, (&ty, shape), init.as_ref(), context)?;
                                    continue;
                                }
                                let slot = self.new_slot();
                                let q = format!("{}::{name}", self.inst_prefix);
                                let initv = match init.as_ref() {
                                    Some(e) => self.typed(e, &ty)?.constant().ok_or_else(|| {
                                        self.err(e.text_range(), "initial values must be constant expressions")
                                    })?,
                                    None => self.uninitialised(&q, f, tnode.as_ref(), &ty),
                                };
                                self.design().vars.push(Var { name: q, slot, dom, init: initv });
                                self.names.insert(name, Name::Var { slot, dom, shared: false, update: None });
                            }
                        }
                    }
                    CLOCK => {
                        let name = name_of(&c);
                        let slot = self.new_slot();
                        let q = format!("{}::{name}", self.inst_prefix);
                        self.design().clocks.push(Clock { name: q, slot, cap: 0 });
                        self.clock_caps.insert(slot, 0);
                        self.names.insert(name, Name::Clock(slot));
                    }
                    EVENT => {
                        let name = name_of(&c);
                        let tnode = c.children().find(|t| ast::is_type_kind(t.kind()));
                        let full = match &tnode {
                            Some(t) => Some(self.ty_of(f, Some(t), c.text_range())?),
                            None => None,
                        };
                        if let Some(Ty::Set(_)) = &full {
                            return Err(self.err(
                                c.text_range(),
                                format!("events carrying sets (`{name}`) are not supported by the native checker yet"),
                            ));
                        }
                        let ty = full.as_ref().map(Ty::dom);
                        let shape: Vec<Param> = full
                            .iter()
                            .map(|t| self.param_of(f, tnode.as_ref()).unwrap_or_else(|| t.param()))
                            .collect();
                        if let Some(t) = &full {
                            self.bind_ty(&name, t);
                        }
                        let chan = match external(&name) {
                            Ok(Some(link)) => {
                                let both_ways = self.cx.lone || self.cx.bidirectional.contains(&link.name);
                                if both_ways && link.dir == Dir::In && sent_events(node).contains(&name) {
                                    // A machine on its own, or connected both
                                    // ways, that also sends the event it
                                    // receives: `e.out` is a channel of its own.
                                    let out = self.channel(&link.name, Dir::Out, false, shape.clone());
                                    self.sends.insert(name.clone(), out);
                                }
                                let chan = self.channel(&link.name, link.dir, false, shape);
                                if link.internal && self.cx.robosim {
                                    return Err(self.err(
                                        c.text_range(),
                                        format!(
                                            "`{name}` connects two RoboSim machines or controllers: not supported yet \
                                             (the paper keeps such events in the module's memory, Rule 8, and in \
                                             which cycle the receiver reads what the sender wrote is not pinned \
                                             down)"
                                        ),
                                    ));
                                }
                                if link.internal {
                                    // Both ends share the channel: its buffer is made once.
                                    // RT-12: RoboTool's buffer unless the user assumes another.
                                    let policy = self.cx.defaults.async_buffer.unwrap_or(AsyncBuffer::ROBOTOOL);
                                    let policy = Some(policy).filter(|_| link.buffered);
                                    if let Some(policy) =
                                        policy.filter(|_| self.design().channels[chan as usize].buffer.is_none())
                                    {
                                        let slot = self.new_slot();
                                        for _ in 0..policy.size {
                                            self.new_slot();
                                        }
                                        self.design().channels[chan as usize].buffer = Some(Buffer { slot, policy });
                                    }
                                    let c = &mut self.design().channels[chan as usize];
                                    c.internal = true;
                                    c.register = None;
                                    c.alone = link.hidden;
                                    c.receivers = link.receivers;
                                }
                                Some((chan, link.dir))
                            }
                            Ok(None) => None,
                            Err(msg) => return Err(self.err(c.text_range(), msg)),
                        };
                        self.names.insert(name, Name::Event { chan, ty });
                    }
                    OPERATION_SIG => {
                        let name = name_of(&c);
                        let (mut params, mut shape) = (Vec::new(), Vec::new());
                        if let Some(pl) = c.children().find(|p| p.kind() == PARAM_LIST) {
                            for p in pl.children().filter(|p| p.kind() == PARAM) {
                                let tnode = p.children().find(|t| ast::is_type_kind(t.kind()));
                                let d = self.ty(f, tnode.as_ref(), p.text_range())?;
                                params.push(d);
                                shape.push(self.param_of(f, tnode.as_ref()).unwrap_or(Param::Num(d)));
                            }
                        }
                        // The controller may define it: then it is no platform call.
                        if let Some(i) = self.op_defs.iter().position(|(n, ..)| *n == name) {
                            let k = self.operation(i, &params)?;
                            self.op_names.insert(name, Name::Defined(k));
                            continue;
                        }
                        let chan = self.channel(&name, Dir::Out, true, shape);
                        self.op_names.insert(name, Name::Op { params, chan });
                    }
                    OPERATION_DEF | OPERATION_REF | FUNCTION => return Err(self.err(
                        c.text_range(),
                        "operations defined in machines, and functions, are not supported by the native checker yet",
                    )),
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// The slot of the shared variable `name` (one per design), made on
    /// first use. A variable of the robotic platform is also an output of
    /// the design (paper §5.2: "platform variables are outputs"): in
    /// RoboChart, every update is an event `set_x.v`; in RoboSim, a variable
    /// of the output context is written to its register (`registerWrite`),
    /// and one of the input context is read from its register at the start
    /// of each cycle (`registerRead.i_x.v`). `context` is the RoboSim I/O
    /// context the variable comes through.
    fn shared_variable(
        &mut self,
        decl: &SyntaxNode,
        name: &str,
        (ty, shape): (&Ty, Param),
        init: Option<&SyntaxNode>,
        context: Option<Dir>,
    ) -> Result<(), Unsupported> {
        let dom = ty.dom();
        if self.cx.robosim && context.is_none() {
            return Err(self.err(
                decl.text_range(),
                format!(
                    "`{name}` is required by the machine itself: a RoboSim machine's variables of the platform are \
                     inputs or outputs, required in its input or output context (RS:SM4)"
                ),
            ));
        }
        let platform = self.cx.robosim || self.cx.platform_vars.contains(name);
        if platform && !ty.is_num() && !matches!(ty, Ty::Tuple(_) | Ty::Record(..)) {
            return Err(self.err(
                decl.text_range(),
                format!(
                    "variables of the platform carrying sets (`{name}`) are not supported by the native checker yet"
                ),
            ));
        }
        let slot = match self.cx.shared_vars.get(name) {
            Some(&(slot, d)) if d == dom => slot,
            Some(_) => {
                return Err(self.err(decl.text_range(), format!("`{name}` is required with two different types")))
            }
            None => {
                let slot = self.new_slot();
                let value = match init {
                    Some(e) => self
                        .typed(e, ty)?
                        .constant()
                        .ok_or_else(|| self.err(e.text_range(), "initial values must be constant expressions"))?,
                    // RT-4: booleans, platform memories too, start true.
                    None if shape == Param::Bool => {
                        self.design().defaults.push(format!("variable {name} starts true (RT-4)"));
                        1
                    }
                    None => ty.default_value(),
                };
                self.design().vars.push(Var { name: name.to_string(), slot, dom, init: value });
                self.cx.shared_vars.insert(name.to_string(), (slot, dom));
                slot
            }
        };
        let shared = self.cx.machine_count > 1;
        // RT-16: with several machines, each reads its own copy of a
        // variable its controller provides (see `Cx::forwards`).
        let slot = if shared && !platform {
            let machine = self.design().machines.len();
            let copies = self.cx.copies.entry(name.to_string()).or_default();
            match copies.iter().find(|(m, _)| *m == machine) {
                Some(&(_, copy)) => copy,
                None => {
                    let copy = self.new_slot();
                    self.cx.copies.get_mut(name).expect("made above").push((machine, copy));
                    let init = self.design().vars.iter().find(|v| v.slot == slot).map_or(0, |v| v.init);
                    let var = format!("{name} ({}'s copy)", self.inst_prefix);
                    self.design().vars.push(Var { name: var, slot: copy, dom, init });
                    copy
                }
            }
        } else {
            slot
        };
        let update = match (platform, context) {
            (false, _) => None,
            // A RoboSim input: the register is the variable, set by each
            // cycle's read.
            (true, Some(Dir::In)) => {
                self.var_channel(name, Dir::In, shape, slot);
                // An input and output keeps the output channel met before.
                match self.names.get(name) {
                    Some(Name::Var { update, .. }) => *update,
                    _ => None,
                }
            }
            (true, _) => Some(self.var_channel(name, Dir::Out, shape, slot)),
        };
        self.names.insert(name.to_string(), Name::Var { slot, dom, shared, update });
        Ok(())
    }

    /// The channel of the platform variable `name` kept in `slot`, in
    /// direction `dir` (made on first use).
    fn var_channel(&mut self, name: &str, dir: Dir, shape: Param, slot: u16) -> u16 {
        let d = self.design();
        if let Some(i) = d.channels.iter().position(|c| c.var && c.name == name && c.dir == dir) {
            return i as u16;
        }
        let mut c = Channel::new(name, dir, false, vec![shape]);
        c.register = (dir == Dir::In).then_some(slot);
        c.var = true;
        d.channels.push(c);
        (d.channels.len() - 1) as u16
    }

    /// The channel `name` (made on first use); `shape` names its parameters.
    fn channel(&mut self, name: &str, dir: Dir, is_call: bool, shape: Vec<Param>) -> u16 {
        // A lone machine's `e.in` and `e.out` are two channels, and so are
        // those of a platform event connected both ways; otherwise the two
        // ends of a connection between machines share one.
        let by_dir = self.cx.lone || self.cx.bidirectional.contains(name);
        if let Some(i) = self
            .design()
            .channels
            .iter()
            .position(|c| !c.var && c.name == name && c.is_call == is_call && (!by_dir || c.dir == dir))
        {
            return i as u16;
        }
        // A RoboSim input is read into a register: presence, then value.
        let register = (self.cx.robosim && dir == Dir::In).then(|| {
            let s = self.new_slot();
            self.new_slot();
            s
        });
        let d = self.design();
        let mut c = Channel::new(name, dir, is_call, shape);
        c.register = register;
        d.channels.push(c);
        (d.channels.len() - 1) as u16
    }

    /// Nodes of a region (the machine's or a state's), recursively.
    fn collect_nodes(&mut self, region: &SyntaxNode, parent: Option<u16>) -> Result<(), Unsupported> {
        for c in region.children() {
            let kind = match c.kind() {
                STATE => NodeKind::State,
                JUNCTION => NodeKind::Junction,
                INITIAL => NodeKind::Initial,
                FINAL => NodeKind::Final,
                PROBABILISTIC_JUNCTION => {
                    return Err(self.err(
                        c.text_range(),
                        "probabilistic junctions have no meaning in the tock-CSP semantics and cannot be verified",
                    ))
                }
                _ => continue,
            };
            let id = self.nodes.len() as u16;
            let range = c.children().find(|n| n.kind() == NAME).map(|n| n.text_range()).unwrap_or(c.text_range());
            self.nodes.push(Node {
                name: name_of(&c),
                op: self.cur_op,
                kind,
                parent,
                entry_pc: 0,
                exit_pc: 0,
                since_entry: None,
                during: None,
                timer: None,
                activity: None,
                out: Vec::new(),
                range,
            });
            self.node_syntax.push(c.clone());
            if kind == NodeKind::State {
                self.collect_nodes(&c, Some(id))?;
            }
        }
        Ok(())
    }

    /// The node named `name` in the region of `parent`.
    fn sibling(&self, parent: Option<u16>, name: &str) -> Option<u16> {
        self.nodes.iter().position(|n| n.op == self.cur_op && n.parent == parent && n.name == name).map(|i| i as u16)
    }

    fn compile(&mut self, machine: &SyntaxNode) -> Result<(), Unsupported> {
        // Transitions of every region.
        let mut regions = vec![(machine.clone(), None)];
        for (i, n) in self.nodes.iter().enumerate() {
            if n.kind == NodeKind::State && n.op == self.cur_op {
                regions.push((self.node_syntax[i].clone(), Some(i as u16)));
            }
        }
        for (region, parent) in regions {
            for t in region.children().filter(|c| c.kind() == TRANSITION) {
                self.transition(&t, parent)?;
            }
        }
        // `condition else`: enabled when no other transition of the same
        // source is.
        for t in std::mem::take(&mut self.else_transitions) {
            let source = self.transitions[t as usize].source;
            let others: Vec<Expr> = self
                .transitions
                .iter()
                .enumerate()
                .filter(|(i, o)| *i != t as usize && o.source == source)
                .map(|(_, o)| o.guard.clone().unwrap_or(Expr::Const(1)))
                .collect();
            let any = others.into_iter().reduce(|a, b| Expr::Log(LogOp::Or, Box::new(a), Box::new(b)));
            self.transitions[t as usize].guard = Some(match any {
                Some(e) => Expr::Not(Box::new(e)),
                None => Expr::Const(1),
            });
        }
        // Entry and exit code of every node.
        for id in 0..self.nodes.len() {
            if self.nodes[id].op != self.cur_op {
                continue;
            }
            let syn = self.node_syntax[id].clone();
            let node_id = id as u16;
            self.at = self.nodes[id].range;
            match self.nodes[id].kind {
                NodeKind::State => {
                    let entry_pc = self.code.len() as u32;
                    if let Some(a) = syn.children().find(|a| a.kind() == ENTRY_ACTION) {
                        self.action_stmt(&a)?;
                    }
                    self.at = self.nodes[id].range;
                    self.start_parent_activity(id);
                    let has_children = self.nodes.iter().any(|n| n.parent == Some(node_id));
                    // The state's activity starts when its entry action ends
                    // (the exporter's `activate__`): the deadline timer of
                    // its transitions. A composite state's during action is
                    // compiled here and started by its substates (RT-17).
                    let limits: Vec<Expr> =
                        self.deadlines.iter().filter(|(s, _)| *s == node_id).map(|(_, e)| e.clone()).collect();
                    if !limits.is_empty() {
                        let slot = *self.slot;
                        *self.slot += 1;
                        self.nodes[id].timer = Some(slot);
                        self.timers.push(slot);
                        self.emit(Instr::StartTimer { slot, limits });
                    }
                    let during = syn.children().find(|a| a.kind() == DURING_ACTION);
                    if let (Some(a), true) = (&during, has_children) {
                        self.activity(node_id, a)?;
                        self.at = self.nodes[id].range;
                    }
                    // A simple state's during action runs after the entry
                    // action; any transition of the state may interrupt it.
                    if let (Some(a), false) = (during, has_children) {
                        let start = self.code.len() as u32;
                        self.action_stmt(&a)?;
                        self.nodes[id].during = Some((start, self.code.len() as u32));
                        self.at = self.nodes[id].range;
                    }
                    if has_children {
                        let pc = self.code.len() as u32;
                        self.emit(Instr::Jump(u32::MAX));
                        let start = self.region_start(&syn, Some(node_id))?;
                        self.code[pc as usize] = Instr::Jump(start);
                    } else {
                        self.emit(Instr::Rest);
                    }
                    let exit_pc = self.code.len() as u32;
                    if let Some(a) = syn.children().find(|a| a.kind() == EXIT_ACTION) {
                        self.action_stmt(&a)?;
                    }
                    self.at = self.nodes[id].range;
                    self.emit(Instr::ExitDone(node_id));
                    self.nodes[id].entry_pc = entry_pc;
                    self.nodes[id].exit_pc = exit_pc;
                }
                NodeKind::Junction => {
                    self.nodes[id].entry_pc = self.code.len() as u32;
                    self.emit(Instr::Junction(node_id));
                    self.nodes[id].exit_pc = self.code.len() as u32;
                    self.emit(Instr::ExitDone(node_id));
                }
                NodeKind::Final => {
                    self.nodes[id].entry_pc = self.code.len() as u32;
                    self.start_parent_activity(id);
                    // A final state ends the machine, or returns from an
                    // operation's body; in a composite state it just rests.
                    self.emit(match (self.nodes[id].parent, self.cur_op) {
                        (Some(_), _) => Instr::Rest,
                        (None, Some(op)) => Instr::Return(op),
                        (None, None) => Instr::Terminate,
                    });
                    self.nodes[id].exit_pc = self.code.len() as u32;
                    self.emit(Instr::ExitDone(node_id));
                }
                NodeKind::Initial => {
                    self.nodes[id].exit_pc = self.code.len() as u32;
                    self.emit(Instr::ExitDone(node_id));
                }
            }
        }
        Ok(())
    }

    /// RT-17: a composite state's during action starts once the substate
    /// first entered has finished its entry action (the generated
    /// `During` waits for a substate's `entered`), and only then: a
    /// substate entered later finds it running (or done) and leaves it.
    /// Parents come before their substates in `nodes`, so the parent's
    /// activity is known here.
    fn start_parent_activity(&mut self, id: usize) {
        if let Some(k) = self.nodes[id].parent.and_then(|p| self.nodes[p as usize].activity) {
            self.emit(Instr::StartActivity(k));
        }
    }

    /// A composite state's during action: an activity of the machine,
    /// started by its substates' entry code (see
    /// [`MachineCx::start_parent_activity`]), its code out of line.
    fn activity(&mut self, state: u16, during: &SyntaxNode) -> Result<(), Unsupported> {
        if self.cx.robosim {
            return Err(self.err(
                during.text_range(),
                "during actions of composite RoboSim states are not supported: how they share the cycle \
                 with the substates (`exec`) is not pinned down",
            ));
        }
        let k = self.activities.len() as u16;
        let slots = *self.slot;
        *self.slot += 3;
        let jump = self.code.len();
        self.emit(Instr::Jump(u32::MAX));
        let start_pc = self.code.len() as u32;
        self.action_stmt(during)?;
        self.at = during.text_range();
        self.emit(Instr::ActivityEnd);
        let end = self.code.len();
        self.code[jump] = Instr::Jump(end as u32);
        if let Some(i) = (start_pc as usize..end).find(|&i| matches!(self.code[i], Instr::CallOp { .. })) {
            return Err(self.err(
                self.code_ranges[i],
                "calls of operations defined in the model from the during action of a composite state \
                 are not supported by the native checker yet",
            ));
        }
        self.activities.push(Activity {
            state,
            start_pc,
            pc_slot: slots,
            wait_slot: slots + 1,
            deadline_slot: slots + 2,
        });
        self.nodes[state as usize].activity = Some(k);
        Ok(())
    }

    /// Code for the initial transition of a region; returns its pc.
    fn region_start(&mut self, region: &SyntaxNode, parent: Option<u16>) -> Result<u32, Unsupported> {
        let init = self
            .nodes
            .iter()
            .position(|n| n.op == self.cur_op && n.parent == parent && n.kind == NodeKind::Initial)
            .ok_or_else(|| self.err(region.text_range(), "a region without an initial junction cannot be executed"))?;
        let t = self.nodes[init]
            .out
            .first()
            .copied()
            .ok_or_else(|| self.err(self.nodes[init].range, "the initial junction has no transition"))?;
        Ok(self.transitions[t as usize].body_pc)
    }

    fn transition(&mut self, t: &SyntaxNode, parent: Option<u16>) -> Result<(), Unsupported> {
        let name = name_of(t);
        let end = |kind: SyntaxKind| {
            t.children()
                .find(|c| c.kind() == kind)
                .and_then(|c| c.children().find(|n| n.kind() == NAME_REF))
                .map(|n| ident_text(&n))
        };
        let (Some(src), Some(dst)) = (end(TRANSITION_SOURCE), end(TRANSITION_TARGET)) else {
            return Err(self.err(t.text_range(), format!("transition `{name}` lacks a source or a target")));
        };
        let source = self
            .sibling(parent, &src)
            .ok_or_else(|| self.err(t.text_range(), format!("`{src}` is not a node of this region")))?;
        let target = self
            .sibling(parent, &dst)
            .ok_or_else(|| self.err(t.text_range(), format!("`{dst}` is not a node of this region")))?;
        let mut trigger = None;
        let mut guard = None;
        let mut exec = false;
        let mut is_else = false;
        self.binds.clear();
        let body_pc = self.code.len() as u32;
        let name_range = t.children().find(|n| n.kind() == NAME).map(|n| n.text_range()).unwrap_or(t.text_range());
        self.at = name_range;
        for c in t.children() {
            match c.kind() {
                TRIGGER => {
                    if let Some(comm) = c.children().find(|n| n.kind() == COMMUNICATION) {
                        trigger = Some(self.trigger(&comm)?);
                    }
                }
                CLOCK_RESET => {
                    let n = c.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)).unwrap_or_default();
                    match self.names.get(&n) {
                        Some(Name::Clock(s)) => self.emit(Instr::ResetClock(*s)),
                        _ => return Err(self.err(c.text_range(), format!("`{n}` is not a clock"))),
                    }
                }
                CONDITION => {
                    if c.children().any(|n| n.kind() == ELSE_CONDITION) {
                        // Completed once every transition of the source is known.
                        is_else = true;
                    }
                    if let Some(e) = c.children().find(|e| ast::is_expr_kind(e.kind())) {
                        guard = Some(self.expr(&e)?);
                    }
                }
                DEADLINE => {
                    // The state's timer starts when its entry action ends.
                    if self.nodes[source as usize].kind != NodeKind::State {
                        return Err(self.err(
                            c.text_range(),
                            "deadlines on transitions from junctions are not supported \
                             (a junction is left at once or waits for a guard)",
                        ));
                    }
                    let limit = c
                        .children()
                        .find(|e| ast::is_expr_kind(e.kind()))
                        .ok_or_else(|| self.err(c.text_range(), "an incomplete deadline"))?;
                    let limit = self.expr(&limit)?;
                    self.deadlines.push((source, limit));
                }
                EXEC_TRIGGER => exec = true,
                PROBABILITY => {
                    return Err(self.err(
                        c.text_range(),
                        "probabilistic transitions have no meaning in the tock-CSP semantics and cannot be verified",
                    ))
                }
                _ => {}
            }
        }
        if let Some(a) = t.children().find(|c| c.kind() == TRANSITION_ACTION) {
            self.action_stmt(&a)?;
        }
        self.at = name_range;
        self.emit(Instr::Enter(target));
        let id = self.transitions.len() as u16;
        if is_else {
            self.else_transitions.push(id);
        }
        self.transitions.push(Transition {
            name,
            source,
            target,
            trigger,
            guard,
            body_pc,
            exec,
            binds: std::mem::take(&mut self.binds),
            range: t.children().find(|n| n.kind() == NAME).map(|n| n.text_range()).unwrap_or(t.text_range()),
            file: self.file_ix,
        });
        self.nodes[source as usize].out.push(id);
        Ok(())
    }

    fn trigger(&mut self, comm: &SyntaxNode) -> Result<Trigger, Unsupported> {
        let ev = comm.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)).unwrap_or_default();
        let (chan, dir, ty) = self.event(&ev, comm.text_range())?;
        let (value, bind, out) = self.comm_parts(comm, &ev, ty)?;
        Ok(match (dir, out.is_some()) {
            (Dir::Out, _) | (_, true) => {
                let chan = if out.is_some() { self.sends.get(&ev).copied().unwrap_or(chan) } else { chan };
                let args = out.or(value).into_iter().collect();
                Trigger::Out { chan, args }
            }
            (Dir::In, false) => Trigger::In { chan, value, bind },
        })
    }

    fn event(&self, name: &str, at: TextRange) -> Result<(u16, Dir, Option<Dom>), Unsupported> {
        match self.names.get(name) {
            Some(Name::Event { chan: Some((c, d)), ty }) => Ok((*c, *d, *ty)),
            Some(Name::Event { chan: None, .. }) => Err(self.err(
                at,
                format!(
                    "event `{name}` is not connected to the robotic platform; events between machines are not supported yet"
                ),
            )),
            _ => Err(self.err(at, format!("`{name}` is not an event"))),
        }
    }

    /// `e.v` value, `e?x` binding and `e!v` value of a communication.
    #[allow(clippy::type_complexity)]
    fn comm_parts(
        &mut self,
        comm: &SyntaxNode,
        ev: &str,
        ty: Option<Dom>,
    ) -> Result<(Option<Expr>, Option<(u16, Dom)>, Option<Expr>), Unsupported> {
        let mut value = None;
        let mut bind = None;
        let mut out = None;
        let want = self.types.get(ev).cloned().unwrap_or(Ty::Num(ty.unwrap_or(Dom::BOOL)));
        for p in comm.children() {
            match p.kind() {
                COMM_SYNC => {
                    if let Some(e) = p.children().find(|e| ast::is_expr_kind(e.kind())) {
                        value = Some(self.typed(&e, &want)?);
                    }
                }
                COMM_OUTPUT => {
                    if let Some(e) = p.children().find(|e| ast::is_expr_kind(e.kind())) {
                        out = Some(self.typed(&e, &want)?);
                    }
                }
                COMM_INPUT => {
                    if p.children().any(|n| ast::is_expr_kind(n.kind()) || n.kind() == COMM_GUARD) {
                        return Err(self.err(p.text_range(), "guarded inputs `e[|g|]?x` are not supported yet"));
                    }
                    let var = path_of(&p).join("::");
                    if self.types.get(&var) != self.types.get(ev) {
                        return Err(
                            self.err(p.text_range(), format!("`{var}` and the values of `{ev}` have different types"))
                        );
                    }
                    match self.names.get(&var) {
                        Some(Name::Var { update: Some(_), .. }) => {
                            return Err(self.err(
                                p.text_range(),
                                format!("receiving into `{var}`, a variable of the robotic platform, is not supported: receive into a local variable and assign it"),
                            ))
                        }
                        Some(Name::Var { slot, dom, .. }) => bind = Some((*slot, *dom)),
                        _ => return Err(self.err(p.text_range(), format!("`{var}` is not a variable"))),
                    }
                }
                _ => {}
            }
        }
        if ty.is_none() && (value.is_some() || bind.is_some() || out.is_some()) {
            return Err(self.err(comm.text_range(), "a value on an untyped event"));
        }
        Ok((value, bind, out))
    }

    fn action_stmt(&mut self, action: &SyntaxNode) -> Result<(), Unsupported> {
        if let Some(s) = action.children().find(|s| ast::is_stmt_kind(s.kind())) {
            self.stmt(&s)?;
        }
        Ok(())
    }

    fn stmt(&mut self, s: &SyntaxNode) -> Result<(), Unsupported> {
        if s.kind() != SEQ_STMT {
            self.at = s.text_range();
        }
        match s.kind() {
            SEQ_STMT => {
                for c in s.children().filter(|c| ast::is_stmt_kind(c.kind())) {
                    self.stmt(&c)?;
                }
            }
            SKIP_STMT => {}
            ASSIGN_STMT => {
                let target = s.children().find(|c| c.kind() == ASSIGNABLE).map(|a| path_of(&a).join("::"));
                let target = target.unwrap_or_default();
                let e = s
                    .children()
                    .find(|c| ast::is_expr_kind(c.kind()))
                    .ok_or_else(|| self.err(s.text_range(), "an assignment without a value"))?;
                let want = self.types.get(&target).cloned();
                let index = s
                    .children()
                    .find(|c| c.kind() == ASSIGNABLE)
                    .and_then(|a| a.children().find(|c| c.kind() == INDEX_ACCESS));
                let expr = match (index, want) {
                    (None, Some(t)) => self.typed(&e, &t)?,
                    (None, None) => self.expr(&e)?,
                    // `x[i] = v` of a tuple: the tuple with component i replaced.
                    (Some(ix), Some(Ty::Tuple(ds))) => {
                        let i = self.component(&ix, &ds)?;
                        let slot = match self.names.get(&target) {
                            Some(Name::Var { slot, .. }) => *slot,
                            _ => return Err(self.err(s.text_range(), format!("`{target}` is not a variable"))),
                        };
                        let mut parts = Vec::new();
                        for (j, d) in ds.iter().enumerate() {
                            let part = if j == i {
                                self.expr(&e)?
                            } else {
                                Expr::Proj(Box::new(Expr::Slot(slot)), stride(&ds, j), *d)
                            };
                            parts.push((part, *d));
                        }
                        Expr::Tuple(parts)
                    }
                    (Some(ix), _) => {
                        return Err(self.err(ix.text_range(), "only the components of tuples can be indexed"))
                    }
                };
                match self.names.get(&target) {
                    // The update of a platform variable is an output, urgent
                    // as an operation call: the platform cannot refuse it.
                    Some(&Name::Var { slot, dom, update: Some(chan), .. }) => {
                        self.emit(Instr::Out { chan, args: vec![expr], urgent: true, store: Some((slot, dom)) })
                    }
                    Some(&Name::Var { slot, dom, shared, update: None }) => {
                        let is_input = self.design().channels.iter().any(|c| c.var && c.name == target);
                        if is_input {
                            return Err(self.err(
                                s.text_range(),
                                format!("`{target}` is an input of the machine: to write it, require it in the output context too"),
                            ));
                        }
                        self.emit(Instr::Assign { slot, expr, dom, shared, forward: None })
                    }
                    _ => return Err(self.err(s.text_range(), format!("`{target}` is not a variable of the machine"))),
                }
            }
            CLOCK_RESET_STMT => {
                let n = s.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)).unwrap_or_default();
                match self.names.get(&n) {
                    Some(Name::Clock(c)) => self.emit(Instr::ResetClock(*c)),
                    _ => return Err(self.err(s.text_range(), format!("`{n}` is not a clock"))),
                }
            }
            IF_STMT => {
                let cond = s
                    .children()
                    .find(|c| ast::is_expr_kind(c.kind()))
                    .ok_or_else(|| self.err(s.text_range(), "`if` without a condition"))?;
                let cond = self.expr(&cond)?;
                let branches: Vec<SyntaxNode> = s.children().filter(|c| ast::is_stmt_kind(c.kind())).collect();
                let jif = self.code.len();
                self.emit(Instr::JumpIfNot(cond.clone(), u32::MAX));
                if let Some(t) = branches.first() {
                    self.stmt(t)?;
                }
                if let Some(e) = branches.get(1) {
                    let jend = self.code.len();
                    self.emit(Instr::Jump(u32::MAX));
                    self.code[jif] = Instr::JumpIfNot(cond, self.code.len() as u32);
                    self.stmt(e)?;
                    self.code[jend] = Instr::Jump(self.code.len() as u32);
                } else {
                    self.code[jif] = Instr::JumpIfNot(cond, self.code.len() as u32);
                }
            }
            COMM_STMT => {
                let comm = s
                    .children()
                    .find(|c| c.kind() == COMMUNICATION)
                    .ok_or_else(|| self.err(s.text_range(), "an incomplete communication"))?;
                let ev = comm.children().find(|n| n.kind() == NAME_REF).map(|n| ident_text(&n)).unwrap_or_default();
                let (chan, dir, ty) = self.event(&ev, comm.text_range())?;
                let (value, bind, out) = self.comm_parts(&comm, &ev, ty)?;
                // A lone machine sends on the `e.out` of an event it also receives.
                let (chan, dir) = match self.sends.get(&ev) {
                    Some(&c) if out.is_some() => (c, Dir::Out),
                    _ => (chan, dir),
                };
                match dir {
                    Dir::Out => {
                        if bind.is_some() {
                            return Err(self.err(comm.text_range(), format!("`{ev}` is an output: it cannot receive")));
                        }
                        let args = out.or(value).into_iter().collect();
                        self.emit(Instr::Out { chan, args, urgent: false, store: None });
                    }
                    Dir::In => {
                        if out.is_some() {
                            return Err(self.err(comm.text_range(), format!("`{ev}` is an input: it cannot send")));
                        }
                        self.emit(Instr::In { chan, value, bind });
                    }
                }
            }
            CALL_STMT => {
                let name = path_of(s).join("::");
                if let Some(&Name::Defined(op)) = self.op_names.get(&name) {
                    let args = self.arguments(s, self.ops[op as usize].params.len(), &name)?;
                    self.emit(Instr::CallOp { op, args });
                } else {
                    let (chan, args) = self.call(s, "an operation of the robotic platform required by the machine")?;
                    self.emit(Instr::Out { chan, args, urgent: true, store: None });
                }
            }
            WAIT_STMT => {
                let e = s
                    .children()
                    .find(|c| ast::is_expr_kind(c.kind()))
                    .ok_or_else(|| self.err(s.text_range(), "`wait` without a duration"))?;
                if e.kind() == INTERVAL_EXPR {
                    let bounds = ast::operand_exprs(&e);
                    let [lo, hi] = bounds.as_slice() else {
                        return Err(self.err(e.text_range(), "an interval needs two bounds"));
                    };
                    let open_lo = e.first_token().is_some_and(|t| t.kind() == L_PAREN);
                    let open_hi = e.last_token().is_some_and(|t| t.kind() == R_PAREN);
                    let mut lo = self.expr(lo)?;
                    let mut hi = self.expr(hi)?;
                    let wide = Dom { lo: Val::MIN / 4, hi: Val::MAX / 4 };
                    if open_lo {
                        lo = Expr::Arith(ArOp::Add, Box::new(lo), Box::new(Expr::Const(1)), wide);
                    }
                    if open_hi {
                        hi = Expr::Arith(ArOp::Sub, Box::new(hi), Box::new(Expr::Const(1)), wide);
                    }
                    self.emit(Instr::ChooseWait(lo, hi));
                } else {
                    let n = self.expr(&e)?;
                    self.emit(Instr::SetWait(n));
                }
                self.emit(Instr::Wait);
            }
            SIM_CALL_STMT => {
                // Register writes cannot be postponed (RoboTool: EDeadline(…, 0)).
                let (chan, args) = self.call(s, "an output operation of the machine")?;
                self.emit(Instr::Out { chan, args, urgent: true, store: None });
            }
            OUTPUT_COMM_STMT => {
                let name = path_of(s).join("::");
                let (chan, dir, ty) = self.event(&name, s.text_range())?;
                if dir != Dir::Out {
                    return Err(self.err(s.text_range(), format!("`{name}` is not an output")));
                }
                let value = s.children().find(|e| ast::is_expr_kind(e.kind()));
                let want = self.types.get(&name).cloned().unwrap_or(Ty::Num(ty.unwrap_or(Dom::BOOL)));
                let args = match value {
                    Some(v) => vec![self.typed(&v, &want)?],
                    None => Vec::new(),
                };
                if ty.is_some() == args.is_empty() {
                    return Err(self.err(s.text_range(), format!("`{name}` needs exactly its declared value")));
                }
                self.emit(Instr::Out { chan, args, urgent: true, store: None });
            }
            EXEC_STMT => {
                let next = self.code.len() as u32 + 1;
                self.emit(Instr::Exec(next));
            }
            TIMED_STMT => {
                let body = s.children().find(|c| ast::is_stmt_kind(c.kind()));
                let limit = s
                    .children()
                    .find(|c| c.kind() == DEADLINE)
                    .and_then(|d| d.children().find(|e| ast::is_expr_kind(e.kind())));
                let (Some(body), Some(limit)) = (body, limit) else {
                    return Err(self.err(s.text_range(), "an incomplete deadline"));
                };
                let limit = self.expr(&limit)?;
                self.emit(Instr::Deadline(limit));
                self.stmt(&body)?;
                self.at = s.text_range();
                self.emit(Instr::EndDeadline);
            }
            PAR_STMT => {
                let inner: Vec<SyntaxNode> = s.children().filter(|c| ast::is_stmt_kind(c.kind())).collect();
                let [one] = inner.as_slice() else {
                    return Err(self.err(s.text_range(), "parallel statements are not supported yet"));
                };
                self.stmt(one)?;
            }
            k => {
                return Err(self.err(
                    s.text_range(),
                    format!("this statement ({}) is not supported by the native checker yet", kind_words(k)),
                ))
            }
        }
        Ok(())
    }

    /// The channel and argument values of a call `op(args)` / `$op(args)`
    /// of a platform operation (`what` says what `op` must be).
    fn call(&mut self, s: &SyntaxNode, what: &str) -> Result<(u16, Vec<Expr>), Unsupported> {
        let name = path_of(s).join("::");
        let Some(Name::Op { params, chan }) = self.op_names.get(&name).cloned() else {
            return Err(self.err(s.text_range(), format!("`{name}` is not {what}")));
        };
        Ok((chan, self.arguments(s, params.len(), &name)?))
    }

    /// The `n` argument values of the call `s` of `name`.
    fn arguments(&mut self, s: &SyntaxNode, n: usize, name: &str) -> Result<Vec<Expr>, Unsupported> {
        let args: Vec<SyntaxNode> = s
            .children()
            .find(|c| c.kind() == ARG_LIST)
            .map(|a| a.children().filter(|e| ast::is_expr_kind(e.kind())).collect())
            .unwrap_or_default();
        if n != args.len() {
            return Err(self.err(s.text_range(), format!("`{name}` takes {n} arguments")));
        }
        let mut exprs = Vec::new();
        for a in &args {
            exprs.push(self.expr(a)?);
        }
        Ok(exprs)
    }

    /// The operation of `op_defs[i]` in this machine: its parameters and
    /// return slots now, its body once the caller's code is complete.
    fn operation(&mut self, i: usize, params: &[Dom]) -> Result<u16, Unsupported> {
        if let Some(&k) = self.op_of_def.get(&i) {
            return Ok(k);
        }
        let (name, file, node) = self.op_defs[i].clone();
        // The definition's own parameter types win over the signature's.
        let mut slots = Vec::new();
        let plist = node.children().find(|p| p.kind() == PARAM_LIST);
        let defined: Vec<SyntaxNode> =
            plist.map(|pl| pl.children().filter(|p| p.kind() == PARAM).collect()).unwrap_or_default();
        if defined.len() != params.len() {
            return Err(self.cx.unsupported(
                file,
                node.text_range(),
                format!(
                    "operation `{name}` is defined with {} parameters and required with {}",
                    defined.len(),
                    params.len()
                ),
            ));
        }
        for p in &defined {
            let tnode = p.children().find(|t| ast::is_type_kind(t.kind()));
            let dom = self.ty(file, tnode.as_ref(), p.text_range())?;
            slots.push((self.new_slot(), dom));
        }
        let ret_slot = self.new_slot();
        let leaf_slot = self.new_slot();
        let k = self.ops.len() as u16;
        self.ops.push(Operation { name: name.clone(), params: slots, start_pc: 0, ret_slot, leaf_slot });
        self.op_of_def.insert(i, k);
        self.pending_ops.push((k, i));
        Ok(k)
    }

    /// Compiles the bodies of the operations the machine calls (each in
    /// its own scope: its parameters and declarations; `external` maps its
    /// events as the machine's).
    fn operation_bodies(
        &mut self,
        external: &impl Fn(&str) -> Result<Option<Link>, String>,
    ) -> Result<(), Unsupported> {
        while let Some((k, i)) = self.pending_ops.pop() {
            let (name, file, node) = self.op_defs[i].clone();
            // The body's names resolve, and its code is located, in the
            // file that defines it.
            let saved_file = std::mem::replace(&mut self.file, file);
            let saved_ix = std::mem::replace(&mut self.file_ix, self.cx.file_index(file));
            let saved_names = std::mem::take(&mut self.names);
            let saved_types = std::mem::take(&mut self.types);
            let saved_decl = std::mem::replace(&mut self.decl_name, name.clone());
            let saved_op = self.cur_op.replace(k);
            let plist = node.children().find(|p| p.kind() == PARAM_LIST);
            let params: Vec<SyntaxNode> =
                plist.map(|pl| pl.children().filter(|p| p.kind() == PARAM).collect()).unwrap_or_default();
            for (p, &(slot, dom)) in params.iter().zip(&self.ops[k as usize].params.clone()) {
                self.names.insert(name_of(p), Name::Var { slot, dom, shared: false, update: None });
            }
            // The body runs in the caller's context: its events are the
            // caller's connections.
            self.declarations(&node, external)?;
            self.collect_nodes(&node, None)?;
            self.compile(&node)?;
            let start = self.region_start(&node, None)?;
            self.ops[k as usize].start_pc = start;
            self.names = saved_names;
            self.types = saved_types;
            self.decl_name = saved_decl;
            self.cur_op = saved_op;
            self.file = saved_file;
            self.file_ix = saved_ix;
        }
        Ok(())
    }

    fn expr(&mut self, e: &SyntaxNode) -> Result<Expr, Unsupported> {
        let num = self.cx.defaults.real;
        let int_dom = Dom { lo: self.cx.defaults.int.lo.min(num.lo), hi: self.cx.defaults.int.hi.max(num.hi) };
        Ok(match e.kind() {
            PAREN_EXPR => {
                let inner = e
                    .children()
                    .find(|c| ast::is_expr_kind(c.kind()))
                    .ok_or_else(|| self.err(e.text_range(), "empty parentheses"))?;
                self.expr(&inner)?
            }
            LITERAL => {
                let tok = e.first_token().ok_or_else(|| self.err(e.text_range(), "an empty literal"))?;
                match tok.kind() {
                    INT_NUMBER => Expr::Const(
                        tok.text().parse().map_err(|_| self.err(e.text_range(), "this number is too large"))?,
                    ),
                    TRUE_KW => Expr::Const(1),
                    FALSE_KW => Expr::Const(0),
                    FLOAT_NUMBER => {
                        let v: f64 = tok.text().parse().unwrap_or(f64::NAN);
                        if v.fract() == 0.0 && v.abs() < 1e15 {
                            Expr::Const(v as Val)
                        } else {
                            return Err(self.err(
                                e.text_range(),
                                "real numbers with a fractional part are not supported (reals are bounded integers, as in RoboTool)",
                            ));
                        }
                    }
                    _ => return Err(self.err(e.text_range(), "this literal is not supported by the native checker")),
                }
            }
            REF_EXPR => {
                let n = ident_text(e);
                if self.types.contains_key(&n) {
                    return Err(self.err(e.text_range(), format!("`{n}` is a tuple or a set, used here as a number")));
                }
                self.value_of(e, &n)?
            }
            ENUM_LITERAL_EXPR => {
                let parts: Vec<String> =
                    e.children().filter(|c| c.kind() == NAME_REF).map(|c| ident_text(&c)).collect();
                let (lit, en) = parts.split_last().ok_or_else(|| self.err(e.text_range(), "an empty literal"))?;
                let (_, decl) = self
                    .cx
                    .resolve(self.file, en, |k| k == DefKind::Enumeration)
                    .ok_or_else(|| self.err(e.text_range(), "the enumeration could not be resolved"))?;
                let ix =
                    decl.children().filter(|c| c.kind() == ENUM_LITERAL).position(|c| name_of(&c) == *lit).ok_or_else(
                        || self.err(e.text_range(), format!("`{lit}` is not a literal of the enumeration")),
                    )?;
                Expr::Const(ix as Val)
            }
            SIM_REF_EXPR => {
                let name = path_of(e).join("::");
                let suffix = e.children().find(|c| c.kind() == SIM_INPUT_SUFFIX);
                match self.names.get(&name) {
                    // `$x`: the variable's value (its register for an input).
                    Some(&Name::Var { slot, .. }) if suffix.is_none() => return Ok(Expr::Slot(slot)),
                    Some(Name::Var { .. }) => {
                        return Err(self.err(e.text_range(), format!("`${name}` is a variable: it cannot be received")))
                    }
                    _ => {}
                }
                let Some(Name::Event { chan: Some((chan, Dir::In)), ty }) = self.names.get(&name).cloned() else {
                    return Err(self
                        .err(e.text_range(), format!("`${name}` is not an input event or a variable of the machine")));
                };
                let Some(reg) = self.design().channels[chan as usize].register else {
                    return Err(self.err(e.text_range(), "`$` references belong to RoboSim machines"));
                };
                if let Some(suffix) = suffix {
                    let var = path_of(&suffix).join("::");
                    let Some(Name::Var { slot, dom, .. }) = self.names.get(&var).cloned() else {
                        return Err(self.err(suffix.text_range(), format!("`{var}` is not a variable")));
                    };
                    if ty.is_none() {
                        return Err(self.err(suffix.text_range(), format!("`{name}` carries no value")));
                    }
                    self.binds.push((slot, dom, reg + 1));
                }
                Expr::Slot(reg)
            }
            SINCE_EXPR => {
                let n = e.children().find(|c| c.kind() == NAME_REF).map(|c| ident_text(&c)).unwrap_or_default();
                match self.names.get(&n) {
                    Some(Name::Clock(s)) => Expr::Clock(*s),
                    _ => return Err(self.err(e.text_range(), format!("`{n}` is not a clock"))),
                }
            }
            SINCE_ENTRY_EXPR => {
                let path = path_of(e);
                let n = path.last().cloned().unwrap_or_default();
                let Some(node) = self.nodes.iter().position(|x| x.name == n && x.kind == NodeKind::State) else {
                    return Err(self.err(e.text_range(), format!("`{n}` is not a state of the machine")));
                };
                let slot = match self.nodes[node].since_entry {
                    Some(s) => s,
                    None => {
                        let s = self.new_slot();
                        self.nodes[node].since_entry = Some(s);
                        let q = format!("{}::sinceEntry({n})", self.inst_prefix);
                        self.design().clocks.push(Clock { name: q, slot: s, cap: 0 });
                        self.clock_caps.insert(s, 0);
                        s
                    }
                };
                Expr::Clock(slot)
            }
            PREFIX_EXPR => {
                let op = e.first_token().map(|t| t.kind());
                let inner = e
                    .children()
                    .find(|c| ast::is_expr_kind(c.kind()))
                    .ok_or_else(|| self.err(e.text_range(), "an operator without an operand"))?;
                let inner = self.expr(&inner)?;
                match op {
                    Some(NOT_KW) => Expr::Not(Box::new(inner)),
                    Some(MINUS) => match inner.constant() {
                        Some(v) => Expr::Const(-v),
                        None => Expr::Neg(Box::new(inner), int_dom),
                    },
                    _ => return Err(self.err(e.text_range(), "this operator is not supported by the native checker")),
                }
            }
            BIN_EXPR => {
                let ops = ast::operand_exprs(e);
                let [a, b] = ops.as_slice() else {
                    return Err(self.err(e.text_range(), "an incomplete expression"));
                };
                let op = ast::binary_operator(e);
                if let Some(r) = self.structured_binary(e, op, a, b)? {
                    return Ok(r);
                }
                let x = self.expr(a)?;
                let y = self.expr(b)?;
                // Clock comparisons bound the clock's range.
                if let Some(op @ (EQ2 | NEQ | LT | LTEQ | GT | GTEQ)) = op {
                    let _ = op;
                    for (c, other) in [(&x, &y), (&y, &x)] {
                        if let Expr::Clock(s) = c {
                            let v = other.constant().map(|v| v.clamp(0, i32::MAX as Val) as i32).unwrap_or(-1);
                            // RoboTool's generator refuses this too: the clock
                            // would stop below the value and the guard would
                            // never change.
                            let max = self.cx.defaults.clock_max;
                            if v > max {
                                let clock =
                                    self.cx.design.as_ref().and_then(|d| d.clocks.iter().find(|k| k.slot == *s));
                                let name = clock.map_or("a clock".to_string(), |k| format!("`{}`", k.name));
                                return Err(self.err(
                                    e.text_range(),
                                    format!(
                                        "{name} is compared with {v}, above the greatest clock value {max} \
                                         (`core_clock_type = {{0..{max}}}`): widen it with \
                                         `nametype core_clock_type = {{0..{v}}}` in a `csp` block of an assertion file"
                                    ),
                                ));
                            }
                            let cap = self.clock_caps.entry(*s).or_insert(0);
                            *cap = if v < 0 || *cap < 0 { -1 } else { (*cap).max(v) };
                        }
                    }
                }
                let ar = |op| Expr::Arith(op, Box::new(x.clone()), Box::new(y.clone()), int_dom);
                let result = match op {
                    Some(PLUS) => ar(ArOp::Add),
                    Some(MINUS) => ar(ArOp::Sub),
                    Some(STAR) => ar(ArOp::Mul),
                    Some(SLASH) => ar(ArOp::Div),
                    Some(PERCENT) => ar(ArOp::Mod),
                    Some(EQ2) => Expr::Cmp(CmpOp::Eq, Box::new(x), Box::new(y)),
                    Some(NEQ) => Expr::Cmp(CmpOp::Ne, Box::new(x), Box::new(y)),
                    Some(LT) => Expr::Cmp(CmpOp::Lt, Box::new(x), Box::new(y)),
                    Some(LTEQ) => Expr::Cmp(CmpOp::Le, Box::new(x), Box::new(y)),
                    Some(GT) => Expr::Cmp(CmpOp::Gt, Box::new(x), Box::new(y)),
                    Some(GTEQ) => Expr::Cmp(CmpOp::Ge, Box::new(x), Box::new(y)),
                    Some(AND) => Expr::Log(LogOp::And, Box::new(x), Box::new(y)),
                    Some(OR) => Expr::Log(LogOp::Or, Box::new(x), Box::new(y)),
                    Some(IMPLIES) => Expr::Log(LogOp::Implies, Box::new(x), Box::new(y)),
                    Some(IFF_KW) => Expr::Log(LogOp::Iff, Box::new(x), Box::new(y)),
                    _ => return Err(self.err(e.text_range(), "this operator is not supported by the native checker")),
                };
                // Fold constant subexpressions (`PI / av`).
                match result.constant() {
                    Some(v) if matches!(result, Expr::Arith(..)) => Expr::Const(v),
                    _ => result,
                }
            }
            IF_EXPR => {
                let parts = ast::operand_exprs(e);
                let [c, a, b] = parts.as_slice() else {
                    return Err(self.err(e.text_range(), "an incomplete conditional"));
                };
                Expr::If(Box::new(self.expr(c)?), Box::new(self.expr(a)?), Box::new(self.expr(b)?))
            }
            SELECT_EXPR => {
                // `r.f` of a record: its field's component.
                let base = ast::operand_exprs(e).into_iter().next();
                let field = e.children().filter(|c| c.kind() == NAME_REF).last().map(|n| ident_text(&n));
                let (Some(base), Some(field)) = (base, field) else {
                    return Err(self.err(e.text_range(), "an incomplete field access"));
                };
                let t = self.infer(&base);
                let Some(Ty::Record(names, ds)) = &t else {
                    return Err(self.err(e.text_range(), "only the fields of records can be selected"));
                };
                let (names, ds) = (names.clone(), ds.clone());
                let t = t.expect("a record");
                let i = names
                    .iter()
                    .position(|n| *n == field)
                    .ok_or_else(|| self.err(e.text_range(), format!("the record has no field `{field}`")))?;
                let r = self.typed(&base, &t)?;
                Expr::Proj(Box::new(r), stride(&ds, i), ds[i])
            }
            INDEX_EXPR => {
                let parts = ast::operand_exprs(e);
                let [base, _] = parts.as_slice() else {
                    return Err(self.err(e.text_range(), "an incomplete index"));
                };
                let Some(Ty::Tuple(ds)) = self.infer(base) else {
                    return Err(self.err(e.text_range(), "only the components of tuples can be indexed"));
                };
                let i = self.component(e, &ds)?;
                let t = self.typed(base, &Ty::Tuple(ds.clone()))?;
                Expr::Proj(Box::new(t), stride(&ds, i), ds[i])
            }
            CALL_EXPR if matches!(call_parts(e).0.as_str(), "member" | "size" | "card" | "subset") => {
                let (f, args) = call_parts(e);
                match (f.as_str(), args.as_slice()) {
                    ("member", [x, set]) => self.member(e, x, set)?,
                    ("size" | "card", [set]) => {
                        let Some(t @ Ty::Set(_)) = self.infer(set) else {
                            return Err(self.err(e.text_range(), format!("`{f}` of a set whose type is not known")));
                        };
                        Expr::Card(Box::new(self.typed(set, &t)?))
                    }
                    ("subset", [x, y]) => {
                        let Some(t @ Ty::Set(_)) = self.infer(x).or_else(|| self.infer(y)) else {
                            return Err(self.err(e.text_range(), "`subset` of sets whose type is not known"));
                        };
                        Expr::Set(SetOp::Subset, Box::new(self.typed(x, &t)?), Box::new(self.typed(y, &t)?))
                    }
                    _ => return Err(self.err(e.text_range(), format!("`{f}` with {} arguments", args.len()))),
                }
            }
            TUPLE_EXPR | SET_EXPR => {
                return Err(self.err(e.text_range(), "a tuple or set where a number is expected"));
            }
            CALL_EXPR => {
                let (f, args) = call_parts(e);
                if !self.cx.defaults.functions.iter().any(|c| c.name == f) {
                    return Err(self.err(
                        e.text_range(),
                        format!(
                            "`{f}` has no definition the native checker can read: define it in a `csp` block \
                             of an assertion file, as for FDR (`{f}(x) = …`)"
                        ),
                    ));
                }
                let mut values = Vec::new();
                for a in &args {
                    values.push(self.expr(a)?);
                }
                self.csp_call(e.text_range(), &f, values, 0)?
            }
            k => {
                return Err(self.err(
                    e.text_range(),
                    format!("this expression ({}) is not supported by the native checker yet", kind_words(k)),
                ))
            }
        })
    }

    /// A call of `name`, defined in CSPm by an instantiation block, on
    /// argument values: its clauses tried in order, inlined.
    fn csp_call(&mut self, at: TextRange, name: &str, args: Vec<Expr>, depth: usize) -> Result<Expr, Unsupported> {
        if depth > 16 {
            return Err(self.err(at, format!("the CSPm definition of `{name}` calls itself too deeply to inline")));
        }
        let clauses: Vec<CspFunction> = self
            .cx
            .defaults
            .functions
            .iter()
            .filter(|c| c.name == name && c.params.len() == args.len())
            .cloned()
            .collect();
        if clauses.is_empty() {
            return Err(self.err(at, format!("no CSPm definition of `{name}` takes {} arguments", args.len())));
        }
        // From the last clause back: `if pattern then body else (the rest)`.
        let mut rest: Option<Expr> = None;
        for clause in clauses.iter().rev() {
            let mut env = HashMap::new();
            let mut conds = Vec::new();
            for (p, a) in clause.params.iter().zip(&args) {
                let v = match p {
                    CspExpr::Bool(b) => Some(*b as Val),
                    CspExpr::Name(n) => match self.csp_constructor(n) {
                        Some((v, _)) => Some(v),
                        None => {
                            env.insert(n.clone(), a.clone());
                            None
                        }
                    },
                    _ => Some(int_pattern(p).ok_or_else(|| {
                        self.err(at, format!("a pattern of `{name}` the native checker cannot match"))
                    })?),
                };
                if let Some(v) = v {
                    conds.push(Expr::Cmp(CmpOp::Eq, Box::new(a.clone()), Box::new(Expr::Const(v))));
                }
            }
            let body = self.csp_expr(at, &clause.body, &env, depth)?;
            let cond = conds.into_iter().reduce(|a, b| Expr::Log(LogOp::And, Box::new(a), Box::new(b)));
            rest = Some(match (cond, rest) {
                (None, _) => body,
                (Some(c), Some(r)) => Expr::If(Box::new(c), Box::new(body), Box::new(r)),
                (Some(_), None) => {
                    // The last clause matches on a value: the clauses must
                    // cover every value (FDR stops with an error otherwise).
                    if !self.csp_exhaustive(&clauses) {
                        return Err(self.err(
                            at,
                            format!(
                                "the CSPm clauses of `{name}` do not cover every value of its arguments \
                                 (add a clause with a variable pattern)"
                            ),
                        ));
                    }
                    body
                }
            });
        }
        Ok(rest.expect("at least one clause"))
    }

    /// Whether the clauses of a one-argument function match every
    /// constructor of the enumeration their patterns name.
    fn csp_exhaustive(&self, clauses: &[CspFunction]) -> bool {
        let mut covered = Vec::new();
        let mut size = None;
        for c in clauses {
            let [CspExpr::Name(n)] = c.params.as_slice() else { return false };
            let Some((v, n)) = self.csp_constructor(n) else { return false };
            covered.push(v);
            size = Some(n);
        }
        size.is_some_and(|n| (0..n).all(|v| covered.contains(&v)))
    }

    /// A CSPm constructor `Type_Literal` of an enumeration in scope: its
    /// value and the enumeration's size.
    fn csp_constructor(&self, name: &str) -> Option<(Val, Val)> {
        name.match_indices('_').find_map(|(i, _)| {
            let (ty, lit) = (&name[..i], &name[i + 1..]);
            let (_, en) = self.cx.resolve(self.file, &[ty.to_string()], |k| k == DefKind::Enumeration)?;
            let lits: Vec<String> = en.children().filter(|c| c.kind() == ENUM_LITERAL).map(|c| name_of(&c)).collect();
            let v = lits.iter().position(|l| l == lit)?;
            Some((v as Val, lits.len() as Val))
        })
    }

    /// A CSPm body with its parameters bound to `env`. CSPm arithmetic is
    /// not saturating: it is evaluated in a wide domain.
    fn csp_expr(
        &mut self,
        at: TextRange,
        e: &CspExpr,
        env: &HashMap<String, Expr>,
        depth: usize,
    ) -> Result<Expr, Unsupported> {
        let wide = Dom { lo: Val::MIN / 4, hi: Val::MAX / 4 };
        Ok(match e {
            CspExpr::Int(v) => Expr::Const(*v),
            CspExpr::Bool(b) => Expr::Const(*b as Val),
            CspExpr::Name(n) => {
                if let Some(x) = env.get(n) {
                    x.clone()
                } else if let Some((v, _)) = self.csp_constructor(n) {
                    Expr::Const(v)
                } else if let Some((_, v)) = self.cx.defaults.constants.iter().find(|(c, _)| c == n) {
                    Expr::Const(*v)
                } else if self.cx.defaults.functions.iter().any(|c| c.name == *n && c.params.is_empty()) {
                    self.csp_call(at, n, Vec::new(), depth + 1)?
                } else {
                    return Err(self.err(at, format!("`{n}` in a CSPm definition is not known to the native checker")));
                }
            }
            CspExpr::Call(f, args) => {
                let mut values = Vec::new();
                for a in args {
                    values.push(self.csp_expr(at, a, env, depth)?);
                }
                self.csp_call(at, f, values, depth + 1)?
            }
            CspExpr::Neg(x) => Expr::Neg(Box::new(self.csp_expr(at, x, env, depth)?), wide),
            CspExpr::Not(x) => Expr::Not(Box::new(self.csp_expr(at, x, env, depth)?)),
            CspExpr::Bin(op, a, b) => {
                let (a, b) = (Box::new(self.csp_expr(at, a, env, depth)?), Box::new(self.csp_expr(at, b, env, depth)?));
                match op {
                    CspBinOp::Add => Expr::Arith(ArOp::Add, a, b, wide),
                    CspBinOp::Sub => Expr::Arith(ArOp::Sub, a, b, wide),
                    CspBinOp::Mul => Expr::Arith(ArOp::Mul, a, b, wide),
                    CspBinOp::Div => Expr::Arith(ArOp::Div, a, b, wide),
                    CspBinOp::Mod => Expr::Arith(ArOp::Mod, a, b, wide),
                    CspBinOp::Eq => Expr::Cmp(CmpOp::Eq, a, b),
                    CspBinOp::Ne => Expr::Cmp(CmpOp::Ne, a, b),
                    CspBinOp::Lt => Expr::Cmp(CmpOp::Lt, a, b),
                    CspBinOp::Le => Expr::Cmp(CmpOp::Le, a, b),
                    CspBinOp::Gt => Expr::Cmp(CmpOp::Gt, a, b),
                    CspBinOp::Ge => Expr::Cmp(CmpOp::Ge, a, b),
                    CspBinOp::And => Expr::Log(LogOp::And, a, b),
                    CspBinOp::Or => Expr::Log(LogOp::Or, a, b),
                    CspBinOp::Cat => return Err(self.err(at, "sequences in CSPm definitions are not supported")),
                }
            }
            CspExpr::If(c, a, b) => Expr::If(
                Box::new(self.csp_expr(at, c, env, depth)?),
                Box::new(self.csp_expr(at, a, env, depth)?),
                Box::new(self.csp_expr(at, b, env, depth)?),
            ),
        })
    }
}

impl MachineCx<'_, '_> {
    /// The type of `e` when it is a tuple or a set, as far as the names in
    /// it tell (literals take the type their context wants).
    fn infer(&self, e: &SyntaxNode) -> Option<Ty> {
        let exprs = || e.children().filter(|c| ast::is_expr_kind(c.kind()));
        match e.kind() {
            PAREN_EXPR => self.infer(&exprs().next()?),
            REF_EXPR => self.types.get(&ident_text(e)).cloned(),
            CALL_EXPR => {
                let (f, args) = call_parts(e);
                matches!(f.as_str(), "union" | "inter" | "diff").then(|| args.iter().find_map(|a| self.infer(a)))?
            }
            IF_EXPR => exprs().skip(1).find_map(|b| self.infer(&b)),
            _ => None,
        }
    }

    /// Lowers `e` as a value of type `want`.
    fn typed(&mut self, e: &SyntaxNode, want: &Ty) -> Result<Expr, Unsupported> {
        if want.is_num() {
            return self.expr(e);
        }
        let exprs = ast::operand_exprs(e);
        let r = match (e.kind(), want) {
            (PAREN_EXPR, _) if exprs.len() == 1 => self.typed(&exprs[0], want)?,
            (IF_EXPR, _) if exprs.len() == 3 => Expr::If(
                Box::new(self.expr(&exprs[0])?),
                Box::new(self.typed(&exprs[1], want)?),
                Box::new(self.typed(&exprs[2], want)?),
            ),
            (TUPLE_EXPR, Ty::Tuple(ds)) => {
                if exprs.len() != ds.len() {
                    return Err(self.err(e.text_range(), format!("a tuple of {} components is expected", ds.len())));
                }
                let mut parts = Vec::new();
                for (x, d) in exprs.iter().zip(ds) {
                    parts.push((self.expr(x)?, *d));
                }
                Expr::Tuple(parts)
            }
            (RECORD_LITERAL, Ty::Record(names, ds)) => {
                let mut parts = Vec::new();
                for (n, d) in names.iter().zip(ds) {
                    let value = e
                        .children()
                        .filter(|f| f.kind() == FIELD_VALUE)
                        .find(|f| f.children().find(|c| c.kind() == NAME_REF).is_some_and(|c| ident_text(&c) == *n))
                        .and_then(|f| f.children().find(|c| ast::is_expr_kind(c.kind())))
                        .ok_or_else(|| {
                            self.err(e.text_range(), format!("the record literal gives no value to `{n}`"))
                        })?;
                    parts.push((self.expr(&value)?, *d));
                }
                Expr::Tuple(parts)
            }
            (SET_EXPR, Ty::Set(el)) => {
                let mut acc: Option<Expr> = None;
                for x in &exprs {
                    let bit = Expr::Elem(Box::new(self.typed(x, el)?), el.dom());
                    acc = Some(match acc {
                        None => bit,
                        Some(a) => Expr::Set(SetOp::Union, Box::new(a), Box::new(bit)),
                    });
                }
                acc.unwrap_or(Expr::Const(0))
            }
            (CALL_EXPR, Ty::Set(_)) if matches!(call_parts(e).0.as_str(), "union" | "inter" | "diff") => {
                let (f, args) = call_parts(e);
                let [a, b] = args.as_slice() else {
                    return Err(self.err(e.text_range(), format!("`{f}` takes two sets")));
                };
                let op = match f.as_str() {
                    "union" => SetOp::Union,
                    "inter" => SetOp::Inter,
                    _ => SetOp::Diff,
                };
                Expr::Set(op, Box::new(self.typed(a, want)?), Box::new(self.typed(b, want)?))
            }
            (REF_EXPR, _) => {
                let n = ident_text(e);
                if self.types.get(&n) != Some(want) {
                    return Err(self.err(e.text_range(), format!("`{n}` does not have the type expected here")));
                }
                self.value_of(e, &n)?
            }
            _ => {
                let what = if matches!(want, Ty::Set(_)) { "a set" } else { "a tuple" };
                return Err(self.err(
                    e.text_range(),
                    format!("{what} is expected here; this expression is not supported as one by the native checker"),
                ));
            }
        };
        // Fold constant values (initial values, constants).
        Ok(match r.constant() {
            Some(v) if !matches!(r, Expr::Slot(_)) => Expr::Const(v),
            _ => r,
        })
    }

    /// `==`, `!=` of tuples and sets, and `x in s`; `None` for numbers.
    fn structured_binary(
        &mut self,
        e: &SyntaxNode,
        op: Option<SyntaxKind>,
        a: &SyntaxNode,
        b: &SyntaxNode,
    ) -> Result<Option<Expr>, Unsupported> {
        Ok(match op {
            Some(k @ (EQ2 | NEQ)) => {
                let Some(t) = self.infer(a).or_else(|| self.infer(b)) else { return Ok(None) };
                let cmp = if k == EQ2 { CmpOp::Eq } else { CmpOp::Ne };
                Some(Expr::Cmp(cmp, Box::new(self.typed(a, &t)?), Box::new(self.typed(b, &t)?)))
            }
            Some(IN_KW) => Some(self.member(e, a, b)?),
            _ => None,
        })
    }

    /// `x in set`, `member(x, set)`.
    fn member(&mut self, e: &SyntaxNode, x: &SyntaxNode, set: &SyntaxNode) -> Result<Expr, Unsupported> {
        if let Some(t @ Ty::Set(_)) = self.infer(set) {
            let Ty::Set(el) = &t else { unreachable!() };
            let bit = Expr::Elem(Box::new(self.typed(x, el)?), el.dom());
            return Ok(Expr::Set(SetOp::Meets, Box::new(bit), Box::new(self.typed(set, &t)?)));
        }
        // A literal set of numbers: one of the elements.
        let mut inner = set.clone();
        while inner.kind() == PAREN_EXPR {
            match inner.children().find(|c| ast::is_expr_kind(c.kind())) {
                Some(c) => inner = c,
                None => break,
            }
        }
        if inner.kind() == SET_EXPR && self.infer(x).is_none() {
            let v = self.expr(x)?;
            let mut acc = Expr::Const(0);
            for el in inner.children().filter(|c| ast::is_expr_kind(c.kind())) {
                let eq = Expr::Cmp(CmpOp::Eq, Box::new(v.clone()), Box::new(self.expr(&el)?));
                acc = Expr::Log(LogOp::Or, Box::new(acc), Box::new(eq));
            }
            return Ok(acc);
        }
        Err(self.err(e.text_range(), "membership in a set whose type is not known"))
    }

    /// The component (0-based) an index `[i]` selects, `i` from 1.
    fn component(&mut self, index: &SyntaxNode, ds: &[Dom]) -> Result<usize, Unsupported> {
        let ix = index.children().filter(|c| ast::is_expr_kind(c.kind())).last();
        let i = match ix {
            Some(ix) => self.expr(&ix)?.constant(),
            None => None,
        };
        match i {
            Some(i) if 1 <= i && i as usize <= ds.len() => Ok(i as usize - 1),
            _ => Err(self.err(
                index.text_range(),
                format!("a tuple of {} components is indexed by a constant from 1 to {}", ds.len(), ds.len()),
            )),
        }
    }
}

/// The weight of component `i` in a tuple's code.
fn stride(ds: &[Dom], i: usize) -> Val {
    tuple_size(&ds[i + 1..]) as Val
}

/// The value of an integer pattern `n` or `-n` of a CSPm clause.
fn int_pattern(p: &CspExpr) -> Option<Val> {
    match p {
        CspExpr::Int(v) => Some(*v),
        CspExpr::Neg(x) => match **x {
            CspExpr::Int(v) => Some(-v),
            _ => None,
        },
        _ => None,
    }
}

/// The function's name and arguments of a call expression.
fn call_parts(e: &SyntaxNode) -> (String, Vec<SyntaxNode>) {
    let f = e.children().find(|c| c.kind() == REF_EXPR).map(|c| ident_text(&c)).unwrap_or_default();
    let args = e
        .children()
        .find(|c| c.kind() == ARG_LIST)
        .map(|a| a.children().filter(|x| ast::is_expr_kind(x.kind())).collect())
        .unwrap_or_default();
    (f, args)
}

fn kind_words(k: SyntaxKind) -> String {
    format!("{k:?}").to_lowercase().replace('_', " ")
}
