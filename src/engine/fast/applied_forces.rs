//! Fast mode, first stage: the applied forces at the step's start (gravity, damping, springs, loads, callbacks:
//! the equations of motion's force part; without the springs for the soft step, which evaluates them at every
//! substep), and the actors as the contact solve sees them, sleeping ones fixed.

use super::context::StepContext;
use crate::engine::failure::failure;
use crate::mode::FastSolver;
use crate::WorldError;
use tumble_contact::BodyState;

/// Evaluates the applied forces at the current state (velocity form: the body kinematics read from it); returns the
/// actors with those forces. With the soft solver the springs are left out: its substeps evaluate them
/// (`soft_solve.rs`).
pub(super) fn applied_forces(cx: &mut StepContext<'_>) -> Result<Vec<BodyState>, WorldError> {
    let t = cx.t;
    let springs = matches!(cx.settings.solver, FastSolver::Exact { .. });
    cx.kin =
        cx.model.velocity_forces(cx.tally, t, &cx.memory.y, cx.dy, springs).map_err(|e| failure(t, e.to_string()))?;
    actors(cx)
}

/// The actors with the forces of the last evaluation (checked finite); sleeping actors are passed as fixed.
pub(super) fn actors(cx: &StepContext<'_>) -> Result<Vec<BodyState>, WorldError> {
    let statics = cx.collider_set.as_deref().map_or(&[][..], |s| &s.static_poses[..]);
    Ok(cx.model.step_actors(&cx.kin, cx.t, &cx.memory.y, cx.dy, statics, cx.memory.sleep.flags())?)
}
