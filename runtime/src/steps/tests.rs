//! Unit tests of the step functions: spec §5.1–5.3 and §8.4 examples, boundaries,
//! validity, NaN propagation and finite-difference checks of the derivative companions.

use super::*;
use crate::test_util::{assert_ulps, central_diff, check_grad};

type StepFn = fn(f64, f64, f64, f64, f64) -> f64;
type GradFn = fn(f64, f64, f64, f64, f64) -> (f64, [f64; 5]);

const FAMILY: [(&str, StepFn, GradFn, StepFn); 3] = [
    ("step", step, step_grad, step_d2),
    ("step5", step5, step5_grad, step5_d2),
    ("havsin", havsin, havsin_grad, havsin_d2),
];

#[test]
fn step_examples_of_spec_5_1_and_f8() {
    // All exact in binary.
    assert_eq!(step(0.25, 0.0, 0.0, 1.0, 1.0), 0.15625);
    assert_eq!(step(1.5, 1.0, 2.0, 2.0, 5.0), 3.5);
    assert_eq!(step(-1.0, 0.0, 3.0, 1.0, 7.0), 3.0);
    assert_eq!(step(2.0, 0.0, 3.0, 1.0, 7.0), 7.0);
    assert_eq!(step(0.0, 0.0, 0.0, 1.0, 1.0), 0.0);
    assert_eq!(step(1.0, 0.0, 0.0, 1.0, 1.0), 1.0);
    // View example: STEP(x, 3, 0, 4, 1) at 2, 3, 3.5, 4, 5.
    let got: Vec<f64> = [2.0, 3.0, 3.5, 4.0, 5.0]
        .iter()
        .map(|&x| step(x, 3.0, 0.0, 4.0, 1.0))
        .collect();
    assert_eq!(got, [0.0, 0.0, 0.5, 1.0, 1.0]);
}

#[test]
fn step_derivative_examples() {
    // Spec §5.1: d/dx at 0.5 = 1.5, d²/dx² at 0.25 = 3.0 (exact).
    assert_eq!(step_grad(0.5, 0.0, 0.0, 1.0, 1.0).1[0], 1.5);
    assert_eq!(step_d2(0.25, 0.0, 0.0, 1.0, 1.0), 3.0);
    // STEP5: 30Δ²(1−Δ)² at 0.5 = 1.875; 60Δ − 180Δ² + 120Δ³ at 0.25 = 5.625 (exact).
    assert_eq!(step5_grad(0.5, 0.0, 0.0, 1.0, 1.0).1[0], 1.875);
    assert_eq!(step5_d2(0.25, 0.0, 0.0, 1.0, 1.0), 5.625);
    // HAVSIN: slope π/2 at the middle, where the curvature is 0.
    assert_ulps(havsin_grad(0.5, 0.0, 0.0, 1.0, 1.0).1[0], FRAC_PI_2, 1);
    assert_eq!(havsin_d2(0.5, 0.0, 0.0, 1.0, 1.0), 0.0);
}

#[test]
fn step5_examples_of_spec_5_2_and_f11() {
    // Exact in binary.
    assert_eq!(step5(0.25, 0.0, 0.0, 1.0, 1.0), 0.103515625);
    assert_eq!(step5(0.5, 0.0, 0.0, 1.0, 1.0), 0.5);
    assert_eq!(step5(1.5, 1.0, 2.0, 2.0, 5.0), 3.5);
    assert_eq!(step5(0.0, 0.0, 0.0, 1.0, 1.0), 0.0);
    assert_eq!(step5(1.0, 0.0, 0.0, 1.0, 1.0), 1.0);
}

#[test]
fn havsin_examples_of_spec_5_3_and_f12() {
    // 0.5 − sin(π/4)/2 goes through libm sin: 1 ulp.
    assert_ulps(havsin(0.25, 0.0, 0.0, 1.0, 1.0), 0.1464466094067263, 1);
    // sin(0) = 0 exactly, so these are exact.
    assert_eq!(havsin(0.5, 0.0, 0.0, 1.0, 1.0), 0.5);
    assert_eq!(havsin(1.5, 1.0, 2.0, 2.0, 5.0), 3.5);
    assert_eq!(havsin(0.0, 0.0, 0.0, 1.0, 1.0), 0.0);
    assert_eq!(havsin(1.0, 0.0, 0.0, 1.0, 1.0), 1.0);
}

#[test]
fn x0_not_below_x1_is_nan() {
    // F9 (x0 = x1) and F10 (x0 > x1), decision 6.
    for (name, f, g, d2) in FAMILY {
        for x in [0.0, 1.0, 1.5, 3.0] {
            assert!(f(x, 1.0, 0.0, 1.0, 1.0).is_nan(), "{name}");
            assert!(f(x, 2.0, 0.0, 1.0, 1.0).is_nan(), "{name}");
            assert!(
                g(x, 2.0, 0.0, 1.0, 1.0).1.iter().all(|p| p.is_nan()),
                "{name}"
            );
            assert!(d2(x, 2.0, 0.0, 1.0, 1.0).is_nan(), "{name}");
        }
    }
}

