//! Colliders and materials: the shapes a body carries (each with its pose in the body frame, whose origin is the
//! centre of mass) and the restitution and friction its contacts use, with the rule that combines two materials.

use crate::error::WorldError;
use nalgebra::{Isometry3, Matrix3, Vector3};
use tumble_collide::rotated_tensor;
use tumble_collide::{MassProperties, Shape};

/// A shape attached to a body, posed in the body frame (origin at the centre of mass).
#[derive(Clone, Debug)]
pub struct Collider {
    /// The shape, in its own frame.
    pub shape: Shape,
    /// Where the shape's frame sits in the body frame.
    pub offset: Isometry3<f64>,
}

/// How the coefficients of two surfaces combine at a contact between them. A surface's own rule comes before the
/// world's; where two surfaces ask for different rules of their own, the later in this list wins (Rapier's and
/// PhysX's priority: average, then geometric mean, min, product, max).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Combine {
    /// (a + b) / 2.
    Average,
    /// sqrt(a b): zero if either is (Box2D's friction).
    GeometricMean,
    /// The smaller.
    Min,
    /// a b (Bullet's, so Blender's, for friction and restitution).
    Product,
    /// The larger (Box2D's restitution).
    Max,
}

impl Combine {
    /// Every rule, by its name.
    pub const ALL: [(&'static str, Combine); 5] = [
        ("average", Combine::Average),
        ("geometric_mean", Combine::GeometricMean),
        ("min", Combine::Min),
        ("product", Combine::Product),
        ("max", Combine::Max),
    ];

    /// The two coefficients combined.
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Combine::Average => 0.5 * (a + b),
            Combine::GeometricMean => (a * b).sqrt(),
            Combine::Min => a.min(b),
            Combine::Product => a * b,
            Combine::Max => a.max(b),
        }
    }

    /// The rule called `name` ("average", "geometric_mean", "min", "product" or "max"); an error naming `argument`
    /// otherwise.
    pub fn parse(argument: &'static str, name: &str) -> Result<Combine, WorldError> {
        Combine::ALL.iter().find(|(n, _)| *n == name).map(|(_, c)| *c).ok_or_else(|| {
            let names: Vec<&str> = Combine::ALL.iter().map(|(n, _)| *n).collect();
            WorldError::invalid(argument, format!("must be one of {}, got {name:?}", names.join(", ")))
        })
    }

    /// Its name (as `parse` takes it).
    pub fn name(self) -> &'static str {
        Combine::ALL.iter().find(|(_, c)| *c == self).map(|(n, _)| *n).expect("every rule is named")
    }

    /// The rule of a pair whose surfaces ask for `a` and `b` (`None`: none of their own): a surface's own rule over
    /// the world's `world`, and of two own rules the later in the list.
    fn of_pair(a: Option<Combine>, b: Option<Combine>, world: Combine) -> Combine {
        match (a, b) {
            (Some(a), Some(b)) => a.max(b),
            (Some(own), None) | (None, Some(own)) => own,
            (None, None) => world,
        }
    }
}

/// A world's rules for surfaces that name none: by default the geometric mean of the frictions and the larger
/// restitution (a bouncy ball bounces on any floor; a dead one stays dead only on a dead floor), Box2D's and most
/// game engines'.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CombineRules {
    pub friction: Combine,
    pub restitution: Combine,
}

impl Default for CombineRules {
    fn default() -> Self {
        CombineRules { friction: Combine::GeometricMean, restitution: Combine::Max }
    }
}

