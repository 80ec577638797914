//! A long call's control from Python: told how far the world's work has come, it checks for Ctrl-C (and other
//! signals) and calls the run's progress callable; an exception from either stops the call, and is raised once the
//! world has kept what it did (a run stopped by Ctrl-C: its frames, the world at the last) or gone back as it was
//! (a step, or any other exception). The one line a slow accurate call
//! says goes to the run's `hint` callable, or to Python's standard error.

use crate::convert::world_error;
use pyo3::prelude::*;
use tumble::WorldError;

/// The control of one `step` or `run`.
pub(crate) struct Control {
    progress: Option<Py<PyAny>>,
    hint: Option<Py<PyAny>>,
    error: Option<PyErr>,
}

impl Control {
    pub fn new(progress: Option<Py<PyAny>>, hint: Option<Py<PyAny>>) -> Control {
        Control { progress, hint, error: None }
    }

    /// The exception that stopped the call.
    pub fn take_error(&mut self) -> PyErr {
        self.error.take().unwrap_or_else(|| world_error(WorldError::Interrupted))
    }
}

impl tumble::Control for &mut Control {
    /// Whether the call goes on after `fraction` of it: false when a signal handler or the progress callable
    /// raised (the error is kept for `take_error`).
    fn go_on(&mut self, fraction: f64) -> bool {
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

    /// A stop keeps the run's work only when it is the user's Ctrl-C (a KeyboardInterrupt); any other exception
    /// (from the progress callable or a signal handler) fails the call, the world left as it was.
    fn keeps_work(&self) -> bool {
        Python::attach(|py| {
            self.error.as_ref().is_none_or(|e| e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py))
        })
    }

    /// The line, to the `hint` callable or Python's standard error (where a notebook shows it); a failure to
    /// show it does not stop the call.
    fn hint(&mut self, line: &str) {
        Python::attach(|py| {
            let shown = match &self.hint {
                Some(cb) => cb.call1(py, (line,)).map(|_| ()),
                None => py
                    .import("sys")
                    .and_then(|sys| sys.getattr("stderr"))
                    .and_then(|err| err.call_method1("write", (format!("tumble: {line}\n"),)))
                    .map(|_| ()),
            };
            if let Err(e) = shown {
                e.print(py);
            }
        })
    }
}
