//! Functions of the model as CSPm functions: one defined by a
//! postcondition `result == e` is RoboTool's `f(x) = e`; one without a body
//! returns its result type's default (RT-2), defined in the instantiations
//! by RoboTool's name.

use std::rc::Rc;

use robosim_hir::model as m;
use robosim_hir::File;

use super::{ECtx, Gen, Nm};
use crate::cspm::Decl;
use crate::export::{Exporter, Ty};

/// A function of the model exported as a CSPm function.
#[derive(Debug, Clone)]
pub(crate) struct FunctionOut {
    /// Its CSPm name.
    pub csp: String,
    /// The types of its parameters; `None` for a generic one (`?X`): a
    /// CSPm function is untyped, so its argument is written at its own
    /// type.
    pub params: Vec<Option<Ty>>,
    /// The type of its result.
    pub result: Ty,
    /// Whether it has no body: its definition is RT-2's default, in the
    /// instantiations.
    pub bodiless: bool,
    /// The functions without a body its definition calls (through others
    /// too).
    pub calls: std::collections::BTreeSet<String>,
}

/// The CSPm function of the model's function `f` of `file`, made on first
/// use: one defined by a postcondition `result == e` is RoboTool's
/// function `f(x) = e` (in the model's file); one without a body returns
/// its result type's default (RT-2), written into the instantiations by
/// RoboTool's name (`Mathematics_random() = 0`), which a `csp` block of an
/// assertion file may define instead (RT-7).
pub(crate) fn function(ex: &mut Exporter<'_>, file: File, f: &m::Function) -> Result<Rc<FunctionOut>, String> {
    let key = (file, f.range);
    let fname = f.name.clone();
    match ex.functions.get(&key) {
        Some(Some(f)) => return Ok(f.clone()),
        Some(None) => return Err(format!("the function `{fname}` is recursive: not supported by the export yet")),
        None => {}
    }
    ex.functions.insert(key, None);
    let r = function_inner(ex, file, f);
    match &r {
        Ok(f) => {
            ex.functions.insert(key, Some(f.clone()));
        }
        Err(_) => {
            ex.functions.remove(&key);
        }
    }
    r
}

fn function_inner(ex: &mut Exporter<'_>, file: File, model: &m::Function) -> Result<Rc<FunctionOut>, String> {
    let fname = model.name.clone();
    // The engine refuses for the same reason (a generic result, or a body
    // over generic types).
    if let Some(why) = model.generic_refusal() {
        return Err(why);
    }
    let mut params = Vec::new();
    for p in &model.params {
        // RoboTool's `p_f(x, y) = true` needs no type for a generic
        // parameter: a function without a body ignores its arguments.
        if p.ty.as_ref().is_some_and(|t| t.ty.type_variable().is_some()) {
            params.push((p.name.clone(), None));
            continue;
        }
        let t = ex.ty_ref(file, p.ty.as_ref()).map_err(|m| format!("function `{fname}`: {m}"))?;
        params.push((p.name.clone(), Some(t)));
    }
    let result = ex.ty_ref(file, model.result.as_ref()).map_err(|m| format!("function `{fname}`: {m}"))?;
    // The one postcondition `result == e` (or `result iff e`) defines it.
    let body = match model.result_definitions().as_slice() {
        [body] => *body,
        [] if !model.pins_result() => {
            return bodiless(ex, file, model, params, result);
        }
        _ => {
            return Err(format!(
                "the function `{fname}` is defined by its postconditions in a form other than one `result == …`, \
                 whose CSPm RoboTool's is not established: calls of it are not exported"
            ))
        }
    };
    if body.kind == m::ExprKind::Missing {
        return Err(format!("function `{fname}`: an incomplete postcondition"));
    }
    let mut path = ex.package(file);
    path.push(fname.clone());
    let csp = ex.module_name(&path);
    let mut g = Gen::new(ex, file, None, path.clone(), model.range, false);
    let mut names = Vec::new();
    for (n, t) in &params {
        // (`generic_refusal` leaves no generic parameter to a body.)
        let Some(t) = t else {
            return Err(format!("function `{fname}`: the parameter `{n}` has a generic type"));
        };
        let local = g.local(n);
        g.names.insert(n.clone(), Nm::Param(local.clone(), t.clone()));
        names.push(local);
    }
    // `f() = e`, called `f()` (see `bodiless`).
    if names.is_empty() {
        names.push(String::new());
    }
    let out = g.expr(body, ECtx::Const, Some(&result));
    let problems = std::mem::take(&mut g.problems);
    let calls = std::mem::take(&mut g.fn_calls);
    let Some(out) = out else {
        let why = problems.first().map(|p| p.2.clone()).unwrap_or_default();
        return Err(format!("function `{fname}` is not exported: {why}"));
    };
    ex.emit(
        file,
        vec![Decl::Comment(format!("function {}", path.join("::"))), Decl::Def(csp.clone(), names, out.e), Decl::Blank],
    );
    Ok(Rc::new(FunctionOut {
        csp,
        params: params.into_iter().map(|(_, t)| t).collect(),
        result,
        bodiless: false,
        calls,
    }))
}

