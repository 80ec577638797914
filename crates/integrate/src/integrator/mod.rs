//! The driver: a running integration (`Integrator`), built for a system, settings and a starting state, read (time,
//! state, report, step log) and given a new state. Its advance is `advance.rs`, the first adaptive step
//! `first_step.rs`, its side of events `events.rs`, and its memory taken and given back `memory.rs`.

mod advance;
mod events;
mod first_step;
mod memory;

use crate::controller::Controller;
use crate::error::OdeError;
use crate::point::Point;
use crate::report::Report;
use crate::settings::Settings;
use crate::steppers::{self, Ctx, Stepper};
use crate::system::OdeSystem;

/// A running integration that can be advanced repeatedly (as a world advances frame by frame). It keeps the
/// method's state between calls: the last step size, first-same-as-last derivatives, multistep histories.
pub struct Integrator<S: OdeSystem + ?Sized> {
    pub(crate) settings: Settings,
    pub(crate) stepper: Box<dyn Stepper<S> + Send>,
    pub(crate) controller: Controller,
    pub(crate) ctx: Ctx,
    pub(crate) cur: Point,
    pub(crate) next: Point,
    pub(crate) h: Option<f64>,
    pub(crate) last_step: Option<f64>,
    pub(crate) step_log: Option<Vec<(f64, f64)>>,
    pub(crate) last_rejected: bool,
    pub(crate) dense_buf: Vec<f64>,
    pub(crate) backup: Vec<f64>,
}

impl<S: OdeSystem + ?Sized> Clone for Integrator<S> {
    /// A copy of the whole integration: state, step, controller, the method's caches and histories. Continuing the
    /// copy gives the same numbers as continuing the original.
    fn clone(&self) -> Self {
        Integrator {
            settings: self.settings.clone(),
            stepper: self.stepper.clone_box(),
            controller: self.controller.clone(),
            ctx: self.ctx.clone(),
            cur: self.cur.clone(),
            next: self.next.clone(),
            h: self.h,
            last_step: self.last_step,
            step_log: self.step_log.clone(),
            last_rejected: self.last_rejected,
            dense_buf: self.dense_buf.clone(),
            backup: self.backup.clone(),
        }
    }
}

pub(crate) fn check_initial(dim: usize, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
    if !t0.is_finite() {
        return Err(OdeError::invalid("t0", format!("must be finite, got {t0}")));
    }
    if y0.len() != dim {
        return Err(OdeError::invalid("y0", format!("has length {}, the system has dimension {dim}", y0.len())));
    }
    if let Some(i) = y0.iter().position(|v| !v.is_finite()) {
        return Err(OdeError::invalid("y0", format!("component {i} is {}", y0[i])));
    }
    Ok(())
}

impl<S: OdeSystem + ?Sized> Integrator<S> {
    /// Validates the settings against the system and the initial state, and prepares the method.
    pub fn new(sys: &mut S, settings: Settings, t0: f64, y0: &[f64]) -> Result<Self, OdeError> {
        settings.validate(sys)?;
        check_initial(sys.dim(), t0, y0)?;
        let (rtol, atol) = settings.weights();
        let stepper = steppers::build(sys, &settings)?;
        Ok(Integrator {
            controller: Controller::for_settings(&settings),
            ctx: Ctx { report: Report::new(settings.method.name()), rtol, atol, newton: settings.newton },
            stepper,
            cur: Point::new(t0, y0),
            next: Point::new(t0, y0),
            h: None,
            last_step: None,
            step_log: None,
            last_rejected: false,
            dense_buf: vec![0.0; y0.len()],
            backup: y0.to_vec(),
            settings,
        })
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.cur.t
    }

    /// Current state.
    pub fn state(&self) -> &[f64] {
        &self.cur.y
    }

    /// What the integration has cost so far.
    pub fn report(&self) -> &Report {
        &self.ctx.report
    }

    /// The settings it runs with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Sets the most steps (taken or rejected) one advance may take; callers that share one budget across several
    /// advances set what is left of it before each (0 is read as 1).
    pub fn set_max_steps(&mut self, max_steps: usize) {
        self.settings.max_steps = max_steps.max(1);
    }

    /// Sets the size past which a state component is divergence (callers that keep one limit across integrators
    /// they rebuild).
    pub fn set_divergence_limit(&mut self, limit: f64) {
        self.settings.divergence_limit = limit;
    }

    /// Returns the report so far and starts a new one (for callers that report per call).
    pub fn take_report(&mut self) -> Report {
        std::mem::replace(&mut self.ctx.report, Report::new(self.settings.method.name()))
    }

    /// Starts or stops recording (time, size) of every accepted step.
    pub fn log_steps(&mut self, on: bool) {
        self.step_log = on.then(Vec::new);
    }

    /// The (time at the end of the step, step size) pairs recorded since the last call.
    pub fn take_step_log(&mut self) -> Vec<(f64, f64)> {
        self.step_log.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// The size of the last accepted step (None before the first).
    pub fn last_step(&self) -> Option<f64> {
        self.last_step
    }

    /// The step the adaptive control proposes next (None before the first adaptive step).
    pub fn proposed_step(&self) -> Option<f64> {
        self.h
    }

    /// Replaces the state (after an impulse, say). Histories and cached derivatives are dropped; the proposed
    /// step is kept.
    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), OdeError> {
        check_initial(self.cur.y.len(), t, y)?;
        self.cur.y.copy_from_slice(y);
        self.cur.renew(t);
        self.stepper.reset();
        Ok(())
    }
}
