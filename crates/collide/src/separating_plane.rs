//! Separating planes of convex polyhedra, as the chapter describes: two convex polyhedra are disjoint exactly when a
//! plane puts them on opposite sides, and if one exists, one exists that holds a face of either polyhedron or that
//! holds an edge of one and runs parallel to an edge of the other (normal = the cross product of the two edges). The
//! candidates are searched exhaustively; the plane found is cached per pair and tried first the next time, and the
//! search runs again only when it no longer separates.

use crate::pair_map::PairMap;
use crate::polyhedron::Polyhedron;
use nalgebra::{Isometry3, Unit, Vector3};

/// Which candidate produced a separating plane (indices into `Polyhedron::faces` and `edge_directions`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaneSource {
    /// The plane of face `i` of A.
    FaceOfA(usize),
    /// The plane of face `j` of B.
    FaceOfB(usize),
    /// The plane spanned by edge direction `edge_a` of A and `edge_b` of B; `flipped` when the normal is
    /// `-(e_a x e_b)`.
    EdgePair { edge_a: usize, edge_b: usize, flipped: bool },
}

/// A plane that separates A from B: every point x of A has `normal . x < offset` and every point of B
/// `normal . x > offset` (world frame; the normal points from A to B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeparatingPlane {
    /// Unit normal, from A toward B.
    pub normal: Unit<Vector3<f64>>,
    /// The plane is `normal . x = offset`, midway between the two bodies along `normal`.
    pub offset: f64,
    /// The width of the empty slab between A and B along `normal` (> 0; a lower bound on their distance).
    pub gap: f64,
    /// The candidate it came from.
    pub source: PlaneSource,
}

/// The gap along `n` (world, from A to B) between A's top and B's bottom.
#[inline]
fn gap(
    a: &Polyhedron,
    pose_a: &Isometry3<f64>,
    b: &Polyhedron,
    pose_b: &Isometry3<f64>,
    n: &Vector3<f64>,
) -> (f64, f64) {
    let (_, hi_a) = a.extent(&pose_a.rotation.inverse_transform_vector(n));
    let (lo_b, _) = b.extent(&pose_b.rotation.inverse_transform_vector(n));
    let top_a = hi_a + n.dot(&pose_a.translation.vector);
    let bottom_b = lo_b + n.dot(&pose_b.translation.vector);
    (bottom_b - top_a, 0.5 * (top_a + bottom_b))
}

/// The world normal of a candidate, or `None` for an edge pair that is parallel.
#[inline]
fn candidate_normal(
    source: PlaneSource,
    a: &Polyhedron,
    pose_a: &Isometry3<f64>,
    b: &Polyhedron,
    pose_b: &Isometry3<f64>,
) -> Option<Vector3<f64>> {
    match source {
        PlaneSource::FaceOfA(i) => Some(pose_a.rotation * a.faces()[i].0.into_inner()),
        PlaneSource::FaceOfB(j) => Some(-(pose_b.rotation * b.faces()[j].0.into_inner())),
        PlaneSource::EdgePair { edge_a, edge_b, flipped } => {
            let n = (pose_a.rotation * a.edge_directions()[edge_a].into_inner())
                .cross(&(pose_b.rotation * b.edge_directions()[edge_b].into_inner()));
            let len = n.norm();
            (len > 1e-9).then(|| if flipped { -n / len } else { n / len })
        }
    }
}

/// Evaluates one candidate: the plane when it separates.
fn evaluate(
    source: PlaneSource,
    a: &Polyhedron,
    pose_a: &Isometry3<f64>,
    b: &Polyhedron,
    pose_b: &Isometry3<f64>,
) -> Option<SeparatingPlane> {
    let n = candidate_normal(source, a, pose_a, b, pose_b)?;
    let (g, offset) = gap(a, pose_a, b, pose_b, &n);
    (g > 0.0).then(|| SeparatingPlane { normal: Unit::new_unchecked(n), offset, gap: g, source })
}

