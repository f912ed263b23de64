//! Math aliases used throughout Prehensile: double precision, SI units, right-handed frames.

/// A 3-vector in metres (or a direction).
pub type Vec3 = nalgebra::Vector3<f64>;
/// A point in metres.
pub type Point3 = nalgebra::Point3<f64>;
/// A unit quaternion (rotation).
pub type Rotation = nalgebra::UnitQuaternion<f64>;
/// A rigid transform (rotation + translation).
pub type Transform = nalgebra::Isometry3<f64>;

/// True when every component is finite.
pub fn is_finite_vec(v: &Vec3) -> bool {
    v.iter().all(|c| c.is_finite())
}
