//! Describing a rigid body to add: `RigidBodyBuilder` (dynamic from a shape and a density or mass, or from a mass
//! and an inertia; static; kinematic on keyframes), its checks, and its mass properties resolved.

use crate::body::{Kinematic, RigidBody, ALL_GROUPS};
use crate::collider::{compound_mass, Collider, Material};
use crate::error::{check_finite, check_scalar, WorldError};
use crate::keyframes::Keyframes;
use crate::limits;
use crate::look::Look;
use crate::mesh_shape::MeshShape;
use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use std::sync::Arc;
use tumble_collide::rotated_tensor;
use tumble_collide::Shape;

/// Describes a rigid body to add.
#[derive(Clone, Debug)]
pub struct RigidBodyBuilder {
    mass: Option<f64>,
    inertia: Option<Matrix3<f64>>,
    density: Option<f64>,
    shape: Option<Shape>,
    extra: Vec<(Shape, Isometry3<f64>)>,
    is_static: bool,
    position: Vector3<f64>,
    orientation: UnitQuaternion<f64>,
    velocity: Vector3<f64>,
    angular_velocity: Vector3<f64>,
    linear_damping: f64,
    angular_damping: f64,
    material: Material,
    mesh_shape: Option<MeshShape>,
    /// The modelled frame's origin in the body frame, as a saved world has it.
    origin: Option<Vector3<f64>>,
    look: Look,
    groups: u32,
    keyframes: Option<Keyframes>,
    /// Whether a position or orientation was given (a kinematic body has its pose from its keyframes).
    posed: bool,
}

impl RigidBodyBuilder {
    fn empty() -> Self {
        RigidBodyBuilder {
            mass: None,
            inertia: None,
            density: None,
            shape: None,
            extra: Vec::new(),
            is_static: false,
            position: Vector3::zeros(),
            orientation: UnitQuaternion::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            linear_damping: 0.0,
            angular_damping: 0.0,
            material: Material::default(),
            mesh_shape: None,
            origin: None,
            look: Look::default(),
            groups: ALL_GROUPS,
            keyframes: None,
            posed: false,
        }
    }

    /// A dynamic body with the given mass and body-frame inertia tensor (symmetric positive definite).
    pub fn new(mass: f64, inertia: Matrix3<f64>) -> Self {
        RigidBodyBuilder { mass: Some(mass), inertia: Some(inertia), ..Self::empty() }
    }

    /// A dynamic body whose mass properties come from `shape` at `density`.
    pub fn from_shape(shape: Shape, density: f64) -> Self {
        RigidBodyBuilder { shape: Some(shape), density: Some(density), ..Self::empty() }
    }

    /// A dynamic body shaped `shape` with total mass `mass` (the shape's inertia scaled to that mass).
    pub fn from_shape_with_mass(shape: Shape, mass: f64) -> Self {
        RigidBodyBuilder { shape: Some(shape), mass: Some(mass), ..Self::empty() }
    }

    /// A static body: immovable, not integrated; it may carry any shape and anchor springs.
    pub fn fixed(shape: Option<Shape>) -> Self {
        RigidBodyBuilder { shape, is_static: true, ..Self::empty() }
    }

    /// A kinematic body: it follows `keyframes` (the poses of its shapes' frame, as a static body's), pushes the
    /// bodies it touches with its velocity and is never pushed back (Blender's "Animated", MuJoCo's mocap bodies,
    /// Rapier's kinematic bodies). It has no mass; a position, orientation, velocity or damping does not apply.
    pub fn kinematic(shape: Option<Shape>, keyframes: Keyframes) -> Self {
        RigidBodyBuilder { shape, keyframes: Some(keyframes), ..Self::empty() }
    }

