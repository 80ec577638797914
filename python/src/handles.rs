//! Typed handles as Python objects: a particle, body, spring or load of one world.

use pyo3::prelude::*;
use tumble::{BodyHandle, JointHandle, LoadHandle, ParticleHandle, SpringHandle};

macro_rules! handle_class {
    ($py:ident, $name:literal, $rust:ty, $doc:literal) => {
        #[doc = $doc]
        #[pyclass(module = "tumble._tumble", name = $name, frozen, eq, hash, from_py_object)]
        #[derive(Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $py {
            pub world: u64,
            pub index: u32,
            pub generation: u32,
        }

        #[pymethods]
        impl $py {
            /// Slot index in the world.
            #[getter]
            fn index(&self) -> u32 {
                self.index
            }
            /// Generation of the slot when the handle was issued.
            #[getter]
            fn generation(&self) -> u32 {
                self.generation
            }
            /// The number of the world that issued it.
            #[getter]
            fn world(&self) -> u64 {
                self.world
            }
            fn __repr__(&self) -> String {
                format!("{}({}v{})", $name, self.index, self.generation)
            }
            /// Pickles as its kind, world number, index and generation (a handle names an object of one world:
            /// a world loaded from a file answers to it only through rows, not handles).
            fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (&'static str, u64, u32, u32))> {
                let rebuild = py.import("tumble._tumble")?.getattr("_handle")?;
                Ok((rebuild, ($name, self.world, self.index, self.generation)))
            }
        }

        impl From<$rust> for $py {
            fn from(h: $rust) -> Self {
                $py { world: h.world(), index: h.index(), generation: h.generation() }
            }
        }

        impl From<$py> for $rust {
            fn from(h: $py) -> Self {
                <$rust>::from_world_parts(h.world, h.index, h.generation)
            }
        }
    };
}

handle_class!(PyParticleHandle, "ParticleHandle", ParticleHandle, "A particle of a world.");
handle_class!(PyBodyHandle, "BodyHandle", BodyHandle, "A rigid body of a world.");
handle_class!(PySpringHandle, "SpringHandle", SpringHandle, "A spring of a world.");
handle_class!(PyLoadHandle, "LoadHandle", LoadHandle, "A load (force, torque or callback) of a world.");
handle_class!(PyJointHandle, "JointHandle", JointHandle, "A joint of a world.");

/// A handle from its parts (unpickling: each handle's `__reduce__`).
#[pyfunction]
pub fn _handle(py: Python<'_>, kind: &str, world: u64, index: u32, generation: u32) -> PyResult<Py<PyAny>> {
    Ok(match kind {
        "ParticleHandle" => Py::new(py, PyParticleHandle { world, index, generation })?.into_any(),
        "BodyHandle" => Py::new(py, PyBodyHandle { world, index, generation })?.into_any(),
        "SpringHandle" => Py::new(py, PySpringHandle { world, index, generation })?.into_any(),
        "LoadHandle" => Py::new(py, PyLoadHandle { world, index, generation })?.into_any(),
        "JointHandle" => Py::new(py, PyJointHandle { world, index, generation })?.into_any(),
        other => return Err(crate::convert::invalid("kind", format!("no handle kind {other}"))),
    })
}
