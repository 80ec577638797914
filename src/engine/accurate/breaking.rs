//! Breakable joints in accurate mode. Between events a joint's load is a function of the state: its rows' forces
//! from the right-hand side's joint solve (`joint_forces.rs`). After each accepted integrator step the loads at
//! its end are checked; a joint taken past its bounds within the step breaks at the first time it is, located by
//! bisection on the step's dense output to the time tolerance (as a collision's time is), where the step is cut:
//! the joint is let go there and the integration restarts without it. In the touching phase the loads are the
//! convex program's joint impulses over each accepted step (`ConvexStep::joint_loads`), and a joint past its
//! bounds breaks at that step's end. A joint with a break window is judged by its load averaged over the window
//! (`Model::judged_loads`): between events the average is brought on through each accepted step from its dense
//! output (the load taken linear between a few points, the exponential integrated exactly; a break located on it
//! as above); in the touching phase by each step's impulses.

use super::joint_forces::joint_forces;
use super::system::AccurateSystem;
use crate::engine::failure::failure;
use crate::model::breaking::JointLoad;
use crate::plan::Stage;
use crate::report::WorldReport;
use tumble_integrate::{OdeError, StepView};

/// The collider set whose joined pairs a break changes (none without contact).
pub(super) type ColliderSetRef<'a> = Option<&'a mut crate::engine::collider_set::ColliderSet>;
/// Most halvings of a break time's bisection (2^-100 of the step).
const HALVINGS: usize = 100;

/// Each joint's load at (t, y): the rows' forces the right-hand side gives there.
pub(super) fn loads_at(system: &mut AccurateSystem, t: f64, y: &[f64]) -> Result<Vec<JointLoad>, OdeError> {
    let model = &system.model;
    let mut dy = vec![0.0; y.len()];
    model.rates(&mut system.tally, t, y, &mut dy, true).map_err(|e| failure(t, e.to_string()))?;
    let q = model.layout.positions();
    let mut loads = vec![JointLoad::default(); model.joints.len()];
    let model = &system.model;
    joint_forces(model, y, &mut dy[q..], |k, r, ends, lambda| {
        loads[k].add(&r.lin, &r.ang_b, &model.anchor_b(k, ends), lambda)
    });
    Ok(loads)
}

/// The joints past their bounds at (t, y), in order: each judged by its load there, or, with a window, by
/// `averages` (brought to t already).
pub(super) fn overloaded_at(
    system: &mut AccurateSystem,
    averages: &[JointLoad],
    t: f64,
    y: &[f64],
) -> Result<Vec<usize>, OdeError> {
    if !system.model.can_break() {
        return Ok(Vec::new());
    }
    let mut loads = loads_at(system, t, y)?;
    for (k, j) in system.model.holding_joints() {
        if j.breaking.is_some_and(|b| b.window > 0.0) {
            loads[k] = averages.get(k).copied().unwrap_or_default();
        }
    }
    Ok(system.model.overloaded(&loads))
}

/// Pieces the load is taken linear over when it is averaged through part of a step.
const PIECES: usize = 4;

/// The averaged loads at t within an accepted step, from `start` (theirs at the step's start t0): each windowed
/// joint's e^(-(t - t0) / window) start + the integral over (t0, t) of e^(-(t - s) / window) F(s) ds / window, with
/// F taken linear between `PIECES + 1` points of the step's dense output and the exponential integrated exactly
/// (so a window far shorter than the step still gives the load itself); the others' entries as they are.
fn averages_at(
    step: &mut StepView<'_, AccurateSystem>,
    start: &[JointLoad],
    t: f64,
) -> Result<Vec<JointLoad>, OdeError> {
    let t0 = step.t0();
    let mut out = start.to_vec();
    out.resize(step.system().model.joints.len(), JointLoad::default());
    let windows: Vec<(usize, f64)> = step
        .system()
        .model
        .holding_joints()
        .filter_map(|(k, j)| j.breaking.filter(|b| b.window > 0.0).map(|b| (k, b.window)))
        .collect();
    for &(k, window) in &windows {
        let keep = (-(t - t0) / window).exp();
        out[k].force *= keep;
        out[k].torque *= keep;
    }
    if t <= t0 {
        return Ok(out);
    }
    let at = |step: &mut StepView<'_, AccurateSystem>, s: f64| -> Result<Vec<JointLoad>, OdeError> {
        let y = step.state_at(s)?;
        loads_at(step.system_mut(), s, &y)
    };
    let mut s0 = t0;
    let mut f0 = at(step, s0)?;
    for i in 1..=PIECES {
        let s1 = t0 + (t - t0) * i as f64 / PIECES as f64;
        let f1 = at(step, s1)?;
        for &(k, window) in &windows {
            // over [s0, s1] with F linear from f0 to f1: f0 (E1 - E0) + (f1 - f0) (E1 - window (E1 - E0) / (s1 - s0)),
            // E(s) = e^(-(t - s) / window)
            let (e0, e1) = ((-(t - s0) / window).exp(), (-(t - s1) / window).exp());
            let slope = e1 - window * (e1 - e0) / (s1 - s0);
            out[k].force += f0[k].force * (e1 - e0) + (f1[k].force - f0[k].force) * slope;
            out[k].torque += f0[k].torque * (e1 - e0) + (f1[k].torque - f0[k].torque) * slope;
        }
        (s0, f0) = (s1, f1);
    }
    Ok(out)
}

