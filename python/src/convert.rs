//! Arguments in (sequences and numpy arrays to nalgebra, with errors naming the argument) and results out (flat
//! vectors handed to numpy without copying; errors mapped to Python exceptions).

use crate::SimulationError;
use nalgebra::{Matrix3, Point3, Quaternion, UnitQuaternion, Vector3};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use tumble::WorldError;

/// A ValueError in the library's own wording.
pub fn invalid(name: &str, reason: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("invalid argument `{name}`: {reason}"))
}

/// The Python exception for a world error: bad arguments and handles are ValueError, failed steps
/// SimulationError (a RuntimeError), with the library's message.
pub fn world_error(e: WorldError) -> PyErr {
    match e {
        WorldError::InvalidArgument { .. } | WorldError::UnknownHandle { .. } => PyValueError::new_err(e.to_string()),
        WorldError::Simulation(_) => SimulationError::new_err(e.to_string()),
        WorldError::Interrupted => PyRuntimeError::new_err(e.to_string()),
    }
}

/// A number (int or float); a TypeError naming the argument otherwise.
pub fn number(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    obj.extract::<f64>().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "invalid argument `{name}`: expected a number, got {}",
            repr(obj)
        ))
    })
}

/// Three numbers: a tuple, list or array.
pub fn vec3(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vector3<f64>> {
    let v: [f64; 3] = obj.extract().map_err(|_| invalid(name, format!("expected 3 numbers, got {}", repr(obj))))?;
    Ok(Vector3::from(v))
}

/// An optional three-vector.
pub fn opt_vec3(name: &str, obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Vector3<f64>>> {
    obj.filter(|o| !o.is_none()).map(|o| vec3(name, o)).transpose()
}

/// An optional colour: 3 (RGB, opaque) or 4 (RGBA) numbers, linear, each in [0, 1] (checked by the world).
pub fn opt_color(name: &str, obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<[f64; 4]>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else { return Ok(None) };
    let v: Vec<f64> = obj
        .extract()
        .map_err(|_| invalid(name, format!("expected 3 or 4 numbers (RGB or RGBA), got {}", repr(obj))))?;
    tumble::Look::color_of(&v).map(Some).map_err(world_error)
}

/// A quaternion given as (w, x, y, z), normalised; it must be finite and nonzero.
pub fn quat(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<UnitQuaternion<f64>> {
    let q: [f64; 4] =
        obj.extract().map_err(|_| invalid(name, format!("expected 4 numbers (w, x, y, z), got {}", repr(obj))))?;
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    let n = q.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(invalid(
            name,
            format!("must be a finite nonzero quaternion (w, x, y, z), got {:?}", [q.w, q.i, q.j, q.k]),
        ));
    }
    Ok(UnitQuaternion::new_normalize(q))
}

/// A 3x3 matrix: nested sequences or a (3, 3) array.
pub fn mat3(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Matrix3<f64>> {
    let m: [[f64; 3]; 3] =
        obj.extract().map_err(|_| invalid(name, format!("expected a 3x3 matrix, got {}", repr(obj))))?;
    Ok(Matrix3::from_fn(|i, j| m[i][j]))
}

/// An (N, 3) array of points, or a sequence of triples.
pub fn points(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<Point3<f64>>> {
    if let Ok(a) = obj.extract::<PyReadonlyArray2<'_, f64>>() {
        let view = a.as_array();
        if view.ncols() != 3 {
            return Err(invalid(name, format!("expected an (N, 3) array, got shape {:?}", view.shape())));
        }
        return Ok(view.rows().into_iter().map(|r| Point3::new(r[0], r[1], r[2])).collect());
    }
    let v: Vec<[f64; 3]> =
        obj.extract().map_err(|_| invalid(name, format!("expected (N, 3) points, got {}", repr(obj))))?;
    Ok(v.into_iter().map(Point3::from).collect())
}

/// An (N, W) array of rows, or a sequence of W-tuples.
pub fn rows<const W: usize>(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; W]>> {
    if let Ok(a) = obj.extract::<PyReadonlyArray2<'_, f64>>() {
        let view = a.as_array();
        if view.ncols() != W {
            return Err(invalid(name, format!("expected an (N, {W}) array, got shape {:?}", view.shape())));
        }
        return Ok(view.rows().into_iter().map(|r| std::array::from_fn(|i| r[i])).collect());
    }
    obj.extract::<Vec<[f64; W]>>().map_err(|_| invalid(name, format!("expected an (N, {W}) array, got {}", repr(obj))))
}

/// An object's repr for a message ("an object" when it has none).
pub fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map(|r| r.to_string()).unwrap_or_else(|_| "an object".into())
}

/// A flat vector as a read-only numpy array of the given shape: writing to it raises instead of changing nothing.
pub fn frozen<'py>(py: Python<'py>, data: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    let a = array(py, data, shape)?;
    a.getattr("flags")?.setattr("writeable", false)?;
    Ok(a)
}

/// A flat vector as a numpy array of the given shape, without copying.
pub fn array<'py>(py: Python<'py>, data: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Bound<'py, PyArray1<f64>> = data.into_pyarray(py);
    Ok(flat.reshape(shape.to_vec())?.into_any())
}

/// A kinematic path from `(times, positions[, orientations])`: (K,) times, (K, 3) positions, (K, 4) orientations
/// (w, x, y, z; normalised).
pub fn keyframes(obj: &Bound<'_, PyAny>) -> PyResult<tumble::Keyframes> {
    let parts: Vec<Bound<'_, PyAny>> = obj
        .try_iter()
        .and_then(|items| items.collect::<PyResult<Vec<_>>>())
        .ok()
        .filter(|p| p.len() == 2 || p.len() == 3)
        .ok_or_else(|| {
            invalid("keyframes", format!("expected (times, positions[, orientations]), got {}", repr(obj)))
        })?;
    let times: Vec<f64> = match parts[0].extract::<numpy::PyReadonlyArray1<'_, f64>>() {
        Ok(a) => a.as_array().to_vec(),
        Err(_) => parts[0]
            .extract()
            .map_err(|_| invalid("keyframes", format!("times: expected K numbers, got {}", repr(&parts[0]))))?,
    };
    let positions = rows::<3>("keyframes", &parts[1])?.into_iter().map(nalgebra::Vector3::from).collect();
    let orientations = match parts.get(2).filter(|o| !o.is_none()) {
        None => None,
        Some(o) => Some(
            rows::<4>("keyframes", o)?
                .into_iter()
                .map(|q| {
                    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
                    let n = q.norm();
                    if n.is_finite() && n > 0.0 {
                        Ok(UnitQuaternion::new_normalize(q))
                    } else {
                        Err(invalid("keyframes", "orientations must be finite nonzero quaternions (w, x, y, z)"))
                    }
                })
                .collect::<PyResult<Vec<_>>>()?,
        ),
    };
    tumble::Keyframes::new(times, positions, orientations)
        .map_err(|e| invalid("keyframes", e.to_string().trim_start_matches("invalid argument ").to_string()))
}
