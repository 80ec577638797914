//! A stage's failure, said as the integrator's error (a system error at time t): accurate mode's as it is, fast mode's
//! as the world's simulation error it converts to.

use tumble_integrate::OdeError;

/// The error of a stage that failed at time t.
pub(crate) fn failure(t: f64, message: String) -> OdeError {
    OdeError::System { t, message }
}
