//! The soft step's bodies as the substeps move them (`Mover`). The rows themselves are laid out in the lanes of
//! bundles (`bundle.rs`).

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
    /// The body's mover, its free motion with Euler's gyroscopic term if `gyroscopic` (`SoftSettings::gyroscopic`).
    pub fn new(b: &BodyState, gyroscopic: bool) -> Mover {
        let dynamic = b.is_dynamic();
        Mover {
            inv_mass: b.inv_mass,
            inv_inertia: b.inv_inertia,
            v: b.velocity,
            w: b.angular_velocity,
            accel: if dynamic { b.force * b.inv_mass } else { Vector3::zeros() },
            angular_accel: if dynamic { b.free_angular_acceleration(gyroscopic) } else { Vector3::zeros() },
            dp: Vector3::zeros(),
            dq: UnitQuaternion::identity(),
            turn: Matrix3::identity(),
            moving: b.inv_mass > 0.0 || b.inv_inertia != Matrix3::zeros(),
        }
    }

    /// Free motion over h in `substeps` (no contact): the same sequence the groups' bodies follow.
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

    /// The work its applied force did over its displacement since the step's start (J; zero for a body that does
    /// not move).
    pub fn force_work(&self) -> f64 {
        if self.moving && self.inv_mass > 0.0 {
            self.accel.dot(&self.dp) / self.inv_mass
        } else {
            0.0
        }
    }
}
