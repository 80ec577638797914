//! Loads on particles and bodies: constant forces (at the centre of mass or at a body point), constant torques,
//! and user callbacks that return a force and torque from the target's state.

use crate::handle::Handle;
use crate::spring::{BodyHandle, ParticleHandle};
use nalgebra::{UnitQuaternion, Vector3};
use std::sync::{Arc, Mutex};

/// Handle of a load.
pub type LoadHandle = Handle<Load>;

/// What a load acts on; also a side of a contact (`World::contacts`, where it may be a static body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// A particle.
    Particle(ParticleHandle),
    /// A dynamic body.
    Body(BodyHandle),
}

/// The state a callback sees: of a particle (orientation identity, angular velocity zero) or a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetState {
    /// Position (a body's centre of mass).
    pub position: Vector3<f64>,
    /// Velocity.
    pub velocity: Vector3<f64>,
    /// Orientation.
    pub orientation: UnitQuaternion<f64>,
    /// Angular velocity.
    pub angular_velocity: Vector3<f64>,
}

/// A force through the centre of mass and a torque (the torque is ignored for particles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wrench {
    /// Force.
    pub force: Vector3<f64>,
    /// Torque about the centre of mass.
    pub torque: Vector3<f64>,
}

/// A user force: called with the time and the target's state; an `Err` stops the step with that message.
pub type ForceCallback = Arc<Mutex<dyn FnMut(f64, &TargetState) -> Result<Wrench, String> + Send>>;

/// A load in a world.
#[derive(Clone)]
pub enum Load {
    /// A constant force, fixed in world axes, at the centre of mass or at a body point (body frame, relative to
    /// the centre of mass), which then also exerts the torque (r - x) x F.
    Force { target: Target, force: Vector3<f64>, at: Option<Vector3<f64>> },
    /// A constant torque, world axes.
    Torque { body: BodyHandle, torque: Vector3<f64> },
    /// A callback evaluated at every right-hand side.
    Callback { target: Target, callback: ForceCallback },
}

impl std::fmt::Debug for Load {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Load::Force { target, force, at } => write!(f, "Force {{ {target:?}, {force:?}, at {at:?} }}"),
            Load::Torque { body, torque } => write!(f, "Torque {{ {body:?}, {torque:?} }}"),
            Load::Callback { target, .. } => write!(f, "Callback {{ {target:?} }}"),
        }
    }
}

impl Load {
    /// A callback load from a closure.
    pub fn callback(
        target: Target,
        f: impl FnMut(f64, &TargetState) -> Result<Wrench, String> + Send + 'static,
    ) -> Load {
        Load::Callback { target, callback: Arc::new(Mutex::new(f)) }
    }

    pub(crate) fn target(&self) -> Target {
        match self {
            Load::Force { target, .. } | Load::Callback { target, .. } => *target,
            Load::Torque { body, .. } => Target::Body(*body),
        }
    }
}
