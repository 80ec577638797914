//! Step-size controllers: Hairer's PI controller (dopri5), Gustafsson's predictive controller (rodas4),
//! halving and doubling for the Adams corrector (each change restarts its history), and the chapter's
//! step-doubling formula h_new = h (e_max / e)^(1/(n+1)). The first step of an adaptive integration is the driver's
//! (`integrator/first_step.rs`).

use crate::memory::{MemoryReader, MemoryWriter};
use crate::method::Method;
use crate::settings::{Settings, StepControl};

const SAFE: f64 = 0.9;

#[derive(Clone, Debug)]
pub(crate) enum Controller {
    /// A fixed step: nothing to control.
    Fixed,
    /// PI control: fac = err^expo / err_old^beta, h_new = h / fac within [h / max_decrease, h max_increase]
    /// (err_old kept as its logarithm, so a step costs one logarithm and one exponential). Dopri5:
    /// expo = 1/5 - 0.75 beta, beta = 0.04, factors 5 and 10; dop853: expo = 1/8, beta = 0, factors 3 and 6.
    Pi { ln_errold: f64, expo: f64, beta: f64, max_decrease: f64, max_increase: f64 },
    /// fac = err^(1/4) / safety, sharpened by the ratio of the last two accepted steps and errors (Gustafsson);
    /// the step may shrink 5-fold and grow `max_increase`-fold (rodas4: 6, radau5: 8).
    Predictive { last: Option<(f64, f64)>, max_increase: f64 },
    /// Halve on rejection; double after several steps with err < 1/64 (an order-4 error grows 32x when h
    /// doubles, so 1/64 leaves a factor 2 of margin).
    Halving { calm: usize },
    /// The chapter's formula with n the method's order, the factor kept within [0.1, 10] (it is unbounded when
    /// e = 0 or e is huge).
    Doubling { order: u32 },
    /// The method chooses its own step (euler-variable).
    Own,
}

impl Controller {
    pub fn for_settings(settings: &Settings) -> Self {
        match settings.control {
            StepControl::Fixed { .. } => Controller::Fixed,
            StepControl::StepDoubling { .. } => Controller::Doubling { order: settings.method.order() },
            StepControl::Derivative { .. } => Controller::Own,
            StepControl::Tolerances { .. } => match settings.method {
                Method::Rodas4 => Controller::Predictive { last: None, max_increase: 6.0 },
                Method::Radau5 => Controller::Predictive { last: None, max_increase: 8.0 },
                Method::Am4 => Controller::Halving { calm: 0 },
                Method::Dop853 => Controller::Pi {
                    ln_errold: (1e-4f64).ln(),
                    expo: 1.0 / 8.0,
                    beta: 0.0,
                    max_decrease: 3.0,
                    max_increase: 6.0,
                },
                _ => Controller::Pi {
                    ln_errold: (1e-4f64).ln(),
                    expo: 0.2 - 0.75 * 0.04,
                    beta: 0.04,
                    max_decrease: 5.0,
                    max_increase: 10.0,
                },
            },
        }
    }

    /// The next step after an accepted step of size `h` with scaled error `err` (<= 1). A step without an
    /// estimate (a multistep starting step) keeps h.
    #[inline]
    pub fn accepted(&mut self, err: Option<f64>, safety: Option<f64>, h: f64, after_rejection: bool) -> f64 {
        let Some(err) = err else { return h };
        let safe = safety.unwrap_or(SAFE);
        let h_new = match self {
            Controller::Fixed | Controller::Own => h,
            Controller::Pi { ln_errold, expo, beta, max_decrease, max_increase } => {
                let ln_err = err.max(1e-300).ln();
                let fac =
                    ((*expo * ln_err - *beta * *ln_errold).exp() / safe).clamp(1.0 / *max_increase, *max_decrease);
                *ln_errold = ln_err.max((1e-4f64).ln());
                h / fac
            }
            Controller::Predictive { last, max_increase } => {
                let mut fac = (root4(err) / safe).clamp(1.0 / *max_increase, 5.0);
                if let Some((h_acc, err_acc)) = *last {
                    let gus = ((h_acc / h) * root4(err * err / err_acc) / safe).clamp(1.0 / *max_increase, 5.0);
                    fac = fac.max(gus);
                }
                *last = Some((h, err.max(1e-2)));
                h / fac
            }
            Controller::Halving { calm } => {
                if err < 1.0 / 64.0 {
                    *calm += 1;
                } else {
                    *calm = 0;
                }
                if *calm >= 8 {
                    *calm = 0;
                    2.0 * h
                } else {
                    h
                }
            }
            Controller::Doubling { order } => h * doubling_factor(err, *order),
        };
        if after_rejection {
            h_new.min(h)
        } else {
            h_new
        }
    }

    /// The next attempt after a rejected step of size `h` with scaled error `err` (> 1).
    pub fn rejected(&mut self, err: f64, safety: Option<f64>, h: f64, first_step: bool) -> f64 {
        let safe = safety.unwrap_or(SAFE);
        match self {
            Controller::Fixed | Controller::Own => h,
            Controller::Pi { expo, max_decrease, .. } => h / (err.powf(*expo) / safe).min(*max_decrease),
            Controller::Predictive { .. } if first_step => 0.1 * h,
            Controller::Predictive { max_increase, .. } => h / (root4(err) / safe).clamp(1.0 / *max_increase, 5.0),
            Controller::Halving { calm } => {
                *calm = 0;
                0.5 * h
            }
            Controller::Doubling { order } => h * doubling_factor(err, *order),
        }
    }
}

impl Controller {
    /// Writes the controller's history (`memory.rs`); its constants come from the settings.
    pub fn save(&self, out: &mut MemoryWriter) {
        match self {
            Controller::Pi { ln_errold, .. } => out.number(*ln_errold),
            Controller::Predictive { last, .. } => {
                out.maybe(last.map(|l| l.0));
                out.maybe(last.map(|l| l.1));
            }
            Controller::Halving { calm } => out.count(*calm as u64),
            Controller::Fixed | Controller::Doubling { .. } | Controller::Own => {}
        }
    }

    pub fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        match self {
            Controller::Pi { ln_errold, .. } => *ln_errold = input.number("controller error")?,
            Controller::Predictive { last, .. } => {
                let (h, err) = (input.maybe("controller step")?, input.maybe("controller error")?);
                *last = h.zip(err);
            }
            Controller::Halving { calm } => *calm = input.count("controller calm steps")?.min(8) as usize,
            Controller::Fixed | Controller::Doubling { .. } | Controller::Own => {}
        }
        Ok(())
    }
}

/// (e_max / e)^(1/(n+1)) with err = e / e_max.
fn doubling_factor(err: f64, order: u32) -> f64 {
    if err <= 0.0 {
        return 10.0;
    }
    err.powf(-1.0 / (order as f64 + 1.0)).clamp(0.1, 10.0)
}

/// x^(1/4) by two square roots (cheaper than powf).
#[inline]
fn root4(x: f64) -> f64 {
    x.sqrt().sqrt()
}
