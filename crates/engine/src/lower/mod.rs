//! Lowering of a RoboChart module, controller or machine into the
//! compiled [`Design`]: machines as instruction lists, variables and clocks as
//! slots of a flat state vector, types as bounded ranges (semantics.md §3),
//! events and platform operations as channels to the platform.
//!
//! The lowering reads the semantic model ([`robosim_hir::model`]), never
//! syntax: `compose` puts the machines of a module or controller together
//! and decides where each event leads, `machine` compiles one machine's
//! declarations, nodes and transitions, `stmt` and `expr` its actions and
//! expressions, and `types` how values of each type are laid out in a slot.
//!
//! What the engine cannot interpret yet is refused with a reason and a
//! source location ([`Unsupported`]) instead of being approximated: a wrong
//! verdict is worse than none.

mod cells;
mod compose;
mod expr;
mod functions;
mod inspect;
mod machine;
mod stmt;
mod types;

use std::collections::{BTreeMap, BTreeSet, HashMap};

use robosim_hir::index::ItemLoc;
use robosim_hir::model::{self, Behaviour, Item};
use robosim_hir::{Db, File, TextRange, Workspace};

use crate::ir::*;
pub use inspect::{inspect_element, ElementView, EventView};
use robosim_hir::csp_fn::CspFunction;
use types::Layout;

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
    /// Whether the assertion's file has a `csp Instantiations` block, which
    /// replaces RoboTool's generated defaults (RT-7): a function it does
    /// not define then has no definition at all (no RT-2 default).
    pub replaced: bool,
    /// Whether the script is RoboSim's (a `.rsa` file): RoboTool's RoboSim
    /// script includes `sim/instantiations.csp`, whose number types cover
    /// the project's RoboChart and RoboSim models, for every element it
    /// names — a RoboChart design under `simulation` too (RT-5).
    pub robosim_script: bool,
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
            replaced: false,
            robosim_script: false,
        }
    }
}

impl DomainDefaults {
    /// What RT-5's computation of the number domains takes from these
    /// (what the instantiations fixed and define).
    pub fn domain_inputs(&self) -> robosim_hir::domains::DomainInputs {
        use robosim_hir::domains::NumRange;
        let r = |d: Dom| NumRange { lo: d.lo, hi: d.hi };
        let doms = [self.nat, self.int, self.real];
        robosim_hir::domains::DomainInputs {
            fixed: [0, 1, 2].map(|i| self.fixed[i].then(|| r(doms[i]))),
            types: self.types.iter().map(|(n, d)| (n.clone(), r(*d))).collect(),
            constants: self.constants.clone(),
            functions: self.functions.clone(),
            replaced: self.replaced,
        }
    }

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
        primitive_defaults: Default::default(),
        op_subject: false,
    };
    let mut design = cx.lower(loc, inner)?;
    design.defaults.extend(cx.primitive_defaults.into_inner());
    Ok(design)
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
    /// RT-3: the primitive types given no range, which range over {0, 1}
    /// (noted when a type is laid out, which only reads the context).
    primitive_defaults: std::cell::RefCell<BTreeSet<String>>,
    /// RT-11: the element checked is an operation on its own.
    op_subject: bool,
}

/// An operation a controller defines or references: its name there, the
/// file that defines it, and its definition.
type OpDef<'a> = (String, File, &'a Behaviour);

/// One machine to compile: its declaration and where it sits.
struct Instance<'a> {
    /// Controller reference (or controller) name; "" for a lone machine.
    ctrl: String,
    /// Machine reference name.
    name: String,
    /// The machine's own declared name (for `constant … of`).
    decl_name: String,
    file: File,
    body: &'a Behaviour,
    /// Whether it is declared inside its controller.
    inline: bool,
    /// Operations its controller defines (or references).
    ops: Vec<OpDef<'a>>,
}

