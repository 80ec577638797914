//! Accurate mode's engine given a memory (`AccurateEngine::set_memory`, a rollback, a snapshot, a file): the memory
//! checked against the engine (its joints, its time, its integrations, its contact memory against the scene), its
//! saved integrations made live on the engine's own integrator, and then put in place; on an error nothing changes.

use super::memory::{engine_name, AccurateMemory};
use super::AccurateEngine;
use crate::engine::failure::failure;

impl AccurateEngine {
    /// Puts `memory` in place after checking it against the engine: every integration made live (one read from a
    /// file given to an integrator of this system and checked by it), the contact memory checked against the scene.
    pub(super) fn give_memory(&mut self, memory: AccurateMemory) -> Result<(), String> {
        let AccurateMemory { clock, integration, contact, mut broken, load_averages } = memory;
        if broken.is_empty() {
            broken = vec![false; self.system.model.joints.len()];
        }
        if !(load_averages.is_empty() || load_averages.len() == self.system.model.joints.len()) {
            return Err("its joints' averaged loads are not the collider_set's".into());
        }
        if !load_averages.iter().all(|l| l.force.iter().chain(&l.torque).all(|v| v.is_finite())) {
            return Err("a joint's averaged load is not finite".into());
        }
        let dim = self.system.model.layout.dim();
        let (collider_set, has_contacts) = (self.contacts.as_ref().map(|c| &c.collider_set), self.contacts.is_some());
        if contact.is_some() != has_contacts {
            return Err(format!("it is the memory of {}, which this world does not run", engine_name(&contact)));
        }
        if !clock.is_finite() {
            return Err("its time is not finite".into());
        }
        if integration.is_some() != (dim > 0) {
            return Err("it has an integration where the world has nothing to integrate, or none where it has".into());
        }
        if let (Some(c), Some(collider_set)) = (&contact, collider_set) {
            c.check(collider_set.actors(), collider_set.colliders.len(), dim)?;
        }
        // a saved integration is given to a copy of the engine's own integrator (made only then)
        let current = self.memory.integration.as_ref();
        let template = || current.map(|i| i.live().clone()).ok_or_else(|| failure(clock, "no integrator".into()));
        let integration = integration.map(|i| i.into_live(template)).transpose()?;
        let contact = match (contact, &integration) {
            (Some(c), Some(main)) => {
                let (t, y) = c
                    .touching_at()
                    .map_or_else(|| (main.live().time(), main.live().state().to_vec()), |(t, y)| (t, y.to_vec()));
                let free_settings = &self.contacts.as_ref().expect("checked above").free_settings;
                Some(c.into_live(&mut self.system, free_settings, t, &y)?)
            }
            (c, _) => c,
        };
        crate::engine::breaking::set_broken(
            &mut self.system.model,
            self.contacts.as_mut().map(|c| &mut c.collider_set),
            &broken,
        )?;
        self.memory = AccurateMemory { clock, integration, contact, broken, load_averages };
        Ok(())
    }
}
