//! Unit tests of IMPACT and BISTOP: spec §5.4–5.5 and §8.4 (F13–F19) examples, contact
//! on/off, clamp on/off, validation, NaN propagation and finite-difference gradients.

use super::*;
use crate::test_util::{assert_close, assert_ulps, check_grad};

/// IMPACT with the spec's parameters x1 = 1, k = 1e5, e = 1.5, cmax = 100, d = 0.1.
fn spec_impact(x: f64, xd: f64) -> f64 {
    impact(x, xd, 1.0, 1e5, 1.5, 100.0, 0.1)
}

/// BISTOP with the spec's parameters x1 = −2, x2 = 2, k = 1000, e = 2, cmax = 10, d = 0.1.
fn spec_bistop(x: f64, xd: f64) -> f64 {
    bistop(x, xd, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1)
}

fn impact_a(a: [f64; 7]) -> f64 {
    impact(a[0], a[1], a[2], a[3], a[4], a[5], a[6])
}

fn impact_grad_a(a: [f64; 7]) -> (f64, [f64; 7]) {
    impact_grad(a[0], a[1], a[2], a[3], a[4], a[5], a[6])
}

fn bistop_a(a: [f64; 8]) -> f64 {
    bistop(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7])
}

fn bistop_grad_a(a: [f64; 8]) -> (f64, [f64; 8]) {
    bistop_grad(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7])
}

#[test]
fn impact_examples_of_f13_f15() {
    // The spec values were computed in doubles from 1 − 0.95 etc.; not exact: ≤ 4 ulp.
    assert_ulps(spec_impact(0.95, -2.0), 1218.0339887498967, 4);
    assert_ulps(spec_impact(0.85, -2.0), 6009.475019311127, 4);
}

#[test]
fn impact_without_contact_is_zero() {
    assert_eq!(spec_impact(1.0, -5.0), 0.0);
    assert_eq!(spec_impact(1.5, -5.0), 0.0);
    assert_eq!(spec_impact(f64::INFINITY, 1.0), 0.0);
}

#[test]
fn impact_clamp_of_f14() {
    // Decision 5: the unclamped −381.966… becomes 0.
    assert_eq!(spec_impact(0.95, 30.0), 0.0);
    assert_eq!(
        impact_grad(0.95, 30.0, 1.0, 1e5, 1.5, 100.0, 0.1),
        (0.0, [0.0; 7])
    );
    // Pulling velocity but the spring still wins: the clamp is inactive.
    let v = spec_impact(0.95, 5.0);
    assert!(v > 0.0 && v < 1118.1, "{v}");
    // Zero force exactly (k = 0, ẋ = 0): the zero branch, partials 0.
    assert_eq!(
        impact_grad(0.95, 0.0, 1.0, 0.0, 1.5, 100.0, 0.1),
        (0.0, [0.0; 7])
    );
}

#[test]
fn impact_validation_of_f16() {
    assert!(impact(0.9, 0.0, 1.0, 1e5, 1.5, 100.0, 0.0).is_nan());
    assert!(impact(0.9, 0.0, 1.0, 1e5, -1.5, 100.0, 0.1).is_nan());
    assert!(impact(0.9, 0.0, 1.0, -1e5, 1.5, 100.0, 0.1).is_nan());
    assert!(impact(0.9, 0.0, 1.0, 1e5, 1.5, -100.0, 0.1).is_nan());
    // Also out of contact: the parameters are invalid whatever x is.
    assert!(impact(2.0, 0.0, 1.0, 1e5, 1.5, 100.0, 0.0).is_nan());
    // k = 0 and cmax = 0 are allowed.
    assert_eq!(impact(0.9, 1.0, 1.0, 0.0, 1.5, 0.0, 0.1), 0.0);
}

