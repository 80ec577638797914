//! Accurate mode: the chapter's scheme for free flight and impacts, error-controlled convex steps while bodies touch.
//!
//! Free motion is carried by the integrator under its error control (`system.rs`: the model's equations of motion
//! with the joints' forces, `joint_forces.rs`). A world whose colliders cannot touch is only that. Otherwise, after
//! every accepted step the contacts are checked (`detect.rs`); a collision inside the step is located by bisection
//! on the step's dense output (`collision_time.rs`), a pass through a thin body by a distance-bounded search
//! (`pass_through.rs`); the step is cut at the event. At each event the impact stage (`impact.rs`) looks at the
//! contacts that close or touch. Frictionless collisions get Newton's impulses at the located time (so a bouncing
//! ball's apexes stay exact); when a contact has friction, or contacts stay touching after the impulses, the world
//! enters the touching phase (`touching.rs`): convex steps (`convex_step.rs`: semi-implicit Euler, every contact
//! and its Coulomb friction one convex program per island, so a step always has an answer) whose size comes from
//! an error estimate by step doubling, after Drake's CENIC. Impacts during that phase are contacts of the convex
//! program with Newton's restitution as their bound, located in time by the error control. When no pair is within
//! reach of a step, the integrator takes over again. Why the split: the integrator's order carries free flight and
//! exact bisection-located bounces cheaply, while the touching phase cannot cascade (no event ends a step there: a
//! rocking corner, a settling stack or a Zeno bounce is a sequence of convex steps) and brings friction.
//!
//! With `Persistent::RestingForces` the chapter's own resting contact is used instead: contacts that stay touching
//! get frictionless QP forces inside the right-hand side (`resting.rs`), with drift caught as an event
//! (`drift.rs`).
//!
//! The advance reads as: impact stage; then repeatedly either take contact steps while touching, or integrate
//! until an event, record it, impact stage. Everything the steps carry between calls is the engine's memory
//! (`memory.rs`; given back, it is checked and put in place by `give_memory.rs`). The stages fail with
//! `failure.rs`'s error.

mod advance;
mod breaking;
mod clocks;
mod collision_time;
mod contact_memory;
mod contact_stages;
mod convex_step;
mod detect;
mod doubled_step;
mod drift;
mod energy_guard;
mod free_flight;
mod free_flight_memory;
mod give_memory;
mod held;
mod impact;
mod integration;
mod joint_forces;
mod late_sink;
mod memory;
mod pass_through;
mod qp;
mod resting;
mod sleep;
mod slide_limit;
mod step_estimate;
mod step_judgement;
mod sync;
mod system;
#[cfg(test)]
mod tests;
mod touching;
mod touching_phase;

pub(crate) use memory::{engine_name, AccurateMemory};
pub(crate) use system::AccurateSystem;

use super::budget::Budget;
use super::{Engine, EngineCore, EngineMemory};
use crate::error::WorldError;
use crate::mode::AccurateSettings;
use crate::model::{Compiled, Model, Tally};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use integration::{within_budget, Integration};
use std::sync::Arc;
use tumble_integrate::{Integrator, Settings};

/// Events at one time without progress before the advance gives up (an impact stage that cannot settle).
const STUCK: usize = 200;

/// Accurate mode's engine: the integration of its equations of motion and, when colliders can touch, its contact
/// stages.
#[derive(Clone)]
pub(crate) struct AccurateEngine {
    core: EngineCore,
    system: AccurateSystem,
    settings: Settings,
    /// The colliders and the contact stages' settings; `None` when no two colliders can touch.
    contacts: Option<contact_stages::ContactRules>,
    memory: AccurateMemory,
    /// The time tolerance of event times: a joint's break is located to it (as a collision's time is).
    time_tolerance: f64,
    /// The memory where the current call began (`checkpoint`).
    checkpoint: Option<EngineMemory>,
}

