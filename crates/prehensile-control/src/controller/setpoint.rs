//! The six setpoints of the grasp state machine (Pollard & Zordan, Fig. 3) by name, and values
//! kept one per setpoint: positions, velocities, blend weights.

use std::ops::{Index, IndexMut};

/// Names of the six setpoints, in order (Fig. 3).
pub const SETPOINT_NAMES: [&str; 6] = ["neutral", "open", "grip", "release", "open-again", "relax"];

/// One of the state machine's six setpoints, in the paper's order (θ_0 … θ_5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Setpoint {
    /// θ_0: before a grasp.
    Neutral,
    /// θ_1: the hand open for the object.
    Open,
    /// θ_2: closed on the object (extrapolated by the grip strength α while gripping).
    Grip,
    /// θ_3: letting go.
    Release,
    /// θ_4: open again as the hand moves away.
    OpenAgain,
    /// θ_5: relaxed, back at neutral.
    Relax,
}

impl Setpoint {
    /// Every setpoint, in order.
    pub const ALL: [Setpoint; 6] = [
        Setpoint::Neutral,
        Setpoint::Open,
        Setpoint::Grip,
        Setpoint::Release,
        Setpoint::OpenAgain,
        Setpoint::Relax,
    ];

    /// Its position in [`Setpoint::ALL`] (the paper's subscript).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The setpoint with subscript `k`, if there is one.
    pub fn from_index(k: usize) -> Option<Self> {
        Self::ALL.get(k).copied()
    }

    /// Its name in controller files.
    pub fn name(self) -> &'static str {
        SETPOINT_NAMES[self.index()]
    }
}

/// One value per setpoint, indexed by [`Setpoint`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PerSetpoint<T>(pub [T; 6]);

impl<T> PerSetpoint<T> {
    /// The value of each setpoint from `f`.
    pub fn from_fn(mut f: impl FnMut(Setpoint) -> T) -> Self {
        Self(std::array::from_fn(|k| f(Setpoint::ALL[k])))
    }

    /// The values, in setpoint order.
    pub fn values(&self) -> std::slice::Iter<'_, T> {
        self.0.iter()
    }

    /// Each setpoint with its value, in order.
    pub fn iter(&self) -> impl Iterator<Item = (Setpoint, &T)> {
        Setpoint::ALL.into_iter().zip(&self.0)
    }
}

impl<T> Index<Setpoint> for PerSetpoint<T> {
    type Output = T;
    fn index(&self, s: Setpoint) -> &T {
        &self.0[s.index()]
    }
}

impl<T> IndexMut<Setpoint> for PerSetpoint<T> {
    fn index_mut(&mut self, s: Setpoint) -> &mut T {
        &mut self.0[s.index()]
    }
}

/// Blend weights B over the setpoints (Eq. 10–12, 15–16).
pub type Blend = PerSetpoint<f64>;

impl Blend {
    /// `Σ_s B_s · values_s[k]`: the blended value of degree of freedom `k`.
    pub fn mix(&self, values: &PerSetpoint<Vec<f64>>, k: usize) -> f64 {
        self.iter().map(|(s, b)| b * values[s][k]).sum()
    }

    /// Weight 1 on setpoint `s` alone.
    pub fn only(s: Setpoint) -> Self {
        Self::from_fn(|t| if t == s { 1.0 } else { 0.0 })
    }
}
