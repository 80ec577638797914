//! Fast mode's contact pairs kept across steps: each collider pair that touched keeps, from one step to the next,
//! its manifold in its bodies' frames, its contacts' impulses (for the warm start) and which of its points the
//! reduction chose, in one list sorted by pair that a step's search walks forward (the broad phase gives the pairs
//! sorted): no map of keys, no sort.
//!
//! A pair of polyhedral colliders whose relative pose has moved less than `REUSE` of the smaller one's size since its
//! manifold was computed skips the narrow phase and reuses it, each point carried by its body (A's point in A's
//! frame, B's in B's, the normal with the face that gives it) and its gap measured anew. Manifolds are computed with
//! the reuse distance added to the prediction, so a point that the motion since could have brought within reach is
//! already among them; what reuse gives up is only the clipping of face contacts to the motion since (points off by
//! at most the reuse distance along the faces). When the same points are carried as last step, the reduction's
//! choice among them is kept too. Resting piles and stacks, whose pairs barely move, find most of their contacts
//! this way. Pairs with a curved contact (spheres, capsules, cylinders' rims), whose points slide over the surface
//! as they turn, are always computed.

use crate::engine::contact_reduction::{deepest, MAX_POINTS};
use crate::engine::found_contact::FoundContact;
use nalgebra::{Isometry3, Point3, Unit, UnitQuaternion, Vector3};
use smallvec::SmallVec;
use std::sync::Arc;
use tumble_collide::{Contact, ContactKind, Shape};
use tumble_contact::SoftImpulse;

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
struct Manifold {
    /// The smaller collider's pose in the larger's frame when computed (`flipped`: A's in B's).
    relative: Isometry3<f64>,
    flipped: bool,
    /// The prediction it was computed with (the reuse distance included).
    prediction: f64,
    points: Vec<Local>,
}

/// The reduction's last choice: which of the manifold's points were within reach, the deepest, and which it kept.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, PartialEq)]
struct Chosen {
    carried: Vec<u32>,
    /// The deepest of them (the reduction's first point), by its place among the carried.
    deepest: usize,
    kept: Vec<u32>,
}

/// What a collider pair keeps from one step to the next.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct Pair {
    pair: (usize, usize),
    /// (Shared, as is the choice: a step moves every pair's entry, most pairs of a pile have neither, and a call's
    /// copy of the memory, put back if it fails, then costs a count, not a copy: both are replaced, never changed.)
    manifold: Option<Arc<Manifold>>,
    /// Its contacts' impulses of the last step, by their features (sorted; held in place up to a reduced pair's
    /// four, so that copying the memory allocates nothing for them).
    warm: SmallVec<[((u64, u64), SoftImpulse); MAX_POINTS]>,
    chosen: Option<Arc<Chosen>>,
    /// This step's search: the manifold's points carried (when it has a manifold).
    #[serde(skip)]
    carried: Option<Vec<u32>>,
}

/// How a pair's contacts were found this step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Found {
    /// Its kept manifold carried.
    Reused,
    /// Computed (and kept, if polyhedral).
    Computed,
}

/// The pairs kept across steps, sorted by pair.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub(crate) struct ContactPairs {
    pairs: Vec<Pair>,
}

/// Whether a pair of these shapes keeps the reduction's choice while it carries the same points: not a decomposed
/// mesh, whose contact planes (one a piece) are each reduced with the centres of mass they hold, which its pieces'
/// tumbling moves (kept, a seeded mesh drop penetrated 10.3 mm, past the 1 cm bound it keeps when chosen afresh).
fn keeps_choice(a: &Shape, b: &Shape) -> bool {
    !matches!(a, Shape::Decomposed(_)) && !matches!(b, Shape::Decomposed(_))
}

fn polyhedral(s: &Shape) -> bool {
    matches!(s, Shape::Cuboid { .. } | Shape::ConvexHull(_) | Shape::Decomposed(_) | Shape::HalfSpace { .. })
}

