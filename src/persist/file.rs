//! The scene file: what a saved world holds, as serde types. The same structure is written as readable JSON (a
//! person can write one by hand: most fields have defaults) and, after a versioned header, as compact binary.
//! Places: springs, loads and joints name particles and bodies by their place in the file's lists (the order of the
//! world's `particles()` and `bodies()`), as the world names them by handle.

use crate::collider::Material;
use crate::mode::Mode;
use crate::world::SpringJacobian;
use serde::{Deserialize, Serialize};
use tumble_collide::Decomposition;
use tumble_integrate::Settings;

/// The format's name, written first in a JSON file.
pub const FORMAT: &str = "tumble-scene";
/// The format's version: files of another version are refused with a clear error.
pub const VERSION: u32 = 1;

fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}
fn one() -> f64 {
    1.0
}
fn half() -> f64 {
    0.5
}
fn identity() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

/// A whole world.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Always "tumble-scene".
    pub format: String,
    /// The format's version (1).
    pub version: u32,
    #[serde(default)]
    pub time: f64,
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    /// How two materials combine where neither names its own rule (the geometric mean of the frictions and the
    /// larger restitution if absent).
    #[serde(default)]
    pub combine: crate::collider::CombineRules,
    /// Accurate (the default) or fast mode with its settings.
    #[serde(default)]
    pub mode: Mode,
    /// The integrator (accurate mode); Dormand-Prince at rtol 1e-6, atol 1e-9 if absent.
    #[serde(default)]
    pub integrator: Option<Settings>,
    /// Threads of the contact solves (0: one per core).
    #[serde(default)]
    pub threads: usize,
    #[serde(default)]
    pub divergence_factor: Option<f64>,
    #[serde(default)]
    pub spring_jacobian: Option<SpringJacobian>,
    #[serde(default)]
    pub particles: Vec<ParticleFile>,
    #[serde(default)]
    pub bodies: Vec<BodyFile>,
    #[serde(default)]
    pub springs: Vec<SpringFile>,
    #[serde(default)]
    pub loads: Vec<LoadFile>,
    #[serde(default)]
    pub joints: Vec<JointFile>,
    /// The engine's memory (base64 of its binary form), so that a loaded world continues bit for bit; null or
    /// absent in a scene written without it (or by hand), whose engine starts afresh.
    #[serde(default)]
    pub memory: Option<String>,
}

/// A particle.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct ParticleFile {
    #[serde(default = "one")]
    pub mass: f64,
    #[serde(default)]
    pub position: [f64; 3],
    #[serde(default)]
    pub velocity: [f64; 3],
    #[serde(default)]
    pub damping: f64,
    #[serde(default)]
    pub stiffness: f64,
    #[serde(default)]
    pub anchor: [f64; 3],
    #[serde(default)]
    pub radius: f64,
    #[serde(default = "half")]
    pub restitution: f64,
    #[serde(default = "half")]
    pub friction: f64,
    /// Rolling and torsional resistance, and the surface's own combine rules (absent: none, the world's).
    #[serde(default)]
    pub rolling_resistance: f64,
    #[serde(default)]
    pub torsional_resistance: f64,
    #[serde(default)]
    pub friction_combine: Option<crate::collider::Combine>,
    #[serde(default)]
    pub restitution_combine: Option<crate::collider::Combine>,
    /// The state `reset` returns to (position, velocity); the loaded state if absent.
    #[serde(default)]
    pub start: Option<[[f64; 3]; 2]>,
}