impl AccurateEngine {
    /// The engine of `compiled` from (t, y), with contact stages over `scene` if given.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        compiled: Compiled,
        collider_set: Option<crate::engine::collider_set::ColliderSet>,
        settings: Settings,
        accurate: AccurateSettings,
        gravity: f64,
        threads: usize,
        t: f64,
        y: Vec<f64>,
    ) -> Result<Self, WorldError> {
        let Compiled { model, handles } = compiled;
        let broken = model.broken_joints();
        let mut system = AccurateSystem::new(model);
        let integration =
            if y.is_empty() { None } else { Some(Integration::new(&mut system, settings.clone(), t, &y)?) };
        // the contact stages book their counters in a report of their own name, the integration in the method's
        let report = WorldReport::new(if collider_set.is_some() { "accurate" } else { settings.method.name() });
        let mut engine = AccurateEngine {
            core: EngineCore::new(handles, settings.divergence_limit, threads, report),
            system,
            settings,
            contacts: None,
            memory: AccurateMemory { clock: t, integration, contact: None, broken, load_averages: Vec::new() },
            time_tolerance: accurate.time_tolerance,
            checkpoint: None,
        };
        if let Some(collider_set) = collider_set {
            engine.system.statics = Arc::clone(&collider_set.static_poses);
            let (rules, memory) =
                contact_stages::ContactRules::new(collider_set, accurate, &engine.settings, gravity, t, &y);
            engine.contacts = Some(rules);
            engine.memory.contact = Some(memory);
        }
        Ok(engine)
    }

    /// The engine's own stages for a state of length `dim`, with or without contact stages.
    /// (`breaks`: a joint can break, its time located by bisection.)
    pub fn planned(
        settings: &Settings,
        accurate: Option<&AccurateSettings>,
        dim: usize,
        (joints, breaks): (bool, bool),
    ) -> Vec<Stage> {
        let mut out = Vec::new();
        if breaks && accurate.is_none() {
            out.push(Stage::Bisection);
        }
        if let Some(a) = accurate {
            out.extend([Stage::CollisionDetection, Stage::Bisection, Stage::Impulses]);
            out.push(match a.persistent {
                crate::mode::Persistent::ContactSteps => Stage::ContactConeProgram,
                crate::mode::Persistent::RestingForces => Stage::RestingContact,
            });
            // jointed worlds do not sleep (`sleep.rs`)
            if a.sleep && !joints && a.persistent == crate::mode::Persistent::ContactSteps {
                out.push(Stage::Sleeping);
            }
        }
        if dim > 0 {
            out.push(Stage::Integrate);
            if settings.method.uses_jacobian() {
                out.push(Stage::Jacobian);
            }
        }
        out
    }

    /// The accurate-mode settings of the contact stages, if the engine has them.
    fn accurate_settings(&self) -> Option<&AccurateSettings> {
        self.contacts.as_ref().map(|c| &c.settings)
    }

    /// Integrates to `t_end` (pausing past `pause`) with no contact: the integrator's advance, or for an empty
    /// state the clock alone.
    fn integrate(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let model = &mut self.system;
        let Some(integration) = &mut self.memory.integration else {
            // Nothing moves: every save is the same empty state.
            if let Some(run) = run {
                for &t in saves {
                    run.record(&model.model, t, &[], 0.0, []);
                }
            }
            self.memory.clock = t_end;
            return Ok(saves.len());
        };
        let integrator = integration.live_mut();
        integrator.log_steps(run.is_some());
        let report = &mut self.core.report;
        let (broken, tolerance) = (&mut self.memory.broken, self.time_tolerance);
        let averages = &mut self.memory.load_averages;
        Ok(within_budget(integrator, budget, None, |integrator| {
            let energy = mechanical_energy(&model.model, integrator.state());
            let mut delivered = 0;
            loop {
                let adv = integrator.advance_with_events(
                    model,
                    t_end,
                    pause,
                    &saves[delivered..],
                    |m, t, y| {
                        if let Some(run) = run.as_deref_mut() {
                            run.record(&m.model, t, y, 0.0, []);
                        }
                    },
                    |step| breaking::break_time(step, None, averages, tolerance, report),
                )?;
                delivered += adv.delivered;
                let Some(t) = adv.event else { break };
                // a joint breaks: let go of it, and integrate the new equations afresh from here
                let y = integrator.state().to_vec();
                for k in breaking::break_overloaded(model, broken, averages, None, t, &y)? {
                    if let Some(run) = run.as_deref_mut() {
                        run.break_joint(t, k);
                    }
                }
                integrator.set_state(t, &y)?;
            }
            if let Some(run) = run {
                for (t, h) in integrator.take_step_log() {
                    run.log_step(t, h);
                }
            }
            report.energy_change += mechanical_energy(&model.model, integrator.state()) - energy;
            Ok(delivered)
        })?)
    }
}

