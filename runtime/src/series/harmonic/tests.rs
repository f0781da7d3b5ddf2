//! Unit tests of FORCOS, FORSIN, SHF and SWEEP.

use super::*;
use crate::test_util::{assert_close, assert_ulps, central_diff, check_grad};
use core::f64::consts::PI;

type Grad = fn(f64, f64, f64, &[f64], &mut [f64]) -> (f64, f64, f64, f64);

/// Checks a Fourier gradient against central differences in x, x0, ω and every a_j.
fn check_fourier(f: fn(f64, f64, f64, &[f64]) -> f64, g: Grad, at: [f64; 3], a: &[f64]) {
    let mut da = vec![0.0; a.len()];
    let (v, dx, dx0, dw) = g(at[0], at[1], at[2], a, &mut da);
    assert_eq!(v.to_bits(), f(at[0], at[1], at[2], a).to_bits());
    let fs = |p: [f64; 3]| f(p[0], p[1], p[2], a);
    for (i, d) in [dx, dx0, dw].into_iter().enumerate() {
        assert_close(d, central_diff(&fs, at, i), 1e-6);
    }
    for j in 0..a.len() {
        let fa = |p: [f64; 1]| {
            let mut b = a.to_vec();
            b[j] = p[0];
            f(at[0], at[1], at[2], &b)
        };
        assert_close(da[j], central_diff(&fa, [a[j]], 0), 1e-6);
    }
}

fn sweep_a(p: [f64; 7]) -> f64 {
    sweep(p[0], p[1], p[2], p[3], p[4], p[5], p[6])
}

fn sweep_grad_a(p: [f64; 7]) -> (f64, [f64; 7]) {
    sweep_grad(p[0], p[1], p[2], p[3], p[4], p[5], p[6])
}

#[test]
fn fourier_examples_of_f22() {
    // Through libm cos/sin: 4 ulp.
    assert_ulps(
        forcos(0.25, 0.0, PI, &[1.0, 2.0, 3.0]),
        2.4142135623730954,
        4,
    );
    assert_ulps(
        forsin(0.25, 0.0, PI, &[1.0, 2.0, 3.0]),
        5.414213562373095,
        4,
    );
    // a0 is a constant term, not a0·cos 0 / a0·sin 0.
    assert_eq!(forsin(0.7, 0.0, 3.0, &[4.0]), 4.0);
    assert_eq!(forcos(0.0, 0.0, 3.0, &[4.0, 1.0]), 5.0);
}

#[test]
fn shf_examples_of_f23_and_spec_5_9() {
    // sin(π/2) = 1 and sin(0) = 0 exactly, so these are exact.
    assert_eq!(shf(1.0, 0.0, 2.0, PI / 2.0, 0.0, 3.0), 5.0);
    assert_eq!(shf(0.25, 0.0, 1.0, 2.0 * PI, PI / 2.0, 0.0), 0.0);
    // The documented SHF(TIME,25D,PI,360D,0,5) = 5 + PI·SIN(360D·(TIME−25D)).
    let d = PI / 180.0;
    let t = 1.3;
    assert_ulps(
        shf(t, 25.0 * d, PI, 360.0 * d, 0.0, 5.0),
        5.0 + PI * (360.0 * d * (t - 25.0 * d)).sin(),
        0,
    );
}

#[test]
fn fourier_validation_and_nan() {
    for f in [forcos, forsin] {
        assert!(f(0.5, 0.0, 1.0, &[]).is_nan());
        assert!(f(0.5, 0.0, 1.0, &[1.0; 32]).is_nan());
        assert!(!f(0.5, 0.0, 1.0, &[1.0; 31]).is_nan());
        assert!(f(f64::NAN, 0.0, 1.0, &[1.0]).is_nan());
        assert!(f(0.5, f64::NAN, 1.0, &[1.0]).is_nan());
        assert!(f(0.5, 0.0, f64::NAN, &[1.0]).is_nan());
        assert!(f(0.5, 0.0, 1.0, &[1.0, f64::NAN]).is_nan());
    }
    let mut d = [0.0; 2];
    for g in [forcos_grad, forsin_grad] {
        let (v, dx, dx0, dw) = g(0.5, 0.0, f64::NAN, &[1.0, 2.0], &mut d);
        assert!([v, dx, dx0, dw, d[0], d[1]].iter().all(|p| p.is_nan()));
        assert!(g(0.5, 0.0, 1.0, &[1.0, 2.0, 3.0], &mut d).0.is_nan());
    }
    for i in 0..6 {
        let mut p = [0.3, 0.1, 2.0, 1.5, 0.2, 3.0];
        p[i] = f64::NAN;
        assert!(shf(p[0], p[1], p[2], p[3], p[4], p[5]).is_nan());
        assert!(shf_grad(p[0], p[1], p[2], p[3], p[4], p[5])
            .1
            .iter()
            .all(|v| v.is_nan()));
    }
}

