//! The behaviour: one process per state, junction and final node, offering the transitions.

use super::*;

impl<'e, 'a> Gen<'e, 'a> {
    pub(super) fn enter(&self, n: usize) -> Expr {
        let node = &self.nodes[n];
        match node.kind {
            NodeKind::State => name(format!("Enter__{}", node.tag)),
            NodeKind::Junction | NodeKind::Initial => name(format!("Junction__{}", node.tag)),
            // RoboTool's final state has an `entered` of its own (`Entering
            // = entered -> SKIP ; Active`), which its composite's waits for
            // as a substate's.
            NodeKind::Final => {
                let mut parts = if self.after_entry() {
                    self.entered_marks(n)
                } else {
                    vec![prefix("entered__", vec![Field::Dot(name(format!("SID_{}", node.tag)))], Expr::Skip)]
                };
                parts.push(match node.parent {
                    Some(_) => self.ready(n, name(format!("Rest__{}", node.tag))),
                    None if self.robosim => name("Ending__"),
                    None => Expr::Skip,
                });
                fold_seq(parts)
            }
        }
    }

    /// Whether a state's `entered` follows its entry action (and a
    /// composite's its first substate's), as in RoboTool 3's semantics,
    /// RoboChart's and RoboSim's alike (`Active = entry ; Behaviour`,
    /// `Behaviour = entered -> During` in `csp-gen/timed` and
    /// `csp-gen/sim`); the 2019 paper's semantics marks the entry at its
    /// start.
    pub(super) fn after_entry(&self) -> bool {
        self.profile != Profile::Paper2019
    }

    /// What follows the entry action of the simple or final state `n`
    /// (`after_entry`): `entered__` of `n` and of each state around it,
    /// innermost first; after each composite's, the restart of its
    /// `sinceEntry` clock, which takes effect only on the first substate
    /// entry since the composite was entered (RoboTool's composite
    /// `entered` comes once per entry: `During = ([] e : enteredSS @ e ->
    /// SKIP) ; entered -> …`, and the state clock restarts on it).
    pub(super) fn entered_marks(&self, n: usize) -> Vec<Expr> {
        let mut parts = Vec::new();
        let mut cur = Some(n);
        while let Some(c) = cur {
            if matches!(self.nodes[c].kind, NodeKind::State | NodeKind::Final) {
                let sid = Field::Dot(name(format!("SID_{}", self.nodes[c].tag)));
                parts.push(prefix("entered__", vec![sid], Expr::Skip));
            }
            if c != n {
                if let Some(k) = self.clocks.iter().find(|k| k.state == Some(c)) {
                    parts.push(prefix(format!("restart_{}", k.csp), vec![], Expr::Skip));
                }
            }
            cur = self.nodes[c].parent;
        }
        parts
    }

    /// The process of an action clause (none when absent or empty);
    /// `None` when it is not exported.
    pub(super) fn action_of(&mut self, a: Option<&m::Action>) -> Option<Option<Expr>> {
        match a.and_then(|a| a.stmt.as_ref()) {
            Some(s) => Some(Some(self.stmt(s)?)),
            None => Some(None),
        }
    }

