//! The nalgebra aliases every module of the core uses, in one place.

pub type Vec3 = nalgebra::Vector3<f64>;
pub type Mat3 = nalgebra::Matrix3<f64>;
pub type Quat = nalgebra::UnitQuaternion<f64>;
pub type DVec = nalgebra::DVector<f64>;
pub type DMat = nalgebra::DMatrix<f64>;
