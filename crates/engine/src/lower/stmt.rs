//! Actions: statements as code.

use robosim_hir::model::{self, ExprKind, Selector, Stmt, StmtKind};

use super::types::stride;
use super::*;

impl MachineCx<'_, '_> {
    /// The code of an action clause.
    pub(super) fn action_stmt(&mut self, action: &model::Action) -> Result<(), Unsupported> {
        if let Some(s) = &action.stmt {
            self.stmt(s)?;
        }
        Ok(())
    }

    fn stmt(&mut self, s: &Stmt) -> Result<(), Unsupported> {
        let range = s.range;
        if !matches!(s.kind, StmtKind::Seq(_)) {
            self.at = range;
        }
        match &s.kind {
            StmtKind::Seq(parts) => {
                for c in parts {
                    self.stmt(c)?;
                }
            }
            StmtKind::Skip => {}
            StmtKind::Assign { target, selectors, value: e, .. } => {
                let target = target.join("::");
                if matches!(e.kind, ExprKind::Missing) {
                    return Err(self.err(range, "an assignment without a value"));
                }
                let want = self.types.get(&target).cloned();
                let index = selectors.iter().find_map(|sel| match sel {
                    Selector::Index(ix, r) => Some((ix, *r)),
                    Selector::Field(..) => None,
                });
                let field = match selectors.as_slice() {
                    [Selector::Field(f, r)] => Some((f.clone(), *r)),
                    _ => None,
                };
                let expr = match (index, want) {
                    // `r.f = v` of a record of numbers: the record with that
                    // field replaced.
                    (None, Some(Layout::Record(names, ds))) if field.is_some() => {
                        let (f, f_range) = field.expect("a field");
                        let Some(i) = names.iter().position(|n| *n == f) else {
                            return Err(self.err(f_range, format!("the record has no field `{f}`")));
                        };
                        self.with_component(&target, range, &ds, i, e)?
                    }
                    (None, Some(_)) if !selectors.is_empty() => {
                        return Err(self.err(range, "only a field of a record of numbers can be assigned this way"))
                    }
                    (None, Some(t)) => self.typed(e, &t)?,
                    (None, None) => self.expr(e)?,
                    // `x[i] = v` of a tuple: the tuple with component i replaced.
                    (Some((ix, ix_range)), Some(Layout::Tuple(ds))) => {
                        let i = self.component(ix_range, ix, &ds)?;
                        self.with_component(&target, range, &ds, i, e)?
                    }
                    (Some((_, ix_range)), _) => {
                        return Err(self.err(ix_range, "only the components of tuples can be indexed"))
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
                                range,
                                format!("`{target}` is an input of the machine: to write it, require it in the output context too"),
                            ));
                        }
                        self.emit(Instr::Assign { slot, expr, dom, shared, forward: None })
                    }
                    _ => return Err(self.err(range, format!("`{target}` is not a variable of the machine"))),
                }
            }
            StmtKind::ClockReset(n) => match self.names.get(n) {
                Some(Name::Clock(c)) => self.emit(Instr::ResetClock(*c)),
                _ => return Err(self.err(range, format!("`{n}` is not a clock"))),
            },
            StmtKind::If(cond, then, els) => {
                if matches!(cond.kind, ExprKind::Missing) {
                    return Err(self.err(range, "`if` without a condition"));
                }
                let cond = self.expr(cond)?;
                let jif = self.code.len();
                self.emit(Instr::JumpIfNot(cond.clone(), u32::MAX));
                self.stmt(then)?;
                if let Some(e) = els {
                    let jend = self.code.len();
                    self.emit(Instr::Jump(u32::MAX));
                    self.code[jif] = Instr::JumpIfNot(cond, self.code.len() as u32);
                    self.stmt(e)?;
                    self.code[jend] = Instr::Jump(self.code.len() as u32);
                } else {
                    self.code[jif] = Instr::JumpIfNot(cond, self.code.len() as u32);
                }
            }
            StmtKind::Comm(comm) => {
                let ev = &comm.event;
                let (chan, dir, ty) = self.event(ev, comm.range)?;
                let (value, bind, out, then) = self.comm_parts(comm, ty)?;
                // A lone machine sends on the `e.out` of an event it also receives.
                let (chan, dir) = match self.sends.get(ev) {
                    Some(&c) if out.is_some() => (c, Dir::Out),
                    _ => (chan, dir),
                };
                match dir {
                    Dir::Out => {
                        if bind.is_some() {
                            return Err(self.err(comm.range, format!("`{ev}` is an output: it cannot receive")));
                        }
                        let args = out.or(value).into_iter().collect();
                        self.emit(Instr::Out { chan, args, urgent: false, store: None });
                    }
                    Dir::In => {
                        if out.is_some() {
                            return Err(self.err(comm.range, format!("`{ev}` is an input: it cannot send")));
                        }
                        self.emit(Instr::In { chan, value, bind });
                        for i in then {
                            self.emit(i);
                        }
                    }
                }
            }
            StmtKind::Call { name, args } => {
                let name = name.join("::");
                if let Some(&Name::Defined(op)) = self.op_names.get(&name) {
                    let args = self.arguments(range, args, self.ops[op as usize].params.len(), &name)?;
                    self.emit(Instr::CallOp { op, args });
                } else {
                    let (chan, args) =
                        self.call(range, &name, args, "an operation of the robotic platform required by the machine")?;
                    self.emit(Instr::Out { chan, args, urgent: true, store: None });
                }
            }
            StmtKind::Wait(e) => {
                if let ExprKind::Interval { lo, hi, open_lo, open_hi } = &e.kind {
                    let mut lo = self.expr(lo)?;
                    let mut hi = self.expr(hi)?;
                    let wide = Dom { lo: Val::MIN / 4, hi: Val::MAX / 4 };
                    if *open_lo {
                        lo = Expr::Arith(ArOp::Add, Box::new(lo), Box::new(Expr::Const(1)), wide);
                    }
                    if *open_hi {
                        hi = Expr::Arith(ArOp::Sub, Box::new(hi), Box::new(Expr::Const(1)), wide);
                    }
                    self.emit(Instr::ChooseWait(lo, hi));
                } else if matches!(e.kind, ExprKind::Missing) {
                    return Err(self.err(range, "`wait` without a duration"));
                } else {
                    let n = self.expr(e)?;
                    self.emit(Instr::SetWait(n));
                }
                self.emit(Instr::Wait);
            }
            StmtKind::SimCall { name, args } => {
                // Register writes cannot be postponed (RoboTool: EDeadline(…, 0)).
                let (chan, args) = self.call(range, &name.join("::"), args, "an output operation of the machine")?;
                self.emit(Instr::Out { chan, args, urgent: true, store: None });
            }
            StmtKind::Output(name, value) => {
                let name = name.join("::");
                let (chan, dir, ty) = self.event(&name, range)?;
                // An event of both I/O contexts is written to its own
                // output register.
                let (chan, dir) = self.sends.get(&name).map_or((chan, dir), |&c| (c, Dir::Out));
                if dir != Dir::Out {
                    return Err(self.err(range, format!("`{name}` is not an output")));
                }
                let want = self.types.get(&name).cloned().unwrap_or(Layout::Num(ty.unwrap_or(Dom::BOOL)));
                let args = match value {
                    Some(v) => vec![self.typed(v, &want)?],
                    None => Vec::new(),
                };
                if ty.is_some() == args.is_empty() {
                    return Err(self.err(range, format!("`{name}` needs exactly its declared value")));
                }
                self.emit(Instr::Out { chan, args, urgent: true, store: None });
            }
            StmtKind::Exec => {
                let next = self.code.len() as u32 + 1;
                self.emit(Instr::Exec(next));
            }
            StmtKind::Timed(body, limit) => {
                let (Some(body), Some(limit)) = (body, limit) else {
                    return Err(self.err(range, "an incomplete deadline"));
                };
                let limit = self.expr(limit)?;
                self.emit(Instr::Deadline(limit));
                self.stmt(body)?;
                self.at = range;
                self.emit(Instr::EndDeadline);
            }
            StmtKind::Par(inner) => {
                let [one] = inner.as_slice() else {
                    return Err(self.err(range, "parallel statements are not supported yet"));
                };
                self.stmt(one)?;
            }
            StmtKind::Other(k) => {
                return Err(self.err(range, format!("this statement ({k}) is not supported by the native checker yet")))
            }
        }
        Ok(())
    }

    /// The channel and argument values of a call `op(args)` / `$op(args)`
    /// of a platform operation (`what` says what `op` must be).
    fn call(
        &mut self,
        at: TextRange,
        name: &str,
        args: &[model::Expr],
        what: &str,
    ) -> Result<(u16, Vec<Expr>), Unsupported> {
        let Some(Name::Op { params, chan }) = self.op_names.get(name).cloned() else {
            return Err(self.err(at, format!("`{name}` is not {what}")));
        };
        Ok((chan, self.arguments(at, args, params.len(), name)?))
    }

    /// The `n` argument values `args` of the call at `at` of `name`.
    fn arguments(
        &mut self,
        at: TextRange,
        args: &[model::Expr],
        n: usize,
        name: &str,
    ) -> Result<Vec<Expr>, Unsupported> {
        if n != args.len() {
            return Err(self.err(at, format!("`{name}` takes {n} arguments")));
        }
        let mut exprs = Vec::new();
        for a in args {
            exprs.push(self.expr(a)?);
        }
        Ok(exprs)
    }

    /// `target` (a record's or tuple's variable, components `ds`) with
    /// component `i` replaced by `e`, the others read from its slot.
    fn with_component(
        &mut self,
        target: &str,
        range: TextRange,
        ds: &[Dom],
        i: usize,
        e: &model::Expr,
    ) -> Result<Expr, Unsupported> {
        let slot = match self.names.get(target) {
            Some(Name::Var { slot, .. }) => *slot,
            _ => return Err(self.err(range, format!("`{target}` is not a variable"))),
        };
        let mut parts = Vec::new();
        for (j, d) in ds.iter().enumerate() {
            let part = if j == i { self.expr(e)? } else { Expr::Proj(Box::new(Expr::Slot(slot)), stride(ds, j), *d) };
            parts.push((part, *d));
        }
        Ok(Expr::Tuple(parts))
    }
}
