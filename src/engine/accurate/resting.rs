//! Resting contacts inside the equations of motion (accurate mode): contacts attached to the bodies that carry
//! them, and the right-hand-side stage that gives them the chapter's QP forces, so that resting bodies neither
//! sink into nor accelerate away from what holds them.

use crate::engine::contact_scene::{ContactKey, Found};
use crate::model::layout::add3;
use crate::model::{actor_poses, Model};
use nalgebra::{Isometry3, Point3, Vector3};
use std::time::Instant;
use tumble_contact::{contact_wrenches, resting_forces, Contact, NormalMotion, SolverSettings};
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

/// The resting contacts of an accurate-mode world between two contact phases.
#[derive(Clone, Debug, Default)]
pub(crate) struct RestingSet {
    pub contacts: Vec<RestingContact>,
    pub statics: Vec<Isometry3<f64>>,
    pub settings: SolverSettings,
    /// Contacts whose gap has opened past this no longer push (m).
    pub reach: f64,
    /// QP solves and their wall time since the last report.
    pub solves: usize,
    pub seconds: f64,
}

impl RestingContact {
    /// Attaches a contact found at `poses` to its actors.
    pub fn attach(f: &Found, poses: &[Isometry3<f64>]) -> Self {
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
        };
        (contact, gap)
    }
}

impl Model {
    /// Adds the resting-contact forces to the p rates (the last stage of the right-hand side).
    pub(crate) fn add_resting_forces(&mut self, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        let Some(mut set) = self.resting.take() else { return Ok(()) };
        let result = self.resting_stage(&mut set, y, dp);
        self.resting = Some(set);
        result
    }

    fn resting_stage(&self, set: &mut RestingSet, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        if set.contacts.is_empty() {
            return Ok(());
        }
        let clock = Instant::now();
        let poses = actor_poses(self.layout, y, &set.statics);
        let states = self.contact_states(y, dp, &set.statics, Default::default());
        let contacts: Vec<Contact> =
            set.contacts.iter().map(|r| r.place(&poses)).filter(|(_, gap)| *gap <= set.reach).map(|(c, _)| c).collect();
        if contacts.is_empty() {
            return Ok(());
        }
        let out = resting_forces(&states, &contacts, &set.settings)
            .map_err(|e| SystemError::new(format!("resting contact: {e}")))?;
        set.solves += out.solver_calls;
        let (l, q) = (self.layout, self.layout.positions());
        for (k, (force, torque)) in contact_wrenches(&states, &contacts, &out.forces).iter().enumerate() {
            if k < l.particles {
                add3(dp, l.pv(k) - q, &(force * self.particles[k].inv_mass));
            } else if k < l.particles + l.bodies {
                let j = k - l.particles;
                add3(dp, l.bp(j) - q, force);
                add3(dp, l.bl(j) - q, torque);
            }
        }
        set.seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }
}
