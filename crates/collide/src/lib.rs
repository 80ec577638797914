//! tumble-collide: the geometry of tumble. Shapes and their mass properties, world bounding boxes and swept boxes,
//! the chapter's sort-and-sweep broad phase, separating planes of convex polyhedra with a per-pair cache, contact
//! geometry and collision time (bisection, or parry's shape cast). parry's glam types stay inside this crate; its
//! API speaks nalgebra.
//!
//! ```
//! use nalgebra::{Isometry3, Vector3};
//! use tumble_collide::{contacts, time_of_impact, Motion, Shape, SortAndSweep, ToiOptions};
//!
//! let ball = Shape::sphere(0.5)?;
//! let ground = Shape::half_space(Vector3::z())?;
//! // Which boxes overlap (indices into the slice), kept sorted from call to call:
//! let poses = [Isometry3::translation(0.0, 0.0, 0.4), Isometry3::translation(3.0, 0.0, 0.4)];
//! let boxes: Vec<_> = poses.iter().map(|p| ball.aabb(p)).collect::<Result<_, _>>()?;
//! assert_eq!(SortAndSweep::new().update(&boxes)?, &[] as &[(u32, u32)]);
//! // Where a ball sunk 0.1 into the ground touches it:
//! let c = &contacts(&ball, &poses[0], &ground, &Isometry3::identity(), 0.0)?[0];
//! assert!((c.distance + 0.1).abs() < 1e-12 && (c.normal.z + 1.0).abs() < 1e-12);
//! // When a ball dropped at 2 m/s from 1.5 m first touches it: (1.5 - 0.5) / 2 = 0.5 s.
//! let fall = Motion::new(Isometry3::translation(0.0, 0.0, 1.5), Vector3::new(0.0, 0.0, -2.0), Vector3::zeros())?;
//! let hit = time_of_impact(&ball, &fall, &ground, &Motion::stationary(Isometry3::identity()), 1.0, &ToiOptions::default())?;
//! assert!((hit.unwrap().time - 0.5).abs() < 1e-9);
//! # Ok::<(), tumble_collide::ShapeError>(())
//! ```

mod aabb;
mod contact;
mod contact_point;
mod convert;
mod convex_hull;
mod decompose;
mod error;
mod face_contact;
mod fracture;
mod geometry;
mod hull_axis;
mod mass;
mod mass_properties;
mod mesh;
mod mesh_builders;
mod mesh_file;
mod mesh_overlap;
mod motion;
mod pair_map;
mod polyhedron;
mod proximity;
mod separating_plane;
mod shape;
mod split_mix;
mod surface_mesh;
mod sweep_prune;
mod toi;

pub use aabb::Aabb;
pub use contact::contacts;
pub use contact_point::{ContactKind, Feature, ShapeContact};
pub use convex_hull::ConvexHull;
pub use decompose::{Decomposed, Decomposition, MAX_DECOMPOSED_TRIANGLES};
pub use error::{ShapeError, LENGTH};
pub use fracture::{shared_faces, Cells, SharedFace, MAX_PIECES};
pub use mass_properties::{rotated_tensor, MassProperties};
pub use mesh_file::UpAxis;
pub use motion::Motion;
pub use polyhedron::Polyhedron;
pub use proximity::{distance, intersects};
pub use separating_plane::{separating_plane, PlaneSource, SeparatingPlane, SeparatingPlaneCache};
pub use shape::{Shape, TriMesh};
pub use split_mix::SplitMix;
pub use surface_mesh::{Mesh, MAX_TRIANGLES};
pub use sweep_prune::{brute_force_pairs, SortAndSweep, SweepStats};
pub use toi::{bisect_collision_time, first_contact, time_of_impact, Bisection, Impact, ToiMethod, ToiOptions};
