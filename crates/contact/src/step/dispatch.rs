//! Which method answers an island: none where no contact needs an impulse (`untouched`), tumble's Newton method
//! where it applies and its answer passes the check, clarabel otherwise (with the `clarabel` feature; without it an
//! island the Newton method cannot answer is an error).

use super::check::{residual, untouched};
use super::island::{moved_by_joints, row_layout, IslandSolution};
use super::newton::{solve_island_newton, Island};
use super::problem::BilateralRow;
use super::settings::{StepMethod, StepSettings};
use crate::body::BodyState;
use crate::contact::Contact;
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use nalgebra::Vector3;

/// One island's answer: its velocity unknowns laid out (3 per moving particle, 6 per moving rigid body), then the
/// first method that answers.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_island(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    bilateral: &[&BilateralRow],
    free: &[BodyVelocity],
    s: &StepSettings,
    warm: Option<&[Vector3<f64>]>,
) -> Result<IslandSolution, ContactError> {
    // Velocity variables: 3 per moving particle, 6 per moving rigid body.
    let mut offset = vec![usize::MAX; bodies.len()];
    let mut members = Vec::new();
    let mut n = 0;
    let ends = island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]);
    for k in ends.chain(bilateral.iter().flat_map(|r| [r.a, r.b])) {
        if bodies[k].is_dynamic() && offset[k] == usize::MAX {
            offset[k] = n;
            members.push(k);
            n += if bodies[k].rotates() { 6 } else { 3 };
        }
    }
    if bilateral.is_empty() {
        if let Some(untouched) = untouched(bodies, contacts, bounds, island, &members, free, s) {
            return Ok(untouched);
        }
    }
    // tumble's own solver first (lagged friction or none), its answer held to the same test as clarabel's
    let mut building = 0.0;
    let lagged_or_frictionless = bounds.is_some() || island.iter().all(|&i| contacts[i].friction == 0.0);
    if s.method == StepMethod::Newton && lagged_or_frictionless {
        let zeros = vec![0.0; contacts.len()];
        let b = bounds.unwrap_or(&zeros);
        let input =
            Island { bodies, contacts, bounds: b, island, bilateral, free, s, offset: &offset, members: &members, n };
        let answer = solve_island_newton(&input, warm, &mut building);
        if let Some((out, joints)) = answer {
            let (layout, _) = row_layout(contacts, bounds, island, n);
            let moved = moved_by_joints(bodies, bilateral, free, &joints);
            if residual(bodies, contacts, island, &layout, &moved, &out, s) <= s.solver.complementarity_tolerance {
                return Ok(IslandSolution { building_seconds: building, joints, ..out });
            }
        }
    }
    #[cfg(feature = "clarabel")]
    return super::clarabel::solve_island(
        bodies,
        contacts,
        bounds,
        island,
        bilateral,
        free,
        s,
        (&offset, &members, n),
        building,
    );
    #[cfg(not(feature = "clarabel"))]
    Err(ContactError::Solver {
        problem: "friction-step",
        status: "the Newton method did not answer the island, and clarabel is not built (the `clarabel` feature)"
            .into(),
        iterations: 0,
    })
}