/// RT-2: the function `model` of `file` has no body (no postcondition
/// `result == e`), so RoboTool's CSPm returns its result type's default,
/// whatever else its pre- and postconditions say; the definition is
/// registered for the instantiations under RoboTool's name, the package's
/// path and the function's name joined by `_` (`Mathematics_random`).
fn bodiless(
    ex: &mut Exporter<'_>,
    file: File,
    model: &m::Function,
    params: Vec<(String, Option<Ty>)>,
    result: Ty,
) -> Result<Rc<FunctionOut>, String> {
    let fname = &model.name;
    if let Some(t) = abstract_part(ex, &result) {
        return Err(format!(
            "the function `{fname}` has no body and returns a value of the primitive type `{t}`, whose default \
             in RoboTool's CSPm is not established (RT-2): calls of it are not exported"
        ));
    }
    let mut path = ex.package(file);
    path.push(fname.clone());
    let csp = crate::util::qualified(&path);
    // A name CSPm reserves (`card`, `union`…) is RoboTool's all the same,
    // and clashes in its script: what FDR makes of it is not established.
    if csp != path.join("_") {
        return Err(format!(
            "RoboTool's CSPm name `{}` of the function `{fname}` is reserved in CSPm: calls of it are not exported",
            path.join("_")
        ));
    }
    if ex.module_name(&path) != csp {
        return Err(format!(
            "RoboTool's CSPm name `{csp}` of the function `{fname}` is taken by another element of the export: \
             calls of it are not exported"
        ));
    }
    let mut g = Gen::new(ex, file, None, path.clone(), model.range, false);
    let mut names: Vec<String> = params.iter().map(|(n, _)| g.local(n)).collect();
    // `f() = e`: a function of no arguments, called `f()` (RT-2's
    // `Mathematics_random() = 0`), not the constant `f = e`.
    if names.is_empty() {
        names.push(String::new());
    }
    let comment = format!(
        "function {} ({}): no body, its result type's default (RT-2)",
        path.join("::"),
        ex.loc(file, model.range)
    );
    ex.fn_defaults.push(crate::export::FnDefault {
        csp: csp.clone(),
        name: fname.clone(),
        params: names,
        value: result.default_value(),
        comment,
    });
    Ok(Rc::new(FunctionOut {
        csp,
        params: params.into_iter().map(|(_, t)| t).collect(),
        result,
        bodiless: true,
        calls: Default::default(),
    }))
}

/// The name of an abstract primitive type (`type T`) in `t` where the
/// default depends on it (not inside a set or a sequence, empty anyway).
fn abstract_part(ex: &Exporter<'_>, t: &Ty) -> Option<String> {
    match t {
        Ty::Named(n, _) => ex.abstract_types.values().any(|a| a == n).then(|| n.clone()),
        Ty::Product(ts) => ts.iter().find_map(|t| abstract_part(ex, t)),
        Ty::Record(r) => r.fields.iter().find_map(|(_, t)| abstract_part(ex, t)),
        _ => None,
    }
}
