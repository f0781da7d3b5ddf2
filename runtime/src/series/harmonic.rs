//! Harmonic functions: FORCOS and FORSIN (Fourier series, spec §5.8), SHF (simple
//! harmonic, §5.9) and SWEEP (linear frequency sweep, §5.10).

use core::f64::consts::TAU;

use super::{count_valid, grad_args_valid};
use crate::math::trig::{cos, sin};
use crate::steps::{step5, step5_grad};
use crate::{any_nan, nan_grad};

/// Shared body of FORCOS/FORSIN: `sum = a[0]; for j in 1..n { sum = sum + a[j] *
/// trig(j as f64 * w * t) }`.
#[inline]
fn fourier(x: f64, x0: f64, w: f64, coeffs: &[f64], trig: fn(f64) -> f64) -> f64 {
    let t = x - x0;
    if !count_valid(coeffs) || t.is_nan() || w.is_nan() {
        return f64::NAN;
    }
    let mut sum = 0.0;
    for (j, &a) in coeffs.iter().enumerate() {
        if j == 0 {
            sum = a;
        } else {
            sum += a * trig(j as f64 * w * t);
        }
    }
    sum
}

/// Shared body of the FORCOS/FORSIN gradients. `trig` gives the term's function and
/// `dtrig` its derivative.
fn fourier_grad(
    x: f64,
    x0: f64,
    w: f64,
    coeffs: &[f64],
    d_coeffs: &mut [f64],
    trig: fn(f64) -> f64,
    dtrig: fn(f64) -> f64,
) -> (f64, f64, f64, f64) {
    let t = x - x0;
    let nan = (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
    if !grad_args_valid(coeffs, d_coeffs, t.is_nan() || w.is_nan()) {
        return nan;
    }
    let (mut sum, mut dt, mut dw) = (0.0, 0.0, 0.0);
    for (j, (&a, d)) in coeffs.iter().zip(d_coeffs.iter_mut()).enumerate() {
        if j == 0 {
            sum = a;
            *d = 1.0;
            continue;
        }
        let jf = j as f64;
        let theta = jf * w * t;
        sum += a * trig(theta);
        let slope = a * dtrig(theta);
        dt += slope * (jf * w);
        dw += slope * (jf * t);
        *d = trig(theta);
    }
    if sum.is_nan() {
        d_coeffs.fill(f64::NAN);
        return nan;
    }
    (sum, dt, -dt, dw)
}

/// `FORCOS(x, x0, ω, a0, …, an)` = a0 + Σ_{j≥1} a_j·cos(j·ω·(x − x0)), 1 ..= 31
/// coefficients; a0 is a constant term.
///
/// Order: `t = x - x0; sum = a[0]; for j in 1..n { sum = sum + a[j] * cos(j as f64 * w *
/// t); }` (the angle is `(j * w) * t`; cos is [`crate::math::trig::cos`]). NaN for an
/// empty or too long list, or a NaN t or ω (tested first, so a single coefficient does
/// not hide them).
/// `FORCOS(0.25,0,PI,1,2,3)` = 2.4142135623730954.
#[doc(alias = "FORCOS")]
pub fn forcos(x: f64, x0: f64, w: f64, coeffs: &[f64]) -> f64 {
    fourier(x, x0, w, coeffs, cos)
}

/// [`forcos`] with its partials: returns (value, ∂/∂x, ∂/∂x0, ∂/∂ω) and writes
/// ∂/∂a_j into `d_coeffs[j]` (1 for j = 0, cos(jωt) after).
///
/// ∂/∂x = −Σ a_j·sin(jωt)·jω, ∂/∂x0 = −∂/∂x, ∂/∂ω = −Σ a_j·sin(jωt)·jt. Invalid calls
/// (also `d_coeffs` shorter than `coeffs`) and NaN values give NaN everywhere, with
/// `d_coeffs` filled with NaN.
pub fn forcos_grad(
    x: f64,
    x0: f64,
    w: f64,
    coeffs: &[f64],
    d_coeffs: &mut [f64],
) -> (f64, f64, f64, f64) {
    fourier_grad(x, x0, w, coeffs, d_coeffs, cos, |a| -sin(a))
}

/// `FORSIN(x, x0, ω, a0, …, an)` = a0 + Σ_{j≥1} a_j·sin(j·ω·(x − x0)), 1 ..= 31
/// coefficients; a0 is a constant term.
///
/// Order and validity as [`forcos`] with `sin`. `FORSIN(0.25,0,PI,1,2,3)` =
/// 5.414213562373095.
#[doc(alias = "FORSIN")]
pub fn forsin(x: f64, x0: f64, w: f64, coeffs: &[f64]) -> f64 {
    fourier(x, x0, w, coeffs, f64::sin)
}

/// [`forsin`] with its partials: (value, ∂/∂x, ∂/∂x0, ∂/∂ω) and ∂/∂a_j in `d_coeffs`
/// (1 for j = 0, sin(jωt) after). ∂/∂x = Σ a_j·cos(jωt)·jω, ∂/∂ω = Σ a_j·cos(jωt)·jt.
pub fn forsin_grad(
    x: f64,
    x0: f64,
    w: f64,
    coeffs: &[f64],
    d_coeffs: &mut [f64],
) -> (f64, f64, f64, f64) {
    fourier_grad(x, x0, w, coeffs, d_coeffs, sin, cos)
}

/// `SHF(x, x0, a, ω, φ, b)` = a·sin(ω·(x − x0) − φ) + b (note the minus on φ).
///
/// Order: `a * sin(w * (x - x0) - phi) + b`. Every argument enters the arithmetic,
/// so NaN propagates. `SHF(1,0,2,PI/2,0,3)` = 5.
#[doc(alias = "SHF")]
#[inline]
pub fn shf(x: f64, x0: f64, a: f64, w: f64, phi: f64, b: f64) -> f64 {
    a * sin(w * (x - x0) - phi) + b
}

/// [`shf`] and its partials with respect to (x, x0, a, ω, φ, b): with θ = ω(x − x0) − φ,
/// ∂x = a·cos θ·ω, ∂x0 = −∂x, ∂a = sin θ, ∂ω = a·cos θ·(x − x0), ∂φ = −a·cos θ, ∂b = 1.
pub fn shf_grad(x: f64, x0: f64, a: f64, w: f64, phi: f64, b: f64) -> (f64, [f64; 6]) {
    let v = shf(x, x0, a, w, phi, b);
    if v.is_nan() {
        return nan_grad();
    }
    let t = x - x0;
    let theta = w * t - phi;
    let ac = a * cos(theta);
    (v, [ac * w, -(ac * w), sin(theta), ac * t, -ac, 1.0])
}

/// Phase (in cycles) of SWEEP and its partials (∂x, ∂x0, ∂f0, ∂x1, ∂f1).
fn sweep_phase(x: f64, x0: f64, f0: f64, x1: f64, f1: f64) -> (f64, [f64; 5]) {
    if x <= x0 {
        (f0 * x, [f0, 0.0, x, 0.0, 0.0])
    } else if x >= x1 {
        let mid = (x1 + x0) / 2.0;
        let half = (f1 - f0) / 2.0;
        let phase = f1 * x - (f1 - f0) / 2.0 * (x1 + x0);
        (phase, [f1, -half, mid, -half, x - mid])
    } else {
        let u = x - x0;
        let l = x1 - x0;
        let c = (f1 - f0) / (2.0 * l);
        let phase = f0 * u + (f1 - f0) / (2.0 * (x1 - x0)) * u * u + f0 * x0;
        let u2l = u * u / l;
        let partials = [
            f0 + 2.0 * c * u,
            -2.0 * c * u + c * u2l,
            u - u2l / 2.0 + x0,
            -c * u2l,
            u2l / 2.0,
        ];
        (phase, partials)
    }
}

/// `SWEEP(x, a, x0, f0, x1, f1, dx)`: constant-amplitude sine whose frequency (cycles per
/// unit of x) goes linearly from f0 at x0 to f1 at x1, faded in over dx.
///
/// ```text
/// NaN                      any NaN argument, x0 >= x1, or not dx > 0
/// phase = f0 * x                                                   x <= x0
///         f1 * x - (f1 - f0) / 2.0 * (x1 + x0)                     x >= x1
///         u = x - x0;
///         f0 * u + (f1 - f0) / (2.0 * (x1 - x0)) * u * u + f0 * x0  otherwise
/// STEP5(x, x0, 0.0, x0 + dx, 1.0) * a * sin(TAU * phase)
/// ```
/// (`TAU` = 2π, exactly `2.0 * PI`; products left to right.)
///
/// Decision: the spec leaves the fade's start unknown (the mirror prints
/// `STEP5(x,0,0,dx,1)` but calls x0 + dx the point of full amplitude); mbfx fades in
/// over [x0, x0 + dx]. If x0 + dx rounds to x0 the fade STEP5 is invalid and SWEEP is
/// NaN.
#[doc(alias = "SWEEP")]
pub fn sweep(x: f64, a: f64, x0: f64, f0: f64, x1: f64, f1: f64, dx: f64) -> f64 {
    if any_nan([x, a, x0, f0, x1, f1, dx]) || x0 >= x1 || dx <= 0.0 {
        return f64::NAN;
    }
    let (phase, _) = sweep_phase(x, x0, f0, x1, f1);
    step5(x, x0, 0.0, x0 + dx, 1.0) * a * sin(TAU * phase)
}

/// [`sweep`] and its partials with respect to (x, a, x0, f0, x1, f1, dx).
///
/// With F the fade STEP5 and its partials, S = sin 2πφ, C = cos 2πφ, κ = a·F·2π·C:
/// ∂x = a·F_x·S + κ·φ_x, ∂a = F·S, ∂x0 = a·(F_x0 + F_x1)·S + κ·φ_x0, ∂f0 = κ·φ_f0,
/// ∂x1 = κ·φ_x1, ∂f1 = κ·φ_f1, ∂dx = a·F_x1·S. The phase and the fade are C¹ in x, so
/// the branch chosen at x0, x1 and x0 + dx (the constant one) does not change ∂x.
pub fn sweep_grad(x: f64, a: f64, x0: f64, f0: f64, x1: f64, f1: f64, dx: f64) -> (f64, [f64; 7]) {
    let v = sweep(x, a, x0, f0, x1, f1, dx);
    if v.is_nan() {
        return nan_grad();
    }
    let (phase, [px, px0, pf0, px1, pf1]) = sweep_phase(x, x0, f0, x1, f1);
    let (fade, [gx, gx0, _, gx1, _]) = step5_grad(x, x0, 0.0, x0 + dx, 1.0);
    let s = sin(TAU * phase);
    let kappa = a * fade * TAU * cos(TAU * phase);
    let g = [
        a * gx * s + kappa * px,
        fade * s,
        a * (gx0 + gx1) * s + kappa * px0,
        kappa * pf0,
        kappa * px1,
        kappa * pf1,
        a * gx1 * s,
    ];
    (v, g)
}

#[cfg(test)]
mod tests;
