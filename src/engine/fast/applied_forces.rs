//! Fast mode, first stage: the applied forces at the step's start (gravity, damping, springs, loads, callbacks:
//! the equations of motion's force part; without the springs for the soft step, which evaluates them at every
//! substep), and the actors as the contact solve sees them, sleeping ones fixed.

use super::{failure, FastEngine};
use crate::engine::Engine;
use crate::mode::FastSolver;
use crate::model::StateOptions;
use crate::WorldError;
use tumble_contact::BodyState;
use tumble_integrate::OdeError;

impl FastEngine {
    /// Evaluates the equations of motion at the current state; returns the actors with those forces. With the soft
    /// solver the springs are left out: its substeps evaluate them (`soft_solve.rs`).
    pub(super) fn applied_forces(&mut self) -> Result<Vec<BodyState>, WorldError> {
        let t = self.time();
        let model = &mut self.model;
        match self.settings.solver {
            FastSolver::Soft(_) => model.rates(t, &self.memory.y, &mut self.dy, false),
            FastSolver::Exact { .. } => model.rates(t, &self.memory.y, &mut self.dy, true),
        }
        .map_err(|e| failure(t, e.to_string()))?;
        if let Some(index) = self.dy.iter().position(|v| !v.is_finite()) {
            return Err(WorldError::Simulation(OdeError::NonFinite { t, what: "force", index }));
        }
        Ok(self.body_states())
    }

    /// The actors with the forces of the last evaluation; sleeping actors are passed as fixed. The step conserves
    /// angular momentum (w* = I^-1 (L + h tau)), so Euler's gyroscopic term that tumble-contact adds is cancelled.
    pub(super) fn body_states(&self) -> Vec<BodyState> {
        let model = &self.model;
        let statics = self.scene.as_ref().map_or(&[][..], |s| &s.static_poses[..]);
        let options = StateOptions { asleep: self.memory.sleep.flags(), cancel_gyroscopic: true };
        model.contact_states(&self.memory.y, &self.dy[model.layout.positions()..], statics, options)
    }
}
