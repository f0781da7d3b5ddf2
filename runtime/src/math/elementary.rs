//! Smooth elementary functions of spec §4 (ACOS … SQRT) and the `**` operator, each with
//! its analytic derivative companion.
//!
//! Values come straight from `std` (`f64::exp`, `f64::powf`, …), so both back ends call
//! the same libm routine; SIN, COS and ATAN2 are mbfx's own ([`super::trig`]), the same
//! bits on every platform and vectorisable over arrays. Derivative formulas are written
//! in the order stated in each doc comment. Domains follow IEEE: outside its domain a function gives NaN (or ±∞ at a
//! pole), and so does its derivative.

use core::f64::consts::LN_10;

/// `ACOS(a)`: arccosine, result in [0, π]. Domain |a| ≤ 1, NaN outside. `f64::acos`.
#[doc(alias = "ACOS")]
#[inline]
pub fn acos(a: f64) -> f64 {
    a.acos()
}

/// [`acos`] and d/da = `-1.0 / (1.0 - a * a).sqrt()` (−∞ at |a| = 1, NaN outside).
pub fn acos_grad(a: f64) -> (f64, [f64; 1]) {
    (a.acos(), [-1.0 / (1.0 - a * a).sqrt()])
}

/// `ASIN(a)`: arcsine, result in [−π/2, π/2]. Domain |a| ≤ 1, NaN outside. `f64::asin`.
#[doc(alias = "ASIN")]
#[inline]
pub fn asin(a: f64) -> f64 {
    a.asin()
}

/// [`asin`] and d/da = `1.0 / (1.0 - a * a).sqrt()` (+∞ at |a| = 1, NaN outside).
pub fn asin_grad(a: f64) -> (f64, [f64; 1]) {
    (a.asin(), [1.0 / (1.0 - a * a).sqrt()])
}

/// `ATAN(a)`: arctangent, result in (−π/2, π/2). Defined for every a. `f64::atan`.
#[doc(alias = "ATAN")]
#[inline]
pub fn atan(a: f64) -> f64 {
    a.atan()
}

/// [`atan`] and d/da = `1.0 / (1.0 + a * a)`.
pub fn atan_grad(a: f64) -> (f64, [f64; 1]) {
    (a.atan(), [1.0 / (1.0 + a * a)])
}

/// `ATAN2(a1, a2)`: angle of the point (x = a2, y = a1) in (−π, π] (FORTRAN order: the
/// first argument is y). [`super::trig::atan2`], under 1 ulp. At (0, 0) Adams leaves it
/// undefined; IEEE gives ±0 or ±π depending on the signs of the zeros.
#[doc(alias = "ATAN2")]
#[inline]
pub fn atan2(a1: f64, a2: f64) -> f64 {
    super::trig::atan2(a1, a2)
}

/// [`atan2`] and its partials: with `r2 = a1 * a1 + a2 * a2`,
/// ∂/∂a1 = `a2 / r2`, ∂/∂a2 = `-a1 / r2` (NaN at the origin).
pub fn atan2_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    let r2 = a1 * a1 + a2 * a2;
    (atan2(a1, a2), [a2 / r2, -a1 / r2])
}

/// `COS(a)`, a in radians. [`super::trig::cos`], under 1 ulp; NaN for ±∞.
#[doc(alias = "COS")]
#[inline]
pub fn cos(a: f64) -> f64 {
    super::trig::cos(a)
}

/// [`cos`] and d/da = `-sin(a)`.
pub fn cos_grad(a: f64) -> (f64, [f64; 1]) {
    (cos(a), [-sin(a)])
}

/// `SIN(a)`, a in radians. [`super::trig::sin`], under 1 ulp; NaN for ±∞.
#[doc(alias = "SIN")]
#[inline]
pub fn sin(a: f64) -> f64 {
    super::trig::sin(a)
}

/// [`sin`] and d/da = `cos(a)`.
pub fn sin_grad(a: f64) -> (f64, [f64; 1]) {
    (sin(a), [cos(a)])
}

