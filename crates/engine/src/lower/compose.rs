//! Putting a design together: the machines of a module or controller,
//! where each of their events leads (the platform, another machine, or
//! nowhere), and the variables they share.

use std::collections::{BTreeSet, HashMap};

use robosim_hir::defs::{file_defs, Io};
use robosim_hir::index::ItemLoc;
use robosim_hir::model::{self, Behaviour, Connection, Controller, Definition, Item};
use robosim_hir::File;

use super::*;

/// What is compiled: a module, a controller or a machine on its own.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Top {
    Module,
    Controller,
    Machine,
}

impl<'a> Cx<'a> {
    /// Records the variables a robotic platform declares or provides.
    fn platform_variables(&mut self, decls: &'a model::Decls) {
        let interfaces: Vec<&model::Decls> =
            decls.uses.iter().filter_map(|u| self.interface(u.target)).map(|(_, d)| d).collect();
        for d in std::iter::once(decls).chain(interfaces) {
            for decl in &d.decls {
                if let model::Decl::Vars { vars, .. } = decl {
                    self.platform_vars.extend(vars.iter().map(|v| v.name.clone()));
                }
            }
        }
    }

    /// The events a RoboSim machine's input context declares, itself or
    /// through the interfaces it uses.
    fn input_context_events(&self, machine: &'a Behaviour) -> Vec<String> {
        let mut out = Vec::new();
        for (_, ctx) in machine.contexts.iter().filter(|(io, _)| *io == Io::Input) {
            let interfaces = ctx.uses.iter().filter_map(|u| self.interface(u.target)).map(|(_, d)| d);
            for d in std::iter::once(ctx).chain(interfaces) {
                for decl in &d.decls {
                    if let model::Decl::Event { name, .. } = decl {
                        out.push(name.clone());
                    }
                }
            }
        }
        out
    }

    /// A connection with the platform marked `[ mult ]` carries its event
    /// both ways: `e.in` and `e.out` are channels of their own.
    fn note_bidirectional(&mut self, connection: &Connection, platform_event: &str) {
        if connection.is_mult {
            self.bidirectional.insert(platform_event.to_string());
        }
    }

