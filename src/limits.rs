//! The ranges of the values a world accepts, checked where each value enters. They are wide enough for anything a
//! scene of particles and bodies needs (a mass of 1e-30 to 1e30 kg, a scene within 1e12 m of the origin, speeds up
//! to 1e12 m/s) and narrow enough that no product the dynamics forms (momentum, energy, inertia times spin) can
//! overflow: with these limits m v^2 stays below 1e54 and a NaN cannot come from the input alone.

use crate::error::WorldError;
use nalgebra::{Matrix3, Vector3};

/// Smallest and largest mass (kg).
pub const MASS: (f64, f64) = (1e-30, 1e30);
/// Largest coordinate of a position, anchor or point (m).
pub const COORDINATE: f64 = 1e12;
/// Largest speed (m/s) and angular speed (rad/s).
pub const SPEED: f64 = 1e12;
/// Largest force (N) and torque (N m).
pub const FORCE: f64 = 1e30;
/// Largest spring stiffness (N/m), damping (N s/m) and particle restoring stiffness.
pub const STIFFNESS: f64 = 1e20;
/// Largest gravity (m/s^2).
pub const GRAVITY: f64 = 1e12;
/// Largest time and time span (s).
pub const TIME: f64 = 1e12;
/// Largest eigenvalue of an inertia tensor (kg m^2), and the smallest as a fraction of the largest.
pub const INERTIA: f64 = 1e54;

/// A finite scalar in [lo, hi].
pub(crate) fn in_range(name: &'static str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<f64, WorldError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(WorldError::invalid(name, format!("must be finite and within [{lo:e}, {hi:e}] {unit}, got {v:e}")))
    }
}

/// A finite scalar in (0, hi].
pub(crate) fn positive(name: &'static str, v: f64, hi: f64, unit: &str) -> Result<f64, WorldError> {
    if v.is_finite() && v > 0.0 && v <= hi {
        Ok(v)
    } else {
        Err(WorldError::invalid(name, format!("must be finite, > 0 and at most {hi:e} {unit}, got {v:e}")))
    }
}

/// A finite scalar in [0, hi].
pub(crate) fn non_negative(name: &'static str, v: f64, hi: f64, unit: &str) -> Result<f64, WorldError> {
    in_range(name, v, 0.0, hi, unit)
}

/// A vector whose components are finite and at most `hi` in size.
pub(crate) fn vector(name: &'static str, v: &Vector3<f64>, hi: f64, unit: &str) -> Result<(), WorldError> {
    if v.iter().all(|c| c.is_finite() && c.abs() <= hi) {
        Ok(())
    } else {
        Err(WorldError::invalid(
            name,
            format!(
                "components must be finite and at most {hi:e} {unit} in size, got [{:e}, {:e}, {:e}]",
                v.x, v.y, v.z
            ),
        ))
    }
}

/// A mass in range; `name` is the argument it came from (mass or density).
pub(crate) fn mass(name: &'static str, m: f64) -> Result<f64, WorldError> {
    if m.is_finite() && m >= MASS.0 && m <= MASS.1 {
        Ok(m)
    } else {
        Err(WorldError::invalid(name, format!("gives a mass of {m:e} kg, outside [{:e}, {:e}] kg", MASS.0, MASS.1)))
    }
}

/// An inertia tensor whose eigenvalues are at most `INERTIA` (its other checks are the body's).
pub(crate) fn inertia(name: &'static str, i: &Matrix3<f64>) -> Result<(), WorldError> {
    if i.iter().all(|v| v.is_finite() && v.abs() <= INERTIA) {
        Ok(())
    } else {
        Err(WorldError::invalid(name, format!("gives an inertia tensor with entries above {INERTIA:e} kg m^2: {i}")))
    }
}
