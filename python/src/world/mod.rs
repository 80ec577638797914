//! `World` for Python, building and stepping: the keyword arguments of the public contract mapped onto the Rust
//! world, runs with the interpreter lock released and a progress callback between chunks. Reading state is in
//! `state.rs`, adding bodies in `bodies.rs`, joints in `joints.rs`, the modes in `modes.rs`, the built-in scenes in
//! `scenes.rs`.

mod bodies;
mod joints;
mod modes;
mod scenes;
mod state;

use crate::args::{attachment, integrator_options, to_target};
use crate::control::Control;
use crate::convert::{array, invalid, number, opt_vec3, quat, vec3, world_error};
use crate::handles::{PyBodyHandle, PyLoadHandle, PyParticleHandle, PySpringHandle};
use crate::material::MaterialArgs;
use crate::report::run_arrays;
use crate::SimulationError;
use nalgebra::Vector3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Arc, Mutex};
use tumble::{ParticleBuilder, SpringBuilder, World, WorldError, WorldOptions, Wrench};

/// A world of particles and rigid bodies (see the package documentation for the whole contract).
#[pyclass(module = "tumble._tumble", name = "World", subclass)]
pub struct PyWorld {
    /// Behind a mutex only so that the class is `Sync`; `&mut self` methods reach it without locking.
    inner: Mutex<World>,
    /// The first exception raised by a Python callback during the current call.
    callback_error: Arc<Mutex<Option<PyErr>>>,
}

