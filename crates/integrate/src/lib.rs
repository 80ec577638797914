//! tumble-integrate: integrators for y' = f(t, y), small or large, stiff or not.
//!
//! The chapter's methods (explicit Euler, the variable-step Euler, midpoint, RK4, Adams-Bashforth 4, the
//! Adams-Moulton 4 predictor-corrector, implicit Euler linearised or with Newton, step doubling) and what the
//! field uses today (Dormand-Prince 5(4) with PI control and dense output, the Rosenbrock method Rodas4, symplectic
//! Euler and velocity Verlet). Every run returns a [`Report`] of what it cost and the error it estimates, and
//! [`work_precision`] measures error against run time.
//!
//! ```
//! use tumble_integrate::{solve, FnSystem, Method, SaveAt, Settings};
//! // y' = -y, y(0) = 1.
//! let mut sys = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0]).autonomous();
//! let sol = solve(&mut sys, &Settings::tolerances(Method::Dopri5, 1e-10, 1e-12), 0.0, &[1.0], 1.0, &SaveAt::End)
//!     .unwrap();
//! assert!((sol.final_state[0] - (-1.0f64).exp()).abs() < 1e-9);
//! ```

// Negated comparisons (`!(x > 0.0)`) are how the checks here also reject NaN; published reference values keep
// the digits they were published with; the numerical kernels index several arrays in one loop.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::excessive_precision, clippy::needless_range_loop)]

mod controller;
mod error;
mod events;
mod factorization;
#[cfg(feature = "serde")]
pub mod float_serde;
mod integrator;
mod jacobian;
mod memory;
mod method;
mod point;
pub mod problems;
mod reduced;
mod report;
mod scratch;
mod second_order;
mod settings;
mod small_lu;
mod solve;
mod steppers;
mod system;
pub mod work_precision;

pub use error::{OdeError, SystemError};
pub use events::{Advance, StepView};
pub use integrator::Integrator;
pub use memory::IntegratorMemory;
pub use method::Method;
pub use report::Report;
pub use second_order::{FirstOrder, SecondOrderSystem};
pub use settings::{LinearSolver, NewtonMode, Settings, StepControl};
pub use solve::{solve, SaveAt, Solution};
pub use system::{FnSystem, JacobianStructure, OdeSystem, Split};

/// faer, re-exported so that systems can fill dense Jacobians (`faer::MatMut`) with the same version.
pub use faer;
