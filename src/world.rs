//! The world: particles, rigid bodies, springs and loads, stepped by any method of tumble-integrate. Its contents
//! are compiled into a model (flat arrays, state vector) when its structure changes; a step that fails leaves the
//! world exactly as it was.

use crate::body::{RigidBody, RigidBodyBuilder};
use crate::error::{check_finite, check_scalar, WorldError};
use crate::handle::{Arena, Handle};
use crate::load::{Load, LoadHandle, Target, TargetState, Wrench};
use crate::mode::Mode;
use crate::model::{compile, Compiled, CompiledLoad, JacobianKind, Model};
use crate::particle::{Particle, ParticleBuilder};
use crate::plan::Plan;
use crate::report::WorldReport;
use crate::run::{BodySource, Run};
use crate::spring::{Attachment, BodyHandle, ParticleHandle, Spring, SpringBuilder, SpringHandle};
use nalgebra::{UnitQuaternion, Vector3};
use tumble_integrate::{Integrator, Method, Settings};

/// The compiled model and the integrator that steps it.
pub(crate) struct Engine {
    pub(crate) compiled: Compiled,
    pub(crate) integrator: Integrator<Model>,
    /// The contact stage of accurate mode, when the scene has colliders that can touch.
    #[cfg(feature = "contact")]
    pub(crate) accurate: Option<crate::accurate::Accurate>,
}

/// Which Jacobian the springs contribute to implicit methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpringJacobian {
    /// The exact derivative: Newton-type methods (full Newton, Rodas4, Radau5) need it for their convergence
    /// and order.
    Exact,
    /// Compression's transverse term clamped at zero and damping's position derivative dropped: every spring block
    /// is negative semidefinite, so the chapter's single linearised implicit Euler step cannot gain energy.
    Definite,
}

/// A world of particles and rigid bodies.
pub struct World {
    pub(crate) gravity: Vector3<f64>,
    pub(crate) settings: Settings,
    pub(crate) time: f64,
    pub(crate) particles: Arena<Particle>,
    pub(crate) bodies: Arena<RigidBody>,
    pub(crate) springs: Arena<Spring>,
    pub(crate) loads: Arena<Load>,
    pub(crate) engine: Option<Engine>,
    pub(crate) state_changed: bool,
    pub(crate) totals: WorldReport,
    pub(crate) divergence_factor: f64,
    pub(crate) spring_jacobian: Option<SpringJacobian>,
    pub(crate) mode: Mode,
    #[cfg(feature = "contact")]
    pub(crate) fast: Option<crate::fast::FastEngine>,
}

impl Default for World {
    fn default() -> Self {
        World::new()
    }
}

fn unknown<T>(name: &'static str, h: Handle<T>) -> WorldError {
    WorldError::UnknownHandle { name, handle: format!("{h:?}") }
}

impl World {
    /// An empty world with gravity (0, 0, -9.81) and Dormand-Prince at rtol = 1e-6, atol = 1e-9.
    pub fn new() -> Self {
        let settings = Settings::tolerances(Method::Dopri5, 1e-6, 1e-9);
        World {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            totals: WorldReport::new(settings.method.name()),
            settings,
            time: 0.0,
            particles: Arena::default(),
            bodies: Arena::default(),
            springs: Arena::default(),
            loads: Arena::default(),
            engine: None,
            state_changed: false,
            divergence_factor: 1e9,
            spring_jacobian: None,
            mode: Mode::default(),
            #[cfg(feature = "contact")]
            fast: None,
        }
    }

    /// How the world treats contact.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Chooses accurate (event-driven) or fast (time-stepping) contact. Fast mode needs the `contact` feature.
    pub fn set_mode(&mut self, mode: Mode) -> Result<(), WorldError> {
        mode.check()?;
        if cfg!(not(feature = "contact")) && matches!(mode, Mode::Fast(_)) {
            return Err(WorldError::invalid("mode", "fast mode needs tumble built with the `contact` feature"));
        }
        self.mode = mode;
        self.retire_engine();
        Ok(())
    }