impl PyWorld {
    pub(crate) fn w(&mut self) -> &mut World {
        self.inner.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn r(&self) -> std::sync::MutexGuard<'_, World> {
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
}

#[pymethods]
impl PyWorld {
    #[new]
    #[pyo3(signature = (gravity = None, integrator = None, rtol = None, atol = None, dt = None,
                        step_doubling = false, tolerance = None, mode = "accurate", linear_solver = None,
                        newton = false, max_steps = None, sleep = None, threads = None,
                        contact_tolerance = None, solver = None, substeps = None, friction_combine = None,
                        restitution_combine = None))]
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
        contact_tolerance: Option<f64>,
        solver: Option<String>,
        substeps: Option<usize>,
        friction_combine: Option<String>,
        restitution_combine: Option<String>,
    ) -> PyResult<Self> {
        let options = WorldOptions {
            gravity: opt_vec3("gravity", gravity)?,
            mode: Some(mode.to_string()),
            sleep,
            threads,
            contact_tolerance,
            solver,
            substeps,
            friction_combine,
            restitution_combine,
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

    /// Threads of the contact solves: 0 is one per core (the default), 1 the calling thread only. Results are the
    /// same bit for bit whatever the count.
    #[getter]
    fn threads(&self) -> usize {
        self.r().threads()
    }

    #[setter]
    fn set_threads(&mut self, threads: &Bound<'_, PyAny>) -> PyResult<()> {
        let whole = threads.is_instance_of::<pyo3::types::PyInt>() && !threads.is_instance_of::<pyo3::types::PyBool>();
        let n = if whole { threads.extract::<usize>().ok() } else { None };
        let n = n.ok_or_else(|| invalid("threads", format!("must be a whole number >= 0, got {threads}")))?;
        self.w().set_threads(n).map_err(world_error)
    }

    /// The contact mode: "accurate" or "fast".
    #[getter]
    fn mode(&self) -> &'static str {
        self.r().mode().name()
    }

    /// Adds a ground: a static half-space below the plane z = height (normal +z). Returns its body handle.
    /// Its surface as a body's (`add_body`): defaults from `tumble::Material::default()`.
    #[pyo3(signature = (height = 0.0, restitution = None, friction = None, rolling_resistance = None,
                        torsional_resistance = None, friction_combine = None, restitution_combine = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_ground(
        &mut self,
        height: f64,
        restitution: Option<f64>,
        friction: Option<f64>,
        rolling_resistance: Option<f64>,
        torsional_resistance: Option<f64>,
        friction_combine: Option<String>,
        restitution_combine: Option<String>,
    ) -> PyResult<PyBodyHandle> {
        let material = MaterialArgs {
            friction,
            restitution,
            rolling_resistance,
            torsional_resistance,
            friction_combine,
            restitution_combine,
        }
        .material()?;
        self.w().add_ground(height, material).map(Into::into).map_err(world_error)
    }

    /// Adds a particle obeying m x'' + d x' + h (x - anchor) = sum F.
    /// With `radius` > 0 it collides with bodies as a small sphere (particles do not collide with each other).
    #[pyo3(signature = (mass = None, position = None, velocity = None, damping = 0.0, stiffness = 0.0, anchor = None,
                        radius = 0.0, restitution = None, friction = None, friction_combine = None,
                        restitution_combine = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_particle(
        &mut self,
        mass: Option<f64>,
        position: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        damping: f64,
        stiffness: f64,
        anchor: Option<&Bound<'_, PyAny>>,
        radius: f64,
        restitution: Option<f64>,
        friction: Option<f64>,
        friction_combine: Option<String>,
        restitution_combine: Option<String>,
    ) -> PyResult<PyParticleHandle> {
        let surface =
            MaterialArgs { friction, restitution, friction_combine, restitution_combine, ..Default::default() };
        let mut b = ParticleBuilder::default()
            .damping(damping)
            .stiffness(stiffness)
            .radius(radius)
            .material(surface.material()?);
        if let Some(m) = mass {
            b = b.mass(m);
        }
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

    /// Adds a damped spring between `a` and `b` (particles or bodies; `b=None` with `world_point` for a fixed
    /// point). Anchors are body-frame points relative to the centre of mass; `rest_length=None` takes the current
    /// distance.
    #[pyo3(signature = (a, b = None, stiffness = None, damping = 0.0, rest_length = None, anchor_a = None,
                        anchor_b = None, world_point = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_spring(
        &mut self,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        stiffness: Option<f64>,
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
        let mut s = SpringBuilder::new(end_a, end_b).damping(damping);
        if let Some(k) = stiffness {
            s = s.stiffness(k);
        }
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
        if !callback.bind(target.py()).is_callable() {
            return Err(invalid("callback", "must be callable as callback(t, position, velocity)"));
        }
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
        // The argument here is `handle`, whatever kind it is.
        r.map_err(|e| match e {
            WorldError::UnknownHandle { handle, .. } => WorldError::UnknownHandle { name: "handle", handle },
            other => other,
        })
        .map_err(world_error)
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

    /// Sets a particle's or body's surface (static bodies included; what is None is left as it is), between steps,
    /// in either mode: the contacts found from the next step on use it, and the engine keeps its memory. A combine
    /// rule "world" gives the surface the world's rule again. Copies and saved files keep the new material.
    /// Raises ValueError naming a bad value.
    #[pyo3(signature = (handle, friction = None, restitution = None, rolling_resistance = None,
                        torsional_resistance = None, friction_combine = None, restitution_combine = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_material(
        &mut self,
        handle: &Bound<'_, PyAny>,
        friction: Option<&Bound<'_, PyAny>>,
        restitution: Option<&Bound<'_, PyAny>>,
        rolling_resistance: Option<&Bound<'_, PyAny>>,
        torsional_resistance: Option<&Bound<'_, PyAny>>,
        friction_combine: Option<String>,
        restitution_combine: Option<String>,
    ) -> PyResult<()> {
        let target = to_target(handle, "handle")?;
        let given = |name: &'static str, v: Option<&Bound<'_, PyAny>>| {
            v.filter(|f| !f.is_none()).map(|f| number(name, f)).transpose()
        };
        let change = MaterialArgs {
            friction: given("friction", friction)?,
            restitution: given("restitution", restitution)?,
            rolling_resistance: given("rolling_resistance", rolling_resistance)?,
            torsional_resistance: given("torsional_resistance", torsional_resistance)?,
            friction_combine,
            restitution_combine,
        }
        .change()?;
        self.w()
            .set_material(target, change)
            .map_err(|e| match e {
                WorldError::UnknownHandle { handle, .. } => WorldError::UnknownHandle { name: "handle", handle },
                other => other,
            })
            .map_err(world_error)
    }

    /// Sets how two surfaces' frictions and restitutions combine where neither names its own rule ("average",
    /// "geometric_mean", "min", "product", "max"; each left as it is when None). The engine is built anew.
    #[pyo3(signature = (friction = None, restitution = None))]
    fn set_combine_rules(&mut self, friction: Option<&str>, restitution: Option<&str>) -> PyResult<()> {
        let mut rules = self.r().combine_rules();
        if let Some(f) = friction {
            rules.friction = tumble::Combine::parse("friction", f).map_err(world_error)?;
        }
        if let Some(r) = restitution {
            rules.restitution = tumble::Combine::parse("restitution", r).map_err(world_error)?;
        }
        self.w().set_combine_rules(rules);
        Ok(())
    }

    /// The world's combine rules: {"friction": name, "restitution": name}.
    #[getter]
    fn combine_rules(&self) -> std::collections::BTreeMap<&'static str, &'static str> {
        let rules = self.r().combine_rules();
        [("friction", rules.friction.name()), ("restitution", rules.restitution.name())].into_iter().collect()
    }

    /// Advances by exactly `dt` (several internal steps if the integrator is adaptive). Raises SimulationError,
    /// leaving the world unchanged, if the step cannot be completed; Ctrl-C stops it and leaves the world
    /// unchanged too (a step records no frame to keep).
    fn step(&mut self, py: Python<'_>, dt: f64) -> PyResult<()> {
        let mut control = Control::new(None, None);
        let inner = self.w();
        let r = py.detach(|| inner.step_with(dt, &mut control));
        match r {
            Err(WorldError::Interrupted) => Err(control.take_error()),
            r => r.map_err(|e| self.error(py, e)),
        }
    }

    /// Runs for `duration`, recording a frame every `frame_interval`; returns a dict of arrays (the package
    /// wraps it in `tumble.Run`). `progress(fraction)` is called between chunks, `hint(line)` with the one line a
    /// slow accurate run says; Ctrl-C stops the run at its last whole frame, the world left there and the frames
    /// done riding on the exception (a failure, or an exception from `progress`, restores the world, its frames
    /// riding on the error too).
    #[pyo3(signature = (duration, frame_interval = None, progress = None, hint = None))]
    fn _run<'py>(
        &mut self,
        py: Python<'py>,
        duration: f64,
        frame_interval: Option<f64>,
        progress: Option<Py<PyAny>>,
        hint: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut control = Control::new(progress, hint);
        let inner = self.w();
        let interval = frame_interval.unwrap_or(tumble::DEFAULT_FRAME_INTERVAL);
        let result = py.detach(|| inner.run_with(duration, interval, &mut control));
        let err = match result {
            Ok(run) => return run_arrays(py, run),
            Err(WorldError::Interrupted) => control.take_error(),
            Err(e) => self.error(py, e),
        };
        // the frames up to the failure or interrupt ride on the exception (the package makes them `error.run`)
        if let Some(run) = self.w().take_failed_run() {
            err.value(py).setattr("_partial", run_arrays(py, run)?)?;
        }
        Err(err)
    }
}
