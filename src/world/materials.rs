//! Changing a surface between steps (`set_material`): a particle's or body's restitution and friction, for the
//! contacts found from the next step on. The engine keeps its memory (warm starts, the touching phase, sleep): only
//! the colliders' materials change, in the world, in the engine's colliders, and so in copies and files.

use super::{unknown, World};
use crate::collider::Material;
use crate::error::WorldError;
use crate::load::Target;

impl World {
    /// Sets the friction and restitution (either left as it is when `None`) of a particle's or body's surfaces
    /// (static bodies included), between steps, in either mode. A bad value is an error naming it, and the world
    /// is left as it was.
    pub fn set_material(
        &mut self,
        target: Target,
        friction: Option<f64>,
        restitution: Option<f64>,
    ) -> Result<(), WorldError> {
        let old = match target {
            Target::Particle(h) => self.particles.get(h).ok_or_else(|| unknown("target", h))?.material,
            Target::Body(h) => self.bodies.get(h).ok_or_else(|| unknown("target", h))?.material,
        };
        let new = Material {
            friction: friction.unwrap_or(old.friction),
            restitution: restitution.unwrap_or(old.restitution),
        };
        new.check()?;
        match target {
            Target::Particle(h) => self.particles.get_mut(h).expect("checked above").material = new,
            Target::Body(h) => self.bodies.get_mut(h).expect("checked above").material = new,
        }
        #[cfg(feature = "contact")]
        if let Some(actor) = self.actor_of(target) {
            if let Some(engine) = &mut self.engine {
                engine.set_material(actor, new);
            }
        }
        Ok(())
    }

    /// The index of a particle or body among the engine's actors (particles, then dynamic bodies, then static
    /// bodies), if the world has an engine.
    #[cfg(feature = "contact")]
    fn actor_of(&self, target: Target) -> Option<usize> {
        let rows = self.engine.as_ref()?.rows();
        let (np, nb) = (rows.particles.len(), rows.bodies.len());
        match target {
            Target::Particle(h) => rows.particles.iter().position(|&p| p == h),
            Target::Body(h) => rows.bodies.iter().position(|&b| b == h).map(|j| np + j).or_else(|| {
                let statics = self.bodies.iter().filter(|(_, b)| b.is_static);
                statics.map(|(s, _)| s).position(|s| s == h).map(|s| np + nb + s)
            }),
        }
    }
}
