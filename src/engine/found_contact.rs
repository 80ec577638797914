//! A contact found in a state, ready for tumble-contact, and the key that names it from one step to the next (its
//! collider pair and the two features that touch), for warm starts and lagged friction.

use nalgebra::Point3;
use tumble_collide::Feature;

/// The runs of `items` that share a collider pair (`pair` of each), if the pairs come in order, as the scene gives
/// them (each pair's contacts together, pairs sorted); `None` otherwise.
pub(crate) fn pair_runs<T>(items: &[T], pair: impl Fn(&T) -> (u32, u32)) -> Option<Vec<std::ops::Range<usize>>> {
    if !items.windows(2).all(|w| pair(&w[0]) <= pair(&w[1])) {
        return None;
    }
    let mut runs = Vec::new();
    let mut start = 0;
    for end in 1..=items.len() {
        if end == items.len() || pair(&items[end]) != pair(&items[start]) {
            runs.push(start..end);
            start = end;
        }
    }
    Some(runs)
}

/// Identifies a contact from one step to the next (for friction lagged on the previous normal impulse).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct ContactKey {
    pub colliders: (u32, u32),
    pub features: (u64, u64),
}

impl ContactKey {
    /// Whether both colliders are among the first `colliders`.
    pub fn fits(&self, colliders: usize) -> bool {
        (self.colliders.0 as usize) < colliders && (self.colliders.1 as usize) < colliders
    }
}

/// The contact point tumble-contact takes for a contact of parry's: the vertex (or curved point) that carries it, or
/// between the two points.
pub(crate) fn contact_point(c: &tumble_collide::ShapeContact) -> Point3<f64> {
    match c.kind {
        tumble_collide::ContactKind::FaceVertex => c.point_b,
        tumble_collide::ContactKind::VertexFace => c.point_a,
        _ => Point3::from((c.point_a.coords + c.point_b.coords) * 0.5),
    }
}

/// A feature as a number: its kind in the high bits, its index in the low ones.
pub(crate) fn feature_code(f: Feature) -> u64 {
    match f {
        Feature::Vertex(i) => 1 << 32 | i as u64,
        Feature::Edge(i) => 2 << 32 | i as u64,
        Feature::Face(i) => 3 << 32 | i as u64,
        Feature::Curved => 4 << 32,
        Feature::Unknown => 5 << 32,
    }
}

/// A contact found in a state, ready for tumble-contact.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FoundContact {
    pub contact: tumble_contact::Contact,
    pub key: ContactKey,
    /// The contact's points on A's and B's surfaces (world).
    pub point_a: Point3<f64>,
    pub point_b: Point3<f64>,
}
