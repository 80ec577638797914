//! Accurate mode: the chapter's scheme for free flight and impacts, error-controlled convex steps while bodies touch.
//!
//! Free motion is carried by the integrator under its error control; after every accepted step the contacts are
//! checked (`detect.rs`); a collision inside the step is located by bisection on the step's dense output
//! (`collision_time.rs`), a pass through a thin body by a distance-bounded search (`pass_through.rs`); the step is
//! cut at the event. At each event the contact phase (`contact_phase.rs`) looks at the contacts that close or
//! touch. Frictionless collisions get Newton's impulses at the located time (so a bouncing ball's apexes stay
//! exact); when a contact has friction, or contacts stay touching after the impulses, the world enters the
//! touching phase (`touching.rs`): contact steps (`contact_step.rs`: semi-implicit Euler, every contact and its
//! Coulomb friction one convex program per island, so a step always has an answer) whose size comes from an
//! error estimate by step doubling, after Drake's CENIC. Impacts during that phase are contacts of the convex
//! program with Newton's restitution as their bound, located in time by the error control. When no pair is within
//! reach of a step, the integrator takes over again. Why the split: the integrator's order carries free flight
//! and exact bisection-located bounces cheaply, while the touching phase cannot cascade (no event ends a step
//! there: a rocking corner, a settling stack or a Zeno bounce is a sequence of convex steps) and brings friction.
//!
//! With `Persistent::RestingForces` the chapter's own resting contact is used instead: contacts that stay touching
//! get frictionless QP forces inside the right-hand side (`resting.rs`), with drift caught as an event
//! (`drift.rs`).
//!
//! The advance reads as: contact phase; then repeatedly either take contact steps while touching, or integrate
//! until an event, record it, contact phase.

mod collision_time;
mod contact_phase;
mod contact_step;
mod detect;
mod drift;
mod free_flight;
mod pass_through;
mod resting;
mod saved;
mod touching;

pub(crate) use resting::RestingSet;
pub(crate) use saved::SavedAccurate;

use crate::engine::contact_scene::{ContactKey, ContactScene};
use crate::engine::smooth::{attempts, mechanical_energy, over_budget, take_integrator_report};
use crate::engine::Budget;
use crate::error::WorldError;
use crate::mode::{AccurateSettings, Persistent};
use crate::model::{Compiled, Model};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use std::collections::BTreeSet;
use tumble_contact::SolverSettings;
use tumble_integrate::{Integrator, OdeError, Settings};

/// Events at one time without progress before the advance gives up (a contact phase that cannot settle).
const STUCK: usize = 200;
/// Accepted steps over which the mean step is watched: below the stall step, the advance gives up (contact forces
/// the method cannot follow: a light body under one a million times heavier took steps of 5e-9 to 5e-7 s, 15 s of
/// work per simulated millisecond).
const STALL: usize = 2_000;

/// The contact side of an accurate-mode engine: what it knows between steps.
#[derive(Clone)]
pub(crate) struct Contacts {
    pub scene: ContactScene,
    settings: AccurateSettings,
    /// Relative normal speed below which contacts rest (resolved from the settings or the scene's size).
    pub resting_speed: f64,
    /// The contacts resting since the last contact phase (ordered: no hashing reaches the answers).
    resting_keys: BTreeSet<ContactKey>,
    solver: SolverSettings,
    /// Contact counters since the last report.
    pub report: WorldReport,
    /// Largest penetration found at the last contact phase.
    pub penetration: f64,
    /// A mean step below this over `STALL` steps is a stall: 1e-5 of the scene's time scale sqrt(size / g), at most
    /// 1e-5 s.
    pub(crate) stall_step: f64,
    /// The current window: its start time and the accepted steps in it.
    window: (f64, usize),
    /// Error allowed in one contact step (m).
    tolerance: f64,
    /// |g| (m/s^2), for the first contact step.
    gravity: f64,
    /// Largest contact step: 1/20 of the scene's time scale sqrt(size / g), at most 1/60 s.
    max_step: f64,
    /// The touching phase, while bodies touch.
    touching: Option<touching::Touching>,
    /// Threads of the contact solves.
    pub(crate) threads: usize,
    /// A state component past this is divergence.
    divergence_limit: f64,
    /// The lagged-friction fixed point is reached when no normal impulse moves by more than this fraction of the
    /// largest: ten times the tolerance relative to the scene's size, within 1e-9 to 1e-3 (a friction bound off
    /// by this fraction is a deceleration off by as much, so a tight tolerance needs a tight fixed point).
    lagged_tolerance: f64,
    /// Why clarabel last failed to answer a contact step (for the message if steps shrink to nothing).
    last_solver_error: String,
    /// The contact steps' convex solves weighted by island size (`VelocityStep::solver_work`), charged to budgets.
    solve_work: usize,
    /// The integrator's settings, for the actors that fly free while others touch (`free_flight.rs`).
    free_settings: Settings,
    /// The counters of those free flights since the last report.
    free_report: tumble_integrate::Report,
}