impl Pair {
    fn new(pair: (usize, usize)) -> Pair {
        Pair { pair, manifold: None, warm: SmallVec::new(), chosen: None, carried: None }
    }

    /// The collider pair.
    pub fn pair(&self) -> (usize, usize) {
        self.pair
    }

    /// The pair's contacts (shapes and world poses given, radii their bounding radii) within `prediction`: reused if
    /// the pair barely moved since its manifold was computed, else from `compute`, asked for a prediction distance
    /// (the reuse distance added).
    pub fn contacts<E>(
        &mut self,
        (shape_a, pose_a, radius_a): (&Shape, &Isometry3<f64>, f64),
        (shape_b, pose_b, radius_b): (&Shape, &Isometry3<f64>, f64),
        prediction: f64,
        compute: impl FnOnce(f64) -> Result<Vec<Contact>, E>,
    ) -> Result<(Vec<Contact>, Found), E> {
        self.carried = None;
        let size = radius_a.min(radius_b);
        let reuse = REUSE * size;
        if !(polyhedral(shape_a) && polyhedral(shape_b) && size.is_finite() && size > 0.0) {
            self.manifold = None;
            return Ok((compute(prediction)?, Found::Computed));
        }
        let flipped = radius_a < radius_b;
        let relative = if flipped { pose_b.inv_mul(pose_a) } else { pose_a.inv_mul(pose_b) };
        if let Some(m) = &self.manifold {
            let turn = m.relative.rotation.angle_to(&relative.rotation);
            let motion = (relative.translation.vector - m.relative.translation.vector).norm() + turn * size;
            if m.flipped == flipped && motion < reuse && prediction + motion <= m.prediction {
                // which points were carried matters only where the reduction chooses among more than four
                let choosing = m.points.len() > MAX_POINTS && keeps_choice(shape_a, shape_b);
                let carried = m.points.iter().map(|l| carry(l, pose_a, pose_b, prediction));
                let (found, carried) = within_reach(carried, m.points.len(), choosing);
                self.carried = carried;
                return Ok((found, Found::Reused));
            }
        }
        self.manifold = None;
        let enlarged = prediction + reuse;
        let all = compute(enlarged)?;
        self.manifold = all.iter().all(|c| c.kind != ContactKind::Curved).then(|| {
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
            Arc::new(Manifold { relative, flipped, prediction: enlarged, points })
        });
        let choosing = all.len() > MAX_POINTS && self.manifold.is_some() && keeps_choice(shape_a, shape_b);
        let n = all.len();
        let (found, carried) =
            within_reach(all.into_iter().map(|c| (c.distance <= prediction).then_some(c)), n, choosing);
        self.carried = carried;
        Ok((found, Found::Computed))
    }

    /// The reduction of this step's contacts `found` (those `contacts` gave, in its order), into `kept` (indices
    /// into `found`, increasing): none is left out of four or fewer; else the last step's choice if the same points
    /// of the same manifold were carried, else `reduce`'s, kept for the next step.
    pub fn choose(
        &mut self,
        found: &[FoundContact],
        reduce: impl FnOnce(&[FoundContact]) -> Vec<usize>,
        kept: &mut Vec<usize>,
    ) {
        kept.clear();
        let carried = self.carried.take();
        if found.len() <= MAX_POINTS {
            self.chosen = None;
            kept.extend(0..found.len());
            return;
        }
        let now_deepest = deepest(found.iter().map(|f| f.contact.distance));
        if let (Some(carried), Some(chosen), Some(_)) = (&carried, &self.chosen, &self.manifold) {
            if *carried == chosen.carried && now_deepest == chosen.deepest {
                kept.extend(chosen.kept.iter().map(|&k| k as usize));
                return;
            }
        }
        kept.extend(reduce(found));
        self.chosen = carried.map(|carried| {
            Arc::new(Chosen { carried, deepest: now_deepest, kept: kept.iter().map(|&k| k as u32).collect() })
        });
    }
}

