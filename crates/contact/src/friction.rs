//! Time stepping with Coulomb friction as a velocity-level conic program (Anitescu's convex model), per island:
//! min 1/2 |v - v*|_M^2 over the bodies' velocities v, subject to (J_n v + beta, mu J_t v) in a second-order cone at
//! each contact (frictionless: J_n v + beta >= 0). v* is the velocity the applied forces alone would give after the
//! step; beta carries restitution and penetration correction; the impulses come back as the cone duals:
//! normal p_n = z_0, friction p_t = mu (z_1, z_2).
//!
//! The convex model's known artefact: while sliding, the cone makes the contact separate at mu |v_t|, and the
//! tangential velocity ends at (v*_t + mu v*_n) / (1 + mu^2) instead of Coulomb's v*_t + mu v*_n. The remedy
//! (`velocity_step_lagged`, Drake's "lagged" approximation): the normal constraint stays J_n v + beta >= 0 and each
//! contact's friction impulse is bounded by mu times a given normal impulse (the previous step's), which makes
//! friction a norm term mu p_prev |J_t v| in the objective (an epigraph variable per contact and a cone
//! (s, J_t v)); sliding then decelerates at exactly mu g and nothing hops.

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use crate::friction_island::{bias, solve_island, IslandSolution};
use crate::impulse::BodyVelocity;
use crate::islands::islands;
use crate::lcp::SolverSettings;
use nalgebra::Vector3;

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
}

impl StepSettings {
    /// Defaults for step `dt`: erp 0.2, bounce threshold 0.05 m/s, the default solver settings.
    pub fn new(dt: f64) -> StepSettings {
        StepSettings { dt, erp: 0.2, bounce_threshold: 0.05, solver: SolverSettings::default() }
    }

    fn check(&self) -> Result<(), ContactError> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(ContactError::invalid("dt", format!("must be finite and > 0, got {}", self.dt)));
        }
        if !(0.0..=1.0).contains(&self.erp) {
            return Err(ContactError::invalid("erp", format!("must be in [0, 1], got {}", self.erp)));
        }
        if !(self.bounce_threshold.is_finite() && self.bounce_threshold >= 0.0) {
            return Err(ContactError::invalid("bounce_threshold", "must be finite and >= 0"));
        }
        self.solver.check()
    }
}

/// The outcome of a time step's velocity solve.
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityStep {
    /// Every body's velocities at the end of the step.
    pub velocities: Vec<BodyVelocity>,
    /// Normal impulse at each contact (>= 0).
    pub normal_impulses: Vec<f64>,
    /// Friction impulse at each contact (world vector on B, tangent to the contact, length <= mu p_n).
    pub friction_impulses: Vec<Vector3<f64>>,
    /// clarabel iterations, summed over islands.
    pub iterations: u32,
    /// clarabel calls (a lone particle on something static is solved in closed form).
    pub solver_calls: usize,
}

/// The velocity each body would have after the step under its applied force and torque alone (explicit gyroscopic
/// term).
pub(crate) fn free_velocity(b: &BodyState, h: f64) -> BodyVelocity {
    if !b.is_dynamic() {
        return BodyVelocity { linear: b.velocity, angular: b.angular_velocity };
    }
    let w = b.angular_velocity;
    BodyVelocity {
        linear: b.velocity + b.force * (b.inv_mass * h),
        angular: w + b.inv_inertia * (b.torque - w.cross(&(b.inertia * w))) * h,
    }
}

/// Velocities after one step of `settings.dt`, with contact, friction (Anitescu's cone) and restitution.
pub fn velocity_step(
    bodies: &[BodyState],
    contacts: &[Contact],
    settings: &StepSettings,
) -> Result<VelocityStep, ContactError> {
    step(bodies, contacts, None, settings)
}