/// Integration with event-driven contact.
#[derive(Clone)]
pub(crate) struct AccurateEngine {
    compiled: Compiled,
    integrator: Integrator<Model>,
    settings: Settings,
    pub(crate) contacts: Contacts,
}

/// What a failed call puts back: the whole integrator (state, next step, controller, caches, histories), the
/// resting set and what the contact phase knew.
#[derive(Clone)]
pub(crate) struct AccurateSnapshot {
    integrator: Integrator<Model>,
    resting: Option<RestingSet>,
    resting_keys: BTreeSet<ContactKey>,
    penetration: f64,
    window: (f64, usize),
    touching: Option<touching::Touching>,
    scales: Scales,
}

/// The contact engine's scales, set from the scene's size where the engine was built (a world built, stepped
/// and loaded elsewhere must keep the original's): resting speed, stall step, contact tolerance, largest contact
/// step, the lagged-friction tolerance.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scales([f64; 5]);

impl Contacts {
    fn scales(&self) -> Scales {
        Scales([self.resting_speed, self.stall_step, self.tolerance, self.max_step, self.lagged_tolerance])
    }

    fn set_scales(&mut self, s: Scales) {
        [self.resting_speed, self.stall_step, self.tolerance, self.max_step, self.lagged_tolerance] = s.0;
    }
}

impl Scales {
    /// Each positive and finite (the resting speed may be zero).
    fn valid(&self) -> bool {
        self.0[0] >= 0.0 && self.0.iter().all(|x| x.is_finite()) && self.0[1..].iter().all(|&x| x > 0.0)
    }
}

pub(crate) fn failure(t: f64, message: String) -> OdeError {
    OdeError::System { t, message }
}

