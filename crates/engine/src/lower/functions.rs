//! Calls of functions the model declares (robotool-facts RT-2): one
//! defined by a postcondition `result == e` is RoboTool's CSPm function
//! `f(x) = e`, inlined at the call; one without such a definition returns
//! its result type's default — 0, `true`, the first literal, the empty
//! set, component-wise for tuples and records — whatever its other
//! postconditions say, unless a `csp` block defines it (then
//! [`super::expr`] inlines that definition).

use robosim_hir::csp_fn::block_definition;
use robosim_hir::index::resolve_item;
use robosim_hir::model::DefKind;
use robosim_hir::model::{ExprKind, Function, Item};
use robosim_hir::resolve::Target;

use super::types::Layout;
use super::*;

impl MachineCx<'_, '_> {
    /// The value a call of `f` (at `at`, resolved to `res`) returns when
    /// no CSPm definition is given: RT-2's default, noted as one. A
    /// function defined by a `result == e` postcondition, or one that an
    /// `Instantiations` block (which replaces RoboTool's defaults, RT-7)
    /// does not define, is refused with the reason.
    pub(super) fn bodiless_call(
        &mut self,
        at: TextRange,
        f: &str,
        res: Option<&Target>,
    ) -> Result<(Val, Layout), Unsupported> {
        let (file, func) = self
            .function_decl(f, res)
            .ok_or_else(|| self.err(at, format!("the function `{f}` could not be resolved")))?;
        // Generic parameters alone do not matter: the default is the
        // result's, whatever the arguments (RT-2).
        if let Some(why) = func.generic_refusal() {
            return Err(self.err(at, why));
        }
        if func.pins_result() {
            return Err(self.err(
                at,
                format!(
                    "`{f}` is defined by a postcondition `result == …`, which the native checker does not \
                     inline yet: define it in a `csp` block of an assertion file, as for FDR (`{f}(x) = …`)"
                ),
            ));
        }
        if self.cx.defaults.replaced {
            return Err(self.err(
                at,
                format!(
                    "`{f}` has no definition the native checker can read: the assertion file's `csp \
                     Instantiations` block replaces RoboTool's generated defaults (RT-7) and does not define \
                     it, so FDR would stop on the undefined name; define it there (`{f}(x) = …`)"
                ),
            ));
        }
        let ty = self.ty_of(file, func.result.as_ref(), func.range)?;
        let v = self.default_of(func.result.as_ref(), &ty);
        let params: Vec<&str> = func.params.iter().map(|p| p.name.as_str()).collect();
        let shown = match &ty {
            Layout::Set(_) => "{}".to_string(),
            Layout::Num(_) => self.value_text(func.result.as_ref(), &ty, v),
            Layout::Seq(_) => "<>".to_string(),
            // Tuples and records: each component's default (numbers 0).
            Layout::Tuple(ds) | Layout::Record(_, ds) => {
                let parts: Vec<String> = ds.iter().map(|d| d.lo.max(0).min(d.hi).to_string()).collect();
                format!("({})", parts.join(", "))
            }
            // Nested products: their numbers in order.
            Layout::Product(_) => {
                let parts: Vec<String> = ty.leaves().iter().map(|d| d.lo.max(0).min(d.hi).to_string()).collect();
                format!("({})", parts.join(", "))
            }
        };
        let note = format!("function {}({}) = {shown} (RT-2)", func.name, params.join(", "));
        let design = self.design();
        if !design.defaults.contains(&note) {
            design.defaults.push(note);
        }
        Ok((v, ty))
    }
}