/// A surface: restitution, friction, rolling and torsional resistance, and, if it asks for its own, how its
/// friction and restitution combine with another's.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    /// Coefficient of friction >= 0.
    pub friction: f64,
    /// Coefficient of rolling resistance >= 0 (dimensionless; 0: none): a contact resists the bodies' relative
    /// turn across its normal with a torque of at most this times the normal force times the rolling radius (the
    /// distance along the normal from the contact to the turning body's centre of mass: a ball's radius), so a
    /// solid ball rolling on a flat floor slows at 5/7 of this times g. Box3D's rolling resistance.
    #[serde(default)]
    pub rolling_resistance: f64,
    /// Coefficient of torsional resistance >= 0 (dimensionless; 0: none): as rolling resistance, about the normal
    /// (a ball spinning in place on a floor stops).
    #[serde(default)]
    pub torsional_resistance: f64,
    /// How its friction and restitution combine with another surface's (`None`: the world's rules).
    #[serde(default)]
    pub friction_combine: Option<Combine>,
    #[serde(default)]
    pub restitution_combine: Option<Combine>,
}

impl Default for Material {
    /// Restitution 0, friction 0.5 (the API's defaults: bodies that meet come to rest together, as in Blender's
    /// and Rapier's defaults; a bounce is asked for), no rolling or torsional resistance, the world's rules.
    fn default() -> Self {
        Material::new(0.0, 0.5)
    }
}

impl Material {
    /// Restitution and friction, no resistance, the world's rules.
    pub const fn new(restitution: f64, friction: f64) -> Material {
        Material {
            restitution,
            friction,
            rolling_resistance: 0.0,
            torsional_resistance: 0.0,
            friction_combine: None,
            restitution_combine: None,
        }
    }

    /// Checks every coefficient.
    pub(crate) fn check(&self) -> Result<(), WorldError> {
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(WorldError::invalid("restitution", format!("must be in [0, 1], got {}", self.restitution)));
        }
        crate::limits::non_negative("friction", self.friction, 1e3, "")?;
        crate::limits::non_negative("rolling_resistance", self.rolling_resistance, 1e3, "")?;
        crate::limits::non_negative("torsional_resistance", self.torsional_resistance, 1e3, "")?;
        Ok(())
    }

    /// Whether it resists turning (rolling or torsion).
    pub fn resists_turning(&self) -> bool {
        self.rolling_resistance > 0.0 || self.torsional_resistance > 0.0
    }

    /// Whether `mode` can hold this material: resistance to turning needs contact steps with lagged friction or
    /// the soft step (the chapter's resting forces and Anitescu's cone have no rows for it); else why not.
    pub(crate) fn fits_mode(&self, mode: &crate::mode::Mode) -> Result<(), &'static str> {
        use crate::mode::{FastFriction, FastSolver, Mode, Persistent};
        if !self.resists_turning() {
            return Ok(());
        }
        match mode {
            Mode::Accurate(a) if a.persistent == Persistent::RestingForces => {
                Err("the chapter's resting forces have no rolling or torsional resistance: use persistent contact \
                     steps (the default)")
            }
            Mode::Fast(f) if matches!(f.solver, FastSolver::Exact { friction: FastFriction::Cone, .. }) => {
                Err("Anitescu's cone has no rolling or torsional resistance: use lagged friction or the soft step")
            }
            _ => Ok(()),
        }
    }

    /// The material of a contact between two surfaces: friction and restitution by the pair's rules (a surface's
    /// own, the later in `Combine`'s list where both have one, else the world's `rules`), rolling and
    /// torsional resistance the larger (a ball's own resistance acts on any floor, as Box3D's).
    pub fn combine(&self, other: &Material, rules: &CombineRules) -> Material {
        let friction = Combine::of_pair(self.friction_combine, other.friction_combine, rules.friction);
        let restitution = Combine::of_pair(self.restitution_combine, other.restitution_combine, rules.restitution);
        Material {
            restitution: restitution.apply(self.restitution, other.restitution),
            friction: friction.apply(self.friction, other.friction),
            rolling_resistance: self.rolling_resistance.max(other.rolling_resistance),
            torsional_resistance: self.torsional_resistance.max(other.torsional_resistance),
            friction_combine: None,
            restitution_combine: None,
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
        inertia += rotated_tensor(r.matrix(), &p.inertia)
            + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * p.mass;
    }
    Ok(MassProperties { mass, local_com: com, inertia: 0.5 * (inertia + inertia.transpose()) })
}
