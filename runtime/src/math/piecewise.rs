//! Non-smooth functions of spec §4: ABS, AINT, ANINT, MOD, SIGN, DIM, MAX, MIN.
//!
//! Each is a short sequence of comparisons written so that a NaN argument fails every
//! test and reaches a NaN result (no `f64::max`/`f64::min`, which return the other
//! argument). The derivative companions return the derivative of the active branch; the
//! branch taken at a kink is stated per function.

/// `ABS(a)` = |a|: clears the sign bit (`f64::abs`, Cranelift `fabs`), so `ABS(-0.0)` = +0
/// and `ABS(NaN)` is NaN.
#[doc(alias = "ABS")]
#[inline]
pub fn abs(a: f64) -> f64 {
    a.abs()
}

/// [`abs`] and d/da: +1 for a ≥ 0 (also at a = 0 and −0: the branch a ≥ 0 is active),
/// −1 for a < 0, NaN for NaN.
pub fn abs_grad(a: f64) -> (f64, [f64; 1]) {
    let d = if a >= 0.0 {
        1.0
    } else if a < 0.0 {
        -1.0
    } else {
        f64::NAN
    };
    (a.abs(), [d])
}

/// `AINT(a)`: truncation toward zero (`f64::trunc`): `AINT(-6.5)` = −6, `AINT(4.6)` = 4,
/// 0 (signed like a) when |a| < 1. ±∞ and NaN pass through.
#[doc(alias = "AINT")]
#[inline]
pub fn aint(a: f64) -> f64 {
    a.trunc()
}

/// [`aint`] and d/da = 0 (the function is a staircase; at an integer the step above or
/// below is equally flat). NaN for NaN.
pub fn aint_grad(a: f64) -> (f64, [f64; 1]) {
    (a.trunc(), [if a.is_nan() { f64::NAN } else { 0.0 }])
}

/// `ANINT(a)`: nearest whole number, halves away from zero (`f64::round`):
/// `ANINT(2.5)` = 3, `ANINT(-2.5)` = −3, `ANINT(-4.6)` = −5. Note that the FORTRAN text
/// `int(a + 0.5)` would round 0.49999999999999994 up in floating point; `round` does not.
#[doc(alias = "ANINT")]
#[inline]
pub fn anint(a: f64) -> f64 {
    a.round()
}

/// [`anint`] and d/da = 0 (staircase, as [`aint_grad`]). NaN for NaN.
pub fn anint_grad(a: f64) -> (f64, [f64; 1]) {
    (a.round(), [if a.is_nan() { f64::NAN } else { 0.0 }])
}

/// `MOD(a1, a2)`: FORTRAN remainder a1 − int(a1/a2)·a2, with the sign of a1.
///
/// Computed as `a1 % a2` (C `fmod`): the exact remainder, with no rounding at all, so it
/// can differ from the literal formula evaluated in floating point, which rounds a1/a2
/// (`MOD(0.5, 0.1)` is 0.09999999999999998, not 0). `MOD(45,16)` = 13, `MOD(-7,3)` = −1,
/// `MOD(7,-3)` = 1. a2 = 0 or a1 = ±∞ gives NaN; a2 = ±∞ gives a1. The JIT must call
/// `mbfx_mod` (Cranelift has no float remainder). Named `amod` (FORTRAN's specific real
/// MOD) because `mod` is a Rust keyword.
#[doc(alias = "MOD")]
#[inline]
pub fn amod(a1: f64, a2: f64) -> f64 {
    a1 % a2
}

/// [`amod`] and its partials: ∂/∂a1 = 1, ∂/∂a2 = −q where q = int(a1/a2) is recovered
/// exactly as `((a1 - r) / a2).round()`. At a multiple of a2 (the jump) the branch with
/// remainder 0 is active, i.e. the quotient that makes r = 0.
pub fn amod_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    let r = a1 % a2;
    if r.is_nan() {
        return crate::nan_grad();
    }
    let q = ((a1 - r) / a2).round();
    (r, [1.0, -q])
}

/// `SIGN(a1, a2)`: |a1| if a2 ≥ 0, −|a1| if a2 < 0, NaN if either is NaN.
///
/// Operation order: `m = a1.abs(); if a2 >= 0.0 { m } else if a2 < 0.0 { -m } else { NaN }`.
/// Unlike IEEE `copysign`, a2 = −0.0 counts as ≥ 0, so `SIGN(-9.6, -0.0)` = 9.6 (the
/// SOLIDWORKS rule for a2 = 0, spec §4).
#[doc(alias = "SIGN")]
#[inline]
pub fn sign(a1: f64, a2: f64) -> f64 {
    let m = a1.abs();
    if a2 >= 0.0 {
        m
    } else if a2 < 0.0 {
        -m
    } else {
        f64::NAN
    }
}

