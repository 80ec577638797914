//! The chapter's classification of a contact by its relative normal velocity: separating (it opens by itself),
//! resting (it needs a force), colliding (it needs an impulse), with a tolerance that scales with the scene.

use crate::body::BodyState;
use crate::contact::Contact;

/// What a contact needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactClass {
    /// v_rel > tolerance: the bodies are parting; nothing to do.
    Separating,
    /// |v_rel| <= tolerance: the bodies stay in contact; a resting force may be needed.
    Resting,
    /// v_rel < -tolerance: the bodies are closing; an impulse is needed.
    Colliding,
}

/// The resting-velocity tolerance of a scene of size `length` under gravity `g`: 1e-3 sqrt(2 g L), a thousandth of
/// the speed of a fall through the whole scene (a bounce slower than that rises less than 1e-6 L). Without gravity
/// or size, 1e-9 m/s.
pub fn velocity_tolerance(length: f64, gravity: f64) -> f64 {
    let v = (2.0 * gravity.abs() * length.abs()).sqrt();
    if v.is_finite() && v > 0.0 {
        1e-3 * v
    } else {
        1e-9
    }
}

/// The class of contact `c` at velocity tolerance `tolerance`.
pub fn classify(bodies: &[BodyState], c: &Contact, tolerance: f64) -> ContactClass {
    let v = c.relative_normal_velocity(bodies);
    if v > tolerance {
        ContactClass::Separating
    } else if v < -tolerance {
        ContactClass::Colliding
    } else {
        ContactClass::Resting
    }
}
