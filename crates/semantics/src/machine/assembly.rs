//! Assembly: the memory, the behaviour and (RoboSim) the cycle put together as the machine's module.

use super::*;

impl<'e, 'a> Gen<'e, 'a> {
    /// `base`, or `base` with `x`s appended, so that it is no tagged
    /// channel's name (`v__` for an event `v`): a pattern or generator of
    /// that name would shadow the channel (or, in FDR, be the channel).
    pub(super) fn fresh_var(&self, base: &str) -> String {
        let mut n = base.to_string();
        while self.events.iter().any(|e| n.strip_suffix("__") == Some(e.csp.as_str())) {
            n.push('x');
        }
        n
    }

    pub(super) fn memory(&mut self) -> Decl {
        let params = self.memory_params();
        let mut alts = Vec::new();
        let same: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();
        let with = |i: usize, v: Expr| {
            let mut a = same.clone();
            a[i] = v;
            a
        };
        let value = self.fresh_var("v__");
        let sharable = self.sharable();
        for (i, v) in self.vars.iter().filter(|v| !v.shared).enumerate() {
            alts.push(prefix(
                format!("get_{}", v.csp),
                vec![Field::Out(name(v.csp.clone()))],
                self.memory_call(same.clone()),
            ));
            alts.push(prefix(
                format!("set_{}", v.csp),
                vec![Field::In(value.clone())],
                self.memory_call(with(i, name(value.clone()))),
            ));
            // RT-16: the controller forwards another machine's write.
            if sharable.contains(&i) {
                alts.push(prefix(
                    format!("set_EXT_{}", v.csp),
                    vec![Field::In(value.clone())],
                    self.memory_call(with(i, name(value.clone()))),
                ));
            }
        }
        let nv = self.vars.iter().filter(|v| !v.shared).count();
        let armed = self.armed_clocks();
        let mut ticked = same.clone();
        for (k, c) in self.clocks.iter().enumerate() {
            let i = nv + k;
            if c.read {
                alts.push(prefix(
                    format!("get_{}", c.csp),
                    vec![Field::Out(name(c.csp.clone()))],
                    self.memory_call(same.clone()),
                ));
            }
            // A composite's clock restarts only through `restart_` (below).
            if !armed.contains(&k) {
                alts.push(prefix(format!("reset_{}", c.csp), vec![], self.memory_call(with(i, Expr::Int(0)))));
            }
            ticked[i] = call("ClockTick", vec![name(c.csp.clone()), name(format!("ClockMax__{}", c.csp))]);
        }
        // A composite's clock: armed when it is entered, restarted by the
        // first substate's `entered` after that.
        let first_flag = params.len() - armed.len();
        for (j, &k) in armed.iter().enumerate() {
            let (clock, flag) = (nv + k, first_flag + j);
            let mut armed = same.clone();
            armed[flag] = Expr::Bool(true);
            alts.push(prefix(format!("arm_{}", self.clocks[k].csp), vec![], self.memory_call(armed)));
            let mut restarted = same.clone();
            restarted[clock] =
                Expr::If(Box::new(same[flag].clone()), Box::new(Expr::Int(0)), Box::new(same[clock].clone()));
            restarted[flag] = Expr::Bool(false);
            alts.push(prefix(format!("restart_{}", self.clocks[k].csp), vec![], self.memory_call(restarted)));
        }
        self.push_tock(&mut alts, self.memory_call(ticked));
        // RoboSim: the cycle's reads update the inputs (Rule 5).
        let mut pos = nv + self.clocks.len();
        for e in self.events.iter().filter(|e| self.is_input(e)) {
            let ctor = self.ex.in_reg(&e.name);
            let mut fields = vec![Field::Dot(name(ctor)), Field::In("b__".into())];
            let mut args = same.clone();
            args[pos] = name("b__");
            if let Some(t) = &e.ty {
                let (f, v) = t.input_fields("x__");
                fields.extend(f);
                args[pos + 1] = v;
                pos += 1;
            }
            pos += 1;
            alts.push(prefix("registerRead", fields, self.memory_call(args)));
        }
        for g in &self.gates {
            alts.push(self.gate(g));
        }
        if self.robosim {
            if !self.sim_op {
                if self.uses_exec_stmt {
                    alts.push(prefix("endexec__", vec![Field::Dot(name("TID_exec"))], self.memory_call(same.clone())));
                }
                alts.push(prefix("endexec__", vec![Field::Dot(name("TID_final"))], self.memory_call(same.clone())));
            }
            alts.push(prefix("terminate", vec![], Expr::Skip));
        } else {
            alts.push(prefix("end__", vec![], Expr::Skip));
        }
        Decl::Def("Memory__".into(), params, ext(alts))
    }

