//! Smooth step functions of spec §5.1–5.3: STEP (cubic), STEP5 (quintic), HAVSIN
//! (haversine), with first-derivative companions and second derivatives in x.
//!
//! All three share one shape: with Δ = (x − x0)/(x1 − x0),
//! the value is h0 for x ≤ x0, h1 for x ≥ x1, and h0 + (h1 − h0)·s(Δ) between, where s
//! rises from 0 to 1 with s′(0) = s′(1) = 0. The rows are tested in that order.
//!
//! Validity (spec §10 decision 6): x0 < x1, otherwise the result is NaN; any NaN argument
//! gives NaN. Every `_grad` returns the value and the partials with respect to
//! (x, x0, h0, x1, h1). At x = x0 and x = x1 the constant row is active; since s′ = 0
//! there the first derivatives agree from both sides, and `_d2` returns 0 (the one-sided
//! second derivative of the constant row; the interior limit differs).

use core::f64::consts::{FRAC_PI_2, PI};

use crate::math::trig::{cos, sin};
use crate::{any_nan, nan_grad};

/// Partials of h0 + (h1 − h0)·s(Δ) with respect to (x, x0, h0, x1, h1), given
/// a = h1 − h0, l = x1 − x0, Δ, s(Δ) and s′(Δ).
#[inline]
fn interior_grad(a: f64, l: f64, d: f64, s: f64, ds: f64) -> [f64; 5] {
    let dx = a * ds / l;
    [dx, dx * (d - 1.0), 1.0 - s, -dx * d, s]
}

/// STEP rows without the x0 < x1 check, for IMPACT and BISTOP (whose damping STEP has
/// x0 = x1 − d, which can round to x1 only when d is below an ulp of x1; the rows then
/// still give cmax or 0 without dividing by zero).
#[inline]
pub(crate) fn step_rows(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if x <= x0 {
        h0
    } else if x >= x1 {
        h1
    } else {
        let d = (x - x0) / (x1 - x0);
        h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)
    }
}

/// [`step_rows`] with the partials of [`step_grad`].
#[inline]
pub(crate) fn step_rows_grad(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> (f64, [f64; 5]) {
    if x <= x0 {
        (h0, [0.0, 0.0, 1.0, 0.0, 0.0])
    } else if x >= x1 {
        (h1, [0.0, 0.0, 0.0, 0.0, 1.0])
    } else {
        let (a, l) = (h1 - h0, x1 - x0);
        let d = (x - x0) / l;
        let v = h0 + a * d * d * (3.0 - 2.0 * d);
        let s = d * d * (3.0 - 2.0 * d);
        let ds = 6.0 * d * (1.0 - d);
        (v, interior_grad(a, l, d, s, ds))
    }
}

/// `STEP(x, x0, h0, x1, h1)`: cubic step from h0 to h1 over [x0, x1] (C¹).
///
/// ```text
/// NaN                                      any NaN argument, or x0 >= x1
/// h0                                       x <= x0
/// h1                                       x >= x1
/// d = (x - x0) / (x1 - x0);
/// h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d) otherwise (left to right)
/// ```
/// `STEP(0.25,0,0,1,1)` = 0.15625, `STEP(1.5,1,2,2,5)` = 3.5.
#[doc(alias = "STEP")]
#[inline]
pub fn step(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    StepParams::new(x0, h0, x1, h1).map_or(f64::NAN, |p| p.step(x))
}

/// The parameters `x0, h0, x1, h1` of a STEP, STEP5 or HAVSIN checked once (none NaN,
/// x0 < x1), for a host that calls one step many times with the same parameters (the
/// interpreter, for constant parameters).
///
/// [`step`], [`step5`] and [`havsin`] are `StepParams::new(x0, h0, x1, h1)` and then the
/// method of that name at x (NaN when `new` refuses), so the two entry points are one
/// code. A NaN x needs no test of its own: it fails both end tests, and the interior row
/// computes with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepParams {
    x0: f64,
    h0: f64,
    x1: f64,
    h1: f64,
}

