//! Engines: the ways of stepping a compiled world, behind one interface. `Smooth` integrates the equations of
//! motion under the integrator's control (no contact); `Accurate` adds the chapter's event-driven contact;
//! `Fast` time-steps contact at a fixed step. The world owns one engine, drives it with one run loop
//! (`world/stepping.rs`), and builds its plan from the engine's `stages()`. Engines never see the `World`.

#[cfg(feature = "contact")]
pub(crate) mod accurate;
mod budget;
#[cfg(feature = "contact")]
pub(crate) mod contact_scene;
#[cfg(feature = "contact")]
pub(crate) mod fast;
#[cfg(feature = "contact")]
mod manifold;
#[cfg(feature = "contact")]
mod manifold_cache;
#[cfg(feature = "contact")]
mod semi_implicit;
mod smooth;
#[cfg(feature = "contact")]
mod state_error;
#[cfg(feature = "contact")]
pub(crate) mod step_contacts;

pub(crate) use budget::Budget;
pub(crate) use smooth::SmoothEngine;

use crate::error::WorldError;
use crate::mode::Mode;
use crate::model::{Compiled, Model};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use tumble_integrate::Settings;

/// What an engine is built from, besides the compiled model and its state (without the `contact` feature only
/// the integrator's settings matter).
#[cfg_attr(not(feature = "contact"), allow(dead_code))]
pub(crate) struct EngineSpec {
    /// The contact mode and its settings.
    pub mode: Mode,
    /// The integrator's settings (smooth and accurate engines), with the divergence limit already set.
    pub settings: Settings,
    /// The colliders, when two of them can touch.
    #[cfg(feature = "contact")]
    pub scene: Option<contact_scene::ContactScene>,
    /// |g|, for the accurate engine's resting speed.
    pub gravity: f64,
    /// Threads for the contact solves (0: one per core).
    pub threads: usize,
}

/// One engine of a world (one lives per world, so the variants' sizes do not matter).
#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
pub(crate) enum Engine {
    Smooth(SmoothEngine),
    #[cfg(feature = "contact")]
    Accurate(accurate::AccurateEngine),
    #[cfg(feature = "contact")]
    Fast(fast::FastEngine),
}

/// Everything an engine must put back for a failed call to leave no trace: time, state, the integrator's next
/// step, and each engine's memory (resting set, lagged impulses, sleep).
#[derive(Clone)]
pub(crate) enum Snapshot {
    Smooth(Box<smooth::SmoothSnapshot>),
    #[cfg(feature = "contact")]
    Accurate(Box<accurate::AccurateSnapshot>),
    #[cfg(feature = "contact")]
    Fast(Box<fast::FastSnapshot>),
}

/// An engine's memory as a file holds it: fast mode's snapshot as it is; the integrating engines' with their
/// integrations as plain data (their factorizations are rebuilt when next needed, to the same bits). The variants
/// keep their order with or without the `contact` feature, so that the binary format does not depend on it.
#[allow(clippy::large_enum_variant)]
#[derive(serde::Serialize, serde::Deserialize, Clone)]
pub(crate) enum SavedMemory {
    Smooth(smooth::SavedSmooth),
    #[cfg(feature = "contact")]
    Accurate(Box<accurate::SavedAccurate>),
    #[cfg(feature = "contact")]
    Fast(Box<fast::FastSnapshot>),
}

impl SavedMemory {
    fn engine_name(&self) -> &'static str {
        match self {
            SavedMemory::Smooth(_) => "integration without contact",
            #[cfg(feature = "contact")]
            SavedMemory::Accurate(_) => "accurate mode's contact engine",
            #[cfg(feature = "contact")]
            SavedMemory::Fast(_) => "fast mode",
        }
    }
}

/// Whether the mode can solve the model's joints: fast mode's soft solver takes every kind and option; its exact
/// solver none; accurate mode holds them exactly (a softness is fast mode's) and needs its contact steps.
#[cfg(feature = "contact")]
fn check_joints(mode: &Mode, model: &Model) -> Result<(), WorldError> {
    if model.joints.is_empty() {
        return Ok(());
    }
    match mode {
        Mode::Fast(f) if matches!(f.solver, crate::mode::FastSolver::Exact { .. }) => Err(WorldError::invalid(
            "joint",
            "fast mode's exact solver has no joint rows: use solver=\"soft\" (the default) for joints",
        )),
        Mode::Fast(_) => Ok(()),
        Mode::Accurate(a) => {
            if a.persistent == crate::mode::Persistent::RestingForces {
                return Err(WorldError::invalid(
                    "joint",
                    "the chapter's resting forces know nothing of joints: use persistent contact steps (the default)",
                ));
            }
            if model.joints.iter().any(|cj| cj.joint.softness.is_some()) {
                return Err(WorldError::invalid(
                    "softness",
                    "a joint's softness applies to fast mode (accurate mode holds joints exactly)",
                ));
            }
            Ok(())
        }
    }
}

