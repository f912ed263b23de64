//! The sizes a hand must keep to: what no hand exceeds, so that absurd numbers are refused
//! before they reach the search.

/// Most bones a hand may have.
pub const MAX_BONES: usize = 1000;

/// Largest distance of any bone position, tip or capsule from its frame, and largest capsule
/// radius, metres: no hand is bigger, and absurd sizes (1e300) made the search spin forever.
pub const MAX_HAND_EXTENT: f64 = 2.0;

/// Shortest bone accepted, metres.
pub const MIN_BONE_LENGTH: f64 = 1e-5;