#[test]
fn fourier_grads_match_finite_differences() {
    let sets: [&[f64]; 3] = [&[4.0], &[1.0, 2.0, 3.0], &[0.5, -1.0, 0.25, 2.0, -0.75]];
    for a in sets {
        for at in [[0.25, 0.0, PI], [1.7, 0.4, 2.3], [-0.6, 0.1, -1.1]] {
            check_fourier(forcos, forcos_grad, at, a);
            check_fourier(forsin, forsin_grad, at, a);
        }
    }
}

#[test]
fn shf_grad_matches_finite_differences() {
    let f = |p: [f64; 6]| shf(p[0], p[1], p[2], p[3], p[4], p[5]);
    let g = |p: [f64; 6]| shf_grad(p[0], p[1], p[2], p[3], p[4], p[5]);
    for at in [
        [0.3, 0.1, 2.0, 1.5, 0.2, 3.0],
        [2.2, -1.0, -0.5, 4.0, 1.0, 0.0],
    ] {
        check_grad(f, g, at);
    }
}

/// a = 2, x0 = 1, f0 = 1, x1 = 3, f1 = 3, dx = 0.5.
fn spec_sweep(x: f64) -> f64 {
    sweep(x, 2.0, 1.0, 1.0, 3.0, 3.0, 0.5)
}

#[test]
fn sweep_hand_values() {
    // Before x0 the fade is 0.
    assert_eq!(spec_sweep(0.7), 0.0);
    assert_eq!(spec_sweep(1.0), 0.0);
    // Inside the fade, x = 1.25: STEP5 = 0.5, φ = 0.25 + 0.5·0.0625 + 1 = 1.28125,
    // sin(2π·0.28125) = sin(0.5625π) = 0.9807852804032304; value = 0.5·2·that.
    // The sine of a large angle loses a few ulp: relative 1e-13.
    assert_close(spec_sweep(1.25), 0.9807852804032304, 1e-13);
    // Full amplitude, x = 1.75: φ = 0.75 + 0.5·0.5625 + 1 = 2.03125, sin(π/16).
    assert_close(spec_sweep(1.75), 2.0 * 0.19509032201612825, 1e-13);
    // After x1 the frequency is f1: x = 3.25, φ = 9.75 − 4 = 5.75, sin(11.5π) = −1.
    assert_close(spec_sweep(3.25), -2.0, 1e-13);
}

#[test]
fn sweep_phase_is_continuous_at_x0_and_x1() {
    for edge in [1.0, 3.0] {
        let (below, _) = sweep_phase(edge - 1e-12, 1.0, 1.0, 3.0, 3.0);
        let (above, _) = sweep_phase(edge + 1e-12, 1.0, 1.0, 3.0, 3.0);
        assert!((below - above).abs() < 1e-10, "{edge}: {below} {above}");
    }
}

#[test]
fn sweep_validation_and_nan() {
    assert!(sweep(1.5, 2.0, 3.0, 1.0, 1.0, 3.0, 0.5).is_nan());
    assert!(sweep(1.5, 2.0, 1.0, 1.0, 1.0, 3.0, 0.5).is_nan());
    assert!(sweep(1.5, 2.0, 1.0, 1.0, 3.0, 3.0, 0.0).is_nan());
    for i in 0..7 {
        let mut p = [1.5, 2.0, 1.0, 1.0, 3.0, 3.0, 0.5];
        for x in [0.5, 1.5, 4.0] {
            p[0] = x;
            p[i] = f64::NAN;
            assert!(sweep_a(p).is_nan(), "{p:?}");
            assert!(sweep_grad_a(p).1.iter().all(|v| v.is_nan()), "{p:?}");
        }
    }
    let inf = f64::INFINITY;
    let _ = (
        sweep(inf, 1.0, 0.0, 1.0, 1.0, 2.0, 0.1),
        sweep_grad(0.5, 1.0, -inf, 1.0, 1.0, 2.0, inf),
    );
}

#[test]
fn sweep_grad_matches_finite_differences() {
    for x in [0.6, 1.2, 1.4, 1.9, 2.6, 3.4] {
        check_grad(sweep_a, sweep_grad_a, [x, 2.0, 1.0, 1.0, 3.0, 3.0, 0.5]);
        check_grad(sweep_a, sweep_grad_a, [x, -0.7, 0.9, 2.0, 3.1, 0.5, 0.8]);
    }
}
