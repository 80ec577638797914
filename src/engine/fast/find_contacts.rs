//! Fast mode, second stage: the contacts of the step. Pairs whose boxes, grown by how far each actor can move in
//! the step plus the margin, overlap (pairs of sleeping or static actors left out) get parry's manifolds within how
//! far the two can close on each other in the step, reduced to at most four points a pair: with the soft solver
//! into the pairs the engine keeps (`ColliderSet::keep_closing`: manifolds reused while a pair barely moves, each
//! contact warm-started from its last impulses, pairs coloured as they begin and end), with the exact solver as a
//! list found afresh (`ColliderSet::find_closing`). A sleeping island touched by a moving actor wakes, and the
//! contacts are found again with it awake.

use super::applied_forces::actors;
use super::context::StepContext;
use crate::engine::failure::failure;
use crate::engine::found_contact::FoundContact;
use crate::error::WorldError;
use crate::plan::Stage;
use std::time::Instant;
use tumble_contact::BodyState;

/// The contacts within reach in step h, as a list (the exact solver's) or into the kept pairs (the soft solver's:
/// the list is empty); `states` are renewed if an island woke.
pub(super) fn find_contacts(
    cx: &mut StepContext<'_>,
    states: &mut Vec<BodyState>,
    h: f64,
) -> Result<Vec<FoundContact>, WorldError> {
    if cx.collider_set.is_none() {
        return Ok(Vec::new());
    }
    let clock = Instant::now();
    let checks = cx.collider_set.as_deref().map_or(0, |s| s.checks);
    let dynamic = cx.memory.sleep.len();
    let mut found = search(cx, states, h)?;
    let woke = match &cx.memory.pairs {
        Some(kept) => cx.memory.sleep.wake_touched(kept.touching(), dynamic),
        None => cx.memory.sleep.wake_touched(found.iter().map(|f| (f.contact.a, f.contact.b)), dynamic),
    };
    if woke {
        // The woken actors' own contacts (with the floor under them, say) were left out as idle: find again.
        *states = actors(cx)?;
        found = search(cx, states, h)?;
    }
    let collider_set = cx.collider_set.as_deref_mut().expect("checked above");
    cx.report.collision_checks += collider_set.checks - checks;
    cx.report.stages.mark(Stage::CollisionDetection);
    cx.report.collision_seconds += clock.elapsed().as_secs_f64();
    found.retain(|f| states[f.contact.a].is_dynamic() || states[f.contact.b].is_dynamic());
    cx.memory.penetration = match &cx.memory.pairs {
        Some(kept) => kept.penetration(),
        None => found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max),
    };
    Ok(found)
}

/// One search of the step's contacts at the actors' sleep as it is.
fn search(cx: &mut StepContext<'_>, states: &[BodyState], h: f64) -> Result<Vec<FoundContact>, WorldError> {
    let t = cx.t;
    let collider_set = cx.collider_set.as_deref_mut().expect("a collider_set");
    for a in 0..cx.memory.sleep.len() {
        collider_set.idle[a] = cx.memory.sleep.asleep(a);
    }
    let poses = collider_set.poses(&cx.memory.y);
    let reach = (h, cx.settings.margin);
    match cx.memory.pairs.as_mut() {
        Some(store) => {
            collider_set.keep_closing(&poses, states, reach, store, cx.threads).map_err(|e| failure(t, e))?;
            Ok(Vec::new())
        }
        None => collider_set.find_closing(&poses, states, reach).map_err(|e| failure(t, e).into()),
    }
}