    pub(super) fn lower(&mut self, loc: ItemLoc, inner: Option<&str>) -> Result<Design, Unsupported> {
        let not_found = || Unsupported { message: "the element to verify could not be found".into(), location: None };
        let item = self.item(Some(loc)).ok_or_else(not_found)?;
        let file = loc.file;
        if let Some(m) = inner {
            let Item::Controller(c) = item else {
                let range = self.range_of(loc).ok_or_else(not_found)?;
                return Err(self.unsupported(file, range, format!("the controller declares no state machine `{m}`")));
            };
            // RT-11: an operation the controller declares in its own body,
            // on its own (as a top-level operation).
            let op = c.operations.iter().find_map(|o| match &o.def {
                Definition::Inline(b) if o.name == m => Some(&**b),
                _ => None,
            });
            if let Some(b) = op {
                return self.operation_subject(file, b);
            }
            return self.inner_machine(file, c, m);
        }
        let mut instances = Vec::new();
        // Links between connection ends, and which ends belong to the platform
        // (with the direction seen from the software).
        let mut links: Vec<(End, End)> = Vec::new();
        let mut platform: HashMap<End, Dir> = HashMap::new();
        let mut async_links: Vec<AsyncLink> = Vec::new();
        let (top_name, top) = match item {
            Item::Module(m) => {
                let mut platform_names = BTreeSet::new();
                for p in &m.platforms {
                    platform_names.insert(p.name.clone());
                    match &p.def {
                        Definition::Inline(pl) => self.platform_variables(&pl.decls),
                        Definition::Ref { target, .. } => {
                            if let Some(Item::Platform(pl)) = self.item(*target) {
                                self.platform_variables(&pl.decls);
                            }
                        }
                    }
                }
                for c in &m.controllers {
                    let (cf, cn) = match &c.def {
                        Definition::Inline(cn) => (file, &**cn),
                        Definition::Ref { target, .. } => match (target, self.item(*target)) {
                            (Some(t), Some(Item::Controller(cn))) => (t.file, cn),
                            _ => {
                                return Err(self.unsupported(
                                    file,
                                    c.range,
                                    "the referenced controller could not be resolved",
                                ))
                            }
                        },
                    };
                    self.controller(&c.name, cf, cn, &mut instances, &mut links, &mut async_links)?;
                }
                for c in &m.connections {
                    let (a, b, is_async) = ends(c);
                    if platform_names.contains(&a.0) {
                        platform.insert(a.clone(), Dir::In);
                        self.note_bidirectional(c, &a.1);
                    } else if platform_names.contains(&b.0) {
                        platform.insert(b.clone(), Dir::Out);
                        self.note_bidirectional(c, &b.1);
                    } else if is_async {
                        async_links.push((file, c.range, a.clone(), b.clone()));
                    }
                    links.push((a, b));
                }
                (m.name.clone(), Top::Module)
            }
            Item::Controller(c) => {
                let top_name = c.name.clone();
                self.controller(&top_name, file, c, &mut instances, &mut links, &mut async_links)?;
                // The controller's own events face the platform.
                for conn in &c.connections {
                    let (a, b, _) = ends(conn);
                    if a.0 == top_name {
                        platform.insert((top_name.clone(), a.1.clone()), Dir::In);
                        self.note_bidirectional(conn, &a.1);
                    }
                    if b.0 == top_name {
                        platform.insert((top_name.clone(), b.1.clone()), Dir::Out);
                        self.note_bidirectional(conn, &b.1);
                    }
                }
                // Inside `controller`, its own name is the controller end.
                links =
                    links.into_iter().map(|(a, b)| (rename_ctrl(a, &top_name), rename_ctrl(b, &top_name))).collect();
                platform = platform.into_iter().map(|(e, d)| (rename_ctrl(e, &top_name), d)).collect();
                (top_name, Top::Controller)
            }
            Item::Machine(b) => {
                instances.push(Instance::alone(file, b));
                (b.name.clone(), Top::Machine)
            }
            Item::Operation(b) => return self.operation_subject(file, b),
            _ => {
                let range = self.range_of(loc).ok_or_else(not_found)?;
                return Err(self.unsupported(
                    file,
                    range,
                    "only modules, controllers, state machines and operations can be checked",
                ));
            }
        };
        // RoboSim: `_async` or not, a connection between controllers or
        // machines goes through a memory cell (RT-22, `cells.rs`).
        let async_ends: BTreeSet<End> = async_links.into_iter().flat_map(|(_, _, a, b)| [a, b]).collect();
        self.build(&top_name, top, instances, &links, &platform, &async_ends)
    }

    /// RT-11: the operation `b` (of `file`) on its own, as RoboTool's `O__`
    /// of it: its body as a machine's (reaching its final state
    /// terminates), its parameters constants of the process.
    fn operation_subject(&mut self, file: File, b: &'a Behaviour) -> Result<Design, Unsupported> {
        self.op_subject = true;
        if self.robosim {
            self.sim_operation_supported(file, b)?;
        }
        let inst = Instance::alone(file, b);
        let mut design = self.build(&b.name, Top::Machine, vec![inst], &[], &HashMap::new(), &BTreeSet::new())?;
        if self.robosim {
            design.level = Level::Operation;
        }
        Ok(design)
    }

