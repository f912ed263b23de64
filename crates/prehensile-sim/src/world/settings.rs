//! Every setting of a simulated world in one typed place, as MuJoCo keeps its `mjOption` and
//! rapier its `IntegrationParameters`: the world's own (step, gravity, friction, density), and
//! each engine's solver settings beside them, each with its unit and default.

use std::fmt;
use std::str::FromStr;

use prehensile_core::math::Vec3;

use crate::error::SimError;

/// Which engine steps a simulation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Engine {
    /// rapier3d: one rigid body per bone, joined by impulse joints with motors.
    Rapier,
    /// The default: the hand in reduced coordinates (its joint angles) on the project's own
    /// dynamics (RNEA, CRBA), the controller's springs integrated implicitly, contacts solved by
    /// projected Gauss–Seidel against the object's distance grid and between the hands'
    /// capsules. Why it is the default: docs/decisions/002-reduced-engine-beside-rapier.md.
    #[default]
    Reduced,
}

impl Engine {
    /// Every engine's name, as [`FromStr`] takes it.
    pub const NAMES: [&'static str; 2] = ["rapier", "reduced"];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rapier => Self::NAMES[0],
            Self::Reduced => Self::NAMES[1],
        }
    }
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Engine {
    type Err = SimError;

    fn from_str(name: &str) -> Result<Self, SimError> {
        match name {
            "rapier" => Ok(Self::Rapier),
            "reduced" => Ok(Self::Reduced),
            _ => Err(SimError::UnknownName {
                what: "engine",
                name: name.to_string(),
                known: &Self::NAMES,
            }),
        }
    }
}

/// The reduced-coordinate engine's contact solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReducedSettings {
    /// Most projected Gauss–Seidel sweeps a step (warm-started, they often settle sooner).
    /// Default 10.
    pub sweeps: usize,
    /// A sweep has settled when no impulse changed by more than this share of the largest.
    /// Default 1e-6.
    pub converged: f64,
    /// Contacts are made this far out, metres, so that a resting contact stays one. Default
    /// 1 mm.
    pub margin: f64,
    /// A capsule's nearest point is followed this far out, metres, beyond the margin: a capsule
    /// near the object keeps its place along the bone from step to step, and its next search
    /// starts there. Default 5 mm.
    pub followed: f64,
    /// A capsule's end gets its own contact only this far along it (a share of its length) from
    /// the nearest point; nearer, the two would be one contact counted twice. Default 0.25.
    pub ends_apart: f64,
    /// A penetration is pushed out at its depth over this time, seconds, and at most half of it
    /// in one step: MuJoCo's default contact time constant (`solref` 0.02 s). Default 0.02.
    pub push_out_time: f64,
    /// Contact compliance as a share of each normal row's Delassus diagonal: MuJoCo's default
    /// impedance (d = 0.95 at depth) gives (1 − d) / d ≈ 0.05. Default 0.05.
    pub softness: f64,
}

impl Default for ReducedSettings {
    fn default() -> Self {
        Self {
            sweeps: 10,
            converged: 1e-6,
            margin: 0.001,
            followed: 0.005,
            ends_apart: 0.25,
            push_out_time: 0.02,
            softness: 0.05,
        }
    }
}

impl ReducedSettings {
    /// Refuses settings the solver cannot use.
    pub fn check(&self) -> Result<(), SimError> {
        check_count("reduced.sweeps", self.sweeps, 1, 1000)?;
        let shares = [
            ("reduced.converged", self.converged, 0.0, 1.0),
            ("reduced.margin", self.margin, 0.0, 0.01),
            ("reduced.followed", self.followed, 0.0, 0.05),
            ("reduced.ends_apart", self.ends_apart, 0.0, 1.0),
            ("reduced.push_out_time", self.push_out_time, 1e-6, 10.0),
            ("reduced.softness", self.softness, 0.0, 10.0),
        ];
        for (setting, value, low, high) in shares {
            check_range(setting, value, low, high)?;
        }
        Ok(())
    }
}

/// rapier's solver, as this project sets it up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RapierSettings {
    /// Solver substeps per step (rapier's `num_solver_iterations`);
    /// [`RapierSettings::for_step`] chooses them for a step length.
    pub solver_iterations: usize,
    /// Gauss–Seidel sweeps over the constraints in each substep (rapier's
    /// `num_internal_pgs_iterations`); [`RapierSettings::for_step`] chooses them.
    pub inner_iterations: usize,
    /// How far a bone may come off its joint before the run counts as diverged, metres.
    /// Default 5 mm.
    pub joint_gap_limit: f64,
}

impl Default for RapierSettings {
    /// [`RapierSettings::for_step`] of 1 ms.
    fn default() -> Self {
        Self::for_step(1e-3)
    }
}

