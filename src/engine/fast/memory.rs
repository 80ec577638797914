//! Fast mode's memory: everything its steps carry from one to the next (time, state, each contact's last impulses,
//! the joints' warm starts, sleep, the contact pairs kept across steps, the last step's contacts). It is one type: a
//! copy is what a failed call (or the step-doubling estimate) puts back, serialized it is what a file holds, and
//! given back it is checked here first.

use super::sleep::Sleep;
use crate::engine::contact_pairs::ContactPairs;
use crate::engine::found_contact::ContactKey;
use crate::engine::last_contacts::LastContact;
use crate::model::breaking::JointLoad;
use std::collections::BTreeMap;

/// What fast mode carries from step to step. (Copied into the room of an older copy, `clone_from`, by the run
/// loop's checkpoint at every call.)
#[derive(serde::Serialize, serde::Deserialize)]
pub(crate) struct FastMemory {
    /// Time = origin + steps x dt, so that times are exact multiples of the step from where the engine started.
    pub origin: f64,
    pub steps: u64,
    /// The state in velocity form (`model/velocities.rs`): positions, orientations, and each body's velocity and
    /// angular velocity where the world's state has its momenta.
    pub y: Vec<f64>,
    /// Each contact's normal impulse of the last step (ordered: the warm start sums them in key order).
    pub previous: BTreeMap<ContactKey, f64>,
    /// Each joint's row impulses of the last step.
    pub joint_warm: Vec<tumble_contact::JointImpulse>,
    /// Each joint's broken flag (the model and the collider set are given them, `engine/breaking.rs`).
    /// (Absent from files written before joints could break: none broken.)
    #[serde(default)]
    pub broken: Vec<bool>,
    /// Each joint's load averaged over its break window (`Model::judged_loads`; empty until a joint with a window
    /// has carried a step, and absent from files written before windows).
    #[serde(default)]
    pub load_averages: Vec<JointLoad>,
    pub sleep: Sleep,
    /// Largest penetration among the contacts of the last step.
    pub penetration: f64,
    /// The soft solver's contact pairs kept across steps (manifolds, reductions and impulses), or none.
    pub pairs: Option<ContactPairs>,
    /// The contacts of the last step, with their impulses: the exact solver's (the soft solver's are in `pairs`).
    pub last_contacts: Vec<LastContact>,
}

impl Clone for FastMemory {
    fn clone(&self) -> Self {
        FastMemory {
            origin: self.origin,
            steps: self.steps,
            y: self.y.clone(),
            previous: self.previous.clone(),
            joint_warm: self.joint_warm.clone(),
            broken: self.broken.clone(),
            load_averages: self.load_averages.clone(),
            sleep: self.sleep.clone(),
            penetration: self.penetration,
            pairs: self.pairs.clone(),
            last_contacts: self.last_contacts.clone(),
        }
    }

    fn clone_from(&mut self, o: &Self) {
        (self.origin, self.steps, self.penetration) = (o.origin, o.steps, o.penetration);
        self.y.clone_from(&o.y);
        self.previous.clone_from(&o.previous);
        self.joint_warm.clone_from(&o.joint_warm);
        self.broken.clone_from(&o.broken);
        self.load_averages.clone_from(&o.load_averages);
        self.sleep.clone_from(&o.sleep);
        self.pairs.clone_from(&o.pairs);
        self.last_contacts.clone_from(&o.last_contacts);
    }
}

/// What a fast-mode memory must fit: the state's length, the dynamic actors, all actors, the colliders, the joints,
/// and whether the engine keeps contact pairs.
#[derive(Clone, Copy)]
pub(crate) struct Fit {
    pub dim: usize,
    pub actors: usize,
    pub all_actors: usize,
    pub colliders: usize,
    pub joints: usize,
    pub keeps_pairs: bool,
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
            (self.previous.keys().all(keys_fit), "a contact names no collider"),
            (self.joint_warm.len() == fit.joints, "its joints are not the collider_set's"),
            (self.broken.len() == fit.joints, "its broken joints are not the collider_set's"),
            (self.joint_warm.iter().all(|j| j.0.iter().all(|p| p.is_finite())), "a joint's impulse is not finite"),
            (
                self.load_averages.is_empty() || self.load_averages.len() == fit.joints,
                "its joints' averaged loads are not the collider_set's",
            ),
            (
                self.load_averages.iter().all(|l| l.force.iter().chain(&l.torque).all(|v| v.is_finite())),
                "a joint's averaged load is not finite",
            ),
            (
                self.pairs.is_some() == fit.keeps_pairs,
                "it keeps contact pairs where this solver does not, or none where it does",
            ),
            (
                self.pairs.as_ref().is_none_or(|m| m.fits(fit.colliders)),
                "its kept contact pairs do not fit the colliders or are out of order",
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
