//! The JIT's own contracts.

use super::support::{ir, same};
use mbfx::check::builtins::SplineKind;
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::ir::Func;
use mbfx::jit::{runtime_symbol, spline_symbol, symbol_name, symbol_params, Jit};

/// Every function of the IR has a runtime symbol, and so does its derivative companion,
/// with exactly the parameters the translator passes.
#[test]
fn every_builtin_has_a_symbol_with_the_right_signature() {
    for func in Func::ALL {
        for grad in [false, true] {
            let name = symbol_name(func, grad);
            let sym = runtime_symbol(&name).unwrap_or_else(|| panic!("no symbol {name}"));
            assert_eq!(sym.params, symbol_params(func, grad).as_slice(), "{name}");
        }
    }
    for kind in [SplineKind::Akima, SplineKind::Cubic] {
        let (name, params) = spline_symbol(kind);
        let sym = runtime_symbol(name).unwrap_or_else(|| panic!("no symbol {name}"));
        assert_eq!(sym.params, params.as_slice(), "{name}");
    }
}

fn jit_eval(src: &str, vars: &[f64]) -> f64 {
    let f = ir(src).unwrap();
    Jit::new()
        .unwrap()
        .compile(&f)
        .unwrap()
        .eval(&Context::new(0.0, vars))
}

#[test]
fn if_picks_by_sign_and_nan_gives_nan() {
    let src = "IF(x: LOG(x), 2*y, SQRT(x) + y)";
    for (x, want) in [
        (-1.0, f64::NAN),
        (-0.0, 6.0),
        (0.0, 6.0),
        (4.0, 5.0),
        (f64::NAN, f64::NAN),
    ] {
        let got = jit_eval(src, &[x, 3.0, 0.0]);
        assert!(same(got, want), "x = {x}: {got} != {want}");
    }
    // IF(x: LOG(x), ...) at x = -1 takes the first arm: LOG(-1) is NaN.
    assert!(jit_eval("IF(x: LOG(x), 0, 1)", &[-1.0, 0.0, 0.0]).is_nan());
}

/// Only the taken arm runs: in the Cranelift IR the arm's call sits in its own block,
/// reached by a conditional branch.
#[test]
fn if_arms_are_branches() {
    let f = ir("IF(x: LOG(x), 0, 5)").unwrap();
    let clif = Jit::new().unwrap().clif(&f).unwrap();
    let brif = clif.find("brif").expect("a conditional branch");
    let call = clif.find("call ").expect("the LOG call");
    assert!(call > brif, "{clif}");
}

#[test]
fn batch_of_many_in_one_module() {
    let srcs: Vec<String> = (0..300)
        .map(|i| format!("x*{i} + STEP(y, 0, 0, 1, {i})"))
        .collect();
    let fs: Vec<_> = srcs.iter().map(|s| ir(s).unwrap()).collect();
    let refs: Vec<_> = fs.iter().collect();
    let compiled = Jit::new().unwrap().compile_batch(&refs).unwrap();
    let vars = [2.0, 0.5, 0.0];
    let ctx = Context::new(0.0, &vars);
    for (f, c) in fs.iter().zip(&compiled) {
        let p = Program::new(f.clone());
        assert!(same(p.eval(&ctx), c.eval(&ctx)));
    }
    // The code outlives the compiler and stays valid while any expression holds it.
    let last = compiled.last().cloned().unwrap();
    drop(compiled);
    assert_eq!(last.eval(&ctx), 2.0 * 299.0 + 299.0 * 0.5);
}

#[test]
fn vector_outputs_and_missing_slots() {
    let f = ir("[x, y, z] % [1, 2, 3]").unwrap();
    let c = Jit::new().unwrap().compile(&f).unwrap();
    let mut out = [0.0; 3];
    c.eval_into(&Context::new(0.0, &[1.0, 0.0, 0.0]), &mut out);
    assert_eq!(out, [0.0, -3.0, 2.0]);
    // A context without the slots the expression reads gives NaN, as the interpreter.
    c.eval_into(&Context::new(0.0, &[1.0]), &mut out);
    assert!(out.iter().all(|v| v.is_nan()));
}

/// The cheap library functions compile to straight-line code: no call, no conditional
/// branch (the comparisons become lane masks that blend the values).
#[test]
fn cheap_functions_are_branch_free() {
    let mut jit = Jit::new().unwrap();
    for src in [
        "STEP(x, 0, 0, 1, 5)",
        "STEP5(x, y, 0, z, 1)",
        "MIN(x, y) + MAX(y, z) + DIM(x, z) + SIGN(x, y) + ABS(z)",
        "POLY(x, 0, 1, 2, 3, 4)",
        "POLY(x, y, z)",
    ] {
        let clif = jit.clif(&ir(src).unwrap()).unwrap();
        assert!(
            !clif.contains("brif") && !clif.contains("call "),
            "{src}:\n{clif}"
        );
        assert!(
            clif.contains("bitselect") || src.starts_with("POLY(x, 0"),
            "{src}:\n{clif}"
        );
    }
    // HAVSIN keeps its sine call, but no branch.
    let clif = jit.clif(&ir("HAVSIN(x, 0, 0, 1, 5)").unwrap()).unwrap();
    assert!(
        !clif.contains("brif") && clif.matches("call ").count() == 1,
        "{clif}"
    );
}
