//! Typing of statements and of the positions that take expressions:
//! enumeration literals, initialisers, assignments, operation calls,
//! communications and probabilities.

use robosim_syntax::{ast, SyntaxKind::*, SyntaxNode};

use crate::defs::{file_defs, lower_type, DefData, DefKind};
use crate::index::ItemLoc;
use crate::resolve::Target;

use super::{arguments, compatible, first_operand, narrowing, operands, Ty, Typer};

impl Typer<'_> {
    /// The enumeration literal an expression names (`E::L` or a bare `L`).
    pub(super) fn literal_of(&self, e: &SyntaxNode) -> Option<(ItemLoc, u32)> {
        let r = match e.kind() {
            ENUM_LITERAL_EXPR => e.children().filter(|c| c.kind() == NAME_REF).nth(1)?,
            REF_EXPR => e.children().find(|c| c.kind() == NAME_REF)?,
            _ => return None,
        };
        self.literal_named(&r)
    }

    /// The enumeration literal the name reference `r` denotes.
    pub(super) fn literal_named(&self, r: &SyntaxNode) -> Option<(ItemLoc, u32)> {
        match self.targets.get(&r.text_range())? {
            Target::Member(loc, i) if loc.summary(self.db).members[*i as usize].kind == DefKind::EnumLiteral => {
                Some((*loc, *i))
            }
            _ => None,
        }
    }

    /// RC-EXP-05: a literal that takes arguments is not used bare.
    pub(super) fn bare_literal(&mut self, e: &SyntaxNode) {
        let Some((loc, i)) = self.literal_of(e) else { return };
        self.bare_literal_at(e, loc, i);
    }

    /// [`Typer::bare_literal`] for a `REF_EXPR` `e` whose name is `r`.
    pub(super) fn bare_literal_named(&mut self, e: &SyntaxNode, r: &SyntaxNode) {
        let Some((loc, i)) = self.literal_named(r) else { return };
        self.bare_literal_at(e, loc, i);
    }

    pub(super) fn bare_literal_at(&mut self, e: &SyntaxNode, loc: ItemLoc, i: u32) {
        let is_callee = e.parent().is_some_and(|p| p.kind() == CALL_EXPR && first_operand(&p).as_ref() == Some(e));
        let lit = &loc.summary(self.db).members[i as usize];
        if !is_callee && !lit.params.is_empty() {
            let msg = format!("`{}` expects {}", lit.name, arguments(lit.params.len()));
            self.problem("RC-EXP-05", e.text_range(), msg);
        }
    }

    pub(super) fn initialiser(&mut self, n: &SyntaxNode) {
        let Some(init) = first_operand(n) else { return };
        let Some(ty) = n.children().find(|c| ast::is_type_kind(c.kind())) else { return };
        let declared = self.lower(self.file, &lower_type(&ty));
        let t = self.expr(&init);
        if !compatible(&t, &declared) {
            let name = n.children().find(|c| c.kind() == NAME).map(|x| x.text().to_string()).unwrap_or_default();
            self.problem(
                "RC-VAR-01",
                init.text_range(),
                format!("`{}` has type {declared}, but its initial value has type {t}", name.trim()),
            );
        }
    }

    pub(super) fn assignment(&mut self, n: &SyntaxNode) {
        let Some(target) = n.children().find(|c| c.kind() == ASSIGNABLE) else { return };
        let Some(value) = first_operand(n) else { return };
        let Some(q) = target.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let mut ty = match self.targets.get(&q.text_range()) {
            Some(t) => self.target_type(*t),
            None => {
                let name = crate::defs::name_text(&q);
                self.env.iter().rev().find(|(x, _)| *x == name).map(|(_, t)| t.clone()).unwrap_or(Ty::Error)
            }
        };
        // Follow `.f` and `[i]` selectors.
        for s in target.children() {
            ty = match (s.kind(), &ty) {
                (FIELD_ACCESS, Ty::Named(loc, rname, DefKind::Record)) => {
                    let fref = s.children().find(|c| c.kind() == NAME_REF);
                    let f = fref.as_ref().map(crate::defs::name_text).unwrap_or_default();
                    let field =
                        loc.summary(self.db).members.iter().find(|m| m.kind == DefKind::Field && m.name == f).cloned();
                    match field {
                        Some(m) => m.ty.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error),
                        None => {
                            if let Some(r) = fref {
                                self.problem("LNK-01", r.text_range(), format!("record `{rname}` has no field `{f}`"));
                            }
                            Ty::Error
                        }
                    }
                }
                (INDEX_ACCESS, Ty::Seq(a)) | (INDEX_ACCESS, Ty::Vector(a, _)) | (INDEX_ACCESS, Ty::Matrix(a, _, _)) => {
                    (**a).clone()
                }
                (INDEX_ACCESS, Ty::Function(_, b)) | (INDEX_ACCESS, Ty::Relation(_, b)) => (**b).clone(),
                (FIELD_ACCESS | INDEX_ACCESS, _) => Ty::Error,
                _ => ty,
            };
            for e in operands(&s) {
                self.expr(&e);
            }
        }
        let t = self.expr(&value);
        if !compatible(&t, &ty) {
            self.problem(
                "RC-STMT-02",
                target.text_range(),
                format!("`{}` has type {ty}, but the value has type {t}", target.text().to_string().trim()),
            );
        }
    }

    pub(super) fn call_stmt(&mut self, n: &SyntaxNode) {
        let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let args = self.typed_args(n);
        let params: Vec<Ty> = match self.targets.get(&q.text_range()) {
            Some(Target::Def(f, id)) => match &self.unit.defs_of(self.db, *f, *id).def(*id).data {
                DefData::Signature { params, .. } => {
                    params.iter().map(|(_, t)| t.as_ref().map(|t| self.lower(*f, t)).unwrap_or(Ty::Error)).collect()
                }
                _ => return,
            },
            Some(Target::Member(loc, i)) => {
                let m = &loc.summary(self.db).members[*i as usize];
                m.params.iter().map(|(_, t)| t.as_ref().map(|t| self.lower(loc.file, t)).unwrap_or(Ty::Error)).collect()
            }
            _ => return,
        };
        // Only messages need the name: read it then.
        let name = || q.text().to_string().trim().to_string();
        if params.len() != args.len() {
            self.problem(
                "RC-STMT-05",
                n.text_range(),
                format!("operation `{}` takes {}, not {}", name(), arguments(params.len()), args.len()),
            );
            return;
        }
        for (i, (p, (x, a))) in params.iter().zip(&args).enumerate() {
            if compatible(a, p) {
                continue;
            }
            match narrowing(a, p) {
                // RoboTool accepts a wider numeric argument (it compares the
                // parameter's type with the argument's); the call still means
                // something, but the value may not fit.
                Some(risk) => self.problem(
                    "RC-STMT-05-narrow",
                    x.text_range(),
                    format!(
                        "argument {} of `{}` has type {a} where {p} is expected: {risk} would be wrong at run time",
                        i + 1,
                        name()
                    ),
                ),
                None => self.problem(
                    "RC-STMT-05",
                    x.text_range(),
                    format!("argument {} of `{}` has type {a}, expected {p}", i + 1, name()),
                ),
            }
        }
    }

    pub(super) fn event_type(&self, r: &SyntaxNode) -> Option<Option<Ty>> {
        let t = self.targets.get(&r.text_range())?;
        Some(match t {
            Target::Def(f, id) => match &self.unit.defs_of(self.db, *f, *id).def(*id).data {
                DefData::Typed { ty, .. } => ty.as_ref().map(|t| self.lower(*f, t)),
                _ => None,
            },
            Target::Member(loc, i) => {
                loc.summary(self.db).members[*i as usize].ty.as_ref().map(|t| self.lower(loc.file, t))
            }
            Target::Item(_) => None,
        })
    }

    pub(super) fn communication(&mut self, n: &SyntaxNode) {
        let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = crate::defs::name_text(&r);
        let Some(ety) = self.event_type(&r) else { return };
        let payload = n.children().find(|c| matches!(c.kind(), COMM_INPUT | COMM_OUTPUT | COMM_SYNC));
        match (payload, ety) {
            (None, Some(t)) => self.problem(
                "RC:Tg2",
                r.text_range(),
                format!("`{name}` carries a value of type {t}: receive it (`{name}?x`) or send one (`{name}!v`)"),
            ),
            (Some(p), None) => self.problem(
                "RC:Tg5",
                r.text_range(),
                format!("`{name}` carries no value, so `{}` is not possible", p.text().to_string().trim()),
            ),
            (Some(p), Some(et)) => match p.kind() {
                COMM_INPUT => {
                    if let Some(q) = p.children().find(|c| c.kind() == QUALIFIED_NAME) {
                        let vt = self.targets.get(&q.text_range()).map(|t| self.target_type(*t)).unwrap_or(Ty::Error);
                        if !compatible(&et, &vt) {
                            self.problem(
                                "RC-COMM-01",
                                q.text_range(),
                                format!(
                                    "`{}` has type {vt} and cannot hold values of `{name}`, of type {et}",
                                    q.text().to_string().trim()
                                ),
                            );
                        }
                    }
                }
                _ => {
                    if let Some(v) = &first_operand(&p) {
                        let vt = self.expr(v);
                        if !compatible(&vt, &et) {
                            let code = if p.kind() == COMM_OUTPUT { "RC-COMM-02" } else { "RC-COMM-03" };
                            self.problem(
                                code,
                                v.text_range(),
                                format!("`{name}` carries {et}, but the value has type {vt}"),
                            );
                        }
                    }
                }
            },
            (None, None) => {}
        }
    }

    pub(super) fn output_comm(&mut self, n: &SyntaxNode) {
        let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let Some(ety) = self.event_type(&q) else { return };
        let name = q.text().to_string().trim().to_string();
        match (first_operand(n).as_ref(), ety) {
            (None, Some(t)) => self.problem(
                "RS-IO-06",
                q.text_range(),
                format!("`{name}` carries a value of type {t}: write `${name}!v`"),
            ),
            (Some(v), None) => {
                self.problem("RS-IO-06", v.text_range(), format!("`{name}` carries no value: write `${name}`"))
            }
            (Some(v), Some(et)) => {
                let vt = self.expr(v);
                if !compatible(&vt, &et) {
                    self.problem(
                        "RS-IO-06",
                        v.text_range(),
                        format!("`{name}` carries {et}, but the value has type {vt}"),
                    );
                }
            }
            (None, None) => {}
        }
    }

    pub(super) fn probability(&mut self, n: &SyntaxNode) {
        let Some(e) = first_operand(n) else { return };
        let t = self.expr(&e);
        if !compatible(&t, &Ty::Real) {
            self.problem("RC:PT2", e.text_range(), format!("a probability is a number in [0, 1]; this has type {t}"));
            return;
        }
        // A literal, or a constant whose initialiser is a literal.
        let literal = match e.kind() {
            LITERAL => Some(e.text().to_string()),
            REF_EXPR => e
                .children()
                .find(|c| c.kind() == NAME_REF)
                .and_then(|r| self.targets.get(&r.text_range()).copied())
                .and_then(|t| crate::nav::declaration(self.db, t))
                .and_then(|d| match &file_defs(self.db, d.file).def(d.def).data {
                    DefData::Typed { init: Some(init), .. } => Some(d.file.text(self.db)[*init].to_string()),
                    _ => None,
                }),
            _ => None,
        };
        if let Some(text) = literal {
            if let Ok(v) = text.trim().parse::<f64>() {
                if !(0.0..=1.0).contains(&v) {
                    self.problem("RC:PT2", e.text_range(), "a probability must lie in [0, 1]".into());
                }
            }
        }
    }
}