    /// The process taking transition `t` from the leaf `leaf` (or from
    /// its source when `leaf` is `None`, for junctions and hovers).
    pub(super) fn transition(&mut self, t: usize, leaf: Option<usize>) -> Option<Expr> {
        let syn = self.trans[t].m.clone();
        let mut rest = Vec::new();
        // The timers of the states it leaves stop at once, innermost first
        // (the during actions of composite states stop at the trigger
        // itself, which they share: see `during_process`).
        let mut cur = Some(leaf.unwrap_or(self.trans[t].source));
        while let Some(c) = cur {
            if self.active.get(c).copied().unwrap_or(false) {
                let sid = format!("SID_{}", self.nodes[c].tag);
                rest.push(prefix("deactivate__", vec![Field::Dot(name(sid))], Expr::Skip));
            }
            if c == self.trans[t].source {
                break;
            }
            cur = self.nodes[c].parent;
        }
        // Exit actions from the leaf up to the source.
        if let Some(l) = leaf {
            let mut cur = Some(l);
            while let Some(c) = cur {
                if self.nodes[c].kind == NodeKind::State {
                    let s = self.nodes[c].m.exit.clone();
                    if let Some(a) = self.action_of(s.as_ref())? {
                        rest.push(a);
                    }
                }
                if c == self.trans[t].source {
                    break;
                }
                cur = self.nodes[c].parent;
            }
        }
        for (n, cr) in &syn.resets {
            match self.names.get(n) {
                // RT-9: untimed, a clock reset vanishes.
                Some(Nm::Clock(_)) if !self.timed() => {}
                Some(Nm::Clock(k)) => rest.push(prefix(format!("reset_{}", self.clocks[*k].csp), vec![], Expr::Skip)),
                _ => {
                    self.problem(*cr, format!("`{n}` is not a clock"));
                    return None;
                }
            }
        }
        if let Some(a) = self.action_of(syn.action.as_ref())? {
            rest.push(a);
        }
        rest.push(self.enter(self.trans[t].target));
        let then = fold_seq(rest);
        let tid = self.trans[t].tid.clone();
        if let Some((d, _)) = &syn.deadline {
            // Its timer is part of the source's activity.
            if self.nodes[self.trans[t].source].kind != NodeKind::State {
                self.problem(
                    *d,
                    "deadlines on transitions from junctions are not supported by the export yet \
                     (a junction is left at once or waits for a guard)",
                );
                return None;
            }
        }
        if let Some(p) = syn.probability {
            self.problem(p, "probabilistic transitions have no meaning in the tock-CSP semantics");
            return None;
        }
        if let Some(x) = syn.exec_range {
            if !self.robosim {
                self.problem(x, "`exec` belongs to RoboSim machines");
                return None;
            }
            self.record_term(x, TermKind::Exec, || {
                prefix("endexec__", vec![Field::Dot(name(tid.clone()))], prefix("startexec", vec![], Expr::Skip))
            });
            return Some(prefix("endexec__", vec![Field::Dot(name(tid))], fold_seq(vec![name("StartExec__"), then])));
        }
        match &syn.trigger {
            Some(comm) => self.communication(comm, Some((&tid, then))),
            None => Some(prefix("internal__", vec![Field::Dot(name(tid))], then)),
        }
    }

    pub(super) fn generate(&mut self, module: &str) -> Vec<Decl> {
        // Guards: the memory enables each transition's trigger.
        for t in 0..self.trans.len() {
            if let Some(g) = self.guard_of(t) {
                self.gates.push(g);
            }
        }
        // States with an activity: the deadlines of the transitions from a
        // state; with a during action run alongside their substates.
        self.active = (0..self.nodes.len())
            .map(|n| {
                self.nodes[n].kind == NodeKind::State
                    && self.trans.iter().any(|t| t.source == n && t.m.deadline.is_some())
            })
            .collect();
        self.during = (0..self.nodes.len())
            .map(|n| {
                let node = &self.nodes[n];
                node.kind == NodeKind::State
                    && self.nodes.iter().any(|c| c.parent == Some(n))
                    && node.m.during.as_ref().is_some_and(|a| a.stmt.is_some())
            })
            .collect();
        // States, junctions and finals. A `sinceEntry(S)` first read in an
        // action (RC:TE1 forbids it, but an ill-formed model is still
        // written; guards are translated before) makes S's clock only now,
        // perhaps after S's entry was written without its restart: then
        // they are all written again, every clock known.
        let clocks = self.clocks.len();
        let saved = (self.defs.len(), self.activities.len(), self.terms.len(), self.problems.len(), self.counter);
        for n in 0..self.nodes.len() {
            self.node_process(n);
        }
        if self.clocks.len() > clocks {
            self.defs.truncate(saved.0);
            self.activities.truncate(saved.1);
            self.terms.truncate(saved.2);
            self.problems.truncate(saved.3);
            self.counter = saved.4;
            for n in 0..self.nodes.len() {
                self.node_process(n);
            }
        }
        // Hover terms of the transitions, with triggers as the machine's events.
        if self.record {
            for t in 0..self.trans.len() {
                self.display = true;
                let saved_defs = self.defs.len();
                let saved_counter = self.counter;
                if let Some(e) = self.transition(t, None) {
                    let syn = &self.trans[t].m;
                    // On its name, and on its trigger.
                    let mut ranges = vec![syn.name_range];
                    ranges.extend(syn.trigger_range);
                    let guard =
                        self.gates.iter().find(|g| g.t == t).map(|g| g.cond.clone()).filter(|c| *c != Expr::Bool(true));
                    for range in ranges {
                        self.terms.push(Term {
                            range,
                            kind: TermKind::Transition,
                            expr: e.clone(),
                            guard: guard.clone(),
                        });
                    }
                }
                self.defs.truncate(saved_defs);
                self.counter = saved_counter;
                self.display = false;
            }
        }
        if !self.problems.is_empty() {
            return Vec::new();
        }
        self.assemble(module)
    }

