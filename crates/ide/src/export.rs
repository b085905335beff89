//! The CSPm export (`robosim-semantics`): the types of its result, for
//! [`crate::Analysis::export_csp`].

pub use robosim_semantics::{Export, Options, OutFile, Profile, Warning};
