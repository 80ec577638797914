//! Changing a surface between steps (`set_material`): a particle's or body's restitution, friction, resistance to
//! turning and combine rules, for the contacts found from the next step on. The engine keeps its memory (warm
//! starts, the touching phase, sleep): only the colliders' materials change, in the world, in the engine's
//! colliders, and so in copies and files.

use super::{unknown, World};
use crate::collider::{Combine, Material};
use crate::error::WorldError;
use crate::load::Target;

/// What `World::set_material` changes: each field given replaces the surface's own, the rest are kept.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialChange {
    pub friction: Option<f64>,
    pub restitution: Option<f64>,
    pub rolling_resistance: Option<f64>,
    pub torsional_resistance: Option<f64>,
    /// The surface's own combine rule (`Some(None)`: the world's again).
    pub friction_combine: Option<Option<Combine>>,
    pub restitution_combine: Option<Option<Combine>>,
}

impl MaterialChange {
    /// `old` with the change made.
    pub fn applied_to(&self, old: Material) -> Material {
        Material {
            friction: self.friction.unwrap_or(old.friction),
            restitution: self.restitution.unwrap_or(old.restitution),
            rolling_resistance: self.rolling_resistance.unwrap_or(old.rolling_resistance),
            torsional_resistance: self.torsional_resistance.unwrap_or(old.torsional_resistance),
            friction_combine: self.friction_combine.unwrap_or(old.friction_combine),
            restitution_combine: self.restitution_combine.unwrap_or(old.restitution_combine),
        }
    }
}

impl World {
    /// Changes a particle's or body's surface (static bodies included; what `change` leaves as `None` is kept),
    /// between steps, in either mode. A bad value is an error naming it, and the world is left as it was.
    pub fn set_material(&mut self, target: Target, change: MaterialChange) -> Result<(), WorldError> {
        let old = match target {
            Target::Particle(h) => self.particles.get(h).ok_or_else(|| unknown("target", h))?.material,
            Target::Body(h) => self.bodies.get(h).ok_or_else(|| unknown("target", h))?.material,
        };
        let new = change.applied_to(old);
        new.check()?;
        new.fits_mode(&self.mode).map_err(|why| WorldError::invalid("rolling_resistance", why))?;
        match target {
            Target::Particle(h) => self.particles.get_mut(h).expect("checked above").material = new,
            Target::Body(h) => self.bodies.get_mut(h).expect("checked above").material = new,
        }
        if let Some(actor) = self.actor_of(target) {
            if let Some(engine) = &mut self.engine {
                engine.set_material(actor, new);
            }
        }
        Ok(())
    }

    /// The index of a particle or body among the engine's actors (particles, then dynamic bodies, then static
    /// bodies), if the world has an engine.
    fn actor_of(&self, target: Target) -> Option<usize> {
        let handles = self.engine.as_ref()?.handles();
        let (np, nb) = (handles.particles.len(), handles.bodies.len());
        match target {
            Target::Particle(h) => handles.particles.iter().position(|&p| p == h),
            Target::Body(h) => handles.bodies.iter().position(|&b| b == h).map(|j| np + j).or_else(|| {
                let statics = self.bodies.iter().filter(|(_, b)| b.is_static);
                statics.map(|(s, _)| s).position(|s| s == h).map(|s| np + nb + s)
            }),
        }
    }
}
