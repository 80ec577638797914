//! Accurate mode's touching phase for the actors that touch nothing: while some bodies touch, the actors in no
//! contact of a step (and joined to none by a spring) follow the integrator over that step, under its own error
//! control, with the touching actors held still. Their error then never sets the contact step, which is for the
//! contacts alone: a fast damped particle flying beside a settling pile made every contact step 4e-5 s (first-order
//! contact steps following its smooth motion), 21 s of work for a quarter second. What the free flight carries from
//! step to step is `FreeFlight` (`free_flight_memory.rs`).

use super::contact_stages::ContactStages;
use super::free_flight_memory::FreeFlight;
use super::integration::within_budget;
use super::integration::Integration;
use super::system::AccurateSystem;
use crate::engine::budget::Budget;
use crate::engine::found_contact::FoundContact;
use crate::model::layout::Layout;
use crate::model::Model;
use tumble_integrate::OdeError;

/// Which actors (particles, then dynamic bodies) take part in a step with the contacts `found`: those of a
/// contact, and those joined to them by springs, transitively.
pub(crate) fn involved(model: &Model, found: &[&[FoundContact]]) -> Vec<bool> {
    let l = model.layout;
    let n = l.actors();
    let mut out = vec![false; n];
    for f in found.iter().flat_map(|f| f.iter()) {
        for a in [f.contact.a, f.contact.b] {
            if a < n {
                out[a] = true;
            }
        }
    }
    let links = links(model);
    for _ in 0..=links.len() {
        let mut changed = false;
        for &(a, b) in &links {
            if out[a] != out[b] {
                (out[a], out[b]) = (true, true);
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    out
}

/// The pairs of actors (particles, then dynamic bodies) joined by a spring or a joint.
pub(crate) fn links(model: &Model) -> Vec<(usize, usize)> {
    let l = model.layout;
    let springs = model.springs.iter().map(|s| (s.a.actor(l), s.b.actor(l)));
    let joints = model.holding_joints().map(|(_, j)| (j.a.actor(l), j.b.actor(l)));
    springs.chain(joints).filter_map(|(a, b)| Some((a?, b?))).collect()
}

/// The state components of actor `a`.
fn components(l: Layout, a: usize) -> Vec<usize> {
    let blocks = if a < l.particles {
        vec![(l.px(a), 3), (l.pv(a), 3)]
    } else {
        let j = a - l.particles;
        vec![(l.bx(j), 3), (l.bq(j), 4), (l.bp(j), 3), (l.bl(j), 3)]
    };
    blocks.into_iter().flat_map(|(k, n)| k..k + n).collect()
}

/// Copies the free actors' components of `from` into `to`.
pub(crate) fn copy_free(model: &Model, involved: &[bool], from: &[f64], to: &mut [f64]) {
    for (a, _) in involved.iter().enumerate().filter(|(_, i)| !**i) {
        for k in components(model.layout, a) {
            to[k] = from[k];
        }
    }
}

/// The state at t + h of the actors not `involved`, advanced from (t, y) by the integrator with the others held
/// still (the other components of the answer are y's); `None` when every actor is involved. Its steps are
/// charged to the call's `budget`; its counters go to the report.
#[allow(clippy::too_many_arguments)]
pub fn free_flight(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    free: &mut Option<FreeFlight>,
    involved: &[bool],
    t: f64,
    y: &[f64],
    h: f64,
    budget: &mut Budget<'_>,
) -> Result<Option<Vec<f64>>, OdeError> {
    if involved.iter().all(|i| *i) {
        return Ok(None);
    }
    let held_components: Vec<usize> =
        (0..involved.len()).filter(|a| involved[*a]).flat_map(|a| components(system.model.layout, a)).collect();
    system.held_components = held_components;
    let result = (|| {
        let settings = cx.free_settings.clone();
        let flight = match free.take() {
            Some(mut f) if f.held_components == system.held_components => {
                f.integration.live_mut().set_state(t, y)?;
                f
            }
            _ => FreeFlight {
                held_components: system.held_components.clone(),
                integration: Integration::new(system, settings, t, y)?,
            },
        };
        let flight = free.insert(flight);
        let integrator = flight.integration.live_mut();
        let advanced = within_budget(integrator, budget, Some(t), |i| i.advance_to(system, t + h, &[], |_, _, _| {}));
        cx.free_report.merge(&integrator.take_report());
        advanced?;
        let mut out = y.to_vec();
        copy_free(&system.model, involved, integrator.state(), &mut out);
        Ok(Some(out))
    })();
    system.held_components.clear();
    result
}
