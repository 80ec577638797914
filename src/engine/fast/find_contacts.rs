//! Fast mode, second stage: the contacts of the step. Pairs whose boxes, grown by how far each actor can move in
//! the step plus the margin, overlap (pairs of sleeping or static actors left out) get parry's manifolds within how
//! far the two can close on each other in the step (`ContactScene::find_closing`), reduced to at most four points a
//! pair; a sleeping island touched by a moving actor wakes, and the contacts are found
//! again with it awake.

use super::{failure, FastEngine};
use crate::engine::contact_scene::Found;
use crate::engine::manifold::reduce;
use crate::error::WorldError;
use crate::plan::Stage;
use std::time::Instant;
use tumble_contact::BodyState;

impl FastEngine {
    /// The contacts within reach in step h; `states` are renewed if an island woke.
    pub(super) fn find_contacts(&mut self, states: &mut Vec<BodyState>, h: f64) -> Result<Vec<Found>, WorldError> {
        let Some(scene) = &mut self.scene else { return Ok(Vec::new()) };
        let t = self.memory.origin + self.memory.steps as f64 * self.settings.dt;
        let clock = Instant::now();
        let dynamic = self.memory.sleep.len();
        for a in 0..dynamic {
            scene.inert[a] = self.memory.sleep.asleep(a);
        }
        let poses = scene.poses(&self.memory.y);
        let checks = scene.checks;
        let cache = self.memory.manifolds.as_mut();
        let mut found =
            reduce(scene.find_closing(&poses, states, h, self.settings.margin, cache).map_err(|e| failure(t, e))?);
        if self.memory.sleep.wake_touched(&found, dynamic) {
            // The woken actors' own contacts (with the floor under them, say) were left out as inert: find again.
            for a in 0..dynamic {
                scene.inert[a] = self.memory.sleep.asleep(a);
            }
            *states = self.body_states();
            let scene = self.scene.as_mut().expect("checked above");
            let cache = self.memory.manifolds.as_mut();
            found =
                reduce(scene.find_closing(&poses, states, h, self.settings.margin, cache).map_err(|e| failure(t, e))?);
        }
        let scene = self.scene.as_mut().expect("checked above");
        self.core.report.collision_checks += scene.checks - checks;
        self.core.report.stages.mark(Stage::CollisionDetection);
        self.core.report.collision_seconds += clock.elapsed().as_secs_f64();
        found.retain(|f| states[f.contact.a].is_dynamic() || states[f.contact.b].is_dynamic());
        self.memory.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
        Ok(found)
    }
}
