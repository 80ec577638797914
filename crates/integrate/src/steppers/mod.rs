//! The step of each method behind one trait, so the driver (`integrator.rs`) can run any of them under any
//! step control.

mod adams;
mod dopri5;
mod explicit_rk;
mod implicit_euler;
mod rodas4;
mod step_doubling;
mod symplectic;

use crate::error::OdeError;
use crate::method::Method;
use crate::point::Point;
use crate::report::Report;
use crate::settings::{Control, NewtonMode, Settings};
use crate::system::OdeSystem;

/// What a step needs besides the system and the points: counters and the error weights.
pub(crate) struct Ctx {
    pub report: Report,
    pub rtol: f64,
    pub atol: f64,
    pub newton: NewtonMode,
}

/// The error estimates of one attempted step.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Estimate {
    /// Error relative to the requested tolerance (accept when <= 1), if the method controls error.
    pub scaled: Option<f64>,
    /// Absolute local error, max norm, if the method estimates it.
    pub local: Option<f64>,
}

/// One method's step. `step` advances from `from` by `h` into `to` (whose `t` and id the driver has already
/// renewed); it may evaluate `from`'s derivative and may set `to`'s (first-same-as-last).
pub(crate) trait Stepper<S: OdeSystem + ?Sized> {
    fn step(&mut self, sys: &mut S, from: &mut Point, h: f64, to: &mut Point, ctx: &mut Ctx)
        -> Result<Estimate, OdeError>;

    /// The step from `from` to `to` was accepted.
    fn accepted(&mut self, _from: &Point, _to: &Point, _ctx: &mut Ctx) {}

    /// The state was changed from outside or restored: drop histories and caches.
    fn reset(&mut self) {}

    /// Whether `dense` can interpolate the last accepted step.
    fn has_dense_output(&self) -> bool {
        false
    }

    /// Writes the interpolant at `from.t + theta (to.t - from.t)` of the step just taken.
    fn dense(&self, _from: &Point, _to: &Point, _theta: f64, _out: &mut [f64]) {}

    /// A step size the method picks for itself at `from` (euler-variable), before the driver's limits.
    fn own_step(&mut self, _sys: &mut S, _from: &mut Point, _ctx: &mut Ctx) -> Result<Option<f64>, OdeError> {
        Ok(None)
    }
}

/// Builds the stepper for the settings' method, wrapped in step doubling when asked.
pub(crate) fn build<S: OdeSystem + ?Sized>(sys: &S, settings: &Settings) -> Result<Box<dyn Stepper<S>>, OdeError> {
    let n = sys.dim();
    Ok(match settings.method {
        Method::Euler => finish(explicit_rk::ExplicitRk::new(&explicit_rk::EULER, n), n, settings),
        Method::Midpoint => finish(explicit_rk::ExplicitRk::new(&explicit_rk::MIDPOINT, n), n, settings),
        Method::Rk4 => finish(explicit_rk::ExplicitRk::new(&explicit_rk::RK4, n), n, settings),
        Method::EulerVariable => match settings.control {
            Control::Derivative { tolerance } => Box::new(explicit_rk::EulerVariable::new(n, tolerance)),
            _ => unreachable!("validated: euler-variable runs under Control::Derivative"),
        },
        Method::Ab4 => Box::new(adams::Adams::new(n, false)),
        Method::Am4 => Box::new(adams::Adams::new(n, true)),
        Method::Dopri5 => finish(dopri5::Dopri5::new(n), n, settings),
        Method::ImplicitEuler => finish(implicit_euler::ImplicitEuler::new(sys)?, n, settings),
        Method::Rodas4 => finish(rodas4::Rodas4::new(sys)?, n, settings),
        Method::SymplecticEuler | Method::Verlet => {
            let split = sys.split().expect("validated: symplectic methods need a split");
            finish(symplectic::Symplectic::new(n, split, settings.method == Method::Verlet), n, settings)
        }
    })
}

/// Boxes a one-step method, inside the chapter's step doubling when the control asks for it.
fn finish<S: OdeSystem + ?Sized, T: Stepper<S> + 'static>(stepper: T, n: usize, settings: &Settings) -> Box<dyn Stepper<S>> {
    match settings.control {
        Control::StepDoubling { tolerance, .. } => {
            Box::new(step_doubling::StepDoubling::new(stepper, n, tolerance, settings.method.order()))
        }
        _ => Box::new(stepper),
    }
}
