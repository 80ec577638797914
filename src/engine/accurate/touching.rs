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
//! in; the judgement itself is `step_judgement.rs`, the step `doubled_step.rs`, the energy guard `energy_guard.rs`,
//! the kept state's own contacts `late_sink.rs`, the slide and turn limits `slide_limit.rs`).
//! Only the end of an advance cuts a step: frames inside one are its interpolation (`interpolate`: positions on the
//! step's path, each body's kinetic energy the blend of the ends'). Contacts that sank past the tolerance are lifted
//! apart by a position projection before the step. Sleeping islands (`sleep.rs`) are
//! fixed bodies to the steps. The phase keeps its own (t, y) between the calls it spans (`TouchingPhase::at`) and
//! ends when no pair is within reach of a step and nothing sleeps: the integrator's state is set then, and it takes
//! over (`advance.rs`).

use super::contact_stages::ContactStages;
use super::convex_step::{every_contact_in_reach, ConvexStep};
use super::doubled_step::{doubled_step, held};
use super::drift::correct_drift;
use super::energy_guard::Guarded;
use super::free_flight::{copy_free, free_flight, links};
use super::held::set_moving;
use super::late_sink::{deepest, sunk_step, LATE_SINK};
use super::sleep::Sleep;
use super::slide_limit::slide_limit;
use super::step_estimate::{extrapolate, interpolate, sinking, stopped_slip};
use super::step_judgement::{judge, judge_kept, next_step, Estimates, Verdict};
use super::sync::sync_due;
use super::system::AccurateSystem;
use super::touching_phase::TouchingPhase;
use crate::engine::failure::failure;
use crate::engine::found_contact::FoundContact;
use crate::engine::frames::FrameCursor;
use crate::engine::last_contacts::LastContact;
use crate::engine::semi_implicit::Form;
use crate::engine::state_error::state_difference;
use crate::engine::Budget;
use crate::run::Run;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use tumble_integrate::OdeError;

/// Steps tried (accepted or rejected) over which the touching phase's progress is watched.
const STALL_WINDOW: usize = 200;

/// How a touching phase's advance ended.
pub(crate) struct TouchingEnd {
    pub t: f64,
    pub y: Vec<f64>,
    /// Whether the bodies still touch (the advance reached its end); false when they parted.
    pub touching: bool,
    /// A group's advance's frames (`Until::own_clocks` None): each frame time reached and the state there.
    pub frames: Vec<(f64, Vec<f64>)>,
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
        at: None,
        clocks: BTreeMap::new(),
        synced: f64::NEG_INFINITY,
    });
}

/// The smallest step: 16 ulps of the time, and no less than 1e-14 s.
fn min_step(t: f64) -> f64 {
    (16.0 * f64::EPSILON * t.abs()).max(1e-14)
}

/// The islands' own clocks (`clocks::own_clocks`, which advances each group by `touching_steps`): from (t, y) to
/// the next sync time (at most the end), if the actors split into groups that stay apart, the time and state
/// reached, each frame inside recorded; None where one clock takes the span. The advance hands it in (`Until`),
/// so that this module, which `clocks.rs` runs, does not use it in turn.
pub(crate) type OwnClocks = fn(
    &mut ContactStages<'_>,
    &mut AccurateSystem,
    &[nalgebra::Isometry3<f64>],
    &mut TouchingPhase,
    (f64, &[f64], f64),
    &mut FrameCursor<'_>,
    Option<&mut Run>,
    &mut Budget<'_>,
) -> Result<Option<(f64, Vec<f64>)>, OdeError>;

/// Where a touching phase's advance ends: at `end`, pausing once past `pause` (a progress check or a chunk's end).
#[derive(Clone, Copy)]
pub(crate) struct Until {
    pub end: f64,
    pub pause: f64,
    /// Where groups that cannot meet before the next sync time each go on their own clock (`clocks.rs`); None where
    /// every actor keeps one clock (a group's own advance, which gives back its frames' states instead of recording
    /// them).
    pub own_clocks: Option<OwnClocks>,
}

