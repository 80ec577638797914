//! A long call's control from Python: told how far the world's work has come, it checks for Ctrl-C (and other
//! signals) and calls the run's progress callable; an exception from either stops the call, and is raised once the
//! world is back as it was.

use crate::convert::world_error;
use pyo3::prelude::*;
use tumble::WorldError;

/// The control of one `step` or `run`.
pub(crate) struct Control {
    progress: Option<Py<PyAny>>,
    error: Option<PyErr>,
}

impl Control {
    pub fn new(progress: Option<Py<PyAny>>) -> Control {
        Control { progress, error: None }
    }

    /// Whether the call goes on after `fraction` of it: false when a signal handler or the progress callable
    /// raised (the error is kept for `take_error`).
    pub fn go_on(&mut self, fraction: f64) -> bool {
        Python::attach(|py| {
            let r = py.check_signals().and_then(|_| match &self.progress {
                Some(cb) => cb.call1(py, (fraction,)).map(|_| ()),
                None => Ok(()),
            });
            match r {
                Ok(()) => true,
                Err(e) => {
                    self.error = Some(e);
                    false
                }
            }
        })
    }

    /// The exception that stopped the call.
    pub fn take_error(&mut self) -> PyErr {
        self.error.take().unwrap_or_else(|| world_error(WorldError::Interrupted))
    }
}
