//! One collider pair kept across steps: its manifold in its bodies' frames, which of its points the reduction chose,
//! and its contacts as the soft step solves them.
//!
//! A pair of polyhedral colliders whose relative pose has moved less than `REUSE_DISTANCE` (1 mm, or 5% of the
//! smaller one's size if less) and turned less than `REUSE_TURN` (2 degrees) since its manifold was computed (Jolt's
//! body-pair cache) skips the narrow phase and reuses it, each point carried by its body (A's point in A's frame, B's
//! in B's, the normal with the face that gives it) and its gap measured anew: never a stale distance. Manifolds are
//! computed with the most that motion can close added to the prediction (the distance, and the turn times the
//! smaller collider's size), so a point that the motion since could have brought within reach is already among
//! them; what reuse gives up is only the clipping of face contacts to the motion since (points off by at most the
//! motion along the faces). When the same points are carried as last step, the reduction's
//! choice among them is kept too. Resting piles and stacks, whose pairs barely move, find most of their contacts
//! this way. Pairs with a curved contact (spheres, capsules, cylinders' rims), whose points slide over the surface
//! as they turn, are always computed.

use crate::collider::Material;
use crate::engine::contact_reduction::{deepest, MAX_POINTS};
use crate::engine::found_contact::{contact_point, feature_code, FoundContact};
use nalgebra::{Isometry3, Matrix4, Point3, Unit, Vector3};
use smallvec::SmallVec;
use std::sync::Arc;
use tumble_collide::{ContactKind, Shape, ShapeContact};
use tumble_contact::{SoftManifold, SoftPoint, MANIFOLD_POINTS};

/// The relative motion up to which a manifold is reused (m), and as a fraction of the smaller collider's bounding
/// radius if that is less.
pub(crate) const REUSE_DISTANCE: f64 = 1e-3;
const REUSE_FRACTION: f64 = 0.05;
/// The relative turn up to which a manifold is reused (rad): 2 degrees; and the sine of its half (sin 1 degree).
pub(crate) const REUSE_TURN: f64 = 2.0 * std::f64::consts::PI / 180.0;
const REUSE_HALF_SINE: f64 = 0.017_452_406_437_283_51;

/// How far a pair whose smaller collider has bounding radius `size` may move (translation, turn) and keep its
/// manifold, and how much nearer that motion can bring any point of it (what its manifold's prediction is enlarged by).
pub(crate) fn reuse_limits(size: f64) -> (f64, f64, f64) {
    let distance = REUSE_DISTANCE.min(REUSE_FRACTION * size);
    (distance, REUSE_TURN, distance + REUSE_TURN * size)
}

/// A contact in its bodies' frames.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct Local {
    a: Point3<f64>,
    b: Point3<f64>,
    /// The normal in A's frame, or in B's if `on_b`.
    normal: Vector3<f64>,
    on_b: bool,
    contact: ShapeContact,
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
#[derive(serde::Serialize, serde::Deserialize, Debug)]
pub(crate) struct Pair {
    pair: (usize, usize),
    /// (Shared, as is the choice: a step moves every pair's entry, most pairs of a pile have neither, and a call's
    /// copy of the memory, put back if it fails, then costs a count, not a copy: both are replaced, never changed.)
    manifold: Option<Arc<Manifold>>,
    chosen: Option<Arc<Chosen>>,
    /// Its contacts of the last step as the soft step solved them, four points a manifold (a decomposed mesh's pair
    /// may touch in several planes, four points each; one manifold is held in place, so that copying the memory
    /// allocates nothing for it), and each point's features in the same order (what names it from one step to the
    /// next). A manifold left without points keeps its colour until `ContactPairs::close` gives it back.
    pub(super) contacts: SmallVec<[SoftManifold; 1]>,
    features: SmallVec<[(u64, u64); MAX_POINTS]>,
    /// This step's search: the manifold's points carried (when it has a manifold).
    #[serde(skip)]
    carried: Option<Vec<u32>>,
}

impl Clone for Pair {
    fn clone(&self) -> Self {
        Pair {
            pair: self.pair,
            manifold: self.manifold.clone(),
            chosen: self.chosen.clone(),
            contacts: self.contacts.clone(),
            features: self.features.clone(),
            // a step's scratch, never kept between steps
            carried: None,
        }
    }

    /// Into the room of another pair: a shared manifold or choice that is already the same is not counted again.
    fn clone_from(&mut self, o: &Self) {
        self.pair = o.pair;
        let same = |a: &Option<Arc<Manifold>>, b: &Option<Arc<Manifold>>| match (a, b) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same(&self.manifold, &o.manifold) {
            self.manifold.clone_from(&o.manifold);
        }
        let same_choice = match (&self.chosen, &o.chosen) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same_choice {
            self.chosen.clone_from(&o.chosen);
        }
        self.contacts.clone_from(&o.contacts);
        self.features.clone_from(&o.features);
        self.carried = None;
    }
}

