//! Time stepping with Coulomb friction as a velocity-level conic program (Anitescu's convex model), per island:
//! min 1/2 |v - v*|_M^2 over the bodies' velocities v, subject to (J_n v + beta, mu J_t v) in a second-order cone at
//! each contact (frictionless: J_n v + beta >= 0). v* is the velocity the applied forces alone would give after the
//! step; beta carries restitution and penetration correction; the impulses come back as the cone duals:
//! normal p_n = z_0, friction p_t = mu (z_1, z_2).
//!
//! The convex model's known artefact: while sliding, the cone makes the contact separate at mu |v_t|, and the
//! tangential velocity ends at (v*_t + mu v*_n) / (1 + mu^2) instead of Coulomb's v*_t + mu v*_n.

use crate::body::BodyState;
use crate::contact::{check_all, tangents, Contact};
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use crate::islands::islands;
use crate::jacobian::{rows, Row};
use crate::lcp::{usable, with_retries, SolverSettings};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SupportedConeT};
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
}

/// The velocity each body would have after the step under its applied force and torque alone (explicit gyroscopic
/// term).
fn free_velocity(b: &BodyState, h: f64) -> BodyVelocity {
    if !b.is_dynamic() {
        return BodyVelocity { linear: b.velocity, angular: b.angular_velocity };
    }
    let w = b.angular_velocity;
    BodyVelocity {
        linear: b.velocity + b.force * (b.inv_mass * h),
        angular: w + b.inv_inertia * (b.torque - w.cross(&(b.inertia * w))) * h,
    }
}

/// Velocities after one step of `settings.dt`, with contact, friction and restitution.
pub fn velocity_step(
    bodies: &[BodyState],
    contacts: &[Contact],
    settings: &StepSettings,
) -> Result<VelocityStep, ContactError> {
    check_all(bodies, contacts)?;
    settings.check()?;
    let mut velocities: Vec<BodyVelocity> = bodies.iter().map(|b| free_velocity(b, settings.dt)).collect();
    let mut normal_impulses = vec![0.0; contacts.len()];
    let mut friction_impulses = vec![Vector3::zeros(); contacts.len()];
    let mut iterations = 0;
    for island in islands(bodies, contacts) {
        let sol = solve_island(bodies, contacts, &island, &velocities, settings)?;
        for (k, v) in sol.velocities {
            velocities[k] = v;
        }
        for (slot, &i) in island.iter().enumerate() {
            normal_impulses[i] = sol.normal[slot];
            friction_impulses[i] = sol.friction[slot];
        }
        iterations += sol.iterations;
    }
    Ok(VelocityStep { velocities, normal_impulses, friction_impulses, iterations })
}

#[derive(Clone)]
struct IslandSolution {
    velocities: Vec<(usize, BodyVelocity)>,
    normal: Vec<f64>,
    friction: Vec<Vector3<f64>>,
    iterations: u32,
}

/// The constraint bias of a contact: speculative gap or penetration correction, and restitution.
fn bias(c: &Contact, bodies: &[BodyState], s: &StepSettings) -> f64 {
    let h = s.dt;
    let v_minus = c.relative_normal_velocity(bodies);
    let by_gap = if c.distance > 0.0 { c.distance / h } else { s.erp * c.distance / h };
    let closes_this_step = c.distance + h * v_minus <= 0.0;
    if c.restitution > 0.0 && v_minus < -s.bounce_threshold && closes_this_step {
        by_gap.min(c.restitution * v_minus)
    } else {
        by_gap
    }
}