macro_rules! each {
    ($engine:expr, $e:ident => $body:expr) => {
        match $engine {
            Engine::Smooth($e) => $body,
            #[cfg(feature = "contact")]
            Engine::Accurate($e) => $body,
            #[cfg(feature = "contact")]
            Engine::Fast($e) => $body,
        }
    };
}

impl Engine {
    /// The engine for this mode and scene: fast mode's time stepping, accurate contact when colliders can touch,
    /// else smooth integration.
    pub fn build(spec: EngineSpec, compiled: Compiled, t: f64, y: Vec<f64>) -> Result<Engine, WorldError> {
        #[cfg(feature = "contact")]
        {
            let EngineSpec { mode, settings, scene, gravity, threads } = spec;
            let mut compiled = compiled;
            check_joints(&mode, &compiled.model)?;
            compiled.model.joints_in_rhs = !matches!(mode, Mode::Fast(_));
            match (mode, scene) {
                (Mode::Fast(fast), scene) => {
                    let limit = settings.divergence_limit;
                    Ok(Engine::Fast(fast::FastEngine::new(compiled, scene, t, y, fast, threads, limit)))
                }
                (Mode::Accurate(acc), Some(scene)) => Ok(Engine::Accurate(accurate::AccurateEngine::new(
                    compiled, scene, settings, acc, gravity, threads, t, y,
                )?)),
                (Mode::Accurate(_), None) => Ok(Engine::Smooth(SmoothEngine::new(compiled, settings, t, y)?)),
            }
        }
        #[cfg(not(feature = "contact"))]
        {
            Ok(Engine::Smooth(SmoothEngine::new(compiled, spec.settings, t, y)?))
        }
    }

    /// The stages this engine would run for `model`: the model's terms, then the engine's own. `plan()` and
    /// `stages()` both come from here.
    pub fn planned(mode: &Mode, model: &Model, settings: &Settings, has_scene: bool) -> Vec<Stage> {
        let mut stages = model.stages();
        let dim = model.layout.dim();
        match mode {
            #[cfg(feature = "contact")]
            Mode::Fast(f) => stages.extend(fast::FastEngine::planned(f, dim, has_scene, model.has_joints())),
            #[cfg(feature = "contact")]
            Mode::Accurate(a) if has_scene => stages.extend(accurate::AccurateEngine::planned(settings, a, dim)),
            _ => stages.extend(SmoothEngine::planned(settings, dim)),
        }
        let _ = has_scene;
        stages
    }

    /// The stages this engine runs: its model's terms, then its own.
    pub fn stages(&self) -> Vec<Stage> {
        let mut stages = self.compiled().model.stages();
        stages.extend(each!(self, e => e.own_stages()));
        stages
    }

    /// The compiled model and the handles of its rows.
    pub fn compiled(&self) -> &Compiled {
        each!(self, e => e.compiled())
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        each!(self, e => e.time())
    }

    /// Current state.
    pub fn state(&self) -> &[f64] {
        each!(self, e => e.state())
    }