/// How a pair's contacts were found this step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Found {
    /// Its kept manifold carried.
    Reused,
    /// Computed (and kept, if polyhedral).
    Computed,
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
    pub fn new(pair: (usize, usize)) -> Pair {
        Pair { pair, manifold: None, chosen: None, contacts: SmallVec::new(), features: SmallVec::new(), carried: None }
    }

    /// The collider pair.
    pub fn pair(&self) -> (usize, usize) {
        self.pair
    }

    /// Whether it fits a scene of `colliders` colliders: its colliders in range, a kept choice within its manifold,
    /// its contacts' impulses and features in order.
    pub fn fits(&self, colliders: usize) -> bool {
        let choice_fits = match (&self.chosen, &self.manifold) {
            (None, _) => true,
            (Some(c), Some(m)) => {
                let n = m.points.len() as u32;
                c.carried.iter().all(|&k| k < n)
                    && c.kept.iter().all(|&k| (k as usize) < c.carried.len())
                    && c.deepest < c.carried.len()
            }
            (Some(_), None) => false,
        };
        let fits = |m: &SoftManifold| m.count <= MANIFOLD_POINTS && m.colour <= tumble_contact::OVERFLOW;
        let contacts_fit = self.contacts.iter().all(fits)
            && self.features.len() == self.contacts.iter().map(|m| m.count).sum::<usize>();
        self.pair.0 < colliders && self.pair.1 < colliders && choice_fits && contacts_fit
    }

    /// Whether it keeps a manifold to reuse.
    pub fn has_manifold(&self) -> bool {
        self.manifold.is_some()
    }

    /// The pair's contacts (shapes and world poses given, radii their bounding radii) within `prediction`, into `out`
    /// (cleared first): reused if the pair barely moved since its manifold was computed, else from `compute`, asked
    /// for a prediction distance (the most the reuse limits let the pair close added).
    pub fn contacts<E>(
        &mut self,
        (shape_a, pose_a, radius_a): (&Shape, &Isometry3<f64>, f64),
        (shape_b, pose_b, radius_b): (&Shape, &Isometry3<f64>, f64),
        prediction: f64,
        compute: impl FnOnce(f64) -> Result<Vec<ShapeContact>, E>,
        out: &mut Vec<ShapeContact>,
    ) -> Result<Found, E> {
        out.clear();
        self.carried = None;
        let size = radius_a.min(radius_b);
        let (reuse, _, enlargement) = reuse_limits(size);
        if !(polyhedral(shape_a) && polyhedral(shape_b) && size.is_finite() && size > 0.0) {
            self.manifold = None;
            out.extend(compute(prediction)?);
            return Ok(Found::Computed);
        }
        let flipped = radius_a < radius_b;
        let relative = if flipped { pose_b.inv_mul(pose_a) } else { pose_a.inv_mul(pose_b) };
        if let Some(m) = &self.manifold {
            // the turn by the sine of its half angle (no trigonometry): below the reuse turn's, and then at most
            // 2.0001 times it (asin(s) / s < 1.00006 for s up to sin 1 degree)
            let half_sine = (m.relative.rotation.inverse() * relative.rotation).imag().norm();
            let turn = 2.0001 * half_sine;
            let moved = (relative.translation.vector - m.relative.translation.vector).norm();
            let motion = moved + turn * size;
            let turned_little = half_sine < REUSE_HALF_SINE;
            if m.flipped == flipped && moved < reuse && turned_little && prediction + motion <= m.prediction {
                // which points were carried matters only where the reduction chooses among more than four
                let choosing = m.points.len() > MAX_POINTS && keeps_choice(shape_a, shape_b);
                let frames = (pose_a.to_homogeneous(), pose_b.to_homogeneous());
                let carried = m.points.iter().map(|l| carry(l, &frames, prediction));
                self.carried = within_reach(carried, m.points.len(), choosing, out);
                return Ok(Found::Reused);
            }
        }
        self.manifold = None;
        let enlarged = prediction + enlargement;
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
        self.carried = within_reach(all.into_iter().map(|c| (c.distance <= prediction).then_some(c)), n, choosing, out);
        Ok(Found::Computed)
    }

    /// The reduction of this step's contacts (those `contacts` gave, in its order; `gaps` theirs), into `kept`
    /// (indices, increasing): none is left out of four or fewer; else the last step's choice if the same points of
    /// the same manifold were carried, else `reduce`'s, kept for the next step.
    pub fn choose(&mut self, gaps: &[f64], reduce: impl FnOnce() -> Vec<usize>, kept: &mut Vec<usize>) {
        kept.clear();
        let carried = self.carried.take();
        if gaps.len() <= MAX_POINTS {
            self.chosen = None;
            kept.extend(0..gaps.len());
            return;
        }
        let now_deepest = deepest(gaps.iter().copied());
        if let (Some(carried), Some(chosen), Some(_)) = (&carried, &self.chosen, &self.manifold) {
            if *carried == chosen.carried && now_deepest == chosen.deepest {
                kept.extend(chosen.kept.iter().map(|&k| k as usize));
                return;
            }
        }
        kept.extend(reduce());
        self.chosen = carried.map(|carried| {
            Arc::new(Chosen { carried, deepest: now_deepest, kept: kept.iter().map(|&k| k as u32).collect() })
        });
    }

    /// Carries the pair's kept contacts to `contacts` at `kept` when they are the same points in the same order (by
    /// their features: what a reused manifold gives a resting pair step after step), their impulses and colour kept
    /// as they are and their material `material` (it may have changed between steps); gives whether it did (else
    /// `set_contacts` sets them).
    pub fn carry_kept(&mut self, contacts: &[ShapeContact], kept: &[usize], material: Material) -> bool {
        let same = self.features.len() == kept.len()
            && kept.iter().zip(&self.features).all(|(&k, f)| {
                let c = &contacts[k];
                (feature_code(c.feature_a), feature_code(c.feature_b)) == *f
            });
        if !same {
            return false;
        }
        for (m, chunk) in self.contacts.iter_mut().zip(kept.chunks(MANIFOLD_POINTS)) {
            (m.friction, m.restitution) = (material.friction, material.restitution);
            (m.rolling_resistance, m.torsional_resistance) =
                (material.rolling_resistance, material.torsional_resistance);
            for (point, &k) in m.points.iter_mut().zip(chunk) {
                let c = &contacts[k];
                (point.point, point.normal, point.gap) = (contact_point(c), c.normal.into_inner(), c.distance);
            }
        }
        true
    }

    /// The pair's contacts this step: those of `found` at `kept` (the step's contacts of this pair, in order), four
    /// a manifold, each started from the normal impulse of last step's contact of the same features, else from the
    /// mean of last step's (a contact new to a pair that touched), else from none. Each manifold keeps its friction
    /// impulses and its colour, and one left without points keeps its colour too (`ContactPairs::close` sees to
    /// both).
    pub fn set_contacts(&mut self, found: &[FoundContact], kept: &[usize]) {
        let old: SmallVec<[f64; MAX_POINTS]> =
            self.contacts.iter().flat_map(|m| m.points().iter().map(|p| p.normal_impulse)).collect();
        let mean = if old.is_empty() { 0.0 } else { old.iter().sum::<f64>() / old.len() as f64 };
        let manifolds = kept.len().div_ceil(MANIFOLD_POINTS);
        if let Some(f) = found.first() {
            let c = &f.contact;
            while self.contacts.len() < manifolds {
                self.contacts.push(
                    SoftManifold::new(c.a, c.b, c.friction, c.restitution)
                        .with_resistance(c.rolling_resistance, c.torsional_resistance),
                );
            }
        }
        let mut features = SmallVec::with_capacity(kept.len());
        for (m, chunk) in
            self.contacts.iter_mut().zip(kept.chunks(MANIFOLD_POINTS).map(Some).chain(std::iter::repeat(None)))
        {
            let Some(chunk) = chunk else {
                m.count = 0;
                continue;
            };
            let first = &found[chunk[0]].contact;
            (m.a, m.b, m.friction, m.restitution) = (first.a, first.b, first.friction, first.restitution);
            m.count = chunk.len();
            for (slot, &k) in chunk.iter().enumerate() {
                let f = &found[k];
                // two contacts of the same features take the last one's impulse
                let normal_impulse = match self.features.iter().rposition(|&x| x == f.key.features) {
                    Some(i) => old[i],
                    None => mean,
                };
                let (c, step_normal) = (&f.contact, 0.0);
                let (point, normal, gap) = (c.point, c.normal.into_inner(), c.distance);
                m.points[slot] = SoftPoint { point, normal, gap, normal_impulse, step_normal };
                features.push(f.key.features);
            }
        }
        self.features = features;
    }
}

