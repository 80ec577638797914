//! The error type of every fallible call in this crate: what went wrong, where, and at which time.

use std::fmt;

/// An error raised by a user's system (right-hand side, Jacobian) while it was evaluated.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemError {
    /// What the system reported.
    pub message: String,
}

impl SystemError {
    /// A system error with the given message.
    pub fn new(message: impl Into<String>) -> Self {
        Self { message: message.into() }
    }
}

impl fmt::Display for SystemError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for SystemError {}

/// Why an integration could not be started or completed.
///
/// Whenever a call returns one of these, the caller's state is unchanged: [`crate::solve`] never writes to its
/// input, and [`crate::Integrator::advance_to`] restores the time and state it started from.
#[derive(Clone, Debug, PartialEq)]
pub enum OdeError {
    /// An argument is out of its domain (a step `h <= 0`, `t_end` before `t0`, a wrong dimension, a bad tolerance).
    /// `name` is the argument's name as the caller spelled it.
    InvalidArgument { name: &'static str, reason: String },
    /// The method cannot be used on this system or with this step control.
    Unsupported { method: &'static str, reason: String },
    /// A state component or a derivative became NaN or infinite.
    NonFinite { t: f64, what: &'static str, index: usize },
    /// The state grew past the divergence limit: the method is unstable at this step size.
    Divergence { t: f64, norm: f64, limit: f64, h: f64 },
    /// The step-size controller asked for a step below the minimum step.
    StepTooSmall { t: f64, h: f64, min_step: f64 },
    /// Newton's iteration of an implicit method did not converge.
    NewtonFailure { t: f64, h: f64, iterations: usize, residual: f64 },
    /// The iteration matrix `I/(h gamma) - J` is singular.
    SingularMatrix { t: f64, h: f64 },
    /// The iterative linear solver did not reach its tolerance.
    LinearSolve { t: f64, h: f64, iterations: usize, residual: f64 },
    /// More steps than `max_steps` were needed.
    TooManySteps { t: f64, max_steps: usize },
    /// The system's own evaluation failed.
    System { t: f64, message: String },
}

impl OdeError {
    pub(crate) fn invalid(name: &'static str, reason: impl Into<String>) -> Self {
        OdeError::InvalidArgument { name, reason: reason.into() }
    }
}

impl fmt::Display for OdeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OdeError::InvalidArgument { name, reason } => {
                write!(f, "invalid argument `{name}`: {reason}")
            }
            OdeError::Unsupported { method, reason } => {
                write!(f, "method `{method}` cannot be used here: {reason}")
            }
            OdeError::NonFinite { t, what, index } => {
                write!(f, "non-finite {what} (component {index}) at t = {t:e}")
            }
            OdeError::Divergence { t, norm, limit, h } => write!(
                f,
                "divergence at t = {t:e}: state norm {norm:e} exceeds the limit {limit:e}; \
                 the method is unstable at step h = {h:e}"
            ),
            OdeError::StepTooSmall { t, h, min_step } => {
                write!(f, "step size {h:e} fell below the minimum {min_step:e} at t = {t:e}")
            }
            OdeError::NewtonFailure { t, h, iterations, residual } => write!(
                f,
                "Newton iteration failed at t = {t:e} with h = {h:e}: no convergence after \
                 {iterations} iterations (last correction norm {residual:e})"
            ),
            OdeError::SingularMatrix { t, h } => {
                write!(f, "singular iteration matrix at t = {t:e} with h = {h:e}")
            }
            OdeError::LinearSolve { t, h, iterations, residual } => write!(
                f,
                "iterative linear solve failed at t = {t:e} with h = {h:e}: relative residual {residual:e} after \
                 {iterations} iterations"
            ),
            OdeError::TooManySteps { t, max_steps } => {
                write!(f, "more than {max_steps} steps needed; stopped at t = {t:e} (split the span into shorter calls, or raise max_steps)")
            }
            OdeError::System { t, message } => {
                write!(f, "system evaluation failed at t = {t:e}: {message}")
            }
        }
    }
}

impl std::error::Error for OdeError {}