    /// Translates the guard of transition `t` (evaluated by the memory).
    pub(super) fn guard_of(&mut self, t: usize) -> Option<GateI> {
        let syn = self.trans[t].m.clone();
        self.binds.clear();
        let cond = match &syn.condition {
            Some(c) if c.is_else => self.else_condition(t)?,
            Some(c) => match &c.expr {
                Some(e) => match self.untimed_guard(t, e) {
                    Some(g) => g?,
                    None => self.expr(e, ECtx::Memory, None)?.e,
                },
                None => Expr::Bool(true),
            },
            None => Expr::Bool(true),
        };
        let trigger = if syn.exec {
            GateTrigger::Exec
        } else {
            match &syn.trigger {
                Some(comm) => {
                    let ev = comm.event.clone();
                    let Some(Nm::Event(i)) = self.names.get(&ev).cloned() else {
                        let what = self.what();
                        self.problem(
                            comm.range,
                            format!("`{ev}` is not an event of the {what} (declared or used through an interface)"),
                        );
                        return None;
                    };
                    GateTrigger::Event(i)
                }
                None => GateTrigger::Internal,
            }
        };
        Some(GateI { t, cond, binds: std::mem::take(&mut self.binds), trigger })
    }

    /// `condition else` of transition `t`: none of the guards of the other
    /// transitions from its source holds (an unguarded one always holds).
    pub(super) fn else_condition(&mut self, t: usize) -> Option<Expr> {
        let saved = std::mem::take(&mut self.binds);
        let mut others = Vec::new();
        for u in 0..self.trans.len() {
            if u == t || self.trans[u].source != self.trans[t].source {
                continue;
            }
            if !self.else_allowed(t, u) {
                return None;
            }
            let syn = self.trans[u].m.clone();
            match &syn.condition {
                Some(c) if c.is_else => {}
                Some(c) => match &c.expr {
                    Some(e) => others.push(self.expr(e, ECtx::Memory, None)?.e),
                    None => others.push(Expr::Bool(true)),
                },
                None => others.push(Expr::Bool(true)),
            }
        }
        // Inputs the other guards read (`$e?x`) bind nothing here.
        self.binds = saved;
        if others.contains(&Expr::Bool(true)) {
            return Some(Expr::Bool(false));
        }
        Some(match others.into_iter().reduce(|a, b| bin(BinOp::Or, a, b)) {
            Some(e) => Expr::Not(Box::new(e)),
            None => Expr::Bool(true),
        })
    }

    /// The memory's alternative enabling transition `g.t` when its guard holds.
    pub(super) fn gate(&self, g: &GateI) -> Expr {
        let tid = self.trans[g.t].tid.clone();
        let mut args: Vec<Expr> = self.memory_params().into_iter().map(name).collect();
        for &(v, i) in &g.binds {
            args[v] = name(format!("{}_value", self.events[i].csp));
        }
        let next = self.memory_call(args);
        let ev = match g.trigger {
            GateTrigger::Exec => prefix("endexec__", vec![Field::Dot(name(tid))], next),
            GateTrigger::Internal => prefix("internal__", vec![Field::Dot(name(tid))], next),
            GateTrigger::Event(i) => {
                let chan = format!("{}__", self.events[i].csp);
                Expr::Repl(
                    crate::cspm::ReplOp::ExtChoice,
                    vec![("ev__".into(), Expr::Events(vec![dot(vec![name(chan), name(tid)])]))],
                    Box::new(prefix("ev__", vec![], next)),
                )
            }
        };
        guard(g.cond.clone(), ev)
    }

