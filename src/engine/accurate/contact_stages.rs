//! Accurate mode's contact side during an advance: the colliders and the settings its stages work from
//! (`ContactRules`, made with the engine, with their scratch counters), and the context a stage works on
//! (`ContactStages`: the rules, the contact memory, the broken joints, the engine's report, the thread count and the divergence
//! limit, borrowed together for one advance).

use super::contact_memory::{ContactMemory, ContactScales};
use crate::engine::collider_set::ColliderSet;
use crate::mode::AccurateSettings;
use crate::model::breaking::JointLoad;
use crate::report::WorldReport;
use std::collections::BTreeSet;
use tumble_contact::SolverSettings;
use tumble_integrate::{Report, Settings};

/// The colliders and the settings the contact stages work from, with their scratch counters.
#[derive(Clone)]
pub(crate) struct ContactRules {
    pub collider_set: ColliderSet,
    pub settings: AccurateSettings,
    /// clarabel's settings for impulses, resting forces and position corrections.
    pub solver: SolverSettings,
    /// |g| (m/s^2), for the first contact step.
    pub gravity: f64,
    /// The integrator's settings, for the actors that fly free while others touch (`free_flight.rs`).
    pub free_settings: Settings,
    /// Why clarabel last failed to answer a contact step (for the message if steps shrink to nothing).
    pub last_solver_error: String,
    /// The contact steps' convex solves weighted by island size (`VelocityStep::solver_work`), charged to budgets.
    pub solve_work: usize,
    /// The counters of the free flights since the last report.
    pub free_report: Report,
}

impl ContactRules {
    /// The rules of `scene` and the contact memory of a world starting at (t, y).
    pub fn new(
        collider_set: ColliderSet,
        settings: AccurateSettings,
        integration: &Settings,
        gravity: f64,
        t: f64,
        y: &[f64],
    ) -> (ContactRules, ContactMemory) {
        let scales = ContactScales::new(&settings, collider_set.size(y), gravity);
        let memory = ContactMemory {
            resting: None,
            resting_keys: BTreeSet::new(),
            penetration: 0.0,
            window: (t, 0),
            touching: None,
            scales,
        };
        let rules = ContactRules {
            collider_set,
            settings,
            solver: SolverSettings::default(),
            gravity,
            free_settings: integration.clone(),
            last_solver_error: String::new(),
            solve_work: 0,
            free_report: Report::empty(integration.method.name()),
        };
        (rules, memory)
    }

    /// The view the stages of one advance work through.
    pub fn stages<'a>(
        &'a mut self,
        memory: &'a mut ContactMemory,
        broken: &'a mut [bool],
        averages: &'a mut Vec<JointLoad>,
        report: &'a mut WorldReport,
        threads: usize,
        divergence_limit: f64,
    ) -> ContactStages<'a> {
        ContactStages {
            collider_set: &mut self.collider_set,
            settings: &self.settings,
            solver: &self.solver,
            gravity: self.gravity,
            free_settings: &self.free_settings,
            last_solver_error: &mut self.last_solver_error,
            solve_work: &mut self.solve_work,
            free_report: &mut self.free_report,
            memory,
            broken,
            averages,
            report,
            threads,
            divergence_limit,
        }
    }
}

/// What a contact stage works on during an advance: the colliders and settings, the contact memory, the engine's
/// report, the thread count and the divergence limit.
pub(crate) struct ContactStages<'a> {
    pub collider_set: &'a mut ColliderSet,
    pub settings: &'a AccurateSettings,
    pub solver: &'a SolverSettings,
    pub gravity: f64,
    pub free_settings: &'a Settings,
    pub last_solver_error: &'a mut String,
    pub solve_work: &'a mut usize,
    pub free_report: &'a mut Report,
    pub memory: &'a mut ContactMemory,
    /// The engine memory's broken joints (`breaking.rs`).
    pub broken: &'a mut [bool],
    /// The engine memory's averaged joint loads (`breaking.rs`).
    pub averages: &'a mut Vec<JointLoad>,
    pub report: &'a mut WorldReport,
    pub threads: usize,
    pub divergence_limit: f64,
}
