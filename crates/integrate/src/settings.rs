//! What an integration is asked to do: the method, its step control, and the limits that turn a runaway run into
//! a clear error.

use crate::error::OdeError;
use crate::method::Method;
use crate::system::OdeSystem;

/// How the step size is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case", deny_unknown_fields))]
pub enum StepControl {
    /// Fixed step: each interval between stops (output times, the end) is divided into equal steps no longer
    /// than `dt`, so uniform outputs keep h constant and multistep histories alive.
    Fixed { dt: f64 },
    /// Error control with the method's own estimate (dopri5, rodas4, am4): the weighted RMS norm of the local
    /// error with weights `atol + rtol max(|y|, |y_new|)` is kept at or below 1.
    Tolerances { rtol: f64, atol: f64 },
    /// The chapter's step doubling around any one-step method: e = ||X(t+h) - X(two steps of h/2)||_2,
    /// accept when e <= tolerance, h_new = h (tolerance / e)^(1/(n+1)). `dt` is the first step.
    StepDoubling { tolerance: f64, dt: f64 },
    /// The chapter's variable-step Euler: h = sqrt(2 tolerance / ||df/dt||_2) (euler-variable only).
    Derivative { tolerance: f64 },
}

/// How implicit Euler treats its nonlinear equation X' = X + h f(X').
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case", deny_unknown_fields))]
pub enum NewtonMode {
    /// The chapter's single linearised step: dX = (I/h - J)^-1 f(X).
    Linearised,
    /// Full Newton iteration on the same system, the Jacobian re-evaluated at every iterate, until the
    /// correction satisfies ||dX||_inf <= tol (1 + ||X||_inf).
    Newton { tol: f64, max_iter: usize },
}

/// How implicit Euler solves its linear systems with a sparse Jacobian.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case", deny_unknown_fields))]
pub enum LinearSolver {
    /// Sparse LU (faer), symbolic analysis once. Exact; on 2-D meshes its fill-in makes the cost superlinear.
    Direct,
    /// BiCGSTAB with a diagonal preconditioner, stopped when the residual falls below `rtol` times the right-hand
    /// side: cost per iteration linear in the nonzeros, iterations bounded by the conditioning, not the size.
    Iterative { rtol: f64, max_iter: usize },
}

/// The configuration of one integration.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case", deny_unknown_fields))]
pub struct Settings {
    /// The method.
    pub method: Method,
    /// The step control.
    pub control: StepControl,
    /// Implicit Euler's treatment of the nonlinear equation.
    pub newton: NewtonMode,
    /// Implicit Euler's linear solver for sparse Jacobians.
    pub linear_solver: LinearSolver,
    /// Most steps (accepted and rejected) one call may take; 1e6 by default: enough for a million fixed steps, few
    /// enough that the costliest method (Radau5 on a small body) meets it in seconds rather than minutes.
    pub max_steps: usize,
    /// Smallest step an adaptive control may take (0: only the round-off limit 16 eps |t|).
    pub min_step: f64,
    /// Largest step an adaptive control may take.
    #[cfg_attr(feature = "serde", serde(with = "crate::float_serde"))]
    pub max_step: f64,
    /// First step of an adaptive control (None: chosen automatically).
    pub initial_step: Option<f64>,
    /// A state whose max norm exceeds this is reported as [`OdeError::Divergence`].
    #[cfg_attr(feature = "serde", serde(with = "crate::float_serde"))]
    pub divergence_limit: f64,
    /// Interpolate output times with the method's dense output where it has one (dopri5, rodas4); otherwise
    /// every output time is a step stop.
    pub dense_output: bool,
}

impl Settings {
    fn with_control(method: Method, control: StepControl) -> Self {
        Settings {
            method,
            control,
            newton: NewtonMode::Linearised,
            linear_solver: LinearSolver::Direct,
            max_steps: 1_000_000,
            min_step: 0.0,
            max_step: f64::INFINITY,
            initial_step: None,
            divergence_limit: 1e100,
            dense_output: true,
        }
    }

    /// A fixed step `dt`.
    pub fn fixed(method: Method, dt: f64) -> Self {
        Self::with_control(method, StepControl::Fixed { dt })
    }

    /// Error control by the method's own estimate (dopri5, rodas4, am4).
    pub fn tolerances(method: Method, rtol: f64, atol: f64) -> Self {
        Self::with_control(method, StepControl::Tolerances { rtol, atol })
    }

    /// The chapter's step doubling with per-step error `tolerance`, first step `dt`.
    pub fn step_doubling(method: Method, tolerance: f64, dt: f64) -> Self {
        Self::with_control(method, StepControl::StepDoubling { tolerance, dt })
    }

    /// The chapter's variable-step Euler with per-step error `tolerance`.
    pub fn euler_variable(tolerance: f64) -> Self {
        Self::with_control(Method::EulerVariable, StepControl::Derivative { tolerance })
    }

    /// Sets implicit Euler's Newton mode.
    pub fn newton(mut self, newton: NewtonMode) -> Self {
        self.newton = newton;
        self
    }

