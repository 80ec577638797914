//! Time stepping with Coulomb friction as a velocity-level conic program (Anitescu's convex model), per island:
//! min 1/2 |v - v*|_M^2 over the bodies' velocities v, subject to (J_n v + beta, mu J_t v) in a second-order cone at
//! each contact (frictionless: J_n v + beta >= 0). v* is the velocity the applied forces alone would give after the
//! step; beta carries restitution and penetration correction; the impulses come back as the cone duals:
//! normal p_n = z_0, friction p_t = mu (z_1, z_2).
//!
//! The convex model's known artefact: while sliding, the cone makes the contact separate at mu |v_t|, and the
//! tangential velocity ends at (v*_t + mu v*_n) / (1 + mu^2) instead of Coulomb's v*_t + mu v*_n. The remedy
//! (`VelocityProblem::lagged`, Drake's "lagged" approximation): the normal constraint stays J_n v + beta >= 0 and each
//! contact's friction impulse is bounded by mu times a given normal impulse (the previous step's), which makes
//! friction a norm term mu p_prev |J_t v| in the objective (an epigraph variable per contact and a cone
//! (s, J_t v)); sliding then decelerates at exactly mu g and nothing hops.

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use crate::friction_island::{bias, solve_island, IslandSolution};
use crate::impulse::BodyVelocity;
use crate::lcp::SolverSettings;
use crate::threads::in_parallel_by;
use nalgebra::Vector3;
use std::collections::BTreeMap;

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
}

/// How a velocity step's islands are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StepMethod {
    /// The multiplier method with Newton's method on the velocities (`newton_island.rs`): exact optimality
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
        }
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
        if !(self.velocity_scale.is_finite() && self.velocity_scale >= 0.0) {
            return Err(ContactError::invalid("velocity_scale", "must be finite and >= 0"));
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
    /// Impulse of each joint row (`VelocityProblem::bilateral`, in its order; a row's J^T times it acts on the
    /// bodies).
    pub joint_impulses: Vec<f64>,
    /// Solver iterations (clarabel's, or the Newton method's), summed over islands.
    pub iterations: u32,
    /// Solver calls (a lone particle on something static is solved in closed form, and an island no contact of
    /// which needs an impulse without a solve).
    pub solver_calls: usize,
    /// Of those, the islands the Newton method answered (the rest went to clarabel).
    pub newton_calls: usize,
    /// The islands the contacts and joint rows split into.
    pub islands: usize,
    /// The calls weighted by size, for callers that budget their work: each call counts one for every
    /// `CONTACTS_A_UNIT` contacts of its island (at least one), its cost growing with the island.
    pub solver_work: usize,
    /// Wall time spent building the islands' programs (s): their rows, Jacobians and the Newton method's Hessian
    /// structure, or clarabel's matrices; summed over islands.
    pub building_seconds: f64,
}

/// Contacts of an island that one unit of `VelocityStep::solver_work` stands for.
pub const CONTACTS_A_UNIT: usize = 8;

/// The velocity a body would have after a step of `h` under its applied force and torque alone (explicit gyroscopic
/// term); a static body keeps its velocity.
pub fn free_velocity(b: &BodyState, h: f64) -> BodyVelocity {
    if !b.is_dynamic() {
        return BodyVelocity { linear: b.velocity, angular: b.angular_velocity };
    }
    let w = b.angular_velocity;
    BodyVelocity {
        linear: b.velocity + b.force * (b.inv_mass * h),
        angular: w + b.inv_inertia * (b.torque - w.cross(&(b.inertia * w))) * h,
    }
}

/// How a joint row of a velocity step holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BilateralKind {
    /// J v = speed, any impulse.
    Equal,
    /// J v >= speed, an impulse >= 0 (a limit, a rope).
    AtLeast,
    /// J v = speed as far as an impulse within +-max_impulse reaches (a motor).
    Motor { max_impulse: f64 },
}

/// One joint row of a velocity step: J v = lin . (v_B - v_A) + ang_a . w_A + ang_b . w_B against `speed` at the
/// step's end, as `kind` says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilateralRow {
    pub a: usize,
    pub b: usize,
    pub lin: Vector3<f64>,
    pub ang_a: Vector3<f64>,
    pub ang_b: Vector3<f64>,
    pub speed: f64,
    pub kind: BilateralKind,
}

/// What one velocity step solves: the bodies, their contacts, how friction is bounded, and joint rows held exactly
/// in the same programs (bodies joined by a row share an island).
#[derive(Clone, Copy, Debug, Default)]
pub struct VelocityProblem<'a> {
    pub bodies: &'a [BodyState],
    pub contacts: &'a [Contact],
    /// `None`: Anitescu's cone. `Some(normals)`: friction lagged, contact i's friction impulse at most mu_i
    /// normals[i] (a normal impulse for each contact: the last step's, or 0 for a new contact).
    pub lagged: Option<&'a [f64]>,
    pub bilateral: &'a [BilateralRow],
    /// Impulses to start the Newton method from, one world vector per contact (on B: normal and friction
    /// together), such as the last step's scaled to this one; `None` starts from the lagged normal impulses.
    /// They change how fast the answer is found, not the answer.
    pub warm: Option<&'a [Vector3<f64>]>,
}