/// A shape, in its collider's frame.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeFile {
    Sphere {
        radius: f64,
    },
    Box {
        half_extents: [f64; 3],
    },
    Capsule {
        half_height: f64,
        radius: f64,
    },
    Cylinder {
        half_height: f64,
        radius: f64,
    },
    /// A hull: of the points, or, given its faces (a convex mesh made its own hull), of those faces as they are.
    ConvexHull {
        points: Vec<[f64; 3]>,
        #[serde(default)]
        faces: Option<Vec<[u32; 3]>>,
    },
    TriMesh {
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
    },
    /// A closed mesh: exact on a static body, decomposed (with `decomposition`, else the defaults) on a moving one.
    Mesh {
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        #[serde(default)]
        name: String,
        #[serde(default)]
        decomposition: Option<Decomposition>,
    },
    /// A closed mesh and its convex pieces (point sets), as saved: loading does not decompose it again.
    DecomposedMesh {
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        #[serde(default)]
        name: String,
        decomposition: Decomposition,
        pieces: Vec<Vec<[f64; 3]>>,
        #[serde(default)]
        seconds: f64,
    },
    HalfSpace {
        normal: [f64; 3],
    },
}

/// A shape placed in its body's frame (relative to the centre of mass when the body's mass and inertia are given,
/// else to the body's origin).
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct ColliderFile {
    pub shape: ShapeFile,
    #[serde(default)]
    pub position: [f64; 3],
    #[serde(default = "identity")]
    pub orientation: [f64; 4],
}

/// A body's start as written: position, orientation (w, x, y, z), momentum, angular momentum.
pub type BodyStartFile = ([f64; 3], [f64; 4], [f64; 3], [f64; 3]);

/// A rigid body: either `mass` and `inertia` with colliders placed about the centre of mass (as saved, exact), or
/// colliders with a `density` or a `mass` that give its mass properties (as a person writes it).
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    #[serde(default, rename = "static")]
    pub is_static: bool,
    #[serde(default)]
    pub colliders: Vec<ColliderFile>,
    #[serde(default)]
    pub mass: Option<f64>,
    #[serde(default)]
    pub inertia: Option<[[f64; 3]; 3]>,
    #[serde(default)]
    pub density: Option<f64>,
    #[serde(default)]
    pub position: [f64; 3],
    /// (w, x, y, z).
    #[serde(default = "identity")]
    pub orientation: [f64; 4],
    /// Velocity (m/s), or `momentum` (kg m/s, exact) instead.
    #[serde(default)]
    pub velocity: Option<[f64; 3]>,
    #[serde(default)]
    pub momentum: Option<[f64; 3]>,
    /// Angular velocity (rad/s, world axes), or `angular_momentum` (kg m^2/s, exact) instead.
    #[serde(default)]
    pub angular_velocity: Option<[f64; 3]>,
    #[serde(default)]
    pub angular_momentum: Option<[f64; 3]>,
    #[serde(default)]
    pub linear_damping: f64,
    #[serde(default)]
    pub angular_damping: f64,
    #[serde(default = "half")]
    pub restitution: f64,
    #[serde(default = "half")]
    pub friction: f64,
    /// Rolling and torsional resistance, and the surface's own combine rules (absent: none, the world's).
    #[serde(default)]
    pub rolling_resistance: f64,
    #[serde(default)]
    pub torsional_resistance: f64,
    #[serde(default)]
    pub friction_combine: Option<crate::collider::Combine>,
    #[serde(default)]
    pub restitution_combine: Option<crate::collider::Combine>,
    /// The state `reset` returns to: position, orientation (w, x, y, z), momentum, angular momentum.
    #[serde(default)]
    pub start: Option<BodyStartFile>,
    /// Where the modelled frame's origin sits in the body frame (as saved; absent, it comes from the shapes).
    #[serde(default)]
    pub origin: Option<[f64; 3]>,
    /// Its collision groups (a bit each), if not all of them.
    #[serde(default)]
    pub collision_groups: Option<u32>,
    /// Its name and colour (linear RGBA), if given.
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    pub color: Option<[f64; 4]>,
    /// A kinematic body's path (its shapes' frame at each keyframe).
    #[serde(default)]
    pub keyframes: Option<KeyframesFile>,
}