/// Velocities after one step with friction lagged on `previous[i]`, a normal impulse for each contact (the last
/// step's, or 0 for a new contact): contact i's friction impulse is at most mu_i previous[i].
pub fn velocity_step_lagged(
    bodies: &[BodyState],
    contacts: &[Contact],
    previous: &[f64],
    settings: &StepSettings,
) -> Result<VelocityStep, ContactError> {
    if previous.len() != contacts.len() {
        return Err(ContactError::invalid(
            "previous",
            format!("needs one impulse per contact: {} for {} contacts", previous.len(), contacts.len()),
        ));
    }
    if let Some(i) = previous.iter().position(|p| !(p.is_finite() && *p >= 0.0)) {
        return Err(ContactError::invalid(
            "previous",
            format!("impulse {i} must be finite and >= 0, got {}", previous[i]),
        ));
    }
    step(bodies, contacts, Some(previous), settings)
}

fn step(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    settings: &StepSettings,
) -> Result<VelocityStep, ContactError> {
    check_all(bodies, contacts)?;
    settings.check()?;
    let mut velocities: Vec<BodyVelocity> = bodies.iter().map(|b| free_velocity(b, settings.dt)).collect();
    let mut normal_impulses = vec![0.0; contacts.len()];
    let mut friction_impulses = vec![Vector3::zeros(); contacts.len()];
    let (mut iterations, mut solver_calls) = (0, 0);
    for island in islands(bodies, contacts) {
        let lone = if island.len() == 1 {
            lone_particle(bodies, contacts, bounds, island[0], &velocities, settings)
        } else {
            None
        };
        let sol = match lone {
            Some(sol) => sol,
            None => {
                solver_calls += 1;
                solve_island(bodies, contacts, bounds, &island, &velocities, settings)?
            }
        };
        for (k, v) in sol.velocities {
            velocities[k] = v;
        }
        for (slot, &i) in island.iter().enumerate() {
            normal_impulses[i] = sol.normal[slot];
            friction_impulses[i] = sol.friction[slot];
        }
        iterations += sol.iterations;
    }
    Ok(VelocityStep { velocities, normal_impulses, friction_impulses, iterations, solver_calls })
}

/// The closed form for one particle touching something static, frictionless or with lagged friction: the normal
/// velocity is raised to the constraint's bound, and the tangential one shrinks by at most bound / m (stops if it
/// can). With isotropic mass the two directions decouple, so this is the conic program's exact answer.
fn lone_particle(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    i: usize,
    free: &[BodyVelocity],
    s: &StepSettings,
) -> Option<IslandSolution> {
    let c = &contacts[i];
    let (k, other, sign) = match (bodies[c.a].is_dynamic(), bodies[c.b].is_dynamic()) {
        (false, true) => (c.b, c.a, 1.0),
        (true, false) => (c.a, c.b, -1.0),
        _ => return None,
    };
    let friction_bound = match bounds {
        _ if c.friction == 0.0 => 0.0,
        Some(b) => c.friction * b[i],
        None => return None,
    };
    if bodies[k].rotates() {
        return None;
    }
    let m = 1.0 / bodies[k].inv_mass;
    let n = c.normal.into_inner() * sign;
    let o = &bodies[other];
    let ground = free[other].linear + free[other].angular.cross(&(c.point - o.position));
    let rel = free[k].linear - ground;
    let rn = n.dot(&rel);
    let vn = rn.max(-bias(c, bodies, s));
    let rt = rel - n * rn;
    let (speed, limit) = (rt.norm(), friction_bound / m);
    let vt = if speed <= limit { Vector3::zeros() } else { rt * (1.0 - limit / speed) };
    let linear = ground + n * vn + vt;
    let friction_on_particle = (vt - rt) * m;
    Some(IslandSolution {
        velocities: vec![(k, BodyVelocity { linear, angular: Vector3::zeros() })],
        normal: vec![m * (vn - rn)],
        friction: vec![friction_on_particle * sign],
        iterations: 0,
    })
}
