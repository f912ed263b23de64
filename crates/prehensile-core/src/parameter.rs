//! Why a number or a name given to the library cannot be used: one typed error for every
//! setting the library checks (search parameters, contact models, requests), so that each front
//! end shows the library's own message instead of checking again in its own words.

use std::fmt;
use std::str::FromStr;

use crate::math::Vec3;

/// A parameter the library cannot use.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParameterError {
    /// A number outside the range the library takes (NaN and infinities included).
    #[error("{name} = {value} is outside its range [{low}, {high}]{}", Hint(hint))]
    OutOfRange {
        /// The parameter, as the options call it (`friction`, `budget_ms`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
        /// Smallest value taken.
        low: f64,
        /// Largest value taken.
        high: f64,
        /// What the range is about, when the numbers alone do not say (empty if not).
        hint: &'static str,
    },
    /// A point with a NaN or infinite coordinate, or one farther from the origin than any
    /// object is.
    #[error("{name} {value:?} is not a finite point within 1000 km of the origin; check its units (metres)")]
    BadPoint {
        /// The parameter (`shoulder`, `hook`).
        name: &'static str,
        /// The point given.
        value: [f64; 3],
    },
    /// A name the library does not know.
    #[error("unknown {what} '{name}'; use one of: {}", known.join(", "))]
    UnknownName {
        /// What was named (`up axis`, `validity rule`, `engine`, ...).
        what: &'static str,
        /// The name given.
        name: String,
        /// The names known.
        known: &'static [&'static str],
    },
    /// Quality weights that cannot rank poses: a negative or non-finite weight, the wrong
    /// count, or all zero.
    #[error("quality weights {weights:?}: {problem}")]
    Weights {
        /// The weights given.
        weights: Vec<f64>,
        /// What is wrong with them.
        problem: WeightsProblem,
    },
    /// The up direction is not a finite, non-zero vector.
    #[error("the up direction must be a finite, non-zero vector")]
    Up,
    /// TranslateToFree's steps are not positive, or its precision exceeds its coarse step.
    #[error("TranslateToFree steps must be positive (at least 1 µm) and the precision no larger than the coarse step")]
    TranslateSteps,
}

/// What is wrong with a set of quality weights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum WeightsProblem {
    /// Not four (G, F, T, W) or five (G, F, T, W, S) numbers.
    Count,
    /// A weight is negative, NaN or infinite.
    Negative,
    /// Every weight is zero: every pose would have the same quality.
    AllZero,
}

impl fmt::Display for WeightsProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Count => "give four (G, F, T, W) or five (G, F, T, W, S) numbers",
            Self::Negative => "every weight must be a finite number, not negative",
            Self::AllZero => {
                "all are zero, so every pose would rank the same; give at least one positive weight"
            }
        })
    }
}

/// A hint after a range, with its separator, or nothing.
struct Hint<'a>(&'a str);

impl fmt::Display for Hint<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            Ok(())
        } else {
            write!(f, "; {}", self.0)
        }
    }
}

/// The world's up axis: the hand approaches from above, and the default shoulder stands above
/// the object.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// +x up.
    X,
    /// +y up (glTF's and many engines' convention).
    Y,
    /// +z up (Blender's, MuJoCo's and this project's convention).
    #[default]
    Z,
}

impl UpAxis {
    /// Every axis's name, as [`FromStr`] takes it.
    pub const NAMES: [&'static str; 3] = ["x", "y", "z"];

    /// The unit vector along the axis.
    pub fn vector(self) -> Vec3 {
        match self {
            Self::X => Vec3::x(),
            Self::Y => Vec3::y(),
            Self::Z => Vec3::z(),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

impl fmt::Display for UpAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for UpAxis {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, ParameterError> {
        match s {
            "x" => Ok(Self::X),
            "y" => Ok(Self::Y),
            "z" => Ok(Self::Z),
            _ => Err(ParameterError::UnknownName {
                what: "up axis",
                name: s.to_string(),
                known: &Self::NAMES,
            }),
        }
    }
}

/// `value` itself when it is finite and within [low, high], else [`ParameterError::OutOfRange`].
pub fn in_range(
    name: &'static str,
    value: f64,
    low: f64,
    high: f64,
    hint: &'static str,
) -> Result<f64, ParameterError> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err(ParameterError::OutOfRange {
            name,
            value,
            low,
            high,
            hint,
        })
    }
}

/// `value` itself when it is a finite point within 1000 km of the origin.
pub fn finite_point(name: &'static str, value: [f64; 3]) -> Result<[f64; 3], ParameterError> {
    if value
        .iter()
        .all(|c| c.is_finite() && c.abs() <= crate::mesh::MAX_COORDINATE)
    {
        Ok(value)
    } else {
        Err(ParameterError::BadPoint { name, value })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print_back() {
        for name in UpAxis::NAMES {
            assert_eq!(name.parse::<UpAxis>().unwrap().to_string(), name);
        }
        let e = "w".parse::<UpAxis>().unwrap_err();
        assert_eq!(e.to_string(), "unknown up axis 'w'; use one of: x, y, z");
        assert_eq!(UpAxis::Y.vector(), Vec3::y());
    }

    #[test]
    fn a_range_error_names_the_parameter_its_range_and_the_hint() {
        let e = in_range(
            "friction",
            f64::NAN,
            0.0,
            10.0,
            "rubber on wood is about 0.5-1",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "friction = NaN is outside its range [0, 10]; rubber on wood is about 0.5-1"
        );
        assert_eq!(in_range("x", 2.0, 1.0, 3.0, ""), Ok(2.0));
        assert!(finite_point("shoulder", [0.0, f64::INFINITY, 0.0]).is_err());
        assert!(finite_point("shoulder", [0.0, 2e6, 0.0]).is_err());
    }
}