impl ContactPairs {
    /// The last step's entries of `pairs` (sorted), moved out, a fresh one for a pair new this step; the rest are
    /// dropped (their boxes no longer overlap). `close` puts them back.
    pub fn open(&mut self, pairs: &[(usize, usize)]) -> Vec<Pair> {
        let mut kept = std::mem::take(&mut self.pairs).into_iter().peekable();
        pairs
            .iter()
            .map(|&pair| {
                while kept.next_if(|p| p.pair < pair).is_some() {}
                kept.next_if(|p| p.pair == pair).unwrap_or_else(|| Pair::new(pair))
            })
            .collect()
    }

    /// Ends a step's search: its pairs (as `open` gave them, in order) become the ones kept.
    pub fn close(&mut self, pairs: Vec<Pair>) {
        self.pairs = pairs;
    }

    /// The place of `pair` in the kept list, searched forward from `k` (which it advances): the callers ask for
    /// the pairs of contacts sorted by pair.
    fn find_from(&self, k: &mut usize, pair: (usize, usize)) -> Option<usize> {
        while *k < self.pairs.len() && self.pairs[*k].pair < pair {
            *k += 1;
        }
        (*k < self.pairs.len() && self.pairs[*k].pair == pair).then_some(*k)
    }

    /// Whether it fits a scene of `colliders` colliders: pairs in range and sorted, every kept choice within its
    /// manifold, impulses in order.
    pub fn fits(&self, colliders: usize) -> bool {
        let choice_fits = |p: &Pair| match (&p.chosen, &p.manifold) {
            (None, _) => true,
            (Some(c), Some(m)) => {
                let n = m.points.len() as u32;
                c.carried.iter().all(|&k| k < n)
                    && c.kept.iter().all(|&k| (k as usize) < c.carried.len())
                    && c.deepest < c.carried.len()
            }
            (Some(_), None) => false,
        };
        self.pairs.iter().all(|c| c.pair.0 < colliders && c.pair.1 < colliders && choice_fits(c))
            && self.pairs.windows(2).all(|w| w[0].pair < w[1].pair)
            && self.pairs.iter().all(|p| p.warm.windows(2).all(|w| w[0].0 < w[1].0))
    }

    /// Each of `found` (sorted by collider pair, as the search gives them) started from its impulses of the last
    /// step: its own (same features) if it was there, else its pair's mean, else none.
    pub fn warm(&self, found: &[FoundContact]) -> Vec<SoftImpulse> {
        let mut k = 0;
        found
            .iter()
            .map(|f| {
                let Some(at) = self.find_from(&mut k, pair_of(f)) else { return SoftImpulse::default() };
                let warm = &self.pairs[at].warm;
                match warm.binary_search_by(|(features, _)| features.cmp(&f.key.features)) {
                    Ok(i) => warm[i].1,
                    Err(_) if warm.is_empty() => SoftImpulse::default(),
                    Err(_) => {
                        let mut sum = SoftImpulse::default();
                        for (_, p) in warm {
                            sum.normal += p.normal;
                            sum.tangent += p.tangent;
                        }
                        let n = warm.len() as f64;
                        SoftImpulse { normal: sum.normal / n, tangent: sum.tangent / n }
                    }
                }
            })
            .collect()
    }

    /// Keeps the step's impulses (`impulses[i]` of `found[i]`, sorted by pair) for the next step's warm start; a
    /// pair with neither contacts nor a manifold is dropped. Two contacts of one features keep the last one's.
    pub fn keep(&mut self, found: &[FoundContact], impulses: &[SoftImpulse]) {
        let mut k = 0;
        for p in &mut self.pairs {
            p.warm.clear();
        }
        for (f, &impulse) in found.iter().zip(impulses) {
            let Some(at) = self.find_from(&mut k, pair_of(f)) else { continue };
            let p = &mut self.pairs[at];
            match p.warm.binary_search_by(|(features, _)| features.cmp(&f.key.features)) {
                Ok(i) => p.warm[i].1 = impulse,
                Err(i) => p.warm.insert(i, (f.key.features, impulse)),
            }
        }
        self.pairs.retain(|p| p.manifold.is_some() || !p.warm.is_empty());
    }

