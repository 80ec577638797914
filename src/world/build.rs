//! Building a world: adding particles, bodies, springs and loads (joints: `joints.rs`), each checked where it
//! enters, and removing them with what hangs on them. Any change of structure retires the engine; the next step compiles anew.

use super::{unknown, World};
use crate::body::{RigidBody, RigidBodyBuilder};
use crate::error::WorldError;
use crate::limits;
use crate::load::{Load, LoadHandle, Target, TargetState, Wrench};
use crate::particle::{Particle, ParticleBuilder};
use crate::spring::{Attachment, BodyHandle, ParticleHandle, Spring, SpringBuilder, SpringHandle};
use nalgebra::Vector3;

impl World {
    /// Adds a particle.
    pub fn add_particle(&mut self, particle: ParticleBuilder) -> Result<ParticleHandle, WorldError> {
        let p = particle.build()?;
        p.material.fits_mode(&self.mode).map_err(|why| WorldError::invalid("rolling_resistance", why))?;
        self.retire_engine();
        let h = self.particles.insert(p);
        self.record_particle_start(h);
        Ok(h)
    }

    /// Adds a rigid body.
    pub fn add_body(&mut self, body: RigidBodyBuilder) -> Result<BodyHandle, WorldError> {
        let b = self.built_body(body)?;
        Ok(self.insert_body(b))
    }

    /// `body` built and checked against the world's mode, not yet added.
    pub(crate) fn built_body(&self, body: RigidBodyBuilder) -> Result<crate::body::RigidBody, WorldError> {
        let b = body.build()?;
        b.material.fits_mode(&self.mode).map_err(|why| WorldError::invalid("rolling_resistance", why))?;
        Ok(b)
    }

    /// Adds a body built by `built_body`, on its path if it is kinematic.
    pub(crate) fn insert_body(&mut self, mut b: crate::body::RigidBody) -> BodyHandle {
        b.follow(self.time);
        self.retire_engine();
        let h = self.bodies.insert(b);
        self.record_body_start(h);
        h
    }

    fn attachment_point(&self, name: &'static str, a: &Attachment) -> Result<Vector3<f64>, WorldError> {
        match *a {
            Attachment::Particle(h) => Ok(self.particles.get(h).ok_or_else(|| unknown(name, h))?.position),
            Attachment::Body(h, local) => {
                limits::vector(if name == "a" { "anchor_a" } else { "anchor_b" }, &local, limits::COORDINATE, "m")?;
                Ok(self.bodies.get(h).ok_or_else(|| unknown(name, h))?.world_point(local))
            }
            Attachment::Point(p) => {
                limits::vector("world_point", &p, limits::COORDINATE, "m")?;
                Ok(p)
            }
        }
    }

    /// Adds a spring; without a rest length, the current distance between its ends.
    pub fn add_spring(&mut self, spring: SpringBuilder) -> Result<SpringHandle, WorldError> {
        let pa = self.attachment_point("a", &spring.a)?;
        let pb = self.attachment_point("b", &spring.b)?;
        if let (Attachment::Point(_), Attachment::Point(_)) = (spring.a, spring.b) {
            return Err(WorldError::invalid("b", "a spring between two fixed points acts on nothing"));
        }
        if let (Attachment::Particle(a), Attachment::Particle(b)) = (spring.a, spring.b) {
            if a == b {
                return Err(WorldError::invalid("b", "a spring needs two different ends"));
            }
        }
        let stiffness = limits::positive("stiffness", spring.stiffness, limits::STIFFNESS, "N/m")?;
        let damping = limits::non_negative("damping", spring.damping, limits::STIFFNESS, "N s/m")?;
        let rest_length = match spring.rest_length {
            Some(l) => limits::non_negative("rest_length", l, 4.0 * limits::COORDINATE, "m")?,
            None => (pa - pb).norm(),
        };
        self.retire_engine();
        Ok(self.springs.insert(Spring { a: spring.a, b: spring.b, stiffness, damping, rest_length }))
    }

