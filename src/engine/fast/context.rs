//! Fast mode's step context: the engine's parts, borrowed together for one step, that every stage works on (the
//! stages' files take it; the engine makes it, `FastEngine::context`, and the step runs them on it, `step.rs`).

use super::memory::FastMemory;
use crate::engine::collider_set::ColliderSet;
use crate::mode::FastSettings;
use crate::model::{Kinematics, Model, Tally};
use crate::report::WorldReport;

/// What a stage works on: the engine's parts for one step of `h` from time `t`.
pub(super) struct StepContext<'a> {
    pub model: &'a mut Model,
    pub collider_set: Option<&'a mut ColliderSet>,
    pub settings: &'a FastSettings,
    pub memory: &'a mut FastMemory,
    /// The rates of the step's force evaluation (scratch kept by the engine).
    pub dy: &'a mut Vec<f64>,
    /// The bodies' kinematics at the step's start, from its force evaluation (`applied_forces`).
    pub kin: Kinematics,
    /// What the equations of motion did, for the engine's report.
    pub tally: &'a mut Tally,
    /// The energy of the state where the last step ended (kept by the engine; none once the state was set).
    pub energy: &'a mut Option<f64>,
    pub report: &'a mut WorldReport,
    pub threads: usize,
    /// A state component past this is divergence.
    pub divergence_limit: f64,
    /// The step's start and end times.
    pub t: f64,
    pub t_next: f64,
}
