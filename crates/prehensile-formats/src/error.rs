//! The one error type of this crate: what went wrong, in which file, where in it.

use std::fmt;

use prehensile_core::{HandError, MeshError, ObjectError};

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
    /// The typed error of the library that refused the file's content, when one did (also
    /// [`std::error::Error::source`]).
    #[source]
    pub cause: Option<Box<FormatCause>>,
}

/// Which library refused a file's content, with its typed error: callers can match on it
/// instead of reading the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FormatCause {
    /// The hand described by the file is not a valid hand.
    #[error(transparent)]
    Hand(#[from] HandError),
    /// The triangles do not make a mesh (indices, numbers, size).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The mesh does not make a graspable object.
    #[error(transparent)]
    Object(#[from] ObjectError),
}

impl FormatError {
    /// An error about the whole file.
    pub fn new(source_name: &str, reason: impl Into<String>) -> Self {
        Self {
            source_name: source_name.to_string(),
            location: None,
            reason: reason.into(),
            cause: None,
        }
    }

    /// An error at a place in the file.
    pub fn at(source_name: &str, location: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            source_name: source_name.to_string(),
            location: Some(location.into()),
            reason: reason.into(),
            cause: None,
        }
    }

    /// The file's content was refused by a library: the message is the library's, the typed
    /// error is kept as the cause.
    pub fn caused_by(source_name: &str, cause: impl Into<FormatCause>) -> Self {
        let cause = cause.into();
        Self {
            source_name: source_name.to_string(),
            location: None,
            reason: cause.to_string(),
            cause: Some(Box::new(cause)),
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
