//! Rigid bodies: mass, body-frame inertia tensor about the centre of mass, and the state (x, q, P, L) of the
//! chapter with a unit quaternion in place of the rotation matrix.

use crate::collider::{Collider, Material};
use crate::keyframes::Keyframes;
use crate::look::Look;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use std::sync::Arc;
use tumble_collide::rotated_tensor;
use tumble_collide::Shape;

pub(crate) use crate::body_builder::still;
pub use crate::body_builder::RigidBodyBuilder;

/// A rigid body in a world. Its position is that of its centre of mass, its axes those its shapes are given in; the
/// origin of that modelled frame sits at `origin_offset` in the body frame. Build one with [`RigidBodyBuilder`]
/// (`body_builder.rs`).
#[derive(Clone, Debug)]
pub struct RigidBody {
    pub(crate) mass: f64,
    pub(crate) inertia: Matrix3<f64>,
    pub(crate) inv_inertia: Matrix3<f64>,
    pub(crate) colliders: Vec<Collider>,
    /// Where the modelled frame's origin (the first shape's frame) sits in the body frame: minus the centre of mass
    /// in the shapes' coordinates (zero for a body given by mass and inertia).
    pub(crate) origin: Vector3<f64>,
    pub(crate) position: Vector3<f64>,
    pub(crate) orientation: UnitQuaternion<f64>,
    pub(crate) momentum: Vector3<f64>,
    pub(crate) angular_momentum: Vector3<f64>,
    pub(crate) linear_damping: f64,
    pub(crate) angular_damping: f64,
    pub(crate) material: Material,
    pub(crate) is_static: bool,
    /// What the user calls it and how it is drawn: kept by files, copies and runs, written by the exporters.
    pub(crate) look: Look,
    /// Its collision groups: two bodies touch only if their groups share a bit (all bits by default).
    pub(crate) groups: u32,
    /// A kinematic body's path and its velocities now.
    pub(crate) kinematic: Option<Kinematic>,
}

/// A kinematic body's path and where along it the body is: its velocities at the world's time (the engines keep
/// them in the state, as a dynamic body's momenta).
#[derive(Clone, Debug)]
pub(crate) struct Kinematic {
    pub path: Arc<Keyframes>,
    pub velocity: Vector3<f64>,
    pub angular_velocity: Vector3<f64>,
}

/// Every collision group: a body's by default.
pub const ALL_GROUPS: u32 = u32::MAX;

impl RigidBody {
    /// Its name, if it was given one.
    pub fn name(&self) -> Option<&str> {
        self.look.name.as_deref()
    }

    /// Its colour (linear RGBA), if it was given one.
    pub fn color(&self) -> Option<[f64; 4]> {
        self.look.color
    }

    /// Its collision groups (a bit each): it touches only bodies whose groups share a bit with its own.
    pub fn collision_groups(&self) -> u32 {
        self.groups
    }

    /// Mass M (infinite for a static or kinematic body).
    pub fn mass(&self) -> f64 {
        if self.is_static || self.kinematic.is_some() {
            f64::INFINITY
        } else {
            self.mass
        }
    }
    /// Inertia tensor about the centre of mass, body axes.
    pub fn inertia(&self) -> Matrix3<f64> {
        self.inertia
    }
    /// World inertia tensor I(t) = R I_body R^T.
    pub fn world_inertia(&self) -> Matrix3<f64> {
        let r = self.orientation.to_rotation_matrix();
        rotated_tensor(r.matrix(), &self.inertia)
    }
    /// Centre-of-mass position x.
    pub fn position(&self) -> Vector3<f64> {
        self.position
    }
    /// World position of the modelled frame's origin: where the shapes' coordinates (a mesh's or a hull's vertices,
    /// the first shape of a body of colliders) have their origin, `x + R origin_offset`.
    pub fn origin(&self) -> Vector3<f64> {
        self.position + self.orientation * self.origin
    }
    /// Where the modelled frame's origin sits in the body frame (minus the centre of mass in the shapes'
    /// coordinates).
    pub fn origin_offset(&self) -> Vector3<f64> {
        self.origin
    }
    /// Orientation q (body to world).
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        self.orientation
    }
    /// Linear momentum P.
    pub fn momentum(&self) -> Vector3<f64> {
        self.momentum
    }
    /// Angular momentum L about the centre of mass, world axes.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.angular_momentum
    }
    /// Velocity v = P / M.
    pub fn velocity(&self) -> Vector3<f64> {
        if let Some(k) = &self.kinematic {
            k.velocity
        } else if self.is_static {
            Vector3::zeros()
        } else {
            self.momentum / self.mass
        }
    }
    /// Angular velocity w = I(t)^-1 L.
    pub fn angular_velocity(&self) -> Vector3<f64> {
        if let Some(k) = &self.kinematic {
            return k.angular_velocity;
        }
        if self.is_static {
            return Vector3::zeros();
        }
        let r = self.orientation.to_rotation_matrix();
        rotated_tensor(r.matrix(), &self.inv_inertia) * self.angular_momentum
    }
    /// Velocity of a world point r attached to the body: w x (r - x) + v.
    pub fn point_velocity(&self, r: Vector3<f64>) -> Vector3<f64> {
        self.angular_velocity().cross(&(r - self.position)) + self.velocity()
    }
    /// World position of a point given in the body frame (relative to the centre of mass).
    pub fn world_point(&self, local: Vector3<f64>) -> Vector3<f64> {
        self.position + self.orientation * local
    }
    /// The first collider's shape, if any.
    pub fn shape(&self) -> Option<&Shape> {
        self.colliders.first().map(|c| &c.shape)
    }
    /// Where the first collider's frame sits in the body frame (its translation).
    pub fn shape_offset(&self) -> Vector3<f64> {
        self.colliders.first().map_or(Vector3::zeros(), |c| c.offset.translation.vector)
    }
    /// The colliders, posed in the body frame.
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }
    /// The world pose of the body frame.
    pub fn pose(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.position), self.orientation)
    }
    /// The surface material.
    pub fn material(&self) -> Material {
        self.material
    }
    /// Whether the body is static (immovable, not integrated).
    pub fn is_static(&self) -> bool {
        self.is_static
    }
    /// Whether the body is kinematic: it follows its keyframes, pushes what it touches and is never pushed back.
    pub fn is_kinematic(&self) -> bool {
        self.kinematic.is_some()
    }
    /// A kinematic body's path.
    pub fn keyframes(&self) -> Option<&Keyframes> {
        self.kinematic.as_ref().map(|k| &*k.path)
    }
    /// Puts a kinematic body where its path has it at time t, with the velocities it moves on at.
    pub(crate) fn follow(&mut self, t: f64) {
        if let Some(k) = &mut self.kinematic {
            let pose = k.path.pose_at(t);
            self.position = pose.translation.vector;
            self.orientation = pose.rotation;
            (k.velocity, k.angular_velocity) = k.path.velocity_at(t);
        }
    }
    /// Coefficient of restitution (used by contact).
    pub fn restitution(&self) -> f64 {
        self.material.restitution
    }
    /// Coefficient of friction (used by contact).
    pub fn friction(&self) -> f64 {
        self.material.friction
    }
}
