//! The interface every engine implements (`Engine`): what the world's run loop, its state, its files and its plan
//! ask of the engine that steps its compiled model. An engine is accurate mode's (`accurate/`) or fast mode's
//! (`fast/`); the world holds one behind this trait and never sees which.

use super::budget::Budget;
use super::core::EngineCore;
use super::memory::EngineMemory;
use crate::error::WorldError;
use crate::model::{Model, StateHandles, Tally};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;

/// A way of stepping a compiled world. The run loop calls `advance` between a `memory()` taken at the start of a
/// call and a `set_memory` of it if the call fails.
pub(crate) trait Engine: Send {
    /// What every engine holds.
    fn core(&self) -> &EngineCore;
    fn core_mut(&mut self) -> &mut EngineCore;

    /// The compiled model.
    fn model(&self) -> &Model;
    /// What the equations of motion did since the report was last taken.
    fn tally_mut(&mut self) -> &mut Tally;

    /// Current time.
    fn time(&self) -> f64;

    /// Current state.
    fn state(&self) -> &[f64];

    /// Replaces time and state (the user moved something); the engine's memory of contacts is kept.
    fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError>;

    /// The end time of an advance by `span` from now (an error naming `name` if the engine cannot end there).
    fn end_time(&self, span: f64, name: &'static str) -> Result<f64, WorldError> {
        let _ = name;
        Ok(self.time() + span)
    }

    /// Whether the engine bounds a call by its step count up front (fast mode), so that the call's budget only
    /// carries its control.
    fn counts_its_steps(&self) -> bool {
        false
    }

    /// Advances toward `t_end`, returning once past `pause` (never beyond `t_end`); records into `run` (if any) a
    /// frame for each of `saves` reached, the steps taken and the contact events; returns how many saves were
    /// delivered. The steps are charged to the call's `budget`. A failure may leave the engine anywhere: the caller
    /// gives back the memory it took before.
    fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError>;

    /// The engine's own stages (after the model's terms).
    fn own_stages(&self) -> Vec<Stage>;

    /// Everything the engine carries from one call to the next.
    fn memory(&self) -> EngineMemory;

    /// Keeps a copy of its memory, for `rollback` (the run loop's at the start of a call; an engine may reuse the
    /// room of the copy it kept last).
    fn checkpoint(&mut self);

    /// Gives back the memory of the last `checkpoint` (a call failed); an error only for an engine fault.
    fn rollback(&mut self) -> Result<(), String>;

    /// Gives back a memory taken from an engine of the same structure (a snapshot, or read from a file), checked
    /// against this engine first; on an error nothing changes.
    fn set_memory(&mut self, memory: EngineMemory) -> Result<(), String>;

    /// Sets the divergence limit everywhere the engine keeps it (before its memory is given back).
    fn set_divergence_limit(&mut self, limit: f64);

    /// The contacts of the last step (fast mode) or contact step (accurate mode, while bodies touch).
    fn last_contacts(&self) -> Vec<super::last_contacts::LastContact> {
        Vec::new()
    }

    /// Gives every collider of the actor whose row among particles and dynamic and static bodies is `actor` its
    /// material (a world's `set_material`, between steps); the memory is kept.
    fn set_material(&mut self, actor: usize, material: crate::Material);

    /// What the engine's own work since the last call cost, reset to zero (the model's counters are added by
    /// `take_report`).
    fn take_own_report(&mut self) -> WorldReport;

    /// A copy of the engine.
    fn boxed_clone(&self) -> Box<dyn Engine>;
}

impl Clone for Box<dyn Engine> {
    fn clone(&self) -> Self {
        self.boxed_clone()
    }
}

impl dyn Engine {
    /// The stages this engine runs: its model's terms, then its own.
    pub fn stages(&self) -> Vec<Stage> {
        let mut stages = self.model().stages();
        stages.extend(self.own_stages());
        stages
    }

    /// The state's handles: which particle and body each index is.
    pub fn handles(&self) -> &StateHandles {
        &self.core().handles
    }

    /// The size past which a state component is divergence, set where the engine was built.
    pub fn divergence_limit(&self) -> f64 {
        self.core().divergence_limit
    }

    /// Sets the contact solves' thread count (their answers do not depend on it, so the engine keeps its memory).
    pub fn set_threads(&mut self, threads: usize) {
        self.core_mut().threads = threads;
    }

    /// What the engine's work since the last call cost (its own, the force loops, the stages), reset to zero.
    pub fn take_report(&mut self) -> WorldReport {
        let mut r = self.take_own_report();
        let tally = std::mem::take(self.tally_mut());
        r.forces = tally.forces;
        r.stages += tally.stages;
        r
    }
}