impl RapierSettings {
    /// The solver for a step of `dt` seconds: [`RapierSettings::iterations_for`] substeps of
    /// [`RapierSettings::inner_iterations_for`] sweeps.
    pub fn for_step(dt: f64) -> Self {
        Self {
            solver_iterations: Self::iterations_for(dt),
            inner_iterations: Self::inner_iterations_for(dt),
            joint_gap_limit: 0.005,
        }
    }

    /// The solver substeps for a step of `dt` seconds: one per millisecond and at least one,
    /// so 1 at the paper's 0.2 ms and at 1 ms. A substep rebuilds every joint's constraint and
    /// a sweep only solves them again, so one substep of 1 ms with enough sweeps keeps every
    /// scenario's outcome and is faster than two of 0.5 ms (docs/PERFORMANCE.md).
    pub fn iterations_for(dt: f64) -> usize {
        if dt.is_finite() && dt > 0.0 {
            (dt / 1e-3 - 1e-9).ceil().clamp(1.0, 100.0) as usize
        } else {
            1
        }
    }

    /// The Gauss–Seidel sweeps per substep for a step of `dt` seconds: one per 0.125 ms of
    /// substep and at least 3, so 3 at 0.2 ms and 8 at 1 ms. A hand is a chain of joints that
    /// one sweep leaves unconverged, and a longer substep needs more sweeps: at 1 ms the human
    /// hand dropped the cylinder with 6 and held it with 7 or more (docs/PERFORMANCE.md).
    pub fn inner_iterations_for(dt: f64) -> usize {
        let substep = if dt.is_finite() && dt > 0.0 {
            dt / Self::iterations_for(dt) as f64
        } else {
            0.0
        };
        ((substep / 0.125e-3 - 1e-9).ceil() as usize).clamp(3, 100)
    }

    /// Refuses settings the solver cannot use.
    pub fn check(&self) -> Result<(), SimError> {
        check_count("rapier.solver_iterations", self.solver_iterations, 1, 100)?;
        check_count("rapier.inner_iterations", self.inner_iterations, 1, 100)?;
        check_range("rapier.joint_gap_limit", self.joint_gap_limit, 1e-6, 1.0)
    }
}

/// World settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Time step, seconds. Default 1 ms (the paper used 0.2 ms).
    pub dt: f64,
    /// Gravity, world, m/s² (default 9.81 down −z).
    pub gravity: Vec3,
    /// Friction coefficient of skin and objects (one for both; rapier combines its colliders'
    /// as their mean, the same here). Default 1.
    pub friction: f64,
    /// Object density, kg/m³ (default 20, like expanded polystyrene: with Table 1's gains the
    /// hand squeezes with 0.03–0.62 N for α 0–0.5, enough for objects of a few grams).
    pub object_density: f64,
    /// Frames per second of the recording (for animation export). Default 60.
    pub record_fps: f64,
    /// The engine that steps the world.
    pub engine: Engine,
    /// The reduced engine's solver (read only when it steps the world).
    pub reduced: ReducedSettings,
    /// rapier's solver (read only when it steps the world).
    pub rapier: RapierSettings,
}

impl Default for Settings {
    /// [`Settings::for_step`] of 1 ms.
    fn default() -> Self {
        Self::for_step(1e-3)
    }
}

impl Settings {
    /// The default settings for a step of `dt` seconds, with rapier's solver chosen for it.
    pub fn for_step(dt: f64) -> Self {
        Self {
            dt,
            gravity: Vec3::new(0.0, 0.0, -9.81),
            friction: 1.0,
            object_density: 20.0,
            record_fps: 60.0,
            engine: Engine::default(),
            reduced: ReducedSettings::default(),
            rapier: RapierSettings::for_step(dt),
        }
    }

    /// Refuses settings that cannot give a meaningful run.
    pub fn check(&self) -> Result<(), SimError> {
        // Steps below 10 µs only take longer; fingers need at most 10 ms (0.2–1 ms is typical).
        check_range("dt", self.dt, 1e-5, 0.01)?;
        for g in self.gravity.iter() {
            check_range("gravity", *g, -f64::MAX, f64::MAX)?;
        }
        check_range("friction", self.friction, 0.0, 100.0)?;
        check_range("object_density", self.object_density, 1e-3, 1e5)?;
        check_range("record_fps", self.record_fps, 1e-6, 1e4)?;
        self.reduced.check()?;
        self.rapier.check()
    }
}

/// `value` must be finite and within [low, high].
fn check_range(setting: &'static str, value: f64, low: f64, high: f64) -> Result<(), SimError> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(SimError::OutOfRange {
            setting,
            value,
            low,
            high,
        })
    }
}

/// A count must be within [low, high].
fn check_count(
    setting: &'static str,
    value: usize,
    low: usize,
    high: usize,
) -> Result<(), SimError> {
    check_range(setting, value as f64, low as f64, high as f64)
}
