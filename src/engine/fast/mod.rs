//! Fast mode: time stepping at a fixed step. One step is a list of stages, one file each: the applied forces at
//! the step's start (`applied_forces.rs`), contacts found with a margin (`find_contacts.rs`), the contact solve:
//! either the soft step, which gives velocities and poses from its substeps (`soft_solve.rs`, the default), or the
//! exact solver's velocities from one conic program per island (`solve_velocities.rs`, with `warm_start.rs` and
//! `bounce_limiter.rs`) and positions from them (`integrate_positions.rs`); then sleep (`sleep.rs`) and the report.
//! The engine always steps by its `dt`: an advance ends at a whole number of steps, and frames are the states at the
//! steps that reach them.

mod applied_forces;
mod bounce_limiter;
mod find_contacts;
mod integrate_positions;
mod sleep;
mod soft_solve;
mod solve_velocities;
mod warm_start;

use crate::engine::contact_scene::{ContactKey, ContactScene};
use crate::engine::step_contacts::StepContact;
use crate::engine::Budget;
use crate::error::WorldError;
use crate::mode::{FastSettings, FastSolver};
use crate::model::{Compiled, Model};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use sleep::Sleep;
use std::collections::BTreeMap;
use std::time::Instant;
use tumble_integrate::OdeError;

/// The method name fast mode reports.
pub(crate) const FAST: &str = "fast (semi-implicit Euler, contact by conic program)";
/// ... with the soft step.
pub(crate) const FAST_SOFT: &str = "fast (semi-implicit Euler substeps, soft contact)";

/// Most steps one advance may take (a step budget: a huge span or a tiny step is an error, not a hang).
const MAX_STEPS: f64 = 1e7;

/// The state and memory of a fast-mode world.
#[derive(Clone)]
pub(crate) struct FastEngine {
    compiled: Compiled,
    scene: Option<ContactScene>,
    /// Time = origin + steps x dt, so that times are exact multiples of the step from where the engine started.
    origin: f64,
    steps: u64,
    y: Vec<f64>,
    settings: FastSettings,
    pub(crate) threads: usize,
    /// A state component larger than this is divergence: the step fails instead of running on to overflow.
    pub(crate) divergence_limit: f64,
    /// Each contact's normal impulse of the last step (ordered: the warm start sums them in key order).
    previous: BTreeMap<ContactKey, f64>,
    /// The soft solver's impulses of the last step, by contact (sorted by key).
    warm: Vec<(ContactKey, tumble_contact::SoftImpulse)>,
    /// Each joint's row impulses of the last step.
    joint_warm: Vec<tumble_contact::JointImpulse>,
    sleep: Sleep,
    dy: Vec<f64>,
    /// What the steps since the last `take_report` cost.
    report: WorldReport,
    /// Largest penetration among the contacts of the last step.
    penetration: f64,
    /// The contacts of the last step, with their impulses.
    last_contacts: Vec<StepContact>,
}

/// What a failed call puts back: time, state, lagged impulses, warm starts, sleep, kept manifolds.
#[derive(serde::Serialize, serde::Deserialize, Clone)]
pub(crate) struct FastSnapshot {
    origin: f64,
    steps: u64,
    y: Vec<f64>,
    previous: BTreeMap<ContactKey, f64>,
    warm: Vec<(ContactKey, tumble_contact::SoftImpulse)>,
    joint_warm: Vec<tumble_contact::JointImpulse>,
    sleep: Sleep,
    penetration: f64,
    manifolds: Option<crate::engine::manifold_cache::ManifoldCache>,
    last_contacts: Vec<StepContact>,
}

pub(crate) fn failure(t: f64, message: String) -> WorldError {
    WorldError::Simulation(OdeError::System { t, message })
}

impl FastEngine {
    pub fn new(
        compiled: Compiled,
        scene: Option<ContactScene>,
        t: f64,
        y: Vec<f64>,
        settings: FastSettings,
        threads: usize,
        divergence_limit: f64,
    ) -> Self {
        let actors = compiled.model.layout.particles + compiled.model.layout.bodies;
        let joints = compiled.model.joints.len();
        let mut scene = scene;
        if let (Some(scene), FastSolver::Soft(_)) = (scene.as_mut(), settings.solver) {
            // the soft step reuses the manifolds of pairs that barely moved; the exact solver computes every one
            scene.cache = Some(Default::default());
        }
        FastEngine {
            dy: vec![0.0; y.len()],
            sleep: Sleep::new(actors),
            compiled,
            scene,
            origin: t,
            steps: 0,
            y,
            settings,
            threads,
            divergence_limit,
            previous: BTreeMap::new(),
            warm: Vec::new(),
            joint_warm: vec![Default::default(); joints],
            report: WorldReport::new(method_name(&settings)),
            penetration: 0.0,
            last_contacts: Vec::new(),
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
            // jointed bodies do not sleep (`sleep.rs`)
            if settings.sleep && !joints {
                out.push(Stage::Sleeping);
            }
        }
        if dim > 0 {
            out.push(Stage::Integrate);
        }
        out
    }

