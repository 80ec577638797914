//! The contacts of an engine's last step, kept for `World::contacts`: each pair's point, normal and gap where the
//! step found them (its start) and the normal impulse the step's solve gave it.

use crate::engine::found_contact::FoundContact;
use nalgebra::{Point3, Vector3};

/// A contact of the last step, between two actors (particles, then dynamic bodies, then static bodies).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct LastContact {
    pub a: usize,
    pub b: usize,
    pub point: Point3<f64>,
    pub normal: Vector3<f64>,
    pub gap: f64,
    pub impulse: f64,
    /// The step's length (s).
    pub step: f64,
}

impl LastContact {
    /// The contacts `found` with their impulses over the step of length `step`.
    pub fn from_found(found: &[FoundContact], impulses: impl Iterator<Item = f64>, step: f64) -> Vec<LastContact> {
        found
            .iter()
            .zip(impulses)
            .map(|(f, impulse)| LastContact {
                a: f.contact.a,
                b: f.contact.b,
                point: f.contact.point,
                normal: f.contact.normal.into_inner(),
                gap: f.contact.distance,
                impulse,
                step,
            })
            .collect()
    }
}
