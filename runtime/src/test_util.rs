//! Test helpers shared by the unit tests of every family: ulp and relative comparisons,
//! and a central finite-difference check of the analytic `_grad` companions.

/// Distance in units in the last place between two finite doubles (0 for equal values,
/// including +0 and −0).
pub fn ulps(a: f64, b: f64) -> u64 {
    fn key(x: f64) -> i128 {
        let bits = x.to_bits() as i64;
        if bits < 0 {
            i128::from(i64::MIN) - i128::from(bits)
        } else {
            i128::from(bits)
        }
    }
    (key(a) - key(b)).unsigned_abs() as u64
}

/// Asserts `actual` is within `max` ulps of `expected`.
#[track_caller]
pub fn assert_ulps(actual: f64, expected: f64, max: u64) {
    assert!(
        actual.is_finite() && ulps(actual, expected) <= max,
        "{actual:e} is {} ulps from {expected:e} (allowed {max})",
        ulps(actual, expected)
    );
}

/// Asserts `|actual − expected| ≤ tol · max(1, |expected|)`.
#[track_caller]
pub fn assert_close(actual: f64, expected: f64, tol: f64) {
    let scale = expected.abs().max(1.0);
    assert!(
        (actual - expected).abs() <= tol * scale,
        "{actual:e} differs from {expected:e} by {:e} (allowed {:e})",
        (actual - expected).abs(),
        tol * scale
    );
}

/// Central finite-difference estimate of ∂f/∂args[i].
pub fn central_diff<const N: usize>(f: &impl Fn([f64; N]) -> f64, at: [f64; N], i: usize) -> f64 {
    let h = 1e-6 * at[i].abs().max(1.0);
    let mut hi = at;
    let mut lo = at;
    hi[i] += h;
    lo[i] -= h;
    (f(hi) - f(lo)) / (hi[i] - lo[i])
}

/// Checks every partial of `grad` against central differences of `f` at `at`.
/// The tolerance scales with the size of the partial and of the value.
#[track_caller]
pub fn check_grad<const N: usize>(
    f: impl Fn([f64; N]) -> f64,
    grad: impl Fn([f64; N]) -> (f64, [f64; N]),
    at: [f64; N],
) {
    let (v, g) = grad(at);
    assert_eq!(
        v.to_bits(),
        f(at).to_bits(),
        "grad value differs from f at {at:?}"
    );
    for (i, &gi) in g.iter().enumerate() {
        let fd = central_diff(&f, at, i);
        let tol = 1e-6 * (1.0 + gi.abs() + 1e-3 * v.abs());
        assert!(
            (fd - gi).abs() <= tol,
            "d/darg{i} at {at:?}: analytic {gi:e}, finite difference {fd:e}"
        );
    }
}
