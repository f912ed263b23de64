//! What touched during a step: the report every engine gives of a hand's contacts.

/// Contact between a hand and the object or another hand during one step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contacts {
    /// Total normal force, newtons.
    pub force: f64,
    /// Deepest penetration, metres (0 without contact).
    pub penetration: f64,
    /// Number of hand colliders touching.
    pub touching: usize,
    /// Normal force on each bone, newtons.
    pub bone_forces: Vec<f64>,
}