    pub(super) fn memory_params(&self) -> Vec<String> {
        let mut p: Vec<String> = self.vars.iter().filter(|v| !v.shared).map(|v| v.csp.clone()).collect();
        p.extend(self.clocks.iter().map(|c| c.csp.clone()));
        for e in self.events.iter().filter(|e| self.is_input(e)) {
            p.push(e.csp.clone());
            if e.ty.is_some() {
                p.push(format!("{}_value", e.csp));
            }
        }
        p.extend(self.armed_clocks().into_iter().map(|k| format!("armed__{}", self.clocks[k].csp)));
        p
    }

    /// The clocks restarted by their composite state's own `entered`
    /// (see [`Gen::entered_marks`]): the memory keeps, for each, whether
    /// the composite has been entered and its first substate not yet.
    pub(super) fn armed_clocks(&self) -> Vec<usize> {
        if !self.after_entry() {
            return Vec::new();
        }
        (0..self.clocks.len())
            .filter(|&k| self.clocks[k].state.is_some_and(|s| self.nodes.iter().any(|c| c.parent == Some(s))))
            .collect()
    }

    pub(super) fn is_input(&self, e: &EvI) -> bool {
        self.robosim && (e.io == Some(robosim_hir::model::Io::Input) || (e.io.is_none() && e.received))
    }

    pub(super) fn memory_call(&self, args: Vec<Expr>) -> Expr {
        if args.is_empty() {
            name("Memory__")
        } else {
            call("Memory__", args)
        }
    }

    pub(super) fn node_process(&mut self, n: usize) {
        let node_syn = self.nodes[n].m.clone();
        let tag = self.nodes[n].tag.clone();
        match self.nodes[n].kind {
            NodeKind::State => {
                let mut parts = vec![];
                let Some(entry) = self.action_of(node_syn.entry.as_ref()) else { return };
                parts.extend(entry);
                let composite = self.nodes.iter().any(|c| c.parent == Some(n));
                // RoboTool's `entered` (what reachability watches) follows
                // the entry action, and a composite's its first substate's:
                // a simple state marks itself and the states around it
                // (again on later substates' entries, which reachability
                // does not tell apart). The 2019 paper's semantics keeps
                // the mark at the start.
                let after_entry = self.after_entry();
                if after_entry && !composite {
                    parts.extend(self.entered_marks(n));
                }
                // RoboTool's state clock restarts on `S::entered`: a simple
                // state's after its entry action; a composite's is armed
                // here and restarts at its first substate's `entered`
                // (`entered_marks`), once per entry of the composite.
                if let Some(c) = self.clocks.iter().find(|c| c.state == Some(n)) {
                    if composite && after_entry {
                        parts.insert(0, prefix(format!("arm_{}", c.csp), vec![], Expr::Skip));
                    } else if composite {
                        parts.insert(0, prefix(format!("reset_{}", c.csp), vec![], Expr::Skip));
                    } else {
                        parts.push(prefix(format!("reset_{}", c.csp), vec![], Expr::Skip));
                    }
                }
                if self.active[n] {
                    if !self.activity(n) {
                        return;
                    }
                    parts.push(prefix("activate__", vec![Field::Dot(name(format!("SID_{tag}")))], Expr::Skip));
                }
                if self.during[n] && !self.during_process(n) {
                    return;
                }
                if composite {
                    let Some(init) = self.nodes.iter().position(|c| c.parent == Some(n) && c.kind == NodeKind::Initial)
                    else {
                        self.problem(node_syn.name_range, "a composite state without an initial junction");
                        return;
                    };
                    parts.push(self.enter(init));
                } else {
                    parts.push(self.ready(n, name(format!("Rest__{tag}"))));
                    self.rest(n);
                }
                let body = if after_entry {
                    fold_seq(parts)
                } else {
                    prefix("entered__", vec![Field::Dot(name(format!("SID_{tag}")))], fold_seq(parts))
                };
                self.defs.push(Decl::Def(format!("Enter__{tag}"), vec![], body));
            }
            NodeKind::Final if self.nodes[n].parent.is_some() => self.rest(n),
            NodeKind::Final => {}
            NodeKind::Junction | NodeKind::Initial => {
                let mut alts = Vec::new();
                for t in 0..self.trans.len() {
                    if self.trans[t].source == n {
                        if let Some(p) = self.transition(t, None) {
                            alts.push(p);
                        }
                    }
                }
                let me = format!("Junction__{tag}");
                // RoboChart: time passes until a guard holds; RoboSim: the
                // cycle forbids it, so a dead end is stuck.
                self.push_tock(&mut alts, name(me.clone()));
                self.defs.push(Decl::Def(me, vec![], ext(alts)));
            }
        }
    }