/// The first time in an accepted step (up to `until`, where the step is cut for another reason, if earlier) at
/// which a joint is past its bounds (to `tolerance`, the overloaded side), or None when none is at the end. The
/// averaged loads are brought on to that time (`averages`).
pub(super) fn break_time(
    step: &mut StepView<'_, AccurateSystem>,
    until: Option<f64>,
    averages: &mut Vec<JointLoad>,
    tolerance: f64,
    report: &mut WorldReport,
) -> Result<Option<f64>, OdeError> {
    if !step.system().model.can_break() {
        return Ok(None);
    }
    let windows = step.system().model.has_break_windows();
    let (t0, t1) = (step.t0(), until.map_or(step.t1(), |u| u.min(step.t1())));
    let start = averages.clone();
    // whether a joint is past its bounds at t, and the averaged loads there
    let over = |step: &mut StepView<'_, AccurateSystem>, t: f64| -> Result<(bool, Vec<JointLoad>), OdeError> {
        let at = if windows { averages_at(step, &start, t)? } else { start.clone() };
        let y = if t == step.t1() { step.y1().to_vec() } else { step.state_at(t)? };
        Ok((!overloaded_at(step.system_mut(), &at, t, &y)?.is_empty(), at))
    };
    let (past, at_end) = over(step, t1)?;
    if !past {
        *averages = at_end;
        return Ok(None);
    }
    let (mut lo, mut hi, mut at_hi) = (t0, t1, at_end);
    for _ in 0..HALVINGS {
        let mid = 0.5 * (lo + hi);
        if hi - lo <= tolerance || mid <= lo || mid >= hi {
            break;
        }
        report.bisection_steps += 1;
        report.stages.mark(Stage::Bisection);
        let (past, at) = over(step, mid)?;
        if past {
            (hi, at_hi) = (mid, at);
        } else {
            lo = mid;
        }
    }
    *averages = at_hi;
    Ok(Some(hi))
}

/// Breaks the joints past their bounds at (t, y) (those with a window judged by `averages`): their flags set in
/// `broken` and given to the model and the collider set; gives them, in order.
pub(super) fn break_overloaded(
    system: &mut AccurateSystem,
    broken: &mut [bool],
    averages: &[JointLoad],
    collider_set: ColliderSetRef<'_>,
    t: f64,
    y: &[f64],
) -> Result<Vec<usize>, OdeError> {
    let which = overloaded_at(system, averages, t, y)?;
    give_broken(system, broken, collider_set, &which);
    Ok(which)
}

/// Sets joints `which` broken in `broken` and gives the flags to the model and the collider set.
pub(super) fn give_broken(
    system: &mut AccurateSystem,
    broken: &mut [bool],
    collider_set: ColliderSetRef<'_>,
    which: &[usize],
) {
    if which.is_empty() {
        return;
    }
    for &k in which {
        broken[k] = true;
    }
    crate::engine::breaking::set_broken(&mut system.model, collider_set, broken).expect("one flag per joint");
}

/// Breaks the joints a contact step of `h` takes past their bounds, at the step's end t (booked in `run`); gives
/// whether any broke. `step` is the second of the step's halves: its loads (the forces its impulses make over it)
/// are the load at the instant; a joint with a window is judged by its average, brought on by each half's
/// impulses in turn, and breaks if either half takes it past its bounds.
pub(super) fn break_after_step(
    cx: &mut super::contact_stages::ContactStages<'_>,
    system: &mut AccurateSystem,
    step: &super::convex_step::ConvexStep,
    h: f64,
    t: f64,
    run: Option<&mut crate::run::Run>,
) -> bool {
    let loads = &step.joint_loads;
    if !system.model.can_break() || loads.is_empty() {
        return false;
    }
    let half = 0.5 * h;
    let carried = |loads: &[JointLoad]| -> Vec<JointLoad> {
        loads.iter().map(|l| JointLoad { force: l.force * half, torque: l.torque * half }).collect()
    };
    let mut which = Vec::new();
    if step.first_half_loads.len() == loads.len() {
        let first = &step.first_half_loads;
        let judged = system.model.judged_loads(cx.averages, first, &carried(first), half, half);
        let windowed = |k: &usize| system.model.joints[*k].breaking.is_some_and(|b| b.window > 0.0);
        which.extend(system.model.overloaded(&judged).into_iter().filter(windowed));
    }
    let judged = system.model.judged_loads(cx.averages, loads, &carried(loads), half, half);
    which.extend(system.model.overloaded(&judged));
    which.sort_unstable();
    which.dedup();
    give_broken(system, cx.broken, Some(&mut *cx.collider_set), &which);
    if let Some(run) = run {
        which.iter().for_each(|&k| run.break_joint(t, k));
    }
    !which.is_empty()
}
