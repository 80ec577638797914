//! Choosing how Python's `World` steps: the integrator (accurate mode) and the contact mode with its options,
//! forwarded to the Rust library's rules (`tumble::mode_from`, `IntegratorOptions`).

use crate::args::integrator_options;
use crate::convert::world_error;
use crate::world::PyWorld;
use pyo3::prelude::*;
use tumble::{mode_from, ModeOptions};

#[pymethods]
impl PyWorld {
    /// Chooses the integrator, with the constructor's keyword arguments (accurate mode only).
    #[pyo3(signature = (integrator = None, rtol = None, atol = None, dt = None, step_doubling = false,
                        tolerance = None, linear_solver = None, newton = false, max_steps = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_integrator(
        &mut self,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        dt: Option<f64>,
        step_doubling: bool,
        tolerance: Option<f64>,
        linear_solver: Option<String>,
        newton: bool,
        max_steps: Option<usize>,
    ) -> PyResult<()> {
        let options =
            integrator_options(integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps);
        let s = options.settings().map_err(world_error)?;
        self.w().set_integrator(s).map_err(world_error)
    }

    /// Chooses how contact is handled: mode="accurate" (free flight under the integrator's error control,
    /// impacts located by bisection, touching bodies carried by error-controlled convex steps with Coulomb friction;
    /// `contact_tolerance` is their error per step in metres, default 1e-4 of the scene's size; solver="newton", the
    /// default, or "clarabel") or "fast" (time stepping at dt, default 1/240 s; solver="soft", the default, or
    /// "exact"; substeps of the soft solver, default 8). In both, sleep=False keeps islands at rest simulated. `dt`
    /// and `substeps` apply to fast mode only, `contact_tolerance` to accurate mode only.
    #[pyo3(signature = (mode, dt = None, sleep = None, contact_tolerance = None, solver = None, substeps = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_mode(
        &mut self,
        mode: &str,
        dt: Option<f64>,
        sleep: Option<bool>,
        contact_tolerance: Option<f64>,
        solver: Option<String>,
        substeps: Option<usize>,
    ) -> PyResult<()> {
        let options = ModeOptions { dt, sleep, contact_tolerance, solver, substeps };
        let m = mode_from(mode, &options).map_err(world_error)?;
        self.w().set_mode(m).map_err(world_error)
    }
}
