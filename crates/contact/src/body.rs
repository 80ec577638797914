//! The state of a body as contact response sees it: inverse mass and inertia (zero for a static body, zero inertia
//! for a particle), centre of mass, velocities, and the applied force and torque.

use crate::error::ContactError;
use nalgebra::{Matrix3, Point3, Vector3};

/// One body (or particle) of a contact problem, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// 1 / mass; 0 for a static or kinematic body.
    pub inv_mass: f64,
    /// Inertia tensor about the centre of mass (world axes); zero for a particle or a static body.
    pub inertia: Matrix3<f64>,
    /// Its inverse; zero for a particle or a static body.
    pub inv_inertia: Matrix3<f64>,
    /// Centre of mass.
    pub position: Point3<f64>,
    /// Velocity of the centre of mass.
    pub velocity: Vector3<f64>,
    /// Angular velocity.
    pub angular_velocity: Vector3<f64>,
    /// Applied force (gravity included), for resting-contact forces and time stepping.
    pub force: Vector3<f64>,
    /// Applied torque about the centre of mass.
    pub torque: Vector3<f64>,
}

impl BodyState {
    /// A static body at `position` (infinite mass; it may still move, as a kinematic body, through `velocity`).
    pub fn fixed(position: Point3<f64>) -> BodyState {
        BodyState {
            inv_mass: 0.0,
            inertia: Matrix3::zeros(),
            inv_inertia: Matrix3::zeros(),
            position,
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
        }
    }

    /// A particle: mass > 0, no rotation.
    pub fn particle(mass: f64, position: Point3<f64>, velocity: Vector3<f64>) -> BodyState {
        BodyState { inv_mass: 1.0 / mass, velocity, ..BodyState::fixed(position) }
    }

    /// A rigid body of `mass` and world inertia tensor `inertia` (its inverse is computed; a singular tensor gives
    /// a zero inverse, which `check` refuses).
    pub fn rigid(mass: f64, inertia: Matrix3<f64>, position: Point3<f64>) -> BodyState {
        let inv_inertia = inertia.try_inverse().unwrap_or_else(Matrix3::zeros);
        BodyState { inv_mass: 1.0 / mass, inertia, inv_inertia, ..BodyState::fixed(position) }
    }

    /// Whether the body moves in response to contact (finite mass).
    pub fn is_dynamic(&self) -> bool {
        self.inv_mass > 0.0
    }

    /// Whether the body turns in response to contact.
    pub fn rotates(&self) -> bool {
        self.inv_inertia != Matrix3::zeros()
    }

    /// Velocity of the body's material point at `p`: v + w x (p - x).
    pub fn point_velocity(&self, p: &Point3<f64>) -> Vector3<f64> {
        self.velocity + self.angular_velocity.cross(&(p - self.position))
    }

    /// Acceleration of the material point at `p` under the applied force and torque alone:
    /// F/m + w' x r + w x (w x r), with w' = I^-1 (tau - w x I w) (Euler's equations).
    pub fn free_point_acceleration(&self, p: &Point3<f64>) -> Vector3<f64> {
        let r = p - self.position;
        let w = self.angular_velocity;
        let w_dot = self.free_angular_acceleration(true);
        self.force * self.inv_mass + w_dot.cross(&r) + w.cross(&w.cross(&r))
    }

    /// The angular acceleration under the applied torque alone: I^-1 (tau - w x I w) by Euler's equations with the
    /// `gyroscopic` term, I^-1 tau without it (the rate of a time step that carries angular momentum, L + h tau).
    pub fn free_angular_acceleration(&self, gyroscopic: bool) -> Vector3<f64> {
        let w = self.angular_velocity;
        if gyroscopic {
            self.inv_inertia * (self.torque - w.cross(&(self.inertia * w)))
        } else {
            self.inv_inertia * self.torque
        }
    }

    /// Checks every number is finite, the inverse mass >= 0, and the inertia tensors symmetric, with a dynamic
    /// rotating body's inertia positive definite; `index` names the body in the error.
    pub fn check(&self, index: usize) -> Result<(), ContactError> {
        let finite = |m: &[f64]| m.iter().all(|v| v.is_finite());
        let all = [
            self.inertia.as_slice(),
            self.inv_inertia.as_slice(),
            self.position.coords.as_slice(),
            self.velocity.as_slice(),
            self.angular_velocity.as_slice(),
            self.force.as_slice(),
            self.torque.as_slice(),
        ];
        if !(self.inv_mass.is_finite() && all.iter().all(|m| finite(m))) {
            return Err(ContactError::invalid("bodies", format!("body {index} has a non-finite number")));
        }
        if self.inv_mass < 0.0 {
            return Err(ContactError::invalid("bodies", format!("body {index} has a negative inverse mass")));
        }
        for (name, m) in [("inertia", &self.inertia), ("inv_inertia", &self.inv_inertia)] {
            if (m - m.transpose()).amax() > 1e-9 * m.amax() {
                return Err(ContactError::invalid("bodies", format!("body {index}: {name} is not symmetric")));
            }
        }
        if self.rotates() {
            let check = self.inertia * self.inv_inertia - Matrix3::identity();
            let positive = self.inertia.cholesky().is_some();
            if !positive || check.amax() > 1e-6 {
                return Err(ContactError::invalid(
                    "bodies",
                    format!("body {index}: inertia must be positive definite with inv_inertia its inverse"),
                ));
            }
        }
        Ok(())
    }
}
