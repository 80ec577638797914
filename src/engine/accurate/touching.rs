//! Accurate mode while bodies touch: convex contact steps (`convex_step.rs`) under error control by step doubling,
//! after Drake's CENIC (Kurtz and Castro, 2025). Each step of h is taken once whole and once as two halves (the first
//! half on the whole step's contacts); their difference d = y_half - y_whole estimates the error of the halves, in
//! metres: positions, body turns times the radius of gyration, and velocity differences times h (what they become a
//! step later). The accepted state is the halves extrapolated, 2 y_half - y_whole (second order; exact for the
//! constant forces of sliding, rolling and resting), unless the two disagree on which contacts pushed, the
//! extrapolation sinks a contact deeper than the halves do, or it has more energy than the step started with; then
//! the halves are kept. The extrapolated state's own error is estimated by how d changed since the last step,
//! |d - (h / h_last)^2 d_last| (zero while the forces are constant, of order h^3 while they vary smoothly), and its
//! sinking; the halves' by |d|, their sinking and the slip of a sliding contact that stopped. Events (a change of
//! which contacts push, a stop) take the halves' estimate. A step is accepted when its estimate is at most the
//! contact tolerance, and the next h is h (tol / err)^(1/3) after a smooth extrapolated step and h (tol / err)^(1/2)
//! otherwise, within 0.2 to 2 times h and at most the scene's time scale (what bounds the pairs a step's reach takes
//! in). Only the end of an advance cuts a step: frames inside one are its linear interpolation. Contacts that sank
//! past the tolerance are lifted apart by a position projection before the step. Sleeping islands (`sleep.rs`) are
//! fixed bodies to the steps. The phase ends when no pair is within reach of a step and nothing sleeps: the
//! integrator takes over.

use super::contact_stages::ContactStages;
use super::convex_step::{actors_with_forces, convex_step, every_contact_in_reach, ConvexStep, ANSWER_SHARE};
use super::drift::correct_drift;
use super::failure;
use super::free_flight::{copy_free, free_flight, involved, links, FreeFlight};
use super::sleep::Sleep;
use super::step_estimate::{extrapolate, interpolate, momenta, sinking, stopped_slip};
use super::system::AccurateSystem;
use crate::engine::found_contact::ContactKey;
use crate::engine::last_contacts::LastContact;
use crate::engine::semi_implicit::Form;
use crate::engine::state_error::state_difference;
use crate::engine::Budget;
use crate::run::Run;
use std::collections::{BTreeMap, BTreeSet};
use tumble_integrate::OdeError;

/// What the touching phase carries from step to step (part of the engine's memory).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct TouchingPhase {
    /// Each contact's normal force of the last accepted step (the next step's first friction bound).
    pub lagged: BTreeMap<ContactKey, f64>,
    /// The step the error control proposes.
    pub h: f64,
    /// The stall window: its start time and the steps tried in it.
    pub window: (f64, usize),
    /// The integrator of the actors that touch nothing (`free_flight.rs`).
    pub free: Option<FreeFlight>,
    /// The contacts of the last accepted step, with the whole step's impulses.
    pub last: Vec<LastContact>,
    /// The last accepted step's h and its halves' difference d = y_half - y_whole (for the extrapolated state's
    /// error estimate).
    pub difference: Option<(f64, Vec<f64>)>,
    /// The islands asleep and the actors calm (`sleep.rs`).
    pub sleep: Sleep,
    /// Each contact's whole force of the last accepted step (N, normal and friction), where the next step's
    /// solves start from.
    pub warm: BTreeMap<ContactKey, nalgebra::Vector3<f64>>,
}

impl TouchingPhase {
    /// Whether it fits a scene of `actors` actors and `colliders` colliders and a state of length `dim`.
    pub fn fits(&self, actors: usize, colliders: usize, dim: usize) -> bool {
        self.h > 0.0
            && self.h.is_finite()
            && self.lagged.iter().all(|(k, f)| k.fits(colliders) && f.is_finite())
            && self.last.iter().all(|c| c.a < actors && c.b < actors)
            && self.free.as_ref().is_none_or(|f| f.frozen.iter().all(|&k| k < dim))
            && self.sleep.fits(actors)
            && self.warm.iter().all(|(k, f)| k.fits(colliders) && f.iter().all(|x| x.is_finite()))
            && self
                .difference
                .as_ref()
                .is_none_or(|(h, d)| *h > 0.0 && d.len() == dim && d.iter().all(|x| x.is_finite()))
    }
}