    pub fn own_stages(&self) -> Vec<Stage> {
        Self::planned(&self.settings, self.y.len(), self.scene.is_some(), self.compiled.model.has_joints())
    }

    pub fn compiled(&self) -> &Compiled {
        &self.compiled
    }

    pub fn model_mut(&mut self) -> &mut Model {
        &mut self.compiled.model
    }

    pub fn time(&self) -> f64 {
        self.time_at(self.steps)
    }

    fn time_at(&self, steps: u64) -> f64 {
        self.origin + steps as f64 * self.settings.dt
    }

    pub fn state(&self) -> &[f64] {
        &self.y
    }

    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        self.y.copy_from_slice(y);
        (self.origin, self.steps) = (t, 0);
        Ok(())
    }

    /// The end of `span` from now in whole steps; a span that is not a whole number of steps (to 1e-6 of a step)
    /// is an error naming `name`.
    pub fn end_time(&self, span: f64, name: &'static str) -> Result<f64, WorldError> {
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
        Ok(self.time_at(self.steps + n as u64))
    }

    /// Steps by dt until past `pause` (never beyond `t_end`); each step that reaches one or more of `saves`
    /// records one frame (its state, at its time).
    pub fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let h = self.settings.dt;
        let slack = 1e-9 * h;
        let mut delivered = 0;
        loop {
            let t = self.time();
            let reached = saves[delivered..].iter().take_while(|&&s| s <= t + slack).count();
            if reached > 0 {
                delivered += reached;
                if let Some(run) = run.as_deref_mut() {
                    let contacts = self.last_contacts.iter().map(|c| (c.point, c.normal));
                    run.record(&self.compiled.model, t, &self.y, self.penetration, contacts);
                }
            }
            if t >= pause.min(t_end) - slack {
                return Ok(delivered);
            }
            if self.settings.step_doubling {
                self.doubled_step(h)?;
            } else {
                self.step(h)?;
            }
            if let Some(run) = run.as_deref_mut() {
                run.log_step(self.time(), h);
            }
            budget.charge(1, self.time())?;
        }
    }

    /// One step of size h, as its stages.
    fn step(&mut self, h: f64) -> Result<(), WorldError> {
        let clock = Instant::now();
        let before = self.energy();
        let mut states = self.applied_forces()?;
        let found = self.find_contacts(&mut states, h)?;
        let velocities = match self.settings.solver {
            FastSolver::Soft(soft) => {
                let out = self.soft_solve(&states, &found, h, soft)?;
                self.apply_moves(&out);
                out.velocities
            }
            FastSolver::Exact { .. } => {
                let velocities = self.solve_velocities(&states, &found, h)?;
                self.integrate_positions(&velocities, h);
                velocities
            }
        };
        self.check_state(h)?;
        let model = &self.compiled.model;
        if !model.joints.is_empty() {
            let (rows, errors) = model.joint_errors(&self.y);
            self.report.book_joints(rows, errors);
        }
        self.update_sleep(&states, &velocities, &found, h);
        self.steps += 1;
        let change = self.energy() - before;
        self.report.energy_change += change;
        self.report.energy_gain = Some(self.report.energy_gain.unwrap_or(0.0).max(change));
        self.book_step(h, clock);
        Ok(())
    }

    /// The mechanical energy of the state (kinetic, gravity's and the springs' potential; J).
    fn energy(&self) -> f64 {
        let model = &self.compiled.model;
        model.kinetic_energy(&self.y) + model.potential_energy(&self.y)
    }

    /// A step of h, and its error estimate: the same step taken as two halves from the same start (time, state,
    /// warm starts and sleep as they were), their difference booked in the report; the world goes on from the
    /// whole step, as without the estimate, and the report keeps the whole step's counters (the halves' time is
    /// added to its wall time).
    fn doubled_step(&mut self, h: f64) -> Result<(), WorldError> {
        let start = self.snapshot();
        self.step(h)?;
        let whole = self.snapshot();
        let report = self.report.clone();
        let clock = Instant::now();
        self.restore(start)?;
        let (origin, dt) = (self.time(), self.settings.dt);
        (self.origin, self.steps, self.settings.dt) = (origin, 0, 0.5 * h);
        let halves = self.step(0.5 * h).and_then(|_| self.step(0.5 * h));
        let error = crate::engine::state_error::state_difference(&self.compiled.model, None, &whole.y, &self.y, h);
        self.settings.dt = dt;
        self.restore(whole)?;
        self.report = report;
        halves?;
        self.report.integrator.wall_seconds += clock.elapsed().as_secs_f64();
        self.report.step_error = Some(self.report.step_error.map_or(error, |e| e.max(error)));
        Ok(())
    }

    /// Fails the step if the new state is not finite or has diverged past the limit (one comparison a component;
    /// NaN fails it too).
    fn check_state(&self, h: f64) -> Result<(), WorldError> {
        let limit = self.divergence_limit;
        if self.y.iter().all(|v| v.abs() <= limit) {
            return Ok(());
        }
        let t = self.time_at(self.steps + 1);
        let error = match self.y.iter().position(|v| !v.is_finite()) {
            Some(index) => OdeError::NonFinite { t, what: "state", index },
            None => OdeError::Divergence { t, norm: self.y.iter().fold(0.0, |m, v| m.max(v.abs())), limit, h },
        };
        Err(WorldError::Simulation(error))
    }

    /// The report's share of a step.
    fn book_step(&mut self, h: f64, clock: Instant) {
        self.report.sleepers = self.sleep.count();
        self.report.max_penetration = self.report.max_penetration.max(self.penetration);
        self.report.stages.mark(Stage::Integrate);
        let r = &mut self.report.integrator;
        r.steps += 1;
        r.rhs_evals += 1;
        r.min_step = r.min_step.min(h);
        r.max_step = r.max_step.max(h);
        r.wall_seconds += clock.elapsed().as_secs_f64();
    }

    pub fn snapshot(&self) -> FastSnapshot {
        FastSnapshot {
            origin: self.origin,
            steps: self.steps,
            y: self.y.clone(),
            previous: self.previous.clone(),
            warm: self.warm.clone(),
            joint_warm: self.joint_warm.clone(),
            sleep: self.sleep.clone(),
            penetration: self.penetration,
            manifolds: self.scene.as_ref().and_then(|s| s.cache.clone()),
            last_contacts: self.last_contacts.clone(),
        }
    }

    /// Whether a memory read from a file fits this engine (sizes and indices in range, the state finite): a file's
    /// memory is checked before it is restored, so that a damaged one is an error, never a panic later.
    fn check_memory(&self, s: &FastSnapshot) -> Result<(), String> {
        let actors = self.compiled.model.layout.particles + self.compiled.model.layout.bodies;
        let colliders = self.scene.as_ref().map_or(0, |sc| sc.colliders.len());
        let all_actors = self.scene.as_ref().map_or(actors, |sc| sc.actors());
        let keys_fit = |k: &ContactKey| (k.colliders.0 as usize) < colliders && (k.colliders.1 as usize) < colliders;
        let checks = [
            (s.y.len() == self.y.len(), "its state has another length"),
            (s.y.iter().all(|v| v.is_finite()) && s.origin.is_finite(), "its state is not finite"),
            (s.sleep.fits(actors), "its sleep does not fit the actors"),
            (s.previous.keys().all(keys_fit) && s.warm.iter().all(|(k, _)| keys_fit(k)), "a contact names no collider"),
            (s.warm.windows(2).all(|w| w[0].0 < w[1].0), "its warm starts are out of order"),
            (s.joint_warm.len() == self.joint_warm.len(), "its joints are not the scene's"),
            (s.joint_warm.iter().all(|j| j.0.iter().all(|p| p.is_finite())), "a joint's impulse is not finite"),
            (s.manifolds.as_ref().is_none_or(|m| m.fits(colliders)), "its kept manifolds do not fit the colliders"),
            (s.last_contacts.iter().all(|c| c.a < all_actors && c.b < all_actors), "a contact names no actor"),
        ];
        match checks.iter().find(|(ok, _)| !ok) {
            Some((_, why)) => Err(why.to_string()),
            None => Ok(()),
        }
    }

    pub fn restore(&mut self, s: FastSnapshot) -> Result<(), WorldError> {
        (self.origin, self.steps, self.y, self.previous, self.warm, self.sleep, self.penetration) =
            (s.origin, s.steps, s.y, s.previous, s.warm, s.sleep, s.penetration);
        self.last_contacts = s.last_contacts;
        self.joint_warm = s.joint_warm;
        if let Some(scene) = self.scene.as_mut() {
            scene.cache = s.manifolds;
        }
        Ok(())
    }

    /// Gives back a memory read from a file, checked against the scene first; on an error nothing changes.
    pub fn restore_saved(&mut self, s: FastSnapshot) -> Result<(), String> {
        self.check_memory(&s)?;
        self.restore(s).map_err(|err| err.to_string())
    }

    pub fn take_report(&mut self) -> WorldReport {
        std::mem::replace(&mut self.report, WorldReport::new(method_name(&self.settings)))
    }

    /// The contacts of the last step, with their impulses.
    pub fn last_contacts(&self) -> &[StepContact] {
        &self.last_contacts
    }
}

/// The method name a fast-mode report carries.
fn method_name(settings: &FastSettings) -> &'static str {
    match settings.solver {
        FastSolver::Soft(_) => FAST_SOFT,
        FastSolver::Exact { .. } => FAST,
    }
}
