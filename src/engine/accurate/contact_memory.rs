//! What accurate mode's contact stages carry between calls (`ContactMemory`, part of the engine's memory), with the
//! scales set from the scene's size where the engine was built (`ContactScales`).

use super::free_flight_memory::FreeFlight;
use super::resting::RestingContacts;
use super::system::AccurateSystem;
use super::touching_phase::TouchingPhase;
use crate::engine::found_contact::ContactKey;
use crate::mode::AccurateSettings;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use tumble_integrate::{Integrator, Settings};

/// The default contact tolerance as a fraction of the scene's size (`docs/modes.md` has the measurements behind
/// it): the closed-form scenes (a slide's stop, an incline, a roll) stay within 1e-8 of their distances at any
/// tolerance, since their motion between events is quadratic and a sliding contact's stop is located, so the
/// tolerance buys penetration and the chaotic scenes' paths: a 20-cube pile's deepest contact is 33 micrometres at
/// the defaults, and random drops of one to five shapes cost hundredths of a second per simulated second.
pub(crate) const DEFAULT_TOLERANCE: f64 = 1e-4;

/// The contact stages' scales, set from the scene's size where the engine was built (a world built, stepped and
/// loaded elsewhere keeps the original's).
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactScales {
    /// Relative normal speed below which contacts rest (m/s): the settings' or 1e-3 sqrt(2 g L) for the scene's size.
    pub resting_speed: f64,
    /// A mean step below this is a stall (s): 1e-5 of the scene's time scale sqrt(size / g), at most 1e-5 s, and
    /// for tolerances tighter than 1e-6 of the size that times sqrt(tolerance / (1e-6 size)) (a first-order step's
    /// error goes as h^2, so the steps a tolerance needs shrink as its square root).
    pub stall_step: f64,
    /// Error allowed in one contact step (m).
    pub tolerance: f64,
    /// Largest contact step (s): the scene's time scale sqrt(size / g) (a step's reach takes in the pairs within
    /// what gravity moves a body in it, g h^2: a longer step would take in the whole scene).
    pub max_step: f64,
    /// The lagged-friction fixed point is reached when no normal impulse moves by more than this fraction of the
    /// largest: ten times the tolerance relative to the scene's size, within 1e-9 to 1e-3 (a friction bound off by
    /// this fraction is a deceleration off by as much, so a tight tolerance needs a tight fixed point).
    pub lagged_tolerance: f64,
}

impl ContactScales {
    /// The scales of a scene of size `size` (m) under gravity `gravity` (m/s^2).
    pub fn new(accurate: &AccurateSettings, size: f64, gravity: f64) -> ContactScales {
        let time_scale = (size / gravity.max(1e-300)).sqrt();
        let tolerance = accurate.contact_tolerance.unwrap_or(DEFAULT_TOLERANCE * size);
        ContactScales {
            resting_speed: accurate.resting_speed.unwrap_or_else(|| tumble_contact::velocity_tolerance(size, gravity)),
            stall_step: 1e-5 * time_scale.min(1.0) * (tolerance / (1e-6 * size.max(1e-300))).sqrt().min(1.0),
            tolerance,
            max_step: time_scale,
            lagged_tolerance: (10.0 * tolerance / size.max(1e-300)).clamp(1e-9, 1e-3),
        }
    }

    /// Each positive and finite (the resting speed may be zero).
    fn valid(&self) -> bool {
        let s = [self.resting_speed, self.stall_step, self.tolerance, self.max_step, self.lagged_tolerance];
        s[0] >= 0.0 && s.iter().all(|x| x.is_finite()) && s[1..].iter().all(|&x| x > 0.0)
    }
}

/// What the contact stages carry between calls.
#[derive(Serialize, Deserialize, Clone)]
pub(crate) struct ContactMemory {
    /// The resting contacts whose forces the equations of motion add (`Persistent::RestingForces`).
    pub resting: Option<RestingContacts>,
    /// The keys of the contacts resting since the last impact stage (ordered: no hashing reaches the answers).
    pub resting_keys: BTreeSet<ContactKey>,
    /// Largest penetration found at the last impact stage or contact step (m).
    pub penetration: f64,
    /// The stall window of the integration: its start time and the accepted steps in it.
    pub window: (f64, usize),
    /// The touching phase, while bodies touch.
    pub touching: Option<TouchingPhase>,
    pub scales: ContactScales,
}

impl ContactMemory {
    /// Whether it fits a scene of `actors` actors and `colliders` colliders and a state of length `dim`.
    pub fn check(&self, actors: usize, colliders: usize, dim: usize) -> Result<(), String> {
        let touching_fits = self.touching.as_ref().is_none_or(|t| t.fits(actors, colliders, dim));
        let checks = [
            (
                self.resting.as_ref().is_none_or(|r| r.fits(actors, colliders)),
                "a resting contact names no actor or collider",
            ),
            (self.resting_keys.iter().all(|k| k.fits(colliders)), "a resting key names no collider"),
            (touching_fits, "its touching phase does not fit the collider_set"),
            (self.penetration.is_finite(), "its penetration is not finite"),
            (self.scales.valid(), "its scales are not positive and finite"),
        ];
        match checks.iter().find(|(ok, _)| !ok) {
            Some((_, why)) => Err(why.to_string()),
            None => Ok(()),
        }
    }

    /// The touching phase's time and state where it keeps its own (between the calls it spans), else none.
    pub fn touching_at(&self) -> Option<(f64, &[f64])> {
        self.touching.as_ref().and_then(|p| p.at.as_ref()).map(|(t, y)| (*t, y.as_slice()))
    }

    /// The state the engine is in: the touching phase's own, else `integrator`'s.
    pub fn state_or<'a>(&'a self, integrator: &'a [f64]) -> &'a [f64] {
        self.touching_at().map_or(integrator, |(_, y)| y)
    }

    /// With the free flight's integration made live: one read from a file is given to an integrator of `system`
    /// with its touching actors held (built at (t, y) with `settings`), which checks it.
    pub fn into_live(
        mut self,
        system: &mut AccurateSystem,
        settings: &Settings,
        t: f64,
        y: &[f64],
    ) -> Result<ContactMemory, String> {
        let Some(free) = self.touching.as_mut().and_then(|t| t.free.take()) else { return Ok(self) };
        let held_components = free.held_components;
        let template = || {
            system.held_components.clone_from(&held_components);
            let built = Integrator::new(system, settings.clone(), t, y);
            system.held_components.clear();
            built
        };
        let integration = free.integration.into_live(template).map_err(|e| format!("its free flight's {e}"))?;
        if let Some(touching) = self.touching.as_mut() {
            touching.free = Some(FreeFlight { held_components, integration });
        }
        Ok(self)
    }
}
