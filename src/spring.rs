//! Damped springs between particles, points of bodies and fixed points of space.

use crate::body::RigidBody;
use crate::handle::Handle;
use crate::particle::Particle;
use nalgebra::Vector3;

/// Handle of a particle.
pub type ParticleHandle = Handle<Particle>;
/// Handle of a rigid body.
pub type BodyHandle = Handle<RigidBody>;
/// Handle of a spring.
pub type SpringHandle = Handle<Spring>;

/// What a spring end is attached to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attachment {
    /// A particle.
    Particle(ParticleHandle),
    /// A point of a body, in the body frame relative to its centre of mass.
    Body(BodyHandle, Vector3<f64>),
    /// A fixed point of space.
    Point(Vector3<f64>),
}

/// A spring: force on end a is -(k (l - l0) + c (v_a - v_b) . n) n, with n the unit vector from b to a and l their
/// distance; end b gets the opposite force. A body end also gets the force's torque about its centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub(crate) a: Attachment,
    pub(crate) b: Attachment,
    pub(crate) stiffness: f64,
    pub(crate) damping: f64,
    pub(crate) rest_length: f64,
}

impl Spring {
    /// First end.
    pub fn a(&self) -> Attachment {
        self.a
    }
    /// Second end.
    pub fn b(&self) -> Attachment {
        self.b
    }
    /// Stiffness k.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }
    /// Damping c.
    pub fn damping(&self) -> f64 {
        self.damping
    }
    /// Rest length l0.
    pub fn rest_length(&self) -> f64 {
        self.rest_length
    }
}

/// Describes a spring to add: `SpringBuilder::new(a, b).stiffness(k).damping(c)`. Without a rest length, the
/// distance between the ends when it is added.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringBuilder {
    pub(crate) a: Attachment,
    pub(crate) b: Attachment,
    pub(crate) stiffness: f64,
    pub(crate) damping: f64,
    pub(crate) rest_length: Option<f64>,
}

impl SpringBuilder {
    /// A spring between `a` and `b` with stiffness 1 and no damping.
    pub fn new(a: Attachment, b: Attachment) -> Self {
        SpringBuilder { a, b, stiffness: 1.0, damping: 0.0, rest_length: None }
    }
    /// Stiffness k > 0.
    pub fn stiffness(mut self, k: f64) -> Self {
        self.stiffness = k;
        self
    }
    /// Damping c >= 0.
    pub fn damping(mut self, c: f64) -> Self {
        self.damping = c;
        self
    }
    /// Rest length l0 >= 0.
    pub fn rest_length(mut self, l0: f64) -> Self {
        self.rest_length = Some(l0);
        self
    }
}
