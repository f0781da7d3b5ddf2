//! The nalgebra aliases for small dense math (3-vectors, 3×3 matrices, rotations) and the
//! dense vectors and matrices of the core, in one place: the model reader and the
//! multibody core both speak them.

/// A 3-vector: positions, velocities, forces.
pub type Vec3 = nalgebra::Vector3<f64>;
/// A 3×3 matrix: rotations, inertia tensors.
pub type Mat3 = nalgebra::Matrix3<f64>;
/// A unit quaternion: a part's orientation.
pub type Quat = nalgebra::UnitQuaternion<f64>;
/// A dense vector (q, v, λ and their companions).
pub type DVec = nalgebra::DVector<f64>;
/// A dense matrix.
pub type DMat = nalgebra::DMatrix<f64>;