#[test]
fn nan_in_any_argument_gives_nan() {
    // Includes the constant rows: STEP(−1, 0, 0, 1, NaN) must not return h0.
    let base = [-1.0, 0.0, 2.0, 1.0, 3.0];
    for (name, f, g, d2) in FAMILY {
        for x in [-1.0, 0.5, 2.0] {
            for i in 0..5 {
                let mut a = base;
                a[0] = x;
                a[i] = f64::NAN;
                assert!(f(a[0], a[1], a[2], a[3], a[4]).is_nan(), "{name} {a:?}");
                let (v, p) = g(a[0], a[1], a[2], a[3], a[4]);
                assert!(v.is_nan() && p.iter().all(|p| p.is_nan()), "{name} {a:?}");
                assert!(d2(a[0], a[1], a[2], a[3], a[4]).is_nan(), "{name} {a:?}");
            }
        }
    }
}

#[test]
fn infinities_do_not_panic() {
    let inf = f64::INFINITY;
    for (_, f, g, d2) in FAMILY {
        assert_eq!(f(inf, 0.0, 2.0, 1.0, 3.0), 3.0);
        assert_eq!(f(-inf, 0.0, 2.0, 1.0, 3.0), 2.0);
        for a in [
            [0.5, -inf, 0.0, 1.0, 1.0],
            [0.5, 0.0, 0.0, inf, 1.0],
            [0.5, 0.0, -inf, 1.0, inf],
        ] {
            let _ = (
                f(a[0], a[1], a[2], a[3], a[4]),
                g(a[0], a[1], a[2], a[3], a[4]),
            );
            let _ = d2(a[0], a[1], a[2], a[3], a[4]);
        }
    }
}

#[test]
fn ends_use_the_constant_rows() {
    for (name, f, g, d2) in FAMILY {
        assert_eq!(f(2.0, 2.0, -1.0, 3.0, 4.0), -1.0, "{name}");
        assert_eq!(f(3.0, 2.0, -1.0, 3.0, 4.0), 4.0, "{name}");
        assert_eq!(
            g(2.0, 2.0, -1.0, 3.0, 4.0),
            (-1.0, [0.0, 0.0, 1.0, 0.0, 0.0]),
            "{name}"
        );
        assert_eq!(
            g(3.0, 2.0, -1.0, 3.0, 4.0),
            (4.0, [0.0, 0.0, 0.0, 0.0, 1.0]),
            "{name}"
        );
        assert_eq!(d2(2.0, 2.0, -1.0, 3.0, 4.0), 0.0, "{name}");
        assert_eq!(d2(3.0, 2.0, -1.0, 3.0, 4.0), 0.0, "{name}");
    }
}

#[test]
fn grads_match_finite_differences() {
    let params = [
        [0.0, 0.0, 1.0, 1.0],
        [1.0, 2.0, 2.0, 5.0],
        [-2.0, 3.0, 0.5, -4.0],
    ];
    for (_, f, g, _) in FAMILY {
        for [x0, h0, x1, h1] in params {
            for frac in [0.1, 0.3, 0.5, 0.77, 0.95] {
                let x = x0 + frac * (x1 - x0);
                check_grad(
                    |a| f(a[0], a[1], a[2], a[3], a[4]),
                    |a| g(a[0], a[1], a[2], a[3], a[4]),
                    [x, x0, h0, x1, h1],
                );
            }
            // Outside the ramp.
            for x in [x0 - 0.5, x1 + 0.5] {
                check_grad(
                    |a| f(a[0], a[1], a[2], a[3], a[4]),
                    |a| g(a[0], a[1], a[2], a[3], a[4]),
                    [x, x0, h0, x1, h1],
                );
            }
        }
    }
}

#[test]
fn second_derivatives_match_finite_differences_of_the_first() {
    for (name, _, g, d2) in FAMILY {
        for frac in [0.1, 0.25, 0.6, 0.9] {
            let at = [-1.0 + 2.5 * frac, -1.0, 0.5, 1.5, 2.0];
            let fd = central_diff(&|a: [f64; 5]| g(a[0], a[1], a[2], a[3], a[4]).1[0], at, 0);
            let exact = d2(at[0], at[1], at[2], at[3], at[4]);
            assert!(
                (fd - exact).abs() < 1e-6 * (1.0 + exact.abs()),
                "{name}: {fd} vs {exact}"
            );
        }
    }
}

#[test]
fn branch_free_steps_give_the_rows_bits() {
    // `StepParams::step` and `step5` compute every row and pick one with masks; the
    // branchy rows (`step_rows`, and the old STEP5 body below) are the reference.
    let step5_rows = |x: f64, x0: f64, h0: f64, x1: f64, h1: f64| {
        if x <= x0 {
            h0
        } else if x >= x1 {
            h1
        } else {
            let d = (x - x0) / (x1 - x0);
            h0 + (h1 - h0) * d * d * d * (10.0 - 15.0 * d + 6.0 * d * d)
        }
    };
    let edges = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        0.25,
        2.0,
        5e-324,
        1e308,
        -1e308,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for &x in &edges {
        for &x0 in &edges {
            for &x1 in &edges {
                for (h0, h1) in [(0.0, 5.0), (-0.0, 0.0), (3.0, -7.5), (f64::INFINITY, 1.0)] {
                    let Some(p) = StepParams::new(x0, h0, x1, h1) else {
                        assert!(step(x, x0, h0, x1, h1).is_nan());
                        continue;
                    };
                    assert!(same(p.step(x), step_rows(x, x0, h0, x1, h1)));
                    assert!(same(p.step5(x), step5_rows(x, x0, h0, x1, h1)));
                    assert!(same(step(x, x0, h0, x1, h1), p.step(x)));
                }
            }
        }
    }
}
