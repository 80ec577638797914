//! The smooth engine: the equations of motion integrated by any method of tumble-integrate under its own step
//! control, with no contact. Its step is the integrator's step; a world with nothing that moves only advances its
//! clock.

use super::Budget;
use crate::error::WorldError;
use crate::model::{Compiled, Model};
use crate::plan::Stage;
use crate::report::WorldReport;
use crate::run::Run;
use tumble_integrate::{Integrator, OdeError, Settings};

/// Integration without contact.
#[derive(Clone)]
pub(crate) struct SmoothEngine {
    compiled: Compiled,
    /// None when the state is empty (nothing moves): the clock alone advances.
    integrator: Option<Integrator<Model>>,
    settings: Settings,
    /// The time of an engine without integrator.
    t: f64,
    /// The change of mechanical energy since the report was last taken (J).
    energy_change: f64,
}

/// What a failed call puts back: the whole integrator (state, next step, controller, the method's caches and
/// histories), so that continuing after a failure is continuing from before it.
#[derive(Clone)]
pub(crate) struct SmoothSnapshot {
    t: f64,
    integrator: Option<Integrator<Model>>,
}

/// The smooth engine's memory as a file holds it (a variant of `SavedMemory`).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct SavedSmooth {
    t: f64,
    integrator: Option<tumble_integrate::IntegratorMemory>,
}

impl SmoothEngine {
    pub fn new(mut compiled: Compiled, settings: Settings, t: f64, y: Vec<f64>) -> Result<Self, WorldError> {
        let integrator =
            if y.is_empty() { None } else { Some(Integrator::new(&mut compiled.model, settings.clone(), t, &y)?) };
        Ok(SmoothEngine { compiled, integrator, settings, t, energy_change: 0.0 })
    }

    /// The engine's own stages for a state of length `dim`: the integrator's steps, and Jacobians for an
    /// implicit method.
    pub fn planned(settings: &Settings, dim: usize) -> Vec<Stage> {
        let mut out = Vec::new();
        if dim > 0 {
            out.push(Stage::Integrate);
            if settings.method.uses_jacobian() {
                out.push(Stage::Jacobian);
            }
        }
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
        self.integrator.as_ref().map_or(self.t, |i| i.time())
    }

    pub fn state(&self) -> &[f64] {
        self.integrator.as_ref().map_or(&[], |i| i.state())
    }

    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), WorldError> {
        match &mut self.integrator {
            Some(i) => i.set_state(t, y)?,
            None => self.t = t,
        }
        Ok(())
    }

    pub fn advance(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let Some(integrator) = &mut self.integrator else {
            // Nothing moves: every save is the same empty state.
            if let Some(run) = run {
                for &t in saves {
                    run.record(&self.compiled.model, t, &[], 0.0, []);
                }
            }
            self.t = t_end;
            return Ok(saves.len());
        };
        integrator.log_steps(run.is_some());
        integrator.set_max_steps(budget.left());
        let before = attempts(integrator);
        let energy = mechanical_energy(&self.compiled.model, integrator.state());
        let delivered = integrator.advance_until(&mut self.compiled.model, t_end, pause, saves, |m, t, y| {
            if let Some(run) = run.as_deref_mut() {
                run.record(m, t, y, 0.0, []);
            }
        });
        if let Some(run) = run {
            for (t, h) in integrator.take_step_log() {
                run.log_step(t, h);
            }
        }
        self.energy_change += mechanical_energy(&self.compiled.model, integrator.state()) - energy;
        let charged = budget.charge(attempts(integrator) - before, integrator.time());
        let delivered = delivered.map_err(|e| over_budget(e, budget))?;
        charged?;
        Ok(delivered)
    }

    pub fn snapshot(&self) -> SmoothSnapshot {
        SmoothSnapshot { t: self.t, integrator: self.integrator.clone() }
    }

    /// Puts the snapshot back; the report of the failed call's work is kept (the caller took it).
    pub fn restore(&mut self, s: SmoothSnapshot) -> Result<(), WorldError> {
        self.t = s.t;
        self.integrator = s.integrator.map(|mut i| {
            i.take_report();
            i
        });
        Ok(())
    }

    pub fn divergence_limit(&self) -> f64 {
        self.settings.divergence_limit
    }

    pub fn set_divergence_limit(&mut self, limit: f64) {
        self.settings.divergence_limit = limit;
        if let Some(i) = &mut self.integrator {
            i.set_divergence_limit(limit);
        }
    }

    /// The engine's memory as a file holds it: the clock and the integration as plain data.
    pub fn saved(&self) -> SavedSmooth {
        SavedSmooth { t: self.t, integrator: self.integrator.as_ref().map(|i| i.memory()) }
    }

    /// Gives back a saved memory (checked by the integrator; nothing changes on an error).
    pub fn restore_saved(&mut self, saved: SavedSmooth) -> Result<(), String> {
        if !saved.t.is_finite() {
            return Err("its time is not finite".into());
        }
        let mut integrator = self.integrator.clone();
        match (&mut integrator, &saved.integrator) {
            (Some(i), Some(m)) => i.set_memory(m).map_err(|e| e.to_string())?,
            (None, None) => {}
            _ => {
                return Err(
                    "it has an integration where the world has nothing to integrate, or none where it has".into()
                )
            }
        }
        self.t = saved.t;
        self.integrator = integrator;
        Ok(())
    }

    pub fn take_report(&mut self) -> WorldReport {
        let mut r = take_integrator_report(self.integrator.as_mut(), self.settings.method.name());
        r.energy_change = std::mem::take(&mut self.energy_change);
        r
    }
}

/// Kinetic energy and the potential energy of gravity and the springs in state y (J).
pub(crate) fn mechanical_energy(model: &Model, y: &[f64]) -> f64 {
    model.kinetic_energy(y) + model.potential_energy(y)
}

/// Steps the integrator has taken or rejected since its report was last taken.
pub(crate) fn attempts(i: &Integrator<Model>) -> usize {
    i.report().steps + i.report().rejected
}

/// An integrator that ran out of the steps left names the call's whole budget.
pub(crate) fn over_budget(e: OdeError, budget: &Budget) -> OdeError {
    match e {
        OdeError::TooManySteps { t, .. } => OdeError::TooManySteps { t, max_steps: budget.limit() },
        e => e,
    }
}

/// The integrator's report since the last call, with the integrate and Jacobian stages booked from it.
pub(crate) fn take_integrator_report(integrator: Option<&mut Integrator<Model>>, method: &'static str) -> WorldReport {
    let mut r = WorldReport::new(method);
    if let Some(i) = integrator {
        r.integrator = i.take_report();
    }
    r.stages.add(Stage::Integrate, r.integrator.steps);
    r.stages.add(Stage::Jacobian, r.integrator.jacobians);
    r
}
