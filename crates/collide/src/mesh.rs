//! Triangle meshes of shapes, for drawing and animation export (parry triangulates them).

use crate::convert::{from_parry, point_from_parry, to_parry};
use crate::shape::Shape;
use nalgebra::{Point3, Rotation3, Vector3};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder};

impl Shape {
    /// The shape's surface as triangles in its own frame, curved shapes with `subdivisions` segments around (3 to
    /// 1024; values outside are clamped, so the mesh stays below a few million triangles). A half-space is drawn as a square of side `2 * extent` on its plane.
    pub fn triangle_mesh(&self, subdivisions: u32, extent: f64) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
        let n = subdivisions.clamp(3, 1024);
        let (vertices, triangles) = match self {
            Shape::Sphere { radius } => Ball::new(*radius).to_trimesh(n, n / 2 + 1),
            Shape::Cuboid { half_extents } => Cuboid::new(to_parry(half_extents)).to_trimesh(),
            Shape::Capsule { half_height, radius } => Capsule::new_z(*half_height, *radius).to_trimesh(n, n / 2 + 1),
            Shape::Cylinder { half_height, radius } => {
                // parry's cylinder runs along y; ours along z.
                let (v, t) = Cylinder::new(*half_height, *radius).to_trimesh(n);
                let r = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
                return (v.into_iter().map(|p| Point3::from(r * from_parry(p))).collect(), t);
            }
            Shape::ConvexHull(h) => h.polyhedron.to_trimesh(),
            Shape::TriMesh(m) => (m.mesh.vertices().to_vec(), m.mesh.indices().to_vec()),
            // a mesh is drawn as given, not as its convex pieces
            Shape::Mesh(m) => return (m.vertices().to_vec(), m.triangles().to_vec()),
            Shape::Decomposed(d) => return (d.mesh.vertices().to_vec(), d.mesh.triangles().to_vec()),
            Shape::HalfSpace { normal } => {
                let (u, v) = orthonormal_pair(normal);
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                let pts = corners.iter().map(|(a, b)| Point3::from((u * *a + v * *b) * extent)).collect();
                return (pts, vec![[0, 1, 2], [0, 2, 3]]);
            }
        };
        (vertices.into_iter().map(point_from_parry).collect(), triangles)
    }
}

/// Two unit vectors spanning the plane orthogonal to `n`, with (u, v, n) right-handed.
fn orthonormal_pair(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let seed = if n.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let u = n.cross(&seed).normalize();
    (u, n.cross(&u))
}
