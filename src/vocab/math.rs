//! The nalgebra aliases for small dense math (3-vectors, 3×3 matrices, rotations) and the
//! dense vectors and matrices of the core, in one place: the model reader and the
//! multibody core both speak them.

pub type Vec3 = nalgebra::Vector3<f64>;
pub type Mat3 = nalgebra::Matrix3<f64>;
pub type Quat = nalgebra::UnitQuaternion<f64>;
pub type DVec = nalgebra::DVector<f64>;
pub type DMat = nalgebra::DMatrix<f64>;
