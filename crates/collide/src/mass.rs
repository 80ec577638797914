//! Mass properties of shapes at a density (parry computes them), in the shape's frame and nalgebra types.

use crate::convert::{from_parry, matrix_from_parry, to_parry};
use crate::error::ShapeError;
use crate::mass_properties::{rotated_tensor, MassProperties};
use crate::shape::Shape;
use nalgebra::{Matrix3, Vector3};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, Shape as ParryShape};

impl Shape {
    /// Mass properties at `density` (> 0). Static-only shapes (triangle mesh, half-space) have none. They are
    /// computed at unit density and scaled: parry's eigen-decomposition of a hull's tensor overflowed to NaN
    /// for densities past about 1e157. A mass or inertia that overflows is an error naming `density`.
    pub fn mass_properties(&self, density: f64) -> Result<MassProperties, ShapeError> {
        if !(density.is_finite() && density > 0.0) {
            return Err(ShapeError::new("density", format!("must be finite and > 0, got {density}")));
        }
        let unit = self.unit_mass_properties()?;
        let out =
            MassProperties { mass: unit.mass * density, local_com: unit.local_com, inertia: unit.inertia * density };
        if !(out.mass.is_finite() && out.inertia.iter().all(|v| v.is_finite())) {
            return Err(ShapeError::new("density", format!("{density:e} gives a mass or inertia that overflows")));
        }
        Ok(out)
    }

    fn unit_mass_properties(&self) -> Result<MassProperties, ShapeError> {
        let density = 1.0;
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
                    inertia: rotated_tensor(&r, &i),
                });
            }
            Shape::ConvexHull(h) => h.polyhedron.mass_properties(density),
            Shape::Mesh(m) => return Ok(m.unit),
            Shape::Decomposed(d) => return Ok(d.mesh.unit),
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    #[test]
    fn a_hull_at_a_huge_density_has_finite_mass_properties_or_an_error() {
        // Regression: parry's hull tensor went NaN from a density of about 1e157 (found by the fuzzer).
        let corners: Vec<Point3<f64>> = [-0.3, 0.3]
            .iter()
            .flat_map(|&x| [-0.2, 0.2].into_iter().flat_map(move |y| [-0.25, 0.25].map(|z| Point3::new(x, y, z))))
            .collect();
        let hull = Shape::convex_hull(&corners).unwrap();
        let box_ = Shape::cuboid(Vector3::new(0.3, 0.2, 0.25)).unwrap();
        for density in [1.0, 1e157, 1e300] {
            let (h, b) = (hull.mass_properties(density).unwrap(), box_.mass_properties(density).unwrap());
            assert!(h.inertia.iter().all(|v| v.is_finite()), "density {density:e}: {}", h.inertia);
            // the hull is the box: same mass and tensor to rounding
            assert!((h.mass - b.mass).abs() <= 1e-12 * b.mass);
            assert!((h.inertia - b.inertia).amax() <= 1e-12 * b.inertia.amax(), "{} vs {}", h.inertia, b.inertia);
        }
        let huge = Shape::cuboid(Vector3::repeat(1e9)).unwrap();
        assert_eq!(huge.mass_properties(1e300).unwrap_err().name, "density");
    }
}
