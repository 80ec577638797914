//! `World` for Python: the keyword arguments of the public contract mapped onto the Rust world, state as numpy
//! arrays, runs with the interpreter lock released and a progress callback between chunks.

use crate::convert::{array, invalid, mat3, opt_vec3, quat, vec3, world_error};
use crate::handles::{PyBodyHandle, PyLoadHandle, PyParticleHandle, PySpringHandle};
use crate::shapes::PyShape;
use crate::SimulationError;
use nalgebra::{UnitQuaternion, Vector3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::sync::{Arc, Mutex};
use tumble::integrate::{LinearSolver, NewtonMode};
use tumble::{
    Attachment, FastSettings, Material, Method, Mode, ParticleBuilder, RigidBodyBuilder, RunArrays, Settings,
    SpringBuilder, Target, World, WorldError, WorldReport, Wrench,
};

/// A body's colliders: each shape with its pose in the body frame (position, quaternion w, x, y, z).
type BodyShapes = Vec<(Py<PyShape>, [f64; 3], [f64; 4])>;

/// The contact mode from the constructor's or `set_mode`'s arguments (`sleep` applies to fast mode).
fn mode_of(name: &str, dt: Option<f64>, sleep: bool) -> PyResult<Mode> {
    match name {
        "accurate" => Ok(Mode::default()),
        "fast" => Ok(Mode::Fast(FastSettings { sleep, ..FastSettings::new(dt.unwrap_or(1.0 / 240.0)) })),
        other => Err(invalid("mode", format!("expected \"accurate\" or \"fast\", got {other:?}"))),
    }
}

/// A world of particles and rigid bodies (see the package documentation for the whole contract).
#[pyclass(module = "tumble._tumble", name = "World", subclass)]
pub struct PyWorld {
    /// Behind a mutex only so that the class is `Sync`; `&mut self` methods reach it without locking.
    inner: Mutex<World>,
    /// The first exception raised by a Python callback during the current call.
    callback_error: Arc<Mutex<Option<PyErr>>>,
}

/// The integrator settings from the constructor's keyword arguments.
#[allow(clippy::too_many_arguments)]
fn settings(
    integrator: &str,
    rtol: Option<f64>,
    atol: Option<f64>,
    dt: Option<f64>,
    step_doubling: bool,
    tolerance: Option<f64>,
    linear_solver: &str,
    newton: bool,
    max_steps: Option<usize>,
) -> PyResult<Settings> {
    let method: Method =
        integrator.parse().map_err(|e: tumble::integrate::OdeError| PyValueError::new_err(e.to_string()))?;
    let mut s = if step_doubling {
        if !method.is_one_step() {
            return Err(invalid("step_doubling", format!("needs a one-step method, not {method}")));
        }
        Settings::step_doubling(method, tolerance.unwrap_or(1e-6), dt.unwrap_or(1e-3))
    } else if method == Method::EulerVariable {
        Settings::euler_variable(tolerance.unwrap_or(1e-6))
    } else if method.has_error_estimate() && (dt.is_none() || rtol.is_some() || atol.is_some()) {
        let s = Settings::tolerances(method, rtol.unwrap_or(1e-6), atol.unwrap_or(1e-9));
        match dt {
            Some(h) => s.initial_step(h),
            None => s,
        }
    } else {
        if rtol.is_some() || atol.is_some() {
            return Err(invalid("rtol", format!("{method} is a fixed-step method: give dt, or step_doubling=True")));
        }
        Settings::fixed(method, dt.unwrap_or(1.0 / 240.0))
    };
    s = s.linear_solver(match linear_solver {
        "direct" => LinearSolver::Direct,
        "iterative" => LinearSolver::Iterative { rtol: 1e-6, max_iter: 2000 },
        other => return Err(invalid("linear_solver", format!("expected \"direct\" or \"iterative\", got {other:?}"))),
    });
    if newton {
        s = s.newton(NewtonMode::Newton { tol: 1e-9, max_iter: 10 });
    }
    if let Some(n) = max_steps {
        s = s.max_steps(n);
    }
    Ok(s)
}

fn to_target(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Target> {
    if let Ok(p) = obj.extract::<PyParticleHandle>() {
        return Ok(Target::Particle(p.into()));
    }
    if let Ok(b) = obj.extract::<PyBodyHandle>() {
        return Ok(Target::Body(b.into()));
    }
    Err(invalid(name, "expected a ParticleHandle or a BodyHandle"))
}

fn attachment(
    obj: Option<&Bound<'_, PyAny>>,
    anchor: Option<Vector3<f64>>,
    point: Option<Vector3<f64>>,
    name: &str,
) -> PyResult<Attachment> {
    match obj.filter(|o| !o.is_none()) {
        Some(o) => match to_target(o, name)? {
            Target::Particle(p) => {
                if anchor.is_some_and(|a| a != Vector3::zeros()) {
                    return Err(invalid(&format!("anchor_{name}"), "a particle has no body frame"));
                }
                Ok(Attachment::Particle(p))
            }
            Target::Body(b) => Ok(Attachment::Body(b, anchor.unwrap_or_else(Vector3::zeros))),
        },
        None => point
            .map(Attachment::Point)
            .ok_or_else(|| invalid("world_point", format!("`{name}` is None, so the spring needs a world_point"))),
    }
}

/// A (count, W) array from rows.
fn rows<'py, const W: usize>(
    py: Python<'py>,
    count: usize,
    items: impl Iterator<Item = [f64; W]>,
) -> PyResult<Bound<'py, PyAny>> {
    array(py, items.flatten().collect(), &[count, W])
}