impl AccurateEngine {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mut compiled: Compiled,
        scene: ContactScene,
        settings: Settings,
        accurate: AccurateSettings,
        gravity: f64,
        threads: usize,
        t: f64,
        y: Vec<f64>,
    ) -> Result<Self, WorldError> {
        let integrator = Integrator::new(&mut compiled.model, settings.clone(), t, &y)?;
        let size = scene.size(&y);
        let time_scale = (size / gravity.max(1e-300)).sqrt();
        let resting_speed = accurate.resting_speed.unwrap_or_else(|| tumble_contact::velocity_tolerance(size, gravity));
        let contacts = Contacts {
            scene,
            settings: accurate,
            resting_speed,
            resting_keys: BTreeSet::new(),
            solver: SolverSettings::default(),
            report: WorldReport::new("accurate"),
            penetration: 0.0,
            stall_step: 1e-5 * time_scale.min(1.0),
            window: (t, 0),
            tolerance: accurate.contact_tolerance.unwrap_or(1e-6 * size),
            gravity,
            max_step: (0.05 * time_scale).min(1.0 / 60.0),
            touching: None,
            threads,
            divergence_limit: settings.divergence_limit,
            last_solver_error: String::new(),
            solve_work: 0,
            free_settings: settings.clone(),
            free_report: tumble_integrate::Report::empty(settings.method.name()),
            lagged_tolerance: (10.0 * accurate.contact_tolerance.unwrap_or(1e-6 * size) / size.max(1e-300))
                .clamp(1e-9, 1e-3),
        };
        Ok(AccurateEngine { compiled, integrator, settings, contacts })
    }

    /// The engine's own stages for a state of length `dim`.
    pub fn planned(settings: &Settings, accurate: &AccurateSettings, dim: usize) -> Vec<Stage> {
        let mut out = vec![Stage::CollisionDetection, Stage::Bisection, Stage::Impulses];
        out.push(match accurate.persistent {
            Persistent::ContactSteps => Stage::ContactConeProgram,
            Persistent::RestingForces => Stage::RestingContact,
        });
        out.extend(crate::engine::SmoothEngine::planned(settings, dim));
        out
    }

    pub fn own_stages(&self) -> Vec<Stage> {
        Self::planned(&self.settings, &self.contacts.settings, self.compiled.model.layout.dim())
    }

    pub fn compiled(&self) -> &Compiled {
        &self.compiled
    }

    pub fn model_mut(&mut self) -> &mut Model {
        &mut self.compiled.model
    }

    pub fn time(&self) -> f64 {
        self.integrator.time()
    }

    pub fn state(&self) -> &[f64] {
        self.integrator.state()
    }

    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        Ok(self.integrator.set_state(t, y)?)
    }

    /// Advances to `t_end` (pausing past `pause`), recording frames with the penetration of the last contact
    /// phase and the events' times.
    pub fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let (model, integrator, contacts) = (&mut self.compiled.model, &mut self.integrator, &mut self.contacts);
        integrator.log_steps(run.is_some());
        let energy = mechanical_energy(model, integrator.state());
        let result = (|| {
            contacts.contact_phase(model, integrator)?;
            let (mut done, mut stuck, mut last) = (0, 0, integrator.time());
            loop {
                if contacts.touching.is_some() {
                    let (t, y) = (integrator.time(), integrator.state().to_vec());
                    let end = contacts.touching_steps(
                        model,
                        t,
                        y,
                        t_end,
                        pause,
                        &saves[done..],
                        run.as_deref_mut(),
                        budget,
                    )?;
                    done += end.delivered;
                    integrator.set_state(end.t, &end.y)?;
                    if end.touching {
                        return Ok(done);
                    }
                    continue;
                }
                // The integrator's own budget restarts at every event: it gets what is left of the call's.
                integrator.set_max_steps(budget.left());
                let before = attempts(integrator);
                let penetration = contacts.penetration;
                let adv = integrator.advance_with_events(
                    model,
                    t_end,
                    pause,
                    &saves[done..],
                    |m, t, y| {
                        if let Some(run) = run.as_deref_mut() {
                            run.record(m, t, y, penetration, []);
                        }
                    },
                    |step| contacts.detect(step),
                );
                if let Some(run) = run.as_deref_mut() {
                    for (t, h) in integrator.take_step_log() {
                        run.log_step(t, h);
                    }
                }
                let charged = budget.charge(attempts(integrator) - before, integrator.time());
                let adv = adv.map_err(|e| over_budget(e, budget))?;
                charged?;
                done += adv.delivered;
                let Some(t) = adv.event else { return Ok(done) };
                if let Some(run) = run.as_deref_mut() {
                    run.contact_events.push(t);
                }
                stuck = if t > last { 0 } else { stuck + 1 };
                last = t;
                if stuck > STUCK {
                    return Err(failure(t, format!("{STUCK} contact events at one time: the contacts do not settle")));
                }
                contacts.contact_phase(model, integrator)?;
            }
        })();
        contacts.report.energy_change += mechanical_energy(model, integrator.state()) - energy;
        Ok(result?)
    }

    /// The contacts of the last contact step while bodies touch (none once they fly free).
    pub fn last_contacts(&self) -> &[crate::engine::step_contacts::StepContact] {
        self.contacts.touching.as_ref().map_or(&[], |t| &t.last)
    }

    pub fn divergence_limit(&self) -> f64 {
        self.settings.divergence_limit
    }

    /// Sets the divergence limit of the integration, the contact steps and the free flights to come.
    pub fn set_divergence_limit(&mut self, limit: f64) {
        self.settings.divergence_limit = limit;
        self.integrator.set_divergence_limit(limit);
        self.contacts.divergence_limit = limit;
        self.contacts.free_settings.divergence_limit = limit;
    }

    pub fn snapshot(&self) -> AccurateSnapshot {
        AccurateSnapshot {
            integrator: self.integrator.clone(),
            resting: self.compiled.model.resting.clone(),
            resting_keys: self.contacts.resting_keys.clone(),
            penetration: self.contacts.penetration,
            window: self.contacts.window,
            touching: self.contacts.touching.clone(),
            scales: self.contacts.scales(),
        }
    }

    pub fn restore(&mut self, s: AccurateSnapshot) -> Result<(), WorldError> {
        self.integrator = s.integrator;
        self.integrator.take_report();
        // (The run loop takes the report, with the resting set's counters, before it restores.)
        self.compiled.model.resting = s.resting;
        self.contacts.resting_keys = s.resting_keys;
        self.contacts.penetration = s.penetration;
        self.contacts.window = s.window;
        self.contacts.touching = s.touching;
        self.contacts.set_scales(s.scales);
        Ok(())
    }

    pub fn take_report(&mut self) -> WorldReport {
        let mut r = take_integrator_report(Some(&mut self.integrator), self.settings.method.name());
        let free = std::mem::replace(
            &mut self.contacts.free_report,
            tumble_integrate::Report::empty(self.settings.method.name()),
        );
        r.stages.add(Stage::Integrate, free.steps);
        r.stages.add(Stage::Jacobian, free.jacobians);
        r.integrator.merge(&free);
        let c = std::mem::replace(&mut self.contacts.report, WorldReport::new("accurate"));
        r.merge_contact(&c);
        r.energy_change += c.energy_change;
        r.stages += c.stages;
        if let Some(set) = &mut self.compiled.model.resting {
            let solves = std::mem::take(&mut set.solves);
            r.qp_solves += solves;
            r.stages.add(Stage::RestingContact, solves);
            r.contact_seconds += std::mem::take(&mut set.seconds);
        }
        r
    }
}
