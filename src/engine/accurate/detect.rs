//! After each accepted step of accurate mode, the contact check, as a list of stages: the pairs whose boxes swept
//! over the step overlap, their contacts at the step's end, then the collision time of a new contact
//! (`collision_time.rs`), passes through (`pass_through.rs`) and drift of a resting contact (`drift.rs`), and a
//! joint's break (`breaking.rs`); the earliest of these is where the step is cut.

use super::collision_time::collision_time;
use super::contact_stages::ContactStages;
use super::drift::drifted;
use super::pass_through::pass_through;
use super::system::AccurateSystem;
use crate::engine::failure::failure;
use crate::model::layout::get3;
use crate::model::{actor_poses, Model};
use crate::plan::Stage;
use nalgebra::Isometry3;
use std::sync::Arc;
use std::time::Instant;
use tumble_integrate::{OdeError, StepView};

/// Accepted steps over which the mean step is watched: below the stall step, the advance gives up (contact forces
/// the method cannot follow: a light body under one a million times heavier took steps of 5e-9 to 5e-7 s, 15 s of
/// work per simulated millisecond).
const STALL: usize = 2_000;

/// The earlier of two optional times.
fn earliest(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Looks at an accepted step for a collision, a pass through a thin body or drift of a resting contact;
/// returns the time to stop at.
pub fn detect(cx: &mut ContactStages<'_>, step: &mut StepView<'_, AccurateSystem>) -> Result<Option<f64>, OdeError> {
    watch_for_stall(cx, step.t0(), step.t1())?;
    let clock = Instant::now();
    let result = detect_stages(cx, step);
    cx.report.collision_seconds += clock.elapsed().as_secs_f64();
    let until = result?;
    let broke = super::breaking::break_time(step, until, cx.averages, cx.settings.time_tolerance, cx.report)?;
    Ok(earliest(until, broke))
}

/// Fails when `STALL` accepted steps have taken less than `STALL` stall steps of time: the forces (with
/// `Persistent::RestingForces`, the resting-contact forces) have made the method crawl, and the call would
/// otherwise run for hours.
fn watch_for_stall(cx: &mut ContactStages<'_>, t0: f64, t1: f64) -> Result<(), OdeError> {
    let (start, steps) = cx.memory.window;
    let start = if steps == 0 { t0 } else { start };
    if steps + 1 < STALL {
        cx.memory.window = (start, steps + 1);
        return Ok(());
    }
    cx.memory.window = (t1, 0);
    let mean = (t1 - start) / STALL as f64;
    if mean < cx.memory.scales.stall_step {
        return Err(failure(
            t1,
            format!(
                "{} steps took {:.1e} s, a mean step of {mean:.1e} s: the motion is too stiff for this method \
                 at its tolerances (try fast mode, looser tolerances, or an implicit method if this one is \
                 explicit)",
                STALL,
                t1 - start
            ),
        ));
    }
    Ok(())
}

fn detect_stages(cx: &mut ContactStages<'_>, step: &mut StepView<'_, AccurateSystem>) -> Result<Option<f64>, OdeError> {
    let (t0, t1) = (step.t0(), step.t1());
    let h = t1 - t0;
    let delta = cx.settings.contact_distance;
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let model = &step.system().model;
    let poses0 = actor_poses(model.layout, step.y0(), &statics);
    let poses1 = actor_poses(model.layout, step.y1(), &statics);
    let speeds = speeds(cx, model, step.y0(), step.y1(), &statics);
    // Boxes swept between the ends, grown by how far a curved path can bulge from its chord.
    let margins: Vec<f64> = speeds.iter().map(|(s, bulge)| bulge * h + delta + 1e-12 * s).collect();
    let checks = cx.collider_set.checks;
    cx.report.stages.mark(Stage::CollisionDetection);
    let pairs = cx.collider_set.swept_pairs(&poses0, &poses1, &margins).map_err(|e| failure(t0, e))?;
    if pairs.is_empty() {
        return Ok(None);
    }
    let found1 = cx.collider_set.pair_contacts(&pairs, &poses1, |_, _| delta);
    // A resting contact that sank past the contact distance has drifted; any other contact that interpenetrates
    // at all is a collision.
    let drift = drifted(&found1, &cx.memory.resting_keys, delta);
    let collision = collision_time(cx, step, &found1, &poses0)?;
    let pass = pass_through(cx, step, &pairs, &found1, &poses0, &poses1, &speeds)?;
    cx.report.collision_checks += cx.collider_set.checks - checks;
    Ok(earliest(earliest(collision, pass), drift.then_some(t1)))
}

/// Per actor: a bound on the speed of its points over the step (the larger of the two ends, +10% for the
/// interpolant), and how fast its velocity changes (|v1 - v0| / 4, the bulge of its path per unit time).
#[allow(clippy::needless_range_loop)]
fn speeds(
    cx: &ContactStages<'_>,
    model: &Model,
    y0: &[f64],
    y1: &[f64],
    statics: &[Isometry3<f64>],
) -> Vec<(f64, f64)> {
    let l = model.layout;
    let mut radius = vec![0.0f64; cx.collider_set.actors()];
    for c in &cx.collider_set.colliders {
        let a = cx.collider_set.index(c.actor);
        radius[a] = radius[a].max(if c.reach.is_finite() { c.reach } else { 0.0 });
    }
    let mut out = vec![(0.0, 0.0); l.actors() + statics.len()];
    for i in 0..l.particles {
        let (v0, v1) = (get3(y0, l.pv(i)), get3(y1, l.pv(i)));
        out[i] = (1.1 * v0.norm().max(v1.norm()), 0.25 * (v1 - v0).norm());
    }
    for j in 0..l.bodies {
        let a = l.body_actor(j);
        let (k0, k1) = (model.body_kin(y0, j), model.body_kin(y1, j));
        let s0 = k0.velocity.norm() + k0.omega.norm() * radius[a];
        let s1 = k1.velocity.norm() + k1.omega.norm() * radius[a];
        let change = (k1.velocity - k0.velocity).norm()
            + (k1.omega - k0.omega).norm() * radius[a]
            + 0.5 * k0.omega.norm().max(k1.omega.norm()).powi(2) * radius[a];
        out[a] = (1.1 * s0.max(s1), 0.25 * change);
    }
    out
}