/// The report as a plain dict (the package wraps it in `tumble.Report`).
pub fn report_dict<'py>(py: Python<'py>, r: &WorldReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let i = &r.integrator;
    d.set_item("method", i.method)?;
    d.set_item("steps", i.steps)?;
    d.set_item("rejected", i.rejected)?;
    d.set_item("rhs_evals", i.rhs_evals)?;
    d.set_item("jacobians", i.jacobians)?;
    d.set_item("factorizations", i.factorizations)?;
    d.set_item("linear_solves", i.linear_solves)?;
    d.set_item("newton_iterations", i.newton_iterations)?;
    d.set_item("krylov_iterations", i.krylov_iterations)?;
    d.set_item("min_step", if i.steps > 0 { Some(i.min_step) } else { None })?;
    d.set_item("max_step", if i.steps > 0 { Some(i.max_step) } else { None })?;
    d.set_item("wall_seconds", i.wall_seconds)?;
    d.set_item("error_estimate", i.error_estimate)?;
    d.set_item("qp_solves", r.qp_solves)?;
    d.set_item("collisions", r.collisions)?;
    d.set_item("impulses", r.impulses)?;
    d.set_item("bisection_steps", r.bisection_steps)?;
    d.set_item("collision_checks", r.collision_checks)?;
    d.set_item("islands", r.islands)?;
    d.set_item("sleepers", r.sleepers)?;
    d.set_item("max_penetration", r.max_penetration)?;
    d.set_item("collision_seconds", r.collision_seconds)?;
    d.set_item("contact_seconds", r.contact_seconds)?;
    let f = &r.forces;
    d.set_item("evaluations", f.evaluations)?;
    d.set_item("spring_evaluations", f.spring_evaluations)?;
    d.set_item("load_evaluations", f.load_evaluations)?;
    d.set_item("callback_calls", f.callback_calls)?;
    d.set_item("projections", f.projections)?;
    Ok(d)
}

