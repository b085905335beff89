//! One machine (or operation body): its declarations as slots and
//! channels, its nodes and transitions as code.

use robosim_hir::model::{self, Comm, CommPart, Decl, Region};
use robosim_hir::model::{Io, UseKind};

use super::*;
use crate::events::Param;

impl<'b> MachineCx<'_, 'b> {
    /// The value an assertion gives the constant `name`, else the one an
    /// instantiation block gives it (RoboTool's `pkg_Machine_name` or
    /// `Machine_name`).
    pub(super) fn const_value(&self, name: &str) -> Option<Val> {
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
    pub(super) fn declarations(
        &mut self,
        node: &'b Behaviour,
        external: &impl Fn(&str) -> Result<Option<Link>, String>,
    ) -> Result<(), Unsupported> {
        let file = self.file;
        // Each source of declarations: its file, its declarations, whether
        // it is an interface, and the I/O context it comes through (RoboSim).
        let mut sources: Vec<(File, &'b model::Decls, Option<UseKind>, Option<Dir>)> =
            vec![(file, &node.decls, None, None)];
        // RoboSim declares its inputs and outputs in I/O contexts.
        let contexts: Vec<(&'b model::Decls, Option<Dir>)> =
            node.contexts.iter().map(|(io, d)| (d, Some(if *io == Io::Input { Dir::In } else { Dir::Out }))).collect();
        sources.extend(contexts.iter().map(|(c, d)| (file, *c, None, *d)));
        let uses =
            std::iter::once((&node.decls, None)).chain(contexts).flat_map(|(n, d)| n.uses.iter().map(move |u| (u, d)));
        for (u, context) in uses {
            let (f, n) =
                self.cx.interface(u.target).ok_or_else(|| self.err(u.range, "the interface could not be resolved"))?;
            sources.push((f, n, Some(u.kind), context));
        }
        for (f, n, from_interface, context) in sources {
            // RT-23: a RoboSim machine's `uses` (outside its I/O contexts)
            // declares local variables; an operation's `requires` there
            // names the calling machine's copies.
            let robosim_local = self.cx.robosim && context.is_none();
            let local_use = robosim_local && from_interface == Some(UseKind::Uses) && self.cur_op.is_none();
            let caller_copy = robosim_local && from_interface == Some(UseKind::Requires) && self.caller.is_some();
            let from_interface = from_interface.is_some() && !local_use;
            for c in &n.decls {
                match c {
                    Decl::Vars { is_const, vars, range } => {
                        for v in vars {
                            let name = v.name.clone();
                            let tnode = v.ty.as_ref();
                            let ty = self.ty_of(f, tnode, v.range)?;
                            let dom = ty.dom();
                            let init = v.init.as_ref();
                            self.bind_ty(&name, &ty);
                            if caller_copy {
                                match self.caller.as_ref().and_then(|c| c.get(&name)).cloned() {
                                    Some(n @ (Name::Var { .. } | Name::Const(_))) => {
                                        self.names.insert(name, n);
                                        continue;
                                    }
                                    _ => {
                                        return Err(self.err(
                                            v.range,
                                            format!(
                                                "the operation requires `{name}`, which the calling machine does \
                                                 not declare (RT-23: it uses the caller's copy)"
                                            ),
                                        ))
                                    }
                                }
                            }
                            if *is_const {
                                let q = format!("{}::{name}", self.inst_prefix);
                                let value = match self.const_value(&name) {
                                    Some(v) => v,
                                    None => {
                                        match init.map(|e| self.typed(e, &ty)).transpose()?.and_then(|e| e.constant()) {
                                            Some(v) => v,
                                            None => {
                                                // RT-1: RoboTool writes the type's default.
                                                let v = self.default_of(tnode, &ty);
                                                let shown = self.value_text(tnode, &ty, v);
                                                self.design().defaults.push(format!("constant {q} = {shown} (RT-1)"));
                                                v
                                            }
                                        }
                                    }
                                };
                                // A sequence of literals by their names (`<Skills_MOVE>`).
                                let shown = match ty {
                                    Layout::Seq(_) => self.value_text(tnode, &ty, value),
                                    _ => ty.show(value),
                                };
                                self.design().constants.push((q, value, shown));
                                self.names.insert(name, Name::Const(value));
                            } else {
                                if from_interface {
                                    // A variable the machine requires: shared
                                    // by every machine of the design.
                                    let shape = self.shape_of(tnode, &ty);
                                    self.shared_variable(*range, &name, (&ty, shape), init, context)?;
                                    continue;
                                }
                                let slot = self.new_slot();
                                let q = format!("{}::{name}", self.inst_prefix);
                                let initv = match init {
                                    Some(e) => self.typed(e, &ty)?.constant().ok_or_else(|| {
                                        self.err(e.range, "initial values must be constant expressions")
                                    })?,
                                    None => self.uninitialised(&q, tnode, &ty),
                                };
                                self.design().vars.push(Var { name: q, slot, dom, init: initv });
                                if let Some(k) = self.cur_op {
                                    self.ops[k as usize].locals.push((slot, initv as i32));
                                }
                                self.names.insert(name, Name::Var { slot, dom, shared: false, update: None });
                            }
                        }
                    }
                    Decl::Clock { name, .. } => {
                        let name = name.clone();
                        let slot = self.new_slot();
                        let q = format!("{}::{name}", self.inst_prefix);
                        self.design().clocks.push(Clock { name: q, slot, cap: 0 });
                        // Its own clock restarts with each call; one it requires
                        // is its caller's in RoboTool (`clockReset` events).
                        if let (Some(k), false) = (self.cur_op, from_interface) {
                            self.ops[k as usize].locals.push((slot, 0));
                        }
                        self.clock_caps.insert(slot, 0);
                        self.names.insert(name, Name::Clock(slot));
                    }
                    Decl::Event { name, ty: tnode, range, .. } => {
                        let (name, range) = (name.clone(), *range);
                        let tnode = tnode.as_ref();
                        let full = match tnode {
                            Some(t) => Some(self.ty_of(f, Some(t), range)?),
                            None => None,
                        };
                        // Sets of numbers, booleans and literals are events'
                        // values (`activeSkills.out.{Skills_MOVE}`).
                        let unsupported = match &full {
                            Some(Layout::Set(el)) if !el.is_num() => Some("sets of tuples or records"),
                            Some(Layout::Seq(_)) => Some("sequences"),
                            _ => None,
                        };
                        if let Some(what) = unsupported {
                            return Err(self.err(
                                range,
                                format!(
                                    "events carrying {what} (`{name}`) are not supported by the native checker yet"
                                ),
                            ));
                        }
                        let ty = full.as_ref().map(Layout::dom);
                        let shape: Vec<Param> = full.iter().map(|t| self.shape_of(tnode, t)).collect();
                        if let Some(t) = &full {
                            self.bind_ty(&name, t);
                        }
                        let chan = match external(&name) {
                            Ok(Some(link)) => {
                                let both_ways = self.cx.lone || self.cx.bidirectional.contains(&link.name);
                                // RoboSim: the I/O context says the direction.
                                // An event of both contexts, on its own or
                                // `[mult]` to the platform, has an input
                                // register `i_e` and an output register `o_e`,
                                // independent of each other (the generated
                                // `RegisterDataInput`/`RegisterDataOutput`).
                                let sim_dir = context.filter(|_| self.cx.robosim && both_ways && !link.internal);
                                if sim_dir == Some(Dir::Out) {
                                    let out = self.channel(&link.name, Dir::Out, false, shape);
                                    self.design().channels[out as usize].register_write = true;
                                    self.sends.insert(name.clone(), out);
                                    // The input context's declaration names the
                                    // event for `$e` and `$e?x`.
                                    if !matches!(
                                        self.names.get(&name),
                                        Some(Name::Event { chan: Some((_, Dir::In)), .. })
                                    ) {
                                        self.names.insert(name, Name::Event { chan: Some((out, Dir::Out)), ty });
                                    }
                                    continue;
                                }
                                let link = Link { dir: sim_dir.unwrap_or(link.dir), ..link };
                                if sim_dir.is_none()
                                    && both_ways
                                    && link.dir == Dir::In
                                    && super::compose::sent_events(node).contains(&name)
                                {
                                    // A machine on its own, or connected both
                                    // ways, that also sends the event it
                                    // receives: `e.out` is a channel of its own.
                                    let out = self.channel(&link.name, Dir::Out, false, shape.clone());
                                    self.sends.insert(name.clone(), out);
                                }
                                let chan = self.channel(&link.name, link.dir, false, shape);
                                if link.internal && self.cx.robosim {
                                    self.memory_cell(chan, &name, range)?;
                                } else if link.internal {
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
                            // Every input register of a RoboSim machine is read
                            // at the start of each cycle, used or not (RT-20;
                            // the generated `Cycle`), so an input connected to
                            // nothing matters even when never used, and how
                            // RoboTool reads it is not known (`compose.rs`).
                            Ok(None) if self.cx.robosim && context == Some(Dir::In) => {
                                return Err(self.cx.unsupported(
                                    f,
                                    range,
                                    format!(
                                        "`{name}`, an input of the RoboSim machine `{}`, is connected to nothing: its \
                                         register is read every cycle, and whether RoboTool hides that read, leaves it \
                                         to the environment or blocks it is not known (connect it, or remove it from \
                                         the input context)",
                                        self.inst_prefix
                                    ),
                                ))
                            }
                            Ok(None) => None,
                            Err(msg) => return Err(self.err(range, msg)),
                        };
                        if let (true, Some(Dir::Out), Some((c, Dir::Out))) = (self.cx.robosim, context, chan) {
                            self.design().channels[c as usize].register_write = true;
                        }
                        self.names.insert(name, Name::Event { chan, ty });
                    }
                    Decl::OperationSig { name, params: ps, .. } => {
                        let name = name.clone();
                        let (mut params, mut shape) = (Vec::new(), Vec::new());
                        for p in ps {
                            let d = self.ty(f, p.ty.as_ref(), p.range)?;
                            params.push(d);
                            shape.push(self.param_of(p.ty.as_ref()).unwrap_or(Param::Num(d)));
                        }
                        // The controller may define it: then it is no platform call.
                        if let Some(i) = self.op_defs.iter().position(|(n, ..)| *n == name) {
                            let k = self.operation(i, &params)?;
                            self.op_names.insert(name, Name::Defined(k));
                            continue;
                        }
                        let chan = self.channel(&name, Dir::Out, true, shape);
                        if self.cx.robosim && context.is_none() {
                            self.design().channels[chan as usize].soft_call = true;
                        }
                        if self.cx.robosim && context == Some(Dir::Out) {
                            self.design().channels[chan as usize].register_write = true;
                        }
                        self.op_names.insert(name, Name::Op { params, chan });
                    }
                    Decl::Nested { range, .. } => return Err(self.err(
                        *range,
                        "operations defined in machines, and functions, are not supported by the native checker yet",
                    )),
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
        decl: TextRange,
        name: &str,
        (ty, shape): (&Layout, Param),
        init: Option<&model::Expr>,
        context: Option<Dir>,
    ) -> Result<(), Unsupported> {
        let dom = ty.dom();
        if self.cx.robosim && context.is_none() {
            return Err(self.err(
                decl,
                format!(
                    "`{name}` is required by the machine itself: a RoboSim machine's variables of the platform are \
                     inputs or outputs, required in its input or output context (RS:SM4)"
                ),
            ));
        }
        let platform = self.cx.robosim || self.cx.platform_vars.contains(name);
        if platform && !ty.is_num() && !matches!(ty, Layout::Tuple(_) | Layout::Record(..) | Layout::Product(_)) {
            return Err(self.err(
                decl,
                format!(
                    "variables of the platform carrying sets (`{name}`) are not supported by the native checker yet"
                ),
            ));
        }
        // RT-16: a variable a controller provides lives in that
        // controller's memory: two controllers of a module each keep their
        // own, even of the same name; the platform's is one for all.
        let key = match self.inst_prefix.rsplit_once("::") {
            Some((ctrl, _)) if !platform => format!("{ctrl}::{name}"),
            _ => name.to_string(),
        };
        let slot = match self.cx.shared_vars.get(&key) {
            Some(&(slot, d)) if d == dom => slot,
            Some(_) => return Err(self.err(decl, format!("`{name}` is required with two different types"))),
            None => {
                let slot = self.new_slot();
                let value = match init {
                    Some(e) => self
                        .typed(e, ty)?
                        .constant()
                        .ok_or_else(|| self.err(e.range, "initial values must be constant expressions"))?,
                    // RT-4: booleans, platform memories too, start true.
                    None if shape == Param::Bool => {
                        self.design().defaults.push(format!("variable {name} starts true (RT-4)"));
                        1
                    }
                    None => ty.default_value(),
                };
                self.design().vars.push(Var { name: name.to_string(), slot, dom, init: value });
                self.cx.shared_vars.insert(key.clone(), (slot, dom));
                slot
            }
        };
        let shared = self.cx.machine_count > 1;
        // RT-16: with several machines, each reads its own copy of a
        // variable its controller provides (see `Cx::forwards`).
        let slot = if shared && !platform {
            let machine = self.design().machines.len();
            let copies = self.cx.copies.entry(key.clone()).or_default();
            match copies.iter().find(|(m, _)| *m == machine) {
                Some(&(_, copy)) => copy,
                None => {
                    let copy = self.new_slot();
                    self.cx.copies.get_mut(&key).expect("made above").push((machine, copy));
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
    pub(super) fn collect_nodes(&mut self, region: &'b Region, parent: Option<u16>) -> Result<(), Unsupported> {
        for c in &region.nodes {
            let kind = match c.kind {
                model::NodeKind::State => NodeKind::State,
                model::NodeKind::Junction => NodeKind::Junction,
                model::NodeKind::Initial => NodeKind::Initial,
                model::NodeKind::Final => NodeKind::Final,
                model::NodeKind::Probabilistic => {
                    return Err(self.err(
                        c.range,
                        "probabilistic junctions have no meaning in the tock-CSP semantics and cannot be verified",
                    ))
                }
            };
            let id = self.nodes.len() as u16;
            self.nodes.push(Node {
                name: c.name.clone(),
                op: self.cur_op,
                kind,
                parent,
                entry_pc: 0,
                exit_pc: 0,
                since_entry: None,
                entered_flag: None,
                entered_pc: None,
                during: None,
                timer: None,
                activity: None,
                out: Vec::new(),
                range: c.name_range,
            });
            self.node_models.push(c);
            if kind == NodeKind::State {
                self.collect_nodes(&c.region, Some(id))?;
            }
        }
        Ok(())
    }

    /// The node named `name` in the region of `parent`.
    fn sibling(&self, parent: Option<u16>, name: &str) -> Option<u16> {
        self.nodes.iter().position(|n| n.op == self.cur_op && n.parent == parent && n.name == name).map(|i| i as u16)
    }

    pub(super) fn compile(&mut self, machine: &'b Region) -> Result<(), Unsupported> {
        // Transitions of every region.
        let mut regions = vec![(machine, None)];
        for (i, n) in self.nodes.iter().enumerate() {
            if n.kind == NodeKind::State && n.op == self.cur_op {
                regions.push((&self.node_models[i].region, Some(i as u16)));
            }
        }
        for (region, parent) in regions {
            for t in &region.transitions {
                self.transition(t, parent)?;
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
            let syn = self.node_models[id];
            let node_id = id as u16;
            self.at = self.nodes[id].range;
            match self.nodes[id].kind {
                NodeKind::State => {
                    let entry_pc = self.code.len() as u32;
                    if let Some(a) = &syn.entry {
                        self.action_stmt(a)?;
                    }
                    self.at = self.nodes[id].range;
                    let has_children = self.nodes.iter().any(|n| n.parent == Some(node_id));
                    // RoboTool's `entered` follows the entry action; a
                    // composite's follows its first substate's.
                    if !has_children {
                        self.nodes[id].entered_pc = Some(self.code.len() as u32);
                        self.emit(Instr::Entered(node_id));
                    }
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
                    let during = syn.during.as_ref();
                    if let (Some(a), true) = (during, has_children) {
                        self.activity(node_id, a)?;
                        self.at = self.nodes[id].range;
                    }
                    // A simple state's during action runs after the entry
                    // action; any transition of the state may interrupt it.
                    if let (Some(a), false) = (during, has_children) {
                        let start = self.code.len() as u32;
                        self.action_stmt(a)?;
                        self.nodes[id].during = Some((start, self.code.len() as u32));
                        self.at = self.nodes[id].range;
                    }
                    if has_children {
                        let pc = self.code.len() as u32;
                        self.emit(Instr::Jump(u32::MAX));
                        let start = self.region_start(syn.range, Some(node_id))?;
                        self.code[pc as usize] = Instr::Jump(start);
                    } else {
                        self.emit(Instr::Rest);
                    }
                    let exit_pc = self.code.len() as u32;
                    if let Some(a) = &syn.exit {
                        self.action_stmt(a)?;
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
                    self.nodes[id].entered_pc = Some(self.code.len() as u32);
                    self.emit(Instr::Entered(node_id));
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
    /// A composite state's during action: an activity of the machine,
    /// started when a substate is entered ([`Instr::Entered`]), its code
    /// out of line.
    fn activity(&mut self, state: u16, during: &model::Action) -> Result<(), Unsupported> {
        if self.cx.robosim {
            return Err(self.err(
                during.range,
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
        self.at = during.range;
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
    pub(super) fn region_start(&mut self, region: TextRange, parent: Option<u16>) -> Result<u32, Unsupported> {
        let init = self
            .nodes
            .iter()
            .position(|n| n.op == self.cur_op && n.parent == parent && n.kind == NodeKind::Initial)
            .ok_or_else(|| self.err(region, "a region without an initial junction cannot be executed"))?;
        let t = self.nodes[init]
            .out
            .first()
            .copied()
            .ok_or_else(|| self.err(self.nodes[init].range, "the initial junction has no transition"))?;
        Ok(self.transitions[t as usize].body_pc)
    }

    fn transition(&mut self, t: &'b model::Transition, parent: Option<u16>) -> Result<(), Unsupported> {
        let name = t.name.clone();
        let (Some(src), Some(dst)) = (&t.source, &t.target) else {
            return Err(self.err(t.range, format!("transition `{name}` lacks a source or a target")));
        };
        let source = self
            .sibling(parent, src)
            .ok_or_else(|| self.err(t.range, format!("`{src}` is not a node of this region")))?;
        let target = self
            .sibling(parent, dst)
            .ok_or_else(|| self.err(t.range, format!("`{dst}` is not a node of this region")))?;
        let mut trigger = None;
        let mut guard = None;
        self.binds.clear();
        let body_pc = self.code.len() as u32;
        let name_range = t.name_range;
        self.at = name_range;
        if let Some(p) = t.probability {
            return Err(self
                .err(p, "probabilistic transitions have no meaning in the tock-CSP semantics and cannot be verified"));
        }
        if let Some(comm) = &t.trigger {
            trigger = Some(self.trigger(comm)?);
        }
        for (n, range) in &t.resets {
            match self.names.get(n) {
                Some(Name::Clock(s)) => self.emit(Instr::ResetClock(*s)),
                _ => return Err(self.err(*range, format!("`{n}` is not a clock"))),
            }
        }
        // `condition else` is completed once every transition of the
        // source is known.
        let is_else = t.condition.as_ref().is_some_and(|c| c.is_else);
        if let Some(e) = t.condition.as_ref().and_then(|c| c.expr.as_ref()) {
            guard = Some(self.expr(e)?);
        }
        if let Some((range, limit)) = &t.deadline {
            // The state's timer starts when its entry action ends.
            if self.nodes[source as usize].kind != NodeKind::State {
                return Err(self.err(
                    *range,
                    "deadlines on transitions from junctions are not supported \
                     (a junction is left at once or waits for a guard)",
                ));
            }
            let limit = limit.as_ref().ok_or_else(|| self.err(*range, "an incomplete deadline"))?;
            let limit = self.expr(limit)?;
            self.deadlines.push((source, limit));
        }
        if let Some(a) = &t.action {
            self.action_stmt(a)?;
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
            exec: t.exec,
            binds: std::mem::take(&mut self.binds),
            range: name_range,
            file: self.file_ix,
        });
        self.nodes[source as usize].out.push(id);
        Ok(())
    }

    fn trigger(&mut self, comm: &Comm) -> Result<Trigger, Unsupported> {
        let ev = &comm.event;
        let (chan, dir, ty) = self.event(ev, comm.range)?;
        let (value, bind, out, then) = self.comm_parts(comm, ty)?;
        // The transition's body starts with it (`e.in?x -> set_x!x -> …`).
        for i in then {
            self.emit(i);
        }
        Ok(match (dir, out.is_some()) {
            (Dir::Out, _) | (_, true) => {
                let chan = if out.is_some() { self.sends.get(ev).copied().unwrap_or(chan) } else { chan };
                let args = out.or(value).into_iter().collect();
                Trigger::Out { chan, args }
            }
            (Dir::In, false) => Trigger::In { chan, value, bind },
        })
    }

    pub(super) fn event(&self, name: &str, at: TextRange) -> Result<(u16, Dir, Option<Dom>), Unsupported> {
        match self.names.get(name) {
            Some(Name::Event { chan: Some((c, d)), ty }) => Ok((*c, *d, *ty)),
            // Only a RoboSim output connected to nothing has no channel
            // (`compose.rs`: how RoboTool reads it is not known).
            Some(Name::Event { chan: None, .. }) => Err(self.err(
                at,
                format!(
                    "`{name}`, an output of the RoboSim machine `{}`, is connected to nothing: whether RoboTool \
                     hides its register write, leaves it to the environment or blocks it is not known (connect it)",
                    self.inst_prefix
                ),
            )),
            _ => Err(self.err(at, format!("`{name}` is not an event"))),
        }
    }

    /// `e.v` value, `e?x` binding and `e!v` value of a communication, and
    /// what runs right after it (the update of a platform variable received
    /// into).
    #[allow(clippy::type_complexity)]
    pub(super) fn comm_parts(
        &mut self,
        comm: &Comm,
        ty: Option<Dom>,
    ) -> Result<(Option<Expr>, Option<(u16, Dom)>, Option<Expr>, Vec<Instr>), Unsupported> {
        let ev = &comm.event;
        if let Some(g) = comm.guard {
            // The guard restricts which communications can happen: ignoring
            // it would explore behaviour the model does not have.
            return Err(self.err(g, format!("guarded communications `{ev}[| … |]` are not supported yet")));
        }
        let mut value = None;
        let mut bind = None;
        let mut out = None;
        let mut then = Vec::new();
        let want = self.types.get(ev).cloned().unwrap_or(Layout::Num(ty.unwrap_or(Dom::BOOL)));
        match &comm.part {
            Some(CommPart::Sync(Some(e))) => value = Some(self.typed(e, &want)?),
            Some(CommPart::Output(Some(e))) => out = Some(self.typed(e, &want)?),
            Some(CommPart::Input(path, range)) => {
                let var = path.join("::");
                if self.types.get(&var) != self.types.get(ev) {
                    return Err(self.err(*range, format!("`{var}` and the values of `{ev}` have different types")));
                }
                match self.names.get(&var) {
                    // As RoboTool's `e.in?x -> set_x!x`: received into a
                    // local of its own, then the platform variable's update
                    // (an output, urgent: as an assignment to it), the
                    // local back at rest so that it does not split states.
                    Some(&Name::Var { slot, dom, update: Some(chan), .. }) => {
                        let tmp = self.new_slot();
                        let rest = if dom.contains(0) { 0 } else { dom.lo };
                        let name = format!("{}::{var}__in", self.inst_prefix);
                        self.design().vars.push(Var { name, slot: tmp, dom, init: rest });
                        bind = Some((tmp, dom));
                        then.push(Instr::Out {
                            chan,
                            args: vec![Expr::Slot(tmp)],
                            urgent: true,
                            store: Some((slot, dom)),
                        });
                        then.push(Instr::Assign {
                            slot: tmp,
                            expr: Expr::Const(rest),
                            dom,
                            shared: false,
                            forward: None,
                        });
                    }
                    Some(Name::Var { slot, dom, .. }) => bind = Some((*slot, *dom)),
                    _ => return Err(self.err(*range, format!("`{var}` is not a variable"))),
                }
            }
            _ => {}
        }
        if ty.is_none() && (value.is_some() || bind.is_some() || out.is_some()) {
            return Err(self.err(comm.range, "a value on an untyped event"));
        }
        Ok((value, bind, out, then))
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
        let defined = &node.params;
        if defined.len() != params.len() {
            return Err(self.cx.unsupported(
                file,
                node.range,
                format!(
                    "operation `{name}` is defined with {} parameters and required with {}",
                    defined.len(),
                    params.len()
                ),
            ));
        }
        for p in defined {
            let dom = self.ty(file, p.ty.as_ref(), p.range)?;
            slots.push((self.new_slot(), dom));
        }
        let ret_slot = self.new_slot();
        let leaf_slot = self.new_slot();
        let k = self.ops.len() as u16;
        self.ops.push(Operation {
            name: name.clone(),
            params: slots,
            start_pc: 0,
            ret_slot,
            leaf_slot,
            locals: Vec::new(),
        });
        self.op_of_def.insert(i, k);
        self.pending_ops.push((k, i));
        Ok(k)
    }

    /// Compiles the bodies of the operations the machine calls (each in
    /// its own scope: its parameters and declarations; `external` maps its
    /// events as the machine's).
    pub(super) fn operation_bodies(
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
            for (p, &(slot, dom)) in node.params.iter().zip(&self.ops[k as usize].params.clone()) {
                self.names.insert(p.name.clone(), Name::Var { slot, dom, shared: false, update: None });
            }
            // The body runs in the caller's context: its events are the
            // caller's connections.
            self.caller = Some(saved_names.clone());
            let declared = self.declarations(node, external);
            self.caller = None;
            declared?;
            self.collect_nodes(&node.region, None)?;
            self.compile(&node.region)?;
            let start = self.region_start(node.range, None)?;
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
}
