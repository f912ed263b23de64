//! The Pollard & Zordan grasp controller's torque laws and state machine, engine-agnostic:
//! passive torque toward a neutral pose with joint-limit springs (Eq. 3), active torque toward
//! setpoints blended by state and distance (Eq. 5–12, Fig. 3), grip strength α (Eq. 15–16), plus
//! gravity and arm-motion compensation by inverse dynamics (Eq. 2).
//!
//! `I` of Eq. 3 and 5 is [`OutboardInertia`]: for a hinge the outboard inertia about its axis,
//! for a ball joint the whole 3×3 block, as in the paper (the bracketed terms, per unit
//! inertia, are computed per degree of freedom and then multiplied by `I`).

use prehensile_core::math::Vec3;

use crate::controller::setpoint::{Blend, PerSetpoint, Setpoint};
use crate::dynamics::body_inertia::OutboardInertia;
use crate::dynamics::inverse_dynamics::{bias_torques, BaseMotion};
use crate::dynamics::model::{DynamicsData, DynamicsModel};
use crate::dynamics::outboard_inertia::outboard_inertia_into;
use crate::error::DynamicsError;

/// Gains and distances (Pollard & Zordan, Table 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    /// Stiffness toward setpoints, 1/s².
    pub k_s: f64,
    /// Damping, 1/s.
    pub k_d: f64,
    /// Joint-limit stiffness, 1/s² (acts only outside the range).
    pub k_jl: f64,
    /// Distance at which gripping starts, m.
    pub d0: f64,
    /// Distance at which closing starts, m.
    pub d1: f64,
    /// Distance at which opening starts, m.
    pub d2: f64,
}

impl Gains {
    /// Table 1, grasps: k_S 200, k_D 50, k_JL 5000, D0 0, D1 5 cm, D2 30 cm.
    pub fn grasp() -> Self {
        Self {
            k_s: 200.0,
            k_d: 50.0,
            k_jl: 5000.0,
            d0: 0.0,
            d1: 0.05,
            d2: 0.3,
        }
    }

    /// Table 1, handshake: k_S 300, k_D 60, k_JL 5000, D1 9 cm, D2 20 cm.
    pub fn handshake() -> Self {
        Self {
            k_s: 300.0,
            k_d: 60.0,
            k_jl: 5000.0,
            d0: 0.0,
            d1: 0.09,
            d2: 0.2,
        }
    }
}

impl Default for Gains {
    fn default() -> Self {
        Self::grasp()
    }
}

/// States of the grasp state machine (Fig. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GraspState {
    /// Before a grasp: setpoint 0.
    #[default]
    Neutral,
    /// Opening as the object comes within D2.
    Opening,
    /// Closing as it comes within D1.
    Closing,
    /// Holding at D0.
    Gripping,
    /// Letting go (on command).
    Releasing,
    /// Opening again as the hand moves away past D0.
    OpeningAgain,
    /// Relaxing past D1.
    Relaxing,
    /// Back at neutral past D2: setpoint 5.
    NeutralAgain,
}

impl GraspState {
    /// The next state for a hand–object distance, and whether release was asked.
    pub fn next(self, distance: f64, release: bool, g: &Gains) -> Self {
        use GraspState::*;
        match self {
            Neutral | NeutralAgain if distance < g.d2 && !release => Opening,
            Opening if distance < g.d1 => Closing,
            Closing if distance <= g.d0 => Gripping,
            Gripping if release => Releasing,
            Releasing if distance > g.d0 => OpeningAgain,
            OpeningAgain if distance > g.d1 => Relaxing,
            Relaxing if distance > g.d2 => NeutralAgain,
            s => s,
        }
    }

    /// Blend weights B over the six setpoints (Fig. 3, Eq. 10–12, 15–16).
    pub fn blend(self, distance: f64, alpha: f64, g: &Gains) -> Blend {
        let ramp = |from: f64, to: f64| ((from - distance) / (from - to)).clamp(0.0, 1.0);
        use Setpoint::*;
        let mut b = Blend::default();
        match self {
            GraspState::Neutral => b[Neutral] = 1.0,
            GraspState::Opening => {
                b[Open] = ramp(g.d2, g.d1);
                b[Neutral] = 1.0 - b[Open];
            }
            GraspState::Closing => {
                b[Grip] = ramp(g.d1, g.d0);
                b[Open] = 1.0 - b[Grip];
            }
            GraspState::Gripping => {
                b[Grip] = 1.0 + alpha;
                b[Open] = -alpha;
            }
            GraspState::Releasing => b[Release] = 1.0,
            GraspState::OpeningAgain => {
                b[Release] = ramp(g.d1, g.d0);
                b[OpenAgain] = 1.0 - b[Release];
            }
            GraspState::Relaxing => {
                b[OpenAgain] = ramp(g.d2, g.d1);
                b[Relax] = 1.0 - b[OpenAgain];
            }
            GraspState::NeutralAgain => b[Relax] = 1.0,
        }
        b
    }
}

