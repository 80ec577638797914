//! Contact Jacobian rows: how a contact's relative velocity along a direction depends on the velocities of its two
//! bodies (B counted positive, A negative), and the entries of J M^-1 J^T they produce.

use crate::body::BodyState;
use crate::contact::Contact;
use nalgebra::Vector3;

/// The part of one Jacobian row that belongs to one body: d . v + ang . w.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Row {
    pub body: usize,
    pub lin: Vector3<f64>,
    pub ang: Vector3<f64>,
}

// (the chapter's QPs use these; without clarabel only the rows are)
#[cfg_attr(not(feature = "clarabel"), allow(dead_code))]
impl Row {
    /// This row's share of the relative velocity.
    pub fn velocity(&self, bodies: &[BodyState]) -> f64 {
        let b = &bodies[self.body];
        self.lin.dot(&b.velocity) + self.ang.dot(&b.angular_velocity)
    }

    /// The (i, j) entry of J M^-1 J^T contributed by one shared body: lin_i . lin_j / m + ang_i^T I^-1 ang_j.
    pub fn coupling(&self, other: &Row, bodies: &[BodyState]) -> f64 {
        let b = &bodies[self.body];
        self.lin.dot(&other.lin) * b.inv_mass + self.ang.dot(&(b.inv_inertia * other.ang))
    }
}

/// The two rows of contact `c` along direction `d` (world): relative velocity d . (v_B(p) - v_A(p)).
pub(crate) fn rows(c: &Contact, bodies: &[BodyState], d: &Vector3<f64>) -> [Row; 2] {
    let ra = c.point - bodies[c.a].position;
    let rb = c.point - bodies[c.b].position;
    [Row { body: c.a, lin: -d, ang: -ra.cross(d) }, Row { body: c.b, lin: *d, ang: rb.cross(d) }]
}
