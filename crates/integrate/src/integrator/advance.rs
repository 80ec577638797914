//! The driver's advance: from the current time to a target time under the settings' step control (fixed or
//! adaptive), delivering states at requested output times, showing each accepted step to an event detector, and
//! restoring the starting state if anything fails.

use super::Integrator;
use crate::error::OdeError;
use crate::events::{Advance, StepView};
use crate::point::max_norm;
use crate::settings::StepControl;
use crate::system::OdeSystem;
use std::time::Instant;

/// The detector of calls that watch for no events.
fn no_events<S: OdeSystem + ?Sized>(_: &mut StepView<'_, S>) -> Result<Option<f64>, OdeError> {
    Ok(None)
}

/// Errors that a smaller step may cure: an adaptive control rejects the step and tries a quarter of it.
fn recoverable(e: &OdeError) -> bool {
    matches!(
        e,
        OdeError::NonFinite { .. }
            | OdeError::Divergence { .. }
            | OdeError::NewtonFailure { .. }
            | OdeError::SingularMatrix { .. }
            | OdeError::LinearSolve { .. }
    )
}

impl<S: OdeSystem + ?Sized> Integrator<S> {
    /// Advances to `t_end` exactly, calling `on_save(sys, t, y)` for every time of `save_at` (ascending, within
    /// [current time, t_end]); the system is lent to it read-only, to compute derived quantities. On error the time,
    /// state and proposed step are those before the call.
    pub fn advance_to(
        &mut self,
        sys: &mut S,
        t_end: f64,
        save_at: &[f64],
        on_save: impl FnMut(&S, f64, &[f64]),
    ) -> Result<(), OdeError> {
        self.advance(sys, t_end, t_end, save_at, on_save, &mut no_events).map(|_| ())
    }

    /// Like [`advance_to`](Integrator::advance_to), but returns as soon as the integration has passed `pause_at`
    /// (never going beyond `t_end`), without shortening a step to land on it; returns how many of `save_at` were
    /// delivered (those up to the time reached). Calling it again with the rest continues the same integration,
    /// so a long run can be reported on in chunks without extra steps.
    pub fn advance_until(
        &mut self,
        sys: &mut S,
        t_end: f64,
        pause_at: f64,
        save_at: &[f64],
        on_save: impl FnMut(&S, f64, &[f64]),
    ) -> Result<usize, OdeError> {
        self.advance(sys, t_end, pause_at.min(t_end), save_at, on_save, &mut no_events).map(|a| a.delivered)
    }

    /// Like [`advance_until`](Integrator::advance_until), showing every accepted step to `detect`. When it returns
    /// the time of an event within the step, the step is cut there (the state at the event comes from the method's
    /// dense output, or from a fresh step), the outputs up to it are delivered, the method's histories are dropped
    /// and the advance returns with the event's time. On error the time, state and proposed step are those before
    /// the call.
    pub fn advance_with_events(
        &mut self,
        sys: &mut S,
        t_end: f64,
        pause_at: f64,
        save_at: &[f64],
        on_save: impl FnMut(&S, f64, &[f64]),
        mut detect: impl FnMut(&mut StepView<'_, S>) -> Result<Option<f64>, OdeError>,
    ) -> Result<Advance, OdeError> {
        self.advance(sys, t_end, pause_at.min(t_end), save_at, on_save, &mut detect)
    }

    fn advance(
        &mut self,
        sys: &mut S,
        t_end: f64,
        pause_at: f64,
        save_at: &[f64],
        mut on_save: impl FnMut(&S, f64, &[f64]),
        detect: &mut impl FnMut(&mut StepView<'_, S>) -> Result<Option<f64>, OdeError>,
    ) -> Result<Advance, OdeError> {
        let t0 = self.cur.t;
        if !(t_end.is_finite() && t_end >= t0) {
            return Err(OdeError::invalid(
                "t_end",
                format!("must be finite and >= the current time {t0}, got {t_end}"),
            ));
        }
        if sys.dim() != self.cur.y.len() {
            return Err(OdeError::invalid(
                "system",
                format!("dimension changed from {} to {}", self.cur.y.len(), sys.dim()),
            ));
        }
        if let Some(bad) = save_at.windows(2).position(|w| !(w[0] <= w[1])) {
            return Err(OdeError::invalid("save_at", format!("must be ascending (entry {} is not)", bad + 1)));
        }
        if let Some(&s) = save_at.iter().find(|&&s| !(s >= t0 && s <= t_end)) {
            return Err(OdeError::invalid("save_at", format!("time {s} is outside [{t0}, {t_end}]")));
        }
        self.backup.copy_from_slice(&self.cur.y);
        let h0 = self.h;
        let clock = Instant::now();
        let result = match self.settings.control {
            StepControl::Fixed { dt } => self.run_fixed(sys, dt, t_end, pause_at, save_at, &mut on_save, detect),
            _ => self.run_adaptive(sys, t_end, pause_at, save_at, &mut on_save, detect),
        };
        self.ctx.report.wall_seconds += clock.elapsed().as_secs_f64();
        if result.is_err() {
            self.cur.y.copy_from_slice(&self.backup);
            self.cur.renew(t0);
            self.stepper.reset();
            self.h = h0;
            self.last_rejected = false;
        }
        result
    }

    /// Checks the state just computed: finite, and within the divergence limit (one comparison per component;
    /// NaN fails it too).
    fn check_next(&self, h: f64) -> Result<(), OdeError> {
        let limit = self.settings.divergence_limit;
        if self.next.y.iter().all(|v| v.abs() <= limit) {
            return Ok(());
        }
        if let Some(i) = self.next.y.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFinite { t: self.next.t, what: "state", index: i });
        }
        Err(OdeError::Divergence { t: self.next.t, norm: max_norm(&self.next.y), limit, h })
    }