    pub(super) fn assemble(&mut self, module: &str) -> Vec<Decl> {
        if !self.timed() {
            // RT-9: the untimed semantics has no clocks (their resets are
            // gone; their reads were refused).
            self.clocks.clear();
        }
        let mut private = Vec::new();
        let mut exports = Vec::new();
        // Identifiers.
        let mut tids: Vec<(String, Vec<Expr>)> = self.trans.iter().map(|t| (t.tid.clone(), vec![])).collect();
        if self.robosim && !self.sim_op {
            if self.uses_exec_stmt {
                tids.push(("TID_exec".into(), vec![]));
            }
            tids.push(("TID_final".into(), vec![]));
        }
        if tids.is_empty() {
            tids.push(("TID_none".into(), vec![]));
        }
        let mut sids: Vec<(String, Vec<Expr>)> = self
            .nodes
            .iter()
            .filter(|n| matches!(n.kind, NodeKind::State | NodeKind::Final))
            .map(|n| (format!("SID_{}", n.tag), vec![]))
            .collect();
        if sids.is_empty() {
            sids.push(("SID_none".into(), vec![]));
        }
        private.push(Decl::Comment("Transition identifiers.".into()));
        private.push(Decl::Datatype("TIDS".into(), tids));
        private.push(Decl::Channel(vec!["internal__".into()], vec![name("TIDS")]));
        let mut hidden = vec![name("internal__")];
        let mut sync = vec![name("internal__")];
        if self.timed() {
            sync.push(name("tock"));
        }
        for e in &self.events {
            if e.trig {
                let mut f = vec![name("TIDS"), name("InOut")];
                f.extend(e.ty.iter().flat_map(|t| t.field_sets()));
                private.push(Decl::Channel(vec![format!("{}__", e.csp)], f));
                sync.push(name(format!("{}__", e.csp)));
            }
        }
        if !self.vars.is_empty() || !self.clocks.is_empty() {
            private.push(Decl::Comment("Memory: variables and clocks.".into()));
        }
        let sharable = self.sharable();
        let mut shared_chans = Vec::new();
        for (i, v) in self.vars.iter().filter(|v| !v.shared).enumerate() {
            let (get, set) = (format!("get_{}", v.csp), format!("set_{}", v.csp));
            if sharable.contains(&i) {
                // RT-16: its writes left visible in P__, for a controller
                // that shares it (`DS__`); `D__` hides them.
                private.push(Decl::Channel(vec![get.clone()], vec![v.ty.set()]));
                hidden.push(name(get.clone()));
                shared_chans.push(Decl::Channel(vec![set.clone(), format!("set_EXT_{}", v.csp)], vec![v.ty.set()]));
                sync.extend([name(get), name(set)]);
                continue;
            }
            private.push(Decl::Channel(vec![get.clone(), set.clone()], vec![v.ty.set()]));
            for c in [get, set] {
                hidden.push(name(c.clone()));
                sync.push(name(c));
            }
        }
        let armed = self.armed_clocks();
        for (k, c) in self.clocks.iter().enumerate() {
            // A composite's clock is armed and restarted, never reset.
            let chans = match armed.contains(&k) {
                true => vec![format!("arm_{}", c.csp), format!("restart_{}", c.csp)],
                false => vec![format!("reset_{}", c.csp)],
            };
            for ch in chans {
                private.push(Decl::Channel(vec![ch.clone()], vec![]));
                hidden.push(name(ch.clone()));
                sync.push(name(ch));
            }
            if c.read {
                private.push(Decl::Channel(vec![format!("get_{}", c.csp)], vec![name("core_clock_type")]));
                hidden.push(name(format!("get_{}", c.csp)));
                sync.push(name(format!("get_{}", c.csp)));
            }
        }
        if self.sim_op {
            // Visible: RoboTool's process for the operation on its own has
            // them in its alphabet (`sem__events`).
            exports.push(Decl::Comment("`exec`: `endexec`, then `startexec`, both visible (RT-11).".into()));
            exports.push(Decl::Channel(vec!["endexec".into(), "startexec".into()], vec![]));
            exports.extend(self.sim_call_channels("Calls of other operations (urgent)."));
        } else if self.robosim {
            // RT-19: the software operations nothing defines for it.
            exports.extend(self.sim_call_channels("Calls of operations its controller does not define (urgent)."));
            private.push(Decl::Comment("Cycle events (Rules 4 and 6).".into()));
            private.push(Decl::Channel(vec!["startexec".into()], vec![]));
            private.push(Decl::Channel(vec!["endexec__".into()], vec![name("TIDS")]));
            if self.profile == Profile::Paper2019 && !self.output_regs().is_empty() {
                private.push(Decl::Comment("The outputs buffer (Rule 12).".into()));
                private.push(Decl::Channel(vec!["stmout".into()], vec![name("RegisterDataOutput")]));
                private.push(Decl::Datatype(
                    "BufOut__".into(),
                    vec![("noOut__".into(), vec![]), ("out__".into(), vec![name("RegisterDataOutput")])],
                ));
                private.push(Decl::Channel(vec!["cyclein".into()], vec![name("BufOut__")]));
            }
        } else {
            private.push(Decl::Channel(vec!["end__".into()], vec![]));
            hidden.push(name("end__"));
            sync.push(name("end__"));
        }
        if self.active.contains(&true) {
            private.push(Decl::Comment("Start and end of the timers of states (deadlines of transitions).".into()));
            private.push(Decl::Channel(vec!["activate__".into(), "deactivate__".into()], vec![name("SIDS")]));
            hidden.extend([name("activate__"), name("deactivate__")]);
        }
        if self.during.contains(&true) {
            private.push(Decl::Comment(
                "A substate has finished its entry action: the during action of its composite state starts\n\
                 (RT-17)."
                    .into(),
            ));
            private.push(Decl::Channel(vec!["ready__".into()], vec![name("SIDS")]));
            hidden.push(name("ready__"));
        }
        // Exported interface.
        exports.push(Decl::Comment(
            "State identifiers (final states too); `entered__` marks the entry into a state.".into(),
        ));
        exports.push(Decl::Datatype("SIDS".into(), sids));
        exports.push(Decl::Channel(vec!["entered__".into()], vec![name("SIDS")]));
        let shared: Vec<&VarI> = self.vars.iter().filter(|v| v.shared).collect();
        if !shared.is_empty() {
            exports.push(Decl::Comment("The caller's variables, in the caller's memory.".into()));
        }
        for v in shared {
            exports.push(Decl::Channel(vec![format!("get_{}", v.csp), format!("set_{}", v.csp)], vec![v.ty.set()]));
        }
        if !shared_chans.is_empty() {
            exports.push(Decl::Comment(
                "Its required variables (RT-16): its writes, and the updates of its copy by its controller\n\
                 (RoboTool's `shared_variable_events`)."
                    .into(),
            ));
            exports.append(&mut shared_chans);
        }
        if !self.robosim {
            for e in &self.events {
                let mut f = vec![name("InOut")];
                f.extend(e.ty.iter().flat_map(|t| t.field_sets()));
                exports.push(Decl::Channel(vec![e.csp.clone()], f));
            }
            for o in self.ops.iter().filter(|o| !o.defined) {
                let f: Vec<Expr> = o.params.iter().map(|t| t.set()).collect();
                exports.push(Decl::Channel(vec![op_event(&o.name, "Call")], f));
                if self.profile == Profile::Paper2019 {
                    exports.push(Decl::Channel(vec![op_event(&o.name, "Ret")], vec![]));
                }
            }
        } else {
            // Registers of the machine.
            let inputs: Vec<(String, Vec<Expr>)> = self
                .events
                .iter()
                .filter(|e| self.is_input(e))
                .map(|e| (self.ex.in_reg(&e.name), e.ty.iter().flat_map(|t| t.field_sets()).collect()))
                .collect();
            let outputs = self.output_regs();
            for (c, v) in &inputs {
                if let Err(m) = self.ex.register(true, c, v) {
                    self.problem(self.name_range, m);
                }
            }
            for (c, v) in &outputs {
                if let Err(m) = self.ex.register(false, c, v) {
                    self.problem(self.name_range, m);
                }
            }
            // RoboTool's names of its own (an operation on its own
            // declares its `endexec` above).
            exports.extend(crate::sim_names::own_names(self.profile, &inputs, &outputs, !self.sim_op));
        }

        // The let of P__.
        let mut lets = Vec::new();
        for c in &self.clocks {
            let mut bound = Expr::Int(0);
            for b in &c.bounds {
                bound = call("Max__", vec![bound, b.clone()]);
            }
            let bound = if c.unbounded || c.read {
                name("core_clock_max")
            } else {
                call("Min__", vec![bound, name("core_clock_max")])
            };
            lets.push(Decl::Def(format!("ClockMax__{}", c.csp), vec![], bin(BinOp::Add, bound, Expr::Int(1))));
        }
        let start_node = self.nodes.iter().position(|n| n.parent.is_none() && n.kind == NodeKind::Initial);
        let Some(start_node) = start_node else {
            self.problem(self.name_range, "the machine has no initial junction");
            return Vec::new();
        };
        let start = self.enter(start_node);
        if self.sim_op {
            // No cycle: the operation starts at once.
            lets.push(Decl::Def("Behaviour__".into(), vec![], start.clone()));
            if self.uses_exec_stmt {
                lets.push(Decl::Def(
                    "Exec__".into(),
                    vec![],
                    ext(vec![prefix("endexec", vec![], name("StartExec__")), prefix("tock", vec![], name("Exec__"))]),
                ));
                lets.push(Decl::Def(
                    "StartExec__".into(),
                    vec![],
                    ext(vec![prefix("startexec", vec![], Expr::Skip), prefix("tock", vec![], name("StartExec__"))]),
                ));
            }
        } else if self.robosim {
            lets.push(Decl::Def(
                "StartExec__".into(),
                vec![],
                ext(vec![prefix("startexec", vec![], Expr::Skip), prefix("tock", vec![], name("StartExec__"))]),
            ));
            lets.push(Decl::Def("Behaviour__".into(), vec![], seq(vec![name("StartExec__"), start.clone()])));
        } else {
            lets.push(Decl::Def("Behaviour__".into(), vec![], start.clone()));
        }
        lets.append(&mut self.defs);
        lets.extend(std::mem::take(&mut self.op_calls).into_iter().map(|(_, d)| d));
        if self.sim_op {
            // Reaching the final state ends the operation (`terminate`, hidden by D__).
            lets.push(Decl::Def("Ending__".into(), vec![], prefix("terminate", vec![], Expr::Skip)));
        } else if self.robosim {
            // Rule 13: a finished machine keeps ending its cycles until all agree to terminate.
            lets.push(Decl::Def(
                "Ending__".into(),
                vec![],
                prefix("endexec__", vec![Field::Dot(name("TID_final"))], name("EndWait__")),
            ));
            lets.push(Decl::Def(
                "EndWait__".into(),
                vec![],
                ext(vec![
                    prefix("startexec", vec![], name("Ending__")),
                    prefix("terminate", vec![], Expr::Skip),
                    prefix("tock", vec![], name("EndWait__")),
                ]),
            ));
        }
        lets.push(self.memory());
        let init: Vec<Expr> = self
            .vars
            .iter()
            .filter(|v| !v.shared)
            .map(|v| v.init.clone())
            .chain(self.clocks.iter().map(|_| Expr::Int(0)))
            .chain(
                self.events
                    .iter()
                    .filter(|e| self.is_input(e))
                    .flat_map(|e| {
                        let mut v = vec![Expr::Bool(false)];
                        if let Some(t) = &e.ty {
                            v.push(t.default_value());
                        }
                        v
                    })
                    .collect::<Vec<_>>(),
            )
            .chain(self.armed_clocks().into_iter().map(|_| Expr::Bool(false)))
            .collect();
        let memory = self.memory_call(init);

        let mut params = vec!["id__".to_string()];
        if self.robosim && !self.sim_op {
            params.push("cycle".into());
        }
        params.extend(self.op_params.iter().cloned());
        params.extend(self.consts.iter().map(|c| c.local.clone()));
        let args: Vec<Expr> = params.iter().map(|p| name(p.clone())).collect();

        let body = if self.sim_op {
            let mut sync = sync.clone();
            sync.push(name("terminate"));
            call(
                "TimedPriority",
                vec![hide(par(name("Behaviour__"), Expr::Events(sync), memory), Expr::Events(hidden))],
            )
        } else if self.robosim {
            let (cycle_defs, has_in, has_out) = self.cycle();
            lets.extend(cycle_defs);
            let mut inner_sync = vec![name("endexec__"), name("tock"), name("terminate")];
            if has_in {
                inner_sync.push(name("registerRead"));
            }
            let inner = par(memory, Expr::Events(inner_sync), name("Cycle__"));
            let mut outer_sync = sync.clone();
            outer_sync.extend([name("endexec__"), name("startexec"), name("terminate")]);
            // RT-21: only `startexec` is hidden; the end of the cycle is the
            // visible `endexec` (RoboTool's `STM \ {startexec}`), whichever
            // transition ends it. The paper's Rule 4 hides both.
            let visible_end = self.profile == Profile::RoboTool3;
            hidden.push(name("startexec"));
            if !visible_end {
                hidden.push(name("endexec__"));
            }
            let inner = match (self.profile, has_out) {
                (Profile::RoboTool3, true) => {
                    outer_sync.push(name("registerWrite"));
                    inner
                }
                // Rule 3: the outputs go through the buffer to the cycle.
                (Profile::Paper2019, true) => {
                    outer_sync.push(name("stmout"));
                    hidden.extend([name("stmout"), name("cyclein")]);
                    par(name("Buffer__"), Expr::Events(vec![name("cyclein")]), inner)
                }
                (_, false) => inner,
            };
            let comp = par(name("Behaviour__"), Expr::Events(outer_sync), inner);
            let mut comp = hide(comp, Expr::Events(hidden));
            if visible_end {
                comp = Expr::Rename(
                    Box::new(comp),
                    vec![(dot(vec![name("endexec__"), name("t__")]), name("endexec"))],
                    vec![("t__".into(), name("TIDS"))],
                );
            }
            call("TimedPriority", vec![comp])
        } else {
            let mut beh = seq(vec![name("Behaviour__"), prefix("end__", vec![], Expr::Skip)]);
            if !self.activities.is_empty() {
                // Each in parallel with those after it, sharing the
                // triggers that stop both (a during action and one around it).
                let mut acts: Option<(Expr, std::collections::BTreeSet<usize>)> = None;
                for (a, stops) in std::mem::take(&mut self.activities).into_iter().rev() {
                    let stops: std::collections::BTreeSet<usize> = stops.into_iter().collect();
                    acts = Some(match acts {
                        None => (name(a), stops),
                        Some((acc, seen)) => {
                            let mut sync = self.time_events(&["tock", "end__"]);
                            for &t in stops.intersection(&seen) {
                                sync.extend(self.trigger_event(t));
                            }
                            (par(name(a), Expr::Events(sync), acc), seen.union(&stops).copied().collect())
                        }
                    });
                }
                let (acts, stops) = acts.expect("an activity");
                let mut with = Vec::new();
                if self.active.contains(&true) {
                    with.extend([name("activate__"), name("deactivate__")]);
                }
                if self.during.contains(&true) {
                    with.push(name("ready__"));
                }
                with.extend(self.time_events(&["tock", "end__"]));
                for t in stops {
                    with.extend(self.trigger_event(t));
                }
                beh = par(beh, Expr::Events(with), acts);
            }
            let comp = hide(par(beh, Expr::Events(sync), memory), Expr::Events(hidden));
            // Tagged triggers become the machine's events.
            let mut comp = comp;
            let var = |n: String| self.fresh_var(&n);
            for e in self.events.iter().filter(|e| e.trig) {
                let tagged = format!("{}__", e.csp);
                let (t, d) = (var("t__".into()), var("d__".into()));
                let mut from = vec![name(tagged.clone()), name(t.clone()), name(d.clone())];
                let mut to = vec![name(e.csp.clone()), name(d.clone())];
                let mut gens = vec![(t, name("TIDS")), (d, name("InOut"))];
                let sets: Vec<Expr> = e.ty.iter().flat_map(|t| t.field_sets()).collect();
                for (k, set) in sets.iter().cloned().enumerate() {
                    let v = var(if sets.len() == 1 { "v__".to_string() } else { format!("v{k}__") });
                    from.push(name(v.clone()));
                    to.push(name(v.clone()));
                    gens.push((v, set));
                }
                comp = Expr::Rename(Box::new(comp), vec![(dot(from), dot(to))], gens);
            }
            self.prioritised(comp)
        };
        let p_def = Decl::Def("P__".into(), params.clone(), Expr::Let(lets, Box::new(body)));
        let entered = Expr::Events(vec![name("entered__")]);
        // RT-21: a RoboSim machine on its own shows its `terminate` (and
        // `endexec`, see P__), as RoboTool's `D__`; an operation on its own
        // ends at its final state, and the paper's machine hides its end.
        let show_end = self.robosim && !self.sim_op && self.profile == Profile::RoboTool3;
        let ending = |p: Expr| {
            let p = Expr::Exception(Box::new(p), Box::new(Expr::Set(vec![name("terminate")])), Box::new(Expr::Skip));
            let p = if show_end { p } else { hide(p, Expr::Set(vec![name("terminate")])) };
            call("TimedPriority", vec![p])
        };
        let d_body = if self.robosim {
            ending(hide(call("P__", args.clone()), entered.clone()))
        } else if self.is_operation {
            self.prioritised(hide(call("P__", args.clone()), entered))
        } else {
            // RoboTool's `STM`: the end is hidden inside (`end__`), then the
            // machine offers its `terminate`, time passing meanwhile.
            self.prioritised(seq(vec![hide(self.closed(call("P__", args.clone())), entered), self.terminating()]))
        };
        let vs_body = if self.robosim {
            ending(call("P__", args.clone()))
        } else if self.is_operation {
            call("P__", args.clone())
        } else {
            seq(vec![self.closed(call("P__", args.clone())), self.terminating()])
        };
        let mut doc = vec![Decl::Comment(format!(
            "{} (parameters: {}).",
            if self.sim_op {
                "RoboTool's process for the operation on its own: P__ with `terminate` (its final state)\n\
                 visible; D__: its semantics, terminating at its final state; VS__: with `entered__`\n\
                 visible (reachability); O__: D__ compressed"
            } else if show_end {
                "P__: the machine; D__: its semantics, the end of each cycle (`endexec`) and its\n\
                 `terminate` visible (RT-21); VS__: with `entered__` visible (reachability); O__: D__\n\
                 compressed"
            } else if self.robosim {
                "P__: the machine with `terminate` visible (for composition); D__: its semantics;\n\
                 VS__: with `entered__` visible (reachability); O__: D__ compressed"
            } else if self.is_operation {
                "D__: the operation's semantics, terminating at its final state (callers rename its\n\
                 channels to theirs); VS__: with `entered__` visible; O__: D__ compressed"
            } else {
                "D__: the machine's semantics, offering `terminate` once finished; VS__: with `entered__`\n\
                 visible (reachability); O__: D__ compressed"
            },
            params.join(", ")
        ))];
        if self.robosim {
            doc.push(p_def);
        } else {
            private.push(p_def);
            if !self.is_operation {
                doc.insert(0, Decl::Comment("Its end (RoboTool's `terminate`, per machine).".into()));
                doc.insert(1, Decl::Channel(vec!["terminate".into()], vec![]));
            }
        }
        doc.push(Decl::Def("D__".into(), params.clone(), d_body));
        doc.push(Decl::Def("VS__".into(), params.clone(), vs_body));
        doc.push(Decl::Def("O__".into(), params.clone(), call("sbisim", vec![call("D__", args.clone())])));
        if !self.robosim && !self.is_operation && !self.sharable().is_empty() {
            let (ended, ds, vss) = self.sharing(&args);
            private.push(ended);
            doc.push(Decl::Comment(
                "DS__ and VSS__: D__ and VS__ with its writes of its required variables visible, and its\n\
                 copies updated by its controller, also once it has finished (RT-16)."
                    .into(),
            ));
            doc.push(Decl::Def("DS__".into(), params.clone(), ds));
            doc.push(Decl::Def("VSS__".into(), params.clone(), vss));
        }
        exports.extend(doc);
        let kind = if self.robosim { "RoboSim" } else { "RoboChart" };
        let path = self.path.clone();
        let what = if self.is_operation { "operation" } else { "state machine" };
        let alone = if self.sim_op { ", on its own (RT-11)" } else { "" };
        vec![
            Decl::Comment(format!("{kind} {what} {}{alone}", path.join("::"))),
            Decl::Module(module.to_string(), private, exports),
            Decl::Blank,
        ]
    }

