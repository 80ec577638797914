//! What a world's steps cost: the integrator's report, how often each force loop ran, and the contact counters
//! (zero while a scene has no contact stage, or a stage never ran).

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
    /// Contact QP or conic-program solves (clarabel calls).
    pub qp_solves: usize,
    /// Collisions resolved: contacts that met closing faster than the resting (accurate) or bounce (fast) speed.
    pub collisions: usize,
    /// Contacts that received an impulse.
    pub impulses: usize,
    /// Bisection steps spent locating collision times (accurate mode).
    pub bisection_steps: usize,
    /// Narrow-phase pair tests (pairs whose boxes overlapped).
    pub collision_checks: usize,
    /// Contact islands solved.
    pub islands: usize,
    /// Actors asleep at the end of the last step (fast mode).
    pub sleepers: usize,
    /// Largest penetration seen (m).
    pub max_penetration: f64,
    /// Wall time spent finding contacts (s).
    pub collision_seconds: f64,
    /// Wall time spent in contact solves (s).
    pub contact_seconds: f64,
}

impl WorldReport {
    pub(crate) fn new(method: &'static str) -> Self {
        WorldReport {
            integrator: Report::empty(method),
            forces: ForceCounters::default(),
            qp_solves: 0,
            collisions: 0,
            impulses: 0,
            bisection_steps: 0,
            collision_checks: 0,
            islands: 0,
            sleepers: 0,
            max_penetration: 0.0,
            collision_seconds: 0.0,
            contact_seconds: 0.0,
        }
    }

    pub(crate) fn merge(&mut self, o: &WorldReport) {
        self.integrator.merge(&o.integrator);
        self.forces += o.forces;
        self.merge_contact(o);
        self.islands += o.islands;
        self.sleepers = o.sleepers;
    }

    /// Adds the contact counters of `o` (collisions, impulses, bisection steps, checks, QP solves, penetration,
    /// times), leaving the integrator's, the force loops', islands and sleepers alone.
    pub(crate) fn merge_contact(&mut self, o: &WorldReport) {
        self.qp_solves += o.qp_solves;
        self.collisions += o.collisions;
        self.impulses += o.impulses;
        self.bisection_steps += o.bisection_steps;
        self.collision_checks += o.collision_checks;
        self.max_penetration = self.max_penetration.max(o.max_penetration);
        self.collision_seconds += o.collision_seconds;
        self.contact_seconds += o.contact_seconds;
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
        writeln!(
            f,
            "contact          {} collision checks, {} collisions, {} impulses, {} bisection steps, {} qp solves over {} islands",
            self.collision_checks, self.collisions, self.impulses, self.bisection_steps, self.qp_solves, self.islands
        )?;
        write!(
            f,
            "                 max penetration {:.3e} m, {} asleep; {:.3} s finding contacts, {:.3} s solving them",
            self.max_penetration, self.sleepers, self.collision_seconds, self.contact_seconds
        )
    }
}