#[test]
fn bistop_examples_of_f17_f18() {
    // −2.5 − 5 in exact arithmetic; 2.05 is not a double, so relative 1e-13.
    assert_close(spec_bistop(2.05, 1.0), -7.5, 1e-13);
    assert_close(spec_bistop(-2.05, -1.0), 7.5, 1e-13);
    // Decision 5: the unclamped 47.5 (and −47.5 below) become 0.
    assert_eq!(spec_bistop(2.05, -10.0), 0.0);
    assert_eq!(spec_bistop(-2.05, 10.0), 0.0);
}

#[test]
fn bistop_is_free_inside_the_gap() {
    assert_eq!(spec_bistop(0.0, 5.0), 0.0);
    assert_eq!(spec_bistop(-2.0, -5.0), 0.0);
    assert_eq!(spec_bistop(2.0, 5.0), 0.0);
    let (v, g) = bistop_grad(2.0, 5.0, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1);
    assert_eq!((v, g), (0.0, [0.0; 8]));
}

#[test]
fn bistop_validation_of_f19() {
    assert!(bistop(0.0, 5.0, 2.0, -2.0, 1000.0, 2.0, 10.0, 0.1).is_nan());
    assert!(bistop(0.0, 5.0, 2.0, 2.0, 1000.0, 2.0, 10.0, 0.1).is_nan());
    assert!(bistop(3.0, 5.0, -2.0, 2.0, 1000.0, 0.0, 10.0, 0.1).is_nan());
    assert!(bistop(3.0, 5.0, -2.0, 2.0, 1000.0, 2.0, 10.0, -0.1).is_nan());
}

#[test]
fn full_damping_beyond_d() {
    // Beyond d the damping is cmax: IMPACT(0.5, ẋ) − IMPACT(0.5, 0) = −cmax·ẋ.
    let f0 = spec_impact(0.5, 0.0);
    assert_eq!(f0, 1e5 * 0.5f64.powf(1.5));
    assert_eq!(spec_impact(0.5, -1.0), f0 + 100.0);
}

#[test]
fn values_follow_the_documented_operation_order() {
    use crate::steps::step;
    for x in [0.3f64, 0.91, 0.95, 0.99, 1.0 - 1e-9] {
        for xd in [-3.0, -0.1, 0.7] {
            let f = 1e5 * (1.0 - x).powf(1.5) - step(x, 1.0 - 0.1, 100.0, 1.0, 0.0) * xd;
            let want = if f > 0.0 { f } else { 0.0 };
            assert_eq!(spec_impact(x, xd).to_bits(), want.to_bits(), "{x} {xd}");
            let b = spec_bistop(-2.0 - (1.0 - x), xd);
            let p = 1.0 - x;
            let x = -2.0 - p;
            let f = 1000.0 * (-2.0 - x).powf(2.0) - step(x, -2.0 - 0.1, 10.0, -2.0, 0.0) * xd;
            let want = if f > 0.0 { f } else { 0.0 };
            assert_eq!(b.to_bits(), want.to_bits(), "{x} {xd}");
            let x = 2.0 + p;
            let f = -(1000.0 * (x - 2.0).powf(2.0)) - step(x, 2.0, 0.0, 2.0 + 0.1, 10.0) * xd;
            let want = if f < 0.0 { f } else { 0.0 };
            assert_eq!(spec_bistop(x, xd).to_bits(), want.to_bits(), "{x} {xd}");
        }
    }
}

#[test]
fn nan_in_any_argument_gives_nan() {
    let imp = [0.95, -2.0, 1.0, 1e5, 1.5, 100.0, 0.1];
    for x in [0.95, 2.0] {
        for i in 0..7 {
            let mut a = imp;
            a[0] = x;
            a[i] = f64::NAN;
            assert!(impact_a(a).is_nan(), "{a:?}");
            assert!(impact_grad_a(a).1.iter().all(|p| p.is_nan()), "{a:?}");
        }
    }
    let bis = [0.0, 1.0, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1];
    for x in [-2.05, 0.0, 2.05] {
        for i in 0..8 {
            let mut a = bis;
            a[0] = x;
            a[i] = f64::NAN;
            assert!(bistop_a(a).is_nan(), "{a:?}");
            assert!(bistop_grad_a(a).1.iter().all(|p| p.is_nan()), "{a:?}");
        }
    }
}

