//! Drift of resting contacts in accurate mode: the QP forces keep a resting contact's gap still only up to the
//! integrator's error, so a resting contact that sinks past the contact distance ends the step (an event), and the
//! impact stage moves the bodies back to zero gap by the smallest position change (a position-level LCP).

use super::failure;
use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::model::layout::{get3, get_quat, set3, set_quat};
use crate::model::Model;
use nalgebra::UnitQuaternion;
use std::collections::BTreeSet;
use tumble_contact::{position_correction, BodyState, BodyVelocity, Contact, SolverSettings};
use tumble_integrate::OdeError;

/// Whether a resting contact among `found` has sunk past the contact distance `delta`.
pub(super) fn drifted(found: &[FoundContact], resting: &BTreeSet<ContactKey>, delta: f64) -> bool {
    found.iter().any(|f| resting.contains(&f.key) && f.contact.distance < -delta)
}

/// Moves the actors of state y so that `contacts` no longer interpenetrate; returns the solver calls it took.
pub(super) fn correct_drift(
    model: &Model,
    y: &mut [f64],
    states: &[BodyState],
    contacts: &[Contact],
    solver: &SolverSettings,
    t: f64,
) -> Result<usize, OdeError> {
    let shift = position_correction(states, contacts, solver).map_err(|e| failure(t, format!("projection: {e}")))?;
    shift_positions(model, y, &shift.moves);
    Ok(shift.solver_calls)
}

/// Moves particles and bodies by the displacements and small rotations of a position correction.
#[allow(clippy::needless_range_loop)]
fn shift_positions(model: &Model, y: &mut [f64], shift: &[BodyVelocity]) {
    let l = model.layout;
    for i in 0..l.particles {
        let x = get3(y, l.px(i)) + shift[i].linear;
        set3(y, l.px(i), &x);
    }
    for j in 0..l.bodies {
        let a = l.particles + j;
        let x = get3(y, l.bx(j)) + shift[a].linear;
        let q =
            UnitQuaternion::from_scaled_axis(shift[a].angular) * UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        set3(y, l.bx(j), &x);
        set_quat(y, l.bq(j), &q);
    }
}
