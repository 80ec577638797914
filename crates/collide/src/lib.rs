//! tumble-collide: the geometry of tumble. Shapes and their mass properties, world bounding boxes and swept boxes,
//! the chapter's sort-and-sweep broad phase, separating planes of convex polyhedra with a per-pair cache, contact
//! geometry and collision time (bisection, or parry's shape cast). parry's glam types stay inside this crate; its
//! API speaks nalgebra.

mod aabb;
mod contact;
mod convert;
mod error;
mod geometry;
mod mass;
mod mesh;
mod motion;
mod pair_map;
mod polyhedron;
mod proximity;
mod separating_plane;
mod shape;
mod sweep_prune;
mod toi;

pub use aabb::Aabb;
pub use contact::{contacts, Contact, ContactKind, Feature};
pub use error::ShapeError;
pub use mass::MassProperties;
pub use motion::Motion;
pub use polyhedron::Polyhedron;
pub use proximity::{distance, intersects};
pub use separating_plane::{separating_plane, PlaneSource, SeparatingPlane, SeparatingPlaneCache};
pub use shape::{ConvexHull, Shape, TriMesh};
pub use sweep_prune::{brute_force_pairs, SortAndSweep, SweepStats};
pub use toi::{bisect_collision_time, time_of_impact, Bisection, Impact, ToiMethod, ToiOptions};
