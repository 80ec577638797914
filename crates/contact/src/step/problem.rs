//! What one velocity step solves and what it gives back: the bodies, contacts, friction bounds and joint rows
//! (`VelocityProblem`, `BilateralRow`), the outcome (`VelocityStep`), and each body's free velocity.

use super::settings::StepSettings;
use crate::body::BodyState;
use crate::contact::Contact;
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use nalgebra::Vector3;

/// The outcome of a time step's velocity solve.
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityStep {
    /// Every body's velocities at the end of the step.
    pub velocities: Vec<BodyVelocity>,
    /// Normal impulse at each contact (>= 0).
    pub normal_impulses: Vec<f64>,
    /// Friction impulse at each contact (world vector on B, tangent to the contact, length <= mu p_n).
    pub friction_impulses: Vec<Vector3<f64>>,
    /// Impulse of each joint row (`VelocityProblem::bilateral`, in its order; a row's J^T times it acts on the
    /// bodies).
    pub joint_impulses: Vec<f64>,
    /// Solver iterations (clarabel's, or the Newton method's), summed over islands.
    pub iterations: u32,
    /// Solver calls (a lone particle on something static is solved in closed form, and an island no contact of
    /// which needs an impulse without a solve).
    pub solver_calls: usize,
    /// Of those, the islands the Newton method answered (the rest went to clarabel).
    pub newton_calls: usize,
    /// The islands the contacts and joint rows split into.
    pub islands: usize,
    /// The calls weighted by size, for callers that budget their work: each call counts one for every
    /// `CONTACTS_A_UNIT` contacts of its island (at least one), its cost growing with the island.
    pub solver_work: usize,
    /// Wall time spent building the islands' programs (s): their rows, Jacobians and the Newton method's Hessian
    /// structure, or clarabel's matrices; summed over islands.
    pub building_seconds: f64,
}

/// Contacts of an island that one unit of `VelocityStep::solver_work` stands for.
pub const CONTACTS_A_UNIT: usize = 8;

/// The velocity a body would have after a step of `s.dt` under its applied force and torque alone (with the
/// explicit gyroscopic term if `s.gyroscopic`); a static body keeps its velocity.
pub fn free_velocity(b: &BodyState, s: &StepSettings) -> BodyVelocity {
    if !b.is_dynamic() {
        return BodyVelocity { linear: b.velocity, angular: b.angular_velocity };
    }
    let h = s.dt;
    BodyVelocity {
        linear: b.velocity + b.force * (b.inv_mass * h),
        angular: b.angular_velocity + b.free_angular_acceleration(s.gyroscopic) * h,
    }
}

/// How a joint row of a velocity step holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BilateralKind {
    /// J v = speed, any impulse.
    Equal,
    /// J v >= speed, an impulse >= 0 (a limit, a rope).
    AtLeast,
    /// J v = speed as far as an impulse within +-max_impulse reaches (a motor).
    Motor { max_impulse: f64 },
}

/// One joint row of a velocity step: J v = lin . (v_B - v_A) + ang_a . w_A + ang_b . w_B against `speed` at the
/// step's end, as `kind` says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilateralRow {
    pub a: usize,
    pub b: usize,
    pub lin: Vector3<f64>,
    pub ang_a: Vector3<f64>,
    pub ang_b: Vector3<f64>,
    pub speed: f64,
    pub kind: BilateralKind,
}

/// What one velocity step solves: the bodies, their contacts, how friction is bounded, and joint rows held exactly
/// in the same programs (bodies joined by a row share an island).
#[derive(Clone, Copy, Debug, Default)]
pub struct VelocityProblem<'a> {
    pub bodies: &'a [BodyState],
    pub contacts: &'a [Contact],
    /// `None`: Anitescu's cone. `Some(normals)`: friction lagged, contact i's friction impulse at most mu_i
    /// normals[i] (a normal impulse for each contact: the last step's, or 0 for a new contact).
    pub lagged: Option<&'a [f64]>,
    pub bilateral: &'a [BilateralRow],
    /// Impulses to start the Newton method from, one world vector per contact (on B: normal and friction
    /// together), such as the last step's scaled to this one; `None` starts from the lagged normal impulses.
    /// They change how fast the answer is found, not the answer.
    pub warm: Option<&'a [Vector3<f64>]>,
}

impl<'a> VelocityProblem<'a> {
    /// The bodies and their contacts, friction by the cone, no joint rows.
    pub fn new(bodies: &'a [BodyState], contacts: &'a [Contact]) -> Self {
        VelocityProblem { bodies, contacts, lagged: None, bilateral: &[], warm: None }
    }

    /// Friction lagged on these normal impulses, one per contact.
    pub fn lagged(self, normals: &'a [f64]) -> Self {
        VelocityProblem { lagged: Some(normals), ..self }
    }

    /// Joint rows held in the same programs.
    pub fn bilateral(self, rows: &'a [BilateralRow]) -> Self {
        VelocityProblem { bilateral: rows, ..self }
    }

    /// The Newton method started from these impulses, one per contact.
    pub fn warm(self, impulses: &'a [Vector3<f64>]) -> Self {
        VelocityProblem { warm: Some(impulses), ..self }
    }

    pub(crate) fn check(&self) -> Result<(), ContactError> {
        if let Some(lagged) = self.lagged {
            if lagged.len() != self.contacts.len() {
                return Err(ContactError::invalid(
                    "lagged",
                    format!("needs one impulse per contact: {} for {} contacts", lagged.len(), self.contacts.len()),
                ));
            }
            if let Some(i) = lagged.iter().position(|p| !(p.is_finite() && *p >= 0.0)) {
                return Err(ContactError::invalid(
                    "lagged",
                    format!("impulse {i} must be finite and >= 0, got {}", lagged[i]),
                ));
            }
        }
        if let Some(warm) = self.warm {
            if warm.len() != self.contacts.len() {
                return Err(ContactError::invalid(
                    "warm",
                    format!("needs one impulse per contact: {} for {} contacts", warm.len(), self.contacts.len()),
                ));
            }
            if let Some(i) = warm.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
                return Err(ContactError::invalid("warm", format!("impulse {i} is not finite")));
            }
        }
        for (k, r) in self.bilateral.iter().enumerate() {
            let numbers = [r.lin, r.ang_a, r.ang_b].into_iter().flat_map(|v| [v.x, v.y, v.z]);
            let bound = match r.kind {
                BilateralKind::Motor { max_impulse } => max_impulse,
                _ => 0.0,
            };
            let mut numbers = numbers.chain([r.speed]).chain([bound]);
            let bodies = self.bodies.len();
            if r.a >= bodies || r.b >= bodies || r.a == r.b || !numbers.all(f64::is_finite) || bound < 0.0 {
                return Err(ContactError::invalid(
                    "bilateral",
                    format!("row {k} is not a finite row between two bodies"),
                ));
            }
        }
        Ok(())
    }
}
