//! Colliders and materials: the shapes a body carries (each with its pose in the body frame, whose origin is the
//! centre of mass) and the restitution and friction its contacts use, with the rule that combines two materials.

use crate::error::WorldError;
use nalgebra::{Isometry3, Matrix3, Vector3};
use tumble_collide::{MassProperties, Shape};

/// A shape attached to a body, posed in the body frame (origin at the centre of mass).
#[derive(Clone, Debug)]
pub struct Collider {
    /// The shape, in its own frame.
    pub shape: Shape,
    /// Where the shape's frame sits in the body frame.
    pub offset: Isometry3<f64>,
}

/// Restitution and friction of a surface.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    /// Coefficient of friction >= 0.
    pub friction: f64,
}

impl Default for Material {
    /// Restitution 0, friction 0.5 (the API's defaults: bodies that meet come to rest together, as in Blender's
    /// and Rapier's defaults; a bounce is asked for).
    fn default() -> Self {
        Material { restitution: 0.0, friction: 0.5 }
    }
}

impl Material {
    /// Checks both coefficients.
    pub(crate) fn check(&self) -> Result<(), WorldError> {
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(WorldError::invalid("restitution", format!("must be in [0, 1], got {}", self.restitution)));
        }
        crate::limits::non_negative("friction", self.friction, 1e3, "")?;
        Ok(())
    }

    /// The material of a contact between two surfaces: the larger restitution (a bouncy ball bounces on any floor;
    /// a dead one stays dead only on a dead floor) and the geometric mean of the frictions (zero if either surface
    /// is frictionless), the rule of Box2D and of most game engines.
    pub fn combine(&self, other: &Material) -> Material {
        Material {
            restitution: self.restitution.max(other.restitution),
            friction: (self.friction * other.friction).sqrt(),
        }
    }
}

/// Mass, centre of mass and inertia (about the centre of mass) of several shapes of one density, each posed in a
/// common frame.
pub(crate) fn compound_mass(parts: &[(Shape, Isometry3<f64>)], density: f64) -> Result<MassProperties, WorldError> {
    let props: Vec<(MassProperties, &Isometry3<f64>)> =
        parts.iter().map(|(s, pose)| Ok((s.mass_properties(density)?, pose))).collect::<Result<_, WorldError>>()?;
    let mass: f64 = props.iter().map(|(p, _)| p.mass).sum();
    let com: Vector3<f64> = props
        .iter()
        .map(|(p, pose)| (**pose * nalgebra::Point3::from(p.local_com)).coords * p.mass)
        .sum::<Vector3<f64>>()
        / mass;
    let mut inertia = Matrix3::zeros();
    for (p, pose) in &props {
        let r = pose.rotation.to_rotation_matrix();
        let d = (**pose * nalgebra::Point3::from(p.local_com)).coords - com;
        inertia += r.matrix() * p.inertia * r.matrix().transpose()
            + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * p.mass;
    }
    Ok(MassProperties { mass, local_com: com, inertia: 0.5 * (inertia + inertia.transpose()) })
}
