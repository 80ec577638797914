//! `World.add_body` for Python: a rigid body's keyword arguments (shape or mass and inertia, pose, velocities,
//! material, extra colliders, mesh handling, name, colour, groups, keyframes) forwarded to `RigidBodyBuilder`; the
//! checks and defaults are the library's.

use crate::convert::{invalid, mat3, opt_vec3, quat, repr, vec3, world_error};
use crate::handles::PyBodyHandle;
use crate::shapes::PyShape;
use crate::world::PyWorld;
use nalgebra::UnitQuaternion;
use pyo3::prelude::*;
use tumble::BodyOptions;

#[pymethods]
impl PyWorld {
    /// Adds a rigid body: from a shape and a density (or a total mass), or from a mass and a 3x3 inertia tensor.
    /// A `Mesh` moves as its convex decomposition (`decomposition={"resolution", "max_pieces", "concavity"}`), or
    /// as its hull with `shape="hull"`; a static one keeps its exact triangles (`shape="exact"`). `name` (1 to 256
    /// characters) and `color` (RGB or RGBA, linear, each in [0, 1]) travel with the body into files, copies and
    /// runs, and name and colour it in glTF, USD and the viewer. `collision_groups` (an int of 32 bits, all by
    /// default): two bodies touch only if their groups share a bit. `keyframes=(times, positions[, orientations])`
    /// ((K,), (K, 3), (K, 4) as w, x, y, z) makes it kinematic: it follows them (linearly, turning at a constant
    /// rate between keyframes), pushes what it touches and is never pushed back; it has no mass, pose or velocity
    /// of its own.
    #[pyo3(signature = (geometry = None, /, density = None, mass = None, inertia = None, position = None,
                        orientation = None, velocity = None, angular_velocity = None, restitution = None,
                        friction = None, r#static = false, linear_damping = 0.0, angular_damping = 0.0,
                        colliders = None, shape = None, decomposition = None, name = None, color = None,
                        collision_groups = None, keyframes = None, rolling_resistance = None,
                        torsional_resistance = None, friction_combine = None, restitution_combine = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        py: Python<'_>,
        geometry: Option<&Bound<'_, PyAny>>,
        density: Option<f64>,
        mass: Option<f64>,
        inertia: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        restitution: Option<f64>,
        friction: Option<f64>,
        r#static: bool,
        linear_damping: f64,
        angular_damping: f64,
        colliders: Option<&Bound<'_, PyAny>>,
        shape: Option<&Bound<'_, PyAny>>,
        decomposition: Option<&Bound<'_, PyAny>>,
        name: Option<String>,
        color: Option<&Bound<'_, PyAny>>,
        collision_groups: Option<u32>,
        keyframes: Option<&Bound<'_, PyAny>>,
        rolling_resistance: Option<f64>,
        torsional_resistance: Option<f64>,
        friction_combine: Option<String>,
        restitution_combine: Option<String>,
    ) -> PyResult<PyBodyHandle> {
        let surface = crate::material::MaterialArgs {
            friction,
            restitution,
            rolling_resistance,
            torsional_resistance,
            friction_combine,
            restitution_combine,
        }
        .material()?;
        let (geometry, mesh_shape) = crate::mesh::shape_args(geometry, shape, decomposition)?;
        let shape = geometry;
        let mut extra = Vec::new();
        if let Some(list) = colliders.filter(|c| !c.is_none()) {
            let entries = list.try_iter().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "invalid argument `colliders`: expected a list of (shape, position[, orientation]), got {}",
                    repr(list)
                ))
            })?;
            for (k, item) in entries.enumerate() {
                let item = item?;
                let (s, p, q): (PyRef<'_, PyShape>, Bound<'_, PyAny>, Option<Bound<'_, PyAny>>) = item
                    .extract()
                    .or_else(|_| item.extract::<(PyRef<'_, PyShape>, Bound<'_, PyAny>)>().map(|(s, p)| (s, p, None)))
                    .map_err(|_| invalid("colliders", format!("entry {k} must be (shape, position[, orientation])")))?;
                let position = vec3("colliders", &p)?;
                if !position.iter().all(|v| v.is_finite()) {
                    return Err(invalid(
                        "colliders",
                        format!("entry {k}: the position must be finite, got {position:?}"),
                    ));
                }
                let rotation = match q {
                    Some(q) => quat("colliders", &q)?,
                    None => UnitQuaternion::identity(),
                };
                extra.push((s.shape.clone(), nalgebra::Isometry3::from_parts(position.into(), rotation)));
            }
        }
        let inertia = inertia.filter(|i| !i.is_none()).map(|i| mat3("inertia", i)).transpose()?;
        let keyframes = keyframes.filter(|k| !k.is_none()).map(crate::convert::keyframes).transpose()?;
        let mut b = BodyOptions { shape, density, mass, inertia, is_static: r#static, keyframes }
            .builder()
            .map_err(world_error)?;
        if let Some(p) = opt_vec3("position", position)? {
            b = b.position(p);
        }
        if let Some(q) = orientation.filter(|o| !o.is_none()) {
            b = b.orientation(quat("orientation", q)?);
        }
        if let Some(v) = opt_vec3("velocity", velocity)? {
            b = b.velocity(v);
        }
        if let Some(w) = opt_vec3("angular_velocity", angular_velocity)? {
            b = b.angular_velocity(w);
        }
        for (s, pose) in extra {
            b = b.collider(s, pose);
        }
        b = b.material(surface);
        if let Some(choice) = mesh_shape {
            b = b.mesh_shape(choice);
        }
        b = b.linear_damping(linear_damping).angular_damping(angular_damping);
        if let Some(name) = name {
            b = b.name(name);
        }
        if let Some(rgba) = crate::convert::opt_color("color", color)? {
            b = b.color(rgba);
        }
        if let Some(groups) = collision_groups {
            b = b.collision_groups(groups);
        }
        let mut guard = self.r();
        let world: &mut tumble::World = &mut guard;
        // a mesh's decomposition can take seconds: other Python threads run meanwhile
        py.detach(|| world.add_body(b)).map(Into::into).map_err(world_error)
    }

    /// Lets kinematic body `body` go: from now on a dynamic body of its shapes at `density` (kg/m^3; 1000 if None),
    /// where its keyframes have it, moving and turning as they had it coming there (Blender's "Animated" switched off). Its
    /// handle and row are kept, so the runs before and after join (`Run.join`). ValueError naming the argument for a
    /// body that is not kinematic or has no shape, or a bad density.
    #[pyo3(signature = (body, density = None))]
    fn release(&mut self, body: PyBodyHandle, density: Option<f64>) -> PyResult<()> {
        self.w().release(body.into(), density).map_err(world_error)
    }

    /// Takes dynamic body `body` over: from now on it follows `keyframes=(times, positions[, orientations])` (poses
    /// of its body frame, its origin the centre of mass), or stays where it is (None), pushing what it touches and
    /// never pushed back. ValueError naming the argument for a static or kinematic body.
    #[pyo3(signature = (body, keyframes = None))]
    fn hold(&mut self, body: PyBodyHandle, keyframes: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let keyframes = keyframes.filter(|k| !k.is_none()).map(crate::convert::keyframes).transpose()?;
        self.w().hold(body.into(), keyframes).map_err(world_error)
    }
}
