//! The bodies' kinematics at one state: each body's rotation matrix, angular velocity and velocity, built once from
//! the state (momentum form for the equations of motion, velocity form for fast mode) and passed to what reads them.

use crate::model::layout::{get3, get_quat};
use crate::model::Model;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use tumble_collide::rotated_tensor;

/// A body's rotation, angular and linear velocity at one state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyKin {
    pub rot: Matrix3<f64>,
    pub omega: Vector3<f64>,
    pub velocity: Vector3<f64>,
}

/// Every body's kinematics at one state, in body order.
#[derive(Clone, Debug, Default)]
pub(crate) struct Kinematics(pub Vec<BodyKin>);

impl std::ops::Index<usize> for Kinematics {
    type Output = BodyKin;
    fn index(&self, j: usize) -> &BodyKin {
        &self.0[j]
    }
}

impl Model {
    /// A body's kinematics from a state in momentum form (its quaternion normalised first).
    pub(crate) fn body_kin(&self, y: &[f64], j: usize) -> BodyKin {
        let (l, b) = (self.layout, &self.bodies[j]);
        let rot = UnitQuaternion::new_normalize(get_quat(y, l.bq(j))).to_rotation_matrix().into_inner();
        let inv_inertia = rotated_tensor(&rot, &b.inv_inertia);
        BodyKin { rot, omega: inv_inertia * get3(y, l.bl(j)), velocity: get3(y, l.bp(j)) * b.inv_mass }
    }

    /// The kinematics of a state in momentum form (the equations of motion's).
    pub(crate) fn kinematics(&self, y: &[f64]) -> Kinematics {
        Kinematics((0..self.bodies.len()).map(|j| self.body_kin(y, j)).collect())
    }

    /// The kinematics of a state in velocity form (fast mode's): velocities read as they are.
    pub(crate) fn velocity_kinematics(&self, y: &[f64]) -> Kinematics {
        let l = self.layout;
        Kinematics(
            (0..l.bodies)
                .map(|j| {
                    let rot = UnitQuaternion::new_normalize(get_quat(y, l.bq(j))).to_rotation_matrix().into_inner();
                    BodyKin { rot, omega: get3(y, l.bl(j)), velocity: get3(y, l.bp(j)) }
                })
                .collect(),
        )
    }
}