impl PyWorld {
    fn w(&mut self) -> &mut World {
        self.inner.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    fn r(&self) -> std::sync::MutexGuard<'_, World> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Maps a world error, chaining the Python exception a callback raised, if any.
    fn error(&self, py: Python<'_>, e: WorldError) -> PyErr {
        let err = world_error(e);
        if let Some(cause) = self.callback_error.lock().ok().and_then(|mut c| c.take()) {
            if err.is_instance_of::<SimulationError>(py) {
                err.set_cause(py, Some(cause));
            }
        }
        err
    }

    fn run_arrays<'py>(
        &self,
        py: Python<'py>,
        a: RunArrays,
        report: &WorldReport,
        handles: (Vec<PyParticleHandle>, Vec<PyBodyHandle>),
    ) -> PyResult<Bound<'py, PyDict>> {
        let (f, p, b) = (a.times.len(), a.particle_count, a.body_count);
        let energy: Vec<f64> = a.kinetic_energy.iter().zip(&a.potential_energy).map(|(k, u)| k + u).collect();
        let steps = a.step_times.len();
        let d = PyDict::new(py);
        d.set_item("times", array(py, a.times, &[f])?)?;
        d.set_item("particle_positions", array(py, a.particle_positions, &[f, p, 3])?)?;
        d.set_item("particle_velocities", array(py, a.particle_velocities, &[f, p, 3])?)?;
        d.set_item("body_positions", array(py, a.body_positions, &[f, b, 3])?)?;
        d.set_item("body_orientations", array(py, a.body_orientations, &[f, b, 4])?)?;
        d.set_item("body_velocities", array(py, a.body_velocities, &[f, b, 3])?)?;
        d.set_item("body_angular_velocities", array(py, a.body_angular_velocities, &[f, b, 3])?)?;
        d.set_item("kinetic_energy", array(py, a.kinetic_energy, &[f])?)?;
        d.set_item("potential_energy", array(py, a.potential_energy, &[f])?)?;
        d.set_item("energy", array(py, energy, &[f])?)?;
        d.set_item("momentum", array(py, a.momentum, &[f, 3])?)?;
        d.set_item("angular_momentum", array(py, a.angular_momentum, &[f, 3])?)?;
        d.set_item("step_times", array(py, a.step_times, &[steps])?)?;
        d.set_item("step_sizes", array(py, a.step_sizes, &[steps])?)?;
        let events = a.contact_events.len();
        d.set_item("penetration", array(py, a.penetration, &[f])?)?;
        d.set_item("contact_events", array(py, a.contact_events, &[events])?)?;
        d.set_item("report", report_dict(py, report)?)?;
        d.set_item("particles", PyList::new(py, handles.0)?)?;
        d.set_item("bodies", PyList::new(py, handles.1)?)?;
        Ok(d)
    }
}