    /// Sets the collision shape of a body whose mass and inertia were given directly.
    pub fn shape(mut self, shape: Shape) -> Self {
        self.shape = Some(shape);
        self
    }
    /// Adds another collider, posed relative to the main shape's frame (or, for a body given by mass and inertia,
    /// to its centre of mass). With a density, it adds its mass too.
    pub fn collider(mut self, shape: Shape, offset: Isometry3<f64>) -> Self {
        self.extra.push((shape, offset));
        self
    }
    /// How the body's closed meshes collide (decomposed by default when it moves, exact when static); an error for
    /// a body without a mesh.
    pub fn mesh_shape(mut self, choice: MeshShape) -> Self {
        self.mesh_shape = Some(choice);
        self
    }
    /// Initial position: of the modelled frame's origin for a body of a mesh or of several colliders (the mesh sits
    /// where it was modelled, its centre of mass an offset inside), of the centre of mass for every other body.
    pub fn position(mut self, p: Vector3<f64>) -> Self {
        self.position = p;
        self.posed = true;
        self
    }
    /// The modelled frame's origin in the body frame, as saved (a loaded world keeps it; bodies built otherwise
    /// have it from their shapes).
    pub(crate) fn origin_offset(mut self, o: Vector3<f64>) -> Self {
        self.origin = Some(o);
        self
    }
    /// Initial orientation.
    pub fn orientation(mut self, q: UnitQuaternion<f64>) -> Self {
        self.orientation = q;
        self.posed = true;
        self
    }
    /// Initial velocity of the centre of mass.
    pub fn velocity(mut self, v: Vector3<f64>) -> Self {
        self.velocity = v;
        self
    }
    /// Initial angular velocity (world axes).
    pub fn angular_velocity(mut self, w: Vector3<f64>) -> Self {
        self.angular_velocity = w;
        self
    }
    /// Linear damping c (force -c v).
    pub fn linear_damping(mut self, c: f64) -> Self {
        self.linear_damping = c;
        self
    }
    /// Angular damping c (torque -c w).
    pub fn angular_damping(mut self, c: f64) -> Self {
        self.angular_damping = c;
        self
    }
    /// Coefficient of restitution in [0, 1] (used by contact).
    pub fn restitution(mut self, e: f64) -> Self {
        self.material.restitution = e;
        self
    }
    /// Coefficient of friction >= 0 (used by contact).
    pub fn friction(mut self, mu: f64) -> Self {
        self.material.friction = mu;
        self
    }
    /// Coefficient of rolling resistance >= 0 (`Material::rolling_resistance`).
    pub fn rolling_resistance(mut self, c: f64) -> Self {
        self.material.rolling_resistance = c;
        self
    }
    /// Coefficient of torsional resistance >= 0 (`Material::torsional_resistance`).
    pub fn torsional_resistance(mut self, c: f64) -> Self {
        self.material.torsional_resistance = c;
        self
    }
    /// Its whole surface material (restitution, friction, resistance and its own combine rules).
    pub fn material(mut self, m: Material) -> Self {
        self.material = m;
        self
    }

