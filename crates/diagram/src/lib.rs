//! Diagrams of RoboChart and RoboSim models (issue 9): a diagram model
//! computed from the semantic model ([`model`]), a layered layout with
//! hierarchy handled inside out ([`layout`]), and SVG and DOT rendering.

#![warn(missing_docs)]

pub mod dot;
mod layered;
pub mod layout;
pub mod metrics;
pub mod model;
pub mod svg;

pub use dot::render_dot;
pub use model::{dump, file_diagrams, Diagram, DiagramKind};
pub use svg::{render_svg, render_svg_marked, Marks};
