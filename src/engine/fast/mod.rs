//! Fast mode: time stepping at a fixed step. One step is a list of stages (`step.rs`), one file each: the applied
//! forces at the step's start (`applied_forces.rs`), contacts found with a margin (`find_contacts.rs`), the contact
//! solve: either the soft step, which gives velocities and poses from its substeps (`soft_solve.rs`, the default),
//! or the exact solver's velocities from one conic program per island (`solve_velocities.rs`, with `warm_start.rs`
//! and `bounce_limiter.rs`, both solving with `solver.rs`) and positions from them; the joints the step broke
//! (`breaking.rs`); then sleep (`update_sleep.rs`, over `sleep.rs`) and the report. The stages work on the step's
//! context (`context.rs`: the engine's parts, borrowed for the step) and fail with `failure.rs`'s error; what the
//! steps carry from one to the next is the engine's memory (`memory.rs`). This module is the engine, above all of
//! them: it makes the context and runs the step on it.
//! The engine always steps by its `dt`: an advance ends at a whole number of steps, and frames are the states at the
//! steps that reach them.

mod applied_forces;
mod bounce_limiter;
mod breaking;
mod context;
mod find_contacts;
mod glued;
mod glued_loads;
mod glued_parts;
mod memory;
mod sleep;
mod soft_solve;
mod solve_velocities;
mod solver;
mod step;
#[cfg(test)]
mod tests;
mod update_sleep;
mod warm_start;

pub(crate) use memory::FastMemory;

use crate::engine::collider_set::ColliderSet;
use crate::engine::frames::FrameCursor;
use crate::engine::last_contacts::LastContact;
use crate::engine::semi_implicit::Form;
use crate::engine::{Budget, Engine, EngineCore, EngineMemory};
use crate::error::WorldError;
use crate::mode::{FastSettings, FastSolver};
use crate::model::{Compiled, Kinematics, Model, Tally};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use context::StepContext;
use sleep::Sleep;
use std::collections::BTreeMap;
use std::time::Instant;

/// The method name fast mode reports.
pub(crate) const FAST: &str = "fast (semi-implicit Euler, contact by conic program)";
/// ... with the soft step.
pub(crate) const FAST_SOFT: &str = "fast (semi-implicit Euler substeps, soft contact)";

/// Most steps one advance may take (a step budget: a huge span or a tiny step is an error, not a hang).
const MAX_STEPS: f64 = 1e7;

/// A fast-mode world's engine.
#[derive(Clone)]
pub(crate) struct FastEngine {
    core: EngineCore,
    model: Model,
    collider_set: Option<ColliderSet>,
    settings: FastSettings,
    memory: FastMemory,
    /// The rates of the last force evaluation (scratch).
    dy: Vec<f64>,
    /// What the equations of motion did since the report was last taken.
    tally: Tally,
    /// The energy of the state where the last step ended, for the next step's report (none once the state or the
    /// memory was set).
    energy: Option<f64>,
    /// The world's state (momenta) of the memory's (velocity form): made where a call's chunk ends or a frame is
    /// recorded, not every step.
    published: Vec<f64>,
    /// The memory where the current call began (`checkpoint`), kept after it for its room.
    checkpoint: Option<FastMemory>,
}

impl FastEngine {
    pub fn new(
        compiled: Compiled,
        collider_set: Option<ColliderSet>,
        t: f64,
        y: Vec<f64>,
        settings: FastSettings,
        threads: usize,
        divergence_limit: f64,
    ) -> Self {
        let Compiled { model, handles } = compiled;
        let actors = model.layout.actors();
        let keeps_pairs = keeps_pairs(collider_set.is_some(), &settings);
        let mut own = y.clone();
        model.to_velocities(&y, &mut own);
        let memory = FastMemory {
            origin: t,
            steps: 0,
            previous: BTreeMap::new(),
            joint_warm: vec![Default::default(); model.joints.len()],
            broken: model.broken_joints(),
            load_averages: Vec::new(),
            sleep: Sleep::new(actors),
            penetration: 0.0,
            pairs: keeps_pairs.then(Default::default),
            last_contacts: Vec::new(),
            y: own,
        };
        FastEngine {
            dy: vec![0.0; memory.y.len()],
            tally: Tally::default(),
            energy: None,
            published: y,
            checkpoint: None,
            core: EngineCore::new(handles, divergence_limit, threads, WorldReport::new(method_name(&settings))),
            model,
            collider_set,
            settings,
            memory,
        }
    }