    /// `Activity__S`: the timers of state `S`, from the end of its entry
    /// action until a transition leaves it (`activate__.SID_S` …
    /// `deactivate__.SID_S`): one per transition from `S` with a deadline
    /// `<{d}`, which refuses time after `d` time units (the transition must
    /// be taken by then). Returns false when something is not exported.
    pub(super) fn activity(&mut self, n: usize) -> bool {
        let tag = self.nodes[n].tag.clone();
        let mut parts = Vec::new();
        for t in 0..self.trans.len() {
            if self.trans[t].source != n {
                continue;
            }
            let Some(limit) = self.trans[t].m.deadline.as_ref().and_then(|(_, d)| d.clone()) else { continue };
            if !self.deadline_allowed(limit.range) {
                return false;
            }
            let Some((d, reads)) = self.bexpr(&limit, None) else { return false };
            let p = self.with_reads(&reads, call("Timer__", vec![d]));
            parts.push(p);
            if !self.defs.iter().any(|x| matches!(x, Decl::Def(f, _, _) if f == "Timer__")) {
                // Time passes d times, then no more.
                let body = guard(
                    bin(BinOp::Gt, name("d__"), Expr::Int(0)),
                    prefix("tock", vec![], call("Timer__", vec![bin(BinOp::Sub, name("d__"), Expr::Int(1))])),
                );
                self.defs.push(Decl::Def("Timer__".into(), vec!["d__".into()], body));
            }
        }
        let run = parts
            .into_iter()
            .rev()
            .reduce(|acc, p| par(p, Expr::Set(vec![name("tock")]), acc))
            .unwrap_or_else(|| self.tstop());
        let me = format!("Activity__{tag}");
        let sid = Field::Dot(name(format!("SID_{tag}")));
        let mut alts = vec![prefix(
            "activate__",
            vec![sid.clone()],
            nary(ProcOp::Interrupt, vec![run, prefix("deactivate__", vec![sid], name(me.clone()))]),
        )];
        self.push_tock(&mut alts, name(me.clone()));
        alts.push(prefix("end__", vec![], Expr::Skip));
        let body = ext(alts);
        self.defs.push(Decl::Def(me.clone(), vec![], body));
        self.activities.push((me, Vec::new()));
        true
    }