fn solve_island(
    bodies: &[BodyState],
    contacts: &[Contact],
    island: &[usize],
    free: &[BodyVelocity],
    s: &StepSettings,
) -> Result<IslandSolution, ContactError> {
    // Variables: 3 per moving particle, 6 per moving rigid body.
    let mut offset = vec![usize::MAX; bodies.len()];
    let mut members = Vec::new();
    let mut n = 0;
    for &i in island {
        for k in [contacts[i].a, contacts[i].b] {
            if bodies[k].is_dynamic() && offset[k] == usize::MAX {
                offset[k] = n;
                members.push(k);
                n += if bodies[k].rotates() { 6 } else { 3 };
            }
        }
    }
    // P = M (upper triangle), q = -M v*.
    let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
    let mut q = vec![0.0; n];
    for &k in &members {
        let (b, o, v) = (&bodies[k], offset[k], &free[k]);
        let m = 1.0 / b.inv_mass;
        for d in 0..3 {
            pi.push(o + d);
            pj.push(o + d);
            pv.push(m);
            q[o + d] = -m * v.linear[d];
        }
        if b.rotates() {
            let iw = b.inertia * v.angular;
            for r in 0..3 {
                q[o + 3 + r] = -iw[r];
                for c in r..3 {
                    pi.push(o + 3 + r);
                    pj.push(o + 3 + c);
                    pv.push(b.inertia[(r, c)]);
                }
            }
        }
    }
    // Constraints A x + s = b, s in the cones; one block of rows per contact.
    let (mut ai, mut aj, mut av) = (Vec::new(), Vec::new(), Vec::new());
    let mut rhs = Vec::new();
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    let mut put_row = |row_index: usize, scale: f64, pair: &[Row; 2], rhs: &mut Vec<f64>| {
        let mut constant = 0.0;
        for r in pair {
            let b = &bodies[r.body];
            if !b.is_dynamic() {
                constant += scale * (r.lin.dot(&free[r.body].linear) + r.ang.dot(&free[r.body].angular));
                continue;
            }
            let o = offset[r.body];
            for d in 0..3 {
                ai.push(row_index);
                aj.push(o + d);
                av.push(-scale * r.lin[d]);
                if b.rotates() {
                    ai.push(row_index);
                    aj.push(o + 3 + d);
                    av.push(-scale * r.ang[d]);
                }
            }
        }
        rhs[row_index] += constant;
    };
    for &i in island {
        let c = &contacts[i];
        let nrm = c.normal.into_inner();
        let row0 = rhs.len();
        let width = if c.friction > 0.0 { 3 } else { 1 };
        rhs.extend(std::iter::repeat_n(0.0, width));
        rhs[row0] = bias(c, bodies, s);
        put_row(row0, 1.0, &rows(c, bodies, &nrm), &mut rhs);
        if c.friction > 0.0 {
            let (t1, t2) = tangents(&nrm);
            put_row(row0 + 1, c.friction, &rows(c, bodies, &t1), &mut rhs);
            put_row(row0 + 2, c.friction, &rows(c, bodies, &t2), &mut rhs);
            cones.push(SecondOrderConeT(3));
        } else {
            cones.push(NonnegativeConeT(1));
        }
    }
    let m = rhs.len();
    let p = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
    let a = CscMatrix::new_from_triplets(m, n, ai, aj, av);
    let problem = "friction-step";
    let (solution, _, iterations) = with_retries(&s.solver, problem, |settings| {
        let mut solver = DefaultSolver::new(&p, &q, &a, &rhs, &cones, settings.clarabel(problem)?)
            .map_err(|e| ContactError::Solver { problem, status: format!("{e:?}"), iterations: 0 })?;
        solver.solve();
        let sol = &solver.solution;
        usable(sol.status, sol.iterations, problem)?;
        let out = read_back(bodies, contacts, island, &offset, &members, &sol.x, &sol.z);
        let r = residual(bodies, contacts, island, free, &out, s);
        Ok((out, r, sol.iterations))
    })?;
    Ok(IslandSolution { iterations, ..solution })
}

