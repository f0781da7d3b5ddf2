//! Unit tests of SPLINE construction, AKISPL and CUBSPL: the end-condition-free checks
//! of spec §5.13, an Akima value computed by hand from the slope formula, a natural
//! spline solved by hand, surfaces, extrapolation, errors and gradients.

use super::*;
use crate::test_util::{assert_close, central_diff};

type Interp = fn(f64, f64, &Spline, i32) -> f64;
type InterpGrad = fn(f64, f64, &Spline) -> (f64, f64, f64);
const METHODS: [(&str, Interp, InterpGrad); 2] = [
    ("akispl", akispl, akispl_grad),
    ("cubspl", cubspl, cubspl_grad),
];

fn curve(xs: &[f64], ys: &[f64]) -> Spline {
    Spline::new(xs.to_vec(), vec![0.0], ys.to_vec()).expect("valid curve")
}

/// The Adams View example table (spec §5.13), odd-symmetric.
fn view_table() -> (Vec<f64>, Vec<f64>) {
    let xs = (-4..=4).map(f64::from).collect();
    let ys = vec![-3.6, -2.5, -1.2, -0.4, 0.0, 0.4, 1.2, 2.5, 3.6];
    (xs, ys)
}

#[test]
fn linear_data_is_reproduced_exactly() {
    // Spec §5.13: any cubic or Akima fit is exact on y = 2x; all values exact in binary.
    let xs: Vec<f64> = (0..=5).map(f64::from).collect();
    let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x).collect();
    let s = curve(&xs, &ys);
    for (name, f, _) in METHODS {
        assert_eq!(f(2.5, 0.0, &s, 0), 5.0, "{name}");
        assert_eq!(f(2.5, 0.0, &s, 1), 2.0, "{name}");
        assert_eq!(f(2.5, 0.0, &s, 2), 0.0, "{name}");
        // Linear extrapolation continues the line.
        assert_eq!(f(7.0, 0.0, &s, 0), 14.0, "{name}");
        assert_eq!(f(-1.0, 0.0, &s, 0), -2.0, "{name}");
    }
}

#[test]
fn knots_reproduce_the_data() {
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    for (name, f, _) in METHODS {
        assert_eq!(f(2.0, 0.0, &s, 0), 1.2, "{name}");
        assert_eq!(f(0.0, 0.0, &s, 0), 0.0, "{name}");
        for (&x, &y) in xs.iter().zip(&ys) {
            assert_eq!(f(x, 0.0, &s, 0), y, "{name} at {x}");
        }
    }
}

#[test]
fn odd_data_give_an_odd_interpolant() {
    // Spec §5.13: AKISPL(−0.5) = −AKISPL(0.5). The two sides are evaluated from different
    // knots, so equal to 1e-15 rather than bit for bit.
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    for (name, f, _) in METHODS {
        for x in [0.5, 1.3, 2.75, 3.9, 5.0] {
            for iord in [0, 2] {
                let (right, left) = (f(x, 0.0, &s, iord), f(-x, 0.0, &s, iord));
                assert!((right + left).abs() < 1e-14, "{name} iord {iord} at {x}");
            }
            let (right, left) = (f(x, 0.0, &s, 1), f(-x, 0.0, &s, 1));
            assert!((right - left).abs() < 1e-14, "{name} slope at {x}");
        }
    }
}

#[test]
fn akima_value_matches_a_hand_computation() {
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    // Segment slopes m_i = (y_{i+1} − y_i)/(x_{i+1} − x_i); knots 5 and 6 (x = 1, 2) need
    // m_3 … m_7, all interior, so no end rule is involved.
    let m = |i: usize| (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]);
    // Akima: t_i = (|m_{i+1} − m_i|·m_{i−1} + |m_{i−1} − m_{i−2}|·m_i) / (sum of weights).
    let t = |i: usize| {
        let (w1, w2) = ((m(i + 1) - m(i)).abs(), (m(i - 1) - m(i - 2)).abs());
        (w1 * m(i - 1) + w2 * m(i)) / (w1 + w2)
    };
    let (t5, t6) = (t(5), t(6));
    // By hand: m = 1.1 1.3 0.8 0.4 0.4 0.8 1.3 1.1, t5 = 0.5·0.4/0.5 = 0.4,
    // t6 = (0.2·0.8 + 0.4·1.3)/0.6 = 1.1333…
    assert!((t5 - 0.4).abs() < 1e-12 && (t6 - 0.68 / 0.6).abs() < 1e-12);
    // Hermite basis at the middle of [1, 2] (s = 0.5, h = 1):
    // h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = −0.125.
    let expected = 0.5 * ys[5] + 0.125 * t5 + 0.5 * ys[6] - 0.125 * t6;
    assert!((expected - 0.7083333333333333).abs() < 1e-12);
    assert_close(akispl(1.5, 0.0, &s, 0), expected, 1e-15);
    // The knot slopes are the Akima slopes.
    assert_close(akispl(1.0, 0.0, &s, 1), t5, 1e-15);
    assert_close(akispl(2.0, 0.0, &s, 1), t6, 1e-15);
}

