//! Collision impulses, as the chapter gives them: the impulse magnitude of one frictionless contact, the particle
//! form v' = v_p - e v_n, and the velocities bodies have after impulses.

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use nalgebra::{Unit, Vector3};

/// A body's velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyVelocity {
    /// Velocity of the centre of mass.
    pub linear: Vector3<f64>,
    /// Angular velocity.
    pub angular: Vector3<f64>,
}

/// The chapter's impulse magnitude for contact `c` alone:
/// j = -(1 + e) v_rel / (1/M_a + 1/M_b + n . ((I_a^-1 (r_a x n)) x r_a) + n . ((I_b^-1 (r_b x n)) x r_b)),
/// with v_rel the relative normal velocity (negative when colliding). B receives +j n at the contact point and A
/// receives -j n. A contact that is not colliding gets 0.
pub fn impulse_magnitude(bodies: &[BodyState], c: &Contact) -> Result<f64, ContactError> {
    check_all(bodies, std::slice::from_ref(c))?;
    let v_rel = c.relative_normal_velocity(bodies);
    if v_rel >= 0.0 {
        return Ok(0.0);
    }
    let n = c.normal.into_inner();
    let term = |b: &BodyState| {
        let r = c.point - b.position;
        b.inv_mass + n.dot(&(b.inv_inertia * r.cross(&n)).cross(&r))
    };
    Ok(-(1.0 + c.restitution) * v_rel / (term(&bodies[c.a]) + term(&bodies[c.b])))
}

/// The particle form of a bounce off a fixed surface with normal `n`: v' = v_p - e v_n, with v_n = (v . n) n and
/// v_p = v - v_n.
pub fn reflect(v: &Vector3<f64>, n: &Unit<Vector3<f64>>, e: f64) -> Vector3<f64> {
    let vn = n.into_inner() * v.dot(n);
    (v - vn) - vn * e
}

/// The velocities of all bodies after the world impulse `impulses[i]` is applied to body B of contact i at its point
/// (and its opposite to body A): v += J/m, w += I^-1 (r x J).
pub fn velocities_after(bodies: &[BodyState], contacts: &[Contact], impulses: &[Vector3<f64>]) -> Vec<BodyVelocity> {
    let mut out: Vec<BodyVelocity> =
        bodies.iter().map(|b| BodyVelocity { linear: b.velocity, angular: b.angular_velocity }).collect();
    for (c, j) in contacts.iter().zip(impulses) {
        for (k, sign) in [(c.a, -1.0), (c.b, 1.0)] {
            let b = &bodies[k];
            let r = c.point - b.position;
            out[k].linear += j * (sign * b.inv_mass);
            out[k].angular += b.inv_inertia * r.cross(&(j * sign));
        }
    }
    out
}
