//! A world's state: setting a particle's or body's state (the engine takes it at the next step), and reading
//! objects, energies and momenta.

use super::{unknown, World};
use crate::body::RigidBody;
use crate::error::{check_finite, WorldError};
#[cfg(test)]
use crate::handle::Arena;
use crate::limits;
use crate::model::{compile, Compiled, Model};
use crate::particle::Particle;
use crate::spring::{BodyHandle, ParticleHandle, Spring, SpringHandle};
use crate::SpringJacobian;
use nalgebra::{UnitQuaternion, Vector3};

impl World {
    /// Sets a particle's position and velocity.
    pub fn set_particle_state(
        &mut self,
        h: ParticleHandle,
        position: Vector3<f64>,
        velocity: Vector3<f64>,
    ) -> Result<(), WorldError> {
        limits::vector("position", &position, limits::COORDINATE, "m")?;
        limits::vector("velocity", &velocity, limits::SPEED, "m/s")?;
        let p = self.particles.get_mut(h).ok_or_else(|| unknown("particle", h))?;
        p.position = position;
        p.velocity = velocity;
        self.state_changed = true;
        if !self.stepped {
            self.record_particle_start(h);
        }
        Ok(())
    }

    /// Sets a body's pose, velocity and angular velocity (world axes). A static body is moved to the pose (its
    /// velocities must be zero: it does not move).
    pub fn set_body_state(
        &mut self,
        h: BodyHandle,
        position: Vector3<f64>,
        orientation: UnitQuaternion<f64>,
        velocity: Vector3<f64>,
        angular_velocity: Vector3<f64>,
    ) -> Result<(), WorldError> {
        limits::vector("position", &position, limits::COORDINATE, "m")?;
        check_finite("orientation", orientation.coords.iter())?;
        limits::vector("velocity", &velocity, limits::SPEED, "m/s")?;
        limits::vector("angular_velocity", &angular_velocity, limits::SPEED, "rad/s")?;
        let b = self.bodies.get_mut(h).ok_or_else(|| unknown("body", h))?;
        if b.is_kinematic() {
            return Err(WorldError::invalid("body", "a kinematic body follows its keyframes: its state cannot be set"));
        }
        if b.is_static {
            crate::body::still("velocity", &velocity)?;
            crate::body::still("angular_velocity", &angular_velocity)?;
            b.position = position;
            b.orientation = orientation;
            self.retire_engine();
        } else {
            b.position = position;
            b.orientation = orientation;
            b.momentum = velocity * b.mass;
            b.angular_momentum = b.world_inertia() * angular_velocity;
            self.state_changed = true;
        }
        if !self.stepped {
            self.record_body_start(h);
        }
        Ok(())
    }
    /// A particle.
    pub fn particle(&self, h: ParticleHandle) -> Result<&Particle, WorldError> {
        self.particles.get(h).ok_or_else(|| unknown("particle", h))
    }

    /// A body.
    pub fn body(&self, h: BodyHandle) -> Result<&RigidBody, WorldError> {
        self.bodies.get(h).ok_or_else(|| unknown("body", h))
    }

    /// A spring.
    pub fn spring(&self, h: SpringHandle) -> Result<&Spring, WorldError> {
        self.springs.get(h).ok_or_else(|| unknown("spring", h))
    }

    /// All particles, in the order of the state vector.
    pub fn particles(&self) -> impl Iterator<Item = (ParticleHandle, &Particle)> {
        self.particles.iter()
    }

    /// All bodies (static ones included), in the world's order.
    pub fn bodies(&self) -> impl Iterator<Item = (BodyHandle, &RigidBody)> {
        self.bodies.iter()
    }

    /// All springs.
    pub fn springs(&self) -> impl Iterator<Item = (SpringHandle, &Spring)> {
        self.springs.iter()
    }

    /// Number of particles.
    pub fn particle_count(&self) -> usize {
        self.particles.len()
    }

    /// Number of bodies (static ones included).
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    pub(crate) fn compile(&self) -> Compiled {
        let mut c = compile(self.gravity, &self.particles, &self.bodies, &self.springs, &self.loads, &self.joints);
        c.model.definite_springs = self.spring_jacobian() == SpringJacobian::Definite;
        c
    }

    #[cfg(test)]
    pub(crate) fn particles_arena(&self) -> &Arena<Particle> {
        &self.particles
    }

    #[cfg(test)]
    pub(crate) fn bodies_arena(&self) -> &Arena<RigidBody> {
        &self.bodies
    }

    /// Evaluates `f` on the current model and state.
    fn with_state<R>(&self, f: impl FnOnce(&Model, &[f64]) -> R) -> R {
        match &self.engine {
            Some(e) if !self.state_changed => f(e.model(), e.state()),
            _ => {
                let c = self.compile();
                let y = c.handles.pack(&self.particles, &self.bodies);
                f(&c.model, &y)
            }
        }
    }

    /// Kinetic energy: 1/2 m v^2 of particles, 1/2 P^2/M + 1/2 L . w of bodies.
    pub fn kinetic_energy(&self) -> f64 {
        self.with_state(|m, y| m.kinetic_energy(y))
    }

    /// Potential energy of gravity, springs and the particles' restoring terms.
    pub fn potential_energy(&self) -> f64 {
        self.with_state(|m, y| m.potential_energy(y))
    }

    /// Total linear momentum.
    pub fn momentum(&self) -> Vector3<f64> {
        self.with_state(|m, y| m.momentum(y))
    }

    /// Total angular momentum about the origin.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.with_state(|m, y| m.angular_momentum(y))
    }
}