/// Steps tried (accepted or rejected) over which the touching phase's progress is watched.
const STALL_WINDOW: usize = 200;

/// How a touching phase's advance ended.
pub(crate) struct TouchingEnd {
    pub t: f64,
    pub y: Vec<f64>,
    /// Frames recorded.
    pub delivered: usize,
    /// Whether the bodies still touch (the advance reached its end); false when they parted.
    pub touching: bool,
}

/// Enters the touching phase with a first step from the tolerance: the time to fall the tolerance, sqrt(2 tol
/// / g), within the phase's step bounds.
pub fn start_touching(cx: &mut ContactStages<'_>) {
    let h = (2.0 * cx.memory.scales.tolerance / cx.gravity.max(1e-300))
        .sqrt()
        .clamp(min_step(0.0), cx.memory.scales.max_step);
    cx.memory.touching = Some(TouchingPhase {
        lagged: BTreeMap::new(),
        h,
        window: (f64::NAN, 0),
        free: None,
        last: Vec::new(),
        difference: None,
        sleep: Sleep::default(),
        warm: BTreeMap::new(),
    });
}

/// How far a contact step may slide a touching pair, as a share of the smaller shape's bounding radius.
const SLIDE_SHARE: f64 = 0.1;

/// The longest step that slides no touching pair of `found` (at its relative tangential speed at the contact
/// point) more than `SLIDE_SHARE` of its smaller shape's radius; pairs with a half-space (whose face has no edge)
/// and pairs apart by more than the tolerance are not limited.
fn slide_limit(
    cx: &ContactStages<'_>,
    found: &[crate::engine::found_contact::FoundContact],
    states: &[tumble_contact::BodyState],
) -> f64 {
    let mut limit = f64::INFINITY;
    let touching = cx.memory.scales.tolerance.max(cx.settings.contact_distance);
    for f in found {
        let (ca, cb) = f.key.colliders;
        let (ra, rb) = (cx.scene.colliders[ca as usize].radius, cx.scene.colliders[cb as usize].radius);
        let c = &f.contact;
        if !ra.max(rb).is_finite() || c.distance > touching {
            continue;
        }
        let r = ra.min(rb);
        let v = states[c.a].point_velocity(&c.point) - states[c.b].point_velocity(&c.point);
        let speed = (v - c.normal.into_inner() * c.normal.dot(&v)).norm();
        if speed > 0.0 {
            limit = limit.min(SLIDE_SHARE * r / speed);
        }
    }
    limit
}

/// The smallest step: 16 ulps of the time, and no less than 1e-14 s.
fn min_step(t: f64) -> f64 {
    (16.0 * f64::EPSILON * t.abs()).max(1e-14)
}

/// The share of the tolerance a sliding contact's stop may cut short inside a step before the step is cut at it.
const STOP_SHARE: f64 = 0.1;
/// The earliest stop located, as a fraction of the step: earlier ones are left to the error control.
const STOP_EARLIEST: f64 = 0.01;

