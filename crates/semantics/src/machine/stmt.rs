//! Statements: actions, operation calls and communications as CSPm processes.

use super::*;

/// What makes an operation's process from its definition ([`operation`],
/// [`inlined_sim_operation`]).
type BuildOperation<'a> =
    fn(&mut Exporter<'a>, File, &'a m::Behaviour, Vec<String>) -> Result<Rc<OperationOut>, String>;

impl<'e, 'a> Gen<'e, 'a> {
    pub(super) fn stmt(&mut self, s: &m::Stmt) -> Option<Expr> {
        if self.nesting >= MAX_NESTING {
            self.problem(s.range, "this statement is nested too deeply for the export");
            return None;
        }
        self.nesting += 1;
        let out = self.stmt_inner(s);
        self.nesting -= 1;
        out
    }

    pub(super) fn stmt_inner(&mut self, s: &m::Stmt) -> Option<Expr> {
        let r = s.range;
        match &s.kind {
            m::StmtKind::Seq(stmts) => {
                let mut parts = Vec::new();
                for c in stmts {
                    parts.push(self.stmt(c)?);
                }
                Some(fold_seq(parts))
            }
            m::StmtKind::Skip => Some(Expr::Skip),
            m::StmtKind::Assign { target, selectors, value, .. } => {
                let target = target.join("::");
                let Some(Nm::Var(v)) = self.names.get(&target).cloned() else {
                    self.problem(r, format!("`{target}` is not a variable the export can assign"));
                    return None;
                };
                // `r.f.g = e`: the record fields on the way to the assigned one.
                let mut path: Vec<(Rc<RecordTy>, String)> = Vec::new();
                let mut ty = self.vars[v].ty.clone();
                for a in selectors {
                    match a {
                        m::Selector::Field(f, ar) => {
                            let Ty::Record(rec) = ty.clone() else {
                                self.problem(*ar, "only fields of records can be assigned");
                                return None;
                            };
                            let Some((_, t)) = rec.fields.iter().find(|(n, _)| n == f) else {
                                self.problem(*ar, format!("`{f}` is not a field of the record"));
                                return None;
                            };
                            ty = t.clone();
                            path.push((rec, f.clone()));
                        }
                        m::Selector::Index(_, ar) => {
                            self.problem(*ar, "assignments to indexed elements are not supported by the export yet");
                            return None;
                        }
                    }
                }
                if matches!(value.kind, m::ExprKind::Missing) {
                    return None;
                }
                let (mut val, mut reads) = self.bexpr(value, Some(&ty))?;
                if !path.is_empty() {
                    // r.f.g = e is r = set_f(r, set_g(get_f(r), e)).
                    let csp = self.vars[v].csp.clone();
                    if !reads.contains(&csp) {
                        reads.push(csp.clone());
                    }
                    let mut olds = vec![name(csp)];
                    for (rec, f) in &path[..path.len() - 1] {
                        let prev = olds.last().cloned().expect("a value");
                        olds.push(call(rec.getter(f), vec![prev]));
                    }
                    for ((rec, f), old) in path.iter().zip(olds).rev() {
                        val = call(rec.setter(f), vec![old, val]);
                    }
                }
                let set = prefix(format!("set_{}", self.vars[v].csp), vec![Field::Out(val)], Expr::Skip);
                Some(self.with_reads(&reads, set))
            }
            m::StmtKind::ClockReset(n) => match self.names.get(n) {
                // RT-9: untimed, a clock reset vanishes.
                Some(Nm::Clock(_)) if !self.timed() => Some(Expr::Skip),
                Some(Nm::Clock(c)) => Some(prefix(format!("reset_{}", self.clocks[*c].csp), vec![], Expr::Skip)),
                _ => {
                    self.problem(r, format!("`{n}` is not a clock"));
                    None
                }
            },
            m::StmtKind::If(c, then, els) => {
                if matches!(c.kind, m::ExprKind::Missing) {
                    return None;
                }
                let (cond, reads) = self.bexpr(c, None)?;
                let a = self.stmt(then)?;
                let b = match els {
                    Some(b) => self.stmt(b)?,
                    None => Expr::Skip,
                };
                Some(self.with_reads(&reads, Expr::If(Box::new(cond), Box::new(a), Box::new(b))))
            }
            m::StmtKind::Comm(comm) => {
                let term = self.communication(comm, None)?;
                self.record_term(comm.event_range, TermKind::Event, || term.clone());
                Some(term)
            }
            m::StmtKind::Call { name: path, args } => {
                let n = path.join("::");
                let Some(o) = self.op_names.get(&n).copied() else {
                    self.problem(
                        r,
                        format!("`{n}` is not an operation of the platform: calls of operations defined in the model are not supported by the export yet"),
                    );
                    return None;
                };
                if self.robosim && self.ops[o].io == Some(Io::Output) {
                    // A platform operation (RS:SM6 in hir).
                    self.problem(r, format!("`{n}(…)` in a RoboSim machine must be an output: `${n}(…)`"));
                    return None;
                }
                if self.robosim && !self.ops[o].defined {
                    // A software operation nothing defines for it (on its own,
                    // RT-19; an operation on its own, RT-11): the urgent call
                    // event (the reference's `CALL__op = EDeadline(opCall, 0)`).
                    let (args, reads) = self.arguments(args, r, o)?;
                    let mut fields = vec![name(op_event(&self.ops[o].name, "Call"))];
                    fields.extend(args);
                    self.sim_op_calls.insert(o);
                    let p = self.with_reads(&reads, self.urgent(dot(fields)));
                    self.record_term(s.head, TermKind::Call, || p.clone());
                    return Some(p);
                }
                if self.robosim {
                    return self.call_sim_operation(s, args, o);
                }
                if self.ops[o].defined {
                    return self.call_operation(s, args, o);
                }
                let (args, reads) = self.arguments(args, r, o)?;
                let op = &self.ops[o];
                let mut fields = vec![name(op_event(&op.name, "Call"))];
                fields.extend(args);
                let ret = name(op_event(&op.name, "Ret"));
                let mut p = self.urgent(dot(fields));
                if self.profile == Profile::Paper2019 {
                    p = seq(vec![p, self.urgent(ret)]);
                }
                let p = self.with_reads(&reads, p);
                self.record_term(s.head, TermKind::Call, || p.clone());
                Some(p)
            }
            m::StmtKind::Wait(e) => match &e.kind {
                m::ExprKind::Missing => None,
                // RT-9: untimed, `wait(e)` is `SKIP` (`e` is not evaluated).
                _ if !self.timed() => Some(Expr::Skip),
                m::ExprKind::Interval { lo, hi, open_lo, open_hi } => {
                    if matches!(lo.kind, m::ExprKind::Missing) || matches!(hi.kind, m::ExprKind::Missing) {
                        self.problem(e.range, "an interval needs two bounds");
                        return None;
                    }
                    let (mut lo, mut r1) = self.bexpr(lo, None)?;
                    let (mut hi, r2) = self.bexpr(hi, None)?;
                    if *open_lo {
                        lo = bin(BinOp::Add, lo, Expr::Int(1));
                    }
                    if *open_hi {
                        hi = bin(BinOp::Sub, hi, Expr::Int(1));
                    }
                    for x in r2 {
                        if !r1.contains(&x) {
                            r1.push(x);
                        }
                    }
                    let p = call("WaitInterval", vec![Expr::Range(Box::new(lo), Box::new(hi))]);
                    Some(self.with_reads(&r1, p))
                }
                _ => {
                    let (n, reads) = self.bexpr(e, None)?;
                    Some(self.with_reads(&reads, call("Wait", vec![n])))
                }
            },
            m::StmtKind::Timed(body, limit) => {
                if !self.deadline_allowed(r) {
                    return None;
                }
                let body = body.as_ref()?;
                let limit = limit.as_ref()?;
                let (d, reads) = self.bexpr(limit, None)?;
                let b = self.stmt(body)?;
                Some(self.with_reads(&reads, call("EndBy", vec![b, d])))
            }
            m::StmtKind::Par(inner) => match inner.as_slice() {
                [one] => self.stmt(one),
                _ => {
                    self.problem(r, "parallel statements are not supported by the export yet");
                    None
                }
            },
            m::StmtKind::SimCall { name: path, args } => {
                let n = path.join("::");
                let Some(o) = self.op_names.get(&n).copied() else {
                    self.problem(r, format!("`${n}` is not an output operation of the machine"));
                    return None;
                };
                let (args, reads) = self.arguments(args, r, o)?;
                let model = self.ops[o].name.clone();
                let p = self.output(&model, args, r)?;
                let p = self.with_reads(&reads, p);
                self.record_term(s.head, TermKind::OperationOutput, || p.clone());
                Some(p)
            }
            m::StmtKind::Output(path, value) => {
                let n = path.join("::");
                let Some(Nm::Event(i)) = self.names.get(&n).cloned() else {
                    self.problem(r, format!("`${n}` is not an output event of the machine"));
                    return None;
                };
                let ty = self.events[i].ty.clone();
                let (args, reads) = match (&ty, value) {
                    (Some(t), Some(v)) => {
                        let (e, reads) = self.bexpr(v, Some(t))?;
                        (vec![e], reads)
                    }
                    (None, None) => (Vec::new(), Vec::new()),
                    _ => {
                        self.problem(r, format!("`${n}` needs exactly its declared value"));
                        return None;
                    }
                };
                let model = self.events[i].name.clone();
                let p = self.output(&model, args, r)?;
                let p = self.with_reads(&reads, p);
                self.record_term(s.head, TermKind::Output, || p.clone());
                Some(p)
            }
            m::StmtKind::Exec => {
                if !self.robosim {
                    self.problem(r, "`exec` belongs to RoboSim machines");
                    return None;
                }
                self.uses_exec_stmt = true;
                if self.sim_op {
                    // `endexec -> startexec` in a timed section: time may
                    // pass before either (`Exec__`, see `assemble`).
                    self.record_term(r, TermKind::Exec, || {
                        prefix("endexec", vec![], prefix("startexec", vec![], Expr::Skip))
                    });
                    return Some(name("Exec__"));
                }
                let p = prefix("endexec__", vec![Field::Dot(name("TID_exec"))], name("StartExec__"));
                self.record_term(r, TermKind::Exec, || {
                    prefix("endexec__", vec![Field::Dot(name("TID_exec"))], prefix("startexec", vec![], Expr::Skip))
                });
                Some(p)
            }
            m::StmtKind::Other(words) => {
                self.problem(r, format!("this statement ({words}) is not supported by the export yet"));
                None
            }
        }
    }

