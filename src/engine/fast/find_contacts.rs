//! Fast mode, second stage: the contacts of the step. Pairs whose boxes, grown by how far each actor can move in
//! the step plus the margin, overlap (pairs of sleeping or static actors left out) get parry's manifolds within how
//! far the two can close on each other in the step (`ColliderSet::find_closing`), reduced to at most four points a
//! pair; a sleeping island touched by a moving actor wakes, and the contacts are found
//! again with it awake.

use super::applied_forces::actors;
use super::failure;
use super::step::StepContext;
use crate::engine::found_contact::FoundContact;
use crate::error::WorldError;
use crate::plan::Stage;
use std::time::Instant;
use tumble_contact::BodyState;

/// The contacts within reach in step h; `states` are renewed if an island woke.
pub(super) fn find_contacts(
    cx: &mut StepContext<'_>,
    states: &mut Vec<BodyState>,
    h: f64,
) -> Result<Vec<FoundContact>, WorldError> {
    let Some(scene) = cx.scene.as_deref_mut() else { return Ok(Vec::new()) };
    let t = cx.memory.origin + cx.memory.steps as f64 * cx.settings.dt;
    let clock = Instant::now();
    let dynamic = cx.memory.sleep.len();
    for a in 0..dynamic {
        scene.inert[a] = cx.memory.sleep.asleep(a);
    }
    let poses = scene.poses(&cx.memory.y);
    let checks = scene.checks;
    let store = cx.memory.pairs.as_mut();
    let mut found =
        scene.find_closing(&poses, states, (h, cx.settings.margin), store, cx.threads).map_err(|e| failure(t, e))?;
    if cx.memory.sleep.wake_touched(&found, dynamic) {
        // The woken actors' own contacts (with the floor under them, say) were left out as inert: find again.
        for a in 0..dynamic {
            scene.inert[a] = cx.memory.sleep.asleep(a);
        }
        *states = actors(cx)?;
        let scene = cx.scene.as_deref_mut().expect("checked above");
        let store = cx.memory.pairs.as_mut();
        found = scene
            .find_closing(&poses, states, (h, cx.settings.margin), store, cx.threads)
            .map_err(|e| failure(t, e))?;
    }
    let scene = cx.scene.as_deref_mut().expect("checked above");
    cx.report.collision_checks += scene.checks - checks;
    cx.report.stages.mark(Stage::CollisionDetection);
    cx.report.collision_seconds += clock.elapsed().as_secs_f64();
    found.retain(|f| states[f.contact.a].is_dynamic() || states[f.contact.b].is_dynamic());
    cx.memory.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
    Ok(found)
}
