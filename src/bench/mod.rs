//! Work-precision and stability benches.

pub mod generate;
