//! The JIT's own contracts.

use super::support::{ir, same};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::jit::{runtime_symbol, spline_symbol, symbol_name, symbol_params, Jit};
use mbfx::vocab::builtins::SplineKind;
use mbfx::vocab::func::Func;

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

/// IFs whose arms are cheap call-free arithmetic are if-converted: no branch, and the
/// picked arm's exact bits, also for a zero test of either sign, a −0 zero arm and a NaN
/// test.
#[test]
fn cheap_if_arms_become_selects() {
    let mut jit = Jit::new().unwrap();
    let src = "IF(x - 1: -x*y, -0.0*y, IF(y: x + z, x, IF(z - 0.5: x*z, z, y*x - z)))";
    let f = ir(src).unwrap();
    let clif = jit.clif(&f).unwrap();
    assert!(
        !clif.contains("brif") && clif.contains("bitselect"),
        "{clif}"
    );
    let code = jit.compile(&f).unwrap();
    let program = Program::new(f);
    for p in [
        [0.5, 2.0, 0.0],
        [1.0, 2.0, 0.0],
        [1.0, -0.0, 0.0],
        [2.0, -1.0, 0.25],
        [2.0, 0.0, 0.25],
        [2.0, -0.0, 0.0],
        [2.0, 1.0, 0.5],
        [2.0, 1.0, 1.5],
        [2.0, 1.0, f64::NAN],
        [f64::NAN, 1.0, 1.0],
        [1.5, f64::INFINITY, 0.0],
    ] {
        let ctx = Context::new(0.0, &p);
        let (want, got) = (program.eval(&ctx), code.eval(&ctx));
        assert!(same(want, got), "{src} at {p:?}: {got} vs {want}");
    }
    // The zero arm keeps its sign: x = 1 picks −0·y = −0 for y > 0.
    let ctx = Context::new(0.0, &[1.0, 2.0, 0.0]);
    assert_eq!(code.eval(&ctx).to_bits(), (-0.0f64).to_bits());
    // Too much work in the arms keeps the branches.
    let heavy = (0..30)
        .map(|i| format!("x*{i}"))
        .collect::<Vec<_>>()
        .join(" + ");
    let clif = jit
        .clif(&ir(&format!("IF(x: {heavy}, 0, 1)")).unwrap())
        .unwrap();
    assert!(clif.contains("brif"), "{clif}");
}

/// IMPACT and BISTOP with constant parameters: one branch on contact (x - x1 < 0), the
/// power call only in the contact arm, the damping STEP and the clamp as selects.
#[test]
fn contact_functions_branch_on_contact() {
    let mut jit = Jit::new().unwrap();
    for (src, calls) in [
        ("IMPACT(x, y, 1, 1E5, 1.5, 50, 0.1)", 1),
        ("BISTOP(x, y, 0.5, 1.5, 1E5, 1.5, 50, 0.1)", 2),
    ] {
        let clif = jit.clif(&ir(src).unwrap()).unwrap();
        let brif = clif.find("brif").expect("a conditional branch");
        assert_eq!(clif.matches("call ").count(), calls, "{src}:\n{clif}");
        assert!(clif.find("call ").unwrap() > brif, "{src}:\n{clif}");
        assert!(clif.contains("bitselect"), "{src}:\n{clif}");
        // Spec §5.4 (IMPACT) at x = 0.95, ẋ = -2: 1e5·0.05^1.5 + STEP(0.95, 0.9, 50, 1, 0)·2.
        let f = ir(src).unwrap();
        let c = jit.compile(&f).unwrap().bind::<3>().unwrap();
        let want = 1e5 * 0.05f64.powf(1.5) + 25.0 * 2.0;
        let got = c.eval(&[if calls == 1 { 0.95 } else { 0.45 }, -2.0, 0.0], 0.0);
        assert!((got - want).abs() < 1e-9 * want, "{src}: {got} != {want}");
    }
}