/// [`sign`] and its partials: ∂/∂a1 = ±1 (the sign of a2's branch times the sign of a1,
/// with a1 = 0 taking the a1 ≥ 0 branch as in [`abs_grad`]); ∂/∂a2 = 0 (a jump at a2 = 0,
/// where the a2 ≥ 0 branch is active).
pub fn sign_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    let v = sign(a1, a2);
    if v.is_nan() {
        return crate::nan_grad();
    }
    let s1 = if a1 >= 0.0 { 1.0 } else { -1.0 };
    let s2 = if a2 >= 0.0 { 1.0 } else { -1.0 };
    (v, [s1 * s2, 0.0])
}

/// `DIM(a1, a2)`: positive difference, a1 − a2 if a1 > a2, else 0.
///
/// Operation order: `if a1 > a2 { a1 - a2 } else if a1 <= a2 { 0.0 } else { NaN }`.
/// `DIM(20,5)` = 15, `DIM(3,5)` = 0.
#[doc(alias = "DIM")]
#[inline]
pub fn dim(a1: f64, a2: f64) -> f64 {
    if a1 > a2 {
        a1 - a2
    } else if a1 <= a2 {
        0.0
    } else {
        f64::NAN
    }
}

/// [`dim`] and its partials: (1, −1) when a1 > a2, (0, 0) when a1 ≤ a2 (at the kink
/// a1 = a2 the zero branch is active).
pub fn dim_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    if a1 > a2 {
        (a1 - a2, [1.0, -1.0])
    } else if a1 <= a2 {
        (0.0, [0.0, 0.0])
    } else {
        crate::nan_grad()
    }
}

/// `MAX(a1, a2)`: the larger argument; exactly two arguments (spec §4).
///
/// Operation order: `if a1 >= a2 { a1 } else if a2 > a1 { a2 } else { a1 + a2 }` — ties
/// (including +0 vs −0) return a1, and the unordered case (a NaN) returns the NaN sum.
#[doc(alias = "MAX")]
#[inline]
pub fn max(a1: f64, a2: f64) -> f64 {
    if a1 >= a2 {
        a1
    } else if a2 > a1 {
        a2
    } else {
        a1 + a2
    }
}

/// [`max`] and its partials: (1, 0) when a1 ≥ a2 (ties pick a1, spec §4), (0, 1) when
/// a2 > a1.
pub fn max_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    if a1 >= a2 {
        (a1, [1.0, 0.0])
    } else if a2 > a1 {
        (a2, [0.0, 1.0])
    } else {
        crate::nan_grad()
    }
}

/// `MIN(a1, a2)`: the smaller argument; exactly two arguments.
///
/// Operation order: `if a1 <= a2 { a1 } else if a2 < a1 { a2 } else { a1 + a2 }` — ties
/// return a1, the unordered case returns the NaN sum.
#[doc(alias = "MIN")]
#[inline]
pub fn min(a1: f64, a2: f64) -> f64 {
    if a1 <= a2 {
        a1
    } else if a2 < a1 {
        a2
    } else {
        a1 + a2
    }
}

