//! Fast mode's memory: everything its steps carry from one to the next (time, state, each contact's last impulses,
//! the joints' warm starts, sleep, the manifolds kept across steps, the last step's contacts). It is one type: a
//! copy is what a failed call (or the step-doubling estimate) puts back, serialized it is what a file holds, and
//! given back it is checked here first.

use super::sleep::Sleep;
use crate::engine::found_contact::ContactKey;
use crate::engine::last_contacts::LastContact;
use crate::engine::manifold_cache::ManifoldCache;
use std::collections::BTreeMap;

/// What fast mode carries from step to step.
#[derive(serde::Serialize, serde::Deserialize, Clone)]
pub(crate) struct FastMemory {
    /// Time = origin + steps x dt, so that times are exact multiples of the step from where the engine started.
    pub origin: f64,
    pub steps: u64,
    pub y: Vec<f64>,
    /// Each contact's normal impulse of the last step (ordered: the warm start sums them in key order).
    pub previous: BTreeMap<ContactKey, f64>,
    /// The soft solver's impulses of the last step, by contact (sorted by key).
    pub warm: Vec<(ContactKey, tumble_contact::SoftImpulse)>,
    /// Each joint's row impulses of the last step.
    pub joint_warm: Vec<tumble_contact::JointImpulse>,
    pub sleep: Sleep,
    /// Largest penetration among the contacts of the last step.
    pub penetration: f64,
    /// Manifolds kept across steps (the soft solver reuses those of pairs that barely moved), or none.
    pub manifolds: Option<ManifoldCache>,
    /// The contacts of the last step, with their impulses.
    pub last_contacts: Vec<LastContact>,
}

/// What a fast-mode memory must fit: the state's length, the dynamic actors, all actors, the colliders, the joints,
/// and whether the engine keeps manifolds.
#[derive(Clone, Copy)]
pub(crate) struct Fit {
    pub dim: usize,
    pub actors: usize,
    pub all_actors: usize,
    pub colliders: usize,
    pub joints: usize,
    pub keeps_manifolds: bool,
}

impl FastMemory {
    /// Whether it fits an engine of these sizes (indices in range, the state finite): a memory is checked before it
    /// is given back, so that a damaged file is an error, never a panic later.
    pub fn check(&self, fit: Fit) -> Result<(), String> {
        let keys_fit = |k: &ContactKey| k.fits(fit.colliders);
        let checks = [
            (self.y.len() == fit.dim, "its state has another length"),
            (self.y.iter().all(|v| v.is_finite()) && self.origin.is_finite(), "its state is not finite"),
            (self.sleep.fits(fit.actors), "its sleep does not fit the actors"),
            (
                self.previous.keys().all(keys_fit) && self.warm.iter().all(|(k, _)| keys_fit(k)),
                "a contact names no collider",
            ),
            (self.warm.windows(2).all(|w| w[0].0 < w[1].0), "its warm starts are out of order"),
            (self.joint_warm.len() == fit.joints, "its joints are not the scene's"),
            (self.joint_warm.iter().all(|j| j.0.iter().all(|p| p.is_finite())), "a joint's impulse is not finite"),
            (
                self.manifolds.is_some() == fit.keeps_manifolds,
                "it keeps manifolds where this solver does not, or none where it does",
            ),
            (
                self.manifolds.as_ref().is_none_or(|m| m.fits(fit.colliders)),
                "its kept manifolds do not fit the colliders",
            ),
            (
                self.last_contacts.iter().all(|c| c.a < fit.all_actors && c.b < fit.all_actors),
                "a contact names no actor",
            ),
        ];
        match checks.iter().find(|(ok, _)| !ok) {
            Some((_, why)) => Err(why.to_string()),
            None => Ok(()),
        }
    }
}
