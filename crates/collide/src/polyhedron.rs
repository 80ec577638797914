//! Convex polyhedra as the separating-plane test sees them: vertices, face planes and edge directions (one per set of
//! parallel edges), in the shape's frame.

use crate::convert::from_parry;
use crate::error::ShapeError;
use crate::shape::Shape;
use nalgebra::{Unit, Vector3};

/// A convex polyhedron in its shape's frame: a box or a convex hull.
#[derive(Clone, Debug)]
pub struct Polyhedron {
    vertices: Vec<Vector3<f64>>,
    /// Face planes: outward unit normal n and offset d, the polyhedron being n . x <= d.
    faces: Vec<(Unit<Vector3<f64>>, f64)>,
    /// Edge directions, one per set of parallel edges.
    edges: Vec<Unit<Vector3<f64>>>,
}

impl Polyhedron {
    /// The polyhedron of a box or a convex hull; any other shape is an error (the test needs flat faces).
    pub fn from_shape(shape: &Shape) -> Result<Polyhedron, ShapeError> {
        match shape {
            Shape::Cuboid { half_extents: h } => Ok(Self::cuboid(h)),
            Shape::ConvexHull(hull) => {
                let p = &hull.polyhedron;
                let vertices: Vec<Vector3<f64>> = p.points().iter().map(|&v| from_parry(v)).collect();
                let faces = p
                    .faces()
                    .iter()
                    .map(|f| {
                        let n = Unit::new_normalize(from_parry(f.normal));
                        let v = vertices[p.vertices_adj_to_face()[f.first_vertex_or_edge as usize] as usize];
                        (n, n.dot(&v))
                    })
                    .collect();
                // Only edges that bound a face: parry keeps the diagonals of merged coplanar triangles too.
                let mut edges: Vec<Unit<Vector3<f64>>> = Vec::new();
                for &e in p.edges_adj_to_face() {
                    let [a, b] = p.edges()[e as usize].vertices;
                    push_direction(&mut edges, vertices[b as usize] - vertices[a as usize]);
                }
                Ok(Polyhedron { vertices, faces, edges })
            }
            other => Err(ShapeError::new(
                "shape",
                format!(
                    "the separating-plane test needs a convex polyhedron (a box or a convex hull), got a {}",
                    other.kind()
                ),
            )),
        }
    }

    fn cuboid(h: &Vector3<f64>) -> Polyhedron {
        let mut vertices = Vec::with_capacity(8);
        for &sx in &[-1.0, 1.0] {
            for &sy in &[-1.0, 1.0] {
                for &sz in &[-1.0, 1.0] {
                    vertices.push(Vector3::new(sx * h.x, sy * h.y, sz * h.z));
                }
            }
        }
        let axes = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()];
        let faces = axes.iter().enumerate().flat_map(|(k, a)| [(*a, h[k]), (-*a, h[k])]).collect();
        Polyhedron { vertices, faces, edges: axes.to_vec() }
    }

    /// The vertices, in the shape's frame.
    pub fn vertices(&self) -> &[Vector3<f64>] {
        &self.vertices
    }

    /// The face planes `(n, d)`: the polyhedron is the set of x with n . x <= d for every face.
    pub fn faces(&self) -> &[(Unit<Vector3<f64>>, f64)] {
        &self.faces
    }

    /// One direction per set of parallel edges.
    pub fn edge_directions(&self) -> &[Unit<Vector3<f64>>] {
        &self.edges
    }

    /// The smallest and largest of `dir . v` over the vertices (`dir` in the shape's frame).
    #[inline]
    pub(crate) fn extent(&self, dir: &Vector3<f64>) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for v in &self.vertices {
            let d = dir.dot(v);
            lo = lo.min(d);
            hi = hi.max(d);
        }
        (lo, hi)
    }
}

/// Adds `d`'s direction unless an edge already in `edges` is parallel to it (sines below 1e-9).
fn push_direction(edges: &mut Vec<Unit<Vector3<f64>>>, d: Vector3<f64>) {
    let Some(u) = Unit::try_new(d, 0.0) else { return };
    if edges.iter().all(|e| e.cross(&u).norm() > 1e-9) {
        edges.push(u);
    }
}
