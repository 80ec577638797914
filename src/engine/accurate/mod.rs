//! Accurate mode, the chapter's scheme: the integrator carries the smooth motion under its error control; after
//! every accepted step the contacts are checked (`detect.rs`); a collision inside the step is located by bisection
//! on the step's dense output (`collision_time.rs`), a pass through a thin body by a distance-bounded search
//! (`pass_through.rs`), and a resting contact that sank is caught (`drift.rs`); the step is cut at the event. At
//! each event the contact phase (`contact_phase.rs`) applies impulses, lifts drifted contacts back and hands the
//! resting ones to the right-hand side, which gives them the QP forces (`resting.rs`).
//!
//! The advance reads as: contact phase; then repeatedly integrate until an event, record it, contact phase.

mod collision_time;
mod contact_phase;
mod detect;
mod drift;
mod pass_through;
mod resting;

pub(crate) use resting::RestingSet;

use crate::engine::contact_scene::{ContactKey, ContactScene};
use crate::engine::smooth::take_integrator_report;
use crate::error::WorldError;
use crate::mode::AccurateSettings;
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
    stall_step: f64,
    /// The current window: its start time and the accepted steps in it.
    window: (f64, usize),
}

/// Integration with event-driven contact.
pub(crate) struct AccurateEngine {
    compiled: Compiled,
    integrator: Integrator<Model>,
    settings: Settings,
    contacts: Contacts,
}

/// What a failed call puts back: the whole integrator (state, next step, controller, caches, histories), the
/// resting set and what the contact phase knew.
pub(crate) struct AccurateSnapshot {
    integrator: Integrator<Model>,
    resting: Option<RestingSet>,
    resting_keys: BTreeSet<ContactKey>,
    penetration: f64,
    window: (f64, usize),
}

pub(crate) fn failure(t: f64, message: String) -> OdeError {
    OdeError::System { t, message }
}

impl AccurateEngine {
    pub fn new(
        mut compiled: Compiled,
        scene: ContactScene,
        settings: Settings,
        accurate: AccurateSettings,
        gravity: f64,
        t: f64,
        y: Vec<f64>,
    ) -> Result<Self, WorldError> {
        let integrator = Integrator::new(&mut compiled.model, settings.clone(), t, &y)?;
        let size = scene.size(&y);
        let resting_speed = accurate.resting_speed.unwrap_or_else(|| tumble_contact::velocity_tolerance(size, gravity));
        let contacts = Contacts {
            scene,
            settings: accurate,
            resting_speed,
            resting_keys: BTreeSet::new(),
            solver: SolverSettings::default(),
            report: WorldReport::new("accurate"),
            penetration: 0.0,
            stall_step: 1e-5 * (size / gravity.max(1e-300)).sqrt().min(1.0),
            window: (t, 0),
        };
        Ok(AccurateEngine { compiled, integrator, settings, contacts })
    }

    /// The engine's own stages for a state of length `dim`.
    pub fn planned(settings: &Settings, dim: usize) -> Vec<Stage> {
        let mut out = vec![Stage::CollisionDetection, Stage::Bisection, Stage::Impulses, Stage::RestingContact];
        out.extend(crate::engine::SmoothEngine::planned(settings, dim));
        out
    }

    pub fn own_stages(&self) -> Vec<Stage> {
        Self::planned(&self.settings, self.compiled.model.layout.dim())
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
    ) -> Result<usize, WorldError> {
        let (model, integrator, contacts) = (&mut self.compiled.model, &mut self.integrator, &mut self.contacts);
        integrator.log_steps(run.is_some());
        // One step budget for the whole call (the integrator's own budget restarts at every event).
        let attempts = |i: &Integrator<Model>| i.report().steps + i.report().rejected;
        let (budget, spent) = (self.settings.max_steps, attempts(integrator));
        let result = (|| {
            contacts.contact_phase(model, integrator)?;
            let (mut done, mut stuck, mut last) = (0, 0, integrator.time());
            loop {
                if attempts(integrator) - spent > budget {
                    return Err(OdeError::TooManySteps { t: integrator.time(), max_steps: budget });
                }
                let penetration = contacts.penetration;
                let adv = integrator.advance_with_events(
                    model,
                    t_end,
                    pause,
                    &saves[done..],
                    |m, t, y| {
                        if let Some(run) = run.as_deref_mut() {
                            run.record(m, t, y, penetration);
                        }
                    },
                    |step| contacts.detect(step),
                );
                if let Some(run) = run.as_deref_mut() {
                    for (t, h) in integrator.take_step_log() {
                        run.log_step(t, h);
                    }
                }
                let adv = adv?;
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
        Ok(result?)
    }

    pub fn snapshot(&self) -> AccurateSnapshot {
        AccurateSnapshot {
            integrator: self.integrator.clone(),
            resting: self.compiled.model.resting.clone(),
            resting_keys: self.contacts.resting_keys.clone(),
            penetration: self.contacts.penetration,
            window: self.contacts.window,
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
        Ok(())
    }

    pub fn take_report(&mut self) -> WorldReport {
        let mut r = take_integrator_report(Some(&mut self.integrator), self.settings.method.name());
        let c = std::mem::replace(&mut self.contacts.report, WorldReport::new("accurate"));
        r.merge_contact(&c);
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
