//! Resting contacts inside the equations of motion (accurate mode with `Persistent::RestingForces`): contacts
//! attached to the bodies that carry them, and the right-hand-side stage that gives them the chapter's QP forces,
//! so that resting bodies neither sink into nor accelerate away from what holds them.

use super::qp;
use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::model::layout::add3;
use crate::model::{actor_poses, Kinematics, Model};
use nalgebra::{Isometry3, Point3, Vector3};
use std::time::Instant;
use tumble_contact::{Contact, NormalMotion, SolverSettings};
use tumble_integrate::SystemError;

/// A resting contact held in the frames of its two actors.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct RestingContact {
    pub a: usize,
    pub b: usize,
    /// The contact's point on A's surface, in A's frame; on B's, in B's.
    pub local_a: Vector3<f64>,
    pub local_b: Vector3<f64>,
    /// The normal (A to B) in the frame of the body whose face it is (A for `WithA`, else B).
    pub normal: Vector3<f64>,
    pub motion: NormalMotion,
    pub restitution: f64,
    pub friction: f64,
    pub key: ContactKey,
}

/// The resting contacts of an accurate-mode world between two impact stages (part of the engine's memory).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub(crate) struct RestingContacts {
    pub contacts: Vec<RestingContact>,
    /// Contacts whose gap has opened past this no longer push (m).
    pub reach: f64,
}

impl RestingContacts {
    /// Whether every contact names one of `actors` actors and `colliders` colliders, and the reach is finite.
    pub fn fits(&self, actors: usize, colliders: usize) -> bool {
        self.reach.is_finite() && self.contacts.iter().all(|c| c.a < actors && c.b < actors && c.key.fits(colliders))
    }
}

impl RestingContact {
    /// Attaches a contact found at `poses` to its actors.
    pub fn attach(f: &FoundContact, poses: &[Isometry3<f64>]) -> Self {
        let c = &f.contact;
        let (pa, pb) = (&poses[c.a], &poses[c.b]);
        let owner = if c.normal_motion == NormalMotion::WithA { pa } else { pb };
        RestingContact {
            a: c.a,
            b: c.b,
            local_a: pa.inverse_transform_point(&f.point_a).coords,
            local_b: pb.inverse_transform_point(&f.point_b).coords,
            normal: owner.inverse_transform_vector(&c.normal),
            motion: c.normal_motion,
            restitution: c.restitution,
            friction: c.friction,
            key: f.key,
        }
    }

    /// The contact at `poses` and its gap n . (p_B - p_A).
    pub fn place(&self, poses: &[Isometry3<f64>]) -> (Contact, f64) {
        let (pa, pb) = (&poses[self.a], &poses[self.b]);
        let (wa, wb) = (pa * Point3::from(self.local_a), pb * Point3::from(self.local_b));
        let normal = match self.motion {
            NormalMotion::WithA => nalgebra::Unit::new_normalize(pa * self.normal),
            NormalMotion::BetweenCentres => {
                nalgebra::Unit::try_new(pb.translation.vector - pa.translation.vector, 1e-300)
                    .unwrap_or(nalgebra::Unit::new_normalize(pb * self.normal))
            }
            _ => nalgebra::Unit::new_normalize(pb * self.normal),
        };
        let point = match self.motion {
            NormalMotion::WithA => wb,
            NormalMotion::WithB => wa,
            _ => Point3::from((wa.coords + wb.coords) * 0.5),
        };
        let gap = normal.dot(&(wb - wa));
        let contact = Contact {
            a: self.a,
            b: self.b,
            point,
            normal,
            distance: gap,
            restitution: self.restitution,
            friction: self.friction,
            normal_motion: self.motion,
            // the chapter's resting forces take no resistance to turning (a world that asks for it is refused)
            rolling_resistance: 0.0,
            torsional_resistance: 0.0,
        };
        (contact, gap)
    }
}

/// Adds the forces of the resting contacts `set` at state y to the p rates `dp` (the last stage of the right-hand
/// side): the chapter's QP over the contacts still within reach, with the static actors at `statics`. Returns the
/// solver calls and the seconds they took.
pub(super) fn add_resting_forces(
    model: &Model,
    kin: &Kinematics,
    set: &RestingContacts,
    statics: &[Isometry3<f64>],
    solver: &SolverSettings,
    y: &[f64],
    dp: &mut [f64],
) -> Result<(usize, f64), SystemError> {
    if set.contacts.is_empty() {
        return Ok((0, 0.0));
    }
    let clock = Instant::now();
    let poses = actor_poses(model.layout, y, statics);
    let states = model.contact_states(kin, y, dp, statics, &[]);
    let contacts: Vec<Contact> =
        set.contacts.iter().map(|r| r.place(&poses)).filter(|(_, gap)| *gap <= set.reach).map(|(c, _)| c).collect();
    if contacts.is_empty() {
        return Ok((0, 0.0));
    }
    let (wrenches, calls) = qp::resting_wrenches(&states, &contacts, solver)
        .map_err(|e| SystemError::new(format!("resting contact: {e}")))?;
    let (l, q) = (model.layout, model.layout.positions());
    for (k, (force, torque)) in wrenches.iter().enumerate() {
        if k < l.particles {
            add3(dp, l.pv(k) - q, &(force * model.particles[k].inv_mass));
        } else if k < l.actors() {
            let j = k - l.particles;
            add3(dp, l.bp(j) - q, force);
            add3(dp, l.bl(j) - q, torque);
        }
    }
    Ok((calls, clock.elapsed().as_secs_f64()))
}
