//! The rapier engine: each bone a rigid body, joined by impulse joints whose motors carry the
//! controller's springs; the object a convex hull or a convex decomposition.

pub mod articulated_hand;
pub mod object_body;
pub(crate) mod world;