impl StepParams {
    /// The checked parameters, or `None` when a step with them is NaN for every x.
    pub fn new(x0: f64, h0: f64, x1: f64, h1: f64) -> Option<Self> {
        if any_nan([x0, h0, x1, h1]) || x0 >= x1 {
            return None;
        }
        Some(StepParams { x0, h0, x1, h1 })
    }

    /// [`step`] at x, branch-free: every row is computed, then the end tests pick one (as
    /// the JIT's lowering does). Unpredictable inputs cost no mispredicted branches, and
    /// the rows are cheap arithmetic without side effects.
    #[inline]
    pub fn step(&self, x: f64) -> f64 {
        let StepParams { x0, h0, x1, h1 } = *self;
        let d = (x - x0) / (x1 - x0);
        let mid = h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d);
        pick(x <= x0, h0, pick(x >= x1, h1, mid))
    }

    /// [`step5`] at x, branch-free as [`StepParams::step`].
    #[inline]
    pub fn step5(&self, x: f64) -> f64 {
        let StepParams { x0, h0, x1, h1 } = *self;
        let d = (x - x0) / (x1 - x0);
        let mid = h0 + (h1 - h0) * d * d * d * (10.0 - 15.0 * d + 6.0 * d * d);
        pick(x <= x0, h0, pick(x >= x1, h1, mid))
    }

    /// [`havsin`] at x. Its interior calls `sin`, so the rows stay branches here: a call
    /// on every evaluation would cost more than a mispredicted branch.
    #[inline]
    pub fn havsin(&self, x: f64) -> f64 {
        let StepParams { x0, h0, x1, h1 } = *self;
        if x <= x0 {
            h0
        } else if x >= x1 {
            h1
        } else {
            let d = (x - x0) / (x1 - x0);
            (h0 + h1) / 2.0 + (h1 - h0) / 2.0 * sin(PI * d - FRAC_PI_2)
        }
    }
}

