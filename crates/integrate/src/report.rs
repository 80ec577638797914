//! What an integration cost and what error it estimates.

use std::fmt;

/// The cost and error estimate of an integration. Counters add up over every call on the same integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The method's public name.
    pub method: &'static str,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts.
    pub rejected: usize,
    /// Right-hand-side evaluations, including those for finite-difference Jacobians, the initial-step guess and
    /// euler-variable's df/dt. For the symplectic methods: force (velocity-rate) evaluations.
    pub rhs_evals: usize,
    /// Jacobian evaluations (analytic or by finite differences).
    pub jacobians: usize,
    /// LU factorizations of the iteration matrix.
    pub factorizations: usize,
    /// Solves with a factorized iteration matrix.
    pub linear_solves: usize,
    /// Newton iterations (implicit Euler in Newton mode, Radau5).
    pub newton_iterations: usize,
    /// Iterations of the iterative linear solver.
    pub krylov_iterations: usize,
    /// Restarts of a multistep history (AB4, AM4) after a change of step.
    pub restarts: usize,
    /// Smallest accepted step (infinity before the first step).
    pub min_step: f64,
    /// Largest accepted step.
    pub max_step: f64,
    /// Wall-clock seconds spent inside the integrator.
    pub wall_seconds: f64,
    /// Sum over accepted steps of the estimated local error (max norm), where the method estimates it: the
    /// embedded difference (dopri5, rodas4), Milne's estimate (am4), the doubling difference divided by
    /// 2^p - 1 (step doubling), h^2/2 ||df/dt|| (euler-variable). A first-order guess of the global error that
    /// ignores how errors propagate. `None` for methods without an estimate.
    pub error_estimate: Option<f64>,
}

impl Report {
    pub(crate) fn new(method: &'static str) -> Self {
        Report {
            method,
            steps: 0,
            rejected: 0,
            rhs_evals: 0,
            jacobians: 0,
            factorizations: 0,
            linear_solves: 0,
            newton_iterations: 0,
            krylov_iterations: 0,
            restarts: 0,
            min_step: f64::INFINITY,
            max_step: 0.0,
            wall_seconds: 0.0,
            error_estimate: None,
        }
    }

    /// An empty report for `method`.
    pub fn empty(method: &'static str) -> Self {
        Report::new(method)
    }

    /// Adds another report's counts, step range, time and error estimate to this one.
    pub fn merge(&mut self, o: &Report) {
        self.steps += o.steps;
        self.rejected += o.rejected;
        self.rhs_evals += o.rhs_evals;
        self.jacobians += o.jacobians;
        self.factorizations += o.factorizations;
        self.linear_solves += o.linear_solves;
        self.newton_iterations += o.newton_iterations;
        self.krylov_iterations += o.krylov_iterations;
        self.restarts += o.restarts;
        self.min_step = self.min_step.min(o.min_step);
        self.max_step = self.max_step.max(o.max_step);
        self.wall_seconds += o.wall_seconds;
        self.error_estimate = match (self.error_estimate, o.error_estimate) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(0.0) + b.unwrap_or(0.0)),
        };
        if self.steps == o.steps {
            self.method = o.method;
        }
    }

    pub(crate) fn record_step(&mut self, h: f64, local_error: Option<f64>) {
        self.steps += 1;
        self.min_step = self.min_step.min(h);
        self.max_step = self.max_step.max(h);
        if let Some(e) = local_error {
            *self.error_estimate.get_or_insert(0.0) += e;
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "method           {}", self.method)?;
        writeln!(f, "steps            {} accepted, {} rejected", self.steps, self.rejected)?;
        writeln!(f, "rhs evaluations  {}", self.rhs_evals)?;
        writeln!(
            f,
            "linear algebra   {} jacobians, {} factorizations, {} solves, {} newton iterations, {} krylov iterations",
            self.jacobians, self.factorizations, self.linear_solves, self.newton_iterations, self.krylov_iterations
        )?;
        if self.steps > 0 {
            writeln!(f, "step size        {:.3e} .. {:.3e}", self.min_step, self.max_step)?;
        }
        writeln!(f, "integrator time  {:.6} s", self.wall_seconds)?;
        match self.error_estimate {
            Some(e) => write!(
                f,
                "error estimate   {e:.3e} (the accepted steps' local error estimates summed: max norm over the \
                 state, in its units, metres for positions)"
            ),
            None => write!(f, "error estimate   none (the method has no estimate)"),
        }
    }
}