    /// RT-11: what the native checker reads of a RoboSim operation on its
    /// own (RoboTool's `OP_…::O__`, e.g. the reference's
    /// `csp-gen/sim/defs/pkg223_aggregation_sim_clone_normal_Movement_Turning_RandomTurn_entry.csp`),
    /// refusing the rest with the reason. That process has no memory for
    /// what the operation requires or reads (`varMemory = terminate ->
    /// SKIP`): each step of its `Transitions` starts by reading them with
    /// visible `get_x?x` events whose values the environment chooses, and
    /// writes are visible `set_x!v` events; no reference output has an
    /// `exec`-triggered transition in an operation.
    fn sim_operation_supported(&self, file: File, b: &'a Behaviour) -> Result<(), Unsupported> {
        let refuse = |range, what: &str| {
            Err(self.unsupported(
                file,
                range,
                format!(
                    "the RoboSim operation `{}` {what}: RoboTool's process for it on its own (`OP_…::O__`) has no \
                     memory for them, so it reads them with visible events at every step (`get_x?x`, values chosen \
                     by the environment) and writes or resets them with visible events (`set_x!v`, `clockReset`), \
                     which the native checker does not model yet (check a machine that calls it)",
                    b.name
                ),
            ))
        };
        let has_vars =
            |d: &model::Decls| d.decls.iter().any(|x| matches!(x, model::Decl::Vars { is_const: false, .. }));
        let has_clocks = |d: &model::Decls| d.decls.iter().any(|x| matches!(x, model::Decl::Clock { .. }));
        for u in &b.decls.uses {
            if self.interface(u.target).is_some_and(|(_, d)| has_vars(d)) {
                return refuse(u.range, "requires variables");
            }
            // Its own clocks are served inside its process (`Clocks`); an
            // interface's are reset and read with visible events.
            if self.interface(u.target).is_some_and(|(_, d)| has_clocks(d)) {
                return refuse(u.range, "requires clocks");
            }
        }
        for (io, ctx) in &b.contexts {
            let reads = *io == Io::Input && (!ctx.decls.is_empty() || !ctx.uses.is_empty());
            let vars =
                has_vars(ctx) || ctx.uses.iter().any(|u| self.interface(u.target).is_some_and(|(_, d)| has_vars(d)));
            if reads || vars {
                return refuse(b.name_range, "reads inputs or variables of the platform");
            }
        }
        if let Some(range) = b.region.exec_in_composite() {
            return Err(self.unsupported(
                file,
                range,
                format!(
                    "the RoboSim operation `{}` has an `exec` inside a composite state: in RoboTool's process the \
                     composite's own transitions may interrupt what runs inside it before `endexec`, which the \
                     native checker does not model for an operation on its own",
                    b.name
                ),
            ));
        }
        if let Some(t) = b.region.exec_transition() {
            return Err(self.unsupported(
                file,
                t.exec_range.unwrap_or(t.range),
                format!(
                    "the RoboSim operation `{}` has an `exec`-triggered transition: how RoboTool's process for the \
                     operation on its own (`OP_…::O__`) takes one (is `endexec` its trigger, its guard evaluated \
                     again after time passes?) is not established by any generated output (an `exec` statement \
                     in an action is: `endexec`, then `startexec`)",
                    b.name
                ),
            ));
        }
        Ok(())
    }

    /// The range of the element `loc`'s declaration.
    fn range_of(&self, loc: ItemLoc) -> Option<TextRange> {
        let id = loc.def(self.db)?;
        Some(file_defs(self.db, loc.file).def(id).range)
    }

    /// The machine `name` declared inside the controller `ctrl`, on its own
    /// (every event faces the environment). RoboTool generates such a
    /// machine only inside its controller's module, "in the context of a
    /// controller": the operations the controller defines are inlined, the
    /// others are urgent visible call events (`opCall`) (RT-19; the comment
    /// on "Operation calls" in the reference's `defs/pkg223__MovementC.csp`).
    /// Only a machine declared at package level is ever "in isolation",
    /// with every required operation undefined.
    fn inner_machine(&mut self, file: File, ctrl: &'a Controller, name: &str) -> Result<Design, Unsupported> {
        let (mut instances, mut links, mut async_links) = (Vec::new(), Vec::new(), Vec::new());
        self.controller(&ctrl.name, file, ctrl, &mut instances, &mut links, &mut async_links)?;
        let mut inst = instances.into_iter().find(|i| i.inline && i.name == name).ok_or_else(|| {
            self.unsupported(file, ctrl.range, format!("the controller declares no state machine `{name}`"))
        })?;
        inst.ctrl = String::new();
        self.build(name, Top::Machine, vec![inst], &[], &HashMap::new(), &BTreeSet::new())
    }

