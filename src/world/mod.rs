//! The world: particles, rigid bodies, springs and loads, stepped by any method of tumble-integrate. Its contents
//! are compiled into a model (flat arrays, state vector) when its structure changes and handed to an engine
//! (`crate::engine`) that steps it; a step that fails leaves the world exactly as it was. This file holds the
//! world and its settings; `build.rs` adds and removes things, `state.rs` sets and reads state, `plan.rs` the
//! plan, `stepping.rs` the one run loop.

mod build;
mod contacts;
mod files;
mod fractured;
mod handover;
mod interrupt;
mod joints;
mod materials;
mod pace;
mod plan;
mod state;
mod stepping;
mod whole_state;

pub use contacts::ContactInfo;
pub use fractured::{bond_bounds, bonds, Fractured, Glue, GLUE_WINDOW, MAX_STRENGTH, MIN_STRENGTH, SMALLEST_BOND};
pub use materials::MaterialChange;
pub(crate) use pace::Pace;
pub use whole_state::WorldState;

use crate::body::{RigidBody, RigidBodyBuilder};
use crate::collider::CombineRules;
use crate::engine::Engine;
use crate::error::WorldError;
use crate::handle::{Arena, Handle};
use crate::limits;
use crate::load::Load;
use crate::mode::Mode;
use crate::particle::Particle;
use crate::report::WorldReport;
use crate::spring::{BodyHandle, Spring};
use nalgebra::Vector3;
use tumble_integrate::{Method, Settings};

/// Which Jacobian the springs contribute to implicit methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringJacobian {
    /// The exact derivative: Newton-type methods (full Newton, Rodas4, Radau5) need it for their convergence
    /// and order.
    Exact,
    /// Compression's transverse term clamped at zero and damping's position derivative dropped: every spring block
    /// is negative semidefinite, so the chapter's single linearised implicit Euler step cannot gain energy.
    Definite,
}

/// A world of particles and rigid bodies.
#[derive(Clone)]
pub struct World {
    pub(crate) gravity: Vector3<f64>,
    pub(crate) settings: Settings,
    pub(crate) time: f64,
    pub(crate) particles: Arena<Particle>,
    pub(crate) bodies: Arena<RigidBody>,
    pub(crate) springs: Arena<Spring>,
    pub(crate) loads: Arena<Load>,
    pub(crate) joints: Arena<crate::joint::Joint>,
    pub(crate) engine: Option<Box<dyn Engine>>,
    pub(crate) state_changed: bool,
    /// The frames of the last run that failed, until taken.
    pub(crate) failed_run: Option<crate::run::Run>,
    pub(crate) totals: WorldReport,
    pub(crate) divergence_factor: f64,
    pub(crate) spring_jacobian: Option<SpringJacobian>,
    pub(crate) mode: Mode,
    /// Threads for the contact solves (0: one per core).
    pub(crate) threads: usize,
    /// The state each object was added with, for `reset`.
    pub(crate) starts: whole_state::Starts,
    /// Whether the world has stepped since it was made or reset (until then, setting an object's state also sets
    /// the state `reset` returns to).
    pub(crate) stepped: bool,
    /// How many times the structure or settings changed (each retires the engine): a state's memory applies only
    /// to an engine of the structure it was read from.
    pub(crate) structure: u64,
    /// Whether a slow call has said so (`pace.rs`: once a world).
    pub(crate) hinted: bool,
    /// How two materials combine where neither names its own rule.
    pub(crate) combine: crate::collider::CombineRules,
}

impl Default for World {
    fn default() -> Self {
        World::new()
    }
}

pub(crate) fn unknown<T>(name: &'static str, h: Handle<T>) -> WorldError {
    WorldError::UnknownHandle { name, handle: format!("{h:?}") }
}

impl World {
    /// An empty world with gravity (0, 0, -9.81) and Dormand-Prince at rtol = 1e-6, atol = 1e-9.
    pub fn new() -> Self {
        let settings = Settings::tolerances(Method::Dopri5, 1e-6, 1e-9);
        let number = crate::handle::new_world_number();
        World {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            totals: WorldReport::new(settings.method.name()),
            settings,
            time: 0.0,
            particles: Arena::new(number),
            bodies: Arena::new(number),
            springs: Arena::new(number),
            loads: Arena::new(number),
            joints: Arena::new(number),
            engine: None,
            state_changed: false,
            failed_run: None,
            divergence_factor: 1e9,
            spring_jacobian: None,
            mode: Mode::default(),
            threads: 0,
            starts: Default::default(),
            stepped: false,
            structure: 0,
            hinted: false,
            combine: Default::default(),
        }
    }

