//! POLY (power series, spec §5.6) and CHEBY (Chebyshev series, spec §5.7) in t = x − x0.

use super::{count_valid, grad_args_valid};

/// `POLY(x, x0, a0, …, an)` = Σ a_j·(x − x0)^j, 1 ..= 31 coefficients (`coeffs[j]` = a_j).
///
/// Horner's scheme, in this order:
/// ```text
/// NaN                                 coeffs empty or longer than 31, or t is NaN
/// t = x - x0;
/// acc = a[n-1];
/// for j in (0..n-1).rev() { acc = acc * t + a[j]; }   // separate × then +, no FMA
/// acc
/// ```
/// `POLY(3,1,1,2,3)` = 17. The NaN test on t makes `POLY(NaN,0,5)` NaN although the
/// single coefficient does not use t.
#[doc(alias = "POLY")]
pub fn poly(x: f64, x0: f64, coeffs: &[f64]) -> f64 {
    let t = x - x0;
    let Some((&last, rest)) = coeffs.split_last() else {
        return f64::NAN;
    };
    if !count_valid(coeffs) || t.is_nan() {
        return f64::NAN;
    }
    let mut acc = last;
    for &a in rest.iter().rev() {
        acc = acc * t + a;
    }
    acc
}

/// [`poly`] with its partials: returns (value, ∂/∂x, ∂/∂x0) and writes ∂/∂a_j = t^j into
/// `d_coeffs[j]` for j < n (t^j by repeated multiplication, t⁰ = 1).
///
/// ∂/∂x = Σ j·a_j·t^(j−1) (Horner on the derivative, alongside the value), ∂/∂x0 = −∂/∂x.
/// If the call is invalid (see [`poly`]) or `d_coeffs` is shorter than `coeffs`, or the
/// value is NaN, everything returned is NaN and all of `d_coeffs` is set to NaN.
pub fn poly_grad(x: f64, x0: f64, coeffs: &[f64], d_coeffs: &mut [f64]) -> (f64, f64, f64) {
    let t = x - x0;
    let nan = (f64::NAN, f64::NAN, f64::NAN);
    if !grad_args_valid(coeffs, d_coeffs, t.is_nan()) {
        return nan;
    }
    let Some((&last, rest)) = coeffs.split_last() else {
        return nan;
    };
    let mut acc = last;
    let mut dacc = 0.0;
    for &a in rest.iter().rev() {
        dacc = dacc * t + acc;
        acc = acc * t + a;
    }
    if acc.is_nan() {
        d_coeffs.fill(f64::NAN);
        return nan;
    }
    let mut power = 1.0;
    for d in d_coeffs.iter_mut().take(coeffs.len()) {
        *d = power;
        power *= t;
    }
    (acc, dacc, -dacc)
}

/// `CHEBY(x, x0, a0, …, an)` = Σ a_j·T_j(t), t = x − x0, 1 ..= 31 coefficients, with
/// T0 = 1, T1 = t, T_j = 2t·T_{j−1} − T_{j−2}.
///
/// Evaluated by the recurrence, in this order:
/// ```text
/// NaN                                 coeffs empty or longer than 31, or t is NaN
/// t = x - x0;
/// sum = a[0];
/// if n > 1 { sum = sum + a[1] * t; }
/// tm2 = 1.0; tm1 = t;
/// for j in 2..n { tj = 2.0 * t * tm1 - tm2; sum = sum + a[j] * tj; tm2 = tm1; tm1 = tj; }
/// ```
/// `CHEBY(0.5,0,1,2,3)` = 0.5, `CHEBY(2,1,0,0,0,1)` = 1.
#[doc(alias = "CHEBY")]
pub fn cheby(x: f64, x0: f64, coeffs: &[f64]) -> f64 {
    let t = x - x0;
    if !count_valid(coeffs) || t.is_nan() {
        return f64::NAN;
    }
    let mut it = coeffs.iter();
    let Some(&a0) = it.next() else {
        return f64::NAN;
    };
    let mut sum = a0;
    if let Some(&a1) = it.next() {
        sum += a1 * t;
        let (mut tm2, mut tm1) = (1.0, t);
        for &a in it {
            let tj = 2.0 * t * tm1 - tm2;
            sum += a * tj;
            tm2 = tm1;
            tm1 = tj;
        }
    }
    sum
}

