//! Rest inside a moving island: an actor that has moved slower than the resting speed for the sleep time while its
//! island still moves is held, as a sleeping island is (a fixed body to the contact steps, still in free flight).
//! After each step, the held actors that awake ones touch are checked: freed alone, with the awake actors' forces on
//! them applied as loads and every other actor fixed where it is (the awake ones too: what leans on an awake actor
//! is held up by it, as by any other), would a contact step as long as the sleep time T move them?
//! One whose fastest point would move more than the contact tolerance in it wakes, and the step is taken again with
//! it moving. (A step of T, not of the step being taken: the answers' own accuracy is a share of the tolerance over
//! the step they are asked for, so a check over a short step could not tell a push from the solver's noise.) A check
//! by motion, not by the loads themselves: the forces among resting bodies that lean on
//! each other are not unique (how a leaning domino's weight is shared between the floor and the next is any of many
//! answers), and change from solve to solve while nothing moves. So the fallen half of a domino row costs nothing
//! while its front moves on, and a box dropped on it wakes what it pushes.

use super::contact_stages::ContactStages;
use super::convex_step::{actors_with_forces, convex_step, every_contact_in_reach};
use super::sleep::{speed, Sleep};
use super::system::AccurateSystem;
use super::touching_phase::TouchingPhase;
use crate::engine::found_contact::{ContactKey, FoundContact};
use nalgebra::Vector3;
use std::collections::BTreeMap;
use tumble_contact::BodyState;
use tumble_integrate::OdeError;

impl Sleep {
    /// Whether `actor` is held inside a moving island.
    pub fn is_held(&self, actor: usize) -> bool {
        self.held.binary_search(&actor).is_ok()
    }

    /// Holds `actor` (the caller zeroes its velocity).
    pub(super) fn hold_actor(&mut self, actor: usize) {
        if let Err(at) = self.held.binary_search(&actor) {
            self.held.insert(at, actor);
        }
    }

    /// Wakes the held actors among `actors`; whether any woke.
    pub fn release(&mut self, actors: impl Iterator<Item = usize>) -> bool {
        let before = self.held.len();
        for a in actors {
            if let Ok(at) = self.held.binary_search(&a) {
                self.held.remove(at);
            }
        }
        self.held.len() < before
    }
}

/// The held actors that a step from (t, y) with the contacts `found` (their whole forces `forces`, on B, by key)
/// would set moving (the module's check), in increasing order.
#[allow(clippy::too_many_arguments)]
pub(super) fn set_moving(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    phase: &TouchingPhase,
    found: &[FoundContact],
    forces: &BTreeMap<ContactKey, Vector3<f64>>,
    (t, y): (f64, &[f64]),
) -> Result<Vec<usize>, OdeError> {
    let sleep = &phase.sleep;
    let l = system.model.layout;
    let actors = l.actors();
    let awake = |k: usize| k < actors && !sleep.resting_actor(k);
    let loaded = |a: usize, b: usize| a < actors && sleep.is_held(a) && awake(b);
    if !found.iter().any(|f| loaded(f.contact.a, f.contact.b) || loaded(f.contact.b, f.contact.a)) {
        return Ok(Vec::new());
    }
    // the awake actors' loads on the held ones they touch: force and moment about the held one's centre
    let mut loads: BTreeMap<usize, (Vector3<f64>, Vector3<f64>)> = BTreeMap::new();
    let real = actors_with_forces(system, statics, t, y)?;
    for f in found {
        let (a, b) = (f.contact.a, f.contact.b);
        for (held, other, sign) in [(a, b, -1.0), (b, a, 1.0)] {
            if loaded(held, other) {
                let force = forces.get(&f.key).map_or(Vector3::zeros(), |w| w * sign);
                let load = loads.entry(held).or_insert((Vector3::zeros(), Vector3::zeros()));
                load.0 += force;
                load.1 += (f.contact.point - real[held].position).cross(&force);
            }
        }
    }
    // the loaded held actors freed, with those loads; every other actor fixed where it is
    let states: Vec<BodyState> = real
        .iter()
        .enumerate()
        .map(|(k, s)| match loads.get(&k) {
            Some((force, moment)) => BodyState { force: s.force + force, torque: s.torque + moment, ..*s },
            None if k < actors => BodyState::fixed(s.position),
            None => *s,
        })
        .collect();
    let (tolerance, check) = (cx.memory.scales.tolerance, cx.settings.sleep_time.max(f64::MIN_POSITIVE));
    // (the awake actors are fixed too, their contacts kept: their loads push, and what leans on them is held up)
    let (near, _) = every_contact_in_reach(cx, &system.model, &states, y, t, check)?;
    let loaded: Vec<usize> = loads.keys().copied().collect();
    let Some(step) = convex_step(cx, &system.model, &states, &near, (&phase.lagged, &phase.warm), t, y, check)? else {
        // no answer: they move, to be safe
        return Ok(loaded);
    };
    Ok(loaded.into_iter().filter(|&k| speed(&system.model, &step.y, k) * check > tolerance).collect())
}
