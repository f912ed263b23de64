//! Wrist range (§6.5.4): a pose whose hook rotation strays too far from the starting position's
//! gets quality −∞.

use crate::math::Rotation;

/// Allowed rotation relative to the starting position, in radians, as `[min, max]` about the
/// hand's z, x and y axes (the relative rotation decomposed as Rz·Ry·Rx).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WristRange {
    /// About z (along the fingers): the thesis's 145° one way and 70° the other.
    pub z: [f64; 2],
    /// About x (across the knuckles): ±45°.
    pub x: [f64; 2],
    /// About y (palm normal): ±30°.
    pub y: [f64; 2],
}

impl Default for WristRange {
    fn default() -> Self {
        let d = f64::to_radians;
        Self {
            z: [d(-145.0), d(70.0)],
            x: [d(-45.0), d(45.0)],
            y: [d(-30.0), d(30.0)],
        }
    }
}

impl WristRange {
    /// No limits at all.
    pub fn unlimited() -> Self {
        let all = [-std::f64::consts::PI, std::f64::consts::PI];
        Self {
            z: all,
            x: all,
            y: all,
        }
    }

    /// Is `rotation` within range of `start` (both hook rotations)?
    pub fn contains(&self, start: &Rotation, rotation: &Rotation) -> bool {
        let relative = start.inverse() * rotation;
        let (about_x, about_y, about_z) = relative.euler_angles();
        let inside = |v: f64, [lo, hi]: [f64; 2]| v >= lo - 1e-12 && v <= hi + 1e-12;
        inside(about_z, self.z) && inside(about_x, self.x) && inside(about_y, self.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn thesis_limits() {
        let range = WristRange::default();
        let start = Rotation::from_axis_angle(&Vec3::x_axis(), 0.3);
        let about =
            |axis: Vec3, deg: f64| start * Rotation::from_scaled_axis(axis * deg.to_radians());
        assert!(range.contains(&start, &about(Vec3::z(), -140.0)));
        assert!(!range.contains(&start, &about(Vec3::z(), -150.0)));
        assert!(range.contains(&start, &about(Vec3::z(), 65.0)));
        assert!(!range.contains(&start, &about(Vec3::z(), 75.0)));
        assert!(range.contains(&start, &about(Vec3::x(), 44.0)));
        assert!(!range.contains(&start, &about(Vec3::x(), -46.0)));
        assert!(!range.contains(&start, &about(Vec3::y(), 31.0)));
        assert!(WristRange::unlimited().contains(&start, &about(Vec3::y(), 170.0)));
    }
}