/// The integrator's report since the last call, with the integrate and Jacobian stages booked from it.
fn take_integrator_report(integrator: Option<&mut Integrator<AccurateSystem>>, method: &'static str) -> WorldReport {
    let mut r = WorldReport::new(method);
    if let Some(i) = integrator {
        r.integrator = i.take_report();
    }
    r.stages.add(Stage::Integrate, r.integrator.steps);
    r.stages.add(Stage::Jacobian, r.integrator.jacobians);
    r
}

/// Kinetic energy and the potential energy of gravity and the springs in state y (J).
pub(crate) fn mechanical_energy(model: &Model, y: &[f64]) -> f64 {
    model.kinetic_energy(y) + model.potential_energy(y)
}

impl Engine for AccurateEngine {
    fn core(&self) -> &EngineCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut EngineCore {
        &mut self.core
    }

    fn model(&self) -> &Model {
        &self.system.model
    }

    fn tally_mut(&mut self) -> &mut Tally {
        &mut self.system.tally
    }

    fn time(&self) -> f64 {
        self.memory.time()
    }

    fn state(&self) -> &[f64] {
        self.memory.state()
    }

    /// Sets the state. A set state (a push, an edit) starts afresh: the touching phase, its sleeping islands and
    /// its step history are dropped, and the next advance begins with an impact stage.
    fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        match &mut self.memory.integration {
            Some(i) => i.live_mut().set_state(t, y)?,
            None => self.memory.clock = t,
        }
        if let Some(c) = self.memory.contact.as_mut() {
            c.touching = None;
        }
        Ok(())
    }

    fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let (t_end, pause) = self.drive_kinematic(t_end, pause)?;
        // (frames past an advance cut short at a keyframe wait for the next call)
        let saves = &saves[..saves.partition_point(|&s| s <= t_end)];
        if self.contacts.is_some() {
            return self.advance_with_contacts(t_end, pause, saves, run, budget);
        }
        self.integrate(t_end, pause, saves, run, budget)
    }

    fn own_stages(&self) -> Vec<Stage> {
        let model = &self.system.model;
        Self::planned(
            &self.settings,
            self.accurate_settings(),
            model.layout.dim(),
            (model.has_joints(), model.can_break()),
        )
    }

    fn checkpoint(&mut self) {
        self.checkpoint = Some(self.memory());
    }

    fn rollback(&mut self) -> Result<(), String> {
        let memory = self.checkpoint.take().ok_or("no checkpoint to go back to")?;
        self.set_memory(memory)
    }

    fn memory(&self) -> EngineMemory {
        EngineMemory::Accurate(Box::new(self.memory.clone()))
    }

    fn set_memory(&mut self, memory: EngineMemory) -> Result<(), String> {
        match memory {
            EngineMemory::Accurate(m) => self.give_memory(*m),
            other => Err(format!("it is the memory of {}, which this world does not run", other.engine_name())),
        }
    }

    /// Sets the divergence limit of the integration, the contact steps and the free flights to come.
    fn set_divergence_limit(&mut self, limit: f64) {
        self.core.divergence_limit = limit;
        self.settings.divergence_limit = limit;
        if let Some(i) = &mut self.memory.integration {
            i.live_mut().set_divergence_limit(limit);
        }
        if let Some(c) = &mut self.contacts {
            c.free_settings.divergence_limit = limit;
        }
    }

    fn last_contacts(&self) -> Vec<crate::engine::last_contacts::LastContact> {
        self.memory.contact.as_ref().and_then(|c| c.touching.as_ref()).map_or_else(Vec::new, |t| t.last.clone())
    }

    fn set_material(&mut self, actor: usize, material: crate::Material) {
        if let Some(c) = &mut self.contacts {
            c.collider_set.set_material(actor, material);
        }
        self.wake_all();
    }

    fn take_own_report(&mut self) -> WorldReport {
        let method = self.settings.method.name();
        let integrator = self.memory.integration.as_mut().map(|i| i.live_mut());
        let mut r = take_integrator_report(integrator, method);
        if let Some(rules) = &mut self.contacts {
            let free = std::mem::replace(&mut rules.free_report, tumble_integrate::Report::empty(method));
            r.stages.add(Stage::Integrate, free.steps);
            r.stages.add(Stage::Jacobian, free.jacobians);
            r.integrator.merge(&free);
            let c = std::mem::replace(&mut self.core.report, WorldReport::new("accurate"));
            r.merge_contact(&c);
            r.islands += c.islands;
            r.sleepers = self.memory.contact.as_ref().and_then(|m| m.touching.as_ref()).map_or(0, |t| t.sleep.count());
            r.energy_change += c.energy_change;
            r.wall_seconds += c.wall_seconds;
            r.stages += c.stages;
            let solves = std::mem::take(&mut self.system.resting_solves);
            r.qp_solves += solves;
            r.stages.add(Stage::RestingContact, solves);
            r.contact_seconds += std::mem::take(&mut self.system.resting_seconds);
            r.contact_tolerance = self.memory.contact.as_ref().map(|m| m.scales.tolerance);
            self.book_joints(&mut r);
            return r;
        }
        r.energy_change = std::mem::take(&mut self.core.report.energy_change);
        r.wall_seconds = std::mem::take(&mut self.core.report.wall_seconds);
        self.book_joints(&mut r);
        r
    }

    fn boxed_clone(&self) -> Box<dyn Engine> {
        Box::new(self.clone())
    }
}