/// `if c { a } else { b }` on values already computed, written as a bit mask so that the
/// compiler emits a blend rather than a branch.
#[inline(always)]
pub(crate) fn pick(c: bool, a: f64, b: f64) -> f64 {
    let mask = u64::from(c).wrapping_neg();
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// [`step`] and its partials with respect to (x, x0, h0, x1, h1).
///
/// Inside, with l = x1 − x0, s = Δ²(3 − 2Δ), s′ = 6Δ(1 − Δ) and g = (h1 − h0)·s′/l:
/// ∂x = g, ∂x0 = g·(Δ − 1), ∂h0 = 1 − s, ∂x1 = −g·Δ, ∂h1 = s. Outside only the active
/// constant has partial 1.
pub fn step_grad(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> (f64, [f64; 5]) {
    if any_nan([x, x0, h0, x1, h1]) || x0 >= x1 {
        return nan_grad();
    }
    step_rows_grad(x, x0, h0, x1, h1)
}

/// Second derivative of [`step`] in x (spec §5.1):
/// `(h1 - h0) * (6.0 - 12.0 * d) / (l * l)` inside, 0 for x ≤ x0 or x ≥ x1 (it jumps at
/// both ends; the constant row's 0 is returned there). NaN when [`step`] is.
pub fn step_d2(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if any_nan([x, x0, h0, x1, h1]) || x0 >= x1 {
        return f64::NAN;
    }
    if x <= x0 || x >= x1 {
        return 0.0;
    }
    let l = x1 - x0;
    let d = (x - x0) / l;
    (h1 - h0) * (6.0 - 12.0 * d) / (l * l)
}

/// `STEP5(x, x0, h0, x1, h1)`: quintic step (C²).
///
/// ```text
/// NaN / h0 / h1 rows as in STEP, then
/// d = (x - x0) / (x1 - x0);
/// h0 + (h1 - h0) * d * d * d * (10.0 - 15.0 * d + 6.0 * d * d)
/// ```
/// (left to right; the bracket is `(10.0 - 15.0 * d) + (6.0 * d) * d`).
/// `STEP5(0.25,0,0,1,1)` = 0.103515625.
#[doc(alias = "STEP5")]
pub fn step5(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    StepParams::new(x0, h0, x1, h1).map_or(f64::NAN, |p| p.step5(x))
}

/// [`step5`] and its partials with respect to (x, x0, h0, x1, h1): as [`step_grad`] with
/// s = Δ³(10 − 15Δ + 6Δ²) and s′ = 30Δ²(1 − Δ)².
pub fn step5_grad(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> (f64, [f64; 5]) {
    let v = step5(x, x0, h0, x1, h1);
    if v.is_nan() {
        return nan_grad();
    }
    if x <= x0 {
        (v, [0.0, 0.0, 1.0, 0.0, 0.0])
    } else if x >= x1 {
        (v, [0.0, 0.0, 0.0, 0.0, 1.0])
    } else {
        let l = x1 - x0;
        let d = (x - x0) / l;
        let s = d * d * d * (10.0 - 15.0 * d + 6.0 * d * d);
        let ds = 30.0 * d * d * (1.0 - d) * (1.0 - d);
        (v, interior_grad(h1 - h0, l, d, s, ds))
    }
}

/// Second derivative of [`step5`] in x:
/// `(h1 - h0) * (60.0 * d - 180.0 * d * d + 120.0 * d * d * d) / (l * l)` inside, 0 at
/// and beyond the ends (continuous there: STEP5 is C²).
pub fn step5_d2(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if any_nan([x, x0, h0, x1, h1]) || x0 >= x1 {
        return f64::NAN;
    }
    if x <= x0 || x >= x1 {
        return 0.0;
    }
    let l = x1 - x0;
    let d = (x - x0) / l;
    (h1 - h0) * (60.0 * d - 180.0 * d * d + 120.0 * d * d * d) / (l * l)
}

/// `HAVSIN(x, x0, h0, x1, h1)`: haversine step (C¹).
///
/// ```text
/// NaN / h0 / h1 rows as in STEP, then
/// d = (x - x0) / (x1 - x0);
/// (h0 + h1) / 2.0 + (h1 - h0) / 2.0 * sin(PI * d - FRAC_PI_2)
/// ```
/// with `PI` and `FRAC_PI_2` the `f64` constants (π/2 is exactly PI/2).
/// `HAVSIN(0.25,0,0,1,1)` = 0.1464466094067263.
#[doc(alias = "HAVSIN")]
pub fn havsin(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    StepParams::new(x0, h0, x1, h1).map_or(f64::NAN, |p| p.havsin(x))
}

/// [`havsin`] and its partials with respect to (x, x0, h0, x1, h1): as [`step_grad`] with
/// s = (1 + sin θ)/2 and s′ = (π/2)·cos θ, θ = πΔ − π/2.
pub fn havsin_grad(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> (f64, [f64; 5]) {
    let v = havsin(x, x0, h0, x1, h1);
    if v.is_nan() {
        return nan_grad();
    }
    if x <= x0 {
        (v, [0.0, 0.0, 1.0, 0.0, 0.0])
    } else if x >= x1 {
        (v, [0.0, 0.0, 0.0, 0.0, 1.0])
    } else {
        let l = x1 - x0;
        let d = (x - x0) / l;
        let theta = PI * d - FRAC_PI_2;
        let s = 0.5 + 0.5 * sin(theta);
        let ds = FRAC_PI_2 * cos(theta);
        (v, interior_grad(h1 - h0, l, d, s, ds))
    }
}

/// Second derivative of [`havsin`] in x:
/// `(h1 - h0) / 2.0 * (PI * PI) * -sin(theta) / (l * l)` inside, θ = πΔ − π/2; 0 at and
/// beyond the ends (it jumps there: HAVSIN is only C¹).
pub fn havsin_d2(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if any_nan([x, x0, h0, x1, h1]) || x0 >= x1 {
        return f64::NAN;
    }
    if x <= x0 || x >= x1 {
        return 0.0;
    }
    let l = x1 - x0;
    let d = (x - x0) / l;
    let theta = PI * d - FRAC_PI_2;
    (h1 - h0) / 2.0 * (PI * PI) * -sin(theta) / (l * l)
}

#[cfg(test)]
mod tests;
