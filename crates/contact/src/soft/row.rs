//! The soft step's bodies and rows: a body as the substeps move it (`Mover`), a constraint axis of a contact point
//! (normal or tangent) with its Jacobians and the inverse mass times them computed once a step (`Axis`, laid into
//! the lanes of a bundle by `bundle.rs`, so a sweep over a row is a few dot products and axpys), and what else a row
//! keeps (`RowInfo`).

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
    turn: Matrix3<f64>,
    /// A static body at rest: it never moves (its points' motion is zero without arithmetic).
    still: bool,
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
            still: !dynamic && b.velocity == Vector3::zeros() && w == Vector3::zeros(),
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

    /// Whether no impulse can turn it (a zero inverse inertia: static and kinematic bodies).
    pub fn still_inertia(&self) -> bool {
        self.inv_inertia == Matrix3::zeros()
    }

    /// How far the material point at arm r (from the centre, at the step's start) has moved.
    #[inline]
    pub fn moved(&self, r: &Vector3<f64>) -> Vector3<f64> {
        if self.still {
            return Vector3::zeros();
        }
        self.dp + self.turn * r - r
    }
}

/// One constraint direction of a contact point: the direction d (on B; -d on A), the angular Jacobians
/// r_a x d and r_b x d, the inverse inertia times them, and the effective mass 1 / (J M^-1 J^T).
#[derive(Clone, Debug)]
pub(crate) struct Axis {
    pub dir: Vector3<f64>,
    ca: Vector3<f64>,
    cb: Vector3<f64>,
    ia: Vector3<f64>,
    ib: Vector3<f64>,
    pub mass: f64,
}

impl Axis {
    pub fn new(a: &Mover, b: &Mover, ra: &Vector3<f64>, rb: &Vector3<f64>, dir: Vector3<f64>) -> Axis {
        let (ca, cb) = (ra.cross(&dir), rb.cross(&dir));
        let (ia, ib) = (a.inv_inertia * ca, b.inv_inertia * cb);
        let k = a.inv_mass + b.inv_mass + ca.dot(&ia) + cb.dot(&ib);
        Axis { dir, ca, cb, ia, ib, mass: if k > 0.0 { 1.0 / k } else { 0.0 } }
    }

    /// The relative velocity of B's point against A's along the axis.
    #[inline]
    pub fn speed(&self, a: &Mover, b: &Mover) -> f64 {
        self.dir.dot(&(b.v - a.v)) + self.cb.dot(&b.w) - self.ca.dot(&a.w)
    }

    /// The angular Jacobians r_a x d and r_b x d and the inverse inertia times them.
    pub fn jacobians(&self) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        (self.ca, self.cb, self.ia, self.ib)
    }
}

/// What else a row needs, once a substep or once a step.
#[derive(Clone, Debug)]
pub(crate) struct RowInfo {
    /// The row's place among its island's contacts (rows are solved in another order).
    pub index: usize,
    pub ra: Vector3<f64>,
    pub rb: Vector3<f64>,
    pub restitution: f64,
    /// Gap at the step's start.
    pub gap: f64,
    /// Relative normal velocity at the step's start (for restitution).
    pub closing: f64,
    /// Normal impulse applied over the step so far (each substep's accumulated impulse, plus restitution's).
    pub step_normal: f64,
}
