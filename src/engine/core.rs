//! What every engine holds besides its model and memory: its state's handles (which particle and body each index
//! is), the divergence limit set where it was built, the contact solves' thread count, and the report of its work
//! since the report was last taken.

use crate::model::StateHandles;
use crate::report::WorldReport;

/// The part every engine has.
#[derive(Clone)]
pub(crate) struct EngineCore {
    pub handles: StateHandles,
    /// A state component larger than this is divergence: the step fails instead of running on to overflow.
    pub divergence_limit: f64,
    /// Threads for the contact solves (0: one per core); the answers do not depend on it.
    pub threads: usize,
    /// What the engine's steps since the last report cost (accurate mode: its contact stages' counters).
    pub report: WorldReport,
}

impl EngineCore {
    pub fn new(handles: StateHandles, divergence_limit: f64, threads: usize, report: WorldReport) -> Self {
        EngineCore { handles, divergence_limit, threads, report }
    }
}
