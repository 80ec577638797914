//! A fast-mode stage's failure, said as a world error (a simulation error at the step's time).

use crate::error::WorldError;
use tumble_integrate::OdeError;

/// The error of a stage that failed at time t.
pub(crate) fn failure(t: f64, message: String) -> WorldError {
    WorldError::Simulation(OdeError::System { t, message })
}
