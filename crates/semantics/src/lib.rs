//! The tock-CSP semantics of RoboChart designs and RoboSim simulations as
//! a typed CSPm syntax tree ([`cspm`]), printed in RoboTool's naming and
//! layout for FDR users:
//!
//! - RoboChart state machines, controllers and modules in tock-CSP
//!   (semantics.md §4.1): states, composite states, junctions, triggers,
//!   guards, actions, entry/during/exit actions, `wait`, clocks, `since`,
//!   platform calls (urgent: `EDeadline(opCall.args, 0)`) and events;
//! - RoboSim state machines, controllers and modules per the paper's
//!   Rules 1–13 in the RoboTool 3 reading (semantics.md §2, §5): the
//!   cycle reads the input registers, `startexec`, the machine runs until
//!   `exec` (`endexec`), outputs are urgent register writes, at most one
//!   per register and cycle; a machine or controller on its own shows
//!   `endexec` and `terminate`, a module hides them (RT-21);
//! - for each `simulation S of M`, the assumptions A1–A3, the constrained
//!   design and the schedulability process `TLF` (semantics.md §4.2–4.3);
//! - the same in the `paper2019` profile ([`Profile`]): calls with
//!   returns, the RoboSim buffer and end-of-cycle writes (Rules 4, 7, 12),
//!   the paper's `TA1`–`TA3` and `PConstrained`;
//! - the assertions of `.rsa` and `.assertions` files as FDR `assert`s;
//! - the bounded types and constants (`instantiations.csp`).
//!
//! [`export_workspace`] produces the files; [`lint::check`] checks them
//! structurally (FDR is not needed); [`hover::hover_term`] gives the term
//! of one construct for editors. What is not supported yet is reported as
//! a [`Warning`] and a comment in the output, never approximated.

#![warn(missing_docs)]

mod asserts;
mod compose;
pub mod cspm;
mod defs;
mod doc;
mod export;
pub mod hover;
pub mod lint;
mod machine;
mod sim;
mod sim_names;
mod util;

pub use export::{export_workspace, Export, Options, OutFile, Profile, Warning};
