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
use tumble::{
    mode_from, Attachment, BodyOptions, IntegratorOptions, Material, ParticleBuilder, ReportValue, RunArrays,
    SpringBuilder, Target, World, WorldError, WorldOptions, WorldReport, Wrench,
};

/// A body's colliders: each shape with its pose in the body frame (position, quaternion w, x, y, z).
type BodyShapes = Vec<(Py<PyShape>, [f64; 3], [f64; 4])>;

/// A world of particles and rigid bodies (see the package documentation for the whole contract).
#[pyclass(module = "tumble._tumble", name = "World", subclass)]
pub struct PyWorld {
    /// Behind a mutex only so that the class is `Sync`; `&mut self` methods reach it without locking.
    inner: Mutex<World>,
    /// The first exception raised by a Python callback during the current call.
    callback_error: Arc<Mutex<Option<PyErr>>>,
}

/// The integrator options from keyword arguments (the rules and defaults live in `tumble::IntegratorOptions`).
#[allow(clippy::too_many_arguments)]
fn integrator_options(
    integrator: Option<String>,
    rtol: Option<f64>,
    atol: Option<f64>,
    dt: Option<f64>,
    step_doubling: bool,
    tolerance: Option<f64>,
    linear_solver: Option<String>,
    newton: bool,
    max_steps: Option<usize>,
) -> IntegratorOptions {
    IntegratorOptions { integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps }
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

/// The report as a plain dict of its fields (the package wraps it in `tumble.Report`), with the stages that ran
/// under "stages_ran" and the report's text under "_text".
pub fn report_dict<'py>(py: Python<'py>, r: &WorldReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, value) in r.fields() {
        match value {
            ReportValue::Count(n) => d.set_item(name, n)?,
            ReportValue::Number(x) => d.set_item(name, x)?,
            ReportValue::Optional(x) => d.set_item(name, x)?,
            ReportValue::Text(t) => d.set_item(name, t)?,
        }
    }
    d.set_item("stages_ran", r.stages.ran())?;
    d.set_item("_text", r.to_string())?;
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
        d.set_item("energy", array(py, a.energy, &[f])?)?;
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
    #[pyo3(signature = (gravity = None, integrator = None, rtol = None, atol = None, dt = None,
                        step_doubling = false, tolerance = None, mode = "accurate", linear_solver = None,
                        newton = false, max_steps = None, sleep = None, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        gravity: Option<&Bound<'_, PyAny>>,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        dt: Option<f64>,
        step_doubling: bool,
        tolerance: Option<f64>,
        mode: &str,
        linear_solver: Option<String>,
        newton: bool,
        max_steps: Option<usize>,
        sleep: Option<bool>,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        let options = WorldOptions {
            gravity: opt_vec3("gravity", gravity)?,
            mode: Some(mode.to_string()),
            sleep,
            threads,
            integrator: integrator_options(
                integrator,
                rtol,
                atol,
                dt,
                step_doubling,
                tolerance,
                linear_solver,
                newton,
                max_steps,
            ),
        };
        let inner = options.build().map_err(world_error)?;
        Ok(PyWorld { inner: Mutex::new(inner), callback_error: Arc::new(Mutex::new(None)) })
    }

    /// A built-in scene built by the Rust library (`tumble::scenes::build`), with its numeric parameters by
    /// keyword.
    #[classmethod]
    #[pyo3(signature = (name, **params))]
    fn _rust_scene<'py>(
        cls: &Bound<'py, pyo3::types::PyType>,
        name: &str,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut given: Vec<(String, f64)> = Vec::new();
        if let Some(p) = params {
            for (k, v) in p.iter() {
                let key: String = k.extract()?;
                let value: f64 = v.extract().map_err(|_| invalid(&key, "must be a number"))?;
                given.push((key, value));
            }
        }
        let world = tumble::scenes::build(name, &given).map_err(world_error)?;
        let obj = cls.call0()?;
        {
            let mut w: PyRefMut<'_, PyWorld> = obj.extract()?;
            *w.w() = world;
        }
        Ok(obj)
    }

    /// The built-in scenes' names.
    #[staticmethod]
    fn _scene_names() -> Vec<&'static str> {
        tumble::scenes::NAMES.to_vec()
    }

    /// Chooses the integrator, with the constructor's keyword arguments (accurate mode only).
    #[pyo3(signature = (integrator = None, rtol = None, atol = None, dt = None, step_doubling = false,
                        tolerance = None, linear_solver = None, newton = false, max_steps = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_integrator(
        &mut self,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        dt: Option<f64>,
        step_doubling: bool,
        tolerance: Option<f64>,
        linear_solver: Option<String>,
        newton: bool,
        max_steps: Option<usize>,
    ) -> PyResult<()> {
        let options =
            integrator_options(integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps);
        let s = options.settings().map_err(world_error)?;
        self.w().set_integrator(s).map_err(world_error)
    }

    /// Chooses how contact is handled: mode="accurate" (event-driven, the integrator's error control) or "fast"
    /// (time stepping at dt, default 1/240 s; with sleep=False islands at rest keep being simulated). `dt` and
    /// `sleep` apply to fast mode only.
    #[pyo3(signature = (mode, dt = None, sleep = None))]
    fn set_mode(&mut self, mode: &str, dt: Option<f64>, sleep: Option<bool>) -> PyResult<()> {
        let m = mode_from(mode, dt, sleep).map_err(world_error)?;
        self.w().set_mode(m).map_err(world_error)
    }

    /// Threads of the contact solves: 0 is one per core (the default), 1 the calling thread only. Results are the
    /// same bit for bit whatever the count.
    #[getter]
    fn threads(&self) -> usize {
        self.r().threads()
    }

    #[setter]
    fn set_threads(&mut self, threads: usize) -> PyResult<()> {
        self.w().set_threads(threads).map_err(world_error)
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
        let mut b = BodyOptions { shape, density, mass, inertia, is_static: r#static }.builder().map_err(world_error)?;
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
