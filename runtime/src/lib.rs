//! The library functions of the Adams FUNCTION expression language, as plain Rust.
//!
//! This crate is the one place where `STEP`, `IMPACT`, `POLY`, `AKISPL`, `MOD`, … are
//! defined (spec §4 and §5). Both mbfx back ends use it: the interpreter calls the Rust
//! functions directly, and the Cranelift JIT either calls the `extern "C"` wrappers of
//! [`ffi`] (registered by address from [`ffi::symbols`]) or re-emits the documented
//! operation sequence inline. Either way an expression gives bit-identical results in both
//! back ends, so every piecewise formula here is written as a fixed sequence of IEEE
//! `+ − × ÷` operations, stated in its doc comment, with no fused multiply-add and no
//! `powi`; transcendentals come from `std` (`f64::sin`, `f64::powf`, …).
//!
//! Invariants:
//! * Nothing panics and nothing allocates during evaluation (only [`Spline::new`]
//!   allocates, once, when the host builds the data).
//! * Invalid arguments (`STEP` with x0 ≥ x1, `MOD(x, 0)`, a bad `iord`, an empty or too
//!   long coefficient list, …) give NaN. The checker and the simulation driver turn NaN
//!   into diagnostics (spec §10, decision 7).
//! * A NaN argument gives a NaN result in every function, even where the argument would
//!   otherwise be ignored (a comparison never lets NaN fall silently into a constant
//!   branch). The NaN payload is not specified.
//! * Where the solver needs derivatives, each function has an analytic companion
//!   `<name>_grad` next to it that returns the value and the partial derivative with
//!   respect to every argument. At a kink it returns the derivative of the active branch
//!   (documented per function). When the value is NaN the partials are NaN.
//!
//! Families: [`math`] (spec §4), [`steps`] (§5.1–5.3), [`contact`] (§5.4–5.5), [`series`]
//! (§5.6–5.10), [`spline`] (§5.13) and the C ABI layer [`ffi`].

#![deny(missing_docs)]

pub mod contact;
pub mod ffi;
pub mod math;
pub mod series;
pub mod spline;
pub mod steps;

#[cfg(test)]
mod test_util;

pub use contact::*;
pub use math::*;
pub use series::*;
pub use spline::*;
pub use steps::*;

/// True when any argument is NaN. Used by functions whose constant branches would
/// otherwise return a value without looking at every argument.
#[inline]
pub(crate) fn any_nan<const N: usize>(args: [f64; N]) -> bool {
    args.iter().any(|a| a.is_nan())
}

/// The result of a gradient function for invalid or NaN arguments: everything NaN.
#[inline]
pub(crate) const fn nan_grad<const N: usize>() -> (f64, [f64; N]) {
    (f64::NAN, [f64::NAN; N])
}