impl<'a> VelocityProblem<'a> {
    /// The bodies and their contacts, friction by the cone, no joint rows.
    pub fn new(bodies: &'a [BodyState], contacts: &'a [Contact]) -> Self {
        VelocityProblem { bodies, contacts, lagged: None, bilateral: &[], warm: None }
    }

    /// Friction lagged on these normal impulses, one per contact.
    pub fn lagged(self, normals: &'a [f64]) -> Self {
        VelocityProblem { lagged: Some(normals), ..self }
    }

    /// Joint rows held in the same programs.
    pub fn bilateral(self, rows: &'a [BilateralRow]) -> Self {
        VelocityProblem { bilateral: rows, ..self }
    }

    /// The Newton method started from these impulses, one per contact.
    pub fn warm(self, impulses: &'a [Vector3<f64>]) -> Self {
        VelocityProblem { warm: Some(impulses), ..self }
    }

    fn check(&self) -> Result<(), ContactError> {
        if let Some(lagged) = self.lagged {
            if lagged.len() != self.contacts.len() {
                return Err(ContactError::invalid(
                    "lagged",
                    format!("needs one impulse per contact: {} for {} contacts", lagged.len(), self.contacts.len()),
                ));
            }
            if let Some(i) = lagged.iter().position(|p| !(p.is_finite() && *p >= 0.0)) {
                return Err(ContactError::invalid(
                    "lagged",
                    format!("impulse {i} must be finite and >= 0, got {}", lagged[i]),
                ));
            }
        }
        if let Some(warm) = self.warm {
            if warm.len() != self.contacts.len() {
                return Err(ContactError::invalid(
                    "warm",
                    format!("needs one impulse per contact: {} for {} contacts", warm.len(), self.contacts.len()),
                ));
            }
            if let Some(i) = warm.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
                return Err(ContactError::invalid("warm", format!("impulse {i} is not finite")));
            }
        }
        for (k, r) in self.bilateral.iter().enumerate() {
            let numbers = [r.lin, r.ang_a, r.ang_b].into_iter().flat_map(|v| [v.x, v.y, v.z]);
            let bound = match r.kind {
                BilateralKind::Motor { max_impulse } => max_impulse,
                _ => 0.0,
            };
            let mut numbers = numbers.chain([r.speed]).chain([bound]);
            let bodies = self.bodies.len();
            if r.a >= bodies || r.b >= bodies || r.a == r.b || !numbers.all(f64::is_finite) || bound < 0.0 {
                return Err(ContactError::invalid(
                    "bilateral",
                    format!("row {k} is not a finite row between two bodies"),
                ));
            }
        }
        Ok(())
    }
}

/// Velocities after one step of `settings.dt` with contact, friction and restitution (and joint rows), one conic
/// program per island.
pub fn velocity_step(problem: &VelocityProblem<'_>, settings: &StepSettings) -> Result<VelocityStep, ContactError> {
    problem.check()?;
    step(problem, settings, true)
}

