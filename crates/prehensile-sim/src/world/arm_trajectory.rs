//! The prescribed arm: where the hand's root is at every time. Waypoints joined by minimum-jerk
//! segments (position and rotation start and stop with zero velocity and acceleration), plus an
//! optional sinusoidal shake; velocities and accelerations by central differences of the
//! analytic path, for the arm-motion compensation τARM.

use prehensile_core::math::{Transform, Vec3};

use crate::world::holding_wrench::FrameMotion;

/// One waypoint: the hand's root placement at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    /// Seconds.
    pub time: f64,
    /// The root's parent frame (what [`prehensile_core::hand::kinematics::forward_kinematics`] calls
    /// `root`).
    pub root: Transform,
}

/// A shake: the root moves by `amplitude · sin(2π f t)` along `direction` between two times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shake {
    /// Unit direction, world.
    pub direction: Vec3,
    /// Metres.
    pub amplitude: f64,
    /// Hz.
    pub frequency: f64,
    /// Seconds `[from, to]`; the shake fades in and out over its first and last period.
    pub during: [f64; 2],
}

/// Waypoints joined by minimum-jerk segments, with an optional shake.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmTrajectory {
    waypoints: Vec<Waypoint>,
    shake: Option<Shake>,
}

/// Minimum-jerk blend: 10u³ − 15u⁴ + 6u⁵.
fn min_jerk(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

impl ArmTrajectory {
    /// A trajectory through `waypoints` (sorted by time; at least one).
    pub fn new(mut waypoints: Vec<Waypoint>) -> Self {
        waypoints.sort_by(|a, b| a.time.total_cmp(&b.time));
        Self {
            waypoints,
            shake: None,
        }
    }

    /// The same trajectory with a shake added.
    pub fn with_shake(mut self, shake: Shake) -> Self {
        self.shake = Some(shake);
        self
    }

    /// The root placement at time `t` (held before the first and after the last waypoint).
    pub fn at(&self, t: f64) -> Transform {
        let w = &self.waypoints;
        let mut root = match w.iter().position(|p| p.time > t) {
            None => w[w.len() - 1].root,
            Some(0) => w[0].root,
            Some(k) => {
                let (a, b) = (&w[k - 1], &w[k]);
                let s = min_jerk((t - a.time) / (b.time - a.time));
                Transform::from_parts(
                    a.root
                        .translation
                        .vector
                        .lerp(&b.root.translation.vector, s)
                        .into(),
                    a.root.rotation.slerp(&b.root.rotation, s),
                )
            }
        };
        if let Some(shake) = &self.shake {
            let [from, to] = shake.during;
            if t > from && t < to {
                let period = 1.0 / shake.frequency;
                let fade = min_jerk((t - from) / period) * min_jerk((to - t) / period);
                let phase = 2.0 * std::f64::consts::PI * shake.frequency * (t - from);
                root.translation.vector += shake.direction * shake.amplitude * fade * phase.sin();
            }
        }
        root
    }

    /// The motion of the frame `root · local` at time `t`, world coordinates (central
    /// differences of the analytic path).
    pub fn frame_motion(&self, t: f64, local: &Transform) -> FrameMotion {
        let h = 1e-4;
        let frame = |t: f64| self.at(t) * local;
        let (before, now, after) = (frame(t - h), frame(t), frame(t + h));
        let omega =
            |a: &Transform, b: &Transform| (b.rotation * a.rotation.inverse()).scaled_axis() / h;
        let (w0, w1) = (omega(&before, &now), omega(&now, &after));
        FrameMotion {
            origin: now.translation.vector.into(),
            linear_acceleration: (after.translation.vector - 2.0 * now.translation.vector
                + before.translation.vector)
                / (h * h),
            angular_velocity: (w0 + w1) / 2.0,
            angular_acceleration: (w1 - w0) / h,
        }
    }

    /// The last waypoint's time.
    pub fn end(&self) -> f64 {
        self.waypoints.last().map_or(0.0, |w| w.time)
    }
}
