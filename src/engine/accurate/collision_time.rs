//! Collision time in accurate mode, the chapter's bisection: when a contact that is not resting interpenetrates at
//! the end of an accepted step, the step's dense output is bisected for the last time before any such contact
//! interpenetrates, to the time tolerance.

use super::contact_stages::ContactStages;
use super::system::AccurateSystem;
use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::model::actor_poses;
use crate::plan::Stage;
use nalgebra::Isometry3;
use std::collections::BTreeSet;
use std::sync::Arc;
use tumble_integrate::{OdeError, StepView};

/// How far parry's manifolds of a touching pair can jump from one instant to the next, as a share of the two shapes'
/// radii: a cylinder 3e-10 m from a 75 kg box had no contact at a step's start and one 1.2e-10 m deep an ulp of time
/// later, an event at the same time for ever at a tolerance of 1e-7 m.
const MANIFOLD_NOISE: f64 = 1e-9;

/// Most halvings of a step's collision-time bisection (2^-100 of the step).
const HALVINGS: usize = 100;

/// The time of the first new collision in the step (contacts `found1` at its end; actor poses `poses0` at its
/// start), or None.
pub(super) fn collision_time(
    cx: &mut ContactStages<'_>,
    step: &mut StepView<'_, AccurateSystem>,
    found1: &[FoundContact],
    poses0: &[Isometry3<f64>],
) -> Result<Option<f64>, OdeError> {
    let (t0, t1) = (step.t0(), step.t1());
    let delta = cx.settings.contact_distance;
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let resting = &cx.memory.resting_keys;
    // In a pair that was already touching at the step's start (a contact within the contact distance), a contact
    // that is not resting (it was opening) collides only once it sinks past 1e-3 of the contact distance
    // (1e-10 m by default) or past parry's noise (`MANIFOLD_NOISE`); in other pairs, as soon as it interpenetrates.
    // Touching contacts sit at a gap of zero give or take rounding (+-4e-13 m seen; parry may also renumber their
    // features), so a light body under a heavy one would otherwise raise an event at every step. The collision time of such a contact is off by
    // at most that depth over the closing speed (3e-11 s for the bouncing ball).
    // The collider pairs of the contacts that satisfy `pick`, each once.
    let pairs_where = |pick: &dyn Fn(&FoundContact) -> bool| -> Vec<(usize, usize)> {
        let mut p: Vec<(usize, usize)> = found1
            .iter()
            .filter(|f| pick(f))
            .map(|f| (f.key.colliders.0 as usize, f.key.colliders.1 as usize))
            .collect();
        p.sort_unstable();
        p.dedup();
        p
    };
    let candidate = pairs_where(&|f| !resting.contains(&f.key) && f.contact.distance < 0.0);
    let touching0: BTreeSet<(u32, u32)> = if candidate.is_empty() {
        BTreeSet::new()
    } else {
        let found0 = cx.collider_set.pair_contacts(&candidate, poses0, |_, _| delta);
        let mut touching: BTreeSet<(u32, u32)> =
            found0.iter().filter(|f| f.contact.distance <= delta).map(|f| f.key.colliders).collect();
        // parry's manifolds can leave out a touching piece of a compound (a cylinder at a gap of 1e-9 m from a
        // mesh's piece: no manifold at the step's start, -4e-11 m an ulp of time later, an event at the same time
        // for ever): the pair's distance decides too
        for &(i, j) in &candidate {
            if !touching.contains(&(i as u32, j as u32)) && cx.collider_set.pair_distance(i, j, poses0) <= delta {
                touching.insert((i as u32, j as u32));
            }
        }
        touching
    };
    // In a pair that has resting contacts, a contact parry names differently (it may renumber the features of
    // one geometric contact from step to step) is not a new collision unless it sinks as deep as a drift does.
    let resting_pairs: BTreeSet<(u32, u32)> = resting.iter().map(|k| k.colliders).collect();
    let radius: Vec<f64> =
        cx.collider_set.colliders.iter().map(|c| if c.radius.is_finite() { c.radius } else { 0.0 }).collect();
    let hits = |f: &FoundContact, resting: &BTreeSet<ContactKey>| {
        let depth = if resting_pairs.contains(&f.key.colliders) {
            -delta
        } else if touching0.contains(&f.key.colliders) {
            let (i, j) = (f.key.colliders.0 as usize, f.key.colliders.1 as usize);
            -(1e-3 * delta).max(MANIFOLD_NOISE * (radius[i] + radius[j]))
        } else {
            0.0
        };
        !resting.contains(&f.key) && f.contact.distance < depth
    };
    let fresh = pairs_where(&|f| hits(f, resting));
    let mut event: Option<f64> = None;
    if !fresh.is_empty() {
        // The chapter's bisection: the last time before any new contact interpenetrates. It goes on past the
        // tolerance until the time has moved off the step's start: a flight shorter than the tolerance (a tiny
        // bounce) would otherwise stop at t0 again and again. At most `HALVINGS` halvings: a contact that is
        // already in at the step's start (a body placed inside another) would otherwise be halved toward t0 down
        // to the last bit, a thousand fresh sub-steps for methods without dense output, at every step.
        let (mut lo, mut hi) = (t0, t1);
        let mut halvings = 0;
        while (hi - lo > cx.settings.time_tolerance || lo <= t0) && halvings < HALVINGS {
            halvings += 1;
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            cx.report.bisection_steps += 1;
            cx.report.stages.mark(Stage::Bisection);
            let y = step.state_at(mid)?;
            let poses = actor_poses(step.system().model.layout, &y, &statics);
            let found = cx.collider_set.pair_contacts(&fresh, &poses, |_, _| delta);
            if found.iter().any(|f| hits(f, &cx.memory.resting_keys)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        event = Some(lo);
    }
    Ok(event)
}
