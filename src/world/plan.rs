//! The plan: the stages a world will run, taken from its engine's `stages()` (or, before the engine exists, from
//! the same per-engine lists for the compiled model), so that it names exactly what the steps do.

use super::World;
use crate::mode::Mode;
use crate::plan::{Plan, Stage};

impl World {
    /// The stages this world runs, decided from its contents, its mode and its integrator.
    pub fn plan(&self) -> Plan {
        let compiled = self.compile();
        let stages = match &self.engine {
            Some(engine) => engine.stages(),
            None => crate::engine::planned(&self.mode, &compiled.model, &self.settings, self.has_contact(&compiled)),
        };
        let fast = matches!(self.mode, Mode::Fast(_));
        let decomposed = self
            .bodies
            .iter()
            .any(|(_, b)| b.colliders.iter().any(|c| matches!(c.shape, tumble_collide::Shape::Decomposed(_))));
        let setup = decomposed.then_some(Stage::MeshDecomposition);
        Plan {
            jacobian: stages.contains(&Stage::Jacobian).then(|| compiled.model.jacobian_name()),
            stages: setup.iter().chain(stages.iter()).map(|s| s.name()).collect(),
            state_len: compiled.model.layout.dim(),
            mode: self.mode.name(),
            method: if fast { "fast (semi-implicit Euler)" } else { self.settings.method.name() },
        }
    }
}
