//! The soft step's settings: substeps, sweeps, the contact and joint springs' stiffness and damping, push-out
//! speed, bounce threshold, threads and the gyroscopic switch.

use crate::error::ContactError;

/// Settings of the soft step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftSettings {
    /// Substeps per step (>= 1); 8 by default.
    pub substeps: usize,
    /// Sweeps of each pass per substep (>= 1); 2 by default.
    pub iterations: usize,
    /// Stiffness of contacts between moving bodies (Hz), capped at a quarter of the substep rate (beyond it the
    /// soft step loses its stability margin); contacts with static bodies get twice it. Infinity (the default)
    /// means the cap: the stiffest contact the substeps allow.
    pub contact_hertz: f64,
    /// Damping ratio of the contact springs (>= 0); 10 by default (overdamped: overlaps are pushed out without a
    /// bounce).
    pub damping_ratio: f64,
    /// Largest speed at which an overlap is pushed out (m/s); 3 by default.
    pub max_push_out: f64,
    /// Restitution applies to contacts closing faster than this (m/s); 0.1 by default.
    pub bounce_threshold: f64,
    /// Threads for the islands: 0 uses one per core, 1 stays on the calling thread.
    pub threads: usize,
    /// Stiffness of the pull that holds rigid joints together (Hz), capped at half the substep rate; infinity (the
    /// default) means the cap.
    pub joint_hertz: f64,
    /// Damping ratio of that pull (>= 0); 2 by default.
    pub joint_damping_ratio: f64,
    /// Whether a body's free motion takes Euler's gyroscopic term explicitly (as the velocity step's
    /// `StepSettings::gyroscopic`); off by default: the substeps carry angular momentum.
    pub gyroscopic: bool,
}

impl Default for SoftSettings {
    fn default() -> Self {
        SoftSettings {
            substeps: 8,
            iterations: 2,
            contact_hertz: f64::INFINITY,
            damping_ratio: 10.0,
            max_push_out: 3.0,
            bounce_threshold: 0.1,
            threads: 0,
            joint_hertz: f64::INFINITY,
            joint_damping_ratio: 2.0,
            gyroscopic: false,
        }
    }
}

impl SoftSettings {
    pub(crate) fn check(&self) -> Result<(), ContactError> {
        if self.substeps == 0 || self.substeps > 1000 {
            return Err(ContactError::invalid("substeps", format!("must be 1..=1000, got {}", self.substeps)));
        }
        if self.iterations == 0 || self.iterations > 1000 {
            return Err(ContactError::invalid("iterations", format!("must be 1..=1000, got {}", self.iterations)));
        }
        let positive = |name: &'static str, v: f64, infinite_ok: bool| {
            if v > 0.0 && (v.is_finite() || infinite_ok) {
                Ok(())
            } else {
                Err(ContactError::invalid(name, format!("must be > 0, got {v}")))
            }
        };
        positive("contact_hertz", self.contact_hertz, true)?;
        positive("max_push_out", self.max_push_out, false)?;
        positive("joint_hertz", self.joint_hertz, true)?;
        if !(self.joint_damping_ratio >= 0.0 && self.joint_damping_ratio.is_finite()) {
            return Err(ContactError::invalid(
                "joint_damping_ratio",
                format!("must be >= 0, got {}", self.joint_damping_ratio),
            ));
        }
        if !(self.damping_ratio >= 0.0 && self.damping_ratio.is_finite()) {
            return Err(ContactError::invalid("damping_ratio", format!("must be >= 0, got {}", self.damping_ratio)));
        }
        if !(self.bounce_threshold >= 0.0 && self.bounce_threshold.is_finite()) {
            return Err(ContactError::invalid(
                "bounce_threshold",
                format!("must be >= 0, got {}", self.bounce_threshold),
            ));
        }
        Ok(())
    }
}
