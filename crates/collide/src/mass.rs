//! Mass properties of shapes at a density (parry computes them), in the shape's frame and nalgebra types.

use crate::convert::{from_parry, matrix_from_parry, to_parry};
use crate::error::ShapeError;
use crate::shape::Shape;
use nalgebra::{Matrix3, Vector3};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, Shape as ParryShape};

/// Mass, centre of mass and inertia tensor about the centre of mass, in the shape's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass.
    pub mass: f64,
    /// Centre of mass in the shape's frame.
    pub local_com: Vector3<f64>,
    /// Inertia tensor about the centre of mass, axes of the shape's frame.
    pub inertia: Matrix3<f64>,
}

impl Shape {
    /// Mass properties at `density` (> 0). Static-only shapes (triangle mesh, half-space) have none.
    pub fn mass_properties(&self, density: f64) -> Result<MassProperties, ShapeError> {
        if !(density.is_finite() && density > 0.0) {
            return Err(ShapeError::new("density", format!("must be finite and > 0, got {density}")));
        }
        let props = match self {
            Shape::Sphere { radius } => Ball::new(*radius).mass_properties(density),
            Shape::Cuboid { half_extents } => Cuboid::new(to_parry(half_extents)).mass_properties(density),
            Shape::Capsule { half_height, radius } => Capsule::new_z(*half_height, *radius).mass_properties(density),
            Shape::Cylinder { half_height, radius } => {
                // parry's cylinder runs along y; ours along z: rotate the tensor about x by 90 degrees.
                let p = Cylinder::new(*half_height, *radius).mass_properties(density);
                let i = matrix_from_parry(p.reconstruct_inertia_matrix());
                let r = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
                return Ok(MassProperties {
                    mass: p.mass(),
                    local_com: Vector3::zeros(),
                    inertia: r * i * r.transpose(),
                });
            }
            Shape::ConvexHull(h) => h.polyhedron.mass_properties(density),
            Shape::TriMesh(_) | Shape::HalfSpace { .. } => {
                return Err(ShapeError::new(
                    "shape",
                    format!("a {} has no volume: it can only belong to a static body", self.kind()),
                ))
            }
        };
        let inertia = matrix_from_parry(props.reconstruct_inertia_matrix());
        Ok(MassProperties {
            mass: props.mass(),
            local_com: from_parry(props.local_com),
            inertia: 0.5 * (inertia + inertia.transpose()),
        })
    }
}
