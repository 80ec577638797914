//! Passes through in accurate mode: a pair apart at both ends of an accepted step can still have met inside it (a
//! fast body through a thin one, a hop that comes back). Pairs whose end distances leave room for a contact are
//! searched along the step's dense output by a distance-bounded bisection (`tumble_collide::first_contact`).

use super::contact_stages::ContactStages;
use super::system::AccurateSystem;
use crate::engine::failure::failure;
use crate::engine::found_contact::FoundContact;
use crate::model::actor_poses;
use crate::plan::Stage;
use nalgebra::Isometry3;
use std::collections::BTreeSet;
use std::sync::Arc;
use tumble_collide::{distance, first_contact, ShapeError, ToiMethod, ToiOptions};
use tumble_integrate::{OdeError, StepView};

/// The earliest contact time among the collider `pairs` that are apart at both ends of the step (contacts
/// `found1` at its end, poses `poses0`/`poses1` at its ends, `speeds` bounds per actor), or None; a grazing
/// pair that exhausts the search gives the step's midpoint (the step is halved).
#[allow(clippy::too_many_arguments)]
pub(super) fn pass_through(
    cx: &mut ContactStages<'_>,
    step: &mut StepView<'_, AccurateSystem>,
    pairs: &[(usize, usize)],
    found1: &[FoundContact],
    poses0: &[Isometry3<f64>],
    poses1: &[Isometry3<f64>],
    speeds: &[(f64, f64)],
) -> Result<Option<f64>, OdeError> {
    let (t0, t1) = (step.t0(), step.t1());
    let h = t1 - t0;
    let delta = cx.settings.contact_distance;
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let mut event: Option<f64> = None;
    // Passes through: pairs apart at both ends whose distances leave room for a contact in between.
    let touching: BTreeSet<(usize, usize)> =
        found1.iter().map(|f| (f.key.colliders.0 as usize, f.key.colliders.1 as usize)).collect();
    for &(i, j) in pairs.iter().filter(|p| !touching.contains(p)) {
        let (sa, sb, oa, ob, ia, ib) = cx.collider_set.shapes(i, j);
        let (sa, sb) = (sa.clone(), sb.clone());
        let d0 = distance(&sa, &(poses0[ia] * oa), &sb, &(poses0[ib] * ob)).unwrap_or(f64::INFINITY);
        let d1 = distance(&sa, &(poses1[ia] * oa), &sb, &(poses1[ib] * ob)).unwrap_or(f64::INFINITY);
        let closing = speeds[ia].0 + speeds[ib].0;
        if d1 <= delta || d0 + d1 > closing * h {
            continue;
        }
        let mut trouble: Option<OdeError> = None;
        let model_statics = statics.clone();
        let mut poses = |t: f64| -> Result<(Isometry3<f64>, Isometry3<f64>), ShapeError> {
            let y = step.state_at(t).map_err(|e| {
                let msg = e.to_string();
                trouble = Some(e);
                ShapeError { name: "poses", reason: msg }
            })?;
            let p = actor_poses(step.system().model.layout, &y, &model_statics);
            Ok((p[ia] * oa, p[ib] * ob))
        };
        let options = ToiOptions {
            method: ToiMethod::Bisection,
            tolerance: (delta / closing.max(1e-300)).max(cx.settings.time_tolerance),
            max_iterations: 10_000,
        };
        // A pair touching at the step's start (it has just bounced apart) is searched from the first of
        // t0 + h/2^30, h/2^29, ..., h/2 at which it is clear, so that coming back later in a long step (a
        // ballistic flight that Dormand-Prince takes in one step) is not missed; one still touching at t0 + h/2
        // is left to the next step.
        let mut start = t0;
        if d0 <= delta {
            let clear = (1..=30).rev().map(|k| t0 + h / f64::from(1u32 << k)).find(|&t| {
                poses(t).ok().and_then(|(pa, pb)| distance(&sa, &pa, &sb, &pb).ok()).is_some_and(|d| d > delta)
            });
            match clear {
                Some(t) => start = t,
                None => continue,
            }
        }
        match first_contact(&sa, &sb, poses, start, t1, closing, &options) {
            Ok(Some(hit)) => {
                cx.report.bisection_steps += hit.iterations;
                cx.report.stages.add(Stage::Bisection, hit.iterations);
                event = Some(event.map_or(hit.time, |e: f64| e.min(hit.time)));
            }
            Ok(None) => {}
            // A pair that grazes (apart by little more than the contact distance while turning fast) can need
            // more queries than the search may make: the step is cut in half instead, and the next one searches
            // a shorter interval.
            Err(e) if trouble.is_none() && e.name == "options" => {
                cx.report.bisection_steps += options.max_iterations;
                let half = t0 + 0.5 * h;
                event = Some(event.map_or(half, |e: f64| e.min(half)));
            }
            Err(e) => return Err(trouble.unwrap_or_else(|| failure(t0, format!("pass-through search: {e}")))),
        }
    }
    Ok(event)
}
