//! Example motions for fitting: joint-angle frames at a fixed rate, each with the hand–object
//! distance that drives the state machine, as JSON (`prehensile.motion/1`, see
//! docs/CONTROLLER_FORMAT.md); and a synthetic example built from three poses, so a controller
//! can be fitted without motion capture.

use serde::{Deserialize, Serialize};

use crate::controller::torque_laws::Gains;
use crate::error::DynamicsError;

/// Schema name of motion files.
pub const MOTION_SCHEMA: &str = "prehensile.motion/1";

/// An example motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motion {
    /// Always [`MOTION_SCHEMA`].
    pub schema: String,
    /// Degree-of-freedom names, in the hand's order.
    pub dof_names: Vec<String>,
    /// Seconds between frames.
    pub frame_time: f64,
    /// Joint angles per frame, radians.
    pub frames: Vec<Vec<f64>>,
    /// Hand–object distance per frame, metres.
    pub distances: Vec<f64>,
    /// Frame at which release is commanded (default: the first frame after the closest
    /// approach at which the distance grows).
    #[serde(default)]
    pub release_frame: Option<usize>,
}

impl Motion {
    /// Checks lengths, finiteness and sizes; says what is wrong and where.
    pub fn check(&self, dof_names: &[String]) -> Result<(), DynamicsError> {
        if self.schema != MOTION_SCHEMA {
            return Err(DynamicsError::Schema {
                found: self.schema.clone(),
                expected: MOTION_SCHEMA,
            });
        }
        if self.dof_names != dof_names {
            return Err(DynamicsError::DofNames {
                what: "motion",
                file: self.dof_names.clone(),
                expected: dof_names.to_vec(),
            });
        }
        if !(self.frame_time.is_finite() && self.frame_time > 0.0) {
            return Err(DynamicsError::FrameTime(self.frame_time));
        }
        if self.frames.len() < 3 || self.frames.len() > 1_000_000 {
            return Err(DynamicsError::FrameCount(self.frames.len()));
        }
        if self.distances.len() != self.frames.len() {
            return Err(DynamicsError::DistanceCount {
                distances: self.distances.len(),
                frames: self.frames.len(),
            });
        }
        for (frame, angles) in self.frames.iter().enumerate() {
            if angles.len() != dof_names.len() {
                return Err(DynamicsError::FrameLength {
                    frame,
                    got: angles.len(),
                    expected: dof_names.len(),
                });
            }
            if let Some(k) = angles.iter().position(|v| !v.is_finite()) {
                return Err(DynamicsError::FrameNotFinite {
                    frame,
                    dof: dof_names[k].clone(),
                });
            }
            let distance = self.distances[frame];
            if !(distance.is_finite() && distance >= 0.0) {
                return Err(DynamicsError::FrameDistance { frame, distance });
            }
        }
        if let Some(r) = self.release_frame {
            if r >= self.frames.len() {
                return Err(DynamicsError::ReleaseFrame(r));
            }
        }
        Ok(())
    }

    /// The frame at which release is commanded.
    pub fn release(&self) -> usize {
        self.release_frame.unwrap_or_else(|| {
            let closest = (0..self.distances.len())
                .min_by(|&a, &b| self.distances[a].total_cmp(&self.distances[b]))
                .unwrap_or(0);
            (closest + 1..self.distances.len())
                .find(|&t| self.distances[t] > self.distances[t - 1])
                .unwrap_or(self.distances.len())
        })
    }

    /// A synthetic grasp: the hand comes from 40 cm to the object over 1.2 s, relaxed until
    /// D2, opening until D1, kept open through CLOSING (§7) and closing once there, holds for
    /// 0.5 s, and leaves the way it came, opening and relaxing. Poses move with smooth steps;
    /// frames at 120 Hz.
    pub fn synthetic_grasp(
        dof_names: &[String],
        relaxed: &[f64],
        open: &[f64],
        closed: &[f64],
        gains: &Gains,
    ) -> Self {
        let rate = 120.0;
        let (travel, close, hold) = (1.2, 0.3, 0.5);
        let far = 0.4;
        let smooth = |u: f64| {
            let u = u.clamp(0.0, 1.0);
            u * u * (3.0 - 2.0 * u)
        };
        let mix = |a: &[f64], b: &[f64], s: f64| -> Vec<f64> {
            a.iter().zip(b).map(|(x, y)| x + (y - x) * s).collect()
        };
        let pose_at = |d: f64, closing: f64| -> Vec<f64> {
            if closing > 0.0 {
                mix(open, closed, smooth(closing))
            } else if d >= gains.d2 {
                relaxed.to_vec()
            } else if d >= gains.d1 {
                mix(
                    relaxed,
                    open,
                    smooth((gains.d2 - d) / (gains.d2 - gains.d1)),
                )
            } else {
                open.to_vec()
            }
        };
        let mut frames = Vec::new();
        let mut distances = Vec::new();
        let total = 2.0 * travel + close + hold;
        let count = (total * rate) as usize + 1;
        let mut release_frame = None;
        for k in 0..count {
            let t = k as f64 / rate;
            let (d, q) = if t < travel {
                let d = far * (1.0 - smooth(t / travel));
                (d, pose_at(d, 0.0))
            } else if t < travel + close + hold {
                let closing = ((t - travel) / close).min(1.0);
                (0.0, pose_at(0.0, closing.max(1e-9)))
            } else {
                release_frame.get_or_insert(k);
                let d = far * smooth((t - travel - close - hold) / travel);
                // Leaving: closed → open by D1, open → relaxed by D2.
                let q = if d < gains.d1 {
                    mix(closed, open, smooth(d / gains.d1))
                } else {
                    pose_at(d, 0.0)
                };
                (d, q)
            };
            frames.push(q);
            distances.push(d);
        }
        Self {
            schema: MOTION_SCHEMA.into(),
            dof_names: dof_names.to_vec(),
            frame_time: 1.0 / rate,
            frames,
            distances,
            release_frame,
        }
    }
}