    /// The process of the operation `o` a statement at `r` calls, built by
    /// `build` from its definition; `None` (the problem reported) when it
    /// is not exported or its parameters differ from those the caller
    /// requires.
    fn called_operation(&mut self, r: TextRange, o: usize, build: BuildOperation<'a>) -> Option<Rc<OperationOut>> {
        let n = self.ops[o].name.clone();
        let (_, file, def, outer) = self.op_definition(&n)?;
        let op = match build(self.ex, file, def, outer) {
            Ok(op) => op,
            Err(m) => {
                self.problem(r, m);
                return None;
            }
        };
        if op.params != self.ops[o].params {
            self.problem(r, format!("`{n}`: its definition's parameters differ from the required signature"));
            return None;
        }
        Some(op)
    }

    /// A call of an operation defined in the model: its process
    /// (`pkg::OP_op::D__(id__, args, constants)`, its events renamed to the
    /// caller's), through `CALL__op(args)` as RoboTool names it. The
    /// operation's events and platform calls become the caller's.
    pub(super) fn call_operation(&mut self, s: &m::Stmt, args: &[m::Expr], o: usize) -> Option<Expr> {
        let r = s.range;
        let n = self.ops[o].name.clone();
        let op = self.called_operation(r, o, operation)?;
        self.fn_calls.extend(op.functions.iter().cloned());
        let helper = ident(&format!("CALL__{n}"));
        if !self.op_calls.iter().any(|(h, _)| *h == helper) {
            let def = self.operation_helper(&op, &helper, r)?;
            self.op_calls.push((helper.clone(), def));
        }
        let (args, reads) = self.arguments(args, r, o)?;
        let p = if args.is_empty() { name(helper) } else { call(helper, args) };
        let p = self.with_reads(&reads, p);
        self.record_term(s.head, TermKind::Call, || p.clone());
        Some(p)
    }

