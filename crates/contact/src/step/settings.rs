//! The settings of one velocity step: its size, Baumgarte share, bounce threshold, the solvers' tolerances, the
//! islands' method and threads.

use crate::error::ContactError;
use crate::solver_settings::SolverSettings;

/// Settings of one time step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepSettings {
    /// The step h (> 0).
    pub dt: f64,
    /// Fraction of an interpenetration removed per step, in [0, 1] (Baumgarte); 0.2 by default.
    pub erp: f64,
    /// Restitution applies only to contacts closing faster than this (m/s, >= 0); slower ones come to rest.
    pub bounce_threshold: f64,
    /// clarabel's tolerances.
    pub solver: SolverSettings,
    /// The least velocity scale (m/s) an answer's residual is measured against; 0 by default (the island's own
    /// speeds, at least g h). A caller that needs velocities only to some absolute accuracy says so here: accurate
    /// mode gives its position tolerance over the step, where a body nearly at rest would otherwise be judged
    /// against g h.
    pub velocity_scale: f64,
    /// The islands' solver: tumble's own Newton method (the default), clarabel where it cannot answer.
    pub method: StepMethod,
    /// Threads the islands are solved on: 0 (the default) uses one per core; 1 stays on the calling thread. The
    /// answer is the same bit for bit whatever the count (islands are independent and come back in order).
    pub threads: usize,
    /// Whether a body's free velocity takes Euler's gyroscopic term explicitly, w + h I^-1 (tau - w x I w); off by
    /// default: the step then carries angular momentum (L + h tau), as tumble's engines want (an explicit term
    /// pumps energy into a fast spin about an unstable axis).
    pub gyroscopic: bool,
}

/// How a velocity step's islands are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StepMethod {
    /// The multiplier method with Newton's method on the velocities (`newton/solve.rs`): exact optimality
    /// conditions, warm started from the lagged normal impulses. Islands it cannot answer (Anitescu's cone, more
    /// than a few hundred unknowns, or no convergence within its iteration limits) go to clarabel.
    #[default]
    Newton,
    /// clarabel's interior point for every island (the reference the Newton method is tested against).
    Clarabel,
}

impl StepSettings {
    /// Defaults for step `dt`: erp 0.2, bounce threshold 0.05 m/s, the default solver settings.
    pub fn new(dt: f64) -> StepSettings {
        StepSettings {
            dt,
            erp: 0.2,
            bounce_threshold: 0.05,
            solver: SolverSettings::default(),
            velocity_scale: 0.0,
            method: StepMethod::Newton,
            threads: 0,
            gyroscopic: false,
        }
    }

    pub(crate) fn check(&self) -> Result<(), ContactError> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(ContactError::invalid("dt", format!("must be finite and > 0, got {}", self.dt)));
        }
        if !(0.0..=1.0).contains(&self.erp) {
            return Err(ContactError::invalid("erp", format!("must be in [0, 1], got {}", self.erp)));
        }
        if !(self.bounce_threshold.is_finite() && self.bounce_threshold >= 0.0) {
            return Err(ContactError::invalid("bounce_threshold", "must be finite and >= 0"));
        }
        if !(self.velocity_scale.is_finite() && self.velocity_scale >= 0.0) {
            return Err(ContactError::invalid("velocity_scale", "must be finite and >= 0"));
        }
        if self.method == StepMethod::Clarabel && !cfg!(feature = "clarabel") {
            return Err(ContactError::invalid("method", "clarabel needs the `clarabel` feature"));
        }
        self.solver.check()
    }
}
