//! The lane evaluator against the interpreter, point by point, bit for bit.

use super::run::Level;
use super::{Column, Lanes, LANES};
use crate::check::{compile, Expect, Variables};
use crate::context::Context;
use crate::interp::Program;

fn function(text: &str) -> crate::ir::Function {
    let mut scope = Variables::new();
    for v in ["x", "v"] {
        scope.define(v);
    }
    compile(text, &scope, Expect::Any).expect("valid").function
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Points that cross every IF's three arms and NaN, over more than one block.
fn inputs(n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let pick = |i: usize, k: usize| match (i * 7 + k * 3) % 11 {
        0 => 0.0,
        1 => -0.0,
        2 => f64::NAN,
        3 => 1.0,
        4 => f64::INFINITY,
        j => (i as f64 * 0.37 + k as f64).sin() * 2.0 + j as f64 * 0.1 - 0.5,
    };
    let x = (0..n).map(|i| pick(i, 0)).collect();
    let v = (0..n).map(|i| pick(i, 1)).collect();
    let t = (0..n).map(|i| pick(i, 2)).collect();
    (x, v, t)
}

fn agrees(text: &str) {
    let f = function(text);
    let lanes = Lanes::new(&f).expect("no measures");
    let program = Program::new(f);
    let k = lanes.outputs();
    let n = 2 * LANES + 37;
    let (x, v, t) = inputs(n);
    let mut out = vec![0.0; n * k];
    let columns = [Column::Values(&x), Column::Values(&v)];
    assert!(lanes.eval(&columns, Column::Values(&t), n, &mut out));
    // Every instruction set's kernels, not only the one `eval` picks here (NaN as the
    // one value it is: which operand's NaN an add passes on is the compiler's choice).
    for level in Level::available() {
        let mut at_level = vec![f64::NAN; n * k];
        lanes.run_at(level, &columns, Column::Values(&t), n, &mut at_level);
        assert!(
            out.iter().zip(&at_level).all(|(&a, &b)| same(a, b)),
            "{text}: {level:?} kernels differ"
        );
    }
    let mut want = vec![0.0; k];
    for i in 0..n {
        program.eval_into(&Context::new(t[i], &[x[i], v[i]]), &mut want);
        for j in 0..k {
            let got = out[i * k + j];
            assert!(
                same(got, want[j]),
                "{text} at x={} v={} t={}: lanes {got}, interp {}",
                x[i],
                v[i],
                t[i],
                want[j]
            );
        }
    }
}

#[test]
fn arithmetic_calls_and_contacts_match_the_interpreter() {
    for text in [
        "3*x**3 - 2*x*v + v**2/(1 + TIME*TIME) - 4.5*x + 7",
        "SIN(2*PI*TIME)*COS(x) + ATAN2(v, x)",
        "STEP(TIME, 0, 0, 1, 5) + STEP5(x, 0, 1, 2, -1) + HAVSIN(v, -1, 0, 1, 2)",
        "IMPACT(x, v, 1, 1e5, 1.5, 50, 0.1) + BISTOP(x, v, 0.5, 1.5, 1e5, 1.5, 50, 0.1)",
        "IMPACT(x, v, TIME, 1e5, 1.5, 50, 0.1)",
        "POLY(x, 0, 1, 2, 3, 4) + CHEBY(v, 1, 2, 3) + FORCOS(x, 0, v, 1, 2) + SHF(TIME, 0, 1, 2, 3, 4)",
        "MIN(x, v)*MAX(TIME, 0.5) + DIM(x, v) + SIGN(x, v) + MOD(x, 0.7) + AINT(v) + ANINT(x)",
        "SQRT(ABS(x*v)) + x**0.5 + EXP(-v) + LOG(x) + 5",
        "2.5",
    ] {
        agrees(text);
    }
}

#[test]
fn ifs_take_each_arm_and_nan_tests_give_nan() {
    for text in [
        "IF(x - 1: -x*v, 0, IF(v: x + TIME, x, IF(TIME - 0.5: x*TIME, TIME, v*x - TIME)))",
        "IF(x: LOG(x), 0, SIN(v)/x)",
        "IF(x: IF(v: LOG(-x), EXP(v), 1), 2, IF(TIME: COS(x), 3, LOG(v)))",
    ] {
        agrees(text);
    }
}

#[test]
fn vectors_take_three_outputs() {
    agrees("[x, SIN(v), IF(x: 1, 2, TIME)]");
}

#[test]
fn short_columns_and_outputs_are_refused() {
    let lanes = Lanes::new(&function("x + v")).expect("no measures");
    let x = [1.0, 2.0];
    let mut out = [0.0; 3];
    let cols = [Column::Values(&x), Column::Const(1.0)];
    assert!(!lanes.eval(&cols, Column::Const(0.0), 3, &mut out));
    assert!(!lanes.eval(&cols[..1], Column::Const(0.0), 2, &mut out[..2]));
    assert!(lanes.eval(&cols, Column::Const(0.0), 2, &mut out[..2]));
    assert_eq!(out[..2], [2.0, 3.0]);
}

#[test]
fn a_function_needing_too_many_slots_is_left_to_point_by_point_engines() {
    // Distinct coefficients, so no term is shared: two values a term.
    let terms: Vec<String> = (0..super::MAX_SLOTS)
        .map(|k| format!("{}*x", 1.0 + k as f64 / 8192.0))
        .collect();
    assert!(Lanes::new(&function(&terms.join(" + "))).is_none());
    assert!(Lanes::new(&function(&terms[..100].join(" + "))).is_some());
}

/// SIN, COS and ATAN2 run as the runtime's own block loops, compiled at every level:
/// each level's bits against the interpreter's, over arguments of every scale (the
/// fast paths and the libm ones) and the multiples of π/2 where the reduction cancels.
#[test]
fn trig_matches_the_interpreter_at_every_scale() {
    let f = function("[SIN(x), COS(x), ATAN2(v, x)]");
    let lanes = Lanes::new(&f).expect("no measures");
    let program = Program::new(f);
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let scales = [1e-300, 1e-8, 1.0, 10.0, 1e3, 1e6, 1e7, 1e300];
    let mut x: Vec<f64> = (0..4096).map(|i| scales[i % 8] * next()).collect();
    let mut v: Vec<f64> = (0..4096).map(|i| scales[(i / 8) % 8] * next()).collect();
    for n in 1..500 {
        x.push(f64::from(n) * std::f64::consts::FRAC_PI_2);
        v.push(next());
    }
    x.extend([0.0, -0.0, f64::NAN, f64::INFINITY, 1048576.0, -1048575.9]);
    v.extend([0.0, 1.0, 2.0, -0.0, f64::NEG_INFINITY, 3.0]);
    let n = x.len();
    let columns = [Column::Values(&x), Column::Values(&v)];
    let mut want = vec![0.0; 3 * n];
    for i in 0..n {
        program.eval_into(
            &Context::new(0.0, &[x[i], v[i]]),
            &mut want[3 * i..3 * i + 3],
        );
    }
    for level in Level::available() {
        let mut got = vec![0.0; 3 * n];
        lanes.run_at(level, &columns, Column::Const(0.0), n, &mut got);
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                same(*g, *w),
                "{level:?}: output {} at x={:e} v={:e}: {g:e} vs {w:e}",
                k % 3,
                x[k / 3],
                v[k / 3]
            );
        }
    }
}
