//! The contacts of the world's last step (`World::contacts`): where two particles or bodies touched, the normal,
//! the gap and the normal impulse the step gave, with the world's handles.

use super::World;
use crate::load::Target;
use nalgebra::{Point3, Vector3};

/// A contact of the last step. `a` and `b` are the particles or bodies (static bodies included) that touched;
/// the normal points from `a` toward `b`, and the impulse pushes `b` along it and `a` against it.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactInfo {
    pub a: Target,
    pub b: Target,
    /// The contact point (world), where the step found it (at the step's start).
    pub point: Point3<f64>,
    /// Unit normal from `a` toward `b`.
    pub normal: Vector3<f64>,
    /// Signed gap along the normal at the step's start (negative: overlapping), m.
    pub gap: f64,
    /// Normal impulse over the step (N s).
    pub impulse: f64,
    /// The mean normal force over the step: the impulse over the step's length (N).
    pub force: f64,
}

impl World {
    /// The contacts of the last step: in fast mode every contact its solve took (an impulse of zero: in reach but
    /// not pushing); in accurate mode those of the last contact step while bodies touch, with the whole step's
    /// impulses (none once they fly free, and none for collisions resolved at an instant). Empty before the first
    /// step, and after any change of structure or state.
    pub fn contacts(&self) -> Vec<ContactInfo> {
        if let (Some(e), false) = (&self.engine, self.state_changed) {
            let handles = e.handles();
            let statics: Vec<crate::spring::BodyHandle> =
                self.bodies.iter().filter(|(_, b)| b.is_static).map(|(h, _)| h).collect();
            let (np, nb) = (handles.particles.len(), handles.bodies.len());
            let actor = |i: usize| {
                if i < np {
                    Target::Particle(handles.particles[i])
                } else if i < np + nb {
                    Target::Body(handles.bodies[i - np])
                } else {
                    Target::Body(statics[i - np - nb])
                }
            };
            return e
                .last_contacts()
                .iter()
                .map(|c| ContactInfo {
                    a: actor(c.a),
                    b: actor(c.b),
                    point: c.point,
                    normal: c.normal,
                    gap: c.gap,
                    impulse: c.impulse,
                    force: c.impulse / c.step,
                })
                .collect();
        }
        Vec::new()
    }
}
