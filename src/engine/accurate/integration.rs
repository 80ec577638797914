//! An integration kept in accurate mode's memory. While the engine runs it is the live integrator (a copy of it is
//! a snapshot of the whole integration: state, next step, controller, the method's caches and histories); a file
//! holds its plain data (`IntegratorMemory`), which is read back as that until the engine gives it to an integrator
//! of its system (`AccurateEngine::set_memory`), which then continues bit for bit.

use super::system::AccurateSystem;
use crate::engine::budget::{over_budget, Budget};
use tumble_integrate::{Integrator, IntegratorMemory, OdeError, Settings};

/// A live integrator, or one read from a file and not yet given back.
#[derive(Clone)]
pub(crate) enum Integration {
    Live(Box<Integrator<AccurateSystem>>),
    Saved(IntegratorMemory),
}

impl Integration {
    /// A new integration of `system` from (t, y).
    pub fn new(system: &mut AccurateSystem, settings: Settings, t: f64, y: &[f64]) -> Result<Self, OdeError> {
        Ok(Integration::Live(Box::new(Integrator::new(system, settings, t, y)?)))
    }

    /// The live integrator. An engine's memory holds live integrators only (`set_memory` makes them so).
    pub fn live(&self) -> &Integrator<AccurateSystem> {
        match self {
            Integration::Live(i) => i,
            Integration::Saved(_) => unreachable!("an engine's memory holds live integrators"),
        }
    }

    /// The live integrator, to step.
    pub fn live_mut(&mut self) -> &mut Integrator<AccurateSystem> {
        match self {
            Integration::Live(i) => i,
            Integration::Saved(_) => unreachable!("an engine's memory holds live integrators"),
        }
    }

    /// Made live: a live one keeps its integrator (its counters cleared: they were reported when it was copied); a
    /// saved one is given to `template`'s copy, which checks it (an error names what does not fit).
    pub fn into_live(
        self,
        template: impl FnOnce() -> Result<Integrator<AccurateSystem>, OdeError>,
    ) -> Result<Self, String> {
        match self {
            Integration::Live(mut i) => {
                i.take_report();
                Ok(Integration::Live(i))
            }
            Integration::Saved(memory) => {
                let mut integrator = template().map_err(|e| e.to_string())?;
                integrator.set_memory(&memory).map_err(|e| e.to_string())?;
                Ok(Integration::Live(Box::new(integrator)))
            }
        }
    }
}

/// Runs `advance` on `integrator` with what is left of the call's `budget` as its step limit, then charges the steps
/// it tried (taken or rejected) to the budget at time `at` (the integrator's own when `None`): the one bookkeeping of
/// every integration of accurate mode (free motion, and the free flights beside touching bodies). An integrator that
/// ran out of steps names the call's whole budget.
pub(super) fn within_budget<R>(
    integrator: &mut Integrator<AccurateSystem>,
    budget: &mut Budget<'_>,
    at: Option<f64>,
    advance: impl FnOnce(&mut Integrator<AccurateSystem>) -> Result<R, OdeError>,
) -> Result<R, OdeError> {
    integrator.set_max_steps(budget.left());
    let before = attempts(integrator);
    let result = advance(integrator);
    let charged = budget.charge(attempts(integrator) - before, at.unwrap_or_else(|| integrator.time()));
    let result = result.map_err(|e| over_budget(e, budget))?;
    charged?;
    Ok(result)
}

/// Steps the integrator has taken or rejected since its report was last taken.
fn attempts(i: &Integrator<AccurateSystem>) -> usize {
    i.report().steps + i.report().rejected
}

impl serde::Serialize for Integration {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Integration::Live(i) => i.memory().serialize(s),
            Integration::Saved(m) => m.serialize(s),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Integration {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        IntegratorMemory::deserialize(d).map(Integration::Saved)
    }
}