#[pymethods]
impl PyWorld {
    #[new]
    #[pyo3(signature = (gravity = None, integrator = "dopri5", rtol = None, atol = None, dt = None,
                        step_doubling = false, tolerance = None, mode = "accurate", linear_solver = "direct",
                        newton = false, max_steps = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        gravity: Option<&Bound<'_, PyAny>>,
        integrator: &str,
        rtol: Option<f64>,
        atol: Option<f64>,
        dt: Option<f64>,
        step_doubling: bool,
        tolerance: Option<f64>,
        mode: &str,
        linear_solver: &str,
        newton: bool,
        max_steps: Option<usize>,
    ) -> PyResult<Self> {
        let contact = mode_of(mode, dt, true)?;
        let mut inner = World::new();
        if let Some(g) = opt_vec3("gravity", gravity)? {
            inner.set_gravity(g).map_err(world_error)?;
        }
        if matches!(contact, Mode::Accurate(_)) {
            let s = settings(integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps)?;
            inner.set_integrator(s).map_err(world_error)?;
        }
        inner.set_mode(contact).map_err(world_error)?;
        Ok(PyWorld { inner: Mutex::new(inner), callback_error: Arc::new(Mutex::new(None)) })
    }

    /// A built-in scene built by the Rust library (for comparing with the same scene built from Python):
    /// "cloth" (keyword arguments n, size, mass, stiffness, damping, pin_stiffness) or "spinning_top".
    #[classmethod]
    #[pyo3(signature = (name, **params))]
    fn _rust_scene<'py>(
        cls: &Bound<'py, pyo3::types::PyType>,
        name: &str,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let get = |key: &str, default: f64| -> PyResult<f64> {
            match params.map(|p| p.get_item(key)).transpose()?.flatten() {
                Some(v) => v.extract(),
                None => Ok(default),
            }
        };
        let world = match name {
            "cloth" => {
                let d = tumble::scenes::Cloth::default();
                let cloth = tumble::scenes::Cloth {
                    n: get("n", d.n as f64)? as usize,
                    size: get("size", d.size)?,
                    mass: get("mass", d.mass)?,
                    stiffness: get("stiffness", d.stiffness)?,
                    damping: get("damping", d.damping)?,
                    pin_stiffness: get("pin_stiffness", d.pin_stiffness)?,
                };
                cloth.build().map_err(world_error)?.0
            }
            "spinning_top" => tumble::scenes::spinning_top().map_err(world_error)?.0,
            "bouncing_ball" => {
                let d = tumble::scenes::BouncingBall::default();
                let ball = tumble::scenes::BouncingBall {
                    restitution: get("restitution", d.restitution)?,
                    radius: get("radius", d.radius)?,
                    height: get("height", d.height)?,
                };
                ball.build().map_err(world_error)?.0
            }
            "tumbling_box" => tumble::scenes::tumbling_box().map_err(world_error)?.0,
            "dominoes" => {
                let d = tumble::scenes::Dominoes::default();
                let row = tumble::scenes::Dominoes {
                    count: get("count", d.count as f64)? as usize,
                    spacing: get("spacing", d.spacing)?,
                };
                row.build().map_err(world_error)?.0
            }
            "pyramid" => {
                let layers = get("layers", tumble::scenes::Pyramid::default().layers as f64)? as usize;
                tumble::scenes::Pyramid { layers }.build().map_err(world_error)?.0
            }
            "cloth_drape" => {
                let d = tumble::scenes::ClothDrape::default();
                let drape =
                    tumble::scenes::ClothDrape { n: get("n", d.n as f64)? as usize, size: get("size", d.size)? };
                drape.build().map_err(world_error)?.0
            }
            other => {
                return Err(invalid(
                    "name",
                    format!(
                        "unknown scene {other:?}; expected one of \"cloth\", \"spinning_top\", \"bouncing_ball\", \
                         \"tumbling_box\", \"dominoes\", \"pyramid\", \"cloth_drape\""
                    ),
                ))
            }
        };
        let obj = cls.call0()?;
        {
            let mut w: PyRefMut<'_, PyWorld> = obj.extract()?;
            *w.w() = world;
        }
        Ok(obj)
    }

    /// Chooses the integrator, with the constructor's keyword arguments.
    #[pyo3(signature = (integrator = "dopri5", rtol = None, atol = None, dt = None, step_doubling = false,
                        tolerance = None, linear_solver = "direct", newton = false, max_steps = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_integrator(
        &mut self,
        integrator: &str,
        rtol: Option<f64>,
        atol: Option<f64>,
        dt: Option<f64>,
        step_doubling: bool,
        tolerance: Option<f64>,
        linear_solver: &str,
        newton: bool,
        max_steps: Option<usize>,
    ) -> PyResult<()> {
        let s = settings(integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps)?;
        self.r().set_integrator(s).map_err(world_error)
    }

    /// Chooses how contact is handled: mode="accurate" (event-driven, the integrator's error control) or "fast"
    /// (time stepping at dt, default 1/240 s; with sleep=False islands at rest keep being simulated).
    #[pyo3(signature = (mode, dt = None, sleep = true))]
    fn set_mode(&mut self, mode: &str, dt: Option<f64>, sleep: bool) -> PyResult<()> {
        let m = mode_of(mode, dt, sleep)?;
        self.r().set_mode(m).map_err(world_error)
    }

    /// The contact mode: "accurate" or "fast".
    #[getter]
    fn mode(&self) -> &'static str {
        self.r().mode().name()
    }

    /// Adds a ground: a static half-space below the plane z = height (normal +z). Returns its body handle.
    #[pyo3(signature = (height = 0.0, restitution = 0.5, friction = 0.5))]
    fn add_ground(&mut self, height: f64, restitution: f64, friction: f64) -> PyResult<PyBodyHandle> {
        self.r().add_ground(height, Material { restitution, friction }).map(Into::into).map_err(world_error)
    }

    /// Adds a particle obeying m x'' + d x' + h (x - anchor) = sum F.
    /// With `radius` > 0 it collides with bodies as a small sphere (particles do not collide with each other).
    #[pyo3(signature = (mass = 1.0, position = None, velocity = None, damping = 0.0, stiffness = 0.0, anchor = None,
                        radius = 0.0, restitution = 0.5, friction = 0.5))]
    #[allow(clippy::too_many_arguments)]
    fn add_particle(
        &mut self,
        mass: f64,
        position: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        damping: f64,
        stiffness: f64,
        anchor: Option<&Bound<'_, PyAny>>,
        radius: f64,
        restitution: f64,
        friction: f64,
    ) -> PyResult<PyParticleHandle> {
        let mut b = ParticleBuilder::new(mass)
            .damping(damping)
            .stiffness(stiffness)
            .radius(radius)
            .material(Material { restitution, friction });
        if let Some(p) = opt_vec3("position", position)? {
            b = b.position(p);
        }
        if let Some(v) = opt_vec3("velocity", velocity)? {
            b = b.velocity(v);
        }
        if let Some(a) = opt_vec3("anchor", anchor)? {
            b = b.anchor(a);
        }
        self.r().add_particle(b).map(Into::into).map_err(world_error)
    }

    /// Adds a rigid body: from a shape and a density (or a total mass), or from a mass and a 3x3 inertia tensor.
    #[pyo3(signature = (shape = None, density = None, mass = None, inertia = None, position = None,
                        orientation = None, velocity = None, angular_velocity = None, restitution = 0.5,
                        friction = 0.5, r#static = false, linear_damping = 0.0, angular_damping = 0.0,
                        colliders = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        shape: Option<PyRef<'_, PyShape>>,
        density: Option<f64>,
        mass: Option<f64>,
        inertia: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        restitution: f64,
        friction: f64,
        r#static: bool,
        linear_damping: f64,
        angular_damping: f64,
        colliders: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyBodyHandle> {
        let shape = shape.map(|s| s.shape.clone());
        let mut extra = Vec::new();
        if let Some(list) = colliders.filter(|c| !c.is_none()) {
            for (k, item) in list.try_iter()?.enumerate() {
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
        let mut b = if r#static {
            if density.is_some() || mass.is_some() || inertia.is_some() {
                return Err(invalid("static", "a static body has no density, mass or inertia"));
            }
            RigidBodyBuilder::fixed(shape)
        } else {
            match (shape, density, mass, inertia) {
                (shape, None, Some(m), Some(i)) => {
                    let b = RigidBodyBuilder::new(m, i);
                    match shape {
                        Some(s) => b.shape(s),
                        None => b,
                    }
                }
                (Some(s), Some(d), None, None) => RigidBodyBuilder::from_shape(s, d),
                (Some(s), None, Some(m), None) => RigidBodyBuilder::from_shape_with_mass(s, m),
                (Some(s), None, None, None) => RigidBodyBuilder::from_shape(s, 1000.0),
                (_, Some(_), Some(_), _) => return Err(invalid("density", "give either density or mass, not both")),
                (_, _, None, Some(_)) => return Err(invalid("inertia", "an inertia tensor needs a mass")),
                (None, _, _, None) => {
                    return Err(invalid("shape", "a dynamic body needs a shape, or a mass and an inertia"))
                }
            }
        };
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
        b = b
            .restitution(restitution)
            .friction(friction)
            .linear_damping(linear_damping)
            .angular_damping(angular_damping);
        self.r().add_body(b).map(Into::into).map_err(world_error)
    }

    /// Adds a damped spring between `a` and `b` (particles or bodies; `b=None` with `world_point` for a fixed
    /// point). Anchors are body-frame points relative to the centre of mass; `rest_length=None` takes the current
    /// distance.
    #[pyo3(signature = (a, b = None, stiffness = 1.0, damping = 0.0, rest_length = None, anchor_a = None,
                        anchor_b = None, world_point = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_spring(
        &mut self,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        stiffness: f64,
        damping: f64,
        rest_length: Option<f64>,
        anchor_a: Option<&Bound<'_, PyAny>>,
        anchor_b: Option<&Bound<'_, PyAny>>,
        world_point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PySpringHandle> {
        let point = opt_vec3("world_point", world_point)?;
        if point.is_some() && b.is_some_and(|b| !b.is_none()) {
            return Err(invalid("world_point", "give either b or world_point, not both"));
        }
        let end_a = attachment(Some(a), opt_vec3("anchor_a", anchor_a)?, None, "a")?;
        let end_b = attachment(b, opt_vec3("anchor_b", anchor_b)?, point, "b")?;
        let mut s = SpringBuilder::new(end_a, end_b).stiffness(stiffness).damping(damping);
        if let Some(l) = rest_length {
            s = s.rest_length(l);
        }
        self.r().add_spring(s).map(Into::into).map_err(world_error)
    }

    /// Adds a constant force (world axes) on a particle or body, at the centre of mass or at a body point `at`
    /// (body frame).
    #[pyo3(signature = (target, force, at = None))]
    fn add_force(
        &mut self,
        target: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        at: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyLoadHandle> {
        let t = to_target(target, "target")?;
        let f = vec3("force", force)?;
        let at = opt_vec3("at", at)?;
        self.w().add_force(t, f, at).map(Into::into).map_err(world_error)
    }

    /// Adds a constant torque (world axes) on a body.
    fn add_torque(&mut self, body: PyBodyHandle, torque: &Bound<'_, PyAny>) -> PyResult<PyLoadHandle> {
        let tau = vec3("torque", torque)?;
        self.w().add_torque(body.into(), tau).map(Into::into).map_err(world_error)
    }

    /// Adds a force callback, called as `callback(t, position, velocity)` at every evaluation of the equations of
    /// motion; it returns a force (3 numbers) or, for a body, `(force, torque)`. An exception stops the step
    /// (SimulationError, caused by it).
    fn add_force_callback(&mut self, target: &Bound<'_, PyAny>, callback: Py<PyAny>) -> PyResult<PyLoadHandle> {
        let t = to_target(target, "target")?;
        let slot = self.callback_error.clone();
        let f = move |time: f64, s: &tumble::TargetState| -> Result<Wrench, String> {
            Python::attach(|py| {
                let call = || -> PyResult<Wrench> {
                    let p = array(py, s.position.as_slice().to_vec(), &[3])?;
                    let v = array(py, s.velocity.as_slice().to_vec(), &[3])?;
                    let out = callback.call1(py, (time, p, v))?;
                    let out = out.bind(py);
                    if let Ok(force) = out.extract::<[f64; 3]>() {
                        return Ok(Wrench { force: force.into(), torque: Vector3::zeros() });
                    }
                    let (force, torque): ([f64; 3], [f64; 3]) = out.extract().map_err(|_| {
                        PyValueError::new_err("a force callback must return a force (3 numbers) or (force, torque)")
                    })?;
                    Ok(Wrench { force: force.into(), torque: torque.into() })
                };
                call().map_err(|e| {
                    let message = e.to_string();
                    if let Ok(mut s) = slot.lock() {
                        s.get_or_insert(e);
                    }
                    format!("force callback raised {message}")
                })
            })
        };
        self.w().add_force_callback(t, f).map(Into::into).map_err(world_error)
    }

    /// Removes a particle, body (with their springs and loads), spring or load.
    fn remove(&mut self, handle: &Bound<'_, PyAny>) -> PyResult<()> {
        let r = if let Ok(h) = handle.extract::<PyParticleHandle>() {
            self.w().remove_particle(h.into()).map(|_| ())
        } else if let Ok(h) = handle.extract::<PyBodyHandle>() {
            self.w().remove_body(h.into()).map(|_| ())
        } else if let Ok(h) = handle.extract::<PySpringHandle>() {
            self.w().remove_spring(h.into()).map(|_| ())
        } else if let Ok(h) = handle.extract::<PyLoadHandle>() {
            self.w().remove_load(h.into())
        } else {
            return Err(invalid("handle", "expected a particle, body, spring or load handle"));
        };
        r.map_err(world_error)
    }

    /// Sets a particle's position and/or velocity.
    #[pyo3(signature = (particle, position = None, velocity = None))]
    fn set_particle_state(
        &mut self,
        particle: PyParticleHandle,
        position: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let p = self.w().particle(particle.into()).map_err(world_error)?.clone();
        let x = opt_vec3("position", position)?.unwrap_or(p.position());
        let v = opt_vec3("velocity", velocity)?.unwrap_or(p.velocity());
        self.w().set_particle_state(particle.into(), x, v).map_err(world_error)
    }

    /// Sets a body's pose and/or velocities.
    #[pyo3(signature = (body, position = None, orientation = None, velocity = None, angular_velocity = None))]
    fn set_body_state(
        &mut self,
        body: PyBodyHandle,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let b = self.w().body(body.into()).map_err(world_error)?.clone();
        let x = opt_vec3("position", position)?.unwrap_or(b.position());
        let q = match orientation.filter(|o| !o.is_none()) {
            Some(o) => quat("orientation", o)?,
            None => b.orientation(),
        };
        let v = opt_vec3("velocity", velocity)?.unwrap_or(b.velocity());
        let w = opt_vec3("angular_velocity", angular_velocity)?.unwrap_or(b.angular_velocity());
        self.w().set_body_state(body.into(), x, q, v, w).map_err(world_error)
    }

    /// Advances by exactly `dt` (several internal steps if the integrator is adaptive). Raises SimulationError,
    /// leaving the world unchanged, if the step cannot be completed.
    fn step(&mut self, py: Python<'_>, dt: f64) -> PyResult<()> {
        let inner = self.w();
        let r = py.detach(|| inner.step(dt));
        r.map_err(|e| self.error(py, e))
    }

    /// Runs for `duration`, recording a frame every `frame_interval`; returns a dict of arrays (the package
    /// wraps it in `tumble.Run`). `progress(fraction)` is called between chunks; Ctrl-C stops the run and
    /// restores the world.
    #[pyo3(signature = (duration, frame_interval = 1.0 / 60.0, progress = None))]
    fn _run<'py>(
        &mut self,
        py: Python<'py>,
        duration: f64,
        frame_interval: f64,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let stopped: Arc<Mutex<Option<PyErr>>> = Arc::new(Mutex::new(None));
        let stop = stopped.clone();
        let inner = self.w();
        let result = py.detach(|| {
            inner.run_with(duration, frame_interval, |fraction| {
                Python::attach(|py| {
                    let r = py.check_signals().and_then(|_| match &progress {
                        Some(cb) => cb.call1(py, (fraction,)).map(|_| ()),
                        None => Ok(()),
                    });
                    match r {
                        Ok(()) => true,
                        Err(e) => {
                            *stop.lock().expect("not poisoned") = Some(e);
                            false
                        }
                    }
                })
            })
        });
        match result {
            Ok(run) => {
                let handles =
                    (run.particles.iter().map(|&h| h.into()).collect(), run.bodies.iter().map(|&h| h.into()).collect());
                let (arrays, report) = run.into_arrays();
                self.run_arrays(py, arrays, &report, handles)
            }
            Err(WorldError::Interrupted) => Err(stopped
                .lock()
                .expect("not poisoned")
                .take()
                .unwrap_or_else(|| world_error(WorldError::Interrupted))),
            Err(e) => Err(self.error(py, e)),
        }
    }

    /// Current time.
    #[getter]
    fn time(&self) -> f64 {
        self.r().time()
    }

    /// Gravity, as a (3,) array.
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().gravity().as_slice().to_vec(), &[3])
    }

    /// The particles' handles, in array order.
    fn particle_handles(&self) -> Vec<PyParticleHandle> {
        self.r().particles().map(|(h, _)| h.into()).collect()
    }

    /// The bodies' handles (static ones included), in array order.
    fn body_handles(&self) -> Vec<PyBodyHandle> {
        self.r().bodies().map(|(h, _)| h.into()).collect()
    }

    /// (P, 3) particle positions.
    fn _particle_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.particle_count(), w.particles().map(|(_, p)| p.position().into()))
    }

    /// (P, 3) particle velocities.
    fn _particle_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.particle_count(), w.particles().map(|(_, p)| p.velocity().into()))
    }

    /// (B, 3) body positions.
    fn _body_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.position().into()))
    }

    /// (B, 4) body orientations (w, x, y, z).
    fn _body_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(
            py,
            w.body_count(),
            w.bodies().map(|(_, b)| {
                let q: UnitQuaternion<f64> = b.orientation();
                [q.w, q.i, q.j, q.k]
            }),
        )
    }

    /// (B, 3) body velocities.
    fn _body_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.velocity().into()))
    }

    /// (B, 3) body angular velocities.
    fn _body_angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.angular_velocity().into()))
    }

    /// Each body's colliders (empty where a body has none) as (shape, position, orientation w x y z) in its body
    /// frame, in array order.
    fn _body_shapes(&self, py: Python<'_>) -> PyResult<Vec<BodyShapes>> {
        self.r()
            .bodies()
            .map(|(_, b)| {
                b.colliders()
                    .iter()
                    .map(|c| {
                        let shape = Py::new(py, PyShape { shape: c.shape.clone() })?;
                        let (t, q) = (c.offset.translation.vector, c.offset.rotation);
                        Ok((shape, [t.x, t.y, t.z], [q.w, q.i, q.j, q.k]))
                    })
                    .collect()
            })
            .collect()
    }

    /// Kinetic energy.
    fn kinetic_energy(&self) -> f64 {
        self.r().kinetic_energy()
    }

    /// Potential energy of gravity, springs and the particles' restoring terms.
    fn potential_energy(&self) -> f64 {
        self.r().potential_energy()
    }

    /// Total linear momentum, (3,).
    fn momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().momentum().as_slice().to_vec(), &[3])
    }

    /// Total angular momentum about the origin, (3,).
    fn angular_momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().angular_momentum().as_slice().to_vec(), &[3])
    }

    /// The stages the world runs: {"stages": [...], "state_len": int, "method": str, "jacobian": str | None}.
    fn plan<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.r().plan();
        let d = PyDict::new(py);
        d.set_item("stages", p.stages)?;
        d.set_item("state_len", p.state_len)?;
        d.set_item("method", p.method)?;
        d.set_item("mode", p.mode)?;
        d.set_item("jacobian", p.jacobian)?;
        Ok(d)
    }

    /// Everything the world's steps have cost so far, as a dict (the package wraps it in `tumble.Report`).
    fn _report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        report_dict(py, &self.r().report())
    }
}
