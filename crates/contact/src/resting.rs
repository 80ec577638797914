//! Resting-contact forces, as the chapter and Baraff formulate them: the relative normal accelerations are
//! a = A f + b with A = J M^-1 J^T and b the accelerations without contact forces; find f >= 0, a >= 0, f . a = 0,
//! the KKT conditions of min 1/2 f^T A f + b^T f s.t. f >= 0, solved per island with clarabel.

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::delassus::{free_normal_acceleration, NormalSystem};
use crate::error::ContactError;
use crate::islands::islands;
use crate::lcp::solve;
use crate::solver_settings::SolverSettings;
use nalgebra::Vector3;

/// Resting-contact forces and what they achieve.
#[derive(Clone, Debug, PartialEq)]
pub struct RestingForces {
    /// Force magnitude at each contact (>= 0; B is pushed along +n, A along -n).
    pub forces: Vec<f64>,
    /// Relative normal acceleration at each contact with the forces applied (>= 0).
    pub accelerations: Vec<f64>,
    /// clarabel iterations, summed over islands.
    pub iterations: u32,
    /// clarabel calls (islands of two or more contacts; a lone contact is solved in closed form).
    pub solver_calls: usize,
    /// The largest relative complementarity residual over islands.
    pub residual: f64,
}

/// The contact forces that keep resting contacts from accelerating into each other.
pub fn resting_forces(
    bodies: &[BodyState],
    contacts: &[Contact],
    settings: &SolverSettings,
) -> Result<RestingForces, ContactError> {
    check_all(bodies, contacts)?;
    settings.check()?;
    let mut forces = vec![0.0; contacts.len()];
    let mut accelerations = vec![0.0; contacts.len()];
    let (mut iterations, mut residual, mut solver_calls) = (0, 0.0f64, 0);
    for island in islands(bodies, contacts) {
        let system = NormalSystem::new(bodies, contacts, &island);
        let b: Vec<f64> = island.iter().map(|&i| free_normal_acceleration(&contacts[i], bodies)).collect();
        let sol = solve(&system.delassus(bodies), &b, settings, "resting-contact")?;
        for (k, &i) in island.iter().enumerate() {
            forces[i] = sol.f[k];
            accelerations[i] = sol.w[k];
        }
        iterations += sol.iterations;
        solver_calls += (island.len() > 1) as usize;
        residual = residual.max(sol.residual);
    }
    Ok(RestingForces { forces, accelerations, iterations, solver_calls, residual })
}

/// The total contact force and torque (about the centre of mass) on every body from force magnitudes `forces`.
pub fn contact_wrenches(
    bodies: &[BodyState],
    contacts: &[Contact],
    forces: &[f64],
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let mut out = vec![(Vector3::zeros(), Vector3::zeros()); bodies.len()];
    for (c, &f) in contacts.iter().zip(forces) {
        let push = c.normal.into_inner() * f;
        for (k, sign) in [(c.a, -1.0), (c.b, 1.0)] {
            let r = c.point - bodies[k].position;
            out[k].0 += push * sign;
            out[k].1 += r.cross(&(push * sign));
        }
    }
    out
}