/// A contact step that was kept: the state it ends in and what the phase carries on from it.
struct Kept {
    y: Vec<f64>,
    error: f64,
    grow: f64,
    second: ConvexStep,
    whole: ConvexStep,
    difference: Vec<f64>,
}

/// Advances from (t, y) by error-controlled contact steps until the advance's end (pausing past its pause) or until
/// no pair is within reach; each frame time reached records a frame. Each step tried is charged to the call's
/// `budget`, a contact step counting each convex program it solved by its size (one unit for every eight
/// contacts of the island, `VelocityStep::solver_work`).
pub fn touching_steps(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    (mut t, mut y): (f64, Vec<f64>),
    until: Until,
    frames: &mut FrameCursor<'_>,
    mut run: Option<&mut Run>,
    budget: &mut Budget<'_>,
) -> Result<TouchingEnd, OdeError> {
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let Some(mut phase) = cx.memory.touching.take() else {
        return Err(failure(t, "contact steps without a touching phase".into()));
    };
    let actors = system.model.layout.actors();
    let links = links(&system.model);
    let sleeps = cx.settings.sleep && !system.model.has_joints();
    let sleeping = (cx.memory.scales.resting_speed, cx.settings.sleep_time);
    let one_clock = until.own_clocks.is_none();
    // whether the step being tried was cut at a stop
    let mut located = false;
    let mut kept_frames = Vec::new();
    let result = loop {
        // (each frame at its own time: while everything sleeps the clock jumps past several frames at once)
        while let Some(s) = frames.reached(t) {
            if one_clock {
                kept_frames.push((s, y.clone()));
            } else if let Some(run) = run.as_deref_mut() {
                let contacts = phase.last.iter().map(|c| (c.point, c.normal));
                run.record(&system.model, s, &y, cx.memory.penetration, contacts);
            }
            frames.advance();
        }
        if t >= until.pause.min(until.end) - frames.slack() {
            break Ok(true);
        }
        // groups that cannot meet before the next sync time go on their own clocks to it (`clocks.rs`)
        if let Some(own_clocks) = until.own_clocks.filter(|_| cx.settings.island_clocks && !system.model.has_joints()) {
            if sync_due(&mut phase, t) {
                let at = (t, y.as_slice(), until.end);
                let met = own_clocks(cx, system, &statics, &mut phase, at, frames, run.as_deref_mut(), budget)?;
                if let Some(met) = met {
                    (t, y) = met;
                    continue;
                }
            }
        }
        // frames do not steer the steps: only the end of the advance cuts one
        let h = phase.h.min(until.end - t);
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
                t = until.pause.min(until.end);
                continue;
            }
        }
        // a step slides no touching pair past a share of its smaller shape, and turns none far (the contacts'
        // manifolds hold only while their points stay on the faces they were found on: a box pushed off a table's
        // edge at a steady speed makes no error the estimates see)
        let h = h.min(slide_limit(cx, &found, &states));
        let clipped = h < phase.h;
        cx.memory.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
        if cx.memory.penetration > cx.memory.scales.tolerance {
            // Linearised contacts of turning bodies sink a little each step; past the tolerance, the bodies are
            // moved apart by the smallest position change, the energy it gives each body taken from its motion.
            let sunk: Vec<_> = found.iter().filter(|f| f.contact.distance < 0.0).map(|f| f.contact).collect();
            // a held actor sunk into is no longer resting: it moves apart with the others
            if phase.sleep.release(sunk.iter().flat_map(|c| [c.a, c.b])) {
                states = held(system, &statics, t, &y, &phase.sleep)?;
            }
            cx.report.qp_solves += correct_drift(&system.model, &mut y, &states, &sunk, cx.solver, t)?;
            cx.report.stages.mark(crate::plan::Stage::Impulses);
            states = held(system, &statics, t, &y, &phase.sleep)?;
            (found, every) = every_contact_in_reach(cx, &system.model, &states, &y, t, h)?;
        }
        cx.report.max_penetration = cx.report.max_penetration.max(cx.memory.penetration);
        let work = *cx.solve_work;
        let doubled = doubled_step(cx, system, &statics, &states, &found, &phase, t, &y, h);
        if let Err(e) = budget.charge((*cx.solve_work - work).saturating_sub(1), t) {
            break Err(e);
        }
        let Some((whole, second, involved, sunk_late)) = doubled? else {
            // clarabel could not answer to its tolerance: a smaller step changes the problem
            cx.report.contact_rejected += 1;
            phase.h = 0.25 * h;
            if phase.h < min_step(t) {
                break Err(failure(t, format!("contact steps fell to {:.1e} s: {}", phase.h, *cx.last_solver_error)));
            }
            continue;
        };
        let step = Tried { t, y: &y, h, found: &found, every: &every, states: &states, involved, sunk_late };
        let kept = match judged(cx, system, &statics, &mut phase, step, whole, second, located, budget)? {
            Judged::Kept(kept) => kept,
            Judged::Again { h: again, located: at_stop } => {
                cx.report.contact_rejected += 1;
                located = at_stop;
                phase.h = again;
                if phase.h < min_step(t) {
                    break Err(failure(
                        t,
                        format!(
                            "contact steps fell to {:.1e} s against a tolerance of {:.1e} m: the contacts cannot be \
                             followed (raise contact_tolerance, or try fast mode)",
                            phase.h, cx.memory.scales.tolerance
                        ),
                    ));
                }
                continue;
            }
        };
        // a held actor the step's awake actors would set moving wakes, and the step is taken again with it moving
        // (`held.rs`)
        if !phase.sleep.held.is_empty() {
            let moving = set_moving(cx, system, &statics, &phase, &found, &kept.whole.wrenches, (t, &y))?;
            if phase.sleep.release(moving.into_iter()) {
                cx.report.contact_rejected += 1;
                continue;
            }
        }
        if let Some(index) = kept.y.iter().position(|v| !v.is_finite()) {
            break Err(OdeError::NonFinite { t: t + h, what: "state after a contact step", index });
        }
        let norm = kept.y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if norm > cx.divergence_limit {
            break Err(OdeError::Divergence { t: t + h, norm, limit: cx.divergence_limit, h });
        }
        // A step cut to reach the end lands on it exactly: t + (end - t) can fall an ulp short, and an advance that
        // ends an ulp before its end would be asked to go on from there forever.
        located = false;
        let (t0, y0) = (t, std::mem::replace(&mut y, kept.y));
        t = if h == until.end - t { until.end } else { t + h };
        // frames inside the step from the step's own interpolation (`interpolate`); a frame at its end is its state
        while let Some(s) = frames.inside(t) {
            let frame = || interpolate(&system.model, &y0, &y, (s - t0) / (t - t0));
            if one_clock {
                kept_frames.push((s, frame()));
            } else if let Some(run) = run.as_deref_mut() {
                let contacts = phase.last.iter().map(|c| (c.point, c.normal));
                run.record(&system.model, s, &frame(), cx.memory.penetration, contacts);
            }
            frames.advance();
        }
        if sleeps && phase.sleep.settle(&system.model, &found, &links, &mut y, t, sleeping) {
            cx.report.stages.mark(crate::plan::Stage::Sleeping);
        }
        cx.report.sleepers = phase.sleep.count();
        // joints the step took past their bounds break at its end (the next step's estimate is then its halves':
        // the equations changed)
        let broke = super::breaking::break_after_step(cx, system, &kept.second, h, t, run.as_deref_mut());
        phase.lagged = kept.second.forces;
        phase.warm = kept.second.wrenches;
        phase.difference = if broke { None } else { Some((h, kept.difference)) };
        let impulses = found.iter().map(|f| kept.whole.forces.get(&f.key).map_or(0.0, |force| force * h));
        // the contacts that pushed or touch (within the tolerance), not every pair within the step's reach
        phase.last = LastContact::from_found(&found, impulses, h);
        let touching_gap = cx.memory.scales.tolerance.max(cx.settings.contact_distance);
        phase.last.retain(|c| c.impulse > 0.0 || c.gap <= touching_gap);
        let r = &mut cx.report;
        r.contact_steps += 1;
        r.contact_error = r.contact_error.max(kept.error);
        r.contact_min_step = r.contact_min_step.min(h);
        if let Some(run) = run.as_deref_mut() {
            run.log_step(t, h);
        }
        phase.h = next_step(h, kept.grow, cx.memory.scales.max_step, clipped, phase.h);
    };
    match result {
        Ok(touching) => {
            if touching {
                cx.memory.touching = Some(phase);
            }
            Ok(TouchingEnd { t, y, touching, frames: kept_frames })
        }
        Err(e) => {
            cx.memory.touching = Some(phase);
            Err(e)
        }
    }
}