    /// Its name (1 to 256 characters): the glTF node's, the USD prim's (made a valid, unique identifier there) and
    /// the viewer's label.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.look.name = Some(name.into());
        self
    }

    /// Its collision groups, a bit each (all 32 by default): two bodies touch only if their groups share a bit,
    /// in both modes (as Blender's collision collections and Bullet's groups; 0 touches nothing). Particles are in
    /// every group.
    pub fn collision_groups(mut self, groups: u32) -> Self {
        self.groups = groups;
        self
    }

    /// Its colour, linear RGBA with each component in [0, 1] (alpha 1: opaque): the glTF material's base colour,
    /// the USD meshes' display colour, the viewer's.
    pub fn color(mut self, rgba: [f64; 4]) -> Self {
        self.look.color = Some(rgba);
        self
    }

    /// Resolves the mass properties and checks every field.
    pub(crate) fn build(mut self) -> Result<RigidBody, WorldError> {
        limits::vector("position", &self.position, limits::COORDINATE, "m")?;
        check_finite("orientation", self.orientation.coords.iter())?;
        limits::vector("velocity", &self.velocity, limits::SPEED, "m/s")?;
        limits::vector("angular_velocity", &self.angular_velocity, limits::SPEED, "rad/s")?;
        let immovable = self.is_static || self.keyframes.is_some();
        if immovable {
            still("velocity", &self.velocity)?;
            still("angular_velocity", &self.angular_velocity)?;
        }
        if self.keyframes.is_some() {
            self.kinematic_applies()?;
        }
        limits::non_negative("linear_damping", self.linear_damping, limits::STIFFNESS, "N s/m")?;
        limits::non_negative("angular_damping", self.angular_damping, limits::STIFFNESS, "N m s")?;
        let material = self.material;
        material.check()?;
        self.look.check()?;
        for (_, pose) in &self.extra {
            check_finite("offset", pose.rotation.coords.iter())?;
            limits::vector("offset", &pose.translation.vector, limits::COORDINATE, "m")?;
        }
        // a body of a mesh or of several colliders is placed by its modelled frame
        let by_origin = !immovable
            && self.inertia.is_none()
            && (matches!(self.shape, Some(Shape::Mesh(_))) || !self.extra.is_empty());
        self.resolve_meshes()?;
        let (mass, inertia, offset) =
            if immovable { (f64::INFINITY, Matrix3::identity(), Vector3::zeros()) } else { self.mass_properties()? };
        let shift = Isometry3::translation(offset.x, offset.y, offset.z);
        let mut colliders: Vec<Collider> =
            self.shape.iter().map(|s| Collider { shape: s.clone(), offset: shift }).collect();
        colliders.extend(self.extra.iter().map(|(s, pose)| Collider { shape: s.clone(), offset: shift * pose }));
        if !self.is_static {
            if let Some(c) = colliders.iter().find(|c| c.shape.is_static_only()) {
                return Err(WorldError::invalid(
                    "shape",
                    format!("a {} has no volume: it can only belong to a static body", c.shape.kind()),
                ));
            }
        }
        let inv_inertia = if immovable {
            Matrix3::zeros()
        } else {
            let source = if self.density.is_some() { "density" } else { "mass" };
            limits::mass(source, mass)?;
            limits::inertia(if self.inertia.is_some() { "inertia" } else { source }, &inertia)?;
            check_inertia(&inertia)?
        };
        let (momentum, angular_momentum) = if immovable {
            (Vector3::zeros(), Vector3::zeros())
        } else {
            let r = self.orientation.to_rotation_matrix();
            (mass * self.velocity, rotated_tensor(r.matrix(), &inertia) * self.angular_velocity)
        };
        let position = if by_origin { self.position - self.orientation * offset } else { self.position };
        limits::vector("position", &position, limits::COORDINATE, "m")?;
        Ok(RigidBody {
            mass,
            inertia,
            inv_inertia,
            colliders,
            origin: self.origin.unwrap_or(offset),
            position,
            orientation: self.orientation,
            momentum,
            angular_momentum,
            linear_damping: self.linear_damping,
            angular_damping: self.angular_damping,
            material,
            is_static: self.is_static,
            look: self.look,
            groups: self.groups,
            kinematic: self.keyframes.map(|k| Kinematic {
                path: Arc::new(k),
                velocity: Vector3::zeros(),
                angular_velocity: Vector3::zeros(),
            }),
        })
    }

    /// A kinematic body's settings: what follows from its keyframes may not be given as well.
    fn kinematic_applies(&self) -> Result<(), WorldError> {
        let why = "does not apply to a kinematic body, which follows its keyframes";
        if self.posed {
            let name = if self.position != Vector3::zeros() { "position" } else { "orientation" };
            return Err(WorldError::invalid(name, why));
        }
        for (name, given) in [
            ("mass", self.mass.is_some()),
            ("inertia", self.inertia.is_some()),
            ("density", self.density.is_some()),
            ("linear_damping", self.linear_damping != 0.0),
            ("angular_damping", self.angular_damping != 0.0),
        ] {
            if given {
                return Err(WorldError::invalid(name, why));
            }
        }
        Ok(())
    }

    /// Gives each closed mesh the collision geometry chosen (`MeshShape::resolve`); a choice with no mesh to apply
    /// to is an error.
    fn resolve_meshes(&mut self) -> Result<(), WorldError> {
        let choice = self.mesh_shape.as_ref();
        let has_mesh = self.shape.iter().chain(self.extra.iter().map(|(s, _)| s)).any(|s| matches!(s, Shape::Mesh(_)));
        if let (Some(c), false) = (choice, has_mesh) {
            return Err(WorldError::invalid(
                "shape",
                format!("\"{}\" applies to a mesh, and the body has none", c.name()),
            ));
        }
        let one = |s: &Shape| MeshShape::resolve(s, choice, self.is_static);
        let shape = self.shape.as_ref().map(one).transpose()?;
        let extra = self.extra.iter().map(|(s, pose)| Ok((one(s)?, *pose))).collect::<Result<Vec<_>, WorldError>>()?;
        self.shape = shape;
        self.extra = extra;
        Ok(())
    }

    /// (mass, inertia about the centre of mass, shape origin in the body frame).
    fn mass_properties(&self) -> Result<(f64, Matrix3<f64>, Vector3<f64>), WorldError> {
        match (&self.shape, self.mass, self.inertia, self.density) {
            (_, Some(m), Some(i), None) => Ok((check_scalar("mass", m, true)?, i, Vector3::zeros())),
            (Some(shape), m, None, d) => {
                if shape.is_static_only() {
                    return Err(WorldError::invalid(
                        "shape",
                        format!("a {} has no volume: it can only belong to a static body", shape.kind()),
                    ));
                }
                let mut parts = vec![(shape.clone(), Isometry3::identity())];
                parts.extend(self.extra.iter().filter(|(s, _)| !s.is_static_only()).cloned());
                let props = match (m, d) {
                    (None, Some(d)) => compound_mass(&parts, check_scalar("density", d, true)?)?,
                    (Some(m), None) => {
                        let unit = compound_mass(&parts, 1.0)?;
                        let scale = check_scalar("mass", m, true)? / unit.mass;
                        tumble_collide::MassProperties {
                            mass: m,
                            local_com: unit.local_com,
                            inertia: unit.inertia * scale,
                        }
                    }
                    _ => return Err(WorldError::invalid("density", "give either density or mass, not both")),
                };
                Ok((props.mass, props.inertia, -props.local_com))
            }
            (_, _, Some(_), _) => Err(WorldError::invalid("inertia", "an inertia tensor needs a mass and no density")),
            (None, _, None, _) => {
                Err(WorldError::invalid("shape", "a dynamic body needs a shape or a mass and inertia"))
            }
        }
    }
}

