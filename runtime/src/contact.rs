//! Contact forces of spec §5.4–5.5: IMPACT (one-sided) and BISTOP (two-sided gap).
//!
//! Both are a power-law spring plus a damper whose coefficient rises from 0 at contact
//! to cmax at penetration d along a cubic STEP. Spec §10 decision 5: the force is
//! clamped so that it never pulls (IMPACT and BISTOP's lower branch ≥ 0, BISTOP's upper
//! branch ≤ 0); the clamp is part of these functions.
//!
//! Validity: k ≥ 0, e > 0, cmax ≥ 0, d > 0 and for BISTOP x1 < x2; otherwise NaN, as for
//! any NaN argument. The sign of IMPACT's x1 is not checked (decision: the formula is
//! well defined for any free length; the checker may warn on x1 ≤ 0, spec §5.4).
//!
//! The damping STEP is evaluated with STEP's rows and operation order but without its
//! x0 < x1 check (see `steps::step_rows`), since x1 − d can round to x1 only for a d
//! below an ulp of x1, where the rows still give the right constant.

use crate::steps::{step_rows, step_rows_grad};
use crate::{any_nan, nan_grad};

/// k ≥ 0, e > 0, cmax ≥ 0, d > 0 (false for NaN).
#[inline]
fn params_valid(k: f64, e: f64, cmax: f64, d: f64) -> bool {
    k >= 0.0 && e > 0.0 && cmax >= 0.0 && d > 0.0
}

/// Unclamped lower-branch force for x < x1:
/// `k * (x1 - x).powf(e) - step_rows(x, x1 - d, cmax, x1, 0.0) * xd`.
#[inline]
fn lower_force(x: f64, xd: f64, x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    k * (x1 - x).powf(e) - step_rows(x, x1 - d, cmax, x1, 0.0) * xd
}

/// Unclamped upper-branch force for x > x2:
/// `-(k * (x - x2).powf(e)) - step_rows(x, x2, 0.0, x2 + d, cmax) * xd`.
#[inline]
fn upper_force(x: f64, xd: f64, x2: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    -(k * (x - x2).powf(e)) - step_rows(x, x2, 0.0, x2 + d, cmax) * xd
}

/// Clamp to f ≥ 0: `if f > 0.0 { f } else if f <= 0.0 { 0.0 } else { f }` (NaN stays).
#[inline]
fn push_only(f: f64) -> f64 {
    if f > 0.0 {
        f
    } else if f <= 0.0 {
        0.0
    } else {
        f
    }
}

/// Clamp to f ≤ 0: `if f < 0.0 { f } else if f >= 0.0 { 0.0 } else { f }` (NaN stays).
#[inline]
fn pull_only(f: f64) -> f64 {
    if f < 0.0 {
        f
    } else if f >= 0.0 {
        0.0
    } else {
        f
    }
}

