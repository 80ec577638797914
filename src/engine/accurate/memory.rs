//! Accurate mode's memory: everything its steps carry from one call to the next (the integration, and with contact
//! stages what they know: the resting contacts, the touching phase with its free flight, the scales set where the
//! engine was built). It is one type: a copy is what a failed call puts back, serialized it is what a file holds,
//! and given back it is checked by the engine (`give_memory.rs`) before anything changes.

use super::integration::Integration;
use serde::{Deserialize, Serialize};

pub(crate) use super::contact_memory::ContactMemory;

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
        self.contact.as_ref().and_then(|c| c.touching_at())
    }
}

/// The name of the engine a memory with this contact part comes from.
pub(crate) fn engine_name(contact: &Option<ContactMemory>) -> &'static str {
    match contact {
        None => "integration without contact",
        Some(_) => "accurate mode's contact engine",
    }
}
