//! The soft step's bodies and what a contact point keeps besides its constraint rows: a body as the substeps move
//! it (`Mover`), and a point's place, restitution and step impulse (`RowInfo`). The rows themselves are laid out in
//! the lanes of bundles (`bundle.rs`).

use crate::body::BodyState;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// A body as the substeps move it.
#[derive(Clone, Debug)]
pub(crate) struct Mover {
    pub inv_mass: f64,
    pub inv_inertia: Matrix3<f64>,
    pub v: Vector3<f64>,
    pub w: Vector3<f64>,
    /// Velocity change per second from the applied forces (F / m, I^-1 (tau - w x I w) at the step's start).
    accel: Vector3<f64>,
    angular_accel: Vector3<f64>,
    /// Displacement of the centre of mass since the step's start.
    pub dp: Vector3<f64>,
    /// Rotation since the step's start, and as a matrix.
    pub dq: UnitQuaternion<f64>,
    pub turn: Matrix3<f64>,
    /// Whether an impulse can change its velocities (a positive inverse mass or inertia: a dynamic body).
    moving: bool,
}

impl Mover {
    pub fn new(b: &BodyState) -> Mover {
        let dynamic = b.is_dynamic();
        let w = b.angular_velocity;
        Mover {
            inv_mass: b.inv_mass,
            inv_inertia: b.inv_inertia,
            v: b.velocity,
            w,
            accel: if dynamic { b.force * b.inv_mass } else { Vector3::zeros() },
            angular_accel: if dynamic {
                b.inv_inertia * (b.torque - w.cross(&(b.inertia * w)))
            } else {
                Vector3::zeros()
            },
            dp: Vector3::zeros(),
            dq: UnitQuaternion::identity(),
            turn: Matrix3::identity(),
            moving: b.inv_mass > 0.0 || b.inv_inertia != Matrix3::zeros(),
        }
    }

    /// Free motion over h in `substeps` (no contact): the same sequence the islands' bodies follow.
    pub fn free(&mut self, h: f64, substeps: usize) {
        let hs = h / substeps.max(1) as f64;
        for _ in 0..substeps.max(1) {
            self.integrate_velocity(hs);
            self.integrate_position(hs);
        }
    }

    pub fn integrate_velocity(&mut self, h: f64) {
        self.v += self.accel * h;
        self.w += self.angular_accel * h;
    }

    pub fn integrate_position(&mut self, h: f64) {
        self.dp += self.v * h;
        if self.w != Vector3::zeros() {
            self.dq = UnitQuaternion::from_scaled_axis(self.w * h) * self.dq;
            self.turn = self.dq.to_rotation_matrix().into_inner();
        }
    }

    /// Whether an impulse can change its velocities (a positive inverse mass or inertia: a dynamic body).
    #[inline]
    pub fn moves(&self) -> bool {
        self.moving
    }
}

/// What else a row needs, once a substep or once a step.
#[derive(Clone, Debug)]
pub(crate) struct RowInfo {
    /// The row's place among its island's contacts (rows are solved in another order).
    pub index: usize,
    pub restitution: f64,
    /// Relative normal velocity at the step's start (for restitution).
    pub closing: f64,
    /// Normal impulse applied over the step so far (each substep's accumulated impulse, plus restitution's).
    pub step_normal: f64,
}
