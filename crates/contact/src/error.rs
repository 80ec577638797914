//! The error of contact computations: a bad argument (named), or a solver that did not deliver.

use std::fmt;

/// What went wrong in a contact computation. Nothing is changed when one is returned: every function here is pure.
#[derive(Clone, Debug, PartialEq)]
pub enum ContactError {
    /// An argument out of its domain: its name, and why.
    InvalidArgument { name: &'static str, reason: String },
    /// clarabel stopped without a solution we can use: the problem, its status and iterations.
    Solver { problem: &'static str, status: String, iterations: u32 },
    /// clarabel reported success but the answer misses the complementarity conditions by more than the tolerance.
    Inaccurate { problem: &'static str, residual: f64, tolerance: f64 },
}

impl ContactError {
    pub(crate) fn invalid(name: &'static str, reason: impl Into<String>) -> Self {
        ContactError::InvalidArgument { name, reason: reason.into() }
    }
}

impl fmt::Display for ContactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ContactError::InvalidArgument { name, reason } => write!(f, "invalid argument `{name}`: {reason}"),
            ContactError::Solver { problem, status, iterations } => {
                write!(f, "the {problem} solver (clarabel) stopped with status {status} after {iterations} iterations")
            }
            ContactError::Inaccurate { problem, residual, tolerance } => {
                write!(f, "the {problem} solution misses complementarity by {residual:e} (tolerance {tolerance:e})")
            }
        }
    }
}

impl std::error::Error for ContactError {}
