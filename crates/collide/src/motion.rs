//! A rigid motion over a step: the shape's origin moves at a constant velocity and its frame turns at a constant
//! angular velocity about that origin, which is the straight-line-and-slerp interpolation between two poses.

use crate::aabb::check_pose;
use crate::convert::to_parry;
use crate::error::ShapeError;
use crate::geometry::ParryView;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::Vector;
use parry3d_f64::query::NonlinearRigidMotion;

/// A rigid motion starting at time 0 from `start`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// The pose at time 0.
    pub start: Isometry3<f64>,
    /// Velocity of the origin (world).
    pub linvel: Vector3<f64>,
    /// Angular velocity about the origin (world).
    pub angvel: Vector3<f64>,
}

fn finite(name: &'static str, v: &Vector3<f64>) -> Result<(), ShapeError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(ShapeError::new(name, format!("must be finite, got {v:?}")))
    }
}

impl Motion {
    /// A motion from its start pose and constant velocities (all finite).
    pub fn new(start: Isometry3<f64>, linvel: Vector3<f64>, angvel: Vector3<f64>) -> Result<Motion, ShapeError> {
        check_pose("start", &start)?;
        finite("linvel", &linvel)?;
        finite("angvel", &angvel)?;
        Ok(Motion { start, linvel, angvel })
    }

    /// A shape that stays at `pose`.
    pub fn stationary(pose: Isometry3<f64>) -> Motion {
        Motion { start: pose, linvel: Vector3::zeros(), angvel: Vector3::zeros() }
    }

    /// The motion that is at `start` at time 0 and at `end` at time `dt` (> 0), turning the short way round.
    pub fn between(start: &Isometry3<f64>, end: &Isometry3<f64>, dt: f64) -> Result<Motion, ShapeError> {
        check_pose("start", start)?;
        check_pose("end", end)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(ShapeError::new("dt", format!("must be finite and > 0, got {dt}")));
        }
        let turn = end.rotation * start.rotation.inverse();
        let linvel = (end.translation.vector - start.translation.vector) / dt;
        Ok(Motion { start: *start, linvel, angvel: turn.scaled_axis() / dt })
    }

    /// The pose at time `t`.
    pub fn pose_at(&self, t: f64) -> Isometry3<f64> {
        let rotation = UnitQuaternion::from_scaled_axis(self.angvel * t) * self.start.rotation;
        Isometry3::from_parts(Translation3::from(self.start.translation.vector + self.linvel * t), rotation)
    }

    /// parry's form of the motion for a shape seen through `view`.
    pub(crate) fn as_parry(&self, view: &ParryView) -> NonlinearRigidMotion {
        NonlinearRigidMotion::new(view.pose(&self.start), Vector::ZERO, to_parry(&self.linvel), to_parry(&self.angvel))
    }
}