/// Advances from (t, y) by error-controlled contact steps until `t_end` (pausing past `pause`) or until no
/// pair is within reach; each save time reached records a frame. Each step tried is charged to the call's
/// `budget`, a contact step counting each convex program it solved by its size (one unit for every eight
/// contacts of the island, `VelocityStep::solver_work`).
#[allow(clippy::too_many_arguments)]
pub fn touching_steps(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    mut t: f64,
    mut y: Vec<f64>,
    t_end: f64,
    pause: f64,
    saves: &[f64],
    mut run: Option<&mut Run>,
    budget: &mut Budget<'_>,
) -> Result<TouchingEnd, OdeError> {
    let statics = cx.scene.static_poses.clone();
    let slack = 1e-12 * t_end.abs().max(1.0);
    let mut delivered = 0;
    let Some(mut phase) = cx.memory.touching.take() else {
        return Err(failure(t, "contact steps without a touching phase".into()));
    };
    let actors = system.model.layout.particles + system.model.layout.bodies;
    let links = links(&system.model);
    let sleeps = cx.settings.sleep && !system.model.has_joints();
    let sleeping = (cx.memory.scales.resting_speed, cx.settings.sleep_time);
    // whether the step being tried was cut at a stop
    let mut located = false;
    let result = loop {
        while delivered < saves.len() && saves[delivered] <= t + slack {
            if let Some(run) = run.as_deref_mut() {
                run.record(&system.model, t, &y, cx.memory.penetration, phase.last.iter().map(|c| (c.point, c.normal)));
            }
            delivered += 1;
        }
        if t >= pause.min(t_end) - slack {
            break Ok(true);
        }
        // frames do not steer the steps: only the end of the advance cuts one
        let stop = t_end;
        let h = phase.h.min(stop - t);
        let clipped = h < phase.h;
        if let Err(e) = budget.charge(1, t) {
            break Err(e);
        }
        if let Err(e) = watch_touching(cx, &mut phase, t) {
            break Err(e);
        }
        let mut states = held(system, &statics, t, &y, &phase.sleep)?;
        let (mut found, mut every) = every_contact_in_reach(cx, &system.model, &states, &y, t, h)?;
        while phase.sleep.wake_touched(&found, actors) {
            states = held(system, &statics, t, &y, &phase.sleep)?;
            (found, every) = every_contact_in_reach(cx, &system.model, &states, &y, t, h)?;
        }
        if found.is_empty() {
            if phase.sleep.count() == 0 {
                break Ok(false);
            }
            if phase.sleep.count() == actors {
                // everything sleeps: the clock alone, to the next pause
                t = pause.min(t_end);
                continue;
            }
        }
        // a step slides no touching pair past a share of its smaller shape (the contacts' manifolds hold only
        // while their points stay on the faces they were found on: a box pushed off a table's edge at a steady
        // speed makes no error the estimates see)
        let h = h.min(slide_limit(cx, &found, &states));
        let clipped = clipped || h < phase.h;
        cx.memory.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
        if cx.memory.penetration > cx.memory.scales.tolerance {
            // Linearised contacts of turning bodies sink a little each step; past the tolerance, the bodies are
            // moved apart by the smallest position change (velocities untouched, so no energy but the lift's).
            let sunk: Vec<_> = found.iter().filter(|f| f.contact.distance < 0.0).map(|f| f.contact).collect();
            cx.report.qp_solves += correct_drift(&system.model, &mut y, &states, &sunk, cx.solver, t)?;
            cx.report.stages.mark(crate::plan::Stage::Impulses);
            states = actors_with_forces(system, &statics, t, &y)?;
            (found, every) = every_contact_in_reach(cx, &system.model, &states, &y, t, h)?;
        }
        cx.report.max_penetration = cx.report.max_penetration.max(cx.memory.penetration);
        let work = *cx.solve_work;
        let doubled = doubled_step(cx, system, &statics, &states, &found, &phase, t, &y, h);
        if let Err(e) = budget.charge((*cx.solve_work - work).saturating_sub(1), t) {
            break Err(e);
        }
        let Some((mut whole, mut second, involved, sunk_late)) = doubled? else {
            // clarabel could not answer to its tolerance: a smaller step changes the problem
            cx.report.contact_rejected += 1;
            phase.h = 0.25 * h;
            if phase.h < min_step(t) {
                break Err(failure(t, format!("contact steps fell to {:.1e} s: {}", phase.h, *cx.last_solver_error)));
            }
            continue;
        };
        let halves_error = state_difference(&system.model, Some(&involved), (&whole.y, &second.y), Form::Momenta, h);
        let difference: Vec<f64> = second.y.iter().zip(&whole.y).map(|(a, b)| a - b).collect();
        // the extrapolated state's estimate, when the halves agree with the whole step on which contacts push and
        // the last step left a difference to compare with
        // A step across a change of which contacts push, or across a sliding contact's stop, is an event the
        // extrapolation does not see: the halves' estimate governs it, with the slip a stop may have cut short.
        let pressed_before: BTreeSet<(usize, usize)> =
            phase.last.iter().filter(|c| c.impulse > 0.0).map(|c| (c.a, c.b)).collect();
        let pressed = &second.pressing;
        let after = held(system, &statics, t + h, &second.y, &phase.sleep)?;
        let stopped = stopped_slip(&found, &states, &after, &whole.wrenches);
        let stop = stopped.slip * h;
        // How deep the halves' state, and the extrapolated one, sink any contact of the step: the convex steps hold
        // their contacts to first order in the turning, the extrapolation not at all, and a sunk contact lifted
        // back later gains energy. The extrapolation is used only where it sinks nothing the halves do not.
        let model = &system.model;
        let mut extrapolated = second.y.clone();
        extrapolate(model, &mut extrapolated, &whole.y);
        // (every contact in reach, those the reduction left out of the step included)
        let (sink_halves, sink_extrapolated) =
            (sinking(model, &every, &y, &second.y).max(sunk_late), sinking(model, &every, &y, &extrapolated));
        let extrapolating =
            whole.pressing == second.pressing && sink_extrapolated <= sink_halves + 1e-3 * cx.memory.scales.tolerance;
        let smooth = extrapolating && *pressed == pressed_before && stop == 0.0;
        // (in a jointed world the joints' projection moves the bodies by their drift, whatever the step: its
        // sinking would not shrink with h, so there it only decides the extrapolation)
        let charged = if model.has_joints() { 0.0 } else { sink_halves };
        let halves_error = halves_error.max(stop).max(charged);
        let error = match (&phase.difference, smooth) {
            (Some((h_last, last)), true) => {
                let r = (h / h_last).powi(2);
                let change: Vec<f64> = difference.iter().zip(last).map(|(d, l)| d - r * l).collect();
                let zero = vec![0.0; change.len()];
                let changed = state_difference(model, Some(&involved), (&change, &zero), Form::Momenta, h);
                changed.min(halves_error).max(if model.has_joints() { 0.0 } else { sink_extrapolated })
            }
            _ => halves_error,
        };
        let ratio = error / cx.memory.scales.tolerance;
        if !ratio.is_finite() {
            break Err(OdeError::NonFinite { t, what: "contact step", index: 0 });
        }
        let order = if smooth && phase.difference.is_some() { 3.0 } else { 2.0 };
        let grow = (0.9 * ratio.max(1e-300).powf(-1.0 / order)).clamp(0.2, 2.0);
        // A sliding contact's stop is located, as an impact's time is: a step across a stop that cut short more
        // than `STOP_SHARE` of the tolerance is tried again to end just before the stop, where the slip has
        // nearly run out and the step after it stops it at almost no cost.
        // One try a step: a stop the estimate placed badly (a pair stopped by its neighbours' contacts rather than
        // its own) is then left to the error control.
        let locating =
            !located && stop > STOP_SHARE * cx.memory.scales.tolerance && (STOP_EARLIEST..1.0).contains(&stopped.at);
        if ratio > 1.0 || locating {
            cx.report.contact_rejected += 1;
            located = locating;
            phase.h = if locating { h * (1.0 - 1e-3) * stopped.at } else { h * grow.min(0.5) };
            if phase.h < min_step(t) {
                break Err(failure(
                    t,
                    format!(
                        "contact steps fell to {:.1e} s with an error of {error:.1e} m against a tolerance of \
                         {:.1e} m: the contacts cannot be followed (raise contact_tolerance, or try fast mode)",
                        phase.h, cx.memory.scales.tolerance
                    ),
                ));
            }
            continue;
        }
        // The actors that touch nothing follow the integrator over the accepted step (the sleeping ones held).
        let mut holding = involved.clone();
        phase.sleep.mark(&mut holding);
        let free = free_flight(cx, system, &mut phase.free, &holding, t, &y, h, budget)?;
        if let Some(free) = &free {
            copy_free(&system.model, &holding, free, &mut whole.y);
            copy_free(&system.model, &holding, free, &mut second.y);
            copy_free(&system.model, &holding, free, &mut extrapolated);
        }
        let mut next = second.y;
        let mut kept_error = halves_error;
        if extrapolating {
            let better = extrapolated;
            // Never a gain of energy over the step from the extrapolation, beyond the solves' own accuracy
            // (the velocities' rounding, 1e-9 of tol / h times the momenta, and the work the contact impulses do
            // on the closing speeds the answers leave, `ANSWER_SHARE` of tol / h: that times the impulses, of the
            // halves twice and of the whole step once, as the extrapolation weighs them) and
            // rounding (1e-12 of the kinetic and potential energies' sizes, whose difference the total may be).
            // The free actors' own change of energy (the same in both) is taken out: only the touching ones'
            // is judged. (Extrapolating a rocking body's steps can gain energy; the halves are kept then, and
            // the step is shortened if their own error is past the tolerance.)
            let model = &system.model;
            let energy = |y: &[f64]| model.kinetic_energy(y) + model.potential_energy(y);
            let (kinetic, potential) = (model.kinetic_energy(&y), model.potential_energy(&y));
            let before = kinetic + potential;
            let free_gain = free.as_deref().map_or(0.0, |f| energy(f) - before);
            let slack = 1e-12 * (kinetic.abs() + potential.abs())
                + 1e-9 * cx.memory.scales.tolerance / h * momenta(model, &involved, &next)
                + ANSWER_SHARE
                    * cx.memory.scales.tolerance
                    * (4.0 * pushing(&second.wrenches) + pushing(&whole.wrenches));
            if energy(&better) - free_gain <= before + slack {
                next = better;
                kept_error = error;
            }
        }
        if kept_error > cx.memory.scales.tolerance {
            // the extrapolation was refused and the halves' own error is past the tolerance: a shorter step
            cx.report.contact_rejected += 1;
            phase.h = h * (0.9 * (cx.memory.scales.tolerance / kept_error).sqrt()).clamp(0.2, 0.5);
            if phase.h < min_step(t) {
                break Err(failure(t, format!("contact steps fell to {:.1e} s", phase.h)));
            }
            continue;
        }
        if let Some(free) = &free {
            copy_free(&system.model, &holding, free, &mut next);
        }
        if let Some(index) = next.iter().position(|v| !v.is_finite()) {
            break Err(OdeError::NonFinite { t: t + h, what: "state after a contact step", index });
        }
        let norm = next.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if norm > cx.divergence_limit {
            break Err(OdeError::Divergence { t: t + h, norm, limit: cx.divergence_limit, h });
        }
        // A step cut to reach a frame or the end lands on it exactly: t + (stop - t) can fall an ulp short,
        // and an advance that ends an ulp before its end would be asked to go on from there forever.
        located = false;
        let (t0, y0) = (t, std::mem::replace(&mut y, next));
        t = if h == stop - t { stop } else { t + h };
        // frames inside the step from the step's own interpolation: positions move at the step's end velocities
        // (semi-implicit Euler), so the state is linear in time across it; a frame at the step's end is its state
        while delivered < saves.len() && saves[delivered] < t - slack {
            if let Some(run) = run.as_deref_mut() {
                let frame = interpolate(&system.model, &y0, &y, (saves[delivered] - t0) / (t - t0));
                let contacts = phase.last.iter().map(|c| (c.point, c.normal));
                run.record(&system.model, saves[delivered], &frame, cx.memory.penetration, contacts);
            }
            delivered += 1;
        }
        if sleeps && phase.sleep.settle(&system.model, &found, &links, &mut y, t, sleeping) {
            cx.report.stages.mark(crate::plan::Stage::Sleeping);
        }
        cx.report.sleepers = phase.sleep.count();
        phase.lagged = second.forces;
        phase.warm = second.wrenches;
        phase.difference = Some((h, difference));
        // joints the step took past their bounds break at its end (the next step's estimate is then its halves':
        // the equations changed)
        if super::breaking::break_after_step(cx, system, &second.joint_loads, t, run.as_deref_mut()) {
            phase.difference = None;
        }
        let impulses = found.iter().map(|f| whole.forces.get(&f.key).map_or(0.0, |force| force * h));
        // the contacts that pushed or touch (within the tolerance), not every pair within the step's reach
        phase.last = LastContact::from_found(&found, impulses, h);
        let touching_gap = cx.memory.scales.tolerance.max(cx.settings.contact_distance);
        phase.last.retain(|c| c.impulse > 0.0 || c.gap <= touching_gap);
        let r = &mut cx.report;
        r.contact_steps += 1;
        r.contact_error = r.contact_error.max(kept_error);
        r.contact_min_step = r.contact_min_step.min(h);
        if let Some(run) = run.as_deref_mut() {
            run.log_step(t, h);
        }
        let proposed = (h * grow).min(cx.memory.scales.max_step);
        phase.h = if clipped { proposed.max(phase.h) } else { proposed };
    };
    match result {
        Ok(touching) => {
            if touching {
                cx.memory.touching = Some(phase);
            }
            Ok(TouchingEnd { t, y, delivered, touching })
        }
        Err(e) => {
            cx.memory.touching = Some(phase);
            Err(e)
        }
    }
}

