//! The soft step's data laid out for its sweeps: a body as the substeps move it (`Mover`) and a contact point as
//! three constraint axes (normal and two tangents) with their Jacobians and the inverse mass times them computed
//! once a step, so a sweep over a row is a few dot products and axpys.

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

    /// A static body at rest: its velocities are zero and stay so.
    pub fn is_still(&self) -> bool {
        self.still
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

    /// Applies an impulse of `p` along the axis: +p on B, -p on A.
    #[inline]
    pub fn apply(&self, a: &mut Mover, b: &mut Mover, p: f64) {
        a.v -= self.dir * (p * a.inv_mass);
        a.w -= self.ia * p;
        b.v += self.dir * (p * b.inv_mass);
        b.w += self.ib * p;
    }

    /// `speed`, skipping a side that is `still` (its terms are zeros).
    #[inline]
    pub fn speed_on(&self, a: &Mover, b: &Mover, still: Still) -> f64 {
        match still {
            Still::Neither => self.speed(a, b),
            Still::A => self.dir.dot(&b.v) + self.cb.dot(&b.w),
            Still::B => self.dir.dot(&(-a.v)) - self.ca.dot(&a.w),
        }
    }

    /// `apply`, skipping a side that is `still` (an impulse changes nothing there).
    #[inline]
    pub fn apply_on(&self, a: &mut Mover, b: &mut Mover, p: f64, still: Still) {
        match still {
            Still::Neither => self.apply(a, b, p),
            Still::A => {
                b.v += self.dir * (p * b.inv_mass);
                b.w += self.ib * p;
            }
            Still::B => {
                a.v -= self.dir * (p * a.inv_mass);
                a.w -= self.ia * p;
            }
        }
    }
}

/// Which side of a row, if any, is a static body at rest (whose velocities are zeros a sweep need not read or
/// write: most rows against the floor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Still {
    Neither,
    A,
    B,
}

impl Still {
    pub fn of(a: &Mover, b: &Mover) -> Still {
        match (a.is_still(), b.is_still()) {
            (true, false) => Still::A,
            (false, true) => Still::B,
            _ => Still::Neither,
        }
    }
}

/// One contact point's normal row: what every sweep reads and writes (the friction rows and the rest of the
/// contact are kept apart, so that a sweep without friction streams only these).
#[derive(Clone, Debug)]
pub(crate) struct Row {
    pub a: usize,
    pub b: usize,
    pub normal_axis: Axis,
    /// The gap where the substeps have moved the bodies (negative: penetration).
    pub current_gap: f64,
    /// Against a static or kinematic body (stiffer softness).
    pub fixed: bool,
    /// A side that is a static body at rest.
    pub still: Still,
    /// Accumulated normal impulse of the current substep, and the largest it has been.
    pub normal: f64,
    pub max_normal: f64,
}

/// A contact point's friction: its two tangent axes and accumulated impulses along them.
#[derive(Clone, Debug)]
pub(crate) struct FrictionRow {
    pub axes: [Axis; 2],
    pub tangent: [f64; 2],
    pub friction: f64,
}

impl FrictionRow {
    /// The friction impulse as a world vector.
    pub fn vector(&self) -> Vector3<f64> {
        self.axes[0].dir * self.tangent[0] + self.axes[1].dir * self.tangent[1]
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
