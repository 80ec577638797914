//! The step of each method behind one trait, so the driver (`integrator/`) can run any of them under any
//! step control.

mod adams;
mod dop853;
mod dop853_tableau;
mod dopri5;
mod explicit_rk;
mod implicit_euler;
mod radau5;
mod rodas4;
mod step_doubling;
mod symplectic;

use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::method::Method;
use crate::point::Point;
use crate::report::Report;
use crate::settings::{NewtonMode, Settings, StepControl};
use crate::system::OdeSystem;

/// What a step needs besides the system and the points: counters and the error weights.
#[derive(Clone)]
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
    /// The safety factor the step-size controller should use (Radau lowers it after slow Newton iterations).
    pub safety: Option<f64>,
}

/// One method's step. `step` advances from `from` by `h` into `to` (whose `t` and id the driver has already
/// renewed); it may evaluate `from`'s derivative and may set `to`'s (first-same-as-last).
/// Copies a boxed stepper (its caches and histories included), for integrators that are copied whole.
pub(crate) trait StepperClone<S: OdeSystem + ?Sized> {
    fn clone_box(&self) -> Box<dyn Stepper<S> + Send>;
}

impl<S: OdeSystem + ?Sized, T: Stepper<S> + Clone + Send + 'static> StepperClone<S> for T {
    fn clone_box(&self) -> Box<dyn Stepper<S> + Send> {
        Box::new(self.clone())
    }
}

/// What a method keeps between steps, as plain data (`memory.rs`): `save` writes it, `load` reads it back in the
/// same order into a method built for the same system and settings. Scratch is saved too, so that nothing a later
/// step or interpolation reads is missed; factorizations are dropped and rebuilt from the saved Jacobian.
pub(crate) trait Remember {
    fn save(&self, out: &mut MemoryWriter);
    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String>;
}

pub(crate) trait Stepper<S: OdeSystem + ?Sized>: StepperClone<S> + Remember {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError>;

    /// The step from `from` to `to` was accepted.
    fn accepted(&mut self, _from: &Point, _to: &Point, _ctx: &mut Ctx) {}

    /// The last attempt was rejected (by its error or by a failure a smaller step may cure).
    fn rejected(&mut self) {}

    /// After a recoverable failure, the factor by which to shrink the step (None: the driver's 1/4).
    fn retry_factor(&self) -> Option<f64> {
        None
    }

    /// The step to take next, given the controller's `proposal` after an accepted step of size `h` (Radau keeps h
    /// when the change is small, so that its factorizations stay valid).
    fn prefer_step(&self, _h: f64, proposal: f64) -> f64 {
        proposal
    }

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
pub(crate) fn build<S: OdeSystem + ?Sized>(
    sys: &S,
    settings: &Settings,
) -> Result<Box<dyn Stepper<S> + Send>, OdeError> {
    let n = sys.dim();
    Ok(match settings.method {
        Method::Euler => finish(explicit_rk::ExplicitRk::new(&explicit_rk::EULER, n), n, settings),
        Method::Midpoint => finish(explicit_rk::ExplicitRk::new(&explicit_rk::MIDPOINT, n), n, settings),
        Method::Rk4 => finish(explicit_rk::ExplicitRk::new(&explicit_rk::RK4, n), n, settings),
        Method::EulerVariable => match settings.control {
            StepControl::Derivative { tolerance } => Box::new(explicit_rk::EulerVariable::new(n, tolerance)),
            _ => unreachable!("validated: euler-variable runs under StepControl::Derivative"),
        },
        Method::Ab4 => Box::new(adams::Adams::new(n, false)),
        Method::Am4 => Box::new(adams::Adams::new(n, true)),
        Method::Dopri5 => finish(dopri5::Dopri5::new(n), n, settings),
        Method::ImplicitEuler => finish(implicit_euler::ImplicitEuler::new(sys, settings.linear_solver)?, n, settings),
        Method::Rodas4 => finish(rodas4::Rodas4::new(sys)?, n, settings),
        Method::Radau5 => {
            let (rtol, atol) = settings.weights();
            finish(radau5::Radau5::new(sys, rtol, atol)?, n, settings)
        }
        Method::Dop853 => finish(dop853::Dop853::new(n), n, settings),
        Method::SymplecticEuler | Method::Verlet => {
            let split = sys.split().expect("validated: symplectic methods need a split");
            finish(symplectic::Symplectic::new(n, split, settings.method == Method::Verlet), n, settings)
        }
    })
}

/// Boxes a one-step method, inside the chapter's step doubling when the control asks for it.
fn finish<S: OdeSystem + ?Sized, T: Stepper<S> + Clone + Send + 'static>(
    stepper: T,
    n: usize,
    settings: &Settings,
) -> Box<dyn Stepper<S> + Send> {
    match settings.control {
        StepControl::StepDoubling { tolerance, .. } => {
            Box::new(step_doubling::StepDoubling::new(stepper, n, tolerance, settings.method.order()))
        }
        _ => Box::new(stepper),
    }
}
