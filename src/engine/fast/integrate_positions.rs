//! Fast mode, fourth stage: positions from the new velocities (semi-implicit Euler, `engine/semi_implicit.rs`), or
//! the poses the soft step's substeps reached; sleeping actors stay where they are.

use super::FastEngine;
use crate::engine::semi_implicit::{apply_moves, update_positions};
use tumble_contact::{BodyVelocity, SoftStep};

impl FastEngine {
    /// Semi-implicit Euler: positions and orientations from the new velocities; momenta from them.
    pub(super) fn integrate_positions(&mut self, v: &[BodyVelocity], h: f64) {
        let sleep = &self.memory.sleep;
        update_positions(&self.model, &mut self.memory.y, v, h, |a| !sleep.asleep(a));
    }
}

impl FastEngine {
    /// The soft step's poses and velocities.
    pub(super) fn apply_moves(&mut self, out: &SoftStep) {
        let sleep = &self.memory.sleep;
        apply_moves(&self.model, &mut self.memory.y, out, |a| !sleep.asleep(a));
    }
}