/// `TAN(a)`, a in radians. `f64::tan`; NaN for ±∞.
#[doc(alias = "TAN")]
#[inline]
pub fn tan(a: f64) -> f64 {
    a.tan()
}

/// [`tan`] and d/da = `1.0 + t * t` with `t = a.tan()`.
pub fn tan_grad(a: f64) -> (f64, [f64; 1]) {
    let t = a.tan();
    (t, [1.0 + t * t])
}

/// `COSH(a)`: hyperbolic cosine. `f64::cosh`.
#[doc(alias = "COSH")]
#[inline]
pub fn cosh(a: f64) -> f64 {
    a.cosh()
}

/// [`cosh`] and d/da = `a.sinh()`.
pub fn cosh_grad(a: f64) -> (f64, [f64; 1]) {
    (a.cosh(), [a.sinh()])
}

/// `SINH(a)`: hyperbolic sine. `f64::sinh`.
#[doc(alias = "SINH")]
#[inline]
pub fn sinh(a: f64) -> f64 {
    a.sinh()
}

/// [`sinh`] and d/da = `a.cosh()`.
pub fn sinh_grad(a: f64) -> (f64, [f64; 1]) {
    (a.sinh(), [a.cosh()])
}

/// `TANH(a)`: hyperbolic tangent, in (−1, 1). `f64::tanh`.
#[doc(alias = "TANH")]
#[inline]
pub fn tanh(a: f64) -> f64 {
    a.tanh()
}

/// [`tanh`] and d/da = `1.0 - t * t` with `t = a.tanh()`.
pub fn tanh_grad(a: f64) -> (f64, [f64; 1]) {
    let t = a.tanh();
    (t, [1.0 - t * t])
}

/// `EXP(a)`: eᵃ. `f64::exp`; overflows to +∞ above about 709.78.
#[doc(alias = "EXP")]
#[inline]
pub fn exp(a: f64) -> f64 {
    a.exp()
}

/// [`exp`] and d/da = the value itself.
pub fn exp_grad(a: f64) -> (f64, [f64; 1]) {
    let v = a.exp();
    (v, [v])
}

/// `LOG(a)`: natural logarithm. Domain a > 0; `LOG(0)` = −∞, a < 0 gives NaN. `f64::ln`.
#[doc(alias = "LOG")]
#[inline]
pub fn log(a: f64) -> f64 {
    a.ln()
}

/// [`log`] and d/da = `1.0 / a`.
pub fn log_grad(a: f64) -> (f64, [f64; 1]) {
    let v = a.ln();
    let d = if v.is_nan() { f64::NAN } else { 1.0 / a };
    (v, [d])
}

/// `LOG10(a)`: base-10 logarithm. Domain a > 0; `LOG10(0)` = −∞. `f64::log10`.
#[doc(alias = "LOG10")]
#[inline]
pub fn log10(a: f64) -> f64 {
    a.log10()
}

/// [`log10`] and d/da = `1.0 / (a * LN_10)`.
pub fn log10_grad(a: f64) -> (f64, [f64; 1]) {
    let v = a.log10();
    let d = if v.is_nan() {
        f64::NAN
    } else {
        1.0 / (a * LN_10)
    };
    (v, [d])
}

/// `SQRT(a)`: square root. Domain a ≥ 0, NaN below (`SQRT(-0.0)` = −0). `f64::sqrt`
/// (correctly rounded, the same as Cranelift's `sqrt` instruction).
#[doc(alias = "SQRT")]
#[inline]
pub fn sqrt(a: f64) -> f64 {
    a.sqrt()
}

/// [`sqrt`] and d/da = `0.5 / v` with `v = a.sqrt()` (+∞ at 0).
pub fn sqrt_grad(a: f64) -> (f64, [f64; 1]) {
    let v = a.sqrt();
    (v, [0.5 / v])
}

