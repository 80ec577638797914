//! The accuracy the contact solvers answer to: clarabel's tolerances and iteration cap, and the residual every
//! answer (clarabel's or the Newton method's) is held to.

use crate::error::ContactError;

/// Accuracy and limits of the contact solves: clarabel's, and the residual the Newton method's answers are held to too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// clarabel's gap and feasibility tolerances (relative and absolute); 1e-12 by default: each halving of the
    /// exponent costs about one interior-point iteration, and near the edge of a friction cone (a block on an incline
    /// within 0.1% of its friction angle) 1e-10 leaves velocities 6e-7 m/s off where 1e-12 leaves 1e-10.
    pub tolerance: f64,
    /// clarabel's iteration cap.
    pub max_iterations: u32,
    /// The largest complementarity residual accepted (relative to the force and velocity scales of the problem):
    /// f >= -tol F, w >= -tol W, |f_i w_i| <= tol F W. This, not clarabel's status, decides: an answer clarabel
    /// could not polish to `tolerance` (status AlmostSolved, InsufficientProgress, MaxIterations) is used when it
    /// passes, and a larger residual is an `Inaccurate` error.
    pub complementarity_tolerance: f64,
    /// clarabel's iterative refinement of each linear solve (on by default). Off, a solve takes about a third less
    /// time and an answer that then misses `complementarity_tolerance` is solved again with it on; fast mode turns
    /// it off.
    pub iterative_refinement: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-12,
            max_iterations: 200,
            complementarity_tolerance: 1e-6,
            iterative_refinement: true,
        }
    }
}

impl SolverSettings {
    pub(crate) fn check(&self) -> Result<(), ContactError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(ContactError::invalid(
                "settings",
                format!("tolerance must be in (0, 1), got {}", self.tolerance),
            ));
        }
        if self.max_iterations == 0 {
            return Err(ContactError::invalid("settings", "max_iterations must be > 0"));
        }
        if !(self.complementarity_tolerance.is_finite() && self.complementarity_tolerance > 0.0) {
            return Err(ContactError::invalid("settings", "complementarity_tolerance must be finite and > 0"));
        }
        Ok(())
    }
}
