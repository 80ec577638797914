//! The normal-direction system of a set of contacts: the Delassus matrix A = J M^-1 J^T (sparse: two contacts couple
//! only through a body they share), the relative normal velocities J v, and Baraff's b, the relative normal
//! accelerations with no contact force: n . (p_B'' - p_A'') + 2 n' . (p_B' - p_A').

use crate::body::BodyState;
use crate::contact::Contact;
use crate::jacobian::{rows, Row};
use crate::lcp_problem::Triplets;

/// The normal rows of the contacts `which`, grouped by the body they touch.
pub(crate) struct NormalSystem {
    pub rows: Vec<[Row; 2]>,
}

impl NormalSystem {
    pub fn new(bodies: &[BodyState], contacts: &[Contact], which: &[usize]) -> Self {
        NormalSystem { rows: which.iter().map(|&i| rows(&contacts[i], bodies, &contacts[i].normal)).collect() }
    }

    /// A = J M^-1 J^T over the dynamic bodies.
    pub fn delassus(&self, bodies: &[BodyState]) -> Triplets {
        let mut by_body: Vec<Vec<(usize, &Row)>> = vec![Vec::new(); bodies.len()];
        for (i, pair) in self.rows.iter().enumerate() {
            for row in pair {
                if bodies[row.body].is_dynamic() {
                    by_body[row.body].push((i, row));
                }
            }
        }
        let mut a = Triplets::new(self.rows.len());
        for list in &by_body {
            for (k, &(i, ri)) in list.iter().enumerate() {
                for &(j, rj) in &list[k..] {
                    a.add(i, j, ri.coupling(rj, bodies));
                }
            }
        }
        a
    }

    /// The relative normal velocities J v (positive separating).
    pub fn velocities(&self, bodies: &[BodyState]) -> Vec<f64> {
        self.rows.iter().map(|[ra, rb]| ra.velocity(bodies) + rb.velocity(bodies)).collect()
    }
}

/// Baraff's b_i for contact `c`: the relative normal acceleration under the applied forces alone, including the
/// centripetal and gyroscopic terms of each body and the turning of the normal.
pub(crate) fn free_normal_acceleration(c: &Contact, bodies: &[BodyState]) -> f64 {
    let (a, b) = (&bodies[c.a], &bodies[c.b]);
    let n = c.normal.into_inner();
    let acc = b.free_point_acceleration(&c.point) - a.free_point_acceleration(&c.point);
    let vel = b.point_velocity(&c.point) - a.point_velocity(&c.point);
    n.dot(&acc) + 2.0 * c.normal_rate(bodies).dot(&vel)
}