/// Six setpoints (positions and velocities, one value per degree of freedom each) and the
/// passive controller's neutral pose and joint limits.
#[derive(Debug, Clone, PartialEq)]
pub struct Setpoints {
    /// θ_0 … θ_5.
    pub positions: PerSetpoint<Vec<f64>>,
    /// θ̇_0 … θ̇_5.
    pub velocities: PerSetpoint<Vec<f64>>,
    /// θ_NEUTRAL.
    pub neutral: Vec<f64>,
    /// θ_LIMIT per degree of freedom, `[min, max]`.
    pub limits: Vec<[f64; 2]>,
}

/// The passive law's bracketed term of degree of freedom `k`, per unit inertia.
fn passive_unit(k: usize, q: &[f64], qd: &[f64], s: &Setpoints, g: &Gains) -> f64 {
    let [lo, hi] = s.limits[k];
    let outside = if q[k] < lo {
        lo - q[k]
    } else if q[k] > hi {
        hi - q[k]
    } else {
        0.0
    };
    g.k_s * (s.neutral[k] - q[k]) + g.k_jl * outside - g.k_d * qd[k]
}

/// The active law's bracketed term of degree of freedom `k`, per unit inertia.
fn active_unit(k: usize, q: &[f64], qd: &[f64], s: &Setpoints, blend: &Blend, g: &Gains) -> f64 {
    let target = blend.mix(&s.positions, k);
    let rate = blend.mix(&s.velocities, k);
    g.k_s * (target - q[k]) + g.k_d * (rate - qd[k])
}

/// Passive torque, Eq. 3: τP = I (k_S (θ_N − θ) + k_JL (θ_L − θ) − k_D θ̇), the limit term only
/// outside the range, written into `out`.
pub fn passive_torque(
    inertia: &OutboardInertia,
    q: &[f64],
    qd: &[f64],
    s: &Setpoints,
    g: &Gains,
    out: &mut [f64],
) {
    for (k, out) in out.iter_mut().enumerate() {
        *out = passive_unit(k, q, qd, s, g);
    }
    inertia.apply(out);
}

/// Active torque, Eq. 5–7: τA = I (k_S (B·P_S − θ) + k_D (B·P_D − θ̇)), written into `out`.
pub fn active_torque(
    inertia: &OutboardInertia,
    q: &[f64],
    qd: &[f64],
    s: &Setpoints,
    blend: &Blend,
    g: &Gains,
    out: &mut [f64],
) {
    for (k, out) in out.iter_mut().enumerate() {
        *out = active_unit(k, q, qd, s, blend, g);
    }
    inertia.apply(out);
}

/// One degree of freedom's control law in implicit form: τ = stiffness·(target − θ) +
/// damping·(target_velocity − θ̇). A physics engine can integrate it implicitly (as a joint
/// motor), which stays stable at time steps where the explicit torque would not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointSpring {
    /// N·m/rad.
    pub stiffness: f64,
    /// N·m·s/rad.
    pub damping: f64,
    /// rad.
    pub target: f64,
    /// rad/s.
    pub target_velocity: f64,
}

impl JointSpring {
    /// No stiffness and no damping: the joint is left free (a buffer's value before the
    /// controller's first step).
    pub const SLACK: Self = Self {
        stiffness: 0.0,
        damping: 0.0,
        target: 0.0,
        target_velocity: 0.0,
    };

    /// The torque at `q`, `qd`.
    pub fn torque(&self, q: f64, qd: f64) -> f64 {
        self.stiffness * (self.target - q) + self.damping * (self.target_velocity - qd)
    }
}

/// τP + τA (Eq. 3 and 5) of every degree of freedom as one spring each: both laws are linear in θ
/// and θ̇, so their sum is a single spring with the summed stiffness and the stiffness-weighted
/// target. With `active` false only τP remains (the drop test). The springs carry the diagonal of
/// `I`; a ball joint's cross terms are [`ball_joint_coupling`].
pub fn joint_springs(
    inertia: &OutboardInertia,
    q: &[f64],
    s: &Setpoints,
    blend: &Blend,
    g: &Gains,
    active: bool,
    out: &mut [JointSpring],
) {
    for (k, out) in out.iter_mut().enumerate() {
        let [lo, hi] = s.limits[k];
        let limit = if q[k] < lo {
            Some(lo)
        } else if q[k] > hi {
            Some(hi)
        } else {
            None
        };
        let mut stiffness = g.k_s;
        let mut pull = g.k_s * s.neutral[k];
        let mut damping = g.k_d;
        let mut rate = 0.0;
        if let Some(l) = limit {
            stiffness += g.k_jl;
            pull += g.k_jl * l;
        }
        if active {
            stiffness += g.k_s;
            pull += g.k_s * blend.mix(&s.positions, k);
            damping += g.k_d;
            rate += g.k_d * blend.mix(&s.velocities, k);
        }
        *out = JointSpring {
            stiffness: inertia.diagonal[k] * stiffness,
            damping: inertia.diagonal[k] * damping,
            target: pull / stiffness,
            target_velocity: if damping > 0.0 { rate / damping } else { 0.0 },
        };
    }
}

