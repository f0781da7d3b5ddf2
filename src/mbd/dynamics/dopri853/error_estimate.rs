//! DOP853's error estimate of a step, as the published code combines its two embedded
//! estimators: the fifth-order e₅ = O(h⁶) damped by the third-order e₃ = O(h⁴),
//! err = h·|e₅|²/√(|e₅|² + 0.01·|e₃|²) = O(h⁸), over components each scaled by its own
//! tolerance. The Cartesian and the joint-coordinate forms both read it.

use super::tableau::{B, BHH, ER};

/// The weight of the third-order estimate in the combined one (the published value):
/// small enough that e₅ decides once it is resolved, large enough to damp it when e₅ is
/// accidentally small.
const E3_WEIGHT: f64 = 0.01;

/// DOP853's combined error estimate of a step `h` over `components` components, from
/// stage j's slope of component i, `slope(j, i)`, relative to the scales `scale(i)`;
/// and the component where it is largest.
pub(super) fn estimate(
    components: usize,
    scale: impl Fn(usize) -> f64,
    slope: impl Fn(usize, usize) -> f64,
    h: f64,
) -> (f64, usize) {
    let (mut e5, mut e3, mut worst) = (0.0f64, 0.0f64, 0);
    for i in 0..components {
        let scale = scale(i);
        let dot = |w: &[(usize, f64)]| w.iter().map(|&(j, x)| x * slope(j, i)).sum::<f64>();
        let (s5, s3) = (
            (dot(&ER) / scale).abs(),
            ((dot(&B) - dot(&BHH)) / scale).abs(),
        );
        if s5 > e5 {
            (e5, worst) = (s5, i);
        }
        e3 = e3.max(s3);
    }
    let denominator = (e5 * e5 + E3_WEIGHT * e3 * e3).sqrt();
    match denominator > 0.0 {
        true => (h.abs() * e5 * e5 / denominator, worst),
        false => (0.0, worst),
    }
}
