//! The built-in scenes for Python's `World`: built or checked by the Rust library's registry
//! (`tumble::scenes`), their numeric parameters by keyword.

use crate::convert::{invalid, world_error};
use crate::world::PyWorld;
use pyo3::prelude::*;
use pyo3::types::PyDict;

#[pymethods]
impl PyWorld {
    /// A built-in scene built by the Rust library (`tumble::scenes::build`), with its numeric parameters by
    /// keyword.
    #[classmethod]
    #[pyo3(signature = (name, **params))]
    fn _rust_scene<'py>(
        cls: &Bound<'py, pyo3::types::PyType>,
        name: &str,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let world = tumble::scenes::build(name, &scene_params(params)?).map_err(world_error)?;
        let obj = cls.call0()?;
        {
            let mut w: PyRefMut<'_, PyWorld> = obj.extract()?;
            *w.w() = world;
        }
        Ok(obj)
    }

    /// Checks a built-in scene's parameters by name and range (`tumble::scenes::check`) without building it.
    #[staticmethod]
    #[pyo3(signature = (name, **params))]
    fn _check_scene(name: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        tumble::scenes::check(name, &scene_params(params)?).map_err(world_error)
    }

    /// The built-in scenes' names.
    #[staticmethod]
    fn _scene_names() -> Vec<&'static str> {
        tumble::scenes::NAMES.to_vec()
    }
}

/// A scene's keyword parameters as (name, number) pairs; a value that is not a real number is an error naming it.
fn scene_params(params: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut given: Vec<(String, f64)> = Vec::new();
    if let Some(p) = params {
        for (k, v) in p.iter() {
            let key: String = k.extract()?;
            let value: f64 = v.extract().map_err(|_| invalid(&key, format!("must be a real number, got {v}")))?;
            given.push((key, value));
        }
    }
    Ok(given)
}
