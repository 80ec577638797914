//! The first step of an adaptive integration: the settings' value, step doubling's `dt`, or Hairer's estimate.

use super::Integrator;
use crate::error::OdeError;
use crate::point::eval;
use crate::settings::StepControl;
use crate::system::OdeSystem;

/// The driver's first step size.
impl<S: OdeSystem + ?Sized> Integrator<S> {
    /// The first adaptive step: the settings' value, step doubling's `dt`, or Hairer's estimate from the sizes
    /// of y, f and f' (one extra evaluation).
    pub(crate) fn initial_step(&mut self, sys: &mut S) -> Result<f64, OdeError> {
        if let Some(h) = self.settings.initial_step {
            return Ok(h.min(self.settings.max_step));
        }
        match self.settings.control {
            StepControl::StepDoubling { dt, .. } => return Ok(dt.min(self.settings.max_step)),
            StepControl::Fixed { dt } => return Ok(dt),
            StepControl::Derivative { .. } => return Ok(self.settings.max_step.min(1.0)),
            StepControl::Tolerances { .. } => {}
        }
        let (rtol, atol) = (self.ctx.rtol, self.ctx.atol);
        let order = self.settings.method.order() as f64;
        let p = &mut self.cur;
        p.ensure_f(sys, &mut self.ctx.report)?;
        let (mut dnf, mut dny) = (0.0, 0.0);
        for (y, f) in p.y.iter().zip(&p.f) {
            let sk = atol + rtol * y.abs();
            dnf += (f / sk).powi(2);
            dny += (y / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
        h = h.min(self.settings.max_step);
        let y1: Vec<f64> = p.y.iter().zip(&p.f).map(|(y, f)| y + h * f).collect();
        let mut f1 = vec![0.0; y1.len()];
        eval(sys, p.t + h, &y1, &mut f1, &mut self.ctx.report)?;
        let mut der2 = 0.0;
        for ((a, b), y) in f1.iter().zip(&p.f).zip(&p.y) {
            let sk = atol + rtol * y.abs();
            der2 += ((a - b) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h;
        let der12 = der2.max(dnf.sqrt());
        let h1 = if !(der12 > 1e-15) { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(1.0 / order) };
        Ok((100.0 * h).min(h1).min(self.settings.max_step))
    }
}