impl AccurateEngine {
    /// Puts the kinematic bodies on their path with the velocities they move at from now (a keyframe changes them:
    /// the integration restarts there, and a touching phase carries on with them), and ends the advance at the next
    /// keyframe, so no step straddles a change of velocity.
    fn drive_kinematic(&mut self, t_end: f64, pause: f64) -> Result<(f64, f64), WorldError> {
        let model = &self.system.model;
        if !model.has_kinematic() {
            return Ok((t_end, pause));
        }
        // (a touching phase keeping its own state is driven in it)
        let in_phase = self.memory.contact.as_mut().and_then(|c| c.touching.as_mut()).and_then(|p| p.at.as_mut());
        if let Some((t, y)) = in_phase {
            model.drive_kinematic(*t, y, None);
        } else if let Some(integration) = &mut self.memory.integration {
            let live = integration.live_mut();
            let (t, mut y) = (live.time(), live.state().to_vec());
            if model.drive_kinematic(t, &mut y, None) {
                live.set_state(t, &y)?;
            }
        }
        let stop = model.next_keyframe_after(self.time()).map_or(t_end, |k| k.min(t_end));
        Ok((stop, pause.min(stop)))
    }

    /// Wakes every sleeping island.
    fn wake_all(&mut self) {
        if let Some(touching) = self.memory.contact.as_mut().and_then(|c| c.touching.as_mut()) {
            touching.sleep.wake_all();
        }
    }

    /// Books the joints' rows and errors at the current state (at the end of every call).
    fn book_joints(&self, r: &mut WorldReport) {
        let model = &self.system.model;
        if !model.joints.is_empty() {
            let (rows, errors) = model.joint_errors(self.state());
            r.book_joints(rows, errors);
        }
    }
}
