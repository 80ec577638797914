//! Fast mode, fifth stage: sleep (`Sleep`, `sleep.rs`) brought up to the step's end: how long each actor has been
//! still, and the still groups put to sleep, their momenta zeroed.

use super::context::StepContext;
use crate::engine::found_contact::FoundContact;
use crate::plan::Stage;
use tumble_contact::{BodyState, BodyVelocity};

/// Fifth stage: books how long each actor has been still (at the velocities the step ended with) and puts
/// still islands to sleep, their momenta zeroed.
pub(super) fn update_sleep(
    cx: &mut StepContext<'_>,
    states: &[BodyState],
    v: &[BodyVelocity],
    found: &[FoundContact],
    h: f64,
) {
    let (true, Some(collider_set)) = (cx.settings.sleep, cx.collider_set.as_deref()) else { return };
    // jointed bodies do not sleep (sleep groups bodies by their contacts alone)
    if cx.model.has_joints() {
        return;
    }
    let moved: Vec<BodyState> = states
        .iter()
        .zip(v)
        .map(|(s, v)| BodyState { velocity: v.linear, angular_velocity: v.angular, ..*s })
        .collect();
    let mut speeds = collider_set.reach(&moved, 1.0);
    // a kinematic body with moving still to do is never still
    let p = cx.model.layout.particles;
    for j in (0..cx.model.bodies.len()).filter(|&j| cx.model.kinematic_moves_after(j, cx.t_next)) {
        speeds[p + j] = f64::INFINITY;
    }
    match &cx.memory.pairs {
        Some(kept) => cx.memory.sleep.update(kept.touching(), &speeds, cx.settings, h),
        None => cx.memory.sleep.update(found.iter().map(|f| (f.contact.a, f.contact.b)), &speeds, cx.settings, h),
    }
    cx.memory.sleep.freeze(&mut cx.memory.y, cx.model);
    cx.report.stages.mark(Stage::Sleeping);
}
