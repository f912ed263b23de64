//! A whole controller from one example motion (Pollard & Zordan §4–5.1), and its file format
//! (`prehensile.controller/1`, TOML; see docs/CONTROLLER_FORMAT.md).

use prehensile_core::HandModel;
use serde::{Deserialize, Serialize};

use crate::controller::setpoint::{Blend, PerSetpoint, Setpoint, SETPOINT_NAMES};
use crate::controller::torque_laws::{ControllerState, Gains, GraspController, Setpoints};
use crate::dynamics::inverse_dynamics::BaseMotion;
use crate::error::DynamicsError;
use crate::fitting::active_fitting::fit_active;
use crate::fitting::example_motion::Motion;
use crate::fitting::passive_fitting::fit_passive;

/// Schema name of controller files.
pub const CONTROLLER_SCHEMA: &str = "prehensile.controller/1";

/// Fits a controller to `motion`: neutral = mean pose; limits = the extremes of the motion
/// widened to the hand's own joint limits (our stand-in for the paper's range-of-motion
/// recordings); setpoints by least squares over every frame, with the blends the state machine
/// gives for the motion's distances (release at [`Motion::release`]). `open_while_closing`
/// says whether the example keeps the hand open through CLOSING (§7).
pub fn fit_controller(
    hand: &HandModel,
    motion: &Motion,
    gains: Gains,
    open_while_closing: bool,
    base: &BaseMotion,
) -> Result<GraspController, DynamicsError> {
    motion.check(hand.dof_names())?;
    let (neutral, mut limits) = fit_passive(&motion.frames)?;
    for (limit, [lo, hi]) in limits.iter_mut().zip(hand.dof_limits()) {
        *limit = [limit[0].min(lo), limit[1].max(hi)];
    }
    let n = hand.dof_count();
    let mut controller = GraspController::new(
        gains,
        Setpoints {
            positions: PerSetpoint::from_fn(|_| vec![0.0; n]),
            velocities: PerSetpoint::from_fn(|_| vec![0.0; n]),
            neutral,
            limits,
        },
    );
    controller.open_while_closing = open_while_closing;
    let release = motion.release();
    let blends: Vec<Blend> = motion
        .distances
        .iter()
        .enumerate()
        .scan(ControllerState::default(), |run, (t, &d)| {
            Some(controller.advance(run, d, t >= release))
        })
        .collect();
    fit_active(
        hand,
        &motion.frames,
        motion.frame_time,
        &blends,
        base,
        &gains,
        &mut controller.setpoints,
    )?;
    Ok(controller)
}

/// The gains of a controller file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GainsRecord {
    /// k_S, 1/s².
    pub k_s: f64,
    /// k_D, 1/s.
    pub k_d: f64,
    /// k_JL, 1/s².
    pub k_jl: f64,
    /// D0, D1, D2, metres.
    pub distances: [f64; 3],
}

/// One setpoint of a controller file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetpointRecord {
    /// One of [`SETPOINT_NAMES`].
    pub name: String,
    /// θ_i, radians per degree of freedom.
    pub positions: Vec<f64>,
    /// θ̇_i, rad/s per degree of freedom.
    pub velocities: Vec<f64>,
}

/// A controller file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerFile {
    /// Always [`CONTROLLER_SCHEMA`].
    pub schema: String,
    /// The hand it was fitted for.
    pub hand: String,
    /// Degree-of-freedom names, in order.
    pub dof_names: Vec<String>,
    /// Gains and distances.
    pub gains: GainsRecord,
    /// Grip strength α.
    pub alpha: f64,
    /// Keep open through CLOSING.
    pub open_while_closing: bool,
    /// θ_NEUTRAL.
    pub neutral: Vec<f64>,
    /// θ_LIMIT, `[min, max]` per degree of freedom.
    pub limits: Vec<[f64; 2]>,
    /// The six setpoints.
    pub setpoints: Vec<SetpointRecord>,
}

