//! A closed triangle mesh as a user models it: checked to bound a solid (closed, consistently oriented outward, no
//! degenerate or repeated triangles, positive volume), with its volume, centre of mass and inertia tensor by the
//! divergence theorem.

use crate::convert::point_to_parry;
use crate::error::{ShapeError, LENGTH};
use nalgebra::{Matrix3, Point3, Vector3};
use parry3d_f64::shape::TriMesh as ParryTriMesh;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The most triangles a mesh may have (about 300 MB of vertices and indices).
pub const MAX_TRIANGLES: usize = 10_000_000;

/// A closed, outward-oriented triangle mesh: a solid's surface. A dynamic body carries its convex decomposition, a
/// static one the exact triangles; its mass properties are the solid's.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub(crate) vertices: Arc<Vec<Point3<f64>>>,
    pub(crate) triangles: Arc<Vec<[u32; 3]>>,
    pub(crate) name: Arc<str>,
    /// The exact triangles, for a static body and for queries.
    pub(crate) exact: Arc<ParryTriMesh>,
    /// Volume, centre of mass and inertia about it at unit density.
    pub(crate) unit: crate::MassProperties,
}

impl Mesh {
    /// A mesh of `vertices` and `triangles` (indices into `vertices`, counter-clockwise seen from outside), named
    /// `name` in messages. Vertices at the same place are one vertex of the surface (as files that split vertices
    /// along seams have them). Every check's error names the mesh and what is wrong, and suggests its hull.
    pub fn new(vertices: &[Point3<f64>], triangles: &[[u32; 3]], name: &str) -> Result<Mesh, ShapeError> {
        let label = label(name);
        let bad = |reason: String| ShapeError::new("mesh", format!("{label} {reason}"));
        let hint = "; its convex hull (shape=\"hull\") needs no closed surface";
        for (i, p) in vertices.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite() && c.abs() <= LENGTH.1) {
                return Err(bad(format!("has vertex {i} not finite or past 1e9 m: {p:?}")));
            }
        }
        if triangles.is_empty() {
            return Err(bad("has no triangles".into()));
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(bad(format!("has {} triangles, more than the {MAX_TRIANGLES} allowed", triangles.len())));
        }
        if let Some((i, t)) =
            triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&k| k as usize >= vertices.len()))
        {
            return Err(bad(format!("has triangle {i} {t:?} referring past its {} vertices", vertices.len())));
        }
        let weld = welded(vertices);
        let size = extent(vertices);
        let mut seen: Vec<([u32; 3], usize)> = Vec::with_capacity(triangles.len());
        for (i, t) in triangles.iter().enumerate() {
            let w = t.map(|k| weld[k as usize]);
            let [a, b, c] = t.map(|k| vertices[k as usize].coords);
            if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] || (b - a).cross(&(c - a)).norm() <= 1e-14 * size * size {
                return Err(bad(format!("has degenerate triangle {i} {t:?} (no area){hint}")));
            }
            let mut key = w;
            key.sort_unstable();
            seen.push((key, i));
        }
        seen.sort_unstable();
        if let Some(w) = seen.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(bad(format!(
                "has triangles {} and {} on the same three vertices (duplicates){hint}",
                w[0].1, w[1].1
            )));
        }
        check_edges(triangles, &weld).map_err(|e| bad(format!("{e}{hint}")))?;
        let unit = integrals(vertices, triangles);
        if !(unit.mass > 1e-12 * size * size * size) {
            let why = if unit.mass < 0.0 {
                "is inside out (its triangles wind clockwise seen from outside: reverse each triangle's order)"
            } else {
                "has no volume"
            };
            return Err(bad(format!("{why}{hint}")));
        }
        let exact = ParryTriMesh::new(vertices.iter().map(point_to_parry).collect(), triangles.to_vec())
            .map_err(|e| bad(format!("is refused by the triangle-mesh builder: {e:?}")))?;
        Ok(Mesh {
            vertices: Arc::new(vertices.to_vec()),
            triangles: Arc::new(triangles.to_vec()),
            name: name.into(),
            exact: Arc::new(exact),
            unit,
        })
    }

    /// The vertices, as given.
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// The triangles, as given.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The name given (a file's mesh name, or empty).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether the solid is convex: every vertex on or below every triangle's plane (to 1e-9 of its size). A mesh
    /// too large to check cheaply (more than 1e8 vertex-triangle pairs) counts as not convex.
    pub fn is_convex(&self) -> bool {
        let (v, t) = (self.vertices(), self.triangles());
        if v.len().saturating_mul(t.len()) > 100_000_000 {
            return false;
        }
        let slack = 1e-9 * extent(v);
        t.iter().all(|tri| {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            match (b - a).cross(&(c - a)).try_normalize(0.0) {
                Some(n) => v.iter().all(|p| n.dot(&(p - a)) <= slack),
                None => true,
            }
        })
    }

    /// The enclosed volume (m^3).
    pub fn volume(&self) -> f64 {
        self.unit.mass
    }

    /// A 64-bit digest of the vertices' and triangles' bits (FNV-1a), the decomposition cache's key.
    pub fn digest(&self) -> u64 {
        let mut h = Fnv::default();
        for p in self.vertices.iter() {
            p.iter().for_each(|c| h.add(c.to_bits()));
        }
        for t in self.triangles.iter() {
            t.iter().for_each(|&k| h.add(k as u64));
        }
        h.0
    }
}

