//! Fast mode, fourth stage: positions from the new velocities (semi-implicit Euler, `engine/semi_implicit.rs`);
//! sleeping actors stay where they are.

use super::FastEngine;
use crate::engine::semi_implicit::update_positions;
use tumble_contact::BodyVelocity;

impl FastEngine {
    /// Semi-implicit Euler: positions and orientations from the new velocities; momenta from them.
    pub(super) fn integrate_positions(&mut self, v: &[BodyVelocity], h: f64) {
        let sleep = &self.sleep;
        update_positions(&self.compiled.model, &mut self.y, v, h, |a| !sleep.asleep(a));
    }
}
