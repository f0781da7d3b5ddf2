//! Orientations as a dataset writes them (multibody spec §2.3, §2.4): REULER body-fixed
//! 3-1-3 angles, and the ZP/XP (ZG/XG) point pairs, turned into rotation matrices whose
//! columns are the child axes in parent coordinates.

use crate::vocab::math::{Mat3, Vec3};

/// `REULER = ψ, θ, φ`: R = Rz(ψ)·Rx(θ)·Rz(φ) (spec §2.4).
pub fn reuler(psi: f64, theta: f64, phi: f64) -> Mat3 {
    let (sp, cp) = psi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sf, cf) = phi.sin_cos();
    Mat3::new(
        cp * cf - sp * ct * sf,
        -cp * sf - sp * ct * cf,
        sp * st,
        sp * cf + cp * ct * sf,
        -sp * sf + cp * ct * cf,
        -cp * st,
        st * sf,
        st * cf,
        ct,
    )
}

/// The 3-1-3 angles (ψ, θ, φ) of a rotation, the inverse of [`reuler`] (spec §2.4):
/// θ = acos(R33), ψ = atan2(R13, −R23), φ = atan2(R31, R32). At θ = 0 or π only ψ ± φ is
/// defined; then φ = 0 and ψ carries the whole turn.
pub fn euler_313(r: &Mat3) -> [f64; 3] {
    let theta = r[(2, 2)].clamp(-1.0, 1.0).acos();
    if theta.sin().abs() < 1e-12 {
        return [r[(1, 0)].atan2(r[(0, 0)]), theta, 0.0];
    }
    [
        r[(0, 2)].atan2(-r[(1, 2)]),
        theta,
        r[(2, 0)].atan2(r[(2, 1)]),
    ]
}

/// Why a pair of points does not define axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointsError {
    /// The point that fixes the main axis lies on the origin.
    AtOrigin,
    /// The second point lies on the main axis, so it fixes no plane.
    OnAxis,
}

/// Axes from an origin `o`, a point `zp` on +z and a point `xp` in the +x/z half-plane
/// (spec §2.3): z = unit(zp − o), x = unit of the part of (xp − o) orthogonal to z,
/// y = z × x. With `usexp`, x points exactly at `xp` and `zp` only fixes the x/z plane.
pub fn axes_from_points(o: Vec3, zp: Vec3, xp: Vec3, usexp: bool) -> Result<Mat3, PointsError> {
    let (main, other) = if usexp {
        (xp - o, zp - o)
    } else {
        (zp - o, xp - o)
    };
    if main.norm() == 0.0 || !main.norm().is_finite() {
        return Err(PointsError::AtOrigin);
    }
    let a = main / main.norm();
    let rest = other - a * a.dot(&other);
    if rest.norm() <= 1e-9 * other.norm().max(main.norm()) {
        return Err(PointsError::OnAxis);
    }
    let b = rest / rest.norm();
    let (x, z) = if usexp { (a, b) } else { (b, a) };
    Ok(Mat3::from_columns(&[x, z.cross(&x), z]))
}
