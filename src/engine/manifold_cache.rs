//! Fast mode's manifolds kept across steps: a pair of polyhedral colliders whose relative pose has moved less than
//! `REUSE` of the smaller one's size since its manifold was computed skips the narrow phase and reuses it, each
//! point carried by its body (A's point in A's frame, B's in B's, the normal with the face that gives it) and its
//! gap measured anew. Manifolds are computed with the reuse distance added to the prediction, so a point that the
//! motion since could have brought within reach is already among them; what reuse gives up is only the clipping of
//! face contacts to the motion since (points off by at most the reuse distance along the faces). Resting piles and
//! stacks, whose pairs barely move, find most of their contacts this way. Pairs with a curved contact (spheres,
//! capsules, cylinders' rims), whose points slide over the surface as they turn, are always computed.

use nalgebra::{Isometry3, Point3, Unit, UnitQuaternion, Vector3};
use tumble_collide::{Contact, ContactKind, Shape};

/// The relative motion, as a fraction of the smaller collider's bounding radius, up to which a manifold is reused.
pub(crate) const REUSE: f64 = 1e-4;

/// A contact in its bodies' frames.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct Local {
    a: Point3<f64>,
    b: Point3<f64>,
    /// The normal in A's frame, or in B's if `on_b`.
    normal: Vector3<f64>,
    on_b: bool,
    contact: Contact,
}

/// One pair's manifold as computed.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct Cached {
    pair: (usize, usize),
    /// The smaller collider's pose in the larger's frame when computed (`flipped`: A's in B's).
    relative: Isometry3<f64>,
    flipped: bool,
    /// The prediction it was computed with (the reuse distance included).
    prediction: f64,
    points: Vec<Local>,
}

/// The manifolds of the last step's pairs, sorted by pair.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub(crate) struct ManifoldCache {
    pairs: Vec<Cached>,
    /// This step's, built as pairs are asked for (in sorted order), replacing `pairs` at `finish`.
    next: Vec<Cached>,
    /// Pairs whose manifold was reused, and computed, since the cache was made.
    pub reused: usize,
    pub computed: usize,
}

impl ManifoldCache {
    /// The contacts of collider pair `pair` (shapes and world poses given, radii their bounding radii) within
    /// `prediction`: reused if the pair barely moved since its manifold was computed, else from `compute`, asked
    /// for a prediction distance (the reuse distance added).
    #[allow(clippy::too_many_arguments)]
    pub fn contacts<E>(
        &mut self,
        pair: (usize, usize),
        (shape_a, pose_a, radius_a): (&Shape, &Isometry3<f64>, f64),
        (shape_b, pose_b, radius_b): (&Shape, &Isometry3<f64>, f64),
        prediction: f64,
        compute: impl FnOnce(f64) -> Result<Vec<Contact>, E>,
    ) -> Result<Vec<Contact>, E> {
        let polyhedral = |s: &Shape| {
            matches!(s, Shape::Cuboid { .. } | Shape::ConvexHull(_) | Shape::Decomposed(_) | Shape::HalfSpace { .. })
        };
        let size = radius_a.min(radius_b);
        let reuse = REUSE * size;
        if !(polyhedral(shape_a) && polyhedral(shape_b) && size.is_finite() && size > 0.0) {
            return compute(prediction);
        }
        let flipped = radius_a < radius_b;
        let relative = if flipped { pose_b.inv_mul(pose_a) } else { pose_a.inv_mul(pose_b) };
        if let Ok(k) = self.pairs.binary_search_by(|c| c.pair.cmp(&pair)) {
            let c = &mut self.pairs[k];
            let turn = c.relative.rotation.angle_to(&relative.rotation);
            let motion = (relative.translation.vector - c.relative.translation.vector).norm() + turn * size;
            if c.flipped == flipped && motion < reuse && prediction + motion <= c.prediction {
                let found = c.points.iter().filter_map(|l| carried(l, pose_a, pose_b, prediction)).collect();
                // each pair is asked for once a search: its manifold moves on to the next step's list
                let points = std::mem::take(&mut c.points);
                self.next.push(Cached { points, ..*c });
                self.reused += 1;
                return Ok(found);
            }
        }
        let enlarged = prediction + reuse;
        let all = compute(enlarged)?;
        self.computed += 1;
        if all.iter().all(|c| c.kind != ContactKind::Curved) {
            let points = all
                .iter()
                .map(|c| {
                    let on_b = c.kind == ContactKind::VertexFace;
                    let frame = if on_b { pose_b } else { pose_a };
                    Local {
                        a: pose_a.inverse_transform_point(&c.point_a),
                        b: pose_b.inverse_transform_point(&c.point_b),
                        normal: frame.inverse_transform_vector(&c.normal),
                        on_b,
                        contact: *c,
                    }
                })
                .collect();
            self.next.push(Cached { pair, relative, flipped, prediction: enlarged, points });
        }
        Ok(all.into_iter().filter(|c| c.distance <= prediction).collect())
    }

