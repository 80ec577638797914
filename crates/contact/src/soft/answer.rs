//! What a soft step gives back: each body's new velocity and motion, the contacts' and joints' impulses, and the
//! counts; and how a solved group's answer is taken into it.

use super::group::Group;
use super::{SoftImpulse, SoftManifold, Spec};
use crate::impulse::BodyVelocity;
use crate::joint::JointImpulse;
use nalgebra::{UnitQuaternion, Vector3};
use std::borrow::BorrowMut;

/// What a soft step gives.
#[derive(Clone, Debug)]
pub struct SoftStep {
    /// Each body's velocities at the step's end.
    pub velocities: Vec<BodyVelocity>,
    /// Each body's displacement of its centre of mass over the step.
    pub displacements: Vec<Vector3<f64>>,
    /// Each body's rotation over the step (world frame: new orientation = rotation * old).
    pub rotations: Vec<UnitQuaternion<f64>>,
    /// Each contact's impulses of the last substep (to start the next step with), and its normal impulse over the
    /// whole step (the substeps' sum): `soft_step`'s, by contact (`soft_solve` leaves them empty: its manifolds
    /// hold them).
    pub impulses: Vec<SoftImpulse>,
    pub normal_impulses: Vec<f64>,
    /// Each joint's row impulses of the last substep (to start the next step with), and over the whole step (the
    /// substeps' sum: what it carried; with a window, each substep's weighed by e^(-substep / window) a later
    /// substep, `SoftLinks::windows`).
    pub joint_impulses: Vec<JointImpulse>,
    pub joint_step_impulses: Vec<JointImpulse>,
    /// Each manifold's impulse over the whole step on its body B (normal, friction, twist and rolling together):
    /// linear, and angular about B's centre at the step's start (A takes the opposite linear impulse, at the same
    /// points); with a window (`SoftLinks::manifold_windows`), each substep's weighed by e^(-substep / window) a
    /// later substep. `soft_solve`'s, by manifold (`soft_step` leaves it empty).
    pub manifold_impulses: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Each manifold's impulse as in `manifold_impulses`, but a blow's normal impulse (at a point that closed faster
    /// than the bounce threshold) summed without the window's weights: the blow counted at its full weight wherever
    /// in the step it fell, for judging a load's peak within the step (weighed, a blow early in a step counted
    /// e^(-h / window) of itself at its end: 0.66 at h = 1/240 s and a 10 ms window). The same as
    /// `manifold_impulses` where no point was struck.
    pub manifold_peak_impulses: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Islands solved.
    pub islands: usize,
    /// How far the step's end is from the exact contact conditions (m/s): the largest approach speed of a touching
    /// contact, separating speed of a contact that pushes while apart, or slip of a contact sticking inside its
    /// friction bound. Zero for the exact answer; what the sweeps left unsolved otherwise.
    pub residual: f64,
    /// Time spent building the rows (s: each group's bodies, bundles, constraint axes and effective masses, joints
    /// and springs), summed over the groups (on several threads it can pass the wall time).
    pub prepare_seconds: f64,
    /// Contact points that pushed (a positive impulse over the step), and of those the ones that closed faster than
    /// the bounce threshold (collisions).
    pub pushing: usize,
    pub collisions: usize,
}

/// Two steps are equal when their answers are: the time they took is not part of it.
impl PartialEq for SoftStep {
    fn eq(&self, o: &SoftStep) -> bool {
        self.velocities == o.velocities
            && self.displacements == o.displacements
            && self.rotations == o.rotations
            && self.impulses == o.impulses
            && self.normal_impulses == o.normal_impulses
            && self.joint_impulses == o.joint_impulses
            && self.joint_step_impulses == o.joint_step_impulses
            && self.manifold_impulses == o.manifold_impulses
            && self.manifold_peak_impulses == o.manifold_peak_impulses
            && self.islands == o.islands
            && self.residual.to_bits() == o.residual.to_bits()
            && (self.pushing, self.collisions) == (o.pushing, o.collisions)
    }
}

impl SoftStep {
    /// A solved group's contact impulses (into the manifolds), joint impulses and counts.
    pub(super) fn take<M: BorrowMut<SoftManifold>>(
        &mut self,
        group: &Group,
        spec: &Spec,
        manifolds: &mut [M],
        threshold: f64,
    ) {
        for (bu, fr) in group.bundles.iter().zip(&group.frictions) {
            for l in 0..bu.lanes {
                let m = manifolds[bu.manifold[l]].borrow_mut();
                m.tangent_impulse = fr.vector(l);
                m.twist_impulse = fr.twist[l];
                m.rolling_impulse = if fr.resists { fr.roll_vector(l) } else { nalgebra::Vector3::zeros() };
                let (mut linear, mut angular) = fr.step_impulse(l);
                let (mut peak_linear, mut peak_angular) = (linear, angular);
                let mut collided = false;
                for p in 0..bu.count[l] {
                    let row = &bu.rows[p];
                    let axis = &row.normal_axis;
                    let (dir, arm) = (axis.dir_of(l), Vector3::new(axis.cb[0][l], axis.cb[1][l], axis.cb[2][l]));
                    let struck = row.closing[l] < -threshold;
                    linear += dir * row.weighed[l];
                    angular += arm * row.weighed[l];
                    let held = if struck { row.step[l] } else { row.weighed[l] };
                    peak_linear += dir * held;
                    peak_angular += arm * held;
                    let point = &mut m.points[p];
                    point.normal_impulse = row.normal[l];
                    point.step_normal = row.step[l];
                    if row.step[l] > 0.0 {
                        self.pushing += 1;
                        if struck {
                            self.collisions += 1;
                            // an impact's impulse is not the next step's start (`SoftPoint::normal_impulse`)
                            point.normal_impulse = 0.0;
                            collided = true;
                        }
                    }
                }
                if collided {
                    m.tangent_impulse = nalgebra::Vector3::zeros();
                    m.twist_impulse = 0.0;
                    m.rolling_impulse = nalgebra::Vector3::zeros();
                }
                if let Some(out) = self.manifold_impulses.get_mut(bu.manifold[l]) {
                    *out = (linear, angular);
                }
                if let Some(out) = self.manifold_peak_impulses.get_mut(bu.manifold[l]) {
                    *out = (peak_linear, peak_angular);
                }
            }
        }
        for (set, joints) in group.joints.iter().zip(&spec.joints) {
            for ((&k, impulse), step) in joints.iter().zip(&set.impulses).zip(&set.step_impulses) {
                self.joint_impulses[k] = *impulse;
                self.joint_step_impulses[k] = *step;
            }
        }
    }
}