    /// Books an accepted step, then lets the system project the new state (a changed state loses its cached
    /// derivative).
    fn accept(&mut self, sys: &mut S, h: f64, local: Option<f64>) {
        self.ctx.report.record_step(h, local);
        self.stepper.accepted(&self.cur, &self.next, &mut self.ctx);
        self.last_step = Some(h);
        if let Some(log) = &mut self.step_log {
            log.push((self.next.t, h));
        }
        if sys.project(self.next.t, &mut self.next.y) {
            let t = self.next.t;
            self.next.renew(t);
        }
    }

    /// Fixed steps; every save is a stop, and the run pauses at the first stop at or past `pause_at`. Returns the
    /// number of saves delivered.
    #[allow(clippy::too_many_arguments)]
    fn run_fixed(
        &mut self,
        sys: &mut S,
        dt: f64,
        t_end: f64,
        pause_at: f64,
        saves: &[f64],
        on_save: &mut impl FnMut(&S, f64, &[f64]),
        detect: &mut impl FnMut(&mut StepView<'_, S>) -> Result<Option<f64>, OdeError>,
    ) -> Result<Advance, OdeError> {
        let mut si = 0;
        let mut budget = self.settings.max_steps;
        loop {
            while si < saves.len() && saves[si] <= self.cur.t {
                on_save(sys, saves[si], &self.cur.y);
                si += 1;
            }
            if self.cur.t >= pause_at {
                return Ok(Advance { delivered: si, event: None });
            }
            let stop = if si < saves.len() { saves[si] } else { t_end };
            let span = stop - self.cur.t;
            let steps = ((span / dt) * (1.0 - 1e-12)).ceil().max(1.0);
            if steps > budget as f64 {
                return Err(OdeError::TooManySteps { t: self.cur.t, max_steps: self.settings.max_steps });
            }
            let steps = steps as usize;
            budget -= steps;
            let (start, h) = (self.cur.t, span / steps as f64);
            for k in 1..=steps {
                self.next.renew(if k == steps { stop } else { start + k as f64 * h });
                let est = self.stepper.step(sys, &mut self.cur, h, &mut self.next, &mut self.ctx)?;
                self.check_next(h)?;
                self.accept(sys, h, est.local);
                if let Some(tc) = self.detect(sys, detect)? {
                    self.cut_at(sys, tc)?;
                    while si < saves.len() && saves[si] <= tc {
                        on_save(sys, saves[si], &self.cur.y);
                        si += 1;
                    }
                    return Ok(Advance { delivered: si, event: Some(tc) });
                }
                std::mem::swap(&mut self.cur, &mut self.next);
            }
        }
    }

    /// Adaptive steps toward `t_end` (the only hard stop besides saves without dense output), pausing once past
    /// `pause_at`. Returns the number of saves delivered.
    fn run_adaptive(
        &mut self,
        sys: &mut S,
        t_end: f64,
        pause_at: f64,
        saves: &[f64],
        on_save: &mut impl FnMut(&S, f64, &[f64]),
        detect: &mut impl FnMut(&mut StepView<'_, S>) -> Result<Option<f64>, OdeError>,
    ) -> Result<Advance, OdeError> {
        let dense = self.settings.dense_output
            && self.stepper.has_dense_output()
            && !matches!(self.settings.control, StepControl::StepDoubling { .. });
        let mut si = 0;
        while si < saves.len() && saves[si] <= self.cur.t {
            on_save(sys, saves[si], &self.cur.y);
            si += 1;
        }
        if self.cur.t >= pause_at {
            return Ok(Advance { delivered: si, event: None });
        }
        if self.h.is_none() {
            let h = self.initial_step(sys)?;
            self.h = Some(h);
        }
        let mut attempts = 0;
        while self.cur.t < pause_at {
            attempts += 1;
            if attempts > self.settings.max_steps {
                return Err(OdeError::TooManySteps { t: self.cur.t, max_steps: self.settings.max_steps });
            }
            let stop = if dense || si >= saves.len() { t_end } else { saves[si] };
            let wanted = match self.stepper.own_step(sys, &mut self.cur, &mut self.ctx)? {
                Some(h) => h,
                None => self.h.expect("set above"),
            }
            .min(self.settings.max_step);
            let hits = self.cur.t + 1.01 * wanted >= stop;
            let h = if hits { stop - self.cur.t } else { wanted };
            let floor = self.settings.min_step.max(16.0 * f64::EPSILON * self.cur.t.abs());
            if h < floor && !hits {
                return Err(OdeError::StepTooSmall { t: self.cur.t, h, min_step: floor });
            }
            let first = self.last_step.is_none();
            self.next.renew(if hits { stop } else { self.cur.t + h });
            let attempt = self
                .stepper
                .step(sys, &mut self.cur, h, &mut self.next, &mut self.ctx)
                .and_then(|est| self.check_next(h).map(|_| est));
            let est = match attempt {
                Ok(est) if est.scaled.is_none_or(|e| !e.is_nan()) => est,
                Ok(_) => {
                    self.retry_smaller(
                        h,
                        floor,
                        OdeError::NonFinite { t: self.cur.t, what: "error estimate", index: 0 },
                    )?;
                    continue;
                }
                Err(e) if recoverable(&e) => {
                    self.retry_smaller(h, floor, e)?;
                    continue;
                }
                Err(e) => return Err(e),
            };
            let err = est.scaled.unwrap_or(0.0);
            if err <= 1.0 {
                self.accept(sys, h, est.local);
                let event = self.detect(sys, detect)?;
                let t_new = event.unwrap_or(self.next.t);
                if let Some(tc) = event {
                    // outputs before the event from the full step's interpolant, then the step is cut at tc
                    while si < saves.len() && saves[si] < tc {
                        let s = saves[si];
                        if dense {
                            self.stepper.dense(&self.cur, &self.next, (s - self.cur.t) / h, &mut self.dense_buf);
                            on_save(sys, s, &self.dense_buf);
                        } else {
                            let y = self.view(sys).state_at(s)?;
                            on_save(sys, s, &y);
                        }
                        si += 1;
                    }
                    self.cut_at(sys, tc)?;
                    while si < saves.len() && saves[si] <= tc {
                        on_save(sys, saves[si], &self.cur.y);
                        si += 1;
                    }
                    let proposal = self.controller.accepted(est.scaled, est.safety, h, self.last_rejected);
                    self.h = Some(self.stepper.prefer_step(h, proposal));
                    self.last_rejected = false;
                    return Ok(Advance { delivered: si, event: Some(tc) });
                }
                while si < saves.len() && saves[si] <= t_new {
                    let s = saves[si];
                    if s == t_new || !dense {
                        on_save(sys, s, &self.next.y);
                    } else {
                        let theta = (s - self.cur.t) / h;
                        self.stepper.dense(&self.cur, &self.next, theta, &mut self.dense_buf);
                        on_save(sys, s, &self.dense_buf);
                    }
                    si += 1;
                }
                std::mem::swap(&mut self.cur, &mut self.next);
                let proposal = self.controller.accepted(est.scaled, est.safety, h, self.last_rejected);
                let proposal = self.stepper.prefer_step(h, proposal);
                self.h = Some(if hits { proposal.max(wanted) } else { proposal });
                self.last_rejected = false;
            } else {
                self.ctx.report.rejected += 1;
                self.stepper.rejected();
                self.h = Some(self.controller.rejected(err, est.safety, h, first));
                self.last_rejected = true;
            }
        }
        Ok(Advance { delivered: si, event: None })
    }

    /// Rejects a step that failed in a way a smaller step may cure; gives up with `cause` below the floor.
    fn retry_smaller(&mut self, h: f64, floor: f64, cause: OdeError) -> Result<(), OdeError> {
        self.ctx.report.rejected += 1;
        self.last_rejected = true;
        self.stepper.rejected();
        let smaller = self.stepper.retry_factor().unwrap_or(0.25) * h;
        if smaller < floor {
            return Err(cause);
        }
        self.h = Some(smaller);
        Ok(())
    }
}
