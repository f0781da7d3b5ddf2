//! The geometric stiffness ∂(Φ_qᵀλ)/∂q of the point-coincidence rows, for the Newton
//! matrix.
//!
//! The Newton matrix of the Newmark family is M + β·h²·∂(Φ_qᵀλ − Q)/∂q + …; leaving the
//! constraint term out costs Newton its quadratic convergence. At h = 1e-3 on a pinned
//! chain the term is a tenth of a link's rotational inertia, and each iteration then only
//! gains a factor of fifty. Kept in full it couples the two parts of every joint and
//! breaks the block-diagonal effective mass the Schur-complement solver relies on.
//!
//! Adams writes a point coincidence as d·e_J = 0 along J's turning axes, which couples
//! J's rotation with everything. When every translational row of a marker pair is kept
//! (3 in 3D, the 2 in-plane ones in 2D), the rows only say d = 0, in any basis: the
//! dynamics then uses J's axes frozen at the start, d·e = 0 with e constant
//! ([`super::resolved::freeze_point_rows`]). Each row is a sum of one function of part I
//! and one of part J, so its Hessian falls on each part alone: for a marker offset
//! u = R·s and the rotation increment δθ (R → exp(\[δθ\]×)·R),
//! ∂²(u·e)/∂δθ² = ½(u·eᵀ + e·uᵀ) − (u·e)·I. The multipliers change basis with the
//! rows, and the reactions (Φ_qᵀλ over an element's rows) do not.

use super::setup::Dynamics;
use crate::mbd::constraints::Primitive;
use crate::mbd::system::{Dimension, PartHandle};
use crate::vocab::math::{DVec, Mat3, Vec3};

/// ∂²(u·e)/∂δθ² for u = R·s turned by δθ.
fn offset_hessian(u: &Vec3, e: &Vec3) -> Mat3 {
    (u * e.transpose() + e * u.transpose()) * 0.5 - Mat3::identity() * u.dot(e)
}

impl Dynamics {
    /// ∂(Φ_qᵀλ)/∂q of the `Fixed` rows at the current state, into `self.geo` as
    /// (row, column, value) entries of each part's rotational block.
    pub(super) fn geometric_stiffness(&mut self, lambda: &DVec) {
        self.geo.clear();
        let sys = &self.sys;
        let blocks = &mut self.geo_blocks;
        blocks.clear();
        blocks.resize(sys.moving_parts(), Mat3::zeros());
        let planar_normal = (sys.dim == Dimension::Two).then(|| sys.plane_axes().2);
        for (r, prim) in self.prims.iter().enumerate() {
            let Some((Primitive::Fixed(row), _)) = prim else {
                continue;
            };
            let mut add = |part: PartHandle, s: &Vec3, sign: f64| {
                let p = sys.part(part);
                if let Some(i) = p.index {
                    let (u, w) = (p.rotation() * s, sign * lambda[r]);
                    match planar_normal {
                        // Only the entry about the normal is read: u·e is in-plane.
                        Some(n) => blocks[i][(n, n)] += w * (u[n] * row.axis[n] - u.dot(&row.axis)),
                        None => blocks[i] += offset_hessian(&u, &row.axis) * w,
                    }
                }
            };
            add(row.pi, &row.si, 1.0);
            add(row.pj, &row.sj, -1.0);
        }
        let bs = sys.dim.cols();
        for (i, h) in blocks.iter().enumerate() {
            if *h == Mat3::zeros() {
                continue;
            }
            match planar_normal {
                Some(n) => self.geo.push((i * bs + 2, i * bs + 2, h[(n, n)])),
                None => {
                    for r in 0..3 {
                        for c in 0..3 {
                            self.geo.push((i * bs + 3 + r, i * bs + 3 + c, h[(r, c)]));
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::offset_hessian;
    use crate::vocab::math::{Mat3, Vec3};

    /// The Hessian against second differences of (exp([δθ]×)·u)·e.
    #[test]
    fn offset_hessian_matches_second_differences() {
        let (u, e) = (Vec3::new(0.3, -0.2, 0.5), Vec3::new(0.1, 0.7, -0.4));
        let f = |t: Vec3| (nalgebra::Rotation3::new(t) * u).dot(&e);
        let h = 1e-4;
        let mut fd = Mat3::zeros();
        for r in 0..3 {
            for c in 0..3 {
                let (dr, dc) = (Vec3::ith(r, h), Vec3::ith(c, h));
                fd[(r, c)] = (f(dr + dc) - f(dr - dc) - f(dc - dr) + f(-dr - dc)) / (4.0 * h * h);
            }
        }
        let exact = offset_hessian(&u, &e);
        assert!((fd - exact).amax() < 1e-6, "{fd} vs {exact}");
    }
}
