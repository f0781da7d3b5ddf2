//! Shared helpers: compiling text in a scope of variables `x`, `y`, `z`, and comparing
//! results bit for bit (any NaN equals any NaN: payloads are not specified).

use mbfx::check::{compile, Expect, Variables};
use mbfx::ir::Function;

/// The variables every generated expression may use, in slot order.
pub const VARS: [&str; 3] = ["x", "y", "z"];

pub fn scope() -> Variables {
    let mut s = Variables::new();
    for v in VARS {
        s.define(v);
    }
    s
}

/// The IR of `src` (scalar or vector), or the diagnostics as text.
pub fn ir(src: &str) -> Result<Function, String> {
    compile(src, &scope(), Expect::Any)
        .map(|c| c.function)
        .map_err(|d| format!("{d:?}"))
}

/// Same bits, or both NaN.
pub fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}