    /// RT-19: a RoboSim machine's call of an operation its controller
    /// defines, run as the native checker inlines it: the operation's
    /// process (its module of [`inlined_sim_operation`]) through
    /// `CALL__op(args)`, its `exec` the machine's (`endexec.TID_exec`,
    /// then `startexec`), its register writes the machine's (which it must
    /// have), the variables it requires the machine's, its calls of other
    /// operations the machine's call events.
    pub(super) fn call_sim_operation(&mut self, s: &m::Stmt, args: &[m::Expr], o: usize) -> Option<Expr> {
        let r = s.range;
        let n = self.ops[o].name.clone();
        let op = self.called_operation(r, o, inlined_sim_operation)?;
        for out in &op.outputs {
            let event = self.events.iter().any(|e| e.name == *out && (e.both || !self.is_input(e)));
            let platform = self.ops.iter().any(|x| x.name == *out && x.io == Some(Io::Output));
            if !event && !platform {
                self.problem(r, format!("the operation `{n}` writes `${out}`, which is no output of the machine"));
                return None;
            }
        }
        self.fn_calls.extend(op.functions.iter().cloned());
        let helper = ident(&format!("CALL__{n}"));
        if !self.op_calls.iter().any(|(h, _)| *h == helper) {
            let def = self.operation_helper(&op, &helper, r)?;
            self.op_calls.push((helper.clone(), def));
        }
        if op.uses_exec {
            self.uses_exec_stmt = true;
        }
        let (args, reads) = self.arguments(args, r, o)?;
        let p = if args.is_empty() { name(helper) } else { call(helper, args) };
        let p = self.with_reads(&reads, p);
        self.record_term(s.head, TermKind::Call, || p.clone());
        Some(p)
    }