/// One step; `apart_alone`: islands joined only by contacts apart and unbound are solved apart until an answer
/// closes such a contact (false joins them from the start: the reference the tests hold the split to).
fn step(
    problem: &VelocityProblem<'_>,
    settings: &StepSettings,
    apart_alone: bool,
) -> Result<VelocityStep, ContactError> {
    let VelocityProblem { bodies, contacts, lagged: bounds, bilateral, warm } = *problem;
    check_all(bodies, contacts)?;
    settings.check()?;
    // rolling and torsional resistance: bounded rows after the joints' (their impulses are not reported)
    let joint_rows = bilateral.len();
    let with_resistance: Vec<BilateralRow>;
    let bilateral = match bounds {
        Some(b) if contacts.iter().any(|c| c.rolling_resistance > 0.0 || c.torsional_resistance > 0.0) => {
            let mut rows = bilateral.to_vec();
            for (c, &bound) in contacts.iter().zip(b) {
                crate::resistance::resistance_rows(c, bodies, bound, &mut rows);
            }
            with_resistance = rows;
            &with_resistance[..]
        }
        _ => bilateral,
    };
    let mut velocities: Vec<BodyVelocity> = bodies.iter().map(|b| free_velocity(b, settings.dt)).collect();
    let mut normal_impulses = vec![0.0; contacts.len()];
    let mut friction_impulses = vec![Vector3::zeros(); contacts.len()];
    let mut joint_impulses = vec![0.0; bilateral.len()];
    let (mut iterations, mut solver_calls, mut solver_work, mut newton_calls) = (0, 0, 0, 0);
    let mut building_seconds = 0.0;
    let pairs: Vec<(usize, usize)> = bilateral.iter().map(|r| (r.a, r.b)).collect();
    let unconstrained = velocities.clone();
    let free = &unconstrained;
    let solve = |(island, linked): &(Vec<usize>, Vec<usize>)| -> Result<IslandSolution, ContactError> {
        let rows: Vec<&BilateralRow> = linked.iter().map(|&k| &bilateral[k]).collect();
        let lone = if island.len() == 1 && rows.is_empty() {
            lone_particle(bodies, contacts, bounds, island[0], free, settings)
        } else {
            None
        };
        match lone {
            Some(sol) => Ok(sol),
            None => solve_island(bodies, contacts, bounds, island, &rows, free, settings, warm),
        }
    };
    // a clarabel call takes tens of microseconds or more: worth a thread from a few dozen contacts
    let size = |(island, linked): &(Vec<usize>, Vec<usize>)| island.len() + linked.len();
    let rows = contacts.len() + bilateral.len();
    // Islands joined only by contacts still apart, with no friction bound, whose bodies are not nearing (`nearing`)
    // are solved apart (a row of standing dominoes, each in reach of the next, is then two hundred small programs, not
    // one of 1200 velocities), and joined where the answer would close such a contact: an answer that keeps every
    // constraint left out is the joined program's own (adding a constraint it keeps changes no convex program's
    // optimum).
    let mut links: Vec<bool> = (0..contacts.len())
        .map(|i| {
            !apart_alone
                || !apart_and_unbound(&contacts[i], bounds.map(|b| b[i]))
                || nearing(&contacts[i], bodies, settings.dt)
        })
        .collect();
    let mut answers: BTreeMap<(Vec<usize>, Vec<usize>), IslandSolution> = BTreeMap::new();
    let groups = loop {
        let (groups, apart) = crate::islands::joint_islands(bodies, contacts, &pairs, &links);
        let new: Vec<(Vec<usize>, Vec<usize>)> = groups.iter().filter(|g| !answers.contains_key(*g)).cloned().collect();
        let solved = in_parallel_by(&new, size, (rows, 32), settings.threads, solve);
        for (group, result) in new.into_iter().zip(solved) {
            let sol = result?;
            solver_calls += usize::from(sol.solved);
            newton_calls += usize::from(sol.newton);
            if sol.solved {
                solver_work += group.0.len().div_ceil(CONTACTS_A_UNIT);
            }
            iterations += sol.iterations;
            building_seconds += sol.building_seconds;
            answers.insert(group, sol);
        }
        for group in &groups {
            for &(k, v) in &answers[group].velocities {
                velocities[k] = v;
            }
        }
        let closed: Vec<usize> =
            apart.into_iter().filter(|&i| closes(&contacts[i], bodies, &velocities, settings)).collect();
        if closed.is_empty() {
            break groups;
        }
        closed.into_iter().for_each(|i| links[i] = true);
        velocities.clone_from(&unconstrained);
    };
    for group in &groups {
        let (island, linked) = group;
        let sol = &answers[group];
        for (slot, &i) in island.iter().enumerate() {
            normal_impulses[i] = sol.normal[slot];
            friction_impulses[i] = sol.friction[slot];
        }
        for (&k, &p) in linked.iter().zip(&sol.joints) {
            joint_impulses[k] = p;
        }
    }
    let islands = groups.len();
    joint_impulses.truncate(joint_rows);
    Ok(VelocityStep {
        velocities,
        normal_impulses,
        friction_impulses,
        joint_impulses,
        iterations,
        solver_calls,
        newton_calls,
        islands,
        solver_work,
        building_seconds,
    })
}

/// Whether a contact may be left out of the programs until an answer closes it: apart (a positive gap) with no
/// friction bound (`bound`, its lagged normal impulse: none, or none pushing), so that left out it changes nothing.
fn apart_and_unbound(c: &Contact, bound: Option<f64>) -> bool {
    c.distance > 0.0 && (c.friction == 0.0 || bound.is_some_and(|b| b == 0.0))
}

/// Whether a contact apart may well close within the step: its gap within twice the distance its two points'
/// present speeds cover in the step (a domino tipping onto the next), joined from the start rather than solved
/// apart and joined again.
fn nearing(c: &Contact, bodies: &[BodyState], h: f64) -> bool {
    let speed = |k: usize| bodies[k].point_velocity(&c.point).norm();
    c.distance <= 2.0 * h * (speed(c.a) + speed(c.b))
}

/// Whether velocities `v` close contact `c` past its constraint (`closing`), beyond the solver's own tolerance of
/// the step's velocity scale, as `untouched` judges an island without a solve.
fn closes(c: &Contact, bodies: &[BodyState], v: &[BodyVelocity], s: &StepSettings) -> bool {
    closing(c, bodies, v, s) > s.solver.complementarity_tolerance * s.velocity_scale
}

/// How fast velocities `v` would close contact `c` past its constraint: minus its normal velocity plus its bias
/// (positive: the constraint is broken).
pub(crate) fn closing(c: &Contact, bodies: &[BodyState], v: &[BodyVelocity], s: &StepSettings) -> f64 {
    let point = |k: usize| v[k].linear + v[k].angular.cross(&(c.point - bodies[k].position));
    -(c.normal.dot(&(point(c.b) - point(c.a))) + bias(c, bodies, s))
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
        solved: false,
        newton: false,
        building_seconds: 0.0,
        joints: Vec::new(),
    })
}

#[cfg(test)]
#[path = "friction_tests.rs"]
mod tests;