/// Partials of the lower-branch force with respect to (x, ẋ, x1, k, e, cmax, d), from
/// p = x1 − x > 0 and the damping STEP(x, x1 − d, cmax, x1, 0).
fn lower_grad(x: f64, xd: f64, x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> [f64; 7] {
    let p = x1 - x;
    let pe = p.powf(e);
    let dspring = k * e * p.powf(e - 1.0);
    let (c, [gx, gx0, gh0, gx1, _]) = step_rows_grad(x, x1 - d, cmax, x1, 0.0);
    [
        -dspring - xd * gx,
        -c,
        dspring - xd * (gx0 + gx1),
        pe,
        k * pe * p.ln(),
        -xd * gh0,
        xd * gx0,
    ]
}

/// `IMPACT(x, ẋ, x1, k, e, cmax, d)`: one-sided contact force, clamped (decision 5).
///
/// x is the gap measure, ẋ its time derivative, x1 the free length (contact when
/// x < x1), k the stiffness, e the exponent, cmax the maximum damping, d the penetration
/// of full damping.
/// ```text
/// NaN                                  any NaN, or not (k >= 0, e > 0, cmax >= 0, d > 0)
/// 0.0                                  x >= x1
/// f = k * (x1 - x).powf(e) - STEP(x, x1 - d, cmax, x1, 0.0) * xd
/// if f > 0.0 { f } else if f <= 0.0 { 0.0 } else { f }
/// ```
/// `IMPACT(0.95,-2,1,1E5,1.5,100,0.1)` = 1218.0339887498967; with ẋ = 30 the
/// unclamped force −381.97 is clamped to 0.
#[doc(alias = "IMPACT")]
pub fn impact(x: f64, xd: f64, x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    Impact::new(x1, k, e, cmax, d).map_or(f64::NAN, |c| c.force(x, xd))
}

/// The parameters `x1, k, e, cmax, d` of an IMPACT checked once, for a host that calls
/// one IMPACT many times with the same parameters (the interpreter, for constant ones).
///
/// [`impact`] is `Impact::new(x1, k, e, cmax, d)` and then [`Impact::force`] at (x, ẋ)
/// (NaN when `new` refuses), so both entry points run one code.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    x1: f64,
    k: f64,
    e: f64,
    cmax: f64,
    d: f64,
}

impl Impact {
    /// The checked parameters, or `None` when IMPACT with them is NaN for every x, ẋ.
    pub fn new(x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> Option<Self> {
        if any_nan([x1, k, e, cmax, d]) || !params_valid(k, e, cmax, d) {
            return None;
        }
        Some(Impact { x1, k, e, cmax, d })
    }

    /// [`impact`] at (x, ẋ).
    #[inline]
    pub fn force(&self, x: f64, xd: f64) -> f64 {
        let Impact { x1, k, e, cmax, d } = *self;
        if x.is_nan() || xd.is_nan() {
            return f64::NAN;
        }
        if x >= x1 {
            return 0.0;
        }
        push_only(lower_force(x, xd, x1, k, e, cmax, d))
    }
}

/// The parameters `x1, x2, k, e, cmax, d` of a BISTOP checked once, as [`Impact`]:
/// [`bistop`] is `Bistop::new` and then [`Bistop::force`]. The lower stop's parameters
/// are an [`Impact`]'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bistop {
    lower: Impact,
    x2: f64,
}

impl Bistop {
    /// The checked parameters, or `None` when BISTOP with them is NaN for every x, ẋ.
    pub fn new(x1: f64, x2: f64, k: f64, e: f64, cmax: f64, d: f64) -> Option<Self> {
        let lower = Impact::new(x1, k, e, cmax, d)?;
        if x2.is_nan() || x1 >= x2 {
            return None;
        }
        Some(Bistop { lower, x2 })
    }

    /// [`bistop`] at (x, ẋ).
    #[inline]
    pub fn force(&self, x: f64, xd: f64) -> f64 {
        let Impact { x1, k, e, cmax, d } = self.lower;
        if x.is_nan() || xd.is_nan() {
            return f64::NAN;
        }
        if x < x1 {
            push_only(lower_force(x, xd, x1, k, e, cmax, d))
        } else if x > self.x2 {
            pull_only(upper_force(x, xd, self.x2, k, e, cmax, d))
        } else {
            0.0
        }
    }
}