/// [`min`] and its partials: (1, 0) when a1 ≤ a2 (ties pick a1), (0, 1) when a2 < a1.
pub fn min_grad(a1: f64, a2: f64) -> (f64, [f64; 2]) {
    if a1 <= a2 {
        (a1, [1.0, 0.0])
    } else if a2 < a1 {
        (a2, [0.0, 1.0])
    } else {
        crate::nan_grad()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::check_grad;

    const NAN: f64 = f64::NAN;
    const INF: f64 = f64::INFINITY;

    #[test]
    fn aint_anint_of_f2_f3() {
        // F2, F3: exact.
        assert_eq!(aint(-6.5), -6.0);
        assert_eq!(aint(4.6), 4.0);
        assert_eq!(aint(0.7), 0.0);
        assert_eq!(anint(-4.6), -5.0);
        assert_eq!(anint(4.6), 5.0);
        assert_eq!(anint(2.5), 3.0);
        assert_eq!(anint(-2.5), -3.0);
        assert_eq!(anint(0.49999999999999994), 0.0);
    }

    #[test]
    fn mod_of_f4() {
        // F4: exact.
        assert_eq!(amod(45.0, 16.0), 13.0);
        assert_eq!(amod(-7.0, 3.0), -1.0);
        assert_eq!(amod(7.0, -3.0), 1.0);
        assert!(amod(5.0, 0.0).is_nan());
        assert!(amod(INF, 3.0).is_nan());
        assert_eq!(amod(5.0, INF), 5.0);
        // Exact remainder: the true quotient of 0.5 / 0.1 (as doubles) is just below 5,
        // so r = 0.5 - 4 * 0.1 (exact by Sterbenz), where the rounded formula gives 0.
        assert_eq!(amod(0.5, 0.1), 0.5 - 4.0 * 0.1);
        assert_eq!(0.5 - aint(0.5 / 0.1) * 0.1, 0.0);
    }

    #[test]
    fn sign_of_f5() {
        // F5: exact.
        assert_eq!(sign(9.6, 4.5), 9.6);
        assert_eq!(sign(9.6, -1.0), -9.6);
        assert_eq!(sign(-9.6, 0.0), 9.6);
        assert_eq!(sign(-9.6, -0.0), 9.6);
        assert!(sign(1.0, NAN).is_nan());
        assert!(sign(NAN, 1.0).is_nan());
    }

    #[test]
    fn dim_max_min_of_f6_f7() {
        // F6, F7: exact.
        assert_eq!(dim(5.0 * 4.0, 5.0), 15.0);
        assert_eq!(dim(3.0, 5.0), 0.0);
        assert_eq!(max(0.0, -3.0), 0.0);
        assert_eq!(min(0.0, -3.0), -3.0);
        assert_eq!(max(-3.0, 0.0), 0.0);
        assert_eq!(min(-3.0, 0.0), -3.0);
    }

    #[test]
    fn ties_pick_the_first_argument() {
        assert_eq!(max(-0.0, 0.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(min(0.0, -0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(max_grad(2.0, 2.0).1, [1.0, 0.0]);
        assert_eq!(min_grad(2.0, 2.0).1, [1.0, 0.0]);
    }

    #[test]
    fn nan_propagates_through_every_function() {
        for (a, b) in [(NAN, 1.0), (1.0, NAN), (NAN, NAN)] {
            assert!(max(a, b).is_nan(), "max({a}, {b})");
            assert!(min(a, b).is_nan(), "min({a}, {b})");
            assert!(dim(a, b).is_nan(), "dim({a}, {b})");
            assert!(sign(a, b).is_nan(), "sign({a}, {b})");
            assert!(amod(a, b).is_nan(), "mod({a}, {b})");
            for g in [max_grad, min_grad, dim_grad, sign_grad, amod_grad] {
                let (v, d) = g(a, b);
                assert!(v.is_nan() && d.iter().all(|x| x.is_nan()));
            }
        }
        for f in [abs, aint, anint] {
            assert!(f(NAN).is_nan());
        }
        for g in [abs_grad, aint_grad, anint_grad] {
            assert!(g(NAN).1[0].is_nan());
        }
    }

    #[test]
    fn infinities_do_not_panic() {
        for a in [INF, -INF, 0.0, -0.0, 1.0] {
            for b in [INF, -INF, 0.0, -0.0, 1.0] {
                let _ = (max(a, b), min(a, b), dim(a, b), sign(a, b), amod(a, b));
                let _ = (amod_grad(a, b), sign_grad(a, b), dim_grad(a, b));
            }
        }
        assert_eq!(dim(INF, 0.0), INF);
        assert_eq!(aint(-INF), -INF);
    }

    #[test]
    fn kink_conventions() {
        assert_eq!(abs_grad(0.0).1, [1.0]);
        assert_eq!(abs_grad(-0.0).1, [1.0]);
        assert_eq!(abs_grad(-2.0), (2.0, [-1.0]));
        assert_eq!(dim_grad(5.0, 5.0), (0.0, [0.0, 0.0]));
        assert_eq!(dim_grad(6.0, 5.0), (1.0, [1.0, -1.0]));
        assert_eq!(sign_grad(0.0, -1.0), (-0.0, [-1.0, 0.0]));
        assert_eq!(sign_grad(-2.0, 0.0), (2.0, [-1.0, 0.0]));
        assert_eq!(amod_grad(6.0, 3.0), (0.0, [1.0, -2.0]));
        assert_eq!(aint_grad(2.7), (2.0, [0.0]));
        assert_eq!(anint_grad(2.7), (3.0, [0.0]));
    }

    #[test]
    fn grads_match_finite_differences() {
        for &(a, b) in &[(1.3, 0.4), (-2.3, 0.9), (5.7, -1.7), (-0.6, -2.2)] {
            check_grad(|v| abs(v[0]), |v| abs_grad(v[0]), [a]);
            check_grad(|v| amod(v[0], v[1]), |v| amod_grad(v[0], v[1]), [a, b]);
            check_grad(|v| sign(v[0], v[1]), |v| sign_grad(v[0], v[1]), [a, b]);
            check_grad(|v| dim(v[0], v[1]), |v| dim_grad(v[0], v[1]), [a, b]);
            check_grad(|v| max(v[0], v[1]), |v| max_grad(v[0], v[1]), [a, b]);
            check_grad(|v| min(v[0], v[1]), |v| min_grad(v[0], v[1]), [a, b]);
            check_grad(|v| aint(v[0]), |v| aint_grad(v[0]), [a]);
            check_grad(|v| anint(v[0]), |v| anint_grad(v[0]), [a]);
        }
    }
}
