//! The one error type of this crate: what went wrong, in which file, where in it.

use std::fmt;

/// A file could not be read or understood.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub struct FormatError {
    /// The file (or a name for in-memory data).
    pub source_name: String,
    /// Where in the file: `line 12`, `face 40`, `bone 'index_distal'`.
    pub location: Option<String>,
    /// What is wrong and how to fix it.
    pub reason: String,
}

impl FormatError {
    /// An error about the whole file.
    pub fn new(source_name: &str, reason: impl Into<String>) -> Self {
        Self {
            source_name: source_name.to_string(),
            location: None,
            reason: reason.into(),
        }
    }

    /// An error at a place in the file.
    pub fn at(source_name: &str, location: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            source_name: source_name.to_string(),
            location: Some(location.into()),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => write!(f, "{}: {}: {}", self.source_name, loc, self.reason),
            None => write!(f, "{}: {}", self.source_name, self.reason),
        }
    }
}
