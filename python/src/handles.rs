//! Typed handles as Python objects: a particle, body, spring or load of one world.

use pyo3::prelude::*;
use tumble::{BodyHandle, LoadHandle, ParticleHandle, SpringHandle};

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