    /// `CALL__op(x…) = pkg::OP_op::D__(id__, x…, constants) [[ pkg::OP_op::e <- e, … ]]`:
    /// the operation's constants become the caller's, its channels the
    /// caller's channels of the same name.
    pub(super) fn operation_helper(&mut self, op: &OperationOut, helper: &str, r: TextRange) -> Option<Decl> {
        let params: Vec<String> = (0..op.params.len()).map(|k| format!("x{k}__")).collect();
        let mut args = vec![name("id__")];
        args.extend(params.iter().map(|p| name(p.clone())));
        // The operation's constants are RoboTool's globals (instantiations.csp),
        // not parameters of the caller's processes: `M::D__` takes the
        // machine's own constants only.
        for (c, _) in &op.consts {
            match self.consts.iter().find(|x| x.global == c.global) {
                Some(x) => args.push(name(x.local.clone())),
                None => args.push(name(c.global.clone())),
            }
        }
        let mut renames = Vec::new();
        for ch in &op.chans {
            let mine = match ch.kind {
                OpChanKind::Var => {
                    let mine = match self.names.get(&ch.model).cloned() {
                        Some(Nm::Var(i)) if Some(&self.vars[i].ty) == ch.ty.as_ref() => self.vars[i].csp.clone(),
                        _ => {
                            self.problem(
                                r,
                                format!(
                                    "the operation uses the variable `{}`, which the caller lacks (or of another type)",
                                    ch.model
                                ),
                            );
                            return None;
                        }
                    };
                    for g in ["get_", "set_"] {
                        renames.push((name(format!("{}::{g}{}", op.module, ch.csp)), name(format!("{g}{mine}"))));
                    }
                    continue;
                }
                OpChanKind::Event => {
                    let ty = ch.ty.clone();
                    let i = match self.names.get(&ch.model).cloned() {
                        Some(Nm::Event(i)) => i,
                        None => {
                            let csp = self.local(&ch.model);
                            self.events.push(EvI {
                                name: ch.model.clone(),
                                csp,
                                ty: ty.clone(),
                                io: None,
                                received: false,
                                trig: false,
                                both: false,
                            });
                            self.names.insert(ch.model.clone(), Nm::Event(self.events.len() - 1));
                            self.events.len() - 1
                        }
                        Some(_) => {
                            self.problem(r, format!("`{}` of the operation is not an event of the caller", ch.model));
                            return None;
                        }
                    };
                    if self.events[i].ty != ty {
                        self.problem(r, format!("the event `{}` has another type in the operation", ch.model));
                        return None;
                    }
                    if ch.dir == Dir::In {
                        self.events[i].received = true;
                    }
                    self.events[i].csp.clone()
                }
                OpChanKind::Call | OpChanKind::Ret => {
                    let i = match self.op_names.get(&ch.model).copied() {
                        Some(i) => i,
                        None => {
                            let params = ch.params.clone();
                            self.ops.push(OpI { name: ch.model.clone(), params, defined: false, io: None });
                            self.op_names.insert(ch.model.clone(), self.ops.len() - 1);
                            self.ops.len() - 1
                        }
                    };
                    if self.robosim && self.ops[i].defined {
                        self.problem(
                            r,
                            format!(
                                "the operation calls `{}`, which the controller defines too: calls between \
                                 operations are not run inside a RoboSim machine by the export yet",
                                ch.model
                            ),
                        );
                        return None;
                    }
                    if self.robosim {
                        self.sim_op_calls.insert(i);
                    }
                    if self.ops[i].params != ch.params || self.ops[i].defined {
                        self.problem(r, format!("the operation `{}` has another signature in the callee", ch.model));
                        return None;
                    }
                    let suffix = if ch.kind == OpChanKind::Call { "Call" } else { "Ret" };
                    op_event(&ch.model, suffix)
                }
            };
            renames.push((name(format!("{}::{}", op.module, ch.csp)), name(mine)));
        }
        if op.uses_exec {
            // RoboSim: the operation's `exec` ends the machine's cycle.
            let end = dot(vec![name("endexec__"), name("TID_exec")]);
            renames.push((name(format!("{}::endexec", op.module)), end));
            renames.push((name(format!("{}::startexec", op.module)), name("startexec")));
        }
        let mut body = call(format!("{}::D__", op.module), args);
        if !renames.is_empty() {
            body = Expr::Rename(Box::new(body), renames, vec![]);
        }
        if !op.outputs.is_empty() {
            // RoboSim: its register writes (its module's own, as RoboTool's)
            // become the machine's; its `terminate` is hidden by its `D__`.
            let mine = self.output_regs();
            let regs: Vec<crate::sim_names::RegRename> = op
                .outputs
                .iter()
                .filter_map(|o| {
                    let c = self.ex.out_reg(o);
                    let (_, values) = mine.iter().find(|(m, _)| *m == c)?;
                    Some(crate::sim_names::RegRename { from: c.clone(), to: c, values: values.clone(), input: false })
                })
                .collect();
            body = crate::sim_names::rename_regs(self.profile, body, &op.module, &regs);
        }
        Some(Decl::Def(helper.to_string(), params, body))
    }