impl ControllerFile {
    /// The file of a controller fitted for `hand`.
    pub fn new(hand: &HandModel, c: &GraspController) -> Self {
        let g = &c.gains;
        Self {
            schema: CONTROLLER_SCHEMA.into(),
            hand: hand.name().into(),
            dof_names: hand.dof_names().to_vec(),
            gains: GainsRecord {
                k_s: g.k_s,
                k_d: g.k_d,
                k_jl: g.k_jl,
                distances: [g.d0, g.d1, g.d2],
            },
            alpha: c.alpha,
            open_while_closing: c.open_while_closing,
            neutral: c.setpoints.neutral.clone(),
            limits: c.setpoints.limits.clone(),
            setpoints: Setpoint::ALL
                .iter()
                .map(|&s| SetpointRecord {
                    name: s.name().into(),
                    positions: c.setpoints.positions[s].clone(),
                    velocities: c.setpoints.velocities[s].clone(),
                })
                .collect(),
        }
    }

    /// Reads a file's text; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, DynamicsError> {
        toml::from_str(text).map_err(|e| DynamicsError::Syntax {
            source_name: source.to_string(),
            error: Box::new(e),
        })
    }

    /// The file's text.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a controller file always serializes")
    }

    /// The controller for `hand`, after checking names, lengths, order and finiteness.
    pub fn controller(&self, hand: &HandModel) -> Result<GraspController, DynamicsError> {
        self.check(hand)?;
        let g = &self.gains;
        let [d0, d1, d2] = g.distances;
        let mut c = GraspController::new(
            Gains {
                k_s: g.k_s,
                k_d: g.k_d,
                k_jl: g.k_jl,
                d0,
                d1,
                d2,
            },
            Setpoints {
                positions: PerSetpoint::from_fn(|s| self.setpoints[s.index()].positions.clone()),
                velocities: PerSetpoint::from_fn(|s| self.setpoints[s.index()].velocities.clone()),
                neutral: self.neutral.clone(),
                limits: self.limits.clone(),
            },
        );
        c.alpha = self.alpha;
        c.open_while_closing = self.open_while_closing;
        Ok(c)
    }

    /// Checks the file against `hand`: schema, names, lengths, order and finiteness.
    fn check(&self, hand: &HandModel) -> Result<(), DynamicsError> {
        if self.schema != CONTROLLER_SCHEMA {
            return Err(DynamicsError::Schema {
                found: self.schema.clone(),
                expected: CONTROLLER_SCHEMA,
            });
        }
        if self.dof_names != hand.dof_names() {
            return Err(DynamicsError::DofNames {
                what: "controller",
                file: self.dof_names.clone(),
                expected: hand.dof_names().to_vec(),
            });
        }
        let n = hand.dof_count();
        let names: Vec<&str> = self.setpoints.iter().map(|s| s.name.as_str()).collect();
        if names != SETPOINT_NAMES {
            return Err(DynamicsError::Setpoints {
                found: names.iter().map(|s| s.to_string()).collect(),
                expected: SETPOINT_NAMES,
            });
        }
        let g = &self.gains;
        let scalars = [g.k_s, g.k_d, g.k_jl, self.alpha];
        if scalars.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(DynamicsError::Gains);
        }
        let [d0, d1, d2] = g.distances;
        if !(d0.is_finite() && d2.is_finite() && d0 <= d1 && d1 < d2) {
            return Err(DynamicsError::Distances(g.distances));
        }
        let vectors = self
            .setpoints
            .iter()
            .flat_map(|s| [("positions", &s.positions), ("velocities", &s.velocities)])
            .chain([("neutral", &self.neutral)]);
        for (what, v) in vectors {
            if v.len() != n || v.iter().any(|x| !x.is_finite()) {
                return Err(DynamicsError::Vector { what, expected: n });
            }
        }
        if self.limits.len() != n
            || self
                .limits
                .iter()
                .any(|[a, b]| a.partial_cmp(b).is_none_or(|o| o.is_gt()))
        {
            return Err(DynamicsError::Limits { expected: n });
        }
        Ok(())
    }
}
