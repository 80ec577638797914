//! One step of fast mode as a list of stages, one file each, run in order on the step's context (`context.rs`: the
//! engine's parts, borrowed for the step): the kinematic bodies put on their path, the applied forces at the step's
//! start (`applied_forces.rs`), the contacts found with a margin (`find_contacts.rs`), the contact solve, either the
//! soft step, which gives velocities and poses from its substeps (`soft_solve.rs`, the default), or the exact
//! solver's velocities from one conic program per island (`solve_velocities.rs`) and positions from them by
//! semi-implicit Euler; the joints the step broke (`breaking.rs`); then the state's check, the joints' errors,
//! sleep (`update_sleep.rs`) and the report. This is the scheduler: it uses the stages, and no stage uses it.

use super::applied_forces::applied_forces;
use super::breaking::break_joints;
use super::context::StepContext;
use super::find_contacts::find_contacts;
use super::soft_solve::soft_solve;
use super::solve_velocities::solve_velocities;
use super::update_sleep::update_sleep;
use crate::engine::semi_implicit::{apply_moves, update_positions, Form};
use crate::error::WorldError;
use crate::mode::FastSolver;
use crate::model::Model;
use crate::plan::Stage;
use std::time::Instant;
use tumble_integrate::OdeError;

/// One step of size h, as its stages; gives the joints it broke.
pub(super) fn step(cx: &mut StepContext<'_>, h: f64) -> Result<Vec<usize>, WorldError> {
    let clock = Instant::now();
    // kinematic bodies onto their path, moving at what takes them to its pose at the step's end
    let driven = cx.model.drive_kinematic(cx.t, &mut cx.memory.y, Some(h));
    // the energy where the last step ended, unless a kinematic body's pull moved since
    let before = match cx.energy.take() {
        Some(e) if !driven => e,
        _ => energy(cx.model, &cx.memory.y),
    };
    let mut states = applied_forces(cx)?;
    let found = find_contacts(cx, &mut states, h)?;
    let (velocities, broken) = match cx.settings.solver {
        FastSolver::Soft(soft) => {
            let solved = soft_solve(cx, &states, h, soft)?;
            let sleep = &cx.memory.sleep;
            apply_moves(cx.model, &mut cx.memory.y, &solved.out, |a| !sleep.asleep(a));
            let broken = break_joints(cx, &solved, h / soft.substeps.max(1) as f64, h);
            (solved.out.velocities, broken)
        }
        FastSolver::Exact { .. } => {
            let velocities = solve_velocities(cx, &states, &found, h)?;
            let sleep = &cx.memory.sleep;
            update_positions(cx.model, &mut cx.memory.y, &velocities, h, Form::Velocities, |a| !sleep.asleep(a));
            (velocities, Vec::new())
        }
    };
    check_state(cx, h)?;
    if !cx.model.joints.is_empty() {
        let (rows, errors) = cx.model.joint_errors(&cx.memory.y);
        cx.report.book_joints(rows, errors);
    }
    update_sleep(cx, &states, &velocities, &found, h);
    cx.memory.steps += 1;
    let after = energy(cx.model, &cx.memory.y);
    *cx.energy = Some(after);
    let change = after - before;
    cx.report.energy_change += change;
    cx.report.energy_gain = Some(cx.report.energy_gain.unwrap_or(0.0).max(change));
    book_step(cx, h, clock);
    Ok(broken)
}

/// The mechanical energy of fast mode's state y (velocity form: kinetic, gravity's and the springs' potential; J).
pub(super) fn energy(model: &Model, y: &[f64]) -> f64 {
    model.velocity_kinetic_energy(y) + model.potential_energy(y)
}

/// Fails the step if the new state is not finite or has diverged past the limit (one comparison a component; NaN
/// fails it too).
pub(super) fn check_state(cx: &StepContext<'_>, h: f64) -> Result<(), WorldError> {
    let (limit, y) = (cx.divergence_limit, &cx.memory.y);
    if y.iter().all(|v| v.abs() <= limit) {
        return Ok(());
    }
    let t = cx.t_next;
    let error = match y.iter().position(|v| !v.is_finite()) {
        Some(index) => OdeError::NonFinite { t, what: "state", index },
        None => OdeError::Divergence { t, norm: y.iter().fold(0.0, |m, v| m.max(v.abs())), limit, h },
    };
    Err(WorldError::Simulation(error))
}

/// The report's share of a step.
fn book_step(cx: &mut StepContext<'_>, h: f64, clock: Instant) {
    let report = &mut *cx.report;
    report.sleepers = cx.memory.sleep.count();
    report.max_penetration = report.max_penetration.max(cx.memory.penetration);
    report.stages.mark(Stage::Integrate);
    let r = &mut report.integrator;
    r.steps += 1;
    r.rhs_evals += 1;
    r.min_step = r.min_step.min(h);
    r.max_step = r.max_step.max(h);
    r.wall_seconds += clock.elapsed().as_secs_f64();
}
