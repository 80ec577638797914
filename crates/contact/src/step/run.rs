//! The velocity step over islands: time stepping with Coulomb friction as a velocity-level conic program (Anitescu's convex model), per island:
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

use super::check::closing;
use super::dispatch::solve_island;
use super::island::{bias, IslandSolution};
use super::problem::{free_velocity, BilateralRow, VelocityProblem, VelocityStep, CONTACTS_A_UNIT};
use super::settings::StepSettings;
use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use crate::threads::in_parallel_by;
use nalgebra::Vector3;
use std::collections::BTreeMap;

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
                super::resistance::resistance_rows(c, bodies, bound, &mut rows);
            }
            with_resistance = rows;
            &with_resistance[..]
        }
        _ => bilateral,
    };
    let mut velocities: Vec<BodyVelocity> = bodies.iter().map(|b| free_velocity(b, settings)).collect();
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
#[path = "tests.rs"]
mod tests;
