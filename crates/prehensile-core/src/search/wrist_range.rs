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

    /// The range of the other hand: a mirror image across the hand frame's x (the hands' mirror,
    /// `HandDescription::mirrored`) turns the rotations about z and y the other way and keeps
    /// those about x, so a right hand's 145° one way about z is a left hand's 145° the other.
    pub fn mirrored(&self) -> Self {
        let negated = |[lo, hi]: [f64; 2]| [-hi, -lo];
        Self {
            z: negated(self.z),
            x: self.x,
            y: negated(self.y),
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

    #[test]
    fn the_mirrored_range_holds_the_mirror_image_of_every_rotation_the_range_holds() {
        // Mirroring across x conjugates a rotation by diag(−1, 1, 1).
        let mirror = |r: &Rotation| {
            let m = nalgebra::Matrix3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0));
            Rotation::from_matrix(&(m * r.to_rotation_matrix().matrix() * m))
        };
        let (range, mirrored) = (WristRange::default(), WristRange::default().mirrored());
        let start = Rotation::from_axis_angle(&Vec3::y_axis(), 0.4);
        let mut rng = crate::random::SplitMix64::new(7);
        let (mut inside, mut asymmetric) = (0, 0);
        for _ in 0..2000 {
            let axis = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            );
            let turn = start * Rotation::from_scaled_axis(axis * 2.0);
            let held = range.contains(&start, &turn);
            assert_eq!(held, mirrored.contains(&mirror(&start), &mirror(&turn)));
            inside += usize::from(held);
            asymmetric += usize::from(held != range.contains(&mirror(&start), &mirror(&turn)));
        }
        // Both outcomes occur, and the unmirrored range would judge some mirror images wrongly.
        assert!(inside > 100 && inside < 1900, "{inside}");
        assert!(asymmetric > 50, "{asymmetric}");
    }
}
