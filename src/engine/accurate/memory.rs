//! Accurate mode's memory: everything its steps carry from one call to the next (the integration, and with contact
//! stages what they know: the resting contacts, the touching phase with its free flight, the scales set where the
//! engine was built). It is one type: a copy is what a failed call puts back, serialized it is what a file holds,
//! and given back it is checked here and by the engine (`AccurateEngine::set_memory`) before anything changes.

use super::integration::Integration;
use serde::{Deserialize, Serialize};

#[cfg(feature = "contact")]
pub(crate) use super::contact_memory::ContactMemory;

/// Without the `contact` feature there is no contact memory (the type keeps the format the same in both builds).
#[cfg(not(feature = "contact"))]
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum ContactMemory {}

/// Accurate mode's memory.
#[derive(Clone, Serialize, Deserialize)]
pub(crate) struct AccurateMemory {
    /// The time of a world with nothing to integrate (an integration keeps its own).
    pub clock: f64,
    /// The integration of the equations of motion; `None` when the state is empty.
    pub integration: Option<Integration>,
    /// What the contact stages know; `None` when no two colliders can touch.
    pub contact: Option<ContactMemory>,
    /// Each joint's broken flag (the model and the collider set are given them, `engine/breaking.rs`).
    /// (Absent from files written before joints could break: none broken.)
    #[serde(default)]
    pub broken: Vec<bool>,
    /// Each joint's load averaged over its break window (`Model::judged_loads`; empty until a joint with a window
    /// has carried a step, and absent from files written before windows).
    #[serde(default)]
    pub load_averages: Vec<crate::model::breaking::JointLoad>,
}

impl AccurateMemory {
    /// The current time (the touching phase's while it keeps its own state).
    pub fn time(&self) -> f64 {
        if let Some((t, _)) = self.touching_at() {
            return t;
        }
        self.integration.as_ref().map_or(self.clock, |i| i.live().time())
    }

    /// The current state (the touching phase's while it keeps its own).
    pub fn state(&self) -> &[f64] {
        if let Some((_, y)) = self.touching_at() {
            return y;
        }
        self.integration.as_ref().map_or(&[], |i| i.live().state())
    }

    /// The touching phase's time and state while it keeps its own.
    fn touching_at(&self) -> Option<(f64, &[f64])> {
        #[cfg(feature = "contact")]
        return self.contact.as_ref().and_then(|c| c.touching_at());
        #[cfg(not(feature = "contact"))]
        None
    }
}

/// The name of the engine a memory with this contact part comes from.
pub(crate) fn engine_name(contact: &Option<ContactMemory>) -> &'static str {
    match contact {
        None => "integration without contact",
        Some(_) => "accurate mode's contact engine",
    }
}

impl super::AccurateEngine {
    /// Puts `memory` in place after checking it against the engine: every integration made live (one read from a
    /// file given to an integrator of this system and checked by it), the contact memory checked against the scene.
    pub(super) fn give_memory(&mut self, memory: AccurateMemory) -> Result<(), String> {
        let AccurateMemory { clock, integration, contact, mut broken, load_averages } = memory;
        if broken.is_empty() {
            broken = vec![false; self.system.model.joints.len()];
        }
        if !(load_averages.is_empty() || load_averages.len() == self.system.model.joints.len()) {
            return Err("its joints' averaged loads are not the scene's".into());
        }
        if !load_averages.iter().all(|l| l.force.iter().chain(&l.torque).all(|v| v.is_finite())) {
            return Err("a joint's averaged load is not finite".into());
        }
        let dim = self.system.model.layout.dim();
        #[cfg(feature = "contact")]
        let (scene, has_contacts) = (self.contacts.as_ref().map(|c| &c.scene), self.contacts.is_some());
        #[cfg(not(feature = "contact"))]
        let has_contacts = false;
        if contact.is_some() != has_contacts {
            return Err(format!("it is the memory of {}, which this world does not run", engine_name(&contact)));
        }
        if !clock.is_finite() {
            return Err("its time is not finite".into());
        }
        if integration.is_some() != (dim > 0) {
            return Err("it has an integration where the world has nothing to integrate, or none where it has".into());
        }
        #[cfg(feature = "contact")]
        if let (Some(c), Some(scene)) = (&contact, scene) {
            c.check(scene.actors(), scene.colliders.len(), dim)?;
        }
        // a saved integration is given to a copy of the engine's own integrator (made only then)
        let current = self.memory.integration.as_ref();
        let template =
            || current.map(|i| i.live().clone()).ok_or_else(|| super::failure(clock, "no integrator".into()));
        let integration = integration.map(|i| i.into_live(template)).transpose()?;
        #[cfg(feature = "contact")]
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
        #[cfg(feature = "contact")]
        crate::engine::breaking::set_broken(
            &mut self.system.model,
            self.contacts.as_mut().map(|c| &mut c.scene),
            &broken,
        )?;
        #[cfg(not(feature = "contact"))]
        self.system.model.set_broken_joints(&broken)?;
        self.memory = AccurateMemory { clock, integration, contact, broken, load_averages };
        Ok(())
    }
}