    /// Adds a ground: a static half-space below the plane z = `height` (normal +z) with this material.
    pub fn add_ground(&mut self, height: f64, material: crate::Material) -> Result<BodyHandle, WorldError> {
        check_finite("height", [height].iter())?;
        let ground = tumble_collide::Shape::half_space(Vector3::z())?;
        self.add_body(
            RigidBodyBuilder::fixed(Some(ground))
                .position(Vector3::new(0.0, 0.0, height))
                .restitution(material.restitution)
                .friction(material.friction),
        )
    }

    /// Gravity.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Sets gravity.
    pub fn set_gravity(&mut self, g: Vector3<f64>) -> Result<(), WorldError> {
        check_finite("gravity", g.iter())?;
        self.gravity = g;
        self.retire_engine();
        Ok(())
    }

    /// The integrator settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Chooses the integrator. The settings are checked against the world now.
    pub fn set_integrator(&mut self, settings: Settings) -> Result<(), WorldError> {
        let compiled = self.compile();
        settings.validate(&compiled.model)?;
        self.settings = settings;
        self.retire_engine();
        Ok(())
    }

    /// A state whose max norm grows past `factor` times that of the state a run starts from (at least 1) is
    /// reported as diverging (default 1e9): an unstable explicit step fails with an error long before overflow.
    pub fn set_divergence_factor(&mut self, factor: f64) -> Result<(), WorldError> {
        self.divergence_factor = check_scalar("factor", factor, true)?;
        self.retire_engine();
        Ok(())
    }

    /// Chooses the springs' Jacobian; `None` (the default) picks `Definite` for the linearised implicit Euler and
    /// `Exact` for every other method.
    pub fn set_spring_jacobian(&mut self, choice: Option<SpringJacobian>) {
        self.spring_jacobian = choice;
        self.retire_engine();
    }

    /// The springs' Jacobian in use.
    pub fn spring_jacobian(&self) -> SpringJacobian {
        self.spring_jacobian.unwrap_or(
            if self.settings.method == Method::ImplicitEuler
                && self.settings.newton == tumble_integrate::NewtonMode::Linearised
            {
                SpringJacobian::Definite
            } else {
                SpringJacobian::Exact
            },
        )
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.time
    }

    // ---- building ------------------------------------------------------------------------------------------

    /// Adds a particle.
    pub fn add_particle(&mut self, particle: ParticleBuilder) -> Result<ParticleHandle, WorldError> {
        let p = particle.build()?;
        self.retire_engine();
        Ok(self.particles.insert(p))
    }

    /// Adds a rigid body.
    pub fn add_body(&mut self, body: RigidBodyBuilder) -> Result<BodyHandle, WorldError> {
        let b = body.build()?;
        self.retire_engine();
        Ok(self.bodies.insert(b))
    }

    fn attachment_point(&self, name: &'static str, a: &Attachment) -> Result<Vector3<f64>, WorldError> {
        match *a {
            Attachment::Particle(h) => Ok(self.particles.get(h).ok_or_else(|| unknown(name, h))?.position),
            Attachment::Body(h, local) => {
                check_finite(if name == "a" { "anchor_a" } else { "anchor_b" }, local.iter())?;
                Ok(self.bodies.get(h).ok_or_else(|| unknown(name, h))?.world_point(local))
            }
            Attachment::Point(p) => {
                check_finite("world_point", p.iter())?;
                Ok(p)
            }
        }
    }

