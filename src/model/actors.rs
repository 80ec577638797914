//! Actors as the contact stages see them: the pose of every particle, dynamic body and static body in a state, and
//! their states for tumble-contact (mass, inertia, velocities, applied forces). Actors are numbered particles
//! first, then dynamic bodies, then static bodies, in both lists.

use crate::model::layout::{get3, get_quat, Layout};
use crate::model::{Kinematics, Model};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use tumble_collide::rotated_tensor;
use tumble_contact::BodyState;
use tumble_integrate::OdeError;

/// The pose of every actor (particles: translation only; then dynamic bodies; then `statics`) in state y.
pub(crate) fn actor_poses(l: Layout, y: &[f64], statics: &[Isometry3<f64>]) -> Vec<Isometry3<f64>> {
    let mut out = Vec::with_capacity(l.actors() + statics.len());
    for i in 0..l.particles {
        out.push(Isometry3::from_parts(Translation3::from(get3(y, l.px(i))), UnitQuaternion::identity()));
    }
    for j in 0..l.bodies {
        let q = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        out.push(Isometry3::from_parts(Translation3::from(get3(y, l.bx(j))), q));
    }
    out.extend(statics.iter().copied());
    out
}

impl Model {
    /// The actors as tumble-contact sees them in state y, with the applied forces of `dp` (the p rates, after the
    /// positions), using the body kinematics `kin` of y (those the forces were evaluated with); the actors `asleep`
    /// says (by index; shorter than the actors means the rest are awake) are passed as fixed.
    pub(crate) fn contact_states(
        &self,
        kin: &Kinematics,
        y: &[f64],
        dp: &[f64],
        statics: &[Isometry3<f64>],
        asleep: &[bool],
    ) -> Vec<BodyState> {
        let (l, q) = (self.layout, self.layout.positions());
        let asleep = |a: usize| asleep.get(a).copied().unwrap_or(false);
        let mut out = Vec::with_capacity(l.actors() + statics.len());
        for (i, p) in self.particles.iter().enumerate() {
            let x = Point3::from(get3(y, l.px(i)));
            if asleep(i) {
                out.push(BodyState::fixed(x));
                continue;
            }
            let mut s = BodyState::particle(p.mass, x, get3(y, l.pv(i)));
            s.force = get3(dp, l.pv(i) - q) * p.mass;
            out.push(s);
        }
        for (j, b) in self.bodies.iter().enumerate() {
            let x = Point3::from(get3(y, l.bx(j)));
            if asleep(l.body_actor(j)) {
                out.push(BodyState::fixed(x));
                continue;
            }
            let k = &kin[j];
            if b.kinematic.is_some() {
                // immovable, and moving along its path
                out.push(BodyState { velocity: k.velocity, angular_velocity: k.omega, ..BodyState::fixed(x) });
                continue;
            }
            let inertia = rotated_tensor(&k.rot, &b.inertia);
            let inv_inertia = rotated_tensor(&k.rot, &b.inv_inertia);
            let mut s = BodyState { inv_mass: 1.0 / b.mass, inertia, inv_inertia, ..BodyState::fixed(x) };
            s.velocity = k.velocity;
            s.angular_velocity = k.omega;
            s.force = get3(dp, l.bp(j) - q);
            s.torque = get3(dp, l.bl(j) - q);
            out.push(s);
        }
        out.extend(statics.iter().map(|p| BodyState::fixed(Point3::from(p.translation.vector))));
        out
    }

    /// The actors of a time step from state y and the rates `dy` of its force evaluation (fast mode's steps,
    /// accurate mode's contact steps): the forces checked finite (an error names the first rate that is not), the
    /// `asleep` actors fixed. (The steps carry angular momentum: tumble-contact's settings leave Euler's gyroscopic
    /// term out.)
    pub(crate) fn step_actors(
        &self,
        kin: &Kinematics,
        t: f64,
        y: &[f64],
        dy: &[f64],
        statics: &[Isometry3<f64>],
        asleep: &[bool],
    ) -> Result<Vec<BodyState>, OdeError> {
        if let Some(index) = dy.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFinite { t, what: "force", index });
        }
        Ok(self.contact_states(kin, y, &dy[self.layout.positions()..], statics, asleep))
    }
}