#[test]
fn infinities_do_not_panic() {
    let inf = f64::INFINITY;
    for v in [inf, -inf] {
        for i in 0..7 {
            let mut a = [0.95, -2.0, 1.0, 1e5, 1.5, 100.0, 0.1];
            a[i] = v;
            let _ = (impact_a(a), impact_grad_a(a));
        }
        for i in 0..8 {
            let mut a = [2.05, 1.0, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1];
            a[i] = v;
            let _ = (bistop_a(a), bistop_grad_a(a));
        }
    }
}

#[test]
fn tiny_d_next_to_a_large_x1_still_damps() {
    // x1 − d rounds to x1: the STEP rows give full damping instead of NaN.
    let f = impact(1e17 - 1024.0, -1.0, 1e17, 0.0, 1.5, 7.0, 1.0);
    assert_eq!(f, 7.0);
}

#[test]
fn impact_grad_matches_finite_differences() {
    for x in [0.97, 0.95, 0.93, 0.85, 0.5] {
        for xd in [-2.0, 0.5, 1.0] {
            let at = [x, xd, 1.0, 1e5, 1.5, 100.0, 0.1];
            assert!(impact_a(at) > 0.0);
            check_grad(impact_a, impact_grad_a, at);
        }
    }
    // A softening exponent and other parameters.
    check_grad(
        impact_a,
        impact_grad_a,
        [0.3, -0.7, 0.4, 50.0, 0.6, 3.0, 0.2],
    );
}

#[test]
fn bistop_grad_matches_finite_differences() {
    for x in [-2.5, -2.07, -2.02, 2.02, 2.07, 2.5] {
        // Velocities into the stop (and one slightly out of it) keep the clamp inactive.
        for xd in [-1.0, -0.1, 0.02] {
            let xd = if x < 0.0 { xd } else { -xd };
            let at = [x, xd, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1];
            assert!(bistop_a(at) != 0.0, "{at:?}");
            check_grad(bistop_a, bistop_grad_a, at);
        }
    }
    check_grad(
        bistop_a,
        bistop_grad_a,
        [1.3, 0.3, -0.5, 1.2, 40.0, 1.3, 2.0, 0.3],
    );
}

#[test]
fn checked_parameters_refuse_exactly_what_the_functions_refuse() {
    // impact and bistop are Impact::new / Bistop::new and then force: this pins that a
    // refused parameter set gives NaN everywhere and an accepted one the same bits.
    let values = [0.0, -1.0, 1.0, 1.5, 0.1, 1e5, f64::INFINITY, f64::NAN];
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for &p in &values {
        for &q in &values {
            let points = [
                (p - 0.5, 1.0),
                (q + 0.5, -1.0),
                (0.95, 2.0),
                (f64::NAN, 0.0),
                (p, f64::NAN),
            ];
            match Impact::new(p, q, 1.5, 50.0, 0.1) {
                Some(c) => {
                    for (x, xd) in points {
                        assert!(same(c.force(x, xd), impact(x, xd, p, q, 1.5, 50.0, 0.1)));
                    }
                }
                None => {
                    for (x, xd) in points {
                        assert!(impact(x, xd, p, q, 1.5, 50.0, 0.1).is_nan());
                    }
                }
            }
            match Bistop::new(p, q, 10.0, 1.5, 1.0, 0.1) {
                Some(c) => {
                    for (x, xd) in points {
                        assert!(same(
                            c.force(x, xd),
                            bistop(x, xd, p, q, 10.0, 1.5, 1.0, 0.1)
                        ));
                    }
                }
                None => {
                    for (x, xd) in points {
                        assert!(bistop(x, xd, p, q, 10.0, 1.5, 1.0, 0.1).is_nan());
                    }
                }
            }
        }
    }
}
