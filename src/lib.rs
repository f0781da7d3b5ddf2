//! mbfx: a compiler and runtime for the Adams FUNCTION expression language.
//!
//! Pipeline: [`syntax`] (logos lexer, LALRPOP parser) → [`check`] (names, arity, types,
//! limits) → [`ir`] (typed IR, constant folding) → [`interp`] (evaluator); library
//! functions live in the `mbfx-runtime` crate shared by every back end. [`model`] reads
//! `.adm` datasets; [`mbd`] is the multibody core and [`session`] runs a dataset through
//! it (build, assemble, redundancy); [`diag`] is the one diagnostic type.

#![warn(missing_docs)]

// Unit tests may name the library `mbfx`, as test files shared with the integration tests
// and benches do (tests/common/redundancy_fixtures.rs).
#[cfg(test)]
extern crate self as mbfx;

pub mod bench;
pub mod check;
pub mod cli;
pub mod collide;
pub mod context;
pub mod diag;
pub mod fmu_export;
mod font;
pub mod gltf;
pub mod interp;
pub mod ir;
pub mod jit;
pub mod lanes;
pub mod mbd;
pub mod model;
pub mod scene;
pub mod session;
mod stack;
pub mod syntax;
pub mod viewer;
pub mod vocab;

/// The architecture's tests, read from the sources.
#[cfg(test)]
mod layering;

/// The Rust examples of docs/library.md, compiled and run as doctests so they stay true.
#[cfg(doctest)]
#[doc = include_str!("../docs/library.md")]
pub struct LibraryDoctests;