    /// How the world treats contact.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Chooses accurate (event-driven) or fast (time-stepping) contact.
    pub fn set_mode(&mut self, mode: Mode) -> Result<(), WorldError> {
        mode.check()?;
        // the joints already in the world must fit the new mode (the error names the mode, this call's argument)
        for (_, j) in self.joints.iter() {
            joints::joint_fits_mode(&mode, &j.spec).map_err(|(_, why)| WorldError::invalid("mode", why))?;
        }
        let materials =
            self.particles.iter().map(|(_, p)| p.material).chain(self.bodies.iter().map(|(_, b)| b.material));
        for m in materials {
            m.fits_mode(&mode).map_err(|why| WorldError::invalid("mode", why))?;
        }
        self.mode = mode;
        self.retire_engine();
        Ok(())
    }

    /// Adds a ground: a static half-space below the plane z = `height` (normal +z) with this material.
    pub fn add_ground(&mut self, height: f64, material: crate::Material) -> Result<BodyHandle, WorldError> {
        limits::in_range("height", height, -limits::COORDINATE, limits::COORDINATE, "m")?;
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
        limits::vector("gravity", &g, limits::GRAVITY, "m/s^2")?;
        self.gravity = g;
        self.retire_engine();
        Ok(())
    }

    /// How two materials combine at a contact where neither names its own rule (by default the geometric mean of
    /// the frictions and the larger restitution).
    pub fn combine_rules(&self) -> CombineRules {
        self.combine
    }

    /// Sets how two materials combine where neither names its own rule (from the next step on; the engine is
    /// built anew).
    pub fn set_combine_rules(&mut self, rules: CombineRules) {
        self.combine = rules;
        self.retire_engine();
    }

    /// The integrator settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Chooses the integrator. The settings are checked against the world now. Fast mode steps by its own
    /// scheme, so choosing an integrator there is an error naming `integrator`.
    pub fn set_integrator(&mut self, settings: Settings) -> Result<(), WorldError> {
        if matches!(self.mode, Mode::Fast(_)) {
            return Err(WorldError::invalid(
                "integrator",
                "fast mode steps by semi-implicit Euler at its dt; choose the integrator in accurate mode",
            ));
        }
        settings.validate(&crate::engine::accurate::AccurateSystem::new(self.compile().model))?;
        self.settings = settings;
        self.retire_engine();
        Ok(())
    }

    /// A state whose max norm grows past `factor` times that of the state a run starts from (at least 1) is
    /// reported as diverging (default 1e9): an unstable explicit step fails with an error long before overflow.
    pub fn set_divergence_factor(&mut self, factor: f64) -> Result<(), WorldError> {
        self.divergence_factor = limits::positive("factor", factor, 1e100, "")?;
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

    /// Sets how many threads the contact solves use: 0 (the default) one per core, 1 the calling thread only.
    /// Results are the same bit for bit whatever the count.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), WorldError> {
        if threads > 1024 {
            return Err(WorldError::invalid("threads", format!("must be at most 1024, got {threads}")));
        }
        self.threads = threads;
        // results do not depend on it: the engine keeps its memory
        if let Some(e) = &mut self.engine {
            e.set_threads(threads);
        }
        Ok(())
    }

    /// The thread count of the contact solves (0: one per core).
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Everything the world's steps have cost so far.
    pub fn report(&self) -> WorldReport {
        let mut r = self.totals.clone();
        // each mesh is decomposed once however many bodies carry it
        let mut seen = std::collections::BTreeSet::new();
        for c in self.bodies.iter().flat_map(|(_, b)| b.colliders.iter()) {
            if let tumble_collide::Shape::Decomposed(d) = &c.shape {
                r.mesh_pieces += d.pieces().len();
                if seen.insert(d.key()) {
                    r.decomposition_seconds += d.seconds();
                    r.stages.mark(crate::plan::Stage::MeshDecomposition);
                }
            }
        }
        r
    }
}

/// A world can be moved to another thread (the Python module runs it with the interpreter lock released).
#[allow(dead_code)]
fn world_is_send() {
    fn is_send<T: Send>() {}
    is_send::<World>();
}