    /// Sets implicit Euler's linear solver for sparse Jacobians.
    pub fn linear_solver(mut self, solver: LinearSolver) -> Self {
        self.linear_solver = solver;
        self
    }

    /// Sets the step budget of one call.
    pub fn max_steps(mut self, max_steps: usize) -> Self {
        self.max_steps = max_steps;
        self
    }

    /// Sets the smallest adaptive step.
    pub fn min_step(mut self, min_step: f64) -> Self {
        self.min_step = min_step;
        self
    }

    /// Sets the largest adaptive step.
    pub fn max_step(mut self, max_step: f64) -> Self {
        self.max_step = max_step;
        self
    }

    /// Sets the first adaptive step.
    pub fn initial_step(mut self, h0: f64) -> Self {
        self.initial_step = Some(h0);
        self
    }

    /// Sets the divergence limit on the state's max norm.
    pub fn divergence_limit(mut self, limit: f64) -> Self {
        self.divergence_limit = limit;
        self
    }

    /// Turns dense output on or off.
    pub fn dense_output(mut self, on: bool) -> Self {
        self.dense_output = on;
        self
    }

    /// The tolerances that weight error norms (also used by Newton's convergence test).
    pub(crate) fn weights(&self) -> (f64, f64) {
        match self.control {
            StepControl::Tolerances { rtol, atol } => (rtol, atol),
            _ => (1e-10, 1e-10),
        }
    }

    /// Checks every setting against the method and the system; the error names the offending setting.
    pub fn validate(&self, system: &(impl OdeSystem + ?Sized)) -> Result<(), OdeError> {
        let m = self.method;
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(OdeError::invalid(name, format!("must be finite and > 0, got {v}")))
            }
        };
        let unsupported = |reason: &str| Err(OdeError::Unsupported { method: m.name(), reason: reason.into() });
        match self.control {
            StepControl::Fixed { dt } => {
                positive("dt", dt)?;
                if m == Method::EulerVariable {
                    return unsupported("it chooses its own step; use StepControl::Derivative");
                }
            }
            StepControl::Tolerances { rtol, atol } => {
                for (name, v) in [("rtol", rtol), ("atol", atol)] {
                    if !(v.is_finite() && v >= 0.0) {
                        return Err(OdeError::invalid(name, format!("must be finite and >= 0, got {v}")));
                    }
                }
                if rtol < 1e-15 && atol == 0.0 {
                    return Err(OdeError::invalid("rtol", "rtol < 1e-15 with atol = 0 cannot be met in f64"));
                }
                if !m.has_error_estimate() {
                    return unsupported("it has no error estimate; use a fixed step or step doubling");
                }
            }
            StepControl::StepDoubling { tolerance, dt } => {
                positive("tolerance", tolerance)?;
                positive("dt", dt)?;
                if !m.is_one_step() {
                    return unsupported("step doubling needs a one-step method");
                }
            }
            StepControl::Derivative { tolerance } => {
                positive("tolerance", tolerance)?;
                if m != Method::EulerVariable {
                    return unsupported("StepControl::Derivative belongs to euler-variable");
                }
            }
        }
        if m == Method::EulerVariable && !matches!(self.control, StepControl::Derivative { .. }) {
            return unsupported("euler-variable needs StepControl::Derivative");
        }
        if let NewtonMode::Newton { tol, max_iter } = self.newton {
            positive("newton tol", tol)?;
            if max_iter == 0 {
                return Err(OdeError::invalid("newton max_iter", "must be >= 1"));
            }
        }
        if let LinearSolver::Iterative { rtol, max_iter } = self.linear_solver {
            if !(rtol > 0.0 && rtol < 1.0) {
                return Err(OdeError::invalid("linear_solver rtol", format!("must be in (0, 1), got {rtol}")));
            }
            if max_iter == 0 {
                return Err(OdeError::invalid("linear_solver max_iter", "must be >= 1"));
            }
        }
        if self.max_steps == 0 {
            return Err(OdeError::invalid("max_steps", "must be >= 1"));
        }
        if !(self.min_step.is_finite() && self.min_step >= 0.0) {
            return Err(OdeError::invalid("min_step", format!("must be finite and >= 0, got {}", self.min_step)));
        }
        if !(self.max_step > 0.0) || self.max_step < self.min_step {
            return Err(OdeError::invalid("max_step", format!("must be > 0 and >= min_step, got {}", self.max_step)));
        }
        if let Some(h0) = self.initial_step {
            positive("initial_step", h0)?;
        }
        if !(self.divergence_limit > 0.0) {
            return Err(OdeError::invalid("divergence_limit", "must be > 0"));
        }
        if m.needs_split() {
            match system.split() {
                None => return unsupported("it needs a (q, p) split: implement OdeSystem::split or use FirstOrder"),
                Some(s) if s.positions > system.dim() => {
                    return Err(OdeError::invalid("split", "more positions than the state has"));
                }
                Some(_) => {}
            }
        }
        Ok(())
    }
}
