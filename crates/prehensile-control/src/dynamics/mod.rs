//! Rigid-body dynamics of a hand model, model apart from data: the model and its buffers, body
//! and outboard inertia, inverse dynamics (RNEA), the mass matrix (CRBA) and forward dynamics.

pub mod body_inertia;
pub mod forward_dynamics;
pub mod inverse_dynamics;
pub mod mass_matrix;
pub mod model;
pub mod outboard_inertia;
