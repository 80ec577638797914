//! `State`: a world's whole state as read-only numpy arrays (rows as in `World.bodies` and `World.particles`) with
//! the time and, hidden, the engine's memory; `World.set_state` puts it back and the world continues bit for bit.
//! `replace` gives a copy with arrays swapped (the world then starts from it afresh).

use crate::convert::{frozen, invalid, rows};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Mutex;
use tumble::WorldState;

/// A world's whole state: ``time``; ``particle_positions``, ``particle_velocities`` (P, 3); ``body_positions``
/// (B, 3), ``body_orientations`` (B, 4) as (w, x, y, z), ``body_momenta`` (B, 3) (M v) and
/// ``body_angular_momenta`` (B, 3) (I(t) w, world axes), static bodies included at their rows; and the engine's
/// memory (warm starts, sleep, the integrator's next step), so that ``World.set_state`` continues bit for bit.
/// The arrays are read-only; ``replace(body_positions=..., ...)`` returns an edited copy.
#[pyclass(module = "tumble._tumble", name = "State", frozen)]
pub struct PyState {
    /// Behind a mutex only so that the class is `Sync` (the engine memory holds callbacks).
    pub inner: Mutex<WorldState>,
}

impl PyState {
    pub fn get(&self) -> WorldState {
        self.inner.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

/// Rows of 3-vectors as a read-only (N, 3) array.
fn rows3<'py>(py: Python<'py>, v: &[Vector3<f64>]) -> PyResult<Bound<'py, PyAny>> {
    frozen(py, v.iter().flat_map(|x| [x.x, x.y, x.z]).collect(), &[v.len(), 3])
}

fn set_vectors(name: &str, obj: &Bound<'_, PyAny>, want: usize, out: &mut Vec<Vector3<f64>>) -> PyResult<()> {
    let r = rows::<3>(name, obj)?;
    if r.len() != want {
        return Err(invalid(name, format!("has {} rows for the state's {want}", r.len())));
    }
    *out = r.into_iter().map(Vector3::from).collect();
    Ok(())
}

#[pymethods]
impl PyState {
    /// The time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.get().time
    }

    /// (P, 3) particle positions.
    #[getter]
    fn particle_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows3(py, &self.get().particle_positions)
    }

    /// (P, 3) particle velocities.
    #[getter]
    fn particle_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows3(py, &self.get().particle_velocities)
    }

    /// (B, 3) body positions (centres of mass).
    #[getter]
    fn body_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows3(py, &self.get().body_positions)
    }

    /// (B, 4) body orientations (w, x, y, z).
    #[getter]
    fn body_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let s = self.get();
        let flat = s.body_orientations.iter().flat_map(|q| [q.w, q.i, q.j, q.k]).collect();
        frozen(py, flat, &[s.body_orientations.len(), 4])
    }

    /// (B, 3) linear momenta M v.
    #[getter]
    fn body_momenta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows3(py, &self.get().body_momenta)
    }

    /// (B, 3) angular momenta I(t) w about each centre of mass (world axes).
    #[getter]
    fn body_angular_momenta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows3(py, &self.get().body_angular_momenta)
    }

    /// Whether it carries the engine's memory (a state read from a world that has stepped).
    #[getter]
    fn has_memory(&self) -> bool {
        self.get().has_memory()
    }

    /// A copy with the given arrays (and ``time``) replaced, without the engine's memory (the world starts from it
    /// afresh); each array must have the rows of the one it replaces.
    /// Quaternions are taken as given (``set_state`` refuses one whose norm is off 1 by more than 1e-9).
    #[pyo3(signature = (**changes))]
    fn replace(&self, changes: Option<&Bound<'_, PyDict>>) -> PyResult<PyState> {
        let mut s = self.get();
        s.forget_memory();
        for (key, value) in changes.into_iter().flat_map(|d| d.iter()) {
            let name: String = key.extract()?;
            match name.as_str() {
                "time" => s.time = value.extract().map_err(|_| invalid("time", "expected a number"))?,
                "particle_positions" => {
                    set_vectors(&name, &value, s.particle_positions.len(), &mut s.particle_positions)?
                }
                "particle_velocities" => {
                    set_vectors(&name, &value, s.particle_velocities.len(), &mut s.particle_velocities)?
                }
                "body_positions" => set_vectors(&name, &value, s.body_positions.len(), &mut s.body_positions)?,
                "body_momenta" => set_vectors(&name, &value, s.body_momenta.len(), &mut s.body_momenta)?,
                "body_angular_momenta" => {
                    set_vectors(&name, &value, s.body_angular_momenta.len(), &mut s.body_angular_momenta)?
                }
                "body_orientations" => {
                    let r = rows::<4>(&name, &value)?;
                    if r.len() != s.body_orientations.len() {
                        let reason = format!("has {} rows for the state's {}", r.len(), s.body_orientations.len());
                        return Err(invalid(&name, reason));
                    }
                    s.body_orientations = r
                        .into_iter()
                        .map(|q| UnitQuaternion::new_unchecked(Quaternion::new(q[0], q[1], q[2], q[3])))
                        .collect();
                }
                other => return Err(invalid(other, "is not an array of a state")),
            }
        }
        Ok(PyState { inner: Mutex::new(s) })
    }

    fn __repr__(&self) -> String {
        let s = self.get();
        format!(
            "State(time={}, particles={}, bodies={}, memory={})",
            s.time,
            s.particle_positions.len(),
            s.body_positions.len(),
            if s.has_memory() { "True" } else { "False" }
        )
    }
}