/// The `**` operator: `a ** b = a.powf(b)` (libm `pow`).
///
/// Negative bases work with integral exponents (`(-2)**3 = -8`, `(-2)**2 = 4`); a negative
/// base with a non-integral exponent gives NaN (`(-8)**(1/3)`), and `0**-1` = +∞.
/// Unlike C `pow`, a NaN in either argument always gives NaN (C gives `pow(NaN, 0) = 1`
/// and `pow(1, NaN) = 1`): the NaN test comes first.
#[inline]
pub fn pow(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        return f64::NAN;
    }
    a.powf(b)
}

/// libm `pow` itself, without [`pow`]'s NaN-first test: the two agree whenever neither
/// argument is NaN. Not a language function: the JIT's lowering of IMPACT and BISTOP uses
/// it in the contact arm, where the base is positive and the exponent a checked constant.
#[inline]
pub fn pow_libm(a: f64, b: f64) -> f64 {
    a.powf(b)
}

/// [`pow`] and its partials.
///
/// * ∂/∂a = `b * a.powf(b - 1.0)`, and exactly 0 when b = 0 (`a**0` is constant, also at
///   a = 0 where the formula would give 0·∞).
/// * ∂/∂b = `v * a.ln()` for a > 0. Decision: for a ≤ 0 it is 0 (times the value, so it
///   is NaN when the value is infinite). The function has no real extension in b there
///   (only integral b are defined for a < 0), and a NaN would poison the chain rule of
///   the common constant-exponent case `x**3` with x < 0.
/// * Everything is NaN when the value is NaN.
pub fn pow_grad(a: f64, b: f64) -> (f64, [f64; 2]) {
    let v = pow(a, b);
    if v.is_nan() {
        return crate::nan_grad();
    }
    let da = if b == 0.0 { 0.0 } else { b * a.powf(b - 1.0) };
    let db = if a > 0.0 { v * a.ln() } else { 0.0 * v };
    (v, [da, db])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{assert_ulps, check_grad};
    use core::f64::consts::PI;

    #[test]
    fn atan2_cases_of_f1() {
        // F1; 3π/4 is not exact, so 1 ulp against the spec's shortest decimal.
        assert_ulps(atan2(1.0, -1.0), 2.356194490192345, 1);
        assert_eq!(atan2(0.0, -1.0), PI);
        assert_eq!(atan2(1.0, 0.0), PI / 2.0);
    }

    #[test]
    fn power_operator_cases() {
        // O3, O5, O13: exact in binary.
        assert_eq!(pow(2.0, pow(3.0, 2.0)), 512.0);
        assert_eq!(pow(2.0, -1.0), 0.5);
        assert_eq!(pow(-2.0, 2.0), 4.0);
        assert_eq!(pow(-2.0, 3.0), -8.0);
        assert_eq!(-pow(2.0, -2.0), -0.25);
        // O7: -(2**(-(2**-1))) = -1/√2, 1 ulp.
        assert_ulps(
            -pow(2.0, -pow(2.0, -1.0)),
            -core::f64::consts::FRAC_1_SQRT_2,
            1,
        );
        // O14, O15.
        assert!(pow(-8.0, 1.0 / 3.0).is_nan());
        assert_eq!(pow(0.0, -1.0), f64::INFINITY);
    }

    #[test]
    fn pow_propagates_nan_unlike_c_pow() {
        assert!(pow(f64::NAN, 0.0).is_nan());
        assert!(pow(1.0, f64::NAN).is_nan());
        assert!(pow_grad(f64::NAN, 0.0).1[0].is_nan());
    }

    #[test]
    fn domain_errors_follow_ieee() {
        // O15 and spec §4 domains (decision 7: IEEE values, diagnosed by the caller).
        assert_eq!(log(0.0), f64::NEG_INFINITY);
        assert!(log(-1.0).is_nan());
        assert!(sqrt(-1.0).is_nan());
        assert!(acos(2.0).is_nan());
        assert!(asin(-2.0).is_nan());
        assert_eq!(log10(0.0), f64::NEG_INFINITY);
        assert!(log_grad(-1.0).1[0].is_nan());
        assert!(acos_grad(2.0).1[0].is_nan());
    }

    #[test]
    fn log10_example() {
        // View example LOG10(42) = 1.6 (rounded in the source).
        assert!((log10(42.0) - 1.6).abs() < 0.05);
        assert_eq!(log10(1000.0), 3.0);
    }

    #[test]
    fn exact_values() {
        assert_eq!(cos(0.0), 1.0);
        assert_eq!(sin(0.0), 0.0);
        assert_eq!(tan(0.0), 0.0);
        assert_eq!(cosh(0.0), 1.0);
        assert_eq!(sinh(0.0), 0.0);
        assert_eq!(tanh(0.0), 0.0);
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(log(1.0), 0.0);
        assert_eq!(sqrt(2.25), 1.5);
        assert_eq!(acos(1.0), 0.0);
        assert_eq!(asin(1.0), PI / 2.0);
        assert_eq!(atan(f64::INFINITY), PI / 2.0);
    }

    #[test]
    fn nan_propagates_and_infinities_do_not_panic() {
        let unary: [fn(f64) -> f64; 15] = [
            acos,
            asin,
            atan,
            cos,
            sin,
            tan,
            cosh,
            sinh,
            tanh,
            exp,
            log,
            log10,
            sqrt,
            |a| atan2(a, 1.0),
            |a| atan2(1.0, a),
        ];
        for f in unary {
            assert!(f(f64::NAN).is_nan());
            let _ = f(f64::INFINITY);
            let _ = f(f64::NEG_INFINITY);
        }
        assert!(pow(f64::NAN, 2.0).is_nan());
        assert_eq!(pow(f64::INFINITY, -1.0), 0.0);
        let _ = pow_grad(f64::NEG_INFINITY, f64::INFINITY);
    }

    #[test]
    fn grads_match_finite_differences() {
        let pts = [-0.7, -0.2, 0.3, 0.9];
        for &a in &pts {
            check_grad(|v| acos(v[0]), |v| acos_grad(v[0]), [a]);
            check_grad(|v| asin(v[0]), |v| asin_grad(v[0]), [a]);
            check_grad(|v| atan(v[0]), |v| atan_grad(v[0]), [a * 3.0]);
            check_grad(|v| cos(v[0]), |v| cos_grad(v[0]), [a * 4.0]);
            check_grad(|v| sin(v[0]), |v| sin_grad(v[0]), [a * 4.0]);
            check_grad(|v| tan(v[0]), |v| tan_grad(v[0]), [a]);
            check_grad(|v| cosh(v[0]), |v| cosh_grad(v[0]), [a * 2.0]);
            check_grad(|v| sinh(v[0]), |v| sinh_grad(v[0]), [a * 2.0]);
            check_grad(|v| tanh(v[0]), |v| tanh_grad(v[0]), [a * 2.0]);
            check_grad(|v| exp(v[0]), |v| exp_grad(v[0]), [a * 3.0]);
            check_grad(|v| log(v[0]), |v| log_grad(v[0]), [a + 1.5]);
            check_grad(|v| log10(v[0]), |v| log10_grad(v[0]), [a + 1.5]);
            check_grad(|v| sqrt(v[0]), |v| sqrt_grad(v[0]), [a + 1.5]);
            check_grad(
                |v| atan2(v[0], v[1]),
                |v| atan2_grad(v[0], v[1]),
                [a, 0.4 - a],
            );
            check_grad(
                |v| pow(v[0], v[1]),
                |v| pow_grad(v[0], v[1]),
                [a + 1.5, a * 3.0],
            );
        }
    }

    #[test]
    fn pow_grad_conventions() {
        // x**3 at x < 0: ∂/∂a = 3x², ∂/∂b is 0 by decision.
        assert_eq!(pow_grad(-2.0, 3.0), (-8.0, [12.0, 0.0]));
        // a**0 is constant, also at a = 0.
        assert_eq!(pow_grad(0.0, 0.0), (1.0, [0.0, 0.0]));
        assert_eq!(pow_grad(0.0, 2.0), (0.0, [0.0, 0.0]));
    }
}
