//! A contact step taken whole and as two halves (`touching.rs` compares them), and the actors a step starts from.

use super::contact_stages::ContactStages;
use super::convex_step::{actors_with_forces, convex_step, every_contact_in_reach, ConvexStep};
use super::free_flight::involved;
use super::sleep::Sleep;
use super::step_estimate::sinking;
use super::system::AccurateSystem;
use super::touching_phase::TouchingPhase;
use tumble_integrate::OdeError;

/// One step of h taken whole and as two halves (the first half on the whole step's contacts, the second on its
/// own), with the actors their contacts involve (`free_flight::involved`) and how deep the second half sinks any
/// contact in reach at the middle (a polyhedron's vertex that came round to face the other shape by then, which the
/// start's contacts do not show); `None` if clarabel could not answer one of them.
#[allow(clippy::too_many_arguments)]
pub(super) fn doubled_step(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    states: &[tumble_contact::BodyState],
    found: &[crate::engine::found_contact::FoundContact],
    phase: &TouchingPhase,
    t: f64,
    y: &[f64],
    h: f64,
) -> Result<Option<(ConvexStep, ConvexStep, Vec<bool>, f64)>, OdeError> {
    let lagged = &phase.lagged;
    // each solve starts from the last: the whole step from the last step's forces, the halves from the whole's
    let Some(whole) = convex_step(cx, &system.model, states, found, (lagged, &phase.warm), t, y, h)? else {
        return Ok(None);
    };
    let Some(first) = convex_step(cx, &system.model, states, found, (lagged, &whole.wrenches), t, y, 0.5 * h)? else {
        return Ok(None);
    };
    let mid = t + 0.5 * h;
    let states = held(system, statics, mid, &first.y, &phase.sleep)?;
    let (later, every) = every_contact_in_reach(cx, &system.model, &states, &first.y, mid, 0.5 * h)?;
    let warm = (&first.forces, &first.wrenches);
    let Some(mut second) = convex_step(cx, &system.model, &states, &later, warm, mid, &first.y, 0.5 * h)? else {
        return Ok(None);
    };
    // the joints' loads over the whole step are both halves' (an impact's impulse is mostly the first's)
    second.first_half_loads = first.joint_loads;
    let involved = involved(&system.model, &[found, &later]);
    let sunk = sinking(&system.model, &every, &first.y, &second.y);
    Ok(Some((whole, second, involved, sunk)))
}

/// The actors at state y with their applied forces (`actors_with_forces`), the sleeping ones fixed at rest.
pub(super) fn held(
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    t: f64,
    y: &[f64],
    sleep: &Sleep,
) -> Result<Vec<tumble_contact::BodyState>, OdeError> {
    let mut states = actors_with_forces(system, statics, t, y)?;
    sleep.hold(&mut states);
    Ok(states)
}
