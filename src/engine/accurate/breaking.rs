//! Breakable joints in accurate mode. Between events a joint's load is a function of the state: its rows' forces
//! from the right-hand side's joint solve (`joint_forces.rs`). After each accepted integrator step the loads at
//! its end are checked; a joint taken past its bounds within the step breaks at the first time it is, located by
//! bisection on the step's dense output to the time tolerance (as a collision's time is), where the step is cut:
//! the joint is let go there and the integration restarts without it. In the touching phase the loads are the
//! convex program's joint impulses over each accepted step (`ConvexStep::joint_loads`), and a joint past its
//! bounds breaks at that step's end.

use super::joint_forces::joint_forces;
use super::system::AccurateSystem;
use crate::model::breaking::JointLoad;
use crate::plan::Stage;
use crate::report::WorldReport;
use tumble_integrate::{OdeError, StepView};

/// The collider set whose joined pairs a break changes (none without contact).
#[cfg(feature = "contact")]
pub(super) type Scene<'a> = Option<&'a mut crate::engine::collider_set::ColliderSet>;
#[cfg(not(feature = "contact"))]
pub(super) type Scene<'a> = Option<&'a mut ()>;

/// Most halvings of a break time's bisection (2^-100 of the step).
const HALVINGS: usize = 100;

/// Each joint's load at (t, y): the rows' forces the right-hand side gives there.
pub(super) fn loads_at(system: &mut AccurateSystem, t: f64, y: &[f64]) -> Result<Vec<JointLoad>, OdeError> {
    let model = &mut system.model;
    let mut dy = vec![0.0; y.len()];
    model.rates(t, y, &mut dy, true).map_err(|e| super::failure(t, e.to_string()))?;
    let q = model.layout.positions();
    let mut loads = vec![JointLoad::default(); model.joints.len()];
    let model = &system.model;
    joint_forces(model, y, &mut dy[q..], |k, r, ends, lambda| {
        loads[k].add(&r.lin, &r.ang_b, &model.anchor_b(k, ends), lambda)
    });
    Ok(loads)
}

/// The joints past their bounds at (t, y), in order.
pub(super) fn overloaded_at(system: &mut AccurateSystem, t: f64, y: &[f64]) -> Result<Vec<usize>, OdeError> {
    if !system.model.can_break() {
        return Ok(Vec::new());
    }
    let loads = loads_at(system, t, y)?;
    Ok(system.model.overloaded(&loads))
}

/// The first time in an accepted step at which a joint is past its bounds (to `tolerance`, the overloaded side),
/// or None when none is at the step's end.
pub(super) fn break_time(
    step: &mut StepView<'_, AccurateSystem>,
    tolerance: f64,
    report: &mut WorldReport,
) -> Result<Option<f64>, OdeError> {
    if !step.system().model.can_break() {
        return Ok(None);
    }
    let (t0, t1) = (step.t0(), step.t1());
    let y1 = step.y1().to_vec();
    if overloaded_at(step.system_mut(), t1, &y1)?.is_empty() {
        return Ok(None);
    }
    let (mut lo, mut hi) = (t0, t1);
    for _ in 0..HALVINGS {
        let mid = 0.5 * (lo + hi);
        if hi - lo <= tolerance || mid <= lo || mid >= hi {
            break;
        }
        report.bisection_steps += 1;
        report.stages.mark(Stage::Bisection);
        let y = step.state_at(mid)?;
        if overloaded_at(step.system_mut(), mid, &y)?.is_empty() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some(hi))
}

/// Breaks the joints past their bounds at (t, y): their flags set in `broken` and given to the model and the
/// collider set; gives them, in order.
pub(super) fn break_overloaded(
    system: &mut AccurateSystem,
    broken: &mut [bool],
    scene: Scene<'_>,
    t: f64,
    y: &[f64],
) -> Result<Vec<usize>, OdeError> {
    let which = overloaded_at(system, t, y)?;
    give_broken(system, broken, scene, &which);
    Ok(which)
}

/// Sets joints `which` broken in `broken` and gives the flags to the model and the collider set.
pub(super) fn give_broken(system: &mut AccurateSystem, broken: &mut [bool], scene: Scene<'_>, which: &[usize]) {
    if which.is_empty() {
        return;
    }
    for &k in which {
        broken[k] = true;
    }
    #[cfg(feature = "contact")]
    crate::engine::breaking::set_broken(&mut system.model, scene, broken).expect("one flag per joint");
    #[cfg(not(feature = "contact"))]
    {
        let _ = scene;
        system.model.set_broken_joints(broken).expect("one flag per joint");
    }
}

/// Breaks the joints a contact step's `loads` take past their bounds, at the step's end t (booked in `run`);
/// gives whether any broke.
#[cfg(feature = "contact")]
pub(super) fn break_after_step(
    cx: &mut super::contact_stages::ContactStages<'_>,
    system: &mut AccurateSystem,
    loads: &[JointLoad],
    t: f64,
    run: Option<&mut crate::run::Run>,
) -> bool {
    if !system.model.can_break() || loads.is_empty() {
        return false;
    }
    let which = system.model.overloaded(loads);
    give_broken(system, cx.broken, Some(&mut *cx.scene), &which);
    if let Some(run) = run {
        which.iter().for_each(|&k| run.break_joint(t, k));
    }
    !which.is_empty()
}