    /// Impulses kept, in all.
    #[cfg(test)]
    pub fn kept_impulses(&self) -> usize {
        self.pairs.iter().map(|p| p.warm.len()).sum()
    }
}

/// The collider pair of a found contact.
fn pair_of(f: &FoundContact) -> (usize, usize) {
    (f.key.colliders.0 as usize, f.key.colliders.1 as usize)
}

/// The contacts of `candidates` within reach (the `Some`s), and, if `choosing`, their places among the candidates.
fn within_reach(
    candidates: impl Iterator<Item = Option<Contact>>,
    capacity: usize,
    choosing: bool,
) -> (Vec<Contact>, Option<Vec<u32>>) {
    let mut found = Vec::with_capacity(capacity);
    let mut carried = Vec::with_capacity(if choosing { capacity } else { 0 });
    for (k, c) in candidates.enumerate() {
        if let Some(c) = c {
            found.push(c);
            if choosing {
                carried.push(k as u32);
            }
        }
    }
    (found, choosing.then_some(carried))
}

/// A kept contact where its bodies now are, if within `prediction`.
fn carry(l: &Local, pose_a: &Isometry3<f64>, pose_b: &Isometry3<f64>, prediction: f64) -> Option<Contact> {
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
            let mut pair = Pair::new((0, 1));
            let fresh = |pa: &Isometry3<f64>, pb: &Isometry3<f64>, p: f64| contacts(&a, pa, &b, pb, p);
            let (_, how) = pair
                .contacts((&a, &pose_a, ra), (&b, &pose_b, rb), prediction, |p| fresh(&pose_a, &pose_b, p))
                .unwrap();
            assert_eq!(how, Found::Computed);
            // the smaller box moved about its centre, below the reuse distance (translation and turn share it)
            let reuse = REUSE * ra.min(rb);
            let share = rng.range(0.0, 1.0);
            let step = Isometry3::from_parts(
                Translation3::from(rng.unit() * (0.9 * reuse * share)),
                UnitQuaternion::from_scaled_axis(rng.unit() * (0.9 * reuse * (1.0 - share) / ra.min(rb))),
            );
            let (pose_a, moved_b) = if ra < rb { (pose_a * step, pose_b) } else { (pose_a, pose_b * step) };
            let (carried, how) = pair
                .contacts((&a, &pose_a, ra), (&b, &moved_b, rb), prediction, |_| -> Result<_, ()> {
                    panic!("case {case}: a pair moved below the reuse distance was computed again")
                })
                .unwrap();
            assert_eq!(how, Found::Reused);
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
        let mut pair = Pair::new((0, 1));
        let mut ask = |pb: &Isometry3<f64>| {
            pair.contacts((&a, &pose_a, r), (&b, pb, r), 1e-3, |p| contacts(&a, &pose_a, &b, pb, p)).unwrap().1
        };
        assert_eq!(ask(&pose_b), Found::Computed);
        assert_eq!(ask(&Isometry3::translation(0.0, 0.0, 1.0 + 0.5 * REUSE * r)), Found::Reused);
        assert_eq!(
            ask(&Isometry3::translation(0.0, 0.0, 1.0 + 2.0 * REUSE * r)),
            Found::Computed,
            "moved past the reuse distance"
        );
        // a ball on the box: always computed
        let ball = Shape::sphere(0.5).unwrap();
        let mut pair = Pair::new((0, 2));
        for _ in 0..2 {
            let (_, how) = pair
                .contacts((&a, &pose_a, r), (&ball, &pose_b, 0.5), 1e-3, |p| contacts(&a, &pose_a, &ball, &pose_b, p))
                .unwrap();
            assert_eq!(how, Found::Computed, "a curved pair is never reused");
        }
    }
}
