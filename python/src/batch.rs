//! Batches from Python: `_rollout` runs copies of a world from many states on a Rust thread pool with the
//! interpreter lock released (the package's `tumble.rollout` stacks the runs); `_assign_from` makes a world a copy
//! of another (`copy.copy` and `copy.deepcopy`). Saving and loading are in `files.rs`.

use crate::control::Control;
use crate::convert::world_error;
use crate::report::run_arrays;
use crate::state::PyState;
use crate::world::PyWorld;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tumble::{RolloutSettings, WorldError};

/// Runs a copy of `world` from each state for `duration` (frames every `frame_interval`) on `threads` threads (0:
/// one per core); returns each run's arrays, in the order of `states`.
#[pyfunction]
#[pyo3(signature = (world, states, duration, frame_interval = None, threads = None, progress = None))]
pub fn _rollout<'py>(
    py: Python<'py>,
    world: &PyWorld,
    states: Vec<PyRef<'py, PyState>>,
    duration: f64,
    frame_interval: Option<f64>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let template = world.r().clone();
    let states: Vec<tumble::WorldState> = states.iter().map(|s| s.get()).collect();
    let settings = RolloutSettings {
        duration,
        frame_interval: frame_interval.unwrap_or(tumble::DEFAULT_FRAME_INTERVAL),
        threads: threads.unwrap_or(0),
    };
    let mut control = Control::new(progress, None);
    let mut c = &mut control;
    let result = py.detach(move || {
        tumble::rollout(&template, &states, settings, |fraction| tumble::Control::go_on(&mut c, fraction))
    });
    match result {
        Ok(runs) => runs.into_iter().map(|run| run_arrays(py, run)).collect(),
        Err(WorldError::Interrupted) => Err(control.take_error()),
        Err(e) => Err(world_error(e)),
    }
}

#[pymethods]
impl PyWorld {
    /// Makes this world a copy of `other`: its objects, settings, state, engine memory and report; the copy answers
    /// to `other`'s handles and continues bit for bit as `other` would. Force callbacks are shared.
    fn _assign_from(&mut self, other: &PyWorld) {
        let copy = other.r().clone();
        *self.w() = copy;
    }
}