/// Searches every candidate plane (faces of A, faces of B, then edge pairs in both orientations) and returns the
/// first that separates A from B, or `None` when none does: the polyhedra touch or interpenetrate.
pub fn separating_plane(
    a: &Polyhedron,
    pose_a: &Isometry3<f64>,
    b: &Polyhedron,
    pose_b: &Isometry3<f64>,
) -> Option<SeparatingPlane> {
    let faces_a = (0..a.faces().len()).map(PlaneSource::FaceOfA);
    let faces_b = (0..b.faces().len()).map(PlaneSource::FaceOfB);
    if let Some(p) = faces_a.chain(faces_b).find_map(|s| evaluate(s, a, pose_a, b, pose_b)) {
        return Some(p);
    }
    for edge_a in 0..a.edge_directions().len() {
        for edge_b in 0..b.edge_directions().len() {
            let Some(n) =
                candidate_normal(PlaneSource::EdgePair { edge_a, edge_b, flipped: false }, a, pose_a, b, pose_b)
            else {
                continue;
            };
            // Both orientations from one pass over the vertices of each body.
            let (lo_a, hi_a) = a.extent(&pose_a.rotation.inverse_transform_vector(&n));
            let (lo_b, hi_b) = b.extent(&pose_b.rotation.inverse_transform_vector(&n));
            let (ca, cb) = (n.dot(&pose_a.translation.vector), n.dot(&pose_b.translation.vector));
            let (forward, backward) = (lo_b + cb - (hi_a + ca), lo_a + ca - (hi_b + cb));
            if forward > 0.0 {
                let source = PlaneSource::EdgePair { edge_a, edge_b, flipped: false };
                let offset = 0.5 * (hi_a + ca + lo_b + cb);
                return Some(SeparatingPlane { normal: Unit::new_unchecked(n), offset, gap: forward, source });
            }
            if backward > 0.0 {
                let source = PlaneSource::EdgePair { edge_a, edge_b, flipped: true };
                let offset = -0.5 * (lo_a + ca + hi_b + cb);
                return Some(SeparatingPlane { normal: Unit::new_unchecked(-n), offset, gap: backward, source });
            }
        }
    }
    None
}

/// Separating planes remembered per pair of polyhedra, so that a pair that has moved a little is usually settled by
/// one candidate instead of a search (temporal coherence).
#[derive(Clone, Debug, Default)]
pub struct SeparatingPlaneCache {
    planes: PairMap<PlaneSource>,
    hits: u64,
    searches: u64,
}

impl SeparatingPlaneCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// `separating_plane` for the pair `key` (the caller's ids for A and B, in this order), trying the pair's cached
    /// plane first.
    pub fn test(
        &mut self,
        key: (u32, u32),
        a: &Polyhedron,
        pose_a: &Isometry3<f64>,
        b: &Polyhedron,
        pose_b: &Isometry3<f64>,
    ) -> Option<SeparatingPlane> {
        if let Some(&source) = self.planes.get(&key) {
            if let Some(plane) = evaluate(source, a, pose_a, b, pose_b) {
                self.hits += 1;
                return Some(plane);
            }
        }
        self.searches += 1;
        let found = separating_plane(a, pose_a, b, pose_b);
        match found {
            Some(p) => {
                self.planes.insert(key, p.source);
            }
            None => {
                self.planes.remove(&key);
            }
        }
        found
    }

    /// Tests settled by the cached plane alone.
    pub fn hits(&self) -> u64 {
        self.hits
    }

    /// Tests that needed a search.
    pub fn searches(&self) -> u64 {
        self.searches
    }

    /// Pairs with a cached plane.
    pub fn len(&self) -> usize {
        self.planes.len()
    }

    /// Whether no plane is cached.
    pub fn is_empty(&self) -> bool {
        self.planes.is_empty()
    }

    /// Forgets the pairs for which `keep` is false (pairs that left the broad phase, say).
    pub fn retain(&mut self, mut keep: impl FnMut((u32, u32)) -> bool) {
        self.planes.retain(|k, _| keep(*k));
    }
}
