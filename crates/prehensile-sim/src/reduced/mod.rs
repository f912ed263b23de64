//! The reduced-coordinate engine, the default: each hand stepped in its joint angles on the
//! project's own dynamics, contacts solved by projected Gauss–Seidel. Why it stands beside
//! rapier: docs/decisions/002-reduced-engine-beside-rapier.md.

pub(crate) mod hand;
mod projected_gauss_seidel;
pub(crate) mod world;
