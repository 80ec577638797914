//! Position correction: the smallest mass-weighted displacement that takes every interpenetrating contact back to
//! zero gap, d + A lambda >= 0, lambda >= 0, lambda (d + A lambda) = 0 (the complementarity problem of the
//! distances, with A = J M^-1 J^T), returned as a displacement and a small rotation per body. Used to keep resting
//! contacts from drifting into each other.

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::delassus::NormalSystem;
use crate::error::ContactError;
use crate::impulse::{velocities_after, BodyVelocity};
use crate::islands::islands;
use crate::lcp::solve;
use crate::solver_settings::SolverSettings;

/// The displacement (`linear`) and rotation vector (`angular`) of every body that closes the gaps of the contacts
/// with negative `distance` and opens none of the others beyond what they need (contacts with a positive gap may
/// close up to it).
pub fn position_correction(
    bodies: &[BodyState],
    contacts: &[Contact],
    settings: &SolverSettings,
) -> Result<Correction, ContactError> {
    check_all(bodies, contacts)?;
    settings.check()?;
    let mut lambda = vec![0.0; contacts.len()];
    let mut solver_calls = 0;
    for island in islands(bodies, contacts) {
        solver_calls += (island.len() > 1) as usize;
        let system = NormalSystem::new(bodies, contacts, &island);
        let d: Vec<f64> = island.iter().map(|&i| contacts[i].distance).collect();
        let sol = solve(&system.delassus(bodies), &d, settings, "position-correction")?;
        for (k, &i) in island.iter().enumerate() {
            lambda[i] = sol.f[k];
        }
    }
    // Displacements are "velocities after a unit impulse" from rest.
    let at_rest: Vec<BodyState> = bodies
        .iter()
        .map(|b| BodyState { velocity: nalgebra::Vector3::zeros(), angular_velocity: nalgebra::Vector3::zeros(), ..*b })
        .collect();
    let pushes: Vec<_> = contacts.iter().zip(&lambda).map(|(c, &l)| c.normal.into_inner() * l).collect();
    Ok(Correction { moves: velocities_after(&at_rest, contacts, &pushes), solver_calls })
}

/// A position correction.
#[derive(Clone, Debug, PartialEq)]
pub struct Correction {
    /// Per body: displacement (`linear`) and rotation vector (`angular`).
    pub moves: Vec<BodyVelocity>,
    /// clarabel calls (islands of two or more contacts).
    pub solver_calls: usize,
}