/// The contacts of `candidates` within reach (the `Some`s), into `out`, and, if `choosing`, their places among the
/// candidates.
fn within_reach(
    candidates: impl Iterator<Item = Option<ShapeContact>>,
    capacity: usize,
    choosing: bool,
    out: &mut Vec<ShapeContact>,
) -> Option<Vec<u32>> {
    let mut carried = Vec::with_capacity(if choosing { capacity } else { 0 });
    for (k, c) in candidates.enumerate() {
        if let Some(c) = c {
            out.push(c);
            if choosing {
                carried.push(k as u32);
            }
        }
    }
    choosing.then_some(carried)
}

/// A kept contact where its bodies now are (their poses as matrices, `frames`), if within `prediction`: its points
/// carried by their bodies, its normal by the face that gives it, its gap measured anew.
fn carry(l: &Local, (a, b): &(Matrix4<f64>, Matrix4<f64>), prediction: f64) -> Option<ShapeContact> {
    let point_a = a.transform_point(&l.a);
    let point_b = b.transform_point(&l.b);
    let frame = if l.on_b { b } else { a };
    // a rotation keeps the normal's length to the rounding
    let normal = Unit::new_unchecked(frame.transform_vector(&l.normal));
    let distance = normal.dot(&(point_b - point_a));
    (distance <= prediction).then_some(ShapeContact { point_a, point_b, normal, distance, ..l.contact })
}

#[cfg(test)]
#[path = "pair_tests.rs"]
mod tests;