    /// Collects the machines of a controller (referenced or inline) and its
    /// connections, with ends named `ctrl.machine` for machines and `ctrl`
    /// for the controller itself.
    fn controller(
        &mut self,
        cref: &str,
        file: File,
        node: &'a Controller,
        instances: &mut Vec<Instance<'a>>,
        links: &mut Vec<(End, End)>,
        async_links: &mut Vec<AsyncLink>,
    ) -> Result<(), Unsupported> {
        let ctrl_name = &node.name;
        let mut machines = BTreeSet::new();
        for m in &node.machines {
            let (mf, body, inline) = match &m.def {
                Definition::Inline(b) => (file, &**b, true),
                Definition::Ref { target, .. } => match (target, self.item(*target)) {
                    (Some(t), Some(Item::Machine(b))) => (t.file, b, false),
                    _ => {
                        return Err(self.unsupported(
                            file,
                            m.range,
                            "the referenced state machine could not be resolved",
                        ))
                    }
                },
            };
            machines.insert(m.name.clone());
            instances.push(Instance {
                ctrl: cref.to_string(),
                name: m.name.clone(),
                decl_name: body.name.clone(),
                file: mf,
                body,
                inline,
                ops: Vec::new(),
            });
        }
        let mut ops: Vec<OpDef<'a>> = Vec::new();
        for o in &node.operations {
            match &o.def {
                Definition::Inline(b) => ops.push((o.name.clone(), file, b)),
                Definition::Ref { target, .. } => match (target, self.item(*target)) {
                    // A machine calls the operation by its own name (the
                    // signature its required interface declares), not by the
                    // reference's: `opref op_ref0 = Move` serves `Move()`.
                    (Some(t), Some(Item::Operation(b))) => ops.push((b.name.clone(), t.file, b)),
                    _ => return Err(self.unsupported(file, o.range, "the referenced operation could not be resolved")),
                },
            }
        }
        // The controller's operations serve every one of its machines.
        for inst in instances.iter_mut().filter(|i| i.ctrl == cref) {
            inst.ops = ops.clone();
        }
        for c in &node.connections {
            let (a, b, is_async) = ends(c);
            let qualify = |e: End| -> End {
                if machines.contains(&e.0) {
                    (format!("{cref}.{}", e.0), e.1)
                } else if e.0 == *ctrl_name {
                    (cref.to_string(), e.1)
                } else {
                    e
                }
            };
            let (a, b) = (qualify(a), qualify(b));
            if is_async && a.0.contains('.') && b.0.contains('.') {
                // RoboTool gives an asynchronous link between two machines
                // no semantics (its warning Cn11, RC:Cn11; RT-12 pins the
                // buffer between controllers): checked only under a
                // buffer the user assumes.
                if !self.robosim && self.defaults.async_buffer.is_none() {
                    return Err(self.unsupported(
                        file,
                        c.range,
                        "an asynchronous connection between two machines of a controller has no semantics in \
                         RoboTool (RC:Cn11; RT-12 gives its buffer between controllers only): assume a buffer \
                         with `--async-buffer` (e.g. `1:overwrite`, RoboTool's between controllers) to check it",
                    ));
                }
                async_links.push((file, c.range, a.clone(), b.clone()));
            }
            links.push((a, b));
        }
        Ok(())
    }