    /// Adds a spring; without a rest length, the current distance between its ends.
    pub fn add_spring(&mut self, spring: SpringBuilder) -> Result<SpringHandle, WorldError> {
        let pa = self.attachment_point("a", &spring.a)?;
        let pb = self.attachment_point("b", &spring.b)?;
        if let (Attachment::Point(_), Attachment::Point(_)) = (spring.a, spring.b) {
            return Err(WorldError::invalid("b", "a spring between two fixed points acts on nothing"));
        }
        if let (Attachment::Particle(a), Attachment::Particle(b)) = (spring.a, spring.b) {
            if a == b {
                return Err(WorldError::invalid("b", "a spring needs two different ends"));
            }
        }
        let stiffness = check_scalar("stiffness", spring.stiffness, true)?;
        let damping = check_scalar("damping", spring.damping, false)?;
        let rest_length = match spring.rest_length {
            Some(l) => check_scalar("rest_length", l, false)?,
            None => (pa - pb).norm(),
        };
        self.retire_engine();
        Ok(self.springs.insert(Spring { a: spring.a, b: spring.b, stiffness, damping, rest_length }))
    }

    fn check_target(&self, t: Target) -> Result<(), WorldError> {
        match t {
            Target::Particle(h) => self.particles.get(h).map(|_| ()).ok_or_else(|| unknown("target", h)),
            Target::Body(h) => match self.bodies.get(h) {
                None => Err(unknown("target", h)),
                Some(b) if b.is_static => {
                    Err(WorldError::invalid("target", "a static body does not move: a load on it has no effect"))
                }
                Some(_) => Ok(()),
            },
        }
    }

    /// Adds a load.
    pub fn add_load(&mut self, load: Load) -> Result<LoadHandle, WorldError> {
        self.check_target(load.target())?;
        match &load {
            Load::Force { target, force, at } => {
                check_finite("force", force.iter())?;
                if let Some(at) = at {
                    check_finite("at", at.iter())?;
                    if matches!(target, Target::Particle(_)) {
                        return Err(WorldError::invalid(
                            "at",
                            "a particle has no body frame: apply its force without `at`",
                        ));
                    }
                }
            }
            Load::Torque { torque, .. } => check_finite("torque", torque.iter())?,
            Load::Callback { .. } => {}
        }
        self.retire_engine();
        Ok(self.loads.insert(load))
    }

    /// Adds a constant force, fixed in world axes, at the centre of mass or at a body point `at` (body frame).
    pub fn add_force(
        &mut self,
        target: Target,
        force: Vector3<f64>,
        at: Option<Vector3<f64>>,
    ) -> Result<LoadHandle, WorldError> {
        self.add_load(Load::Force { target, force, at })
    }

    /// Adds a constant torque (world axes) on a body.
    pub fn add_torque(&mut self, body: BodyHandle, torque: Vector3<f64>) -> Result<LoadHandle, WorldError> {
        self.add_load(Load::Torque { body, torque })
    }

    /// Adds a force callback: `f(t, state)` returns the force (and, for a body, the torque) on `target`.
    pub fn add_force_callback(
        &mut self,
        target: Target,
        f: impl FnMut(f64, &TargetState) -> Result<Wrench, String> + Send + 'static,
    ) -> Result<LoadHandle, WorldError> {
        self.add_load(Load::callback(target, f))
    }

    /// Removes a particle, with the springs and loads attached to it.
    pub fn remove_particle(&mut self, h: ParticleHandle) -> Result<Particle, WorldError> {
        let p = self.particles.remove(h).ok_or_else(|| unknown("particle", h))?;
        self.springs.retain(|s| ![s.a, s.b].contains(&Attachment::Particle(h)));
        self.loads.retain(|l| l.target() != Target::Particle(h));
        self.retire_engine();
        Ok(p)
    }

