//! Fast mode, fourth stage: positions from the new velocities (semi-implicit Euler). Orientations turn by the
//! new angular velocity; angular momentum is taken from the inertia the velocities were solved with and scaled back
//! so the turn does not raise the rotational energy.

use super::FastEngine;
use crate::model::layout::{get3, get_quat, set3, set_quat};
use nalgebra::UnitQuaternion;
use tumble_contact::BodyVelocity;

impl FastEngine {
    /// Semi-implicit Euler: positions and orientations from the new velocities; momenta from them.
    #[allow(clippy::needless_range_loop)]
    pub(super) fn integrate_positions(&mut self, v: &[BodyVelocity], h: f64) {
        let m = &self.compiled.model;
        let l = m.layout;
        for i in 0..l.particles {
            if self.sleep.asleep(i) {
                continue;
            }
            let x = get3(&self.y, l.px(i)) + v[i].linear * h;
            set3(&mut self.y, l.px(i), &x);
            set3(&mut self.y, l.pv(i), &v[i].linear);
        }
        for (j, b) in m.bodies.iter().enumerate() {
            let a = l.particles + j;
            if self.sleep.asleep(a) {
                continue;
            }
            let (lin, w) = (v[a].linear, v[a].angular);
            let x = get3(&self.y, l.bx(j)) + lin * h;
            let q0 = UnitQuaternion::new_normalize(get_quat(&self.y, l.bq(j)));
            // L from the inertia the velocities were solved with. Turning the body under a fixed L raises
            // 1/2 L . I(q)^-1 L at second order in the turn (the second derivative is (w x L) . I^-1 (w x L) >= 0),
            // a steady gain for a fast spin; scaling L back to the energy before the turn removes it.
            let r0 = q0.to_rotation_matrix().into_inner();
            let mut momentum = r0 * b.inertia * r0.transpose() * w;
            let q1 = UnitQuaternion::from_scaled_axis(w * h) * q0;
            let r1 = q1.to_rotation_matrix().into_inner();
            let before = 0.5 * momentum.dot(&w);
            let after = 0.5 * momentum.dot(&(r1 * b.inv_inertia * r1.transpose() * momentum));
            if after > before && after > 0.0 {
                momentum *= (before / after).sqrt();
            }
            set3(&mut self.y, l.bx(j), &x);
            set_quat(&mut self.y, l.bq(j), &q1);
            set3(&mut self.y, l.bp(j), &(lin * b.mass));
            set3(&mut self.y, l.bl(j), &momentum);
        }
    }
}
