//! The impact stage of accurate mode, run at each event: find the touching contacts. When one of them has
//! friction, or the world has joints, the touching phase takes over from here (its convex steps resolve the impact
//! with friction and restitution). Otherwise apply impulses to those that close (all at once, restitution only where the closing
//! speed exceeds the resting speed); contacts that then neither close nor open start the touching phase, or, with
//! `Persistent::RestingForces`, are lifted back to zero gap if they drifted and handed to the right-hand side as
//! the resting set. Bounces slower than the resting speed are absorbed, so a bouncing ball comes to rest after
//! finitely many bounces instead of an endless cascade.

use super::contact_stages::ContactStages;
use super::drift::correct_drift;
use super::qp;
use super::resting::{RestingContact, RestingContacts};
use super::system::AccurateSystem;
use super::touching::start_touching;
use crate::engine::failure::failure;
use crate::engine::found_contact::FoundContact;
use crate::mode::Persistent;
use crate::model::layout::set3;
use crate::model::{actor_poses, Model};
use crate::plan::Stage;
use std::sync::Arc;
use std::time::Instant;
use tumble_collide::rotated_tensor;
use tumble_contact::Contact;
use tumble_integrate::{Integrator, OdeError};

/// The impact stage at the integrator's current state: find, impulses, drift correction, resting set.
pub fn impact(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    integ: &mut Integrator<AccurateSystem>,
) -> Result<(), OdeError> {
    let model = &mut system.model;
    let t = integ.time();
    let mut y = integ.state().to_vec();
    let mut active = touching_contacts(cx, model, &y, t)?;
    let steps = cx.settings.persistent == Persistent::ContactSteps;
    // with friction, or joints (which Newton's impulses know nothing of), or without clarabel (the impulses are its
    // QP), the convex steps take the impact
    let joined = (model.has_joints() || !cfg!(feature = "clarabel")) && !active.is_empty();
    if steps && (joined || active.iter().any(|(f, _)| f.contact.friction > 0.0)) {
        cx.memory.resting = None;
        start_touching(cx);
        return Ok(());
    }
    if let Some((f, _)) = active.iter().find(|(f, _)| f.contact.friction > 0.0) {
        return Err(failure(
            t,
            format!(
                "a contact with friction {} at resting forces, which are frictionless (use \
                 Persistent::ContactSteps, or friction 0)",
                f.contact.friction
            ),
        ));
    }
    let clock = Instant::now();
    if active.iter().any(|(_, v)| *v < 0.0) {
        apply_impulses(cx, model, &mut y, &mut active, t)?;
    }
    // Only contacts that now neither close nor open rest; what bounced away (or was drifting apart) leaves,
    // and if it comes back slower than the resting speed, it is stopped then.
    active.retain(|(_, v)| *v <= 1e-3 * cx.memory.scales.resting_speed);
    if steps {
        cx.memory.resting = None;
        if !active.is_empty() {
            start_touching(cx);
        }
        integ.set_state(t, &y)?;
        cx.report.contact_seconds += clock.elapsed().as_secs_f64();
        return Ok(());
    }
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let delta = cx.settings.contact_distance;
    if active.iter().any(|(f, _)| f.contact.distance < -delta) {
        let states = contact_states(model, &y, &statics);
        let contacts: Vec<Contact> = active.iter().map(|(f, _)| f.contact).collect();
        cx.report.qp_solves += correct_drift(model, &mut y, &states, &contacts, cx.solver, t)?;
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(OdeError::NonFinite { t, what: "state after the impact stage", index: i });
    }
    let poses = actor_poses(model.layout, &y, &statics);
    let contacts: Vec<RestingContact> = active.iter().map(|(f, _)| RestingContact::attach(f, &poses)).collect();
    cx.memory.resting_keys = contacts.iter().map(|c| c.key).collect();
    cx.memory.resting = Some(RestingContacts { contacts, reach: delta });
    integ.set_state(t, &y)?;
    cx.report.contact_seconds += clock.elapsed().as_secs_f64();
    Ok(())
}

