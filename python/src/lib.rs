//! tumble's Python module `tumble._tumble`: the World, shapes and handles, numpy arrays in and out. The package
//! `tumble` (python/tumble/) wraps it with `Run`, `Report`, plots, previews and glTF export.

use pyo3::prelude::*;

mod args;
mod batch;
mod control;
mod convert;
mod files;
mod fracture;
mod handles;
mod material;
mod mesh;
mod report;
mod shapes;
mod state;
mod world;

pyo3::create_exception!(
    tumble,
    SimulationError,
    pyo3::exceptions::PyRuntimeError,
    "A step could not be completed (divergence, solver failure, a callback's exception); the world is unchanged."
);

#[pymodule]
fn _tumble(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<world::PyWorld>()?;
    m.add_function(wrap_pyfunction!(batch::_rollout, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::_shape_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(handles::_handle, m)?)?;
    m.add_function(wrap_pyfunction!(fracture::shared_faces, m)?)?;
    m.add_function(wrap_pyfunction!(fracture::bonds, m)?)?;
    m.add_class::<state::PyState>()?;
    m.add_class::<shapes::PyShape>()?;
    m.add_class::<shapes::Sphere>()?;
    m.add_class::<shapes::PyBox>()?;
    m.add_class::<shapes::Capsule>()?;
    m.add_class::<shapes::Cylinder>()?;
    m.add_class::<shapes::PyConvexHull>()?;
    m.add_class::<shapes::PyTriMesh>()?;
    m.add_class::<mesh::PyMesh>()?;
    m.add_class::<handles::PyParticleHandle>()?;
    m.add_class::<handles::PyBodyHandle>()?;
    m.add_class::<handles::PySpringHandle>()?;
    m.add_class::<handles::PyLoadHandle>()?;
    m.add_class::<handles::PyJointHandle>()?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
