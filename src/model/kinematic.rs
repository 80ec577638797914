//! Kinematic bodies in the state: their blocks of the state hold the pose their path gives and the velocities it moves on at
//! (P = v, L = w: the model gives them mass and inertia 1), their rates of momentum are zero, and each engine drives
//! them onto their path: accurate mode at every keyframe (where the velocities change, so its integration stops
//! there), fast mode at every step (with the velocities that take them to the path's pose at the step's end).

use crate::model::layout::{get3, set3, set_quat};
use crate::model::Model;

impl Model {
    /// Whether any body is kinematic.
    pub(crate) fn has_kinematic(&self) -> bool {
        self.bodies.iter().any(|b| b.kinematic.is_some())
    }

    /// The bodies that are not kinematic, by index.
    pub(crate) fn free_bodies(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.bodies.len()).filter(|&j| self.bodies[j].kinematic.is_none())
    }

    /// Zeroes the kinematic bodies' rates of momentum in `dp` (the rates after the positions): whatever pushes on
    /// them, they keep to their path.
    pub(crate) fn hold_kinematic(&self, dp: &mut [f64]) {
        let (l, q) = (self.layout, self.layout.positions());
        for (j, _) in self.bodies.iter().enumerate().filter(|(_, b)| b.kinematic.is_some()) {
            set3(dp, l.bp(j) - q, &nalgebra::Vector3::zeros());
            set3(dp, l.bl(j) - q, &nalgebra::Vector3::zeros());
        }
    }

    /// Puts every kinematic body of state y where its path has it at t, moving at the path's velocities just after
    /// t, or (`step` h given) at those that take it to the path's pose at t + h. Without a step, a body whose
    /// velocities are already the path's is left as it is (so an advance paused between keyframes goes on as one
    /// would). Returns whether any number changed.
    pub(crate) fn drive_kinematic(&self, t: f64, y: &mut [f64], step: Option<f64>) -> bool {
        let l = self.layout;
        let mut changed = false;
        for (j, b) in self.bodies.iter().enumerate() {
            let Some(path) = &b.kinematic else { continue };
            let (v, w) = match step {
                Some(h) => path.step_velocity(t, h),
                None => path.velocity_at(t),
            };
            if step.is_none() && get3(y, l.bp(j)) == v && get3(y, l.bl(j)) == w {
                continue;
            }
            set3(y, l.bp(j), &v);
            set3(y, l.bl(j), &w);
            self.place_one(j, path, t, y);
            changed = true;
        }
        changed
    }

    /// Puts kinematic body j of state y at `path`'s pose at t; whether a number changed.
    fn place_one(&self, j: usize, path: &crate::keyframes::Keyframes, t: f64, y: &mut [f64]) -> bool {
        let (l, pose) = (self.layout, path.pose_at(t));
        let q = pose.rotation;
        if get3(y, l.bx(j)) == pose.translation.vector && y[l.bq(j)..l.bq(j) + 4] == [q.w, q.i, q.j, q.k] {
            return false;
        }
        set3(y, l.bx(j), &pose.translation.vector);
        set_quat(y, l.bq(j), &q);
        true
    }

    /// Puts every kinematic body of state y at its path's pose at t (its velocities untouched): after each accepted
    /// step of accurate mode's integration, whose turn between keyframes would otherwise drift by its error
    /// tolerance. Returns whether any number changed.
    pub(crate) fn place_kinematic(&self, t: f64, y: &mut [f64]) -> bool {
        let mut changed = false;
        for (j, b) in self.bodies.iter().enumerate() {
            if let Some(path) = &b.kinematic {
                changed |= self.place_one(j, path, t, y);
            }
        }
        changed
    }

    /// The first keyframe of any kinematic body after t: where accurate mode's integration must stop.
    pub(crate) fn next_keyframe_after(&self, t: f64) -> Option<f64> {
        self.bodies.iter().filter_map(|b| b.kinematic.as_ref()?.next_time_after(t)).reduce(f64::min)
    }

    /// Whether kinematic body j (by body index) has moving still to do after t (it cannot sleep until then).
    pub(crate) fn kinematic_moves_after(&self, j: usize, t: f64) -> bool {
        self.bodies[j].kinematic.as_ref().is_some_and(|k| k.moves_after(t))
    }
}
