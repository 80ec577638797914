//! Events inside a step: after each accepted step the driver can show it to a detector, which may ask for the
//! state at any time within the step and answer with the time of an event (a collision, say); the driver then ends
//! the step there, so the caller can change the state (apply an impulse) and continue. The driver's side is
//! `integrator/events.rs`.

use crate::error::OdeError;
use crate::point::Point;
use crate::steppers::{Ctx, Stepper};
use crate::system::OdeSystem;

/// An accepted step from (t0, y0) to (t1, y1), offered to an event detector.
pub struct StepView<'a, S: OdeSystem + ?Sized> {
    pub(crate) sys: &'a mut S,
    pub(crate) stepper: &'a mut (dyn Stepper<S> + Send),
    pub(crate) ctx: &'a mut Ctx,
    pub(crate) from: &'a Point,
    pub(crate) to: &'a Point,
    pub(crate) dense: bool,
}

impl<S: OdeSystem + ?Sized> StepView<'_, S> {
    /// Start of the step.
    pub fn t0(&self) -> f64 {
        self.from.t
    }

    /// End of the step.
    pub fn t1(&self) -> f64 {
        self.to.t
    }

    /// State at the start.
    pub fn y0(&self) -> &[f64] {
        &self.from.y
    }

    /// State at the end.
    pub fn y1(&self) -> &[f64] {
        &self.to.y
    }

    /// The system (read-only).
    pub fn system(&self) -> &S {
        self.sys
    }

    /// The system, to evaluate it at states of the step (its right-hand side, say).
    pub fn system_mut(&mut self) -> &mut S {
        self.sys
    }

    /// Whether `state_at` interpolates (dense output) rather than stepping afresh.
    pub fn interpolates(&self) -> bool {
        self.dense
    }

    /// The state at time t in [t0, t1]: the method's dense output where it has one, otherwise a fresh step of the
    /// same method from the start of the step (counted in the report).
    pub fn state_at(&mut self, t: f64) -> Result<Vec<f64>, OdeError> {
        let (t0, t1) = (self.from.t, self.to.t);
        if !(t >= t0 && t <= t1) {
            return Err(OdeError::invalid("t", format!("{t} is outside the step [{t0}, {t1}]")));
        }
        if t == t1 {
            return Ok(self.to.y.clone());
        }
        if t == t0 {
            return Ok(self.from.y.clone());
        }
        let mut out = vec![0.0; self.from.y.len()];
        if self.dense {
            self.stepper.dense(self.from, self.to, (t - t0) / (t1 - t0), &mut out);
            return Ok(out);
        }
        let mut from = self.from.clone();
        let mut to = Point::new(t, &from.y);
        to.renew(t);
        self.stepper.step(self.sys, &mut from, t - t0, &mut to, self.ctx)?;
        Ok(to.y)
    }
}

/// How far an event-aware advance got.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// How many of the requested output times were delivered.
    pub delivered: usize,
    /// The time of the event that ended the advance early (the state is there now), if any.
    pub event: Option<f64>,
}
