//! Body of the `interp_vs_jit` fuzz target, shared with the stable replay test
//! (`tests/fuzz_seeds.rs` includes this file with `#[path]`). Plain Rust: no libfuzzer
//! dependency.
//!
//! Invariant checked on any input bytes taken as an expression: when the expression is
//! accepted (with the variables x, v, t, and with every measure and SPLINE defined), the
//! interpreter and the JIT give the same bits (any NaN equals any NaN) at fixed points
//! that include ±0, subnormals, huge values, ±∞ and NaN; and so do they on the gradient
//! with respect to x, v and TIME.

use mbfx::check::{compile, EveryIdExists, Expect, Variables};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::ir::deriv::{gradient, Input};
use mbfx::ir::Function;
use mbfx::jit::Jit;
use mbfx_runtime::Spline;
use std::cell::RefCell;

/// Points (x, v, t) at which both back ends evaluate; t is also the time.
const POINTS: [[f64; 3]; 7] = [
    [0.0, -0.0, 0.0],
    [0.25, -1.0, 0.5],
    [-2.5, 1e3, 7.0],
    [5e-324, -2.2e-308, 1.0],
    [1e308, -1e300, 0.75],
    [f64::NAN, 1.0, -0.0],
    [f64::INFINITY, f64::NEG_INFINITY, 1e-300],
];

const MEASURES: [f64; 3] = [0.25, -1.5, 2.0];

thread_local! {
    static JIT: RefCell<Option<Jit>> = const { RefCell::new(None) };
}

/// Runs the check on raw fuzzer bytes.
pub fn check_bytes(data: &[u8]) {
    let src = String::from_utf8_lossy(data);
    let mut vars = Variables::new();
    for name in ["x", "v", "t"] {
        vars.define(name);
    }
    if let Ok(c) = compile(&src, &vars, Expect::Any) {
        agree(&src, &c.function, &[]);
        if let Ok(g) = gradient(&c.function, &[Input::Var(0), Input::Var(1), Input::Time]) {
            agree(&src, &g, &[]);
        }
    }
    if let Ok(c) = compile(&src, &EveryIdExists, Expect::Any) {
        agree(&src, &c.function, &MEASURES);
    }
}

/// Same bits, or both NaN.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn agree(src: &str, f: &Function, measures: &[f64]) {
    let code = JIT.with(|j| {
        let mut j = j.borrow_mut();
        let jit = j.get_or_insert_with(|| Jit::new().expect("host supported"));
        jit.compile(f).expect("an accepted expression compiles")
    });
    let spline = [Spline::new(
        vec![0.0, 1.0, 2.0, 3.0],
        vec![0.0],
        vec![0.0, 1.0, 0.5, 2.0],
    )
    .expect("valid")];
    let program = Program::new(f.clone());
    let n = f.outputs.len();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    for p in &POINTS {
        let ctx = Context::new(p[2], p)
            .with_measures(measures)
            .with_splines(&spline);
        program.eval_into(&ctx, &mut a);
        code.eval_into(&ctx, &mut b);
        assert!(
            a.iter().zip(&b).all(|(x, y)| same(*x, *y)),
            "{src:?} at {p:?}: interpreter {a:?}, JIT {b:?}"
        );
    }
}
