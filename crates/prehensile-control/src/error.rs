//! The crate's one error type: why dynamics, a controller or a fit cannot be computed.

/// Why dynamics cannot be computed for this hand or state, or why an example motion or a
/// controller file does not fit the hand.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// A vector has the wrong length.
    #[error("{what} has {got} entries, the hand has {expected} degrees of freedom")]
    Length {
        /// Which vector.
        what: &'static str,
        /// Its length.
        got: usize,
        /// Degrees of freedom.
        expected: usize,
    },
    /// A number is NaN or infinite.
    #[error("{0} contains a non-finite number")]
    NonFinite(&'static str),
    /// A motion or controller file's text is not the TOML or JSON its schema asks for.
    #[error("{source_name}: {error}")]
    Syntax {
        /// The file, or a name for in-memory text.
        source_name: String,
        /// What the parser found.
        #[source]
        error: Box<toml::de::Error>,
    },
    /// A file names another schema.
    #[error("schema '{found}', expected '{expected}'")]
    Schema {
        /// The schema the file names.
        found: String,
        /// The schema this reader takes.
        expected: &'static str,
    },
    /// A file was made for a hand with other degrees of freedom.
    #[error("the {what} is for degrees of freedom [{}], the hand has [{}]", file.join(", "), expected.join(", "))]
    DofNames {
        /// `motion` or `controller`.
        what: &'static str,
        /// The file's degree-of-freedom names.
        file: Vec<String>,
        /// The hand's degree-of-freedom names.
        expected: Vec<String>,
    },
    /// A controller file's setpoints are not the six, in order.
    #[error("setpoints are [{}]; give exactly [{}] in that order", found.join(", "), expected.join(", "))]
    Setpoints {
        /// The names found.
        found: Vec<String>,
        /// The six names, in order.
        expected: [&'static str; 6],
    },
    /// A controller's gains or grip strength are negative or not finite.
    #[error("gains and alpha must be finite and ≥ 0")]
    Gains,
    /// A controller's switching distances are not ordered.
    #[error("distances [{}, {}, {}] must be finite with D0 ≤ D1 < D2", .0[0], .0[1], .0[2])]
    Distances([f64; 3]),
    /// A controller's per-joint vector has the wrong length or a non-finite value.
    #[error("{what}: need {expected} finite values")]
    Vector {
        /// Which vector.
        what: &'static str,
        /// Degrees of freedom.
        expected: usize,
    },
    /// A controller's joint limits are the wrong count or not ordered.
    #[error("limits: need {expected} pairs [min, max] with min ≤ max")]
    Limits {
        /// Degrees of freedom.
        expected: usize,
    },
    /// A motion's frame time is not positive.
    #[error("frame_time {0} must be positive")]
    FrameTime(f64),
    /// A motion has too few or too many frames.
    #[error("{0} frames; give 3 to 1,000,000")]
    FrameCount(usize),
    /// A motion's distances do not match its frames.
    #[error("{distances} distances for {frames} frames; give one per frame")]
    DistanceCount {
        /// Distances given.
        distances: usize,
        /// Frames given.
        frames: usize,
    },
    /// A motion frame has the wrong number of angles.
    #[error("frame {frame} has {got} angles, the hand has {expected} degrees of freedom")]
    FrameLength {
        /// The frame.
        frame: usize,
        /// Angles given.
        got: usize,
        /// Degrees of freedom.
        expected: usize,
    },
    /// A motion frame's angle is not finite.
    #[error("frame {frame}, degree of freedom '{dof}' is not finite")]
    FrameNotFinite {
        /// The frame.
        frame: usize,
        /// The degree of freedom.
        dof: String,
    },
    /// A motion frame's distance is negative or not finite.
    #[error("frame {frame}: distance {distance} must be ≥ 0")]
    FrameDistance {
        /// The frame.
        frame: usize,
        /// The distance given.
        distance: f64,
    },
    /// A motion's release frame is past its end.
    #[error("release_frame {0} is past the last frame")]
    ReleaseFrame(usize),
}
