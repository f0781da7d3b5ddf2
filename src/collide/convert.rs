//! The boundary between mbfx's nalgebra types and parry's glam types: every conversion
//! of this layer happens here, so nothing outside `src/collide` sees a parry type.

use super::Pose;
use crate::vocab::math::{Mat3, Vec3};
use parry3d_f64::glamx::{DMat3, DQuat, DVec3};
use parry3d_f64::math::Pose as Pose3;

/// An nalgebra vector as parry's.
pub fn to_parry(v: &Vec3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// A parry vector as nalgebra's.
pub fn from_parry(v: DVec3) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// A rotation matrix (columns: the frame's axes) as a unit quaternion. The matrix is
/// re-orthonormalised first: a pose integrated by the core drifts by round-off, and
/// glam's conversion assumes an exact rotation.
pub fn rotation_to_parry(rot: &Mat3) -> DQuat {
    // Bounded iterations: the unbounded form never ends on a matrix with a NaN.
    let r = nalgebra::Rotation3::from_matrix_eps(rot, 1e-15, 50, nalgebra::Rotation3::identity());
    let m = r.matrix();
    let cols = [0, 1, 2].map(|c| DVec3::new(m[(0, c)], m[(1, c)], m[(2, c)]));
    DQuat::from_mat3(&DMat3::from_cols(cols[0], cols[1], cols[2])).normalize()
}

/// A pose as parry's.
pub fn pose_to_parry(p: &Pose) -> Pose3 {
    Pose3::from_parts(to_parry(&p.r), rotation_to_parry(&p.rot))
}

/// `outer · inner`: the pose of a frame given in `outer`'s coordinates, globally.
pub fn compose(outer: &Pose, inner: &Pose) -> Pose {
    Pose {
        r: outer.r + outer.rot * inner.r,
        rot: outer.rot * inner.rot,
    }
}