    /// Removes a body, with the springs and loads attached to it.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<RigidBody, WorldError> {
        let b = self.bodies.remove(h).ok_or_else(|| unknown("body", h))?;
        self.springs.retain(|s| ![s.a, s.b].iter().any(|e| matches!(e, Attachment::Body(b, _) if *b == h)));
        self.loads.retain(|l| l.target() != Target::Body(h));
        self.retire_engine();
        Ok(b)
    }

    /// Removes a spring.
    pub fn remove_spring(&mut self, h: SpringHandle) -> Result<Spring, WorldError> {
        let s = self.springs.remove(h).ok_or_else(|| unknown("spring", h))?;
        self.retire_engine();
        Ok(s)
    }

    /// Removes a load.
    pub fn remove_load(&mut self, h: LoadHandle) -> Result<(), WorldError> {
        self.loads.remove(h).ok_or_else(|| unknown("load", h))?;
        self.retire_engine();
        Ok(())
    }

    // ---- state ---------------------------------------------------------------------------------------------

    /// Sets a particle's position and velocity.
    pub fn set_particle_state(
        &mut self,
        h: ParticleHandle,
        position: Vector3<f64>,
        velocity: Vector3<f64>,
    ) -> Result<(), WorldError> {
        check_finite("position", position.iter())?;
        check_finite("velocity", velocity.iter())?;
        let p = self.particles.get_mut(h).ok_or_else(|| unknown("particle", h))?;
        p.position = position;
        p.velocity = velocity;
        self.state_changed = true;
        Ok(())
    }

    /// Sets a dynamic body's pose, velocity and angular velocity (world axes).
    pub fn set_body_state(
        &mut self,
        h: BodyHandle,
        position: Vector3<f64>,
        orientation: UnitQuaternion<f64>,
        velocity: Vector3<f64>,
        angular_velocity: Vector3<f64>,
    ) -> Result<(), WorldError> {
        check_finite("position", position.iter())?;
        check_finite("orientation", orientation.coords.iter())?;
        check_finite("velocity", velocity.iter())?;
        check_finite("angular_velocity", angular_velocity.iter())?;
        let b = self.bodies.get_mut(h).ok_or_else(|| unknown("body", h))?;
        if b.is_static {
            b.position = position;
            b.orientation = orientation;
            self.retire_engine();
            return Ok(());
        }
        b.position = position;
        b.orientation = orientation;
        b.momentum = velocity * b.mass;
        b.angular_momentum = b.world_inertia() * angular_velocity;
        self.state_changed = true;
        Ok(())
    }

    // ---- queries -------------------------------------------------------------------------------------------

    /// A particle.
    pub fn particle(&self, h: ParticleHandle) -> Result<&Particle, WorldError> {
        self.particles.get(h).ok_or_else(|| unknown("particle", h))
    }

    /// A body.
    pub fn body(&self, h: BodyHandle) -> Result<&RigidBody, WorldError> {
        self.bodies.get(h).ok_or_else(|| unknown("body", h))
    }

    /// A spring.
    pub fn spring(&self, h: SpringHandle) -> Result<&Spring, WorldError> {
        self.springs.get(h).ok_or_else(|| unknown("spring", h))
    }

    /// All particles, in the order of the state vector.
    pub fn particles(&self) -> impl Iterator<Item = (ParticleHandle, &Particle)> {
        self.particles.iter()
    }

    /// All bodies (static ones included), in the world's order.
    pub fn bodies(&self) -> impl Iterator<Item = (BodyHandle, &RigidBody)> {
        self.bodies.iter()
    }

    /// All springs.
    pub fn springs(&self) -> impl Iterator<Item = (SpringHandle, &Spring)> {
        self.springs.iter()
    }

    /// Number of particles.
    pub fn particle_count(&self) -> usize {
        self.particles.len()
    }

    /// Number of bodies (static ones included).
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    pub(crate) fn compile(&self) -> Compiled {
        let mut c = compile(self.gravity, &self.particles, &self.bodies, &self.springs, &self.loads);
        c.model.definite_springs = self.spring_jacobian() == SpringJacobian::Definite;
        c
    }

    #[cfg(test)]
    pub(crate) fn particles_arena(&self) -> &Arena<Particle> {
        &self.particles
    }

    #[cfg(test)]
    pub(crate) fn bodies_arena(&self) -> &Arena<RigidBody> {
        &self.bodies
    }

    /// Evaluates `f` on the current model and state.
    fn with_state<R>(&self, f: impl FnOnce(&Model, &[f64]) -> R) -> R {
        match &self.engine {
            Some(e) if !self.state_changed => f(&e.compiled.model, e.integrator.state()),
            _ => {
                let c = self.compile();
                let y = c.pack(&self.particles, &self.bodies);
                f(&c.model, &y)
            }
        }
    }

    /// Kinetic energy: 1/2 m v^2 of particles, 1/2 P^2/M + 1/2 L . w of bodies.
    pub fn kinetic_energy(&self) -> f64 {
        self.with_state(|m, y| m.kinetic_energy(y))
    }

    /// Potential energy of gravity, springs and the particles' restoring terms.
    pub fn potential_energy(&self) -> f64 {
        self.with_state(|m, y| m.potential_energy(y))
    }

    /// Total linear momentum.
    pub fn momentum(&self) -> Vector3<f64> {
        self.with_state(|m, y| m.momentum(y))
    }

    /// Total angular momentum about the origin.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.with_state(|m, y| m.angular_momentum(y))
    }

    /// The stages this world runs, decided from its contents and its integrator.
    pub fn plan(&self) -> Plan {
        let c = self.compile();
        let m = &c.model;
        let l = m.layout;
        let mut stages = Vec::new();
        let mut add = |on: bool, name| {
            if on {
                stages.push(name)
            }
        };
        add(l.particles > 0, "particles");
        add(l.bodies > 0, "rigid-bodies");
        add(l.bodies > 0, "rotation");
        add(l.dim() > 0 && self.gravity != Vector3::zeros(), "gravity");
        add(
            m.particles.iter().any(|p| p.damping > 0.0 || p.stiffness > 0.0)
                || m.bodies.iter().any(|b| b.linear_damping > 0.0 || b.angular_damping > 0.0),
            "damping",
        );
        add(!m.springs.is_empty(), "springs");
        add(m.loads.iter().any(|l| !matches!(l, CompiledLoad::Callback { .. })), "loads");
        add(m.loads.iter().any(|l| matches!(l, CompiledLoad::Callback { .. })), "callbacks");
        #[cfg(feature = "contact")]
        let contact = crate::contact_scene::ContactScene::build(l, &self.particles, &self.bodies, &c.bodies).is_some();
        #[cfg(not(feature = "contact"))]
        let contact = false;
        let fast = matches!(self.mode, Mode::Fast(_));
        add(contact, "collision-detection");
        add(contact && !fast, "bisection");
        add(contact && !fast, "impulses");
        add(contact && !fast, "resting-contact");
        add(contact && fast, "contact-cone-program");
        add(contact && matches!(self.mode, Mode::Fast(f) if f.sleep), "sleeping");
        add(l.dim() > 0, "integrate");
        let uses_jacobian = l.dim() > 0 && self.settings.method.uses_jacobian() && !fast;
        add(uses_jacobian, "jacobian");
        Plan {
            stages,
            state_len: l.dim(),
            mode: self.mode.name(),
            method: if fast { "fast (semi-implicit Euler)" } else { self.settings.method.name() },
            jacobian: uses_jacobian.then_some(match (m.jacobian, m.definite_springs) {
                (JacobianKind::Analytic, false) => "analytic-sparse",
                (JacobianKind::Analytic, true) => "analytic-sparse-definite",
                (JacobianKind::Colored, _) => "colored-finite-differences",
            }),
        }
    }

    /// Everything the world's steps have cost so far.
    pub fn report(&self) -> WorldReport {
        self.totals.clone()
    }

    // ---- stepping ------------------------------------------------------------------------------------------

    /// Drops the compiled model (the structure changed); its report is already in the totals.
    pub(crate) fn retire_engine(&mut self) {
        self.engine = None;
        #[cfg(feature = "contact")]
        {
            self.fast = None;
        }
        self.state_changed = false;
    }

    /// The engine, compiled if the structure changed and given any state the user set.
    pub(crate) fn engine(&mut self) -> Result<&mut Engine, WorldError> {
        match &mut self.engine {
            Some(e) => {
                if self.state_changed {
                    let y = e.compiled.pack(&self.particles, &self.bodies);
                    e.integrator.set_state(self.time, &y)?;
                }
            }
            None => {
                let mut compiled = self.compile();
                let y = compiled.pack(&self.particles, &self.bodies);
                let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let settings = self.settings.clone().divergence_limit(self.divergence_factor * scale);
                let integrator = Integrator::new(&mut compiled.model, settings, self.time, &y)?;
                #[cfg(feature = "contact")]
                let accurate = self.accurate_stage(&compiled);
                self.engine = Some(Engine {
                    compiled,
                    integrator,
                    #[cfg(feature = "contact")]
                    accurate,
                });
            }
        }
        self.state_changed = false;
        Ok(self.engine.as_mut().expect("built above"))
    }

    /// Moves the engine's report and force counters into the totals and returns them.
    pub(crate) fn collect_report(&mut self) -> WorldReport {
        let mut r = WorldReport::new(self.settings.method.name());
        if let Some(e) = &mut self.engine {
            r.integrator = e.integrator.take_report();
            r.forces = std::mem::take(&mut e.compiled.model.counters);
            #[cfg(feature = "contact")]
            crate::world_accurate::take_contact_report(e, &mut r);
        }
        self.totals.merge(&r);
        r
    }

    /// Writes the engine's state into the particles and bodies.
    fn store_state(&mut self) {
        if let Some(e) = &self.engine {
            e.compiled.unpack(e.integrator.state(), &mut self.particles, &mut self.bodies);
            self.time = e.integrator.time();
        }
    }

    /// Advances by exactly `dt` (several internal steps if the method is adaptive). On error the world is
    /// unchanged.
    pub fn step(&mut self, dt: f64) -> Result<(), WorldError> {
        check_scalar("dt", dt, true)?;
        #[cfg(feature = "contact")]
        if let Mode::Fast(settings) = self.mode {
            return self.step_fast(settings, dt);
        }
        let t_end = self.time + dt;
        if self.particles.len() + self.bodies.iter().filter(|(_, b)| !b.is_static).count() == 0 {
            self.time = t_end;
            return Ok(());
        }
        let e = self.engine()?;
        #[cfg(feature = "contact")]
        if e.accurate.is_some() {
            let result = crate::world_accurate::advance(e, t_end, t_end, &[], |_, _, _, _| {}, |_| {});
            self.collect_report();
            result?;
            self.store_state();
            return Ok(());
        }
        let result = e.integrator.advance_to(&mut e.compiled.model, t_end, &[], |_, _, _| {});
        self.collect_report();
        result?;
        self.store_state();
        Ok(())
    }

    /// Runs for `duration`, recording a frame every `frame_interval` (and at the end).
    pub fn run(&mut self, duration: f64, frame_interval: f64) -> Result<Run, WorldError> {
        self.run_with(duration, frame_interval, |_| true)
    }

    /// [`run`](World::run), calling `control(fraction_done)` between chunks of about a hundredth of the frames;
    /// when it returns false the run stops with [`WorldError::Interrupted`]. On any error the world is as it was
    /// before the call.
    pub fn run_with(
        &mut self,
        duration: f64,
        frame_interval: f64,
        mut control: impl FnMut(f64) -> bool,
    ) -> Result<Run, WorldError> {
        check_scalar("duration", duration, true)?;
        check_scalar("frame_interval", frame_interval, true)?;
        let count = (duration / frame_interval * (1.0 + 1e-12)).floor();
        if count > 1e7 {
            return Err(WorldError::invalid("frame_interval", format!("{count:e} frames are too many to record")));
        }
        let t0 = self.time;
        let mut times: Vec<f64> = (0..=count as usize).map(|k| t0 + k as f64 * frame_interval).collect();
        let t_end = t0 + duration;
        match times.last_mut() {
            Some(last) if (t_end - *last).abs() <= 1e-9 * frame_interval => *last = t_end,
            _ => times.push(t_end),
        }
        let sources: Vec<BodySource> = {
            let c = self.compile();
            self.bodies
                .iter()
                .map(|(h, b)| match c.bodies.iter().position(|&d| d == h) {
                    Some(j) => BodySource::Dynamic(j),
                    None => BodySource::Static(b.position, b.orientation),
                })
                .collect()
        };
        let particles: Vec<ParticleHandle> = self.particles.iter().map(|(h, _)| h).collect();
        let bodies: Vec<BodyHandle> = self.bodies.iter().map(|(h, _)| h).collect();
        let mut run = Run::new(particles, bodies, sources, self.settings.method.name());
        #[cfg(feature = "contact")]
        if let Mode::Fast(settings) = self.mode {
            return self.run_fast(settings, &times, run, control);
        }
        let dynamic = self.particles.len() + self.bodies.iter().filter(|(_, b)| !b.is_static).count();
        if dynamic == 0 {
            let c = self.compile();
            for &t in &times {
                run.record(&c.model, t, &[]);
                run.penetration.push(0.0);
            }
            self.time = t_end;
            return Ok(run);
        }
        let e = self.engine()?;
        let y0 = e.integrator.state().to_vec();
        e.integrator.log_steps(true);
        // Pause about a hundred times to report progress; pausing does not shorten a step, so the run takes the
        // same steps as one call would.
        let chunk = times.len().div_ceil(100).max(1);
        let mut outcome = Ok(());
        let mut done = 0;
        #[cfg_attr(not(feature = "contact"), allow(unused_mut))]
        let mut contact_events: Vec<f64> = Vec::new();
        while done < times.len() {
            let pause = times[(done + chunk).min(times.len()) - 1];
            #[cfg(feature = "contact")]
            let result = if e.accurate.is_some() {
                let (frames, events) = (&mut run, &mut contact_events);
                crate::world_accurate::advance(
                    e,
                    t_end,
                    pause,
                    &times[done..],
                    |m, t, y, penetration| {
                        frames.record(m, t, y);
                        frames.penetration.push(penetration);
                    },
                    |t| events.push(t),
                )
            } else {
                e.integrator.advance_until(&mut e.compiled.model, t_end, pause, &times[done..], |m, t, y| {
                    run.record(m, t, y);
                    run.penetration.push(0.0);
                })
            };
            #[cfg(not(feature = "contact"))]
            let result = e.integrator.advance_until(&mut e.compiled.model, t_end, pause, &times[done..], |m, t, y| {
                run.record(m, t, y);
                run.penetration.push(0.0);
            });
            for (t, h) in e.integrator.take_step_log() {
                run.step_times.push(t);
                run.step_sizes.push(h);
            }
            match result {
                Ok(delivered) => done += delivered,
                Err(err) => {
                    outcome = Err(WorldError::from(err));
                    break;
                }
            }
            if !control(done as f64 / times.len() as f64) {
                outcome = Err(WorldError::Interrupted);
                break;
            }
        }
        e.integrator.log_steps(false);
        run.contact_events = contact_events;
        if outcome.is_err() {
            e.integrator.set_state(t0, &y0).expect("the starting state was valid");
        }
        run.report = self.collect_report();
        outcome?;
        self.store_state();
        Ok(run)
    }
}

/// A world can be moved to another thread (the Python module runs it with the interpreter lock released).
#[allow(dead_code)]
fn world_is_send() {
    fn is_send<T: Send>() {}
    is_send::<World>();
}