    /// Whether it fits a scene of `colliders` colliders: pairs in range and sorted, no step half-searched.
    pub fn fits(&self, colliders: usize) -> bool {
        self.next.is_empty()
            && self.pairs.iter().all(|c| c.pair.0 < colliders && c.pair.1 < colliders)
            && self.pairs.windows(2).all(|w| w[0].pair < w[1].pair)
    }

    /// Ends a step's search: its pairs become the ones to reuse.
    pub fn finish(&mut self) {
        self.pairs = std::mem::take(&mut self.next);
    }
}

/// A cached contact where its bodies now are, if within `prediction`.
fn carried(l: &Local, pose_a: &Isometry3<f64>, pose_b: &Isometry3<f64>, prediction: f64) -> Option<Contact> {
    let point_a = pose_a * l.a;
    let point_b = pose_b * l.b;
    let rotation: &UnitQuaternion<f64> = if l.on_b { &pose_b.rotation } else { &pose_a.rotation };
    let normal = Unit::new_normalize(rotation * l.normal);
    let distance = normal.dot(&(point_b - point_a));
    (distance <= prediction).then_some(Contact { point_a, point_b, normal, distance, ..l.contact })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Translation3;
    use tumble_collide::contacts;

    /// A seeded generator (the same numbers everywhere).
    struct Lcg(u64);
    impl Lcg {
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
        }
        fn unit(&mut self) -> Vector3<f64> {
            Vector3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0)).normalize()
        }
    }

    #[test]
    fn a_pair_moved_less_than_the_reuse_distance_gets_the_fresh_manifolds_contacts_back() {
        // Seeded random boxes of 0.05 to 1 m, in random orientations, the second resting on the first's top face
        // (turned about its normal, off centre, up to 0.1% of its size deep), then moved by a random relative
        // motion below the reuse distance. The carried contacts are the fresh manifold's: the same features, and
        // gaps that differ by no more than the motion (a vertex on a face keeps its exact gap; only clipped points
        // slide along the faces).
        let mut rng = Lcg(7);
        let (mut reused, mut exact) = (0, 0);
        for case in 0..300 {
            let ha = Vector3::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0));
            let hb = Vector3::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0));
            let (a, b) = (Shape::cuboid(ha).unwrap(), Shape::cuboid(hb).unwrap());
            let (ra, rb) = (a.bounding_radius(), b.bounding_radius());
            let pose_a = Isometry3::from_parts(
                Translation3::from(rng.unit() * rng.range(0.0, 5.0)),
                UnitQuaternion::from_scaled_axis(rng.unit() * rng.range(0.0, 3.0)),
            );
            let depth = rng.range(0.0, 1e-3) * ha.z.min(hb.z);
            let on_top = Vector3::new(rng.range(-0.5, 0.5) * ha.x, rng.range(-0.5, 0.5) * ha.y, ha.z + hb.z - depth);
            let turn = UnitQuaternion::from_scaled_axis(Vector3::z() * rng.range(-3.0, 3.0));
            let pose_b = pose_a * Isometry3::from_parts(Translation3::from(on_top), turn);
            let prediction = 1e-3;
            let mut cache = ManifoldCache::default();
            let fresh = |pa: &Isometry3<f64>, pb: &Isometry3<f64>, p: f64| contacts(&a, pa, &b, pb, p);
            cache
                .contacts((0, 1), (&a, &pose_a, ra), (&b, &pose_b, rb), prediction, |p| fresh(&pose_a, &pose_b, p))
                .unwrap();
            cache.finish();
            // the smaller box moved about its centre, below the reuse distance (translation and turn share it)
            let reuse = REUSE * ra.min(rb);
            let share = rng.range(0.0, 1.0);
            let step = Isometry3::from_parts(
                Translation3::from(rng.unit() * (0.9 * reuse * share)),
                UnitQuaternion::from_scaled_axis(rng.unit() * (0.9 * reuse * (1.0 - share) / ra.min(rb))),
            );
            let (pose_a, moved_b) = if ra < rb { (pose_a * step, pose_b) } else { (pose_a, pose_b * step) };
            let carried = cache
                .contacts((0, 1), (&a, &pose_a, ra), (&b, &moved_b, rb), prediction, |_| -> Result<_, ()> {
                    panic!("case {case}: a pair moved below the reuse distance was computed again")
                })
                .unwrap();
            reused += 1;
            let now = fresh(&pose_a, &moved_b, prediction).unwrap();
            assert_eq!(carried.len(), now.len(), "case {case}: {carried:?} against {now:?}");
            for c in &now {
                let twin = carried
                    .iter()
                    .find(|k| (k.feature_a, k.feature_b) == (c.feature_a, c.feature_b))
                    .unwrap_or_else(|| panic!("case {case}: no carried contact for {c:?}"));
                // the motion, and rounding on coordinates of a few metres
                let gap = (twin.distance - c.distance).abs();
                assert!(
                    gap <= reuse + 1e-12,
                    "case {case}: gaps {} and {} differ by {gap:e}",
                    twin.distance,
                    c.distance
                );
                if gap <= 1e-12 {
                    exact += 1;
                }
            }
        }
        assert_eq!(reused, 300);
        // boxes face to face touch at vertices on faces: their gaps are carried exactly
        assert!(exact > 600, "{exact} contacts carried exactly");
    }

    #[test]
    fn a_pair_moved_past_the_reuse_distance_or_with_a_curved_contact_is_computed_again() {
        let a = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
        let b = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
        let r = a.bounding_radius();
        let pose_a = Isometry3::identity();
        let pose_b = Isometry3::translation(0.0, 0.0, 1.0);
        let mut cache = ManifoldCache::default();
        let ask = |cache: &mut ManifoldCache, pb: &Isometry3<f64>| {
            let out = cache.contacts((0, 1), (&a, &pose_a, r), (&b, pb, r), 1e-3, |p| contacts(&a, &pose_a, &b, pb, p));
            cache.finish();
            out.unwrap()
        };
        ask(&mut cache, &pose_b);
        ask(&mut cache, &Isometry3::translation(0.0, 0.0, 1.0 + 0.5 * REUSE * r));
        assert_eq!((cache.computed, cache.reused), (1, 1));
        ask(&mut cache, &Isometry3::translation(0.0, 0.0, 1.0 + 2.0 * REUSE * r));
        assert_eq!((cache.computed, cache.reused), (2, 1), "moved past the reuse distance");
        // a ball on the box: always computed
        let ball = Shape::sphere(0.5).unwrap();
        for _ in 0..2 {
            cache
                .contacts((0, 2), (&a, &pose_a, r), (&ball, &pose_b, 0.5), 1e-3, |p| {
                    contacts(&a, &pose_a, &ball, &pose_b, p)
                })
                .unwrap();
            cache.finish();
        }
        assert_eq!((cache.computed, cache.reused), (2, 1), "a curved pair never goes through the cache");
    }
}