    /// A RoboSim output: the register write, urgent (robotool3), or its
    /// record in the machine's buffer (paper2019, Rule 7).
    pub(super) fn output(&mut self, model: &str, args: Vec<Expr>, _r: TextRange) -> Option<Expr> {
        self.written.insert(model.to_string());
        let ctor = self.ex.out_reg(model);
        if self.profile == Profile::Paper2019 {
            let mut f = vec![Field::Dot(name(ctor)), Field::Dot(Expr::Bool(true))];
            f.extend(args.into_iter().map(Field::Dot));
            return Some(prefix("stmout", f, Expr::Skip));
        }
        let mut f = vec![name("registerWrite"), name(ctor)];
        f.extend(args);
        Some(call("EDeadline", vec![dot(f), Expr::Int(0)]))
    }

    pub(super) fn arguments(&mut self, args: &[m::Expr], r: TextRange, o: usize) -> Option<(Vec<Expr>, Vec<String>)> {
        let params = self.ops[o].params.clone();
        if args.len() != params.len() {
            self.problem(r, format!("`{}` takes {} arguments", self.ops[o].name, params.len()));
            return None;
        }
        let mut out = Vec::new();
        let mut reads = Vec::new();
        for (a, t) in args.iter().zip(&params) {
            let (e, r) = self.bexpr(a, Some(t))?;
            for x in r {
                if !reads.contains(&x) {
                    reads.push(x);
                }
            }
            out.push(e);
        }
        Some((out, reads))
    }

