//! Hand-over between keyframes and physics, between calls: a keyframed body let go (`release`) goes on as a
//! dynamic body from where its path has it now, with the velocity and spin its path had coming there and the mass of its
//! shapes at a density; a dynamic body taken over (`hold`) follows keyframes from now on (by default it stays where
//! it is). The body keeps its handle and row, so the runs before and after join into one (`Run::join`).

use super::{unknown, World};
use crate::body::Kinematic;
use crate::collider::{compound_mass, Collider};
use crate::error::WorldError;
use crate::keyframes::Keyframes;
use crate::limits;
use crate::spring::BodyHandle;
use nalgebra::{Isometry3, Matrix3, Vector3};
use std::sync::Arc;
use tumble_collide::rotated_tensor;

impl World {
    /// Lets kinematic body `body` go: from the world's time it is a dynamic body of its shapes at `density` (kg/m^3;
    /// `DEFAULT_DENSITY` if `None`), where its keyframes have it, moving and turning as they had it coming there
    /// (the segment that ends there, at a keyframe). Its handle,
    /// row, shapes, look and material are kept. A body that is not kinematic, has no shape or a bad density is an
    /// error naming the argument, and the world is left as it was.
    pub fn release(&mut self, body: BodyHandle, density: Option<f64>) -> Result<(), WorldError> {
        let t = self.time;
        let b = self.bodies.get(body).ok_or_else(|| unknown("body", body))?;
        let Some(k) = &b.kinematic else {
            return Err(WorldError::invalid("body", "is not kinematic: only a body on keyframes is released"));
        };
        let density = limits::positive("density", density.unwrap_or(crate::options::DEFAULT_DENSITY), 1e6, "kg/m^3")?;
        if b.colliders.is_empty() {
            return Err(WorldError::invalid("body", "has no shape to take a mass from"));
        }
        let parts: Vec<_> = b.colliders.iter().map(|c| (c.shape.clone(), c.offset)).collect();
        let props = compound_mass(&parts, density)?;
        limits::mass("density", props.mass)?;
        limits::inertia("density", &props.inertia)?;
        let inv_inertia = crate::body_builder::check_inertia(&props.inertia)?;
        // the frame the keyframes pose (the shapes' frame) where its path has it now, and its motion there
        let (frame, (v, w)) = (k.path.pose_at(t), k.path.velocity_before(t));
        let com = props.local_com;
        let position = frame * nalgebra::Point3::from(com);
        let r = frame.rotation.to_rotation_matrix();
        let b = self.bodies.get_mut(body).expect("checked above");
        let shift = Isometry3::translation(-com.x, -com.y, -com.z);
        for c in &mut b.colliders {
            *c = Collider { shape: c.shape.clone(), offset: shift * c.offset };
        }
        b.origin -= com;
        (b.mass, b.inertia, b.inv_inertia) = (props.mass, props.inertia, inv_inertia);
        b.position = position.coords;
        b.orientation = frame.rotation;
        b.momentum = props.mass * (v + w.cross(&(frame.rotation * com)));
        b.angular_momentum = rotated_tensor(r.matrix(), &props.inertia) * w;
        b.kinematic = None;
        self.retire_engine();
        self.record_body_start(body);
        Ok(())
    }

    /// Takes dynamic body `body` over: from the world's time it follows `keyframes` (poses of its body frame, whose
    /// origin is its centre of mass; `None`: where it is now, still), pushing what it touches and never pushed
    /// back. A body that is static or already kinematic is an error naming the argument.
    pub fn hold(&mut self, body: BodyHandle, keyframes: Option<Keyframes>) -> Result<(), WorldError> {
        let t = self.time;
        let b = self.bodies.get(body).ok_or_else(|| unknown("body", body))?;
        if b.is_static || b.kinematic.is_some() {
            return Err(WorldError::invalid("body", "is not dynamic: only a moving body is taken over"));
        }
        let path = match keyframes {
            Some(k) => k,
            None => Keyframes::new(vec![t], vec![b.position], Some(vec![b.orientation]))?,
        };
        let b = self.bodies.get_mut(body).expect("checked above");
        (b.mass, b.inertia, b.inv_inertia) = (f64::INFINITY, Matrix3::identity(), Matrix3::zeros());
        (b.momentum, b.angular_momentum) = (Vector3::zeros(), Vector3::zeros());
        b.kinematic =
            Some(Kinematic { path: Arc::new(path), velocity: Vector3::zeros(), angular_velocity: Vector3::zeros() });
        b.follow(t);
        self.retire_engine();
        self.record_body_start(body);
        Ok(())
    }
}