/// The contacts touching in state y that do not separate faster than the resting speed, with their relative
/// normal velocities. The bisection stops up to `time_tolerance` before contact, when a pair may still be apart
/// by as much as it closes in that time: contacts within that distance (plus the contact distance) count.
fn touching_contacts(
    cx: &mut ContactStages<'_>,
    model: &mut Model,
    y: &[f64],
    t: f64,
) -> Result<Vec<(FoundContact, f64)>, OdeError> {
    let clock = Instant::now();
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let states = contact_states(model, y, &statics);
    let poses = actor_poses(model.layout, y, &statics);
    let closing = cx.collider_set.reach(&states, 2.0 * cx.settings.time_tolerance);
    let checks = cx.collider_set.checks;
    let found = cx.collider_set.find(&poses, &closing, cx.settings.contact_distance).map_err(|e| failure(t, e))?;
    cx.report.collision_checks += cx.collider_set.checks - checks;
    cx.report.stages.mark(Stage::CollisionDetection);
    cx.memory.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
    cx.report.max_penetration = cx.report.max_penetration.max(cx.memory.penetration);
    let v_rest = cx.memory.scales.resting_speed;
    let active = found
        .into_iter()
        .map(|f| {
            let v = f.contact.relative_normal_velocity(&states);
            (f, v)
        })
        .filter(|(_, v)| *v <= v_rest)
        .collect();
    cx.report.collision_seconds += clock.elapsed().as_secs_f64();
    Ok(active)
}

/// Newton's law at every active contact at once; the relative normal velocities are updated.
fn apply_impulses(
    cx: &mut ContactStages<'_>,
    model: &mut Model,
    y: &mut [f64],
    active: &mut [(FoundContact, f64)],
    t: f64,
) -> Result<(), OdeError> {
    let statics = &cx.collider_set.static_poses;
    let v_rest = cx.memory.scales.resting_speed;
    let states = contact_states(model, y, statics);
    let contacts: Vec<Contact> = active
        .iter()
        .map(|(f, v)| Contact { restitution: if *v < -v_rest { f.contact.restitution } else { 0.0 }, ..f.contact })
        .collect();
    let (velocities, magnitudes, calls) =
        qp::impulses(&states, &contacts, cx.solver).map_err(|e| failure(t, format!("impulses: {e}")))?;
    cx.report.stages.mark(Stage::Impulses);
    cx.report.qp_solves += calls;
    cx.report.collisions += active.iter().filter(|(_, v)| *v < -v_rest).count();
    cx.report.impulses += magnitudes.iter().filter(|&&j| j > 0.0).count();
    write_velocities(model, y, &velocities);
    let states = contact_states(model, y, statics);
    for (f, v) in active.iter_mut() {
        *v = f.contact.relative_normal_velocity(&states);
    }
    Ok(())
}

/// The actors in state y without applied forces.
fn contact_states(
    model: &mut Model,
    y: &[f64],
    statics: &[nalgebra::Isometry3<f64>],
) -> Vec<tumble_contact::BodyState> {
    let dp = vec![0.0; y.len() - model.layout.positions()];
    model.contact_states(&model.kinematics(y), y, &dp, statics, &[])
}

/// Writes the velocities of tumble-contact's bodies into state y (momenta for bodies).
#[allow(clippy::needless_range_loop)]
fn write_velocities(model: &Model, y: &mut [f64], v: &[tumble_contact::BodyVelocity]) {
    let (l, kin) = (model.layout, model.kinematics(y));
    for i in 0..l.particles {
        set3(y, l.pv(i), &v[i].linear);
    }
    for (j, b) in model.bodies.iter().enumerate() {
        let k = &kin[j];
        let a = l.body_actor(j);
        set3(y, l.bp(j), &(v[a].linear * b.mass));
        set3(y, l.bl(j), &(rotated_tensor(&k.rot, &b.inertia) * v[a].angular));
    }
}