#[test]
fn natural_cubic_matches_a_hand_solution() {
    // x = 0..3, y = 0 1 0 1, h = 1: M1·4 + M2 = −12, M1 + 4·M2 = 12 ⇒ M1 = −4, M2 = 4.
    // On [0, 1]: S = M1·x³/6 + (y1 − M1/6)·x, so S(0.5) = −1/12 + 5/6 = 0.75,
    // S′(0.5) = M1·x²/2 + 5/3 = 7/6, S″(0.5) = M1·x = −2.
    let s = curve(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0, 0.0, 1.0]);
    assert_close(cubspl(0.5, 0.0, &s, 0), 0.75, 1e-15);
    assert_close(cubspl(0.5, 0.0, &s, 1), 7.0 / 6.0, 1e-15);
    assert_close(cubspl(0.5, 0.0, &s, 2), -2.0, 1e-15);
    // By symmetry S(2.5) = 1 − S(0.5).
    assert_close(cubspl(2.5, 0.0, &s, 0), 0.25, 1e-15);
}

#[test]
fn natural_cubic_is_c2_with_zero_end_curvature() {
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    assert_close(cubspl(-4.0, 0.0, &s, 2), 0.0, 1e-14);
    assert_close(cubspl(4.0 - 1e-12, 0.0, &s, 2), 0.0, 1e-10);
    for &k in &xs[1..8] {
        for iord in [0, 1, 2] {
            let (l, r) = (
                cubspl(k - 1e-9, 0.0, &s, iord),
                cubspl(k + 1e-9, 0.0, &s, iord),
            );
            assert!((l - r).abs() < 1e-7, "order {iord} at {k}: {l} vs {r}");
        }
        // Akima is C¹ only.
        let (l, r) = (akispl(k - 1e-9, 0.0, &s, 1), akispl(k + 1e-9, 0.0, &s, 1));
        assert!((l - r).abs() < 1e-7, "akima slope at {k}");
    }
}

#[test]
fn extrapolation_is_linear_with_the_end_slope() {
    // Decision: y_end + y′_end·(x − x_end), second derivative 0 beyond the data.
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    for (name, f, _) in METHODS {
        let (right, left) = (f(4.0, 0.0, &s, 1), f(-4.0, 0.0, &s, 1));
        assert_eq!(f(6.0, 0.0, &s, 0), 3.6 + right * 2.0, "{name}");
        assert_eq!(f(-5.5, 0.0, &s, 0), -3.6 + left * -1.5, "{name}");
        assert_eq!(f(6.0, 0.0, &s, 1), right, "{name}");
        assert_eq!(f(6.0, 0.0, &s, 2), 0.0, "{name}");
        assert_eq!(f(-6.0, 0.0, &s, 2), 0.0, "{name}");
        // Continuous at the ends.
        assert!((f(4.0 - 1e-9, 0.0, &s, 0) - 3.6).abs() < 1e-8, "{name}");
    }
}

/// Curves y = (1 + z)·x at z = 0, 1, 3 (linear in x, so both fits are exact).
fn surface() -> Spline {
    let xs: Vec<f64> = (0..=4).map(f64::from).collect();
    let zs = vec![0.0, 1.0, 3.0];
    let ys = zs
        .iter()
        .flat_map(|z| xs.iter().map(move |x| (1.0 + z) * x))
        .collect();
    Spline::new(xs, zs, ys).expect("valid surface")
}

#[test]
fn surface_is_linear_in_z() {
    let s = surface();
    assert!(s.is_surface());
    for (name, f, g) in METHODS {
        // Exact in binary: (1 − w)·v0 + w·v1 with w = 0.25, 0.5, 1.
        assert_eq!(f(2.0, 0.25, &s, 0), 2.5, "{name}");
        assert_eq!(f(2.0, 2.0, &s, 0), 6.0, "{name}");
        assert_eq!(f(2.0, 1.0, &s, 0), 4.0, "{name}");
        assert_eq!(f(2.0, 3.0, &s, 0), 8.0, "{name}");
        // Beyond the curves the end pair's line continues (decision).
        assert_eq!(f(2.0, 5.0, &s, 0), 12.0, "{name}");
        assert_eq!(f(2.0, -1.0, &s, 0), 0.0, "{name}");
        // F25: iord ≠ 0 on a surface.
        assert!(
            f(2.0, 0.5, &s, 1).is_nan() && f(2.0, 0.5, &s, 2).is_nan(),
            "{name}"
        );
        // Gradient: ∂x = 1 + z, ∂z = x.
        assert_eq!(g(2.0, 0.25, &s), (2.5, 1.25, 2.0), "{name}");
        assert_eq!(g(2.0, 2.0, &s), (6.0, 3.0, 2.0), "{name}");
    }
}

