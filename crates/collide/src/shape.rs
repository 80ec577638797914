//! Shapes: sphere, box, capsule, cylinder (both along the body's z axis), convex hull, closed mesh (exact, or
//! decomposed into convex pieces to move), static triangle mesh and half-space, validated on construction. The hull
//! is `convex_hull.rs`'s, the pieces `decompose.rs`'s.

use crate::convert::{point_from_parry, point_to_parry};
use crate::convex_hull::ConvexHull;
use crate::decompose::{Decomposed, Decomposition};
use crate::error::{finite_point, positive, ShapeError};
use crate::surface_mesh::Mesh;
use nalgebra::{Point3, Unit, Vector3};
use parry3d_f64::shape::TriMesh as ParryTriMesh;
use std::sync::Arc;

/// A triangle mesh; static bodies only (it has no volume to give mass).
#[derive(Clone, Debug)]
pub struct TriMesh {
    pub(crate) mesh: Arc<ParryTriMesh>,
}

impl TriMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.mesh.indices().len()
    }

    /// The mesh's vertices.
    pub fn vertices(&self) -> Vec<Point3<f64>> {
        self.mesh.vertices().iter().map(|&p| point_from_parry(p)).collect()
    }

    /// The triangles, as indices into `vertices`.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.mesh.indices().to_vec()
    }
}

/// A collision and mass shape in its body's frame.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A ball of this radius, centred at the origin.
    Sphere { radius: f64 },
    /// A box with these half extents along x, y, z.
    Cuboid { half_extents: Vector3<f64> },
    /// A capsule: a segment from -half_height to +half_height along z, swept by a ball of this radius.
    Capsule { half_height: f64, radius: f64 },
    /// A cylinder from -half_height to +half_height along z.
    Cylinder { half_height: f64, radius: f64 },
    /// A convex hull.
    ConvexHull(ConvexHull),
    /// A triangle mesh (static only).
    TriMesh(TriMesh),
    /// A closed mesh, its exact triangles (a static body keeps them; a dynamic one is given its decomposition).
    Mesh(Mesh),
    /// A closed mesh decomposed into convex pieces, its mass properties the mesh's.
    Decomposed(Decomposed),
    /// The half-space below the plane through the origin with this outward normal (a ground; static only).
    HalfSpace { normal: Unit<Vector3<f64>> },
}

impl Shape {
    /// A sphere; `radius` > 0.
    pub fn sphere(radius: f64) -> Result<Shape, ShapeError> {
        Ok(Shape::Sphere { radius: positive("radius", radius)? })
    }

    /// A box; every half extent > 0.
    pub fn cuboid(half_extents: Vector3<f64>) -> Result<Shape, ShapeError> {
        for (axis, v) in ["x", "y", "z"].iter().zip(half_extents.iter()) {
            positive("half_extents", *v)
                .map_err(|e| ShapeError::new("half_extents", format!("the {axis} half extent {}", e.reason)))?;
        }
        Ok(Shape::Cuboid { half_extents })
    }

    /// A capsule along z; `half_height` > 0 (a zero one is a sphere), `radius` > 0.
    pub fn capsule(half_height: f64, radius: f64) -> Result<Shape, ShapeError> {
        Ok(Shape::Capsule { half_height: positive("half_height", half_height)?, radius: positive("radius", radius)? })
    }

    /// A cylinder along z; `half_height` > 0, `radius` > 0.
    pub fn cylinder(half_height: f64, radius: f64) -> Result<Shape, ShapeError> {
        Ok(Shape::Cylinder { half_height: positive("half_height", half_height)?, radius: positive("radius", radius)? })
    }

    /// The convex hull of `points`: at least four finite points not all in one plane.
    pub fn convex_hull(points: &[Point3<f64>]) -> Result<Shape, ShapeError> {
        ConvexHull::from_points(points).map(Shape::ConvexHull)
    }

    /// A triangle mesh from vertices and triangles (indices into `vertices`); static bodies only.
    pub fn trimesh(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> Result<Shape, ShapeError> {
        for (i, p) in vertices.iter().enumerate() {
            finite_point("vertices", i, p)?;
        }
        if triangles.is_empty() {
            return Err(ShapeError::new("triangles", "at least one triangle is needed"));
        }
        if let Some((i, t)) =
            triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&k| k as usize >= vertices.len()))
        {
            return Err(ShapeError::new(
                "triangles",
                format!("triangle {i} {t:?} refers past the {} vertices", vertices.len()),
            ));
        }
        let mesh = ParryTriMesh::new(vertices.iter().map(point_to_parry).collect(), triangles.to_vec())
            .map_err(|e| ShapeError::new("triangles", format!("{e:?}")))?;
        Ok(Shape::TriMesh(TriMesh { mesh: Arc::new(mesh) }))
    }

    /// A closed mesh as a shape (its exact triangles).
    pub fn mesh(mesh: Mesh) -> Shape {
        Shape::Mesh(mesh)
    }

    /// A closed mesh's approximate convex decomposition (cached per process).
    pub fn decomposed(mesh: &Mesh, params: &Decomposition) -> Result<Shape, ShapeError> {
        Ok(Shape::Decomposed(Decomposed::new(mesh, params)?))
    }

    /// The convex hull of a mesh's vertices.
    pub fn hull_of(mesh: &Mesh) -> Result<Shape, ShapeError> {
        if mesh.is_convex() {
            // a convex mesh is its own hull: its faces as they are (a hull computed of many nearly coplanar points,
            // as a fracture's pieces have, came out up to 0.2% larger than the points' own)
            if let Ok(hull) = Self::convex_mesh(mesh.vertices(), mesh.triangles()) {
                return Ok(hull);
            }
        }
        Self::convex_hull(mesh.vertices()).map_err(|e| ShapeError::new("mesh", format!("its hull: {}", e.reason)))
    }

    /// A convex polyhedron of the given faces (`triangles` into `points`, counter-clockwise seen from outside, the
    /// surface closed and convex), as they are: no hull is computed. An error naming `triangles` where they do not
    /// make a closed polyhedron.
    pub fn convex_mesh(points: &[Point3<f64>], triangles: &[[u32; 3]]) -> Result<Shape, ShapeError> {
        ConvexHull::from_faces(points, triangles).map(Shape::ConvexHull)
    }

    /// The closed mesh a shape was made from (a mesh or its decomposition).
    pub fn source_mesh(&self) -> Option<&Mesh> {
        match self {
            Shape::Mesh(m) => Some(m),
            Shape::Decomposed(d) => Some(&d.mesh),
            _ => None,
        }
    }

    /// A half-space with the given outward normal (normalised here; it must be finite and nonzero).
    pub fn half_space(normal: Vector3<f64>) -> Result<Shape, ShapeError> {
        let n = normal.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(ShapeError::new("normal", format!("must be finite and nonzero, got {normal:?}")));
        }
        Ok(Shape::HalfSpace { normal: Unit::new_normalize(normal) })
    }

    /// Whether only static bodies may carry this shape (it has no finite volume).
    pub fn is_static_only(&self) -> bool {
        matches!(self, Shape::TriMesh(_) | Shape::HalfSpace { .. })
    }

    /// The shape's name, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Cuboid { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::ConvexHull(_) => "convex hull",
            Shape::TriMesh(_) => "triangle mesh",
            Shape::Mesh(_) => "mesh",
            Shape::Decomposed(_) => "decomposed mesh",
            Shape::HalfSpace { .. } => "half-space",
        }
    }
}
