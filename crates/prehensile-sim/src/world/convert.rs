//! Conversions between Prehensile's nalgebra types and rapier's glam types (rapier 0.36 moved its
//! math to glam; the rest of the workspace stays on nalgebra).

use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use rapier3d_f64::prelude::{Pose, Rotation as Quat, Vector};

/// nalgebra vector → glam.
pub(crate) fn vector(v: &Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// nalgebra point → glam vector.
pub(crate) fn point(p: &Point3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// glam vector → nalgebra.
pub(crate) fn vec3(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// nalgebra rotation → glam.
pub(crate) fn quat(r: &Rotation) -> Quat {
    let q = r.quaternion();
    Quat::from_xyzw(q.i, q.j, q.k, q.w)
}

/// glam rotation → nalgebra.
pub(crate) fn rotation(q: &Quat) -> Rotation {
    Rotation::from_quaternion(nalgebra::Quaternion::new(q.w, q.x, q.y, q.z))
}

/// nalgebra transform → glam pose.
pub(crate) fn pose(t: &Transform) -> Pose {
    Pose::from_parts(vector(&t.translation.vector), quat(&t.rotation))
}

/// glam pose → nalgebra transform.
pub(crate) fn transform(p: &Pose) -> Transform {
    Transform::from_parts(vec3(p.translation).into(), rotation(&p.rotation))
}