/// The torques the springs of [`joint_springs`] leave out at `q`, `qd`: the cross terms of every
/// ball joint's 3×3 inertia block (zero for hinges), so springs plus coupling give the paper's
/// `I·(…)` with the whole block.
pub fn ball_joint_coupling(
    inertia: &OutboardInertia,
    springs: &[JointSpring],
    q: &[f64],
    qd: &[f64],
    out: &mut [f64],
) {
    out.fill(0.0);
    for (first, block) in &inertia.balls {
        let unit = Vec3::from_fn(|k, _| {
            let (d, i) = (first + k, inertia.diagonal[first + k]);
            if i > 0.0 {
                springs[d].torque(q[d], qd[d]) / i
            } else {
                0.0
            }
        });
        let whole = block * unit;
        for k in 0..3 {
            out[first + k] = whole[k] - inertia.diagonal[first + k] * unit[k];
        }
    }
}

/// The controller's model: gains, setpoints, grip strength and switches, as fitted or read from
/// a file. What changes as it runs is a [`ControllerState`], kept apart (as MuJoCo keeps mjData
/// apart from mjModel): one controller can drive several hands, each with its own state.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspController {
    /// Gains and distances.
    pub gains: Gains,
    /// Setpoints, neutral pose and limits.
    pub setpoints: Setpoints,
    /// Grip strength α (the paper uses 0 to 0.5).
    pub alpha: f64,
    /// Whether τA acts (false: the passive hand of the drop test).
    pub active: bool,
    /// Keep the hand open (B\[1\] = 1) through CLOSING, as the paper's grasps did (§7) "to keep
    /// the hand from contacting the object too quickly"; it closes on GRIPPING.
    pub open_while_closing: bool,
}

/// What a running controller changes: the state machine's state and a setpoint chosen by hand.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ControllerState {
    /// Current state (NEUTRAL at first).
    pub state: GraspState,
    /// A setpoint chosen by hand (Fig. 7's interactive open/close), overriding the state
    /// machine's blend while set; the grip setpoint is extrapolated by α as in GRIPPING.
    pub manual_setpoint: Option<Setpoint>,
}

impl GraspController {
    /// A controller with α = 0, active, following the state machine.
    pub fn new(gains: Gains, setpoints: Setpoints) -> Self {
        Self {
            gains,
            setpoints,
            alpha: 0.0,
            active: true,
            open_while_closing: false,
        }
    }

    /// Advances the state machine in `run` for the hand–object `distance` and returns the blend
    /// weights.
    pub fn advance(&self, run: &mut ControllerState, distance: f64, release: bool) -> Blend {
        run.state = run.state.next(distance, release, &self.gains);
        match run.manual_setpoint {
            // The grip setpoint carries the grip strength, as in GRIPPING.
            Some(Setpoint::Grip) => GraspState::Gripping.blend(distance, self.alpha, &self.gains),
            Some(s) => Blend::only(s),
            None if self.open_while_closing && run.state == GraspState::Closing => {
                Blend::only(Setpoint::Open)
            }
            None => run.state.blend(distance, self.alpha, &self.gains),
        }
    }

    /// Advances the state machine in `run` and writes into `out` the joint torques τP + τA + τG + τARM
    /// for the hand at `q`, `qd`, its base moving as `base` (gravity included there), the object
    /// `distance` away. `compensate` turns the inverse-dynamics terms τG + τARM on. Allocates
    /// nothing: `model` and `data` are the hand's dynamics and their buffers.
    #[allow(clippy::too_many_arguments)]
    pub fn torques(
        &self,
        run: &mut ControllerState,
        model: &DynamicsModel,
        data: &mut DynamicsData,
        q: &[f64],
        qd: &[f64],
        base: &BaseMotion,
        distance: f64,
        release: bool,
        compensate: bool,
        out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        if !distance.is_finite() || !self.alpha.is_finite() {
            return Err(DynamicsError::NonFinite("distance or grip strength"));
        }
        model.check(&[("qd", qd)])?;
        if out.len() != model.dof_count() {
            return Err(DynamicsError::Length {
                what: "torques",
                got: out.len(),
                expected: model.dof_count(),
            });
        }
        let blend = self.advance(run, distance, release);
        let inertia = outboard_inertia_into(model, data, q)?;
        for (k, out) in out.iter_mut().enumerate() {
            *out = passive_unit(k, q, qd, &self.setpoints, &self.gains);
            if self.active {
                *out += active_unit(k, q, qd, &self.setpoints, &blend, &self.gains);
            }
        }
        inertia.apply(out);
        if compensate {
            let bias = bias_torques(model, data, q, base)?;
            for (out, b) in out.iter_mut().zip(bias) {
                *out += b;
            }
        }
        Ok(())
    }
}
