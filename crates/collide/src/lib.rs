//! tumble-collide: the geometry of tumble. Shapes and their mass properties (parry computes them); parry's glam
//! types stay inside this crate and its API speaks nalgebra.

mod convert;
mod error;
mod mass;
mod mesh;
mod shape;

pub use error::ShapeError;
pub use mass::MassProperties;
pub use shape::{ConvexHull, Shape, TriMesh};
