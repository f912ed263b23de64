//! Slerp between two fixed rotations, with the work that depends only on the two ends done once.
//!
//! Finger closing asks a movement for a bone's rotation at tens of thousands of fractions per
//! search, always between the same two rotations. nalgebra's `UnitQuaternion::slerp` works out
//! the angle between them (a dot product, an arc cosine and a square root) on every call; a
//! [`SlerpPath`] keeps that and gives the bit-identical rotation with only the two sines that
//! depend on the fraction. Written by hand because no crate offers a precomputed slerp that
//! matches nalgebra's to the last bit, which keeps every search's answer unchanged.

use crate::math::Rotation;
use nalgebra::{Quaternion, Vector4};

/// The shortest-arc slerp from one rotation to another (nalgebra's `slerp`, same results).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlerpPath {
    /// Quaternion coordinates of the start.
    from: Vector4<f64>,
    /// Quaternion coordinates of the end, negated when that makes the arc the shorter one.
    to: Vector4<f64>,
    /// Half the angle between the two rotations; `None` when they are the same quaternion.
    half_angle: Option<HalfAngle>,
}

/// The angle between the two quaternions (half the rotation angle) and its sine.
#[derive(Debug, Clone, Copy, PartialEq)]
struct HalfAngle {
    angle: f64,
    sine: f64,
}

impl SlerpPath {
    /// The path from `from` (at 0) to `to` (at 1).
    pub fn new(from: &Rotation, to: &Rotation) -> Self {
        // The steps of nalgebra 0.35's `UnitQuaternion::try_slerp` and `Unit::try_slerp`, in
        // their order, so that rounding is the same.
        let from_coords = from.coords;
        let to_coords = if from.coords.dot(&to.coords) < 0.0 {
            -to.coords
        } else {
            to.coords
        };
        let cosine = from_coords.dot(&to_coords);
        let half_angle = (cosine < 1.0).then(|| HalfAngle {
            angle: cosine.acos(),
            sine: (1.0 - cosine * cosine).sqrt(),
        });
        Self {
            from: from_coords,
            to: to_coords,
            half_angle,
        }
    }

    /// The rotation at fraction `t` of the way (0 the start, 1 the end).
    #[inline]
    pub fn at(&self, t: f64) -> Rotation {
        match self.half_angle {
            None => Rotation::new_unchecked(Quaternion::from(self.from)),
            Some(HalfAngle { angle, sine }) => {
                let ta = ((1.0 - t) * angle).sin() / sine;
                let tb = (t * angle).sin() / sine;
                Rotation::new_unchecked(Quaternion::from(self.from * ta + self.to * tb))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use proptest::prelude::*;

    fn rotation(axis: [f64; 3], angle: f64) -> Rotation {
        let axis = Vec3::from(axis);
        if axis.norm() < 1e-6 {
            return Rotation::identity();
        }
        Rotation::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
    }

    proptest! {
        /// Bit for bit what nalgebra's slerp gives, for any two rotations and any fraction,
        /// including rotations more than half a turn apart (the shorter arc) and equal ones.
        #[test]
        fn matches_nalgebra_slerp_bit_for_bit(
            a in prop::array::uniform3(-1.0f64..1.0), angle_a in -7.0f64..7.0,
            b in prop::array::uniform3(-1.0f64..1.0), angle_b in -7.0f64..7.0,
            t in -0.5f64..1.5, same in any::<bool>(),
        ) {
            let from = rotation(a, angle_a);
            let to = if same { from } else { rotation(b, angle_b) };
            let path = SlerpPath::new(&from, &to);
            for t in [t, 0.0, 1.0, 0.5] {
                let expected = from.slerp(&to, t);
                prop_assert_eq!(path.at(t).coords, expected.coords);
            }
        }
    }
}
