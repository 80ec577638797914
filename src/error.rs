//! The world's error type: a bad argument (named), a handle that is stale or from another world, or a step that
//! could not be completed (the world is then exactly as it was before the call).

use std::fmt;
use tumble_collide::ShapeError;
use tumble_integrate::OdeError;

/// Why a world call failed.
#[derive(Clone, Debug, PartialEq)]
pub enum WorldError {
    /// An argument is out of its domain; `name` is the argument's name.
    InvalidArgument { name: &'static str, reason: String },
    /// A handle that no longer (or never) named an object of this world.
    UnknownHandle { name: &'static str, handle: String },
    /// The step could not be completed; the world is unchanged.
    Simulation(OdeError),
    /// A run was stopped by its caller; the world is as it was before the run.
    Interrupted,
}

impl WorldError {
    pub(crate) fn invalid(name: &'static str, reason: impl Into<String>) -> Self {
        WorldError::InvalidArgument { name, reason: reason.into() }
    }

    /// The offending argument's name, for bad arguments.
    pub fn argument(&self) -> Option<&'static str> {
        match self {
            WorldError::InvalidArgument { name, .. } | WorldError::UnknownHandle { name, .. } => Some(name),
            WorldError::Simulation(_) | WorldError::Interrupted => None,
        }
    }
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorldError::InvalidArgument { name, reason } => write!(f, "invalid argument `{name}`: {reason}"),
            WorldError::UnknownHandle { name, handle } => {
                write!(f, "invalid argument `{name}`: {handle} is not (or no longer) in this world")
            }
            WorldError::Simulation(e) => write!(f, "the step failed and the world is unchanged: {e}"),
            WorldError::Interrupted => write!(f, "the run was interrupted; the world is as it was before it"),
        }
    }
}

impl std::error::Error for WorldError {}

impl From<ShapeError> for WorldError {
    fn from(e: ShapeError) -> Self {
        WorldError::InvalidArgument { name: e.name, reason: e.reason }
    }
}

impl From<OdeError> for WorldError {
    fn from(e: OdeError) -> Self {
        match e {
            OdeError::InvalidArgument { name, reason } => WorldError::InvalidArgument { name, reason },
            other => WorldError::Simulation(other),
        }
    }
}

/// Checks a scalar: finite, and > 0 (`positive`) or >= 0.
pub(crate) fn check_scalar(name: &'static str, v: f64, positive: bool) -> Result<f64, WorldError> {
    let ok = v.is_finite() && if positive { v > 0.0 } else { v >= 0.0 };
    if ok {
        Ok(v)
    } else {
        Err(WorldError::invalid(name, format!("must be finite and {} 0, got {v}", if positive { ">" } else { ">=" })))
    }
}

/// Checks that every component of a vector is finite.
pub(crate) fn check_finite<'a>(name: &'static str, v: impl IntoIterator<Item = &'a f64>) -> Result<(), WorldError> {
    let v: Vec<f64> = v.into_iter().copied().collect();
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(WorldError::invalid(name, format!("must be finite, got {v:?}")))
    }
}
