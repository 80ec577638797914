//! The error of shape construction and geometric queries: which argument was wrong and why.

use std::fmt;

/// A shape or query argument out of its domain.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeError {
    /// The argument's name as the caller spelled it (`radius`, `half_extents`, `points`, ...).
    pub name: &'static str,
    /// What is wrong with it.
    pub reason: String,
}

impl ShapeError {
    pub(crate) fn new(name: &'static str, reason: impl Into<String>) -> Self {
        ShapeError { name, reason: reason.into() }
    }
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid argument `{}`: {}", self.name, self.reason)
    }
}

impl std::error::Error for ShapeError {}

/// Checks that a length is finite and > 0.
pub(crate) fn positive(name: &'static str, v: f64) -> Result<f64, ShapeError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ShapeError::new(name, format!("must be finite and > 0, got {v}")))
    }
}
