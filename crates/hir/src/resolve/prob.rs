//! Names in the probabilistic items of `.assertions` files (syntax.md
//! §5.3): the instance paths of formulas and `constants` blocks
//! (`modUVC::ctrlUVC::stm_ref3::ticks`: a module, its controller reference,
//! the machine reference, then a variable), the property constants
//! (`const t`), enumeration literals, and `with constants NAME`.

use robosim_syntax::{SyntaxKind::*, SyntaxNode, TextRange};

use super::{ctx_def, ctx_members, node_ctx, Ctx, RefKind, Resolver, Target};
use crate::defs::{file_defs, DefKind};
use crate::index::resolve_item;
use crate::{Db, File, Workspace};

impl Resolver<'_> {
    /// Resolves every name of the probabilistic items of the file.
    pub(super) fn probabilistic(&mut self, root: &SyntaxNode) {
        for n in root.descendants() {
            match n.kind() {
                PROB_PATH => {
                    let Some(q) = n.children().find(|c| c.kind() == QUALIFIED_NAME) else { continue };
                    self.formula_path(&q);
                }
                PROB_CONFIG => {
                    let mut qs = n.children().filter(|c| c.kind() == QUALIFIED_NAME);
                    if let Some(q) = qs.next() {
                        let of = qs.next();
                        self.config_target(&q, of.as_ref());
                    }
                    // Values: enumeration literals (`Mode::Idle`, `Idle`).
                    for e in n.descendants().filter(|d| matches!(d.kind(), ENUM_LITERAL_EXPR | REF_EXPR)) {
                        self.value_literal(&e);
                    }
                }
                PROB_WITH_CONSTANTS => {
                    let Some(r) = n.children().find(|c| c.kind() == NAME_REF) else { continue };
                    let name = crate::defs::name_text(&r);
                    let found = self
                        .defs
                        .iter()
                        .find(|(_, d)| d.syntax == PROB_CONSTANTS && d.name == name)
                        .map(|(id, _)| Target::Def(self.file, id));
                    self.push(r.text_range(), name.clone(), RefKind::Type, found);
                    if found.is_none() {
                        self.problem(
                            "LNK-01",
                            r.text_range(),
                            format!("cannot resolve `{name}`: no `constants {name}` block in this file"),
                        );
                    }
                }
                _ => {}
            }
        }
    }

    /// A name in a formula: a property constant, an enumeration literal or
    /// an element of the model by its instance path.
    fn formula_path(&mut self, q: &SyntaxNode) {
        let path = super::segments(q);
        let text = path.join("::");
        let found = if let [one] = path.as_slice() {
            self.defs
                .iter()
                .find(|(_, d)| d.syntax == PROB_CONST && &d.name == one)
                .map(|(id, _)| Target::Def(self.file, id))
                .or_else(|| enum_literal(self.db, self.ws, self.file, &path))
        } else {
            enum_literal(self.db, self.ws, self.file, &path)
                .or_else(|| instance_path(self.db, self.ws, self.file, &path))
        };
        self.push(q.text_range(), text.clone(), RefKind::Type, found);
        if found.is_none() {
            self.problem(
                "LNK-01",
                q.text_range(),
                format!("cannot resolve `{text}`: not a property constant, an enumeration literal or an element of the model (`module::controller::machine::variable`)"),
            );
        }
    }

    /// `[constant] path [of element] set to v`.
    fn config_target(&mut self, q: &SyntaxNode, of: Option<&SyntaxNode>) {
        let mut path = super::segments(q);
        if let Some(of) = of {
            let owner = super::segments(of);
            let found = instance_path(self.db, self.ws, self.file, &owner);
            self.push(of.text_range(), owner.join("::"), RefKind::Type, found);
            if found.is_none() {
                self.problem("LNK-01", of.text_range(), format!("cannot resolve `{}`", owner.join("::")));
                return;
            }
            path = owner.into_iter().chain(path).collect();
        }
        let text = super::segments(q).join("::");
        let found = instance_path(self.db, self.ws, self.file, &path);
        self.push(q.text_range(), text.clone(), RefKind::Type, found);
        if found.is_none() {
            self.problem(
                "LNK-01",
                q.text_range(),
                format!("cannot resolve `{text}`: not a constant of the model by its instance path"),
            );
        }
    }

    fn value_literal(&mut self, e: &SyntaxNode) {
        let refs: Vec<SyntaxNode> = e.children().filter(|c| c.kind() == NAME_REF).collect();
        let path: Vec<String> = refs.iter().map(crate::defs::name_text).collect();
        if path.is_empty() {
            return;
        }
        let range = TextRange::new(refs[0].text_range().start(), refs[refs.len() - 1].text_range().end());
        if let Some(t) = enum_literal(self.db, self.ws, self.file, &path) {
            self.push(range, path.join("::"), RefKind::Type, Some(t));
        }
    }
}

/// `E::L` (qualified or not) or a bare literal `L` of a visible enumeration.
fn enum_literal(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<Target> {
    let (lit, enum_path) = path.split_last()?;
    let candidates = if enum_path.is_empty() {
        let index = crate::index::index_for(db, ws, file);
        let mut all: Vec<_> = index.items.values().flatten().copied().collect();
        all.sort_by(|a, b| (a.file.path(db), a.index).cmp(&(b.file.path(db), b.index)));
        all
    } else {
        resolve_item(db, ws, file, enum_path, |k| k == DefKind::Enumeration)
    };
    candidates.into_iter().find_map(|loc| {
        let s = loc.summary(db);
        if s.kind != DefKind::Enumeration {
            return None;
        }
        let i = s.members.iter().position(|m| m.kind == DefKind::EnumLiteral && &m.name == lit)?;
        Some(Target::Member(loc, i as u32))
    })
}

/// An element by its instance path: the longest prefix that names a
/// module, controller, machine or operation, then the names of references
/// (`cref`, `sref`, `rref`, `opref`), inline parts, states and finally the
/// variable, constant, event, clock or state.
fn instance_path(db: &dyn Db, ws: Workspace, file: File, path: &[String]) -> Option<Target> {
    let accept = |k: DefKind| {
        matches!(
            k,
            DefKind::Module | DefKind::Controller | DefKind::StateMachine | DefKind::Operation | DefKind::Platform
        )
    };
    let (k, loc) =
        (1..=path.len()).rev().find_map(|k| resolve_item(db, ws, file, &path[..k], accept).first().map(|l| (k, *l)))?;
    if k == path.len() {
        return Some(Target::Item(loc));
    }
    let mut ctx = Ctx::Item(loc);
    let rest = &path[k..];
    for (i, seg) in rest.iter().enumerate() {
        let last = i + 1 == rest.len();
        let (f, def) = ctx_def(db, ctx)?;
        let defs = file_defs(db, f);
        if let Some((id, d)) = defs.children(Some(def)).find(|(_, d)| &d.name == seg) {
            if last {
                return Some(Target::Def(f, id));
            }
            ctx = match d.kind {
                DefKind::ControllerRef | DefKind::MachineRef | DefKind::PlatformRef | DefKind::OperationRef => {
                    node_ctx(db, ws, f, id)?
                }
                _ => Ctx::Local(f, id),
            };
            continue;
        }
        // Members that come through interfaces (`uses I` variables, …).
        if last {
            return ctx_members(db, ws, ctx).iter().find(|m| &m.name == seg).map(|m| m.target);
        }
        return None;
    }
    None
}