/// How messages name a mesh: `mesh "cup"`, or `the mesh` when it has no name.
pub(crate) fn label(name: &str) -> String {
    if name.is_empty() {
        "the mesh".to_string()
    } else {
        format!("mesh \"{name}\"")
    }
}

/// FNV-1a over 64-bit words.
pub(crate) struct Fnv(pub u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    pub(crate) fn add(&mut self, word: u64) {
        for byte in word.to_le_bytes() {
            self.0 = (self.0 ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// The largest coordinate extent of the points (1 for none).
pub(crate) fn extent(points: &[Point3<f64>]) -> f64 {
    let (mut lo, mut hi) = (Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.inf(&p.coords);
        hi = hi.sup(&p.coords);
    }
    let e = (hi - lo).amax();
    if e > 0.0 && e.is_finite() {
        e
    } else {
        1.0
    }
}

/// For each vertex, the index of the first vertex at the same place (so messages name vertices as given).
fn welded(vertices: &[Point3<f64>]) -> Vec<u32> {
    let mut first: BTreeMap<[u64; 3], u32> = BTreeMap::new();
    vertices
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // +0.0 and -0.0 are one place
            let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
            *first.entry(key).or_insert(i as u32)
        })
        .collect()
}

/// Every edge (of welded vertices) must be met once in each direction: once means a hole, twice the same way a
/// flipped neighbour, three or more times a non-manifold edge.
fn check_edges(triangles: &[[u32; 3]], weld: &[u32]) -> Result<(), String> {
    let mut edges: Vec<(u32, u32, bool, usize)> = Vec::with_capacity(3 * triangles.len());
    for (i, t) in triangles.iter().enumerate() {
        let w = t.map(|k| weld[k as usize]);
        for k in 0..3 {
            let (a, b) = (w[k], w[(k + 1) % 3]);
            edges.push((a.min(b), a.max(b), a < b, i));
        }
    }
    edges.sort_unstable();
    let mut k = 0;
    while k < edges.len() {
        let (a, b) = (edges[k].0, edges[k].1);
        let run = edges[k..].iter().take_while(|e| e.0 == a && e.1 == b).count();
        let group = &edges[k..k + run];
        let (v, w) = (a, b);
        match run {
            1 => return Err(format!("is not closed: the edge between vertices {v} and {w} has one triangle ({})", group[0].3)),
            2 if group[0].2 == group[1].2 => {
                return Err(format!(
                    "is not consistently oriented: triangles {} and {} run the same way along the edge between vertices {v} and {w}",
                    group[0].3, group[1].3
                ))
            }
            2 => {}
            n => return Err(format!("is not manifold: the edge between vertices {v} and {w} has {n} triangles")),
        }
        k += run;
    }
    Ok(())
}

/// Volume, centre of mass and inertia about it at unit density, summed over the tetrahedra from a reference point
/// (the vertices' mean, to keep the sums small) to each triangle: for a tetrahedron (0, a, b, c) with D = a . (b x c),
/// volume D / 6, first moment D / 24 (a + b + c), second moment D / 120 (a a^T + b b^T + c c^T + s s^T), s = a + b + c.
pub(crate) fn integrals(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> crate::MassProperties {
    let used: Vec<bool> = {
        let mut u = vec![false; vertices.len()];
        triangles.iter().flatten().for_each(|&k| u[k as usize] = true);
        u
    };
    let n = used.iter().filter(|&&u| u).count().max(1) as f64;
    let o = vertices.iter().zip(&used).filter(|(_, &u)| u).fold(Vector3::zeros(), |s, (p, _)| s + p.coords) / n;
    let (mut volume, mut first, mut second) = (0.0, Vector3::zeros(), Matrix3::zeros());
    for t in triangles {
        let [a, b, c] = t.map(|k| vertices[k as usize].coords - o);
        let d = a.dot(&b.cross(&c));
        let s = a + b + c;
        volume += d / 6.0;
        first += s * (d / 24.0);
        second += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose()) * (d / 120.0);
    }
    let com = if volume != 0.0 { first / volume } else { Vector3::zeros() };
    let c = second - com * com.transpose() * volume;
    let inertia = Matrix3::identity() * c.trace() - c;
    crate::MassProperties { mass: volume, local_com: com + o, inertia: 0.5 * (inertia + inertia.transpose()) }
}
