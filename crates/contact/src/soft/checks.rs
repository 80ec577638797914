//! A soft step's input checked before it is solved: joints, springs and bodies in range and finite.

use super::SoftSpring;
use crate::body::BodyState;
use crate::error::ContactError;
use crate::joint::{JointConstraint, JointImpulse};

/// Checks each joint against the bodies: indices in range, two different bodies, one of them moving, every number
/// finite; and the windows, one a joint (or none), each finite and >= 0.
pub(super) fn check_joints(
    bodies: &[BodyState],
    joints: &[JointConstraint],
    warm: &[JointImpulse],
    windows: &[f64],
) -> Result<(), ContactError> {
    check_windows("windows", windows, joints.len())?;
    if warm.len() != joints.len() {
        return Err(ContactError::invalid(
            "joint_warm",
            format!("has {} entries for {} joints", warm.len(), joints.len()),
        ));
    }
    for (k, j) in joints.iter().enumerate() {
        if j.a >= bodies.len() || j.b >= bodies.len() || j.a == j.b {
            return Err(ContactError::invalid("joints", format!("joint {k} joins bodies {} and {}", j.a, j.b)));
        }
        if !(bodies[j.a].is_dynamic() || bodies[j.b].is_dynamic()) {
            return Err(ContactError::invalid("joints", format!("joint {k} joins two bodies that do not move")));
        }
        let f = &j.frame;
        let numbers =
            [f.ra, f.rb, f.axis, f.across[0], f.across[1], f.axis_b].into_iter().flat_map(|v| [v.x, v.y, v.z]);
        if !(numbers.chain(f.error.coords.iter().copied()).all(f64::is_finite)
            && warm[k].0.iter().all(|p| p.is_finite()))
        {
            return Err(ContactError::invalid("joints", format!("joint {k} has a non-finite number")));
        }
    }
    Ok(())
}

/// Checks each spring against the bodies: indices in range, two different bodies, one of them moving, every
/// number finite, stiffness, damping and rest length not negative.
pub(super) fn check_springs(bodies: &[BodyState], springs: &[SoftSpring]) -> Result<(), ContactError> {
    for (k, s) in springs.iter().enumerate() {
        if s.a >= bodies.len() || s.b >= bodies.len() || s.a == s.b {
            return Err(ContactError::invalid("springs", format!("spring {k} joins bodies {} and {}", s.a, s.b)));
        }
        if !(bodies[s.a].is_dynamic() || bodies[s.b].is_dynamic()) {
            return Err(ContactError::invalid("springs", format!("spring {k} joins two bodies that do not move")));
        }
        if !s.is_valid() {
            return Err(ContactError::invalid(
                "springs",
                format!("spring {k} has a non-finite or negative stiffness, damping, rest length or arm"),
            ));
        }
    }
    Ok(())
}

/// Checks the bodies' numbers: finite, inverse masses not negative (their inertias are taken as given: the caller
/// keeps them positive definite).
pub(super) fn check_bodies(bodies: &[BodyState]) -> Result<(), ContactError> {
    // one sum of each body's numbers: finite only if each is
    for (i, b) in bodies.iter().enumerate() {
        let sum =
            [b.position.coords, b.velocity, b.angular_velocity, b.force, b.torque].iter().map(|v| v.sum()).sum::<f64>()
                + b.inertia.sum()
                + b.inv_inertia.sum()
                + b.inv_mass;
        if !(b.inv_mass >= 0.0 && sum.is_finite()) {
            return Err(ContactError::invalid("bodies", format!("body {i} has a non-finite number or negative mass")));
        }
    }
    Ok(())
}

/// Checks windows `name` (one for each of `count`, or none): each finite and >= 0.
pub(super) fn check_windows(name: &'static str, windows: &[f64], count: usize) -> Result<(), ContactError> {
    if !(windows.is_empty() || windows.len() == count) {
        return Err(ContactError::invalid(name, format!("has {} entries for {count}", windows.len())));
    }
    if let Some((k, w)) = windows.iter().enumerate().find(|(_, w)| !(w.is_finite() && **w >= 0.0)) {
        return Err(ContactError::invalid(name, format!("entry {k} is {w}: a window must be finite and >= 0")));
    }
    Ok(())
}
