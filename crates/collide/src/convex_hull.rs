//! The convex hull shape: a convex polyhedron, the hull of a point cloud or a convex mesh's own faces, with the
//! points (and faces) it was made from.

use crate::convert::{point_from_parry, point_to_parry};
use crate::error::{finite_point, ShapeError};
use nalgebra::{Point3, Vector3};
use parry3d_f64::shape::ConvexPolyhedron;
use std::sync::Arc;

/// A convex polyhedron: the hull of a point cloud.
#[derive(Clone, Debug)]
pub struct ConvexHull {
    pub(crate) polyhedron: Arc<ConvexPolyhedron>,
    /// The points it was made from (the hull of the same points is the same hull, features numbered alike).
    pub(crate) source: Arc<Vec<Point3<f64>>>,
    /// The triangles of the points it was made from, for a convex mesh made its own hull (`Shape::convex_mesh`);
    /// None for a hull computed from the points.
    pub(crate) faces: Option<Arc<Vec<[u32; 3]>>>,
}

impl ConvexHull {
    /// The hull's vertices.
    pub fn vertices(&self) -> Vec<Point3<f64>> {
        self.polyhedron.points().iter().map(|&p| point_from_parry(p)).collect()
    }

    /// The points the hull was made from, in their order.
    pub fn source_points(&self) -> &[Point3<f64>] {
        &self.source
    }

    /// The triangles it was made from (a convex mesh's own faces), or None for a hull computed from its points.
    pub fn source_faces(&self) -> Option<&[[u32; 3]]> {
        self.faces.as_deref().map(Vec::as_slice)
    }

    /// The convex hull of `points` (`Shape::convex_hull`): at least four finite points not all in one plane.
    pub(crate) fn from_points(points: &[Point3<f64>]) -> Result<ConvexHull, ShapeError> {
        for (i, p) in points.iter().enumerate() {
            finite_point("points", i, p)?;
        }
        if points.len() < 4 {
            return Err(ShapeError::new("points", format!("a hull needs at least 4 points, got {}", points.len())));
        }
        let pts: Vec<_> = points.iter().map(point_to_parry).collect();
        let polyhedron =
            ConvexPolyhedron::from_convex_hull(&pts).filter(|p| p.points().len() >= 4 && !flat(p)).ok_or_else(
                || ShapeError::new("points", "the points are coplanar (or collinear): their hull has no volume"),
            )?;
        Ok(ConvexHull { polyhedron: Arc::new(polyhedron), source: Arc::new(points.to_vec()), faces: None })
    }

    /// A convex polyhedron of the given faces, as they are (`Shape::convex_mesh`).
    pub(crate) fn from_faces(points: &[Point3<f64>], triangles: &[[u32; 3]]) -> Result<ConvexHull, ShapeError> {
        for (i, p) in points.iter().enumerate() {
            finite_point("points", i, p)?;
        }
        if triangles.iter().any(|t| t.iter().any(|&k| k as usize >= points.len())) {
            return Err(ShapeError::new("triangles", "a triangle refers past the points"));
        }
        let pts: Vec<_> = points.iter().map(point_to_parry).collect();
        let polyhedron = ConvexPolyhedron::from_convex_mesh(pts, triangles)
            .ok_or_else(|| ShapeError::new("triangles", "they do not make a closed convex polyhedron"))?;
        Ok(ConvexHull {
            polyhedron: Arc::new(polyhedron),
            source: Arc::new(points.to_vec()),
            faces: Some(Arc::new(triangles.to_vec())),
        })
    }
}

/// Whether a polyhedron is flat: all its vertices within 1e-12 (relative to its size) of the plane of its first
/// three non-collinear ones.
fn flat(p: &ConvexPolyhedron) -> bool {
    let pts: Vec<Vector3<f64>> = p.points().iter().map(|&v| point_from_parry(v).coords).collect();
    let size = pts.iter().map(|v| (v - pts[0]).norm()).fold(0.0, f64::max);
    let o = pts[0];
    let normal = pts
        .iter()
        .skip(1)
        .flat_map(|a| pts.iter().skip(2).map(move |b| (a - o).cross(&(b - o))))
        .max_by(|x, y| x.norm().total_cmp(&y.norm()));
    match normal {
        Some(n) if n.norm() > 1e-12 * size * size => {
            let n = n.normalize();
            pts.iter().all(|v| (v - pts[0]).dot(&n).abs() <= 1e-12 * size)
        }
        _ => true,
    }
}