    fn build(
        &mut self,
        top_name: &str,
        top: Top,
        instances: Vec<Instance<'a>>,
        links: &[(End, End)],
        platform: &HashMap<End, Dir>,
        async_ends: &BTreeSet<End>,
    ) -> Result<Design, Unsupported> {
        // RT-5: the domains are widened by the values of the project's
        // expressions (`domains`: RoboChart's models in RoboChart's script,
        // its RoboChart and RoboSim models in RoboSim's, which a RoboSim
        // element or a `.rsa` file's assertion is checked in).
        let mut widened = Vec::new();
        if let Some(first) = instances.first() {
            let project = robosim_hir::index::project_of(self.db, self.ws, first.file);
            let robosim = self.robosim || self.defaults.robosim_script;
            let inputs = self.defaults.domain_inputs();
            let computed = robosim_hir::domains::number_domains(self.db, self.ws, project, inputs, robosim)
                .as_ref()
                .map_err(|e| Unsupported {
                    message: e.message.clone(),
                    location: e.location.map(|(f, r)| (f.path(self.db).clone(), r)),
                })?;
            [self.defaults.nat, self.defaults.int, self.defaults.real] =
                computed.domains.map(|d| Dom { lo: d.lo, hi: d.hi });
            widened = computed.notes();
            // The values an assertion gives constants widen nothing: RoboTool
            // computes with the domains above whatever they are (`PI / av`
            // with PI = 45, av = 15 is `Div(45, 15, {-2..2})`, 45), and a
            // value sent or assigned outside its type stops FDR with an
            // error (`EvalError::OutOfDomain`).
            self.defaults.fixed = [true; 3];
        }
        self.design = Some(Design {
            name: top_name.to_string(),
            level: match top {
                Top::Module => Level::Module,
                Top::Controller => Level::Controller,
                Top::Machine => Level::Machine,
            },
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
            defaults: widened,
            readings: Vec::new(),
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
                // controller; one the machine never uses needs no channel.
                //
                // RoboSim: no channel, and `machine.rs` refuses the event
                // where its meaning matters. The facts do not settle it
                // (RT-15 is RoboChart's; RT-20 … RT-22 are about connected
                // events) and the reference output has no RoboSim
                // controller (`csp-gen/sim` holds the machine `Movement`
                // only). What it shows: a machine reads every input register
                // at each cycle's start, used or not (`Cycle =
                // Deadline((registerRead.i_obstacle?x__ -> SKIP ||| …);
                // startexec -> …, 0)`), and accepts only the writes of its own
                // outputs (`CollectOutputs`). So an output the machine never
                // writes changes nothing, whatever the controller does with
                // it; but an input connected to nothing is read every cycle,
                // and verdicts differ between hiding that read (RT-15's
                // analogue: an internal choice of its value), leaving it to
                // the environment (visible), or giving it no partner (the
                // paper's Rule 10 synchronises the machines' `registerReadC`
                // with the controller's cycle, which reads only the
                // connected inputs): a deadlock in the first cycle.
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
            // RoboSim's `_async` is a memory cell too (RT-22, `cells.rs`).
            if buffered && receivers > 1 && !robosim {
                return Err(format!(
                    "event `{}` is sent asynchronously to {receivers} receivers: not supported yet",
                    machine_end.1
                ));
            }
            Ok(Some(Link { name, dir, internal: true, buffered, hidden: false, receivers }))
        };
        let lone = top == Top::Machine;
        self.lone = lone;
        self.machine_count = instances.len();
        let mut slot: u16 = 0;
        for inst in &instances {
            let end: End = (format!("{}.{}", inst.ctrl, inst.name), String::new());
            // A machine on its own: every event faces the environment, as an
            // input if the machine ever receives it (a RoboSim machine: if
            // its input context declares it), else as an output.
            let mut received = received_events(inst.body);
            if self.robosim {
                received.extend(self.input_context_events(inst.body));
            }
            let mut used = communicated_events(inst.body);
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
        if !self.robosim {
            crate::eager::mark_paused_comms(&mut design, &shared);
            crate::eager::mark_paused_durings(&mut design, &shared);
            crate::reads::mark_reads(&mut design, &shared, &mut slot);
        }
        design.slots = slot;
        design.files = self.files.iter().map(|f| f.path(self.db).clone()).collect();
        Ok(design)
    }

    /// RT-16: the forwarding of each variable a controller provides to
    /// several machines: a slot of the machines still to update, and each
    /// machine's writes marked with it (its assignments, and the writes of
    /// values it receives: [`Machine::copy_forwards`]).
    fn forwards(
        &mut self,
        design: &mut Design,
        slot: &mut u16,
        shared: &mut std::collections::HashSet<u16>,
    ) -> Result<(), Unsupported> {
        for (key, copies) in std::mem::take(&mut self.copies) {
            let Some(&(ctrl, _)) = self.shared_vars.get(&key) else { continue };
            // Keyed `controller::x` (`Cx::shared_variable`).
            let name = key.rsplit("::").next().unwrap_or(&key);
            let pending = *slot;
            *slot += 1;
            shared.extend(copies.iter().map(|&(_, c)| c));
            shared.insert(pending);
            let all = (1i32 << copies.len()) - 1;
            for (k, &(mi, copy)) in copies.iter().enumerate() {
                let m = &mut design.machines[mi];
                // RoboTool receives into a local and writes it by `set_x`
                // after the event (`reads.rs`, `Machine::deferred`): a
                // write like any other. RoboSim has no such step.
                if self.robosim {
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
                                "receiving into `{name}`, which the controller provides to several machines, is \
                                 not supported in RoboSim yet"
                            ),
                        ));
                    }
                }
                m.copy_forwards.push((copy, (ctrl, pending, all & !(1 << k))));
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
        inst: &Instance<'a>,
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
            node_models: Vec::new(),
            transitions: Vec::new(),
            code: Vec::new(),
            slot,
            decl_name: inst.decl_name.clone(),
            at: inst.body.range,
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
            caller: None,
            inlining: 0,
        };
        if mc.cx.op_subject {
            mc.parameters_as_constants(inst.body)?;
        }
        mc.declarations(inst.body, &external)?;
        mc.collect_nodes(&inst.body.region, None)?;
        mc.compile(&inst.body.region)?;
        let start_pc = mc.region_start(inst.body.range, None)?;
        mc.operation_bodies(&external)?;
        let first_cycle_pc = mc.code.len() as u32;
        mc.emit(Instr::Exec(start_pc));
        let exec_transition_pc = mc.code.len() as u32;
        mc.emit(Instr::ExecTransition);
        let caps = std::mem::take(&mut mc.clock_caps);
        // A simple state's during action is `(action ; SStop) /\ interrupt`
        // in RoboTool's CSPm, and each write in it a hidden `set_x` step of
        // its own: the state's transitions may interrupt it before any
        // write, also right after an event of the action (the reference's
        // `aggregation_Movement.csp`, node `During`). So each write there
        // is a step of its own, after which a trigger may come.
        for n in &mc.nodes {
            let Some((start, end)) = n.during else { continue };
            for i in &mut mc.code[start as usize..end as usize] {
                if let Instr::Assign { shared, .. } = i {
                    *shared = true;
                }
            }
        }
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
            decl_name: mc.decl_name.clone(),
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
            paused_comms: Vec::new(),
            paused_durings: Vec::new(),
            volatile: Vec::new(),
            latches: Vec::new(),
            deferred: Vec::new(),
            pending: Vec::new(),
            copy_forwards: Vec::new(),
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
fn received_events(machine: &Behaviour) -> Vec<String> {
    machine
        .communications()
        .into_iter()
        .filter(|(c, trigger)| {
            *trigger || matches!(c.part, Some(model::CommPart::Input(..) | model::CommPart::Sync(_)))
        })
        .map(|(c, _)| c.event.clone())
        .collect()
}

/// The events a machine (or an operation) communicates on, in any way.
fn communicated_events(body: &Behaviour) -> Vec<String> {
    body.communications().into_iter().map(|(c, _)| c.event.clone()).collect()
}

/// The events a machine sends a value on (`e!v`).
pub(super) fn sent_events(machine: &Behaviour) -> Vec<String> {
    machine
        .communications()
        .into_iter()
        .filter(|(c, _)| matches!(c.part, Some(model::CommPart::Output(_))))
        .map(|(c, _)| c.event.clone())
        .collect()
}

/// A connection's ends and whether it is asynchronous.
fn ends(c: &Connection) -> (End, End, bool) {
    ((c.from.clone(), c.efrom.clone()), (c.to.clone(), c.eto.clone()), c.is_async)
}