impl<'a> Instance<'a> {
    /// The machine (or operation) `body` of `file` on its own: no
    /// controller, no operations given to it.
    fn alone(file: File, body: &'a Behaviour) -> Self {
        let name = body.name.clone();
        Instance { ctrl: String::new(), decl_name: name.clone(), name, file, body, inline: false, ops: Vec::new() }
    }
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

impl<'a> Cx<'a> {
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

    /// The model of the element `loc`, when it is one.
    fn item(&self, loc: Option<ItemLoc>) -> Option<&'a Item> {
        model::item(self.db, self.ws, loc?)
    }

    /// The declarations of the interface `loc` (none when it is not one).
    fn interface(&self, loc: Option<ItemLoc>) -> Option<(File, &'a model::Decls)> {
        match self.item(loc)? {
            Item::Interface(i) => Some((loc?.file, &i.decls)),
            _ => None,
        }
    }
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
    /// A parameter of a function being inlined: the argument's value.
    Bound(Expr),
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
    /// The model of each node (for its actions and its region).
    node_models: Vec<&'b model::Node>,
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
    op_defs: Vec<OpDef<'b>>,
    ops: Vec<Operation>,
    op_of_def: HashMap<usize, u16>,
    pending_ops: Vec<(u16, usize)>,
    /// The operation whose body is being compiled.
    cur_op: Option<u16>,
    /// Greatest static value each clock slot is compared with (-1: unknown).
    clock_caps: HashMap<u16, i32>,
    /// The types of the variables, constants and events in scope whose
    /// values are not plain numbers (tuples, sets).
    types: HashMap<String, Layout>,
    /// The events a lone machine, or one connected both ways to the
    /// platform, both receives and sends: the channel of their outputs.
    sends: HashMap<String, u16>,
    /// The during actions of composite states, and the deadline timers of
    /// states, so far.
    activities: Vec<Activity>,
    timers: Vec<u16>,
    /// The deadlines `<{d}` of the transitions compiled so far, by source.
    deadlines: Vec<(u16, Expr)>,
    /// RT-23: while a RoboSim operation's declarations are read, the
    /// calling machine's names (its `requires` resolve to the caller's
    /// copies).
    caller: Option<HashMap<String, Name>>,
    /// How deep calls of functions defined by `result == e` are inlined
    /// at the moment (a recursive definition is refused past a bound).
    inlining: u8,
}

impl MachineCx<'_, '_> {
    /// The variable or constant named `n` (at `at`) as an expression.
    fn value_of(&self, at: TextRange, n: &str) -> Result<Expr, Unsupported> {
        match self.names.get(n) {
            Some(Name::Var { slot, .. }) => Ok(Expr::Slot(*slot)),
            Some(Name::Const(v)) => Ok(Expr::Const(*v)),
            Some(Name::Bound(e)) => Ok(e.clone()),
            _ => Err(self.err(at, format!("`{n}` is not a variable or constant"))),
        }
    }

    fn err(&self, range: TextRange, msg: impl Into<String>) -> Unsupported {
        self.cx.unsupported(self.file, range, msg)
    }

    /// Records the type of `name`, which a declaration binds.
    fn bind_ty(&mut self, name: &str, ty: &Layout) {
        if ty.is_num() {
            self.types.remove(name);
        } else {
            self.types.insert(name.to_string(), ty.clone());
        }
    }

    fn emit(&mut self, i: Instr) {
        // A value sent must be one of the channel's type: RoboTool's CSPm
        // stops FDR with an error otherwise (not a clamped value).
        let i = match i {
            Instr::Out { chan, args, urgent, store } => {
                let params = self.design().channels.get(chan as usize).map(|c| c.params.clone()).unwrap_or_default();
                let args = if params.len() == args.len() {
                    args.into_iter().zip(params).map(|(a, d)| a.checked(d)).collect()
                } else {
                    args
                };
                Instr::Out { chan, args, urgent, store }
            }
            i => i,
        };
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
}