/// Velocities from the primal solution, impulses from the duals.
fn read_back(
    bodies: &[BodyState],
    contacts: &[Contact],
    island: &[usize],
    offset: &[usize],
    members: &[usize],
    x: &[f64],
    z: &[f64],
) -> IslandSolution {
    let velocities = members
        .iter()
        .map(|&k| {
            let o = offset[k];
            let linear = Vector3::new(x[o], x[o + 1], x[o + 2]);
            let angular =
                if bodies[k].rotates() { Vector3::new(x[o + 3], x[o + 4], x[o + 5]) } else { Vector3::zeros() };
            (k, BodyVelocity { linear, angular })
        })
        .collect();
    let (mut normal, mut friction) = (Vec::new(), Vec::new());
    let mut row = 0;
    for &i in island {
        let c = &contacts[i];
        normal.push(z[row].max(0.0));
        if c.friction > 0.0 {
            let (t1, t2) = tangents(&c.normal);
            friction.push((t1 * z[row + 1] + t2 * z[row + 2]) * c.friction);
            row += 3;
        } else {
            friction.push(Vector3::zeros());
            row += 1;
        }
    }
    IslandSolution { velocities, normal, friction, iterations: 0 }
}

/// How far an island's answer is from the conditions of the step, relative to its velocity scale V and impulse
/// scale P: momentum balance M (v - v*) = sum of contact impulses (per body, to P), the velocity cones
/// n.v_rel + beta >= mu |v_rel,t| (to V), the impulse cones |p_t| <= mu p_n (to P), and complementarity
/// p_n (n.v_rel + beta) + p_t . v_rel,t = 0 (to P V).
fn residual(
    bodies: &[BodyState],
    contacts: &[Contact],
    island: &[usize],
    free: &[BodyVelocity],
    out: &IslandSolution,
    s: &StepSettings,
) -> f64 {
    let mut after: Vec<BodyVelocity> = free.to_vec();
    for (k, v) in &out.velocities {
        after[*k] = *v;
    }
    let moved: Vec<BodyState> = bodies
        .iter()
        .zip(&after)
        .map(|(b, v)| BodyState { velocity: v.linear, angular_velocity: v.angular, ..*b })
        .collect();
    let free_state: Vec<BodyState> = bodies
        .iter()
        .zip(free)
        .map(|(b, v)| BodyState { velocity: v.linear, angular_velocity: v.angular, ..*b })
        .collect();
    let mut v_scale = f64::MIN_POSITIVE;
    for &i in island {
        let c = &contacts[i];
        let rel = free_state[c.b].point_velocity(&c.point) - free_state[c.a].point_velocity(&c.point);
        v_scale = v_scale.max(rel.norm()).max(bias(c, bodies, s).abs());
    }
    let p_scale = out
        .velocities
        .iter()
        .map(|(k, _)| v_scale / bodies[*k].inv_mass)
        .chain(out.normal.iter().copied())
        .fold(f64::MIN_POSITIVE, f64::max);
    let mut worst = 0.0f64;
    // momentum balance, from the impulses alone
    let impulses: Vec<Vector3<f64>> = island
        .iter()
        .enumerate()
        .map(|(slot, &i)| contacts[i].normal.into_inner() * out.normal[slot] + out.friction[slot])
        .collect();
    let island_contacts: Vec<Contact> = island.iter().map(|&i| contacts[i]).collect();
    let predicted = crate::impulse::velocities_after(&free_state, &island_contacts, &impulses);
    for (k, v) in &out.velocities {
        let b = &bodies[*k];
        let dl = (v.linear - predicted[*k].linear).norm() / b.inv_mass;
        let da = if b.rotates() { (b.inertia * (v.angular - predicted[*k].angular)).norm() } else { 0.0 };
        let reach = island_contacts.iter().map(|c| (c.point - b.position).norm()).fold(1.0, f64::max);
        worst = worst.max(dl / p_scale).max(da / (p_scale * reach));
    }
    for (slot, c) in island_contacts.iter().enumerate() {
        let rel = moved[c.b].point_velocity(&c.point) - moved[c.a].point_velocity(&c.point);
        let n = c.normal.into_inner();
        let vn = n.dot(&rel) + bias(c, bodies, s);
        let vt = rel - n * n.dot(&rel);
        let (pn, pt) = (out.normal[slot], out.friction[slot]);
        worst = worst
            .max((c.friction * vt.norm() - vn) / v_scale)
            .max((pt.norm() - c.friction * pn) / p_scale)
            .max((pn * vn + pt.dot(&vt)).abs() / (p_scale * v_scale));
    }
    worst
}