    /// A communication `e`, `e!v`, `e.v` or `e?x`: as a statement
    /// (`trigger = None`: delayable) or as the trigger of a transition
    /// (tagged with its identifier), followed by `then`.
    pub(super) fn communication(&mut self, comm: &m::Comm, trigger: Option<(&str, Expr)>) -> Option<Expr> {
        let r = comm.range;
        let ev = comm.event.clone();
        let Some(Nm::Event(i)) = self.names.get(&ev).cloned() else {
            let what = self.what();
            self.problem(r, format!("`{ev}` is not an event of the {what} (declared or used through an interface)"));
            return None;
        };
        if self.robosim {
            self.problem(r, "RoboSim machines communicate through `$` inputs and outputs only");
            return None;
        }
        // Refused rather than exported without its guard (which would offer
        // the event whatever the guard says); the engine refuses them too.
        if let (Some(g), false) = (comm.guard, matches!(comm.part, Some(m::CommPart::Input(..)))) {
            self.problem(
                g,
                format!("guarded communications `{ev}[| … |]` are not supported by the export yet (the guard would be lost)"),
            );
            return None;
        }
        let ty = self.events[i].ty.clone();
        let mut dir = if trigger.is_some() { "in" } else { "out" };
        let mut value: Option<Vec<Expr>> = None;
        let mut bind: Option<usize> = None;
        let mut reads = Vec::new();
        match &comm.part {
            Some(p @ (m::CommPart::Sync(e) | m::CommPart::Output(e))) => {
                let Some(t) = ty.clone() else {
                    self.problem(r, format!("`{ev}` carries no value"));
                    return None;
                };
                let e = e.as_ref()?;
                let (v, rd) = self.bexpr(e, Some(&t))?;
                reads = rd;
                value = Some(vec![v]);
                dir = if matches!(p, m::CommPart::Sync(_)) { "in" } else { "out" };
            }
            Some(m::CommPart::Input(var, pr)) => {
                if comm.guard.is_some() {
                    self.problem(*pr, "guarded inputs `e[|g|]?x` are not supported by the export yet");
                    return None;
                }
                let var = var.join("::");
                match self.names.get(&var) {
                    Some(Nm::Var(v)) if ty.is_some() => bind = Some(*v),
                    _ => {
                        self.problem(*pr, format!("`{var}` cannot receive a value of `{ev}`"));
                        return None;
                    }
                }
                dir = "in";
            }
            None => {}
        }
        if dir == "in" {
            self.events[i].received = true;
        }
        let csp = self.events[i].csp.clone();
        let mut fields = vec![Field::Dot(self.direction(dir))];
        // The input field (a tuple for a product) and the value
        // they make, stored in the variable.
        let bound = match (bind, &ty) {
            (Some(v), Some(t)) => {
                let base = if self.display { self.vars[v].csp.clone() } else { format!("{}__in", self.vars[v].csp) };
                Some(t.input_fields(&base))
            }
            _ => None,
        };
        if let Some(v) = &value {
            fields.extend(v.iter().cloned().map(Field::Dot));
        } else if let Some((f, _)) = &bound {
            fields.extend(f.iter().cloned());
        }
        let store = |then: Expr| match (bind, &bound) {
            (Some(v), Some((_, val))) => {
                prefix(format!("set_{}", self.vars[v].csp), vec![Field::Out(val.clone())], then)
            }
            _ => then,
        };
        match trigger {
            Some((tid, then)) => {
                let chan = if self.display {
                    csp.clone()
                } else {
                    self.events[i].trig = true;
                    fields.insert(0, Field::Dot(name(tid)));
                    format!("{csp}__")
                };
                let p = prefix(chan, fields, store(then));
                Some(self.with_reads(&reads, p))
            }
            None => {
                let p = match (bind, &bound) {
                    // Untimed, nothing else happens while it waits.
                    (Some(_), Some(_)) if !self.timed() => prefix(csp.clone(), fields, store(Expr::Skip)),
                    (Some(_), Some(_)) => {
                        // An input: wait for it, then store it.
                        self.counter += 1;
                        let n = format!("Input__{}", self.counter);
                        let body = ext(vec![
                            prefix(csp.clone(), fields, store(Expr::Skip)),
                            prefix("tock", vec![], name(n.clone())),
                        ]);
                        self.defs.push(Decl::Def(n.clone(), vec![], body));
                        name(n)
                    }
                    _ => {
                        let mut f = vec![name(csp.clone())];
                        for x in fields {
                            if let Field::Dot(e) = x {
                                f.push(e);
                            }
                        }
                        self.delayable(dot(f))
                    }
                };
                Some(self.with_reads(&reads, p))
            }
        }
    }
}
