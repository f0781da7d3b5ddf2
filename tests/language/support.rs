//! Shared helpers: compiling and evaluating with the interpreter, float comparison.

use mbfx::check::{compile, Expect, Variables};
use mbfx::context::Context;
use mbfx::diag::Diagnostic;
use mbfx::interp::Program;

/// Scope with the variables x, v, t (slots 0, 1, 2).
pub fn xvt_scope() -> Variables {
    let mut s = Variables::new();
    for n in ["x", "v", "t"] {
        s.define(n);
    }
    s
}

/// Compiles `src` with variables x, v, t and evaluates every output at the given values.
pub fn eval(src: &str, vars: [f64; 3], time: f64) -> Result<Vec<f64>, Vec<Diagnostic>> {
    let checked = compile(src, &xvt_scope(), Expect::Any)?;
    let p = Program::new(checked.function);
    let mut out = vec![0.0; p.function().outputs.len()];
    p.eval_into(&Context::new(time, &vars), &mut out);
    Ok(out)
}

/// Distance in units in the last place between two finite doubles of the same sign.
pub fn ulps(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    if a.is_sign_negative() != b.is_sign_negative() {
        return u64::MAX;
    }
    a.to_bits().abs_diff(b.to_bits())
}

/// Root directory of the shared material (`../shared` beside the repository).
pub fn shared() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")
}