    /// The engine's own stages for a state of length `dim`, with or without colliders that can touch.
    pub fn planned(settings: &FastSettings, dim: usize, has_scene: bool, joints: bool) -> Vec<Stage> {
        let mut out = Vec::new();
        if has_scene {
            out.push(Stage::CollisionDetection);
            out.push(match settings.solver {
                FastSolver::Soft(_) => Stage::ContactSoftStep,
                FastSolver::Exact { .. } => Stage::ContactConeProgram,
            });
            // jointed bodies do not sleep (`update_sleep.rs`)
            if settings.sleep && !joints {
                out.push(Stage::Sleeping);
            }
        }
        if dim > 0 {
            out.push(Stage::Integrate);
        }
        out
    }

    fn time_at(&self, steps: u64) -> f64 {
        self.memory.origin + steps as f64 * self.settings.dt
    }

    /// The step's context: the engine's parts for one step from now.
    fn context(&mut self) -> StepContext<'_> {
        let (t, t_next) = (self.time(), self.time_at(self.memory.steps + 1));
        StepContext {
            model: &mut self.model,
            collider_set: self.collider_set.as_mut(),
            settings: &self.settings,
            memory: &mut self.memory,
            dy: &mut self.dy,
            kin: Kinematics::default(),
            tally: &mut self.tally,
            energy: &mut self.energy,
            report: &mut self.core.report,
            threads: self.core.threads,
            divergence_limit: self.core.divergence_limit,
            t,
            t_next,
        }
    }

    /// One step of size h (`step.rs`): the joints it broke.
    fn step(&mut self, h: f64) -> Result<Vec<usize>, WorldError> {
        step::step(&mut self.context(), h)
    }

    /// Puts the memory's broken joints into the model and the collider set.
    fn give_broken(&mut self) -> Result<(), String> {
        crate::engine::breaking::set_broken(&mut self.model, self.collider_set.as_mut(), &self.memory.broken)
    }

    /// A step of h, and its error estimate: the same step taken as two halves from the same start (time, state,
    /// warm starts and sleep as they were), their difference booked in the report; the world goes on from the
    /// whole step, as without the estimate, and the report keeps the whole step's counters (the halves' time is
    /// added to its wall time).
    fn doubled_step(&mut self, h: f64) -> Result<Vec<usize>, WorldError> {
        let start = self.memory.clone();
        let broken = self.step(h)?;
        let whole = std::mem::replace(&mut self.memory, start);
        self.give_broken().expect("the engine's own memory");
        let report = self.core.report.clone();
        let clock = Instant::now();
        let (origin, dt) = (self.time(), self.settings.dt);
        (self.memory.origin, self.memory.steps, self.settings.dt) = (origin, 0, 0.5 * h);
        let halves = self.step(0.5 * h).and_then(|_| self.step(0.5 * h));
        let error = {
            let states = (&whole.y[..], &self.memory.y[..]);
            crate::engine::state_error::state_difference(&self.model, None, states, Form::Velocities, h)
        };
        self.settings.dt = dt;
        self.memory = whole;
        self.energy = None;
        self.give_broken().expect("the engine's own memory");
        self.core.report = report;
        halves?;
        self.core.report.integrator.wall_seconds += clock.elapsed().as_secs_f64();
        self.core.report.step_error = Some(self.core.report.step_error.map_or(error, |e| e.max(error)));
        Ok(broken)
    }

    /// Makes the world's state (momenta) of the memory's.
    fn publish(&mut self) {
        self.model.to_momenta(&self.memory.y, &mut self.published);
    }

    /// The sizes a memory must fit.
    fn fit(&self) -> memory::Fit {
        let l = self.model.layout;
        let actors = l.actors();
        memory::Fit {
            dim: self.memory.y.len(),
            actors,
            all_actors: self.collider_set.as_ref().map_or(actors, |sc| sc.actors()),
            colliders: self.collider_set.as_ref().map_or(0, |sc| sc.colliders.len()),
            joints: self.model.joints.len(),
            keeps_pairs: keeps_pairs(self.collider_set.is_some(), &self.settings),
        }
    }
}

impl Engine for FastEngine {
    fn core(&self) -> &EngineCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut EngineCore {
        &mut self.core
    }

    fn model(&self) -> &Model {
        &self.model
    }

    fn tally_mut(&mut self) -> &mut Tally {
        &mut self.tally
    }

    fn time(&self) -> f64 {
        self.time_at(self.memory.steps)
    }

    fn state(&self) -> &[f64] {
        &self.published
    }

    fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        self.energy = None;
        self.model.to_velocities(y, &mut self.memory.y);
        self.published.copy_from_slice(y);
        (self.memory.origin, self.memory.steps) = (t, 0);
        Ok(())
    }

    /// The end of `span` from now in whole steps; a span that is not a whole number of steps (to 1e-6 of a step)
    /// is an error naming `name`.
    fn end_time(&self, span: f64, name: &'static str) -> Result<f64, WorldError> {
        let dt = self.settings.dt;
        let n = (span / dt).round();
        if (span / dt - n).abs() > 1e-6 || n < 1.0 {
            return Err(WorldError::invalid(
                name,
                format!("fast mode steps by dt = {dt} s, and {span} s is not a whole number of steps"),
            ));
        }
        if n > MAX_STEPS {
            return Err(WorldError::invalid(
                name,
                format!("{span} s is {n:e} steps of {dt} s, over the {MAX_STEPS:e} a call may take (split it into shorter calls)"),
            ));
        }
        Ok(self.time_at(self.memory.steps + n as u64))
    }

    fn counts_its_steps(&self) -> bool {
        true
    }

    /// Steps by dt until past `pause` (never beyond `t_end`); each step that reaches one or more of `saves`
    /// records one frame (its state, at its time).
    fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let h = self.settings.dt;
        let mut frames = FrameCursor::new(saves, t_end);
        loop {
            let t = self.time();
            if frames.pass_reached(t) > 0 {
                if let Some(run) = run.as_deref_mut() {
                    self.publish();
                    let contacts = self.last_contacts();
                    let contacts = contacts.iter().map(|c| (c.point, c.normal));
                    run.record(&self.model, t, &self.published, self.memory.penetration, contacts);
                }
            }
            if t >= pause.min(t_end) - frames.slack() {
                self.publish();
                return Ok(frames.delivered());
            }
            let broken = if self.settings.step_doubling { self.doubled_step(h)? } else { self.step(h)? };
            if let Some(run) = run.as_deref_mut() {
                run.log_step(self.time(), h);
                for k in broken {
                    run.break_joint(self.time(), k);
                }
            }
            budget.charge(1, self.time())?;
        }
    }

    fn own_stages(&self) -> Vec<Stage> {
        Self::planned(&self.settings, self.memory.y.len(), self.collider_set.is_some(), self.model.has_joints())
    }

    fn memory(&self) -> EngineMemory {
        EngineMemory::Fast(Box::new(self.memory.clone()))
    }

    /// The copy goes into the room of the last one (`FastMemory::clone_from`: a contact pair's manifold, shared and
    /// seldom changed, is not even counted again).
    fn checkpoint(&mut self) {
        match &mut self.checkpoint {
            Some(kept) => kept.clone_from(&self.memory),
            None => self.checkpoint = Some(self.memory.clone()),
        }
    }

    fn rollback(&mut self) -> Result<(), String> {
        let memory = self.checkpoint.take().ok_or("no checkpoint to go back to")?;
        self.set_memory(EngineMemory::Fast(Box::new(memory)))
    }

    fn set_memory(&mut self, memory: EngineMemory) -> Result<(), String> {
        match memory {
            EngineMemory::Fast(mut m) => {
                if m.broken.is_empty() {
                    m.broken = vec![false; self.model.joints.len()];
                }
                m.check(self.fit())?;
                if let (Some(kept), Some(collider_set)) = (m.pairs.as_mut(), &self.collider_set) {
                    kept.rebuild(collider_set.actors(), |a| collider_set.movable(a))?;
                }
                self.memory = *m;
                self.energy = None;
                self.publish();
                self.give_broken()
            }
            other => Err(format!("it is the memory of {}, which this world does not run", other.engine_name())),
        }
    }

    fn set_divergence_limit(&mut self, limit: f64) {
        self.core.divergence_limit = limit;
    }

    fn last_contacts(&self) -> Vec<LastContact> {
        match &self.memory.pairs {
            Some(kept) => kept.last_contacts(self.settings.dt),
            None => self.memory.last_contacts.clone(),
        }
    }

    fn set_material(&mut self, actor: usize, material: crate::Material) {
        if let Some(collider_set) = &mut self.collider_set {
            collider_set.set_material(actor, material);
        }
    }

    fn take_own_report(&mut self) -> WorldReport {
        std::mem::replace(&mut self.core.report, WorldReport::new(method_name(&self.settings)))
    }

    fn boxed_clone(&self) -> Box<dyn Engine> {
        Box::new(self.clone())
    }
}

/// Whether the engine keeps contact pairs across steps: the soft step does, where colliders can touch; the exact
/// solver computes every pair every step.
fn keeps_pairs(has_scene: bool, settings: &FastSettings) -> bool {
    has_scene && matches!(settings.solver, FastSolver::Soft(_))
}

/// The method name a fast-mode report carries.
fn method_name(settings: &FastSettings) -> &'static str {
    match settings.solver {
        FastSolver::Soft(_) => FAST_SOFT,
        FastSolver::Exact { .. } => FAST,
    }
}
