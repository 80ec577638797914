//! The crate's integration tests, linked as one binary: each file a module; `common` what they share.

mod aabb;
mod common;
mod contacts;
mod fracture;
mod irregular_hulls;
mod mass_properties;
mod mesh_mass;
mod separating_plane;
mod sweep_prune;
mod toi;
mod touching_hulls;
