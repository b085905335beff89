//! Names in the assertions and simulations of `.rsa` and `.assertions`
//! files: what `simulation S of M` simulates, the sides of an assertion (a
//! simulation of the file or an element of the model), the element and
//! constant of `with constant k of X`, and the operation and parameter of
//! `with parameter x of P`. Only names that resolve are
//! recorded, for navigation, hover and rename; nothing is reported here
//! (the assertion's check says what it cannot find).

use robosim_syntax::{SyntaxKind::*, SyntaxNode};

use super::{RefKind, Resolver, Target};
use crate::defs::{file_defs, DefKind};
use crate::index::resolve_item;

/// The kinds an assertion or a simulation may name.
fn element(k: DefKind) -> bool {
    matches!(k, DefKind::Module | DefKind::Controller | DefKind::StateMachine | DefKind::Operation)
}

impl Resolver<'_> {
    /// Records the names of the file's assertions and simulations.
    pub(super) fn assertion_names(&mut self, root: &SyntaxNode) {
        for n in root.children() {
            match n.kind() {
                SIMULATION => {
                    let of = n
                        .children_with_tokens()
                        .skip_while(|t| t.kind() != OF_KW)
                        .find_map(|t| t.into_node().filter(|c| c.kind() == QUALIFIED_NAME));
                    if let Some(q) = of {
                        self.element_ref(&q);
                    }
                }
                ASSERTION => {
                    let sides = n
                        .children()
                        .filter(|c| matches!(c.kind(), ASSERTION_SUBJECT | ASSERTION_BODY))
                        .flat_map(|c| c.children().filter(|q| q.kind() == QUALIFIED_NAME).collect::<Vec<_>>());
                    for q in sides {
                        self.side_ref(&q);
                    }
                    for p in n.descendants().filter(|d| d.kind() == CONSTANT_PARAM) {
                        self.constant_param(&p);
                    }
                    for p in n.descendants().filter(|d| d.kind() == PARAMETER_PARAM) {
                        self.parameter_param(&p);
                    }
                }
                _ => {}
            }
        }
    }

    /// A side of an assertion: a simulation of this file by name, else an
    /// element of the model.
    fn side_ref(&mut self, q: &SyntaxNode) {
        let path = super::segments(q);
        if let [name] = path.as_slice() {
            let sim =
                self.defs.iter().find(|(_, d)| d.kind == DefKind::Simulation && d.name == *name).map(|(id, _)| id);
            if let Some(id) = sim {
                self.push(q.text_range(), name.clone(), RefKind::Type, Some(Target::Def(self.file, id)));
                return;
            }
        }
        self.element_ref(q);
    }

    /// An element of the model by its (qualified) name, when it resolves.
    fn element_ref(&mut self, q: &SyntaxNode) -> Option<crate::index::ItemLoc> {
        let path = super::segments(q);
        let loc = resolve_item(self.db, self.ws, self.file, &path, element).first().copied()?;
        self.push(q.text_range(), path.join("::"), RefKind::Type, Some(Target::Item(loc)));
        Some(loc)
    }

    /// `parameter x of P`: the operation `P` names (through an operation
    /// reference or an instance path too, RT-11), and its parameter `x`.
    fn parameter_param(&mut self, p: &SyntaxNode) {
        let Some(of) = p.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let path = super::segments(&of);
        let Some((f, op)) = crate::target::operation_def(self.db, self.ws, self.file, &path) else { return };
        // Through a reference (`D::o`) the name written is the reference's,
        // not the operation's: only a direct name is a reference to it
        // (so that renaming the operation never rewrites `o`).
        if path.last() == Some(&file_defs(self.db, f).def(op).name) {
            self.push(of.text_range(), path.join("::"), RefKind::Type, Some(Target::Def(f, op)));
        }
        let Some(k) = p.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = crate::defs::name_text(&k);
        let param = file_defs(self.db, f)
            .children(Some(op))
            .find(|(_, d)| d.kind == DefKind::Parameter && d.name == name)
            .map(|(id, _)| id);
        if let Some(id) = param {
            self.push(k.text_range(), name, RefKind::Type, Some(Target::Def(f, id)));
        }
    }

    /// `constant k of X`: the element `X`, and `k` when `X` declares it.
    fn constant_param(&mut self, p: &SyntaxNode) {
        let Some(of) = p.children().find(|c| c.kind() == QUALIFIED_NAME) else { return };
        let Some(loc) = self.element_ref(&of) else { return };
        let Some(k) = p.children().find(|c| c.kind() == NAME_REF) else { return };
        let name = crate::defs::name_text(&k);
        let Some(owner) = loc.def(self.db) else { return };
        let constant = file_defs(self.db, loc.file)
            .children(Some(owner))
            .find(|(_, d)| d.kind == DefKind::Constant && d.name == name)
            .map(|(id, _)| id);
        if let Some(id) = constant {
            self.push(k.text_range(), name, RefKind::Type, Some(Target::Def(loc.file, id)));
        }
    }
}
