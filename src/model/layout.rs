//! Where each quantity lives in the state vector y = (q | p): q holds particle positions, body positions and
//! body quaternions (w, x, y, z); p holds particle velocities, body momenta P and angular momenta L. A particle
//! takes 6 numbers, a dynamic body 13; static bodies take none.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Layout {
    pub particles: usize,
    pub bodies: usize,
}

impl Layout {
    /// Length of q (the position part).
    pub fn positions(&self) -> usize {
        3 * self.particles + 7 * self.bodies
    }
    /// The moving actors: the particles, then the dynamic bodies (an actor's index in that order).
    pub fn actors(&self) -> usize {
        self.particles + self.bodies
    }
    /// Dynamic body `j`'s actor index.
    pub fn body_actor(&self, j: usize) -> usize {
        self.particles + j
    }
    /// Length of y.
    pub fn dim(&self) -> usize {
        6 * self.particles + 13 * self.bodies
    }
    pub fn px(&self, i: usize) -> usize {
        3 * i
    }
    pub fn bx(&self, j: usize) -> usize {
        3 * self.particles + 3 * j
    }
    pub fn bq(&self, j: usize) -> usize {
        3 * self.particles + 3 * self.bodies + 4 * j
    }
    pub fn pv(&self, i: usize) -> usize {
        self.positions() + 3 * i
    }
    pub fn bp(&self, j: usize) -> usize {
        self.positions() + 3 * self.particles + 3 * j
    }
    pub fn bl(&self, j: usize) -> usize {
        self.positions() + 3 * self.particles + 3 * self.bodies + 3 * j
    }
}

#[inline]
pub(crate) fn get3(y: &[f64], k: usize) -> Vector3<f64> {
    Vector3::new(y[k], y[k + 1], y[k + 2])
}

#[inline]
pub(crate) fn set3(y: &mut [f64], k: usize, v: &Vector3<f64>) {
    y[k..k + 3].copy_from_slice(v.as_slice());
}

#[inline]
pub(crate) fn add3(y: &mut [f64], k: usize, v: &Vector3<f64>) {
    y[k] += v.x;
    y[k + 1] += v.y;
    y[k + 2] += v.z;
}

/// The quaternion stored at k as (w, x, y, z), not normalised.
#[inline]
pub(crate) fn get_quat(y: &[f64], k: usize) -> Quaternion<f64> {
    Quaternion::new(y[k], y[k + 1], y[k + 2], y[k + 3])
}

#[inline]
pub(crate) fn set_quat(y: &mut [f64], k: usize, q: &UnitQuaternion<f64>) {
    y[k] = q.w;
    y[k + 1] = q.i;
    y[k + 2] = q.j;
    y[k + 3] = q.k;
}
