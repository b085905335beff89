pub mod csp;
pub mod machines;