/// [`impact`] and its partials with respect to (x, ẋ, x1, k, e, cmax, d).
///
/// In contact, with p = x1 − x and c, ∂c the damping STEP and its partials:
/// ∂x = −k·e·p^(e−1) − ẋ·∂c/∂x, ∂ẋ = −c, ∂x1 = k·e·p^(e−1) − ẋ·(∂c/∂x0 + ∂c/∂x1),
/// ∂k = p^e, ∂e = k·p^e·ln p, ∂cmax = −ẋ·∂c/∂h0, ∂d = ẋ·∂c/∂x0.
/// Kinks: at x = x1 (no contact) and where the clamp is active (f ≤ 0, including f = 0)
/// the zero branch is active and every partial is 0.
pub fn impact_grad(x: f64, xd: f64, x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> (f64, [f64; 7]) {
    let v = impact(x, xd, x1, k, e, cmax, d);
    if v.is_nan() {
        return nan_grad();
    }
    if v > 0.0 {
        (v, lower_grad(x, xd, x1, k, e, cmax, d))
    } else {
        (v, [0.0; 7])
    }
}

/// `BISTOP(x, ẋ, x1, x2, k, e, cmax, d)`: two-sided gap force, clamped (decision 5).
///
/// Free between x1 and x2; below x1 a pushing force as [`impact`], above x2 a pulling
/// one.
/// ```text
/// NaN                     any NaN, or not (x1 < x2, k >= 0, e > 0, cmax >= 0, d > 0)
/// x < x1:  f = k * (x1 - x).powf(e) - STEP(x, x1 - d, cmax, x1, 0.0) * xd
///          if f > 0.0 { f } else if f <= 0.0 { 0.0 } else { f }
/// x > x2:  f = -(k * (x - x2).powf(e)) - STEP(x, x2, 0.0, x2 + d, cmax) * xd
///          if f < 0.0 { f } else if f >= 0.0 { 0.0 } else { f }
/// else:    0.0
/// ```
/// `BISTOP(2.05,1,-2,2,1000,2,10,0.1)` = −7.5; with ẋ = −10 the unclamped 47.5 is
/// clamped to 0.
#[doc(alias = "BISTOP")]
#[allow(clippy::too_many_arguments)] // the Adams signature has eight arguments
pub fn bistop(x: f64, xd: f64, x1: f64, x2: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    Bistop::new(x1, x2, k, e, cmax, d).map_or(f64::NAN, |c| c.force(x, xd))
}

/// [`bistop`] and its partials with respect to (x, ẋ, x1, x2, k, e, cmax, d).
///
/// Below x1 as [`impact_grad`] (∂x2 = 0). Above x2, with p = x − x2 and c, ∂c the
/// damping STEP(x, x2, 0, x2 + d, cmax): ∂x = −k·e·p^(e−1) − ẋ·∂c/∂x, ∂ẋ = −c, ∂x1 = 0,
/// ∂x2 = k·e·p^(e−1) − ẋ·(∂c/∂x0 + ∂c/∂x1), ∂k = −p^e, ∂e = −k·p^e·ln p,
/// ∂cmax = −ẋ·∂c/∂h1, ∂d = −ẋ·∂c/∂x1. Kinks: at x = x1, x = x2 and where a clamp is
/// active (including a force of exactly 0) every partial is 0.
#[allow(clippy::too_many_arguments)] // the Adams signature has eight arguments
pub fn bistop_grad(
    x: f64,
    xd: f64,
    x1: f64,
    x2: f64,
    k: f64,
    e: f64,
    cmax: f64,
    d: f64,
) -> (f64, [f64; 8]) {
    let v = bistop(x, xd, x1, x2, k, e, cmax, d);
    if v.is_nan() {
        return nan_grad();
    }
    if x < x1 && v > 0.0 {
        let [gx, gxd, gx1, gk, ge, gc, gd] = lower_grad(x, xd, x1, k, e, cmax, d);
        (v, [gx, gxd, gx1, 0.0, gk, ge, gc, gd])
    } else if x > x2 && v < 0.0 {
        let p = x - x2;
        let pe = p.powf(e);
        let dspring = k * e * p.powf(e - 1.0);
        let (c, [gx, gx0, _, gx1, gh1]) = step_rows_grad(x, x2, 0.0, x2 + d, cmax);
        let g = [
            -dspring - xd * gx,
            -c,
            0.0,
            dspring - xd * (gx0 + gx1),
            -pe,
            -(k * pe * p.ln()),
            -xd * gh1,
            -xd * gx1,
        ];
        (v, g)
    } else {
        (v, [0.0; 8])
    }
}

#[cfg(test)]
mod tests;