/// The inverse of an inertia tensor that is finite, symmetric and positive definite.
pub(crate) fn check_inertia(i: &Matrix3<f64>) -> Result<Matrix3<f64>, WorldError> {
    check_finite("inertia", i.iter())?;
    let scale = i.amax();
    if (i - i.transpose()).amax() > 1e-12 * scale {
        return Err(WorldError::invalid("inertia", format!("must be symmetric, got {i}")));
    }
    let sym = 0.5 * (i + i.transpose());
    let eig = sym.symmetric_eigenvalues();
    if !(eig.min() > 1e-12 * scale) {
        return Err(WorldError::invalid(
            "inertia",
            format!("must be positive definite; its eigenvalues are {:?}", eig.as_slice()),
        ));
    }
    match sym.try_inverse() {
        Some(inv) if inv.iter().all(|v| v.is_finite()) => Ok(inv),
        _ => Err(WorldError::invalid("inertia", "is singular")),
    }
}

/// A static body does not move: a velocity given to one is an error naming it (an option that does not apply).
pub(crate) fn still(name: &'static str, v: &Vector3<f64>) -> Result<(), WorldError> {
    if *v == Vector3::zeros() {
        Ok(())
    } else {
        Err(WorldError::invalid(
            name,
            format!("a static body does not move, so it takes no {name} (got {v:?}); make it dynamic to move it"),
        ))
    }
}
