//! Worlds to and from files from Python: the readable JSON scene and the versioned binary format (which `pickle`
//! uses); the package's `World.save`, `World.load` and `World.from_json` call these.

use crate::convert::world_error;
use crate::world::PyWorld;
use pyo3::prelude::*;

#[pymethods]
impl PyWorld {
    /// The world as readable JSON: every object with its state to the bit, the settings, the start that ``reset``
    /// returns to and (``memory=True``, the default) the engine's memory, so that a world loaded from it continues
    /// bit for bit; ``memory=False`` writes the scene alone, hand-editable, whose engine starts afresh when loaded.
    /// A world with force callbacks cannot be saved (ValueError naming ``loads``).
    #[pyo3(signature = (memory = true))]
    fn to_json(&self, memory: bool) -> PyResult<String> {
        if memory { self.r().to_json() } else { self.r().to_json_scene() }.map_err(world_error)
    }

    /// The world in the versioned binary format (what ``pickle`` and ``save`` to a non-.json path write), with the
    /// engine's memory unless ``memory=False``.
    #[pyo3(signature = (memory = true))]
    fn _to_bytes<'py>(&self, py: Python<'py>, memory: bool) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = if memory { self.r().to_bytes() } else { self.r().to_bytes_scene() }.map_err(world_error)?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// Makes this world the one a scene (JSON text) describes.
    fn _assign_from_json(&mut self, text: &str) -> PyResult<()> {
        *self.w() = tumble::World::from_json(text).map_err(world_error)?;
        Ok(())
    }

    /// Makes this world the one the binary format describes.
    fn _assign_from_bytes(&mut self, data: &[u8]) -> PyResult<()> {
        *self.w() = tumble::World::from_bytes(data).map_err(world_error)?;
        Ok(())
    }
}
