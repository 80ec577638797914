//! The chapter's quadratic programs as accurate mode calls them: simultaneous impulses at an impact, the position
//! projection that lifts sunk contacts apart, and resting forces inside the equations of motion. They are clarabel's
//! (the `clarabel` feature); built without it, each is an error that says so, and the only file of the crate that
//! knows the feature.

use tumble_contact::{BodyState, BodyVelocity, Contact, SolverSettings};

/// Why a program cannot be solved in a build without clarabel.
#[cfg(not(feature = "clarabel"))]
const ABSENT: &str = "needs tumble built with the `clarabel` feature";

/// Simultaneous impulses (Newton's restitution law): each body's velocities after them, each contact's impulse, and
/// the solver calls.
pub(super) fn impulses(
    states: &[BodyState],
    contacts: &[Contact],
    solver: &SolverSettings,
) -> Result<(Vec<BodyVelocity>, Vec<f64>, usize), String> {
    #[cfg(feature = "clarabel")]
    return tumble_contact::collision_impulses(states, contacts, solver)
        .map(|out| (out.velocities, out.magnitudes, out.solver_calls))
        .map_err(|e| e.to_string());
    #[cfg(not(feature = "clarabel"))]
    {
        let _ = (states, solver);
        Err(format!("{} contacts' simultaneous impulses {ABSENT}", contacts.len()))
    }
}

/// The smallest position change that separates `contacts`: each body's move (as a velocity over unit time), and the
/// solver calls.
pub(super) fn projection(
    states: &[BodyState],
    contacts: &[Contact],
    solver: &SolverSettings,
) -> Result<(Vec<BodyVelocity>, usize), String> {
    #[cfg(feature = "clarabel")]
    return tumble_contact::position_correction(states, contacts, solver)
        .map(|out| (out.moves, out.solver_calls))
        .map_err(|e| e.to_string());
    #[cfg(not(feature = "clarabel"))]
    {
        let _ = (states, solver);
        Err(format!("lifting {} sunk contacts apart {ABSENT}", contacts.len()))
    }
}

/// The resting contacts' frictionless forces (the chapter's QP) as each body's force and torque, and the solver
/// calls.
#[allow(clippy::type_complexity)]
pub(super) fn resting_wrenches(
    states: &[BodyState],
    contacts: &[Contact],
    solver: &SolverSettings,
) -> Result<(Vec<(nalgebra::Vector3<f64>, nalgebra::Vector3<f64>)>, usize), String> {
    #[cfg(feature = "clarabel")]
    return tumble_contact::resting_forces(states, contacts, solver)
        .map(|out| (tumble_contact::contact_wrenches(states, contacts, &out.forces), out.solver_calls))
        .map_err(|e| e.to_string());
    #[cfg(not(feature = "clarabel"))]
    {
        let _ = (states, solver);
        Err(format!("resting forces at {} contacts {ABSENT}", contacts.len()))
    }
}
