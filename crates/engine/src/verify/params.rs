//! `with parameter x of Op set to v` (robotool-facts RT-11): the values
//! an assertion gives the parameters of an operation checked on its own,
//! which are constants of its process.

use crate::assertions::{AssertionDecl, Override, Value};
use crate::ir::Val;
use crate::lower::ConstValue;

/// The parameter values assertion `a` gives, as constants of the
/// operation named by `of`.
pub(super) fn parameter_values(a: &AssertionDecl) -> Result<Vec<ConstValue>, String> {
    let mut out = Vec::new();
    for o in &a.overrides {
        if let Override::Parameter { name, of, value, .. } = o {
            let value = match value {
                Value::Int(v) => *v,
                Value::Bool(b) => *b as Val,
                Value::Other(t) => return Err(format!("the value `{t}` of the parameter `{name}` is not supported")),
            };
            out.push(ConstValue { name: name.clone(), of: of.clone(), value });
        }
    }
    Ok(out)
}
