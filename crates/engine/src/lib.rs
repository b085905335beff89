//! Native verification for RoboChart and RoboSim: the models' tock-CSP
//! semantics as transition systems explored on the fly, and the checks the
//! paper runs with FDR (schedulability, deadlock freedom, refinement).

#![warn(missing_docs)]

pub mod algo;
/// Assertion files, read (the reader lives with the semantic model).
pub use robosim_hir::assertions;
pub mod budget;
mod csp;
pub mod design;
mod eager;
pub mod events;
pub mod generate;
pub mod ir;
pub mod lower;
pub mod lts;
pub mod machine;
pub mod pack;
mod reads;
pub mod sched;
pub mod sim;
pub mod untimed;
pub mod verify;
