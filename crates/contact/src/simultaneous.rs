//! Simultaneous collision impulses for several colliding contacts: Newton's restitution law at every contact at
//! once, v+ >= -e v-, j >= 0, j (v+ + e v-) = 0, with v+ = A j + v-: a complementarity problem solved as a QP per
//! island (a lone contact's is the chapter's formula, in closed form).

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::delassus::NormalSystem;
use crate::error::ContactError;
use crate::impulse::{velocities_after, BodyVelocity};
use crate::islands::islands;
use crate::lcp::solve;
use crate::solver_settings::SolverSettings;

/// The outcome of a simultaneous collision.
#[derive(Clone, Debug, PartialEq)]
pub struct Impulses {
    /// Impulse magnitude at each contact (>= 0; B receives +j n).
    pub magnitudes: Vec<f64>,
    /// Every body's velocities after the impulses.
    pub velocities: Vec<BodyVelocity>,
    /// Relative normal velocities after the impulses.
    pub relative_velocities: Vec<f64>,
    /// clarabel iterations, summed over islands.
    pub iterations: u32,
    /// clarabel calls (islands of two or more contacts; a lone contact is solved in closed form).
    pub solver_calls: usize,
    /// The largest relative complementarity residual over islands.
    pub residual: f64,
}

/// Impulses that make every contact obey Newton's restitution law at once (e applies to contacts that are
/// closing; a separating contact only must not start closing).
pub fn collision_impulses(
    bodies: &[BodyState],
    contacts: &[Contact],
    settings: &SolverSettings,
) -> Result<Impulses, ContactError> {
    check_all(bodies, contacts)?;
    settings.check()?;
    let mut magnitudes = vec![0.0; contacts.len()];
    let mut relative_velocities = vec![0.0; contacts.len()];
    let (mut iterations, mut residual, mut solver_calls) = (0, 0.0f64, 0);
    for island in islands(bodies, contacts) {
        let system = NormalSystem::new(bodies, contacts, &island);
        let v_minus = system.velocities(bodies);
        let q: Vec<f64> =
            island.iter().zip(&v_minus).map(|(&i, &v)| v + contacts[i].restitution * v.min(0.0)).collect();
        let sol = solve(&system.delassus(bodies), &q, settings, "simultaneous-impulse")?;
        for (k, &i) in island.iter().enumerate() {
            magnitudes[i] = sol.f[k];
            relative_velocities[i] = sol.w[k] - contacts[i].restitution * v_minus[k].min(0.0);
        }
        iterations += sol.iterations;
        solver_calls += (island.len() > 1) as usize;
        residual = residual.max(sol.residual);
    }
    let impulses: Vec<_> = contacts.iter().zip(&magnitudes).map(|(c, &j)| c.normal.into_inner() * j).collect();
    let velocities = velocities_after(bodies, contacts, &impulses);
    Ok(Impulses { magnitudes, velocities, relative_velocities, iterations, solver_calls, residual })
}