/// Keyframed poses: times (s), positions (m) and orientations (w, x, y, z), one each a keyframe.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct KeyframesFile {
    pub times: Vec<f64>,
    pub positions: Vec<[f64; 3]>,
    pub orientations: Vec<[f64; 4]>,
}

/// A spring's end.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum AttachmentFile {
    /// The particle at this place.
    Particle(usize),
    /// A point of the body at this place, in its frame (relative to its centre of mass).
    Body { body: usize, anchor: [f64; 3] },
    /// A fixed point of space.
    Point([f64; 3]),
}

/// A damped spring.
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SpringFile {
    pub a: AttachmentFile,
    pub b: AttachmentFile,
    #[serde(default = "one")]
    pub stiffness: f64,
    #[serde(default)]
    pub damping: f64,
    /// The distance between the ends when loaded if absent.
    #[serde(default)]
    pub rest_length: Option<f64>,
}

/// What a load acts on.
#[derive(Serialize, Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TargetFile {
    Particle(usize),
    Body(usize),
}

/// A constant load (callbacks are code, which a file cannot hold).
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LoadFile {
    Force { target: TargetFile, force: [f64; 3], at: Option<[f64; 3]> },
    Torque { body: usize, torque: [f64; 3] },
}

fn x_axis() -> [f64; 3] {
    [1.0, 0.0, 0.0]
}

/// A joint between the bodies at places `a` and `b` (absent: the world, whose anchor is a world point).
#[derive(Serialize, Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct JointFile {
    pub kind: crate::joint::JointKind,
    #[serde(default)]
    pub a: Option<usize>,
    #[serde(default)]
    pub b: Option<usize>,
    #[serde(default)]
    pub anchor_a: [f64; 3],
    #[serde(default)]
    pub anchor_b: [f64; 3],
    /// The axis in A's frame.
    #[serde(default = "x_axis")]
    pub axis: [f64; 3],
    #[serde(default)]
    pub limits: Option<[f64; 2]>,
    /// A piston's limits on its turn (rad).
    #[serde(default)]
    pub turn_limits: Option<[f64; 2]>,
    #[serde(default)]
    pub motor: Option<crate::joint::JointMotor>,
    #[serde(default)]
    pub spring: Option<crate::joint::JointSpring>,
    /// Stiffness (Hz) and damping ratio of a soft joint.
    #[serde(default)]
    pub softness: Option<[f64; 2]>,
    /// The joint's zero: B's rotation relative to A's (w, x, y, z) and the axis in B's frame, as when it was made;
    /// absent: the bodies as they are loaded.
    #[serde(default)]
    pub reference: Option<[f64; 4]>,
    #[serde(default)]
    pub axis_b: Option<[f64; 3]>,
    /// The force (N) and the torque (N m) past which it breaks; absent: no bound.
    #[serde(default)]
    pub breaking_force: Option<f64>,
    #[serde(default)]
    pub breaking_torque: Option<f64>,
    /// Whether it has broken.
    #[serde(default)]
    pub broken: bool,
    /// Whether its bodies collide with each other.
    #[serde(default)]
    pub collide: bool,
    /// The window its load is averaged over before it is judged (s); absent: 0, the load at the instant.
    #[serde(default)]
    pub breaking_window: f64,
    /// Whether it binds its bodies into one piece with those other such joints bind (a glued object's welds).
    #[serde(default)]
    pub cluster: bool,
}

/// A file's material fields as a material.
macro_rules! material_fields {
    ($t:ty) => {
        impl $t {
            pub fn material(&self) -> Material {
                Material {
                    restitution: self.restitution,
                    friction: self.friction,
                    rolling_resistance: self.rolling_resistance,
                    torsional_resistance: self.torsional_resistance,
                    friction_combine: self.friction_combine,
                    restitution_combine: self.restitution_combine,
                }
            }
        }
    };
}
material_fields!(ParticleFile);
material_fields!(BodyFile);
