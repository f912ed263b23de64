//! The optimization steps (§5.6, Alg. 5 and 8): rotate the hook by ±angle about its own axes and
//! keep the best of the current pose and the rotated ones.

use crate::math::{Rotation, Vec3};

/// Which step the planner takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepKind {
    /// Alg. 5: the current pose and ±angle about x, y and z (seven poses).
    #[default]
    SevenPose,
    /// Alg. 8: the current pose and ±angle about one axis, alternating x, y, z (three poses).
    Unidirectional,
}

impl StepKind {
    /// Poses per step, P in the thesis's cost model (the current pose included).
    pub fn poses(self) -> usize {
        match self {
            StepKind::SevenPose => 7,
            StepKind::Unidirectional => 3,
        }
    }
}

/// The rotated candidates of one step (the current pose excluded): hook rotations `current ·
/// R(axis, ±angle)`, the rotation applied in the hook's own frame as Unity's `Rotate` does.
/// `axis` (0, 1, 2 = x, y, z) is used by the unidirectional step. Returns how many were written.
pub fn step_candidates(
    kind: StepKind,
    current: &Rotation,
    angle: f64,
    axis: usize,
    out: &mut [Rotation; 6],
) -> usize {
    let axes = [Vec3::x_axis(), Vec3::y_axis(), Vec3::z_axis()];
    let turn = |k: usize, sign: f64| current * Rotation::from_axis_angle(&axes[k], sign * angle);
    match kind {
        StepKind::SevenPose => {
            for k in 0..3 {
                out[2 * k] = turn(k, 1.0);
                out[2 * k + 1] = turn(k, -1.0);
            }
            6
        }
        StepKind::Unidirectional => {
            out[0] = turn(axis % 3, 1.0);
            out[1] = turn(axis % 3, -1.0);
            2
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_rotate_about_the_hooks_own_axes() {
        let current = Rotation::from_axis_angle(&Vec3::y_axis(), 0.5);
        let mut out = [Rotation::identity(); 6];
        assert_eq!(
            step_candidates(StepKind::SevenPose, &current, 0.2, 0, &mut out),
            6
        );
        for (k, pair) in out.chunks(2).enumerate() {
            for (c, sign) in pair.iter().zip([1.0, -1.0]) {
                let rel = current.inverse() * c;
                let expected = Rotation::from_axis_angle(
                    &[Vec3::x_axis(), Vec3::y_axis(), Vec3::z_axis()][k],
                    sign * 0.2,
                );
                assert!(rel.angle_to(&expected) < 1e-12);
            }
        }
        assert_eq!(
            step_candidates(StepKind::Unidirectional, &current, 0.2, 4, &mut out),
            2
        );
        let rel = current.inverse() * out[0];
        assert!((rel.scaled_axis() - Vec3::y() * 0.2).norm() < 1e-12);
        assert_eq!(StepKind::SevenPose.poses(), 7);
    }
}