#[test]
fn construction_errors() {
    let ok_x = vec![0.0, 1.0, 2.0, 3.0];
    let err = |xs: Vec<f64>, zs: Vec<f64>, ys: Vec<f64>| Spline::new(xs, zs, ys).unwrap_err();
    assert_eq!(
        err(vec![0.0, 1.0, 2.0], vec![0.0], vec![0.0; 3]),
        SplineError::TooFewPoints { found: 3 }
    );
    assert_eq!(
        err(vec![0.0, 1.0, 1.0, 3.0], vec![0.0], vec![0.0; 4]),
        SplineError::XNotIncreasing { index: 2 }
    );
    assert_eq!(
        err(vec![0.0, 2.0, 1.0, 3.0], vec![0.0], vec![0.0; 4]),
        SplineError::XNotIncreasing { index: 2 }
    );
    assert_eq!(err(ok_x.clone(), vec![], vec![]), SplineError::NoCurves);
    assert_eq!(
        err(ok_x.clone(), vec![1.0, 0.0], vec![0.0; 8]),
        SplineError::ZNotIncreasing { index: 1 }
    );
    assert_eq!(
        err(ok_x.clone(), vec![0.0, 1.0], vec![0.0; 4]),
        SplineError::LengthMismatch {
            expected: 8,
            found: 4
        }
    );
    assert_eq!(
        err(ok_x.clone(), vec![0.0], vec![0.0, f64::NAN, 0.0, 0.0]),
        SplineError::NotFinite
    );
    assert_eq!(
        err(vec![0.0, 1.0, 2.0, f64::INFINITY], vec![0.0], vec![0.0; 4]),
        SplineError::NotFinite
    );
    assert_eq!(
        err(
            vec![-1e308, 1e308, 1.5e308, 1.7e308],
            vec![0.0],
            vec![0.0; 4]
        ),
        SplineError::Overflow
    );
    assert!(err(vec![0.0; 2], vec![0.0], vec![0.0; 2])
        .to_string()
        .contains("at least 4"));
}

#[test]
fn invalid_and_nan_arguments_give_nan() {
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    for (name, f, g) in METHODS {
        assert!(f(f64::NAN, 0.0, &s, 0).is_nan(), "{name}");
        assert!(f(1.0, f64::NAN, &s, 0).is_nan(), "{name}");
        assert!(f(1.0, 0.0, &s, 3).is_nan(), "{name}");
        assert!(f(1.0, 0.0, &s, -1).is_nan(), "{name}");
        let (v, dx, dz) = g(f64::NAN, 0.0, &s);
        assert!(v.is_nan() && dx.is_nan() && dz.is_nan(), "{name}");
        assert!(g(0.0, f64::NAN, &surface()).0.is_nan(), "{name}");
        // A plain curve ignores a finite z.
        assert_eq!(f(1.5, 123.0, &s, 0), f(1.5, 0.0, &s, 0), "{name}");
        for x in [f64::INFINITY, f64::NEG_INFINITY] {
            let _ = (f(x, 0.0, &s, 0), f(x, 0.0, &s, 2), g(x, 0.0, &s));
            let _ = (f(1.0, x, &surface(), 0), g(1.0, x, &surface()));
        }
    }
}

#[test]
fn grads_match_finite_differences_and_iord_1() {
    let (xs, ys) = view_table();
    let s = curve(&xs, &ys);
    let surf = surface();
    for (name, f, g) in METHODS {
        for x in [-4.7, -3.3, -0.4, 0.6, 2.2, 3.5, 4.8] {
            let (v, dx, dz) = g(x, 0.0, &s);
            assert_eq!(v, f(x, 0.0, &s, 0), "{name}");
            assert_eq!(dx, f(x, 0.0, &s, 1), "{name}");
            assert_eq!(dz, 0.0, "{name}");
            let fx = |p: [f64; 1]| f(p[0], 0.0, &s, 0);
            assert_close(dx, central_diff(&fx, [x], 0), 1e-6);
            let d1 = |p: [f64; 1]| f(p[0], 0.0, &s, 1);
            assert_close(f(x, 0.0, &s, 2), central_diff(&d1, [x], 0), 1e-6);
            for z in [-0.5, 0.4, 1.7, 3.5] {
                let (_, dx, dz) = g(x, z, &surf);
                let fs = |p: [f64; 2]| f(p[0], p[1], &surf, 0);
                assert_close(dx, central_diff(&fs, [x, z], 0), 1e-6);
                assert_close(dz, central_diff(&fs, [x, z], 1), 1e-6);
            }
        }
    }
}
