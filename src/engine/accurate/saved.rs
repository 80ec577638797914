//! Accurate mode's memory as a file holds it: the integration as plain data, the resting contacts, what the contact
//! phase knew and the touching phase (with its free flight's integration), so that a loaded world continues bit for
//! bit. Given back, it is checked against the engine first: every contact must name the scene's actors and
//! colliders, every step be positive, and nothing changes on an error.

use super::free_flight::FreeFlight;
use super::resting::{RestingContact, RestingSet};
use super::touching::Touching;
use super::{AccurateEngine, AccurateSnapshot, Scales};
use crate::engine::contact_scene::ContactKey;
use crate::engine::step_contacts::StepContact;
use std::collections::{BTreeMap, BTreeSet};
use tumble_integrate::{Integrator, IntegratorMemory};

/// The resting contacts (their statics and solver settings are the engine's own).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct SavedResting {
    contacts: Vec<RestingContact>,
    reach: f64,
}

/// The touching phase, with the integration of the actors flying free meanwhile.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct SavedTouching {
    lagged: BTreeMap<ContactKey, f64>,
    h: f64,
    window: (f64, usize),
    free: Option<(Vec<usize>, IntegratorMemory)>,
    last: Vec<StepContact>,
}

#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct SavedAccurate {
    integrator: IntegratorMemory,
    resting: Option<SavedResting>,
    resting_keys: BTreeSet<ContactKey>,
    penetration: f64,
    window: (f64, usize),
    touching: Option<SavedTouching>,
    scales: Scales,
}

impl AccurateEngine {
    /// The engine's memory as a file holds it.
    pub fn saved(&self) -> SavedAccurate {
        let c = &self.contacts;
        SavedAccurate {
            integrator: self.integrator.memory(),
            resting: self
                .compiled
                .model
                .resting
                .as_ref()
                .map(|r| SavedResting { contacts: r.contacts.clone(), reach: r.reach }),
            resting_keys: c.resting_keys.clone(),
            penetration: c.penetration,
            window: c.window,
            touching: c.touching.as_ref().map(|t| SavedTouching {
                lagged: t.lagged.clone(),
                h: t.h,
                window: t.window,
                free: t.free.as_ref().map(|f| (f.frozen.clone(), f.integrator.memory())),
                last: t.last.clone(),
            }),
            scales: c.scales(),
        }
    }

    /// Gives back a saved memory, checked against this engine; on an error nothing changes.
    pub fn restore_saved(&mut self, s: SavedAccurate) -> Result<(), String> {
        self.check_saved(&s)?;
        let mut integrator = self.integrator.clone();
        integrator.set_memory(&s.integrator).map_err(|e| e.to_string())?;
        let resting = s.resting.map(|r| RestingSet {
            contacts: r.contacts,
            statics: self.contacts.scene.static_poses.clone(),
            settings: self.contacts.solver,
            reach: r.reach,
            solves: 0,
            seconds: 0.0,
        });
        let touching = match s.touching {
            None => None,
            Some(t) => {
                let free = match t.free {
                    None => None,
                    Some((frozen, memory)) => Some(self.free_flight_from(frozen, &memory)?),
                };
                Some(Touching { lagged: t.lagged, h: t.h, window: t.window, free, last: t.last })
            }
        };
        let snapshot = AccurateSnapshot {
            integrator,
            resting,
            resting_keys: s.resting_keys,
            penetration: s.penetration,
            window: s.window,
            touching,
            scales: s.scales,
        };
        self.restore(snapshot).map_err(|e| e.to_string())
    }

    /// A free flight's integrator rebuilt with the actors `frozen` held still, given its memory.
    fn free_flight_from(&mut self, frozen: Vec<usize>, memory: &IntegratorMemory) -> Result<FreeFlight, String> {
        let model = &mut self.compiled.model;
        let (t, y) = (self.integrator.time(), self.integrator.state().to_vec());
        model.frozen = frozen.clone();
        let built = Integrator::new(model, self.contacts.free_settings.clone(), t, &y);
        model.frozen.clear();
        let mut integrator = built.map_err(|e| e.to_string())?;
        integrator.set_memory(memory).map_err(|e| format!("its free flight's {e}"))?;
        Ok(FreeFlight { frozen, integrator })
    }

    fn check_saved(&self, s: &SavedAccurate) -> Result<(), String> {
        let scene = &self.contacts.scene;
        let (actors, colliders) = (scene.actors(), scene.colliders.len());
        let dim = self.compiled.model.layout.dim();
        let key_fits = |k: &ContactKey| (k.colliders.0 as usize) < colliders && (k.colliders.1 as usize) < colliders;
        let names_actors = |c: &StepContact| c.a < actors && c.b < actors;
        let resting_fits = s.resting.as_ref().is_none_or(|r| {
            r.reach.is_finite() && r.contacts.iter().all(|c| c.a < actors && c.b < actors && key_fits(&c.key))
        });
        let touching_fits = s.touching.as_ref().is_none_or(|t| {
            t.h > 0.0
                && t.h.is_finite()
                && t.lagged.iter().all(|(k, f)| key_fits(k) && f.is_finite())
                && t.last.iter().all(names_actors)
                && t.free.as_ref().is_none_or(|(frozen, _)| frozen.iter().all(|&k| k < dim))
        });
        let checks = [
            (resting_fits, "a resting contact names no actor or collider"),
            (s.resting_keys.iter().all(key_fits), "a resting key names no collider"),
            (touching_fits, "its touching phase does not fit the scene"),
            (s.penetration.is_finite(), "its penetration is not finite"),
            (s.scales.valid(), "its scales are not positive and finite"),
        ];
        match checks.iter().find(|(ok, _)| !ok) {
            Some((_, why)) => Err(why.to_string()),
            None => Ok(()),
        }
    }
}