    fn check_target(&self, t: Target) -> Result<(), WorldError> {
        match t {
            Target::Particle(h) => self.particles.get(h).map(|_| ()).ok_or_else(|| unknown("target", h)),
            Target::Body(h) => match self.bodies.get(h) {
                None => Err(unknown("target", h)),
                Some(b) if b.is_static => {
                    Err(WorldError::invalid("target", "a static body does not move: a load on it has no effect"))
                }
                Some(b) if b.is_kinematic() => Err(WorldError::invalid(
                    "target",
                    "a kinematic body follows its keyframes: a load on it has no effect",
                )),
                Some(_) => Ok(()),
            },
        }
    }

    /// Adds a load.
    pub fn add_load(&mut self, load: Load) -> Result<LoadHandle, WorldError> {
        self.check_target(load.target())?;
        match &load {
            Load::Force { target, force, at } => {
                limits::vector("force", force, limits::FORCE, "N")?;
                if let Some(at) = at {
                    limits::vector("at", at, limits::COORDINATE, "m")?;
                    if matches!(target, Target::Particle(_)) {
                        return Err(WorldError::invalid(
                            "at",
                            "a particle has no body frame: apply its force without `at`",
                        ));
                    }
                }
            }
            Load::Torque { torque, .. } => limits::vector("torque", torque, limits::FORCE, "N m")?,
            Load::Callback { .. } => {}
        }
        self.retire_engine();
        Ok(self.loads.insert(load))
    }

    /// Adds a constant force, fixed in world axes, at the centre of mass or at a body point `at` (body frame).
    pub fn add_force(
        &mut self,
        target: Target,
        force: Vector3<f64>,
        at: Option<Vector3<f64>>,
    ) -> Result<LoadHandle, WorldError> {
        self.add_load(Load::Force { target, force, at })
    }

    /// Adds a constant torque (world axes) on a body.
    pub fn add_torque(&mut self, body: BodyHandle, torque: Vector3<f64>) -> Result<LoadHandle, WorldError> {
        // The argument is `body` here (`add_load` calls it the load's target).
        self.add_load(Load::Torque { body, torque }).map_err(|e| match e {
            WorldError::UnknownHandle { name: "target", handle } => WorldError::UnknownHandle { name: "body", handle },
            WorldError::InvalidArgument { name: "target", reason } => {
                WorldError::InvalidArgument { name: "body", reason }
            }
            other => other,
        })
    }

    /// Adds a force callback: `f(t, state)` returns the force (and, for a body, the torque) on `target`.
    pub fn add_force_callback(
        &mut self,
        target: Target,
        f: impl FnMut(f64, &TargetState) -> Result<Wrench, String> + Send + 'static,
    ) -> Result<LoadHandle, WorldError> {
        self.add_load(Load::callback(target, f))
    }

    /// Removes a particle, with the springs and loads attached to it.
    pub fn remove_particle(&mut self, h: ParticleHandle) -> Result<Particle, WorldError> {
        let p = self.particles.remove(h).ok_or_else(|| unknown("particle", h))?;
        self.springs.retain(|s| ![s.a, s.b].contains(&Attachment::Particle(h)));
        self.loads.retain(|l| l.target() != Target::Particle(h));
        self.retire_engine();
        Ok(p)
    }

    /// Removes a body, with the springs and loads attached to it.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<RigidBody, WorldError> {
        let b = self.bodies.remove(h).ok_or_else(|| unknown("body", h))?;
        self.springs.retain(|s| ![s.a, s.b].iter().any(|e| matches!(e, Attachment::Body(b, _) if *b == h)));
        self.loads.retain(|l| l.target() != Target::Body(h));
        self.joints.retain(|j| j.a() != Some(h) && j.b() != Some(h));
        self.retire_engine();
        Ok(b)
    }

    /// Removes a spring.
    pub fn remove_spring(&mut self, h: SpringHandle) -> Result<Spring, WorldError> {
        let s = self.springs.remove(h).ok_or_else(|| unknown("spring", h))?;
        self.retire_engine();
        Ok(s)
    }

    /// Removes a load.
    pub fn remove_load(&mut self, h: LoadHandle) -> Result<(), WorldError> {
        self.loads.remove(h).ok_or_else(|| unknown("load", h))?;
        self.retire_engine();
        Ok(())
    }
}