/// A doubled step's inputs the judgement reads.
struct Tried<'a> {
    t: f64,
    y: &'a [f64],
    h: f64,
    found: &'a [FoundContact],
    every: &'a [FoundContact],
    states: &'a [tumble_contact::BodyState],
    involved: Vec<bool>,
    /// How deep the second half sinks a contact in reach at the middle.
    sunk_late: f64,
}

/// What the judgement of a doubled step decided.
enum Judged {
    Kept(Box<Kept>),
    /// Take the step again, this long (`located`: cut to end just before a stop).
    Again {
        h: f64,
        located: bool,
    },
}

/// Judges a doubled step (`step_judgement.rs`) from its estimates: the halves' difference, the slip a stop cut short,
/// how deep the halves' and the extrapolated states sink the contacts in reach, and how the difference changed since
/// the last step; then, for a step kept, the actors that touch nothing follow the integrator over it, and the
/// extrapolated state is kept where it sinks nothing the halves do not and the energy guard (`energy_guard.rs`) lets
/// it, the halves otherwise (taken again shorter when their own estimate is past the tolerance).
#[allow(clippy::too_many_arguments)]
fn judged(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    phase: &mut TouchingPhase,
    step: Tried<'_>,
    mut whole: ConvexStep,
    mut second: ConvexStep,
    located: bool,
    budget: &mut Budget<'_>,
) -> Result<Judged, OdeError> {
    let Tried { t, y, h, found, every, states, involved, sunk_late } = step;
    let tolerance = cx.memory.scales.tolerance;
    let model = &system.model;
    let halves_error = state_difference(model, Some(&involved), (&whole.y, &second.y), Form::Momenta, h);
    let difference: Vec<f64> = second.y.iter().zip(&whole.y).map(|(a, b)| a - b).collect();
    // A step across a change of which contacts push, or across a sliding contact's stop, is an event the
    // extrapolation does not see: the halves' estimate governs it, with the slip a stop may have cut short.
    let pressed_before: BTreeSet<(usize, usize)> =
        phase.last.iter().filter(|c| c.impulse > 0.0).map(|c| (c.a, c.b)).collect();
    let after = held(system, statics, t + h, &second.y, &phase.sleep)?;
    let model = &system.model;
    let stopped = stopped_slip(found, states, &after, &whole.wrenches, cx.settings.contact_distance);
    // A try already cut to end just before a stop that finds a stop again well inside itself (a slide's stop moves to
    // the cut try's end) met an impact whose friction stops the slip within the impulse, whatever the step (a
    // spinning hull landing with sticking friction stopped at 0.55 of every step tried, down to steps of 1e-8 s):
    // its slip is not a stop's error.
    let stop = if located && stopped.at < 0.9 { 0.0 } else { stopped.slip * h };
    // How deep the halves' state, and the extrapolated one, sink any contact of the step (every contact in reach,
    // those the reduction left out included): the convex steps hold their contacts to first order in the turning,
    // the extrapolation not at all, and a sunk contact lifted back later gains energy. The extrapolation is used
    // only where it sinks nothing the halves do not.
    let mut extrapolated = second.y.clone();
    extrapolate(model, &mut extrapolated, &whole.y);
    let (sink_halves, sink_extrapolated) =
        (sinking(model, every, y, &second.y).max(sunk_late), sinking(model, every, y, &extrapolated));
    let extrapolating = whole.pressing == second.pressing && sink_extrapolated <= sink_halves + 1e-3 * tolerance;
    let smooth = extrapolating && second.pressing == pressed_before && stop == 0.0;
    // (in a jointed world the joints' projection moves the bodies by their drift, whatever the step: its sinking
    // would not shrink with h, so there it only decides the extrapolation)
    let jointed = model.has_joints();
    let halves = halves_error.max(stop).max(if jointed { 0.0 } else { sink_halves });
    let change = match (&phase.difference, smooth) {
        (Some((h_last, last)), true) => {
            let r = (h / h_last).powi(2);
            let change: Vec<f64> = difference.iter().zip(last).map(|(d, l)| d - r * l).collect();
            let zero = vec![0.0; change.len()];
            Some(state_difference(model, Some(&involved), (&change, &zero), Form::Momenta, h))
        }
        _ => None,
    };
    let estimates = Estimates {
        h,
        tolerance,
        halves,
        change,
        sink_extrapolated: if jointed { 0.0 } else { sink_extrapolated },
        stop,
        stop_at: stopped.at,
        located,
    };
    if !(halves / tolerance).is_finite() || change.is_some_and(|c| !c.is_finite()) {
        return Err(OdeError::NonFinite { t, what: "contact step", index: 0 });
    }
    let (error, grow) = match judge(&estimates) {
        Verdict::Keep { error, grow } => (error, grow),
        Verdict::Retry(h) => return Ok(Judged::Again { h, located: false }),
        Verdict::Locate(h) => return Ok(Judged::Again { h, located: true }),
    };
    // The actors that touch nothing follow the integrator over the kept step (the sleeping ones held).
    let mut holding = involved.clone();
    phase.sleep.mark(&mut holding);
    let free = free_flight(cx, system, &mut phase.free, &holding, t, y, h, budget)?;
    let model = &system.model;
    if let Some(free) = &free {
        copy_free(model, &holding, free, &mut whole.y);
        copy_free(model, &holding, free, &mut second.y);
        copy_free(model, &holding, free, &mut extrapolated);
    }
    let guard = Guarded {
        model,
        start: y,
        free: free.as_deref(),
        involved: &involved,
        halves: &second.y,
        tolerance,
        h,
        second: &second.wrenches,
        whole: &whole.wrenches,
    };
    let (mut next, kept_error) = if extrapolating && guard.keeps_energy(&extrapolated) {
        (extrapolated, error)
    } else {
        (second.y.clone(), halves)
    };
    if let Some(again) = judge_kept(h, tolerance, kept_error) {
        // the extrapolation was refused and the halves' own error is past the tolerance: a shorter step
        return Ok(Judged::Again { h: again, located: false });
    }
    if let Some(free) = &free {
        copy_free(model, &holding, free, &mut next);
    }
    // The steps hold the contacts found at their start; a feature that was not among them (a hull's vertex coming
    // round, a corner of a face the reduction left out) can sink further within the step: the kept state's own
    // contacts, computed afresh, sink at most `LATE_SINK` tolerances past the start's deepest, or the step is taken
    // again shorter (not in a jointed world, whose joints' projection moves the bodies by their drift whatever the
    // step).
    let depth = if jointed { 0.0 } else { deepest(cx, model, statics, every, &next) };
    if depth > cx.memory.penetration + LATE_SINK * tolerance {
        return Ok(Judged::Again { h: sunk_step(h, depth - cx.memory.penetration, tolerance), located: false });
    }
    Ok(Judged::Kept(Box::new(Kept { y: next, error: kept_error, grow, second, whole, difference })))
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
