//! The world in fast mode: a fast engine built from the compiled model, stepped at equal substeps no longer than
//! its step, its state written back to the particles and bodies; runs record frames and restore the world on error.

use crate::contact_scene::ContactScene;
use crate::fast::FastEngine;
use crate::mode::FastSettings;
use crate::run::Run;
use crate::{World, WorldError};

impl World {
    /// The fast engine, built if the structure changed and given any state the user set.
    fn fast_engine(&mut self, settings: FastSettings) -> &mut FastEngine {
        if self.fast.is_none() || self.state_changed {
            let compiled = self.compile();
            let y = compiled.pack(&self.particles, &self.bodies);
            let scene = ContactScene::build(compiled.model.layout, &self.particles, &self.bodies, &compiled.bodies);
            self.fast = Some(FastEngine::new(compiled, scene, self.time, y, settings));
            self.engine = None;
            self.state_changed = false;
        }
        self.fast.as_mut().expect("built above")
    }

    /// Moves the fast engine's report into the totals.
    fn collect_fast_report(&mut self) -> crate::WorldReport {
        let mut r =
            self.fast.as_mut().map(|e| e.take_report()).unwrap_or_else(|| crate::WorldReport::new(crate::fast::FAST));
        if let Some(e) = &mut self.fast {
            r.forces = std::mem::take(&mut e.compiled.model.counters);
        }
        self.totals.merge(&r);
        r
    }

    fn store_fast_state(&mut self) {
        if let Some(e) = &self.fast {
            e.compiled.unpack(&e.y, &mut self.particles, &mut self.bodies);
            self.time = e.t;
        }
    }

    /// Equal steps no longer than `settings.dt` from the engine's time to `t_end`, logged as (end time, size).
    fn fast_to(
        engine: &mut FastEngine,
        settings: &FastSettings,
        t_end: f64,
        log: &mut Vec<(f64, f64)>,
    ) -> Result<(), WorldError> {
        let span = t_end - engine.t;
        if span <= 0.0 {
            return Ok(());
        }
        let n = (span / settings.dt * (1.0 - 1e-12)).ceil().max(1.0) as usize;
        let (t0, h) = (engine.t, span / n as f64);
        for k in 1..=n {
            engine.step(h)?;
            engine.t = if k == n { t_end } else { t0 + k as f64 * h };
            log.push((engine.t, h));
        }
        Ok(())
    }

    pub(crate) fn step_fast(&mut self, settings: FastSettings, dt: f64) -> Result<(), WorldError> {
        let t_end = self.time + dt;
        let e = self.fast_engine(settings);
        let saved = e.snapshot();
        let result = Self::fast_to(e, &settings, t_end, &mut Vec::new());
        if result.is_err() {
            e.restore(saved);
        }
        self.collect_fast_report();
        result?;
        self.store_fast_state();
        Ok(())
    }

    pub(crate) fn run_fast(
        &mut self,
        settings: FastSettings,
        times: &[f64],
        mut run: Run,
        mut control: impl FnMut(f64) -> bool,
    ) -> Result<Run, WorldError> {
        let e = self.fast_engine(settings);
        let saved = e.snapshot();
        let chunk = times.len().div_ceil(100).max(1);
        let mut outcome = Ok(());
        let mut log = Vec::new();
        for (k, &t) in times.iter().enumerate() {
            if let Err(err) = Self::fast_to(e, &settings, t, &mut log) {
                outcome = Err(err);
                break;
            }
            run.record(&e.compiled.model, t, &e.y);
            run.penetration.push(e.penetration);
            if (k + 1) % chunk == 0 && !control((k + 1) as f64 / times.len() as f64) {
                outcome = Err(WorldError::Interrupted);
                break;
            }
        }
        if outcome.is_err() {
            e.restore(saved);
        }
        (run.step_times, run.step_sizes) = log.into_iter().unzip();
        run.report = self.collect_fast_report();
        outcome?;
        self.store_fast_state();
        Ok(run)
    }
}
