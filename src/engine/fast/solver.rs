//! Fast mode's exact solver for one step (`Solver`): the conic program of a set of contacts among the step's actors,
//! with lagged friction or Anitescu's cone, counting its clarabel calls. The velocity stage (`solve_velocities.rs`)
//! and the bounce limiter (`bounce_limiter.rs`) solve with it.

use crate::engine::failure::failure;
use crate::error::WorldError;
use crate::mode::FastFriction;
use tumble_contact::{velocity_step, BodyState, Contact, StepSettings, VelocityProblem, VelocityStep};

/// The conic-program solver of one step: the actors, the settings, and how many clarabel calls it made.
pub(super) struct Solver<'a> {
    pub states: &'a [BodyState],
    pub settings: StepSettings,
    pub friction: FastFriction,
    pub t: f64,
    pub solves: usize,
}

impl Solver<'_> {
    /// The velocity step for `contacts`, friction bounded by `previous` normal impulses when lagged.
    pub fn solve(&mut self, contacts: &[Contact], previous: &[f64]) -> Result<VelocityStep, WorldError> {
        let out = match self.friction {
            FastFriction::Lagged => {
                velocity_step(&VelocityProblem::new(self.states, contacts).lagged(previous), &self.settings)
            }
            FastFriction::Cone => velocity_step(&VelocityProblem::new(self.states, contacts), &self.settings),
        }
        .map_err(|e| failure(self.t, format!("contact solve: {e}")))?;
        self.solves += out.solver_calls;
        Ok(out)
    }
}