    /// `During__C`: the during action of the composite state `C` (RT-17,
    /// RoboTool's `During` of a composite): it starts once a substate has
    /// finished its entry action (`ready__.SID_C`, RoboTool's `entered` of
    /// a substate, which the substates' own entries repeat: ignored until
    /// it has stopped), runs alongside the substates, and stops at the
    /// trigger of a transition that leaves `C` (one from `C` or from a
    /// state around it), which it shares (RoboTool renames those triggers
    /// to `C`'s `interrupt`), so that it never outlives `C`. Returns false
    /// when something is not exported.
    pub(super) fn during_process(&mut self, n: usize) -> bool {
        let syn = self.nodes[n].m.clone();
        if self.robosim {
            self.problem(
                syn.name_range,
                "during actions of composite RoboSim states are not exported: how they share the \
                 cycle with the substates (`exec`) is not pinned down",
            );
            return false;
        }
        let Some(Some(d)) = self.action_of(syn.during.as_ref()) else { return false };
        let tag = self.nodes[n].tag.clone();
        let me = format!("During__{tag}");
        let ready = dot(vec![name("ready__"), name(format!("SID_{tag}"))]);
        let mut stops = Vec::new();
        let mut events = Vec::new();
        let mut cur = Some(n);
        while let Some(c) = cur {
            let from: Vec<usize> = (0..self.trans.len()).filter(|&t| self.trans[t].source == c).collect();
            for t in from {
                let Some(e) = self.trigger_event(t) else { return false };
                stops.push(t);
                events.push(e);
            }
            cur = self.nodes[c].parent;
        }
        let v = self.fresh_var("ev__");
        let stop = (!events.is_empty()).then(|| {
            Expr::Repl(
                crate::cspm::ReplOp::ExtChoice,
                vec![(v.clone(), Expr::Events(events))],
                Box::new(prefix(v.clone(), vec![], name(me.clone()))),
            )
        });
        let run = nary(
            ProcOp::Interleave,
            vec![seq(vec![d, self.tstop()]), call("RUN", vec![Expr::Set(vec![ready.clone()])])],
        );
        let running = match &stop {
            Some(s) => nary(ProcOp::Interrupt, vec![run, s.clone()]),
            None => run,
        };
        let mut alts = vec![prefix("ready__", vec![Field::Dot(name(format!("SID_{tag}")))], running)];
        alts.extend(stop);
        self.push_tock(&mut alts, name(me.clone()));
        alts.push(prefix("end__", vec![], Expr::Skip));
        self.defs.push(Decl::Def(me.clone(), vec![], ext(alts)));
        self.activities.push((me, stops));
        true
    }

    /// The event that takes transition `t` (its trigger, tagged with the
    /// transition: `e__.TID_t`, or `internal__.TID_t`), `None` when its
    /// trigger is not an event (reported where the transition is made).
    pub(super) fn trigger_event(&mut self, t: usize) -> Option<Expr> {
        let tid = name(self.trans[t].tid.clone());
        match &self.trans[t].m.trigger {
            None => Some(dot(vec![name("internal__"), tid])),
            Some(comm) => match self.names.get(&comm.event) {
                Some(Nm::Event(i)) => {
                    let i = *i;
                    self.events[i].trig = true;
                    Some(dot(vec![name(format!("{}__", self.events[i].csp)), tid]))
                }
                _ => None,
            },
        }
    }

    /// `then` after the hidden `ready__.SID_A` of each state `A` around the
    /// node `n` with a during action (innermost first): `n` has finished
    /// its entry, so the during actions around it start (RT-17).
    pub(super) fn ready(&self, n: usize, then: Expr) -> Expr {
        let mut around = Vec::new();
        let mut cur = self.nodes[n].parent;
        while let Some(c) = cur {
            if self.during.get(c).copied().unwrap_or(false) {
                around.push(c);
            }
            cur = self.nodes[c].parent;
        }
        around
            .into_iter()
            .rev()
            .fold(then, |acc, c| prefix("ready__", vec![Field::Dot(name(format!("SID_{}", self.nodes[c].tag)))], acc))
    }

    /// `Rest__L`: the leaf `L` offers its transitions and those of its
    /// ancestors; time passes meanwhile; its during action runs until a
    /// transition interrupts it.
    pub(super) fn rest(&mut self, leaf: usize) {
        let mut alts = Vec::new();
        let mut cur = Some(leaf);
        while let Some(c) = cur {
            for t in 0..self.trans.len() {
                if self.trans[t].source == c {
                    if let Some(p) = self.transition(t, Some(leaf)) {
                        alts.push(p);
                    }
                }
            }
            cur = self.nodes[c].parent;
        }
        let syn = self.nodes[leaf].m.clone();
        let me = format!("Rest__{}", self.nodes[leaf].tag);
        let during = if self.nodes[leaf].kind == NodeKind::State {
            match self.action_of(syn.during.as_ref()) {
                Some(d) => d,
                None => return,
            }
        } else {
            None
        };
        let body = match during {
            Some(d) => nary(ProcOp::Interrupt, vec![seq(vec![d, self.tstop()]), ext(alts)]),
            None => {
                self.push_tock(&mut alts, name(me.clone()));
                ext(alts)
            }
        };
        self.defs.push(Decl::Def(me, vec![], body));
    }
}
