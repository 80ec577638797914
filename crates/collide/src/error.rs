//! The error of shape construction and geometric queries: which argument was wrong and why.

use nalgebra::Point3;
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

/// Shortest and longest dimension of a shape (m): a nanometre to a million kilometres, so that no product of two
/// dimensions (areas, inertias) can overflow or vanish.
pub const LENGTH: (f64, f64) = (1e-9, 1e9);

/// Checks that a length is finite and within `LENGTH`.
pub(crate) fn positive(name: &'static str, v: f64) -> Result<f64, ShapeError> {
    if v.is_finite() && v >= LENGTH.0 && v <= LENGTH.1 {
        Ok(v)
    } else {
        Err(ShapeError::new(name, format!("must be finite and within [{:e}, {:e}] m, got {v:e}", LENGTH.0, LENGTH.1)))
    }
}

/// Checks that point `i` of argument `name` is finite and within `LENGTH.1` of the origin.
pub(crate) fn finite_point(name: &'static str, i: usize, p: &Point3<f64>) -> Result<(), ShapeError> {
    if p.iter().all(|c| c.is_finite() && c.abs() <= LENGTH.1) {
        Ok(())
    } else {
        Err(ShapeError::new(name, format!("point {i} must be finite and within 1e9 m of the origin: {p:?}")))
    }
}