/// [`cheby`] with its partials: returns (value, ∂/∂x, ∂/∂x0) and writes ∂/∂a_j = T_j(t)
/// into `d_coeffs[j]`.
///
/// ∂/∂x = Σ a_j·T_j′(t) with T0′ = 0, T1′ = 1, T_j′ = 2·T_{j−1} + 2t·T_{j−1}′ − T_{j−2}′;
/// ∂/∂x0 = −∂/∂x. Invalid calls and NaN values give NaN as in [`poly_grad`].
pub fn cheby_grad(x: f64, x0: f64, coeffs: &[f64], d_coeffs: &mut [f64]) -> (f64, f64, f64) {
    let t = x - x0;
    let nan = (f64::NAN, f64::NAN, f64::NAN);
    if !grad_args_valid(coeffs, d_coeffs, t.is_nan()) {
        return nan;
    }
    let mut sum = 0.0;
    let mut dsum = 0.0;
    // (T_{j-2}, T_{j-1}) and their derivatives, seeded so that j = 0 and 1 give 1 and t.
    let (mut tm2, mut tm1, mut dm2, mut dm1) = (0.0, 0.0, 0.0, 0.0);
    for (j, (&a, d)) in coeffs.iter().zip(d_coeffs.iter_mut()).enumerate() {
        let (tj, dj) = match j {
            0 => (1.0, 0.0),
            1 => (t, 1.0),
            _ => (2.0 * t * tm1 - tm2, 2.0 * tm1 + 2.0 * t * dm1 - dm2),
        };
        sum = if j == 0 { a } else { sum + a * tj };
        dsum += a * dj;
        *d = tj;
        (tm2, tm1, dm2, dm1) = (tm1, tj, dm1, dj);
    }
    if sum.is_nan() {
        d_coeffs.fill(f64::NAN);
        return nan;
    }
    (sum, dsum, -dsum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{assert_close, central_diff};

    type Grad = fn(f64, f64, &[f64], &mut [f64]) -> (f64, f64, f64);

    /// Checks a variadic gradient against central differences in x, x0 and every a_j.
    fn check_series(f: fn(f64, f64, &[f64]) -> f64, g: Grad, x: f64, x0: f64, a: &[f64]) {
        let mut da = vec![0.0; a.len()];
        let (v, dx, dx0) = g(x, x0, a, &mut da);
        assert_eq!(v.to_bits(), f(x, x0, a).to_bits());
        let fx = |p: [f64; 2]| f(p[0], p[1], a);
        assert_close(dx, central_diff(&fx, [x, x0], 0), 1e-6);
        assert_close(dx0, central_diff(&fx, [x, x0], 1), 1e-6);
        for j in 0..a.len() {
            let fa = |p: [f64; 1]| {
                let mut b = a.to_vec();
                b[j] = p[0];
                f(x, x0, &b)
            };
            assert_close(da[j], central_diff(&fa, [a[j]], 0), 1e-6);
        }
    }

    #[test]
    fn poly_examples_of_spec_5_6_and_f20() {
        // Exact in binary.
        assert_eq!(poly(3.0, 1.0, &[1.0, 2.0, 3.0]), 17.0);
        assert_eq!(poly(1.5, 0.0, &[0.0, 0.0, 1.0]), 2.25);
        assert_eq!(poly(7.0, 5.0, &[0.0, 10.0]), 20.0);
        assert_eq!(poly(9.0, 5.0, &[4.0]), 4.0);
    }

    #[test]
    fn cheby_examples_of_spec_5_7_and_f21() {
        // Exact in binary.
        assert_eq!(cheby(0.5, 0.0, &[1.0, 2.0, 3.0]), 0.5);
        assert_eq!(cheby(2.0, 1.0, &[0.0, 0.0, 0.0, 1.0]), 1.0);
        // T4(0.5) = 8t⁴ − 8t² + 1 = −0.5.
        assert_eq!(cheby(0.5, 0.0, &[0.0, 0.0, 0.0, 0.0, 1.0]), -0.5);
        assert_eq!(cheby(9.0, 5.0, &[4.0]), 4.0);
    }

    #[test]
    fn coefficient_count_limits() {
        // F24: 32 coefficients are rejected, 31 accepted; an empty list is invalid.
        let ones = [1.0; 32];
        assert!(poly(0.5, 0.0, &ones).is_nan());
        assert!(cheby(0.5, 0.0, &ones).is_nan());
        assert!(poly(0.5, 0.0, &[]).is_nan());
        assert!(cheby(0.5, 0.0, &[]).is_nan());
        assert_eq!(poly(1.0, 0.0, &ones[..31]), 31.0);
        assert_eq!(cheby(1.0, 0.0, &ones[..31]), 31.0);
        let mut d = [0.0; 32];
        assert!(poly_grad(0.5, 0.0, &ones, &mut d).0.is_nan());
        assert!(d.iter().all(|v| v.is_nan()));
        assert!(cheby_grad(0.5, 0.0, &[], &mut d).0.is_nan());
        // d_coeffs too short.
        let mut short = [0.0; 2];
        assert!(poly_grad(0.5, 0.0, &[1.0, 2.0, 3.0], &mut short).1.is_nan());
        assert!(short.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn nan_propagates() {
        for f in [poly, cheby] {
            assert!(f(f64::NAN, 0.0, &[5.0]).is_nan());
            assert!(f(1.0, f64::NAN, &[5.0]).is_nan());
            assert!(f(1.0, 0.0, &[5.0, f64::NAN]).is_nan());
            assert!(f(1.0, 0.0, &[f64::NAN, 5.0, 1.0]).is_nan());
        }
        let mut d = [0.0; 3];
        let (v, dx, dx0) = cheby_grad(1.0, 0.0, &[1.0, f64::NAN, 2.0], &mut d);
        assert!(v.is_nan() && dx.is_nan() && dx0.is_nan() && d.iter().all(|v| v.is_nan()));
        let (v, ..) = poly_grad(f64::NAN, 0.0, &[1.0], &mut d);
        assert!(v.is_nan() && d.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn infinities_do_not_panic() {
        let inf = f64::INFINITY;
        let mut d = [0.0; 3];
        for (x, x0) in [(inf, 0.0), (0.0, inf), (inf, inf), (-inf, 1.0)] {
            let _ = (
                poly(x, x0, &[1.0, 2.0, 3.0]),
                cheby(x, x0, &[1.0, 2.0, 3.0]),
            );
            let _ = poly_grad(x, x0, &[1.0, 2.0, 3.0], &mut d);
            let _ = cheby_grad(x, x0, &[1.0, 2.0, 3.0], &mut d);
        }
    }

    #[test]
    fn grads_match_finite_differences() {
        let sets: [&[f64]; 4] = [
            &[4.0],
            &[1.0, 2.0],
            &[1.0, 2.0, 3.0],
            &[0.5, -1.0, 0.25, 2.0, -0.75, 0.1],
        ];
        for a in sets {
            for (x, x0) in [(0.3, 0.0), (2.5, 1.0), (-0.7, 0.2)] {
                check_series(poly, poly_grad, x, x0, a);
                check_series(cheby, cheby_grad, x, x0, a);
            }
        }
        let mut d = [0.0; 3];
        assert_eq!(
            poly_grad(3.0, 1.0, &[1.0, 2.0, 3.0], &mut d),
            (17.0, 14.0, -14.0)
        );
        assert_eq!(d, [1.0, 2.0, 4.0]);
        assert_eq!(
            cheby_grad(0.5, 0.0, &[1.0, 2.0, 3.0], &mut d),
            (0.5, 8.0, -8.0)
        );
        assert_eq!(d, [1.0, 0.5, -0.5]);
    }
}