/// Fails when `STALL_WINDOW` steps tried have advanced less than that many stall steps (1e-5 of the scene's
/// time scale each): contact steps that crawl (bodies started deep inside each other, which the lifts cannot
/// undo, took steps of 1e-7 s) end in a clear error instead of running for hours.
fn watch_touching(cx: &ContactStages<'_>, phase: &mut TouchingPhase, t: f64) -> Result<(), OdeError> {
    let (start, tried) = phase.window;
    if tried == 0 || start.is_nan() {
        phase.window = (t, 1);
        return Ok(());
    }
    if tried < STALL_WINDOW {
        phase.window = (start, tried + 1);
        return Ok(());
    }
    phase.window = (t, 1);
    let mean = (t - start) / STALL_WINDOW as f64;
    if mean < cx.memory.scales.stall_step {
        return Err(failure(
            t,
            format!(
                "{STALL_WINDOW} contact steps advanced {:.1e} s (a mean step of {mean:.1e} s) with contacts up to \
                 {:.1e} m deep: the steps cannot follow these contacts (bodies started inside each other?); try \
                 fast mode, or a looser contact_tolerance",
                t - start,
                cx.memory.penetration
            ),
        ));
    }
    Ok(())
}

/// One step of h taken whole and as two halves (the first half on the whole step's contacts, the second on its
/// own), with the actors their contacts involve (`free_flight::involved`) and how deep the second half sinks any
/// contact in reach at the middle (a polyhedron's vertex that came round to face the other shape by then, which the
/// start's contacts do not show); `None` if clarabel could not answer one of them.
#[allow(clippy::too_many_arguments)]
fn doubled_step(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    states: &[tumble_contact::BodyState],
    found: &[crate::engine::found_contact::FoundContact],
    phase: &TouchingPhase,
    t: f64,
    y: &[f64],
    h: f64,
) -> Result<Option<(ConvexStep, ConvexStep, Vec<bool>, f64)>, OdeError> {
    let lagged = &phase.lagged;
    // each solve starts from the last: the whole step from the last step's forces, the halves from the whole's
    let Some(whole) = convex_step(cx, &system.model, states, found, (lagged, &phase.warm), t, y, h)? else {
        return Ok(None);
    };
    let Some(first) = convex_step(cx, &system.model, states, found, (lagged, &whole.wrenches), t, y, 0.5 * h)? else {
        return Ok(None);
    };
    let mid = t + 0.5 * h;
    let states = held(system, statics, mid, &first.y, &phase.sleep)?;
    let (later, every) = every_contact_in_reach(cx, &system.model, &states, &first.y, mid, 0.5 * h)?;
    let warm = (&first.forces, &first.wrenches);
    let Some(second) = convex_step(cx, &system.model, &states, &later, warm, mid, &first.y, 0.5 * h)? else {
        return Ok(None);
    };
    let involved = involved(&system.model, &[found, &later]);
    let sunk = sinking(&system.model, &every, &first.y, &second.y);
    Ok(Some((whole, second, involved, sunk)))
}

/// The sum of a convex step's contact force magnitudes (N), from its `wrenches`.
fn pushing(wrenches: &BTreeMap<ContactKey, nalgebra::Vector3<f64>>) -> f64 {
    wrenches.values().map(|f| f.norm()).sum()
}

/// The actors at state y with their applied forces (`actors_with_forces`), the sleeping ones fixed at rest.
fn held(
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    t: f64,
    y: &[f64],
    sleep: &Sleep,
) -> Result<Vec<tumble_contact::BodyState>, OdeError> {
    let mut states = actors_with_forces(system, statics, t, y)?;
    sleep.hold(&mut states);
    Ok(states)
}