    /// The channels of the RoboSim operations this machine calls as
    /// urgent events (RT-19), under `comment` when there are any.
    fn sim_call_channels(&self, comment: &str) -> Vec<Decl> {
        let mut out = Vec::new();
        for &o in &self.sim_op_calls {
            if out.is_empty() {
                out.push(Decl::Comment(comment.into()));
            }
            let f: Vec<Expr> = self.ops[o].params.iter().map(|t| t.set()).collect();
            out.push(Decl::Channel(vec![op_event(&self.ops[o].name, "Call")], f));
        }
        out
    }

    /// The indices of the variables the machine requires (among its
    /// memory's): those a controller may share with its other machines
    /// (RT-16). A RoboSim machine's and an operation's have none.
    pub(super) fn sharable(&self) -> Vec<usize> {
        if self.robosim || self.is_operation {
            return Vec::new();
        }
        let mut out: Vec<usize> = self
            .required
            .iter()
            .filter_map(|n| match self.names.get(n) {
                Some(Nm::Var(i)) if !self.vars[*i].shared => Some(*i),
                _ => None,
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// `p` with the writes of its required variables hidden and their
    /// updates from a controller refused: the machine on its own, or in a
    /// controller that does not share them (RoboTool's `HEXT__` blocks its
    /// `shared_variable_events` likewise).
    pub(super) fn closed(&self, p: Expr) -> Expr {
        let sharable = self.sharable();
        if self.robosim || self.is_operation || sharable.is_empty() {
            return p;
        }
        let writes = sharable.iter().map(|&i| name(format!("set_{}", self.vars[i].csp))).collect();
        let updates = sharable.iter().map(|&i| name(format!("set_EXT_{}", self.vars[i].csp))).collect();
        par(hide(p, Expr::Events(writes)), Expr::Events(updates), Expr::Skip)
    }

    /// RT-16: `Ended__` (once finished, the machine still takes its
    /// controller's updates until `terminate`), and the bodies of `DS__`
    /// and `VSS__` (`args`: their parameters).
    fn sharing(&self, args: &[Expr]) -> (Decl, Expr, Expr) {
        let value = self.fresh_var("v__");
        let mut alts = vec![prefix("terminate", vec![], Expr::Skip)];
        self.push_tock(&mut alts, name("Ended__"));
        for i in self.sharable() {
            alts.push(prefix(format!("set_EXT_{}", self.vars[i].csp), vec![Field::In(value.clone())], name("Ended__")));
        }
        let ended = Decl::Def("Ended__".into(), vec![], ext(alts));
        let p = call("P__", args.to_vec());
        let ds = self.prioritised(seq(vec![hide(p.clone(), Expr::Events(vec![name("entered__")])), name("Ended__")]));
        (ended, ds, seq(vec![p, name("Ended__")]))
    }

    /// The variables the machine requires, as a controller shares them
    /// (RT-16), and those it receives into (`e?x`).
    pub(super) fn shared_vars(&self) -> (Vec<SharedVar>, Vec<(String, File, TextRange)>) {
        let sharable = self.sharable();
        let model: Vec<String> = self
            .required
            .iter()
            .filter(|n| matches!(self.names.get(*n), Some(Nm::Var(i)) if sharable.contains(i)))
            .cloned()
            .collect();
        let mut shared: Vec<SharedVar> = Vec::new();
        for n in &model {
            let Some(Nm::Var(i)) = self.names.get(n) else { continue };
            if shared.iter().any(|s| s.model == *n) {
                continue;
            }
            let v = &self.vars[*i];
            shared.push(SharedVar { model: n.clone(), csp: v.csp.clone(), ty: v.ty.clone(), init: v.init.clone() });
        }
        // Its own communications, and those of the operations it calls
        // that its controller defines (they write the caller's copy, RT-23),
        // unless one declares a variable of that name itself.
        let mut bodies: Vec<(File, &m::Behaviour)> = self.model.map(|b| (self.file, b)).into_iter().collect();
        for o in self.ops.iter().filter(|o| o.defined) {
            if let Some((_, f, b, _)) = self.op_definition(&o.name) {
                bodies.push((f, b));
            }
        }
        let mut receives = Vec::new();
        for (k, (f, b)) in bodies.into_iter().enumerate() {
            let own = |v: &str| {
                k > 0
                    && b.decls
                        .decls
                        .iter()
                        .any(|d| matches!(d, m::Decl::Vars { vars, .. } if vars.iter().any(|x| x.name == v)))
            };
            for (c, _) in b.communications() {
                if let Some(m::CommPart::Input(var, _)) = &c.part {
                    let var = var.join("::");
                    if model.contains(&var) && !own(&var) {
                        receives.push((var, f, c.range));
                    }
                }
            }
        }
        (shared, receives)
    }

    pub(super) fn output_regs(&self) -> Vec<(String, Vec<Expr>)> {
        let mut out = Vec::new();
        for e in self.events.iter().filter(|e| e.both || !self.is_input(e)) {
            if e.io == Some(robosim_hir::model::Io::Output) || e.io.is_none() || e.both {
                out.push((self.ex.out_reg(&e.name), e.ty.iter().flat_map(|t| t.field_sets()).collect()));
            }
        }
        // Platform operations only: a software operation is run or called (RT-19).
        for o in self.ops.iter().filter(|o| o.io == Some(Io::Output)) {
            out.push((self.ex.out_reg(&o.name), o.params.iter().map(|t| t.set()).collect()));
        }
        out
    }

    /// Rule 4 as the paper states it (paper2019): read every input
    /// register, `startexec`, `endexec`, then write the buffered outputs in
    /// order (`registerWrite.o.true.args`) and the others as absent
    /// (`registerWrite.o.false.args`, any arguments), then terminate or
    /// let `cycle` time units pass; the buffer of Rule 12.
    pub(super) fn cycle_paper(&mut self, reads: Expr, has_in: bool) -> (Vec<Decl>, bool, bool) {
        let outs = self.output_regs();
        let mut d = Vec::new();
        let end = ext(vec![
            prefix("terminate", vec![], Expr::Skip),
            seq(vec![call("Wait", vec![name("cycle")]), name("Cycle__")]),
        ]);
        if outs.is_empty() {
            d.push(Decl::Def(
                "Cycle__".into(),
                vec![],
                seq(vec![reads, prefix("startexec", vec![], prefix("endexec__", vec![Field::In("t__".into())], end))]),
            ));
            return (d, has_in, false);
        }
        let flags: Vec<String> = outs.iter().map(|(c, _)| format!("w_{c}")).collect();
        let all = |v: bool| -> Vec<Expr> { flags.iter().map(|_| Expr::Bool(v)).collect() };
        d.push(Decl::Def(
            "Cycle__".into(),
            vec![],
            seq(vec![
                reads,
                prefix(
                    "startexec",
                    vec![],
                    prefix("endexec__", vec![Field::In("t__".into())], seq(vec![call("Collect__", all(true)), end])),
                ),
            ]),
        ));
        // CollectOutputs: the buffered outputs in order, then NoOther.
        let mut alts = vec![prefix(
            "cyclein",
            vec![Field::Dot(name("noOut__"))],
            call("NoOther__", flags.iter().map(|f| name(f.clone())).collect()),
        )];
        let mut others = Vec::new();
        for (k, (c, vals)) in outs.iter().enumerate() {
            let vars: Vec<String> = (0..vals.len()).map(|i| format!("x{i}__")).collect();
            let mut next: Vec<Expr> = flags.iter().map(|f| name(f.clone())).collect();
            next[k] = Expr::Bool(false);
            let mut inf = vec![Field::Dot(name("out__")), Field::Dot(name(c.clone())), Field::In("b__".into())];
            inf.extend(vars.iter().map(|v| Field::In(v.clone())));
            let mut outf = vec![Field::Dot(name(c.clone())), Field::Dot(name("b__"))];
            outf.extend(vars.iter().map(|v| Field::Dot(name(v.clone()))));
            alts.push(guard(
                name(flags[k].clone()),
                prefix("cyclein", inf, prefix("registerWrite", outf, call("Collect__", next))),
            ));
            let mut falsef = vec![Field::Dot(name(c.clone())), Field::Dot(Expr::Bool(false))];
            falsef.extend(vars.iter().map(|v| Field::In(v.clone())));
            others.push(Expr::If(
                Box::new(name(flags[k].clone())),
                Box::new(prefix("registerWrite", falsef, Expr::Skip)),
                Box::new(Expr::Skip),
            ));
        }
        d.push(Decl::Def("Collect__".into(), flags.clone(), ext(alts)));
        d.push(Decl::Def("NoOther__".into(), flags.clone(), nary(ProcOp::Interleave, others)));
        // Rule 12: the buffer, of capacity the number of outputs.
        let n = outs.len() as i64;
        d.push(Decl::Def(
            "Buffer__".into(),
            vec![],
            ext(vec![
                prefix(
                    "stmout",
                    vec![Field::In("o__".into())],
                    call("BufferF__", vec![Expr::SeqLit(vec![name("o__")])]),
                ),
                prefix("cyclein", vec![Field::Dot(name("noOut__"))], name("Buffer__")),
            ]),
        ));
        d.push(Decl::Def(
            "BufferF__".into(),
            vec!["s__".into()],
            ext(vec![
                guard(
                    bin(BinOp::Lt, call("length", vec![name("s__")]), Expr::Int(n)),
                    prefix(
                        "stmout",
                        vec![Field::In("o__".into())],
                        call("BufferF__", vec![bin(BinOp::Cat, name("s__"), Expr::SeqLit(vec![name("o__")]))]),
                    ),
                ),
                call("Flush__", vec![name("s__")]),
            ]),
        ));
        d.push(Decl::Def(
            "Flush__".into(),
            vec!["s__".into()],
            Expr::If(
                Box::new(call("null", vec![name("s__")])),
                Box::new(name("Buffer__")),
                Box::new(prefix(
                    "cyclein",
                    vec![Field::Dot(name("out__")), Field::Dot(call("head", vec![name("s__")]))],
                    call("Flush__", vec![call("tail", vec![name("s__")])]),
                )),
            ),
        ));
        (d, has_in, true)
    }

    /// Rule 4 (robotool3): read every input register (in any order, no
    /// time passing), `startexec`, accept each output register at most
    /// once until `endexec`, then terminate or let `cycle` time units pass.
    pub(super) fn cycle(&mut self) -> (Vec<Decl>, bool, bool) {
        let mut d = Vec::new();
        let reads: Vec<Expr> = self
            .events
            .iter()
            .filter(|e| self.is_input(e))
            .map(|e| {
                let mut f = vec![Field::Dot(name(self.ex.in_reg(&e.name))), Field::In("b__".into())];
                if let Some(t) = &e.ty {
                    f.extend(t.input_fields("x__").0);
                }
                prefix("registerRead", f, Expr::Skip)
            })
            .collect();
        let has_in = !reads.is_empty();
        if self.profile == Profile::Paper2019 {
            return self.cycle_paper(nary(ProcOp::Interleave, reads), has_in);
        }
        let outs = self.output_regs();
        let has_out = !outs.is_empty();
        let flags: Vec<String> = outs.iter().map(|(c, _)| format!("w_{c}")).collect();
        let mut alts = Vec::new();
        for (k, (c, _)) in outs.iter().enumerate() {
            let mut next: Vec<Expr> = flags.iter().map(|f| name(f.clone())).collect();
            next[k] = Expr::Bool(false);
            alts.push(guard(
                name(flags[k].clone()),
                Expr::Repl(
                    crate::cspm::ReplOp::ExtChoice,
                    vec![("w__".into(), Expr::Events(vec![dot(vec![name("registerWrite"), name(c.clone())])]))],
                    Box::new(prefix("w__", vec![], call("Collect__", next))),
                ),
            ));
        }
        alts.push(prefix("endexec__", vec![Field::In("t__".into())], name("CycleEnd__")));
        d.push(Decl::Def(
            "Cycle__".into(),
            vec![],
            seq(vec![
                nary(ProcOp::Interleave, reads),
                prefix(
                    "startexec",
                    vec![],
                    if flags.is_empty() {
                        call("Collect__", vec![])
                    } else {
                        call("Collect__", flags.iter().map(|_| Expr::Bool(true)).collect())
                    },
                ),
            ]),
        ));
        let collect = ext(alts);
        if flags.is_empty() {
            d.push(Decl::Def("Collect__".into(), vec![], collect));
        } else {
            d.push(Decl::Def("Collect__".into(), flags, collect));
        }
        d.push(Decl::Def(
            "CycleEnd__".into(),
            vec![],
            ext(vec![
                prefix("terminate", vec![], Expr::Skip),
                prefix(
                    "tock",
                    vec![],
                    seq(vec![call("Wait", vec![bin(BinOp::Sub, name("cycle"), Expr::Int(1))]), name("Cycle__")]),
                ),
            ]),
        ));
        // A machine without outputs: `Collect__` is a plain name.
        if outs.is_empty() {
            for x in d.iter_mut() {
                replace_call(x, "Collect__");
            }
        }
        (d, has_in, has_out)
    }

    /// The machine's interface for its users.
    pub(super) fn interface(&self, module: String, path: Vec<String>) -> Elem {
        let (shared, receives) = self.shared_vars();
        let mut chans = Vec::new();
        let mut inputs = Vec::new();
        let mut outputs = Vec::new();
        if self.robosim {
            for e in self.events.iter().filter(|e| self.is_input(e)) {
                inputs.push(Reg {
                    ctor: self.ex.in_reg(&e.name),
                    model: e.name.clone(),
                    values: e.ty.iter().flat_map(|t| t.field_sets()).collect(),
                });
            }
            for e in self.events.iter().filter(|e| e.both || !self.is_input(e)) {
                outputs.push(Reg {
                    ctor: self.ex.out_reg(&e.name),
                    model: e.name.clone(),
                    values: e.ty.iter().flat_map(|t| t.field_sets()).collect(),
                });
            }
            for o in self.ops.iter().filter(|o| o.io == Some(Io::Output)) {
                outputs.push(Reg {
                    ctor: self.ex.out_reg(&o.name),
                    model: o.name.clone(),
                    values: o.params.iter().map(|t| t.set()).collect(),
                });
            }
            for &k in &self.sim_op_calls {
                chans.push(call_chan(&self.ops[k]));
            }
        } else {
            for e in &self.events {
                let values: Vec<Expr> = e.ty.iter().flat_map(|t| t.field_sets()).collect();
                let mut fields = vec![name("InOut")];
                fields.extend(values.iter().cloned());
                chans.push(Chan {
                    csp: e.csp.clone(),
                    model: e.name.clone(),
                    kind: ChanKind::Event,
                    fields,
                    dir: if e.received { Dir::In } else { Dir::Out },
                    values,
                });
            }
            for o in self.ops.iter().filter(|o| !o.defined) {
                chans.push(call_chan(o));
                if self.profile == Profile::Paper2019 {
                    chans.push(Chan {
                        csp: op_event(&o.name, "Ret"),
                        model: o.name.clone(),
                        kind: ChanKind::Ret,
                        fields: vec![],
                        dir: Dir::In,
                        values: vec![],
                    });
                }
            }
        }
        Elem {
            kind: ElemKind::Machine,
            robosim: self.robosim,
            module,
            path,
            consts: self.consts.clone(),
            chans,
            inputs,
            outputs,
            period: crate::compose::declared_period(self.ex.db, self.ex.ws, self.file, self.model.and_then(|b| b.def))
                .unwrap_or(1),
            required: self.required.clone(),
            shared,
            receives,
            parts: Vec::new(),
            states: self.state_tags(),
            functions: self.fn_calls.clone(),
        }
    }
}

/// The urgent call event `opCall` of the operation `o`, which the machine
/// calls but nothing defines for it.
fn call_chan(o: &super::OpI) -> Chan {
    let values: Vec<Expr> = o.params.iter().map(|t| t.set()).collect();
    Chan {
        csp: op_event(&o.name, "Call"),
        model: o.name.clone(),
        kind: ChanKind::Call,
        fields: values.clone(),
        dir: Dir::Out,
        values,
    }
}
