//! tumble: particles and rigid bodies for physically based animation.
//!
//! A [`World`] holds particles (the chapter's m x'' + d x' + h x = sum F), rigid bodies (state x, q, P, L with a
//! unit quaternion), springs and loads, and steps them with any method of [`integrate`] (tumble-integrate). It
//! compiles its contents into a state vector that holds only what they need, reports what every step cost, and
//! leaves itself unchanged when a step fails.
//!
//! ```
//! use nalgebra::Vector3;
//! use tumble::{ParticleBuilder, World};
//! let mut world = World::new();
//! let p = world.add_particle(ParticleBuilder::new(1.0).velocity(Vector3::new(1.0, 0.0, 5.0))).unwrap();
//! world.step(1.0).unwrap();
//! let x = world.particle(p).unwrap().position();
//! assert!((x.z - (5.0 - 0.5 * 9.81)).abs() < 1e-9);
//! ```

#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod body;
mod body_builder;
mod collider;
mod control;
mod engine;
mod error;
mod handle;
mod joint;
mod keyframes;
mod limits;
mod load;
mod look;
mod mesh_shape;
mod mode;
mod model;
mod options;
mod particle;
mod persist;
mod plan;
mod report;
mod rollout;
mod run;
pub mod scenes;
mod spring;
mod world;

pub use body::{RigidBody, RigidBodyBuilder, ALL_GROUPS};
pub use collider::{Collider, Combine, CombineRules, Material};
pub use control::Control;
pub use error::WorldError;
pub use handle::Handle;
pub use keyframes::Keyframes;
pub use look::{Look, MAX_NAME};
/// The ranges of accepted values.
pub mod limit {
    pub use crate::limits::{COORDINATE, FORCE, GRAVITY, INERTIA, MASS, SPEED, STIFFNESS, TIME};
}
pub use joint::{Joint, JointBuilder, JointHandle, JointKind, JointMotor, JointSpring};
pub use load::{ForceCallback, Load, LoadHandle, Target, TargetState, Wrench};
pub use mesh_shape::MeshShape;
pub use mode::{
    AccurateSettings, AccurateSolver, FastFriction, FastSettings, FastSolver, Mode, Persistent, SoftSolver,
};
pub use model::ForceCounters;
pub use options::{mode_from, BodyOptions, IntegratorOptions, ModeOptions, WorldOptions, DEFAULT_DENSITY, DEFAULT_DT};
pub use particle::{Particle, ParticleBuilder};
pub use persist::{shape_from_json, shape_to_json};
pub use plan::{Plan, Stage, StageCounts};
pub use report::{ReportValue, WorldReport};
pub use rollout::{rollout, RolloutSettings};
pub use run::{Run, RunArrays, DEFAULT_FRAME_INTERVAL};
pub use spring::{Attachment, BodyHandle, ParticleHandle, Spring, SpringBuilder, SpringHandle};
pub use world::{
    bond_bounds, bonds, ContactInfo, Fractured, Glue, MaterialChange, SpringJacobian, World, WorldState, GLUE_WINDOW,
    MAX_STRENGTH, MIN_STRENGTH, SMALLEST_BOND,
};

/// Shapes and mass properties (tumble-collide).
pub use tumble_collide as collide;
pub use tumble_collide::{Cells, Decomposition, Mesh, Shape, SharedFace};
/// Contact response (tumble-contact).
pub use tumble_contact as contact;
/// The integrators (tumble-integrate).
pub use tumble_integrate as integrate;
pub use tumble_integrate::{Method, OdeError, Settings};
