//! Particles: point masses obeying the chapter's m x'' + d x' + h (x - anchor) = sum F.

use crate::collider::Material;
use crate::error::WorldError;
use crate::limits;
use nalgebra::Vector3;

/// A particle in a world. Its state is read here; build one with [`ParticleBuilder`].
#[derive(Clone, Debug, PartialEq)]
pub struct Particle {
    pub(crate) mass: f64,
    pub(crate) position: Vector3<f64>,
    pub(crate) velocity: Vector3<f64>,
    pub(crate) damping: f64,
    pub(crate) stiffness: f64,
    pub(crate) anchor: Vector3<f64>,
    pub(crate) radius: f64,
    pub(crate) material: Material,
}

impl Particle {
    /// Mass m.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// Position x.
    pub fn position(&self) -> Vector3<f64> {
        self.position
    }
    /// Velocity v.
    pub fn velocity(&self) -> Vector3<f64> {
        self.velocity
    }
    /// Damping d of the chapter's equation.
    pub fn damping(&self) -> f64 {
        self.damping
    }
    /// Restoring stiffness h of the chapter's equation.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }
    /// The point the restoring term pulls towards (the origin, as in the chapter, unless set).
    pub fn anchor(&self) -> Vector3<f64> {
        self.anchor
    }
    /// Collision radius: a particle with a radius collides with bodies as a small sphere; 0 (the default) means it
    /// passes through everything.
    pub fn radius(&self) -> f64 {
        self.radius
    }
    /// The surface material of its collisions.
    pub fn material(&self) -> Material {
        self.material
    }
}

/// Describes a particle to add: `ParticleBuilder::new(mass).position(p).velocity(v)`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleBuilder {
    particle: Particle,
}

impl Default for ParticleBuilder {
    /// A 1 kg particle at rest at the origin (the API's default).
    fn default() -> Self {
        ParticleBuilder::new(1.0)
    }
}

impl ParticleBuilder {
    /// Mass (> 0).
    pub fn mass(mut self, m: f64) -> Self {
        self.particle.mass = m;
        self
    }
    /// Coefficient of restitution of its collisions.
    pub fn restitution(mut self, e: f64) -> Self {
        self.particle.material.restitution = e;
        self
    }
    /// Coefficient of friction of its collisions.
    pub fn friction(mut self, mu: f64) -> Self {
        self.particle.material.friction = mu;
        self
    }
    /// A particle of mass `mass` at rest at the origin, without damping or restoring force.
    pub fn new(mass: f64) -> Self {
        ParticleBuilder {
            particle: Particle {
                mass,
                position: Vector3::zeros(),
                velocity: Vector3::zeros(),
                damping: 0.0,
                stiffness: 0.0,
                anchor: Vector3::zeros(),
                radius: 0.0,
                material: Material::default(),
            },
        }
    }
    /// Collision radius (> 0 to collide with bodies; particles do not collide with each other).
    pub fn radius(mut self, r: f64) -> Self {
        self.particle.radius = r;
        self
    }
    /// The surface material of its collisions (restitution, friction and its own combine rules; a particle does
    /// not turn, so resistance to turning does nothing for it).
    pub fn material(mut self, m: Material) -> Self {
        self.particle.material = m;
        self
    }
    /// Initial position.
    pub fn position(mut self, p: Vector3<f64>) -> Self {
        self.particle.position = p;
        self
    }
    /// Initial velocity.
    pub fn velocity(mut self, v: Vector3<f64>) -> Self {
        self.particle.velocity = v;
        self
    }
    /// Damping d (force -d v).
    pub fn damping(mut self, d: f64) -> Self {
        self.particle.damping = d;
        self
    }
    /// Restoring stiffness h (force -h (x - anchor)).
    pub fn stiffness(mut self, h: f64) -> Self {
        self.particle.stiffness = h;
        self
    }
    /// The restoring term's anchor point.
    pub fn anchor(mut self, a: Vector3<f64>) -> Self {
        self.particle.anchor = a;
        self
    }

    /// Checks every field and returns the particle.
    pub(crate) fn build(self) -> Result<Particle, WorldError> {
        let p = self.particle;
        limits::mass("mass", p.mass)?;
        limits::vector("position", &p.position, limits::COORDINATE, "m")?;
        limits::vector("velocity", &p.velocity, limits::SPEED, "m/s")?;
        limits::non_negative("damping", p.damping, limits::STIFFNESS, "N s/m")?;
        limits::non_negative("stiffness", p.stiffness, limits::STIFFNESS, "N/m")?;
        limits::vector("anchor", &p.anchor, limits::COORDINATE, "m")?;
        if p.radius != 0.0 {
            let (lo, hi) = tumble_collide::LENGTH;
            limits::in_range("radius", p.radius, lo, hi, "m (or 0: no collisions)")?;
        }
        p.material.check()?;
        Ok(p)
    }
}