/// A bound expression gives what `eval` gives through a context, and binding refuses
/// layouts the expression does not fit.
#[test]
fn bound_expressions() {
    let mut jit = Jit::new().unwrap();
    let c = jit.compile(&ir("x*y - z + TIME").unwrap()).unwrap();
    let b = c.bind::<3>().expect("three slots cover x, y, z");
    let vars = [2.0, 3.0, 1.0];
    assert_eq!(b.eval(&vars, 0.5), 5.5);
    assert_eq!(b.eval(&vars, 0.5), c.eval(&Context::new(0.5, &vars)));
    assert!(c.bind::<2>().is_none(), "z is slot 2");
    let v = jit.compile(&ir("[x, y, z]").unwrap()).unwrap();
    assert!(v.bind::<3>().is_none(), "three outputs");
    let m = jit.compile(&ir("MODE").unwrap()).unwrap();
    assert_eq!(m.bind::<0>().unwrap().with_mode(1.0).eval(&[], 0.0), 1.0);
    // The code outlives the compiled expression it was bound from.
    drop(c);
    drop(jit);
    assert_eq!(b.eval(&[1.0, 1.0, 1.0], 0.0), 0.0);
}

/// Expressions that read only variables and time take the minimal `(vars, time)` entry,
/// the others (MODE, several outputs) the general one; both kinds share a batch, and
/// `eval`, `eval_into` and `bind` give the same values through either.
#[test]
fn both_entry_signatures_in_one_batch() {
    let fs: Vec<_> = [
        "x*y - z + TIME",
        "MODE*x + TIME",
        "[x + TIME, y*z, 1]",
        "TIME",
    ]
    .iter()
    .map(|s| ir(s).unwrap())
    .collect();
    let refs: Vec<_> = fs.iter().collect();
    let c = Jit::new().unwrap().compile_batch(&refs).unwrap();
    let vars = [2.0, 3.0, 1.0];
    let ctx = Context::new(0.5, &vars).with_mode(4.0);
    // 2*3 - 1 + 0.5, 4*2 + 0.5, [2 + 0.5, 3*1, 1], 0.5.
    assert_eq!(c[0].eval(&ctx), 5.5);
    assert_eq!(c[1].eval(&ctx), 8.5);
    let mut out = [0.0; 3];
    c[2].eval_into(&ctx, &mut out);
    assert_eq!(out, [2.5, 3.0, 1.0]);
    assert_eq!(c[3].eval(&Context::new(0.5, &[])), 0.5);
    assert_eq!(c[0].bind::<3>().unwrap().eval(&vars, 0.5), 5.5);
    assert_eq!(
        c[1].bind::<3>().unwrap().with_mode(4.0).eval(&vars, 0.5),
        8.5
    );
    assert_eq!(c[3].bind::<0>().unwrap().eval(&[], -1.25), -1.25);
    // The minimal entry still gets the per-call check: a short context gives NaN.
    assert!(c[0].eval(&Context::new(0.5, &[2.0])).is_nan());
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

/// Leaf functions (no call, one return) run without a stack frame and give the
/// interpreter's bits, alone and in one batch with framed functions; anything that calls
/// keeps its frame (the callee needs the aligned stack).
#[test]
fn leaf_functions_run_without_a_frame() {
    let cases = [
        ("POLY(x, 0, 1, 2, 3, 4)", true),
        ("3*x**3 - 2*x*y + y**2/(1 + z*z) - 4.5*x + 7", true),
        ("STEP(z, 0, 0, 1, 5) + MIN(x, y)", true),
        ("IF(x - 1: -x*y, 0, IF(y: x + z, x, z))", true),
        ("SIN(x) + y", false),
        ("IMPACT(x, y, 1, 1e5, 1.5, 50, 0.1)", false),
        ("[x, y*2, z + 1]", true),
    ];
    let fs: Vec<_> = cases.iter().map(|(src, _)| ir(src).unwrap()).collect();
    let refs: Vec<_> = fs.iter().collect();
    let codes = Jit::new().unwrap().compile_batch(&refs).unwrap();
    let points = [
        [0.3, -1.5, 0.7],
        [1.0, 0.0, 0.5],
        [2.0, 1.5, -0.25],
        [f64::NAN, 1.0, 2.0],
    ];
    for (((src, leaf), f), code) in cases.iter().zip(&fs).zip(&codes) {
        assert_eq!(
            code.is_frameless(),
            *leaf && cfg!(target_arch = "x86_64"),
            "{src}"
        );
        let program = Program::new(f.clone());
        for p in &points {
            let ctx = Context::new(0.0, p);
            let (mut want, mut got) = ([0.0; 3], [0.0; 3]);
            program.eval_into(&ctx, &mut want);
            code.eval_into(&ctx, &mut got);
            assert!(
                want.iter().zip(&got).all(|(w, g)| same(*w, *g)),
                "{src} at {p:?}"
            );
        }
    }
}

/// A chain of `n` IF terms whose arms call the runtime (so they stay real branches) and a
/// sum of `n` IMPACTs, in `x`.
fn long_chains(n: usize) -> [String; 2] {
    let ifs: Vec<String> = (0..n)
        .map(|i| format!("IF(x - {i}: LOG(x + {}), 0, SIN(x*{i}))", i + 1))
        .collect();
    let impacts: Vec<String> = (0..n)
        .map(|i| format!("IMPACT(x, y, {i}, 1E5, 1.5, 10, 0.1)"))
        .collect();
    [ifs.join(" + "), impacts.join(" + ")]
}

/// Seconds to compile `src`.
fn compile_seconds(src: &str) -> f64 {
    let f = ir(src).unwrap();
    let t = std::time::Instant::now();
    let code = Jit::new().unwrap().compile(&f).unwrap();
    let s = t.elapsed().as_secs_f64();
    drop(code);
    s
}

/// Regression (issue 11 §2): Cranelift sank every addition of a sum of IFs to the return,
/// so all the IF results stayed live across every later arm, and register allocation grew
/// quadratically (a 3 000-IMPACT sum: 9.3 s and 1.7 GB). Values that cross an IF are now
/// anchored before it (`jit/anchor.rs`), and past 64 IMPACT/BISTOP calls their contact
/// branches stay runtime calls. Eight times the terms must cost about eight times the time
/// (quadratic growth would be 64 times).
#[test]
fn compile_time_of_long_if_and_impact_chains_is_linear() {
    for (kind, (small, big)) in ["IF", "IMPACT"]
        .iter()
        .zip(long_chains(250).iter().zip(long_chains(2000).iter()))
    {
        let (t1, t8) = (compile_seconds(small), compile_seconds(big));
        assert!(
            t8 < (20.0 * t1).max(1.0),
            "{kind}: 250 terms in {t1:.3} s, 2 000 in {t8:.3} s"
        );
    }
}

/// The long chains, both back ends, same bits: anchored values and runtime-called IMPACTs
/// give what the interpreter gives, in contact and out of it, and at NaN.
#[test]
fn long_chains_match_the_interpreter() {
    for src in long_chains(100) {
        let f = ir(&src).unwrap();
        let code = Jit::new().unwrap().compile(&f).unwrap();
        let program = Program::new(f);
        for x in [-1.0, 0.0, 0.5, 3.0, 37.25, 99.0, 150.0, f64::NAN] {
            for y in [-2.0, 0.0, 1.5] {
                let vars = [x, y, 0.0];
                let ctx = Context::new(0.0, &vars);
                let (want, got) = (program.eval(&ctx), code.eval(&ctx));
                assert!(same(got, want), "x = {x}, y = {y}: {got} != {want}");
            }
        }
    }
}

/// The contact budget: up to 64 IMPACTs branch on contact, more stay calls (no IF).
#[test]
fn many_contact_functions_stay_runtime_calls() {
    use mbfx::ir::{lower::lower, Inst};
    let ifs = |n: usize| {
        let f = ir(&long_chains(n)[1]).unwrap();
        lower(&f)
            .insts
            .iter()
            .filter(|i| matches!(i, Inst::If { .. }))
            .count()
    };
    assert_eq!(ifs(64), 64);
    assert_eq!(ifs(65), 0);
}

/// The compiled code's bounds come from its instructions, not from `Function::uses`,
/// which is public: a hand-made function that under-reports what it reads, compiled as
/// it is, still refuses a context too short for it (NaN) instead of reading past it.
#[test]
fn wrong_uses_cannot_make_compiled_code_read_past_the_context() {
    let mut f = ir("y + 1").unwrap();
    f.uses = Default::default();
    let mut jit = Jit::new().unwrap();
    jit.lower = false;
    let code = jit.compile(&f).unwrap();
    assert!(code.eval(&Context::new(0.0, &[2.0])).is_nan());
    assert_eq!(code.eval(&Context::new(0.0, &[2.0, 5.0])), 6.0);
}