impl<'b> MachineCx<'_, 'b> {
    /// A call of `f` (at `at`, resolved to `res`) on `args`, when `f` is
    /// defined by one postcondition `result == e` (or `result iff e`), the
    /// form RoboTool generates a CSPm function from (`f(x) = e`): `e`
    /// inlined with the arguments' values for the parameters, each
    /// operation in the type of its expression, as RoboTool's; `None` when
    /// `f` has no such definition. `e` sees only the parameters (a
    /// function cannot read a machine's variables); numeric parameters
    /// only.
    pub(super) fn defined_call(
        &mut self,
        at: TextRange,
        f: &str,
        res: Option<&Target>,
        args: &[model::Expr],
    ) -> Result<Option<Expr>, Unsupported> {
        let Some((file, func)) = self.function_decl(f, res) else { return Ok(None) };
        let Some(body) = result_definition(func) else { return Ok(None) };
        if let Some(why) = func.generic_refusal() {
            return Err(self.err(at, why));
        }
        if args.len() != func.params.len() {
            return Err(self.err(at, format!("`{f}` takes {} arguments", func.params.len())));
        }
        if self.inlining >= 16 {
            return Err(self.err(at, format!("`{f}` calls itself too deeply to inline")));
        }
        let mut bound = HashMap::new();
        for (p, a) in func.params.iter().zip(args) {
            if !self.ty_of(file, p.ty.as_ref(), p.range)?.is_num() {
                return Err(self.err(
                    at,
                    format!(
                        "`{f}` has a parameter `{}` that is a tuple, a record or a set: inlining its definition \
                         is supported for numbers, booleans and enumerations",
                        p.name
                    ),
                ));
            }
            let v = self.expr(a)?;
            bound.insert(p.name.clone(), Name::Bound(v));
        }
        if !self.ty_of(file, func.result.as_ref(), func.range)?.is_num() {
            return Ok(None);
        }
        // The body in the function's own scope and file (its types, and
        // where an error points).
        let names = std::mem::replace(&mut self.names, bound);
        let types = std::mem::take(&mut self.types);
        let here = std::mem::replace(&mut self.file, file);
        self.inlining += 1;
        let out = self.expr(body);
        self.inlining -= 1;
        self.file = here;
        self.types = types;
        self.names = names;
        out.map(Some)
    }

    /// The name of the `csp` block definition a call of `f` (resolved to
    /// `res`) reads, if a block defines it (RT-7,
    /// [`robosim_hir::csp_fn::block_definition`], as hir's domains read
    /// it); reading the older generators' name is noted.
    pub(super) fn block_function(&mut self, f: &str, res: Option<&Target>) -> Option<String> {
        let decl = self.function_decl(f, res);
        let robotool = decl.map(|(file, func)| {
            robosim_hir::csp_fn::robotool_function_name(
                robosim_hir::element::file_package(self.cx.db, file),
                &func.name,
            )
        });
        let (name, older) =
            block_definition(&self.cx.defaults.functions, robotool.as_deref(), f, self.cx.defaults.replaced)?;
        if let (true, Some(r)) = (older, &robotool) {
            let note = format!(
                "the `csp` block's `{name}` was read as the definition of the model's function (RT-7), as the older \
                 RoboTool generators whose FDR results are recorded named it; RoboTool 3's script calls it `{r}`, \
                 which the block does not define (FDR stops): write `{r}(…) = …` for RoboTool 3"
            );
            let design = self.design();
            if !design.readings.contains(&note) {
                design.readings.push(note);
            }
        }
        Some(name.to_string())
    }

    /// The declaration of the function `f` called here.
    fn function_decl(&self, f: &str, res: Option<&Target>) -> Option<(File, &'b Function)> {
        let loc = match res {
            Some(Target::Item(loc)) => Some(*loc),
            _ => None,
        };
        let loc = loc.or_else(|| {
            let path: Vec<String> = f.split("::").map(|s| s.trim().to_string()).collect();
            resolve_item(self.cx.db, self.cx.ws, self.file, &path, |k| k == DefKind::Function).into_iter().next()
        })?;
        match model::item(self.cx.db, self.cx.ws, loc)? {
            Item::Function(func) => Some((loc.file, func)),
            _ => None,
        }
    }
}

/// The `e` of the one postcondition `result == e` (or `result iff e`)
/// of `f` ([`Function::result_definitions`]); `None` when there is none,
/// or several.
fn result_definition(f: &Function) -> Option<&model::Expr> {
    match f.result_definitions().as_slice() {
        [e] if !matches!(e.kind, ExprKind::Missing) => Some(e),
        _ => None,
    }
}

impl MachineCx<'_, '_> {
    /// RT-11: the parameters of an operation checked on its own are
    /// constants of its process: the value `with parameter x of Op set to
    /// v` gives, else RoboTool's default (`param_x = 0`; `true` for a
    /// boolean, as for constants), noted.
    pub(super) fn parameters_as_constants(&mut self, body: &Behaviour) -> Result<(), Unsupported> {
        for p in &body.params {
            let ty = self.ty_of(self.file, p.ty.as_ref(), p.range)?;
            if !ty.is_num() {
                return Err(self.err(p.range, "parameters of tuple, record or set types are not supported yet"));
            }
            let value = match self.const_value(&p.name) {
                Some(v) => v,
                None => {
                    let v = self.default_of(p.ty.as_ref(), &ty);
                    let shown = self.value_text(p.ty.as_ref(), &ty, v);
                    let note = format!("parameter {}::{} = {shown} (RT-11)", self.decl_name, p.name);
                    self.design().defaults.push(note);
                    v
                }
            };
            let q = format!("{}::{}", self.decl_name, p.name);
            self.design().constants.push((q, value, value.to_string()));
            self.names.insert(p.name.clone(), Name::Const(value));
        }
        Ok(())
    }
}
