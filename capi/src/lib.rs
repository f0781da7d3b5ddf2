//! The C API of mbfx: compile an Adams FUNCTION expression over named variables, evaluate
//! it at one point or at many, take its gradient, and hand its machine code to C as a
//! plain function pointer; step a dataset (`simulation`). It is a thin shell over
//! [`mbfx::session::expression`] and [`mbfx::session::stepping`]; the
//! header `include/mbfx.h` is generated from this crate by cbindgen (`capi/cbindgen.toml`,
//! checked by `capi/tests/header.rs`).
//!
//! The rules every function keeps:
//! - Arguments are checked: a NULL pointer, a wrong length, text that is not UTF-8 or an
//!   unknown engine is a status code ([`Status`]), never undefined behaviour. (A pointer
//!   to too little memory cannot be seen from here: lengths are the caller's word.)
//! - Nothing unwinds into C: a Rust panic inside mbfx becomes [`Status::Internal`].
//! - Ownership: an `mbfx_expr *` and an `mbfx_error *` are the caller's, freed with
//!   `mbfx_expr_free` and `mbfx_error_free` (both accept NULL). A `const char *` returned
//!   by an accessor belongs to the object it came from and lives as long as it does; the
//!   static strings (`mbfx_version`, `mbfx_status_string`) live forever.
//! - Threads: an `mbfx_expr` may be evaluated from several threads at once (it is
//!   immutable); compiling works on any thread. Freeing must not race with other uses.

mod args;
pub mod error;
pub mod expr;
pub mod simulation;

pub use error::Error;
pub use expr::{EntryFn, Expr};
pub use simulation::{Simulation, SimulationState};

use std::ffi::{c_char, c_int};

/// What a call did: `MBFX_STATUS_OK`, or why it failed. The values are stable.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Success.
    Ok = 0,
    /// A pointer that must not be NULL was NULL.
    NullArgument = 1,
    /// A string (the text, a name) is not valid UTF-8.
    InvalidUtf8 = 2,
    /// A length does not match: the number of values, of columns or of outputs.
    BadLength = 3,
    /// An argument has a value no call accepts: an unknown engine, a misaligned array.
    InvalidArgument = 4,
    /// The text has errors: the error's code and report say which and where.
    CompileError = 5,
    /// A variable name is not a name, is a builtin or is given twice; or a gradient was
    /// asked in a name that is neither a variable of the expression nor TIME.
    BadVariable = 6,
    /// The expression cannot be differentiated.
    NotDifferentiable = 7,
    /// The expression has no C entry: it runs on the interpreter.
    NoEntry = 8,
    /// A bug in mbfx (a panic inside Rust, a JIT failure): please report it.
    Internal = 9,
    /// A dataset could not be built or stepped (its errors, a probe's, a failed
    /// integration): the error's code, message and report say why, where and when.
    RunFailed = 10,
}

/// The engine that runs an expression, for `mbfx_compile`'s `engine` argument. Both give
/// the same bits; only the JIT gives a C entry (`mbfx_expr_entry`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// The Cranelift JIT: native code, and a C entry.
    Jit = 0,
    /// The interpreter: no code generation, no C entry.
    Interp = 1,
}

impl Engine {
    /// The engine numbered `value` (an `mbfx_engine` passed as an `int`).
    fn from_c(value: c_int) -> Option<mbfx::session::run::Engine> {
        match value {
            v if v == Engine::Jit as c_int => Some(mbfx::session::run::Engine::Jit),
            v if v == Engine::Interp as c_int => Some(mbfx::session::run::Engine::Interp),
            _ => None,
        }
    }
}

/// The version of mbfx, e.g. `"0.1.0"`: a static string (never freed).
#[unsafe(no_mangle)]
pub extern "C" fn mbfx_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// A short lower-case description of `status` (an `mbfx_status`), e.g. `"a NULL
/// argument"`; `"unknown status"` for a value that is none. A static string (never freed).
#[unsafe(no_mangle)]
pub extern "C" fn mbfx_status_string(status: c_int) -> *const c_char {
    let text: &'static str = match status {
        0 => "ok\0",
        1 => "a NULL argument\0",
        2 => "a string that is not UTF-8\0",
        3 => "a wrong length\0",
        4 => "an invalid argument\0",
        5 => "the expression has errors\0",
        6 => "a bad variable name\0",
        7 => "the expression cannot be differentiated\0",
        8 => "no C entry (the expression runs on the interpreter)\0",
        9 => "an internal error in mbfx\0",
        10 => "the model could not be built or stepped\0",
        _ => "unknown status\0",
    };
    text.as_ptr().cast()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    #[test]
    fn every_status_has_its_own_string() {
        let all = [
            Status::Ok,
            Status::NullArgument,
            Status::InvalidUtf8,
            Status::BadLength,
            Status::InvalidArgument,
            Status::CompileError,
            Status::BadVariable,
            Status::NotDifferentiable,
            Status::NoEntry,
            Status::Internal,
            Status::RunFailed,
        ];
        let unknown = mbfx_status_string(-1);
        let mut seen = std::collections::HashSet::new();
        for s in all {
            let p = mbfx_status_string(s as c_int);
            assert_ne!(p, unknown, "{s:?}");
            // SAFETY: mbfx_status_string returns static NUL-terminated strings.
            let text = unsafe { CStr::from_ptr(p) }.to_str().unwrap();
            assert!(seen.insert(text), "{s:?} shares its string");
        }
        // SAFETY: as above.
        let version = unsafe { CStr::from_ptr(mbfx_version()) };
        assert_eq!(version.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
    }
}
