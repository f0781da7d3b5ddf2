//! Tests of the crate's architecture, read from its sources: the layers of the multibody
//! core and of its dynamics, the core's files free of import circles, the dataset layer
//! kept off the core, and the shells' one door. Each failure quotes the offending line.
//! A reference is a path in code (`crate::…`, `super::…`, a `use` tree's leaves) resolved
//! to the file that defines what it names; comments, literals and `#[cfg(test)]` modules
//! do not count, since a test may build a whole system.

mod boundaries;
mod graph;
mod mbd_layers;
mod scan;
