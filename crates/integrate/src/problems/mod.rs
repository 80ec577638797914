//! Reference problems for convergence, stability and work-precision studies, with their published reference
//! values (the Bari/Hairer IVP test set, computed by RADAU5 at rtol = atol = 1.1e-18) or closed forms: closed-form
//! ones, non-stiff orbits and populations, and the stiff test set (Van der Pol, ROBER, HIRES, OREGO).

mod closed_form;
mod nonstiff;
mod stiff;

pub use closed_form::{Dahlquist, DampedOscillator, Kepler, StiffSpring};
pub use nonstiff::{Arenstorf, LotkaVolterra};
pub use stiff::{Hires, Orego, Rober, VanDerPol};

use crate::system::OdeSystem;

/// How a final state is compared with its reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorNorm {
    /// ||y - ref||_2 / ||ref||_2: for states whose components share one scale (orbits, populations).
    Relative,
    /// max_i |y_i - ref_i| / |ref_i|: significant digits of every component, for stiff chemistry where
    /// components differ by many orders of magnitude (every reference component is nonzero).
    Componentwise,
}

/// Whether explicit methods are of any use on a problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProblemKind {
    /// Explicit methods are efficient.
    NonStiff,
    /// Explicit methods need a number of steps set by stability, not accuracy.
    Stiff,
}

/// A test problem: the system, the interval, the initial state and the reference final state.
pub struct Problem {
    /// Name used in reports and on the command line (`lotka-volterra`, `rober`, ...).
    pub name: &'static str,
    /// Start time.
    pub t0: f64,
    /// End time.
    pub t_end: f64,
    /// Initial state.
    pub y0: Vec<f64>,
    /// Final state from a closed form or a published reference; `None` when it must be computed.
    pub reference: Option<Vec<f64>>,
    /// Stiff or not.
    pub kind: ProblemKind,
    /// atol = rtol x this in tolerance sweeps (components far below 1 need a smaller absolute tolerance).
    pub atol_scale: f64,
    /// How errors are measured.
    pub norm: ErrorNorm,
    make: fn() -> Box<dyn OdeSystem + Send>,
}

impl Problem {
    /// A fresh instance of the system.
    pub fn system(&self) -> Box<dyn OdeSystem + Send> {
        (self.make)()
    }

    /// The error of `y` against `reference` in this problem's norm.
    pub fn error(&self, y: &[f64], reference: &[f64]) -> f64 {
        match self.norm {
            ErrorNorm::Relative => {
                let num: f64 = y.iter().zip(reference).map(|(a, b)| (a - b).powi(2)).sum();
                let den: f64 = reference.iter().map(|b| b * b).sum();
                (num / den).sqrt()
            }
            ErrorNorm::Componentwise => {
                y.iter().zip(reference).map(|(a, b)| (a - b).abs() / b.abs()).fold(0.0, f64::max)
            }
        }
    }
}

/// The work-precision set, in the order the issue lists it.
pub fn all() -> Vec<Problem> {
    vec![
        LotkaVolterra::problem(),
        Arenstorf::problem(),
        Kepler::problem(),
        VanDerPol::problem(),
        Rober::problem(),
        Hires::problem(),
        Orego::problem(),
        StiffSpring::problem(),
    ]
}

/// One problem of [`all`] by name.
pub fn by_name(name: &str) -> Option<Problem> {
    all().into_iter().find(|p| p.name == name)
}
