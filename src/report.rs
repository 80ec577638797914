//! What a world's steps cost: the integrator's report, how often each force loop ran, and the contact counters
//! (zero while a scene has no contact stage).

use crate::model::ForceCounters;
use std::fmt;
use tumble_integrate::Report;

/// The cost and accuracy of a world's steps.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldReport {
    /// The integrator's report: steps, rejections, evaluations, Jacobians, factorizations, time, error estimate.
    pub integrator: Report,
    /// How often each force loop ran.
    pub forces: ForceCounters,
    /// Contact QP solves.
    pub qp_solves: usize,
    /// Collisions resolved by impulses.
    pub collisions: usize,
    /// Bisection steps spent locating collision times.
    pub bisection_steps: usize,
    /// Largest penetration seen.
    pub max_penetration: f64,
}

impl WorldReport {
    pub(crate) fn new(method: &'static str) -> Self {
        WorldReport {
            integrator: Report::empty(method),
            forces: ForceCounters::default(),
            qp_solves: 0,
            collisions: 0,
            bisection_steps: 0,
            max_penetration: 0.0,
        }
    }

    pub(crate) fn merge(&mut self, o: &WorldReport) {
        self.integrator.merge(&o.integrator);
        self.forces += o.forces;
        self.qp_solves += o.qp_solves;
        self.collisions += o.collisions;
        self.bisection_steps += o.bisection_steps;
        self.max_penetration = self.max_penetration.max(o.max_penetration);
    }
}

impl fmt::Display for WorldReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.integrator)?;
        let c = &self.forces;
        writeln!(
            f,
            "force loops      {} evaluations: {} spring, {} load, {} callback; {} quaternion projections",
            c.evaluations, c.spring_evaluations, c.load_evaluations, c.callback_calls, c.projections
        )?;
        write!(
            f,
            "contact          {} qp solves, {} collisions, {} bisection steps, max penetration {:.3e}",
            self.qp_solves, self.collisions, self.bisection_steps, self.max_penetration
        )
    }
}
