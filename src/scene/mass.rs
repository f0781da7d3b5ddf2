//! A part's mass properties as the glyphs and placeholders need them: the CM in the
//! BCS and the principal moments and axes of the inertia about it. IP is given about
//! the IM origin in IM axes (CM's when IM is absent, spec §2.2); it is moved to the CM
//! by the parallel-axis theorem and turned into BCS axes by
//! [`crate::model::inertia::mass_properties`], the core's own.

use crate::model::elements::{Model, Part};
use crate::model::inertia::{mass_properties, MassProperties};
use crate::vocab::math::{Mat3, Vec3};

/// The principal frame and moments of a part's inertia about its CM.
#[derive(Clone, Debug, PartialEq)]
pub struct Principal {
    /// Mass (0 for a massless part).
    pub mass: f64,
    /// The CM in BCS coordinates.
    pub cm: Vec3,
    /// Principal axes as columns, BCS coordinates, a right-handed rotation.
    pub axes: Mat3,
    /// The principal moments about those axes.
    pub moments: [f64; 3],
}

/// The mass properties of `part` in its principal frame.
pub fn principal(model: &Model, part: &Part) -> Principal {
    let MassProperties {
        mass,
        cm,
        inertia: j,
    } = mass_properties(model, part);
    if !j.iter().all(|v| v.is_finite()) {
        return Principal {
            mass,
            cm,
            axes: Mat3::identity(),
            moments: [f64::NAN; 3],
        };
    }
    let eigen = nalgebra::SymmetricEigen::new(j);
    let mut axes = eigen.eigenvectors;
    if axes.determinant() < 0.0 {
        axes.set_column(2, &-axes.column(2));
    }
    Principal {
        mass,
        cm,
        axes,
        moments: [
            eigen.eigenvalues[0],
            eigen.eigenvalues[1],
            eigen.eigenvalues[2],
        ],
    }
}

impl Principal {
    /// The squared half-size along each principal axis of a uniform solid whose
    /// moments are these, `k·(I₂ + I₃ − I₁)/m` and its cyclic variants (`k` = 3/2 for a
    /// box's half sides, 5/2 for an ellipsoid's semi-axes); `None` for no mass, a
    /// non-finite value, or nothing positive.
    fn half_sizes(&self, k: f64) -> Option<[f64; 3]> {
        let [a, b, c] = self.moments;
        let m = self.mass;
        if !(m.is_finite() && m > 0.0) {
            return None;
        }
        let sq = [b + c - a, c + a - b, a + b - c].map(|s| (k * s / m).max(0.0).sqrt());
        let largest = sq.iter().copied().fold(0.0, f64::max);
        (largest > 0.0 && largest.is_finite()).then_some(sq)
    }

    /// The semi-axes of the uniform solid ellipsoid with this mass and these moments
    /// (I₁ = m(b² + c²)/5, so a² = 5(I₂ + I₃ − I₁)/(2m)).
    pub fn ellipsoid_semi_axes(&self) -> Option<[f64; 3]> {
        self.half_sizes(2.5)
    }

    /// The side lengths of the uniform solid box with this mass and these moments
    /// (I₁ = m(b² + c²)/12, so a² = 6(I₂ + I₃ − I₁)/m).
    pub fn box_sides(&self) -> Option<[f64; 3]> {
        self.half_sizes(1.5).map(|h| h.map(|x| 2.0 * x))
    }
}