    /// Replaces time and state (the user moved something); the engine's memory of contacts is kept.
    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        each!(self, e => e.set_state(t, y))
    }

    /// The end time of an advance by `span` from now: now + span, or for fast mode the end of a whole number of
    /// steps (an error naming `name` if `span` is not one).
    pub fn end_time(&self, span: f64, name: &'static str) -> Result<f64, WorldError> {
        match self {
            #[cfg(feature = "contact")]
            Engine::Fast(e) => e.end_time(span, name),
            _ => {
                let _ = name;
                Ok(self.time() + span)
            }
        }
    }

    /// Advances toward `t_end`, returning once past `pause` (never beyond `t_end`); records into `run` (if any)
    /// a frame for each of `saves` reached, the steps taken and the contact events; returns how many saves were
    /// delivered. The steps are charged to the call's `budget` (fast mode's calls are bounded by their step count;
    /// its budget only carries the call's control). A failure may leave the engine anywhere: the caller restores a
    /// snapshot.
    pub fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        match self {
            Engine::Smooth(e) => e.advance(t_end, pause, saves, run, budget),
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => e.advance(t_end, pause, saves, run, budget),
            #[cfg(feature = "contact")]
            Engine::Fast(e) => e.advance(t_end, pause, saves, run, budget),
        }
    }

    /// Whether the engine bounds a call by its step count up front (fast mode), so that the call's budget only
    /// carries its control.
    pub fn counts_its_steps(&self) -> bool {
        #[cfg(feature = "contact")]
        return matches!(self, Engine::Fast(_));
        #[cfg(not(feature = "contact"))]
        false
    }

    /// The contacts of the last step (fast mode) or contact step (accurate mode, while bodies touch).
    #[cfg(feature = "contact")]
    pub fn last_contacts(&self) -> &[step_contacts::StepContact] {
        match self {
            Engine::Smooth(_) => &[],
            Engine::Accurate(e) => e.last_contacts(),
            Engine::Fast(e) => e.last_contacts(),
        }
    }

    /// Sets the contact solves' thread count (their answers do not depend on it, so the engine keeps its memory).
    #[cfg_attr(not(feature = "contact"), allow(unused_variables))]
    pub fn set_threads(&mut self, threads: usize) {
        match self {
            Engine::Smooth(_) => {}
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => e.contacts.threads = threads,
            #[cfg(feature = "contact")]
            Engine::Fast(e) => e.threads = threads,
        }
    }

    /// The size past which a state component is divergence, set where the engine was built (from the state's scale
    /// there): a copy or a loaded world keeps the original's.
    pub fn divergence_limit(&self) -> f64 {
        match self {
            Engine::Smooth(e) => e.divergence_limit(),
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => e.divergence_limit(),
            #[cfg(feature = "contact")]
            Engine::Fast(e) => e.divergence_limit,
        }
    }

    /// Sets the divergence limit everywhere the engine keeps it (before its memory is given back).
    pub fn set_divergence_limit(&mut self, limit: f64) {
        match self {
            Engine::Smooth(e) => e.set_divergence_limit(limit),
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => e.set_divergence_limit(limit),
            #[cfg(feature = "contact")]
            Engine::Fast(e) => e.divergence_limit = limit,
        }
    }

    /// The engine's memory as a file holds it (`saved_memory` in `persist`).
    pub fn saved(&self) -> SavedMemory {
        match self {
            Engine::Smooth(e) => SavedMemory::Smooth(e.saved()),
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => SavedMemory::Accurate(Box::new(e.saved())),
            #[cfg(feature = "contact")]
            Engine::Fast(e) => SavedMemory::Fast(Box::new(e.snapshot())),
        }
    }

    /// Checks a memory read from a file against this engine and gives it back; on an error nothing changes.
    pub fn restore_saved(&mut self, memory: SavedMemory) -> Result<(), String> {
        match (self, memory) {
            (Engine::Smooth(e), SavedMemory::Smooth(m)) => e.restore_saved(m),
            #[cfg(feature = "contact")]
            (Engine::Accurate(e), SavedMemory::Accurate(m)) => e.restore_saved(*m),
            #[cfg(feature = "contact")]
            (Engine::Fast(e), SavedMemory::Fast(m)) => e.restore_saved(*m),
            #[allow(unreachable_patterns)]
            (_, memory) => Err(format!("it is the memory of {}, which this world does not run", memory.engine_name())),
        }
    }

    /// What a failed call must put back.
    pub fn snapshot(&self) -> Snapshot {
        match self {
            Engine::Smooth(e) => Snapshot::Smooth(Box::new(e.snapshot())),
            #[cfg(feature = "contact")]
            Engine::Accurate(e) => Snapshot::Accurate(Box::new(e.snapshot())),
            #[cfg(feature = "contact")]
            Engine::Fast(e) => Snapshot::Fast(Box::new(e.snapshot())),
        }
    }

    /// Puts a snapshot of this engine back.
    pub fn restore(&mut self, snapshot: Snapshot) -> Result<(), WorldError> {
        match (self, snapshot) {
            (Engine::Smooth(e), Snapshot::Smooth(s)) => e.restore(*s),
            #[cfg(feature = "contact")]
            (Engine::Accurate(e), Snapshot::Accurate(s)) => e.restore(*s),
            #[cfg(feature = "contact")]
            (Engine::Fast(e), Snapshot::Fast(s)) => e.restore(*s),
            #[cfg(feature = "contact")]
            _ => unreachable!("a snapshot is restored into the engine it came from"),
        }
    }

    /// What the engine's work since the last call cost (integrator, force loops, contact, stages), reset to zero.
    pub fn take_report(&mut self) -> WorldReport {
        let mut r = each!(self, e => e.take_report());
        let model = each!(self, e => e.model_mut());
        r.forces = std::mem::take(&mut model.counters);
        r.stages += std::mem::take(&mut model.stage_runs);
        r
    }
}
