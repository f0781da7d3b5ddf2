//! The chart the integrators move 3D rotations in: a part's pose is the step's start
//! turned by a global rotation vector θ, R = exp(\[θ\]×)·R₀, whose rate is
//! θ̇ = J_l(θ)⁻¹·ω ([`rotation_vector_rate`], SO(3)'s inverse left Jacobian) and back
//! ([`angular_velocity`]). DOP853's stages, the BDF's predictor and the Newmark family's
//! Hermite extension all read it.

use crate::vocab::math::{Mat3, Vec3};

/// |θ|² below which the inverse Jacobian's coefficient is the series: the closed form
/// loses digits to cancellation there (two and a half at the bound), and the series'
/// first omitted term is below rounding.
const SERIES_BELOW: f64 = 0.04;

/// The coefficient c(φ) = (1 − (φ/2)·cot(φ/2))/φ² of \[θ\]×² in SO(3)'s inverse left
/// Jacobian J_l(θ)⁻¹ = I − ½\[θ\]× + c(φ)·\[θ\]×², φ = |θ|, from `phi2` = φ². From the
/// Bernoulli series of x·cot x, c = Σ |B₂ₖ|·φ²ᵏ⁻²/(2k)! = 1/12 + φ²/720 + φ⁴/30240 + …
fn inverse_jacobian_coefficient(phi2: f64) -> f64 {
    if phi2 < SERIES_BELOW {
        // Through φ⁸; the next term, 691·φ¹⁰/(2730·12!), is below 6e-17 here.
        1.0 / 12.0
            + phi2
                * (1.0 / 720.0
                    + phi2 * (1.0 / 30240.0 + phi2 * (1.0 / 1209600.0 + phi2 / 47900160.0)))
    } else {
        let half = 0.5 * phi2.sqrt();
        (1.0 - half / half.tan()) / phi2
    }
}

/// θ̇ = J_l(θ)⁻¹·ω: the rate of the rotation vector θ of R = exp(\[θ\]×)·R₀ that turns with
/// the global angular velocity ω (Ṙ·Rᵀ = \[ω\]×).
pub(super) fn rotation_vector_rate(theta: Vec3, w: Vec3) -> Vec3 {
    let tw = theta.cross(&w);
    w - 0.5 * tw + inverse_jacobian_coefficient(theta.norm_squared()) * theta.cross(&tw)
}

/// The global angular velocity ω whose chart rate at θ is `rate`: the inverse of
/// [`rotation_vector_rate`], which is linear in ω (J_l(θ)⁻¹·ω), solved as a 3×3 system.
pub(super) fn angular_velocity(theta: Vec3, rate: Vec3) -> Vec3 {
    let columns = [Vec3::x(), Vec3::y(), Vec3::z()].map(|e| rotation_vector_rate(theta, e));
    let m = Mat3::from_columns(&columns);
    // (Regular wherever the chart is: |θ| < 2π.)
    m.try_inverse().map_or(rate, |inv| inv * rate)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vocab::math::Quat;

    #[test]
    fn series_and_closed_form_of_the_coefficient_meet() {
        let phi2 = SERIES_BELOW;
        let half = 0.5 * phi2.sqrt();
        let closed = (1.0 - half / half.tan()) / phi2;
        let series = inverse_jacobian_coefficient(phi2 * (1.0 - 1e-15));
        assert!((closed - series).abs() < 1e-14, "{closed} vs {series}");
        assert_eq!(inverse_jacobian_coefficient(0.0), 1.0 / 12.0);
    }

    /// The global angular velocity of R(t) = exp([θ(t)]×)·R₀ by central differences.
    fn omega_by_differences(theta: Vec3, rate: Vec3) -> Vec3 {
        let r = |t: f64| -> Mat3 {
            Quat::from_scaled_axis(theta + t * rate)
                .to_rotation_matrix()
                .into_inner()
        };
        let dt = 1e-5;
        let dr = (r(dt) - r(-dt)) / (2.0 * dt);
        let wx = dr * r(0.0).transpose();
        Vec3::new(
            wx[(2, 1)] - wx[(1, 2)],
            wx[(0, 2)] - wx[(2, 0)],
            wx[(1, 0)] - wx[(0, 1)],
        ) / 2.0
    }

    #[test]
    fn the_rate_turns_the_chart_with_the_angular_velocity() {
        // θ̇ from the formula, fed back through R(t) = exp([θ(t)]×)·R₀, must give ω back:
        // small angles (the series), large ones (the closed form), near half a turn.
        let w = Vec3::new(0.3, -1.2, 0.7);
        for theta in [
            Vec3::new(1e-9, 0.0, 0.0),
            Vec3::new(0.05, -0.02, 0.03),
            Vec3::new(0.2, 0.3, -0.1),
            Vec3::new(0.9, -0.4, 1.1),
            Vec3::new(-2.0, 1.5, 1.2),
        ] {
            let rate = rotation_vector_rate(theta, w);
            let back = omega_by_differences(theta, rate);
            assert!((back - w).norm() < 1e-8, "θ = {theta:?}: ω back {back:?}");
        }
    }

    #[test]
    fn angular_velocity_inverts_the_chart_rate() {
        let w = Vec3::new(0.4, -1.1, 2.0);
        for theta in [
            Vec3::zeros(),
            Vec3::new(0.3, 0.2, -0.5),
            Vec3::new(-1.5, 1.0, 0.8),
        ] {
            let back = angular_velocity(theta, rotation_vector_rate(theta, w));
            assert!((back - w).norm() < 1e-13, "{theta:?}: {back:?}");
        }
    }
}
