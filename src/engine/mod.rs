//! Engines: the ways of stepping a compiled world, behind one interface (`Engine`, `interface.rs`). Accurate mode's
//! engine integrates the equations of motion under the integrator's error control, with the chapter's event-driven
//! contact when colliders can touch (`accurate/`); fast mode's time-steps contact at a fixed step (`fast/`). The
//! world owns one engine, drives it with one run loop (`world/stepping.rs`), and builds its plan from the engine's
//! `stages()`. Engines never see the `World`. What every engine holds is its `EngineCore`; what it carries from
//! one call to the next is its memory (`EngineMemory`), one type per engine that is at once the snapshot a failed
//! call puts back, what a file holds and what is given back. This module builds the engine for a mode and plans its
//! stages: it uses the engines, and they use only the parts it re-exports (the interface, the core, the memory, the
//! budget), never its own items.

pub(crate) mod accurate;
mod bounce_scale;
pub(crate) mod breaking;
mod budget;
mod closing_pairs;
pub(crate) mod collider_set;
mod contact_pairs;
mod contact_reduction;
mod core;
mod failure;
pub(crate) mod fast;
pub(crate) mod found_contact;
mod frames;
mod interface;
pub(crate) mod last_contacts;
mod memory;
mod reach;
mod semi_implicit;
mod state_error;
mod support_polygon;

pub(crate) use self::core::EngineCore;
pub(crate) use budget::{Budget, Watch};
pub(crate) use interface::Engine;
pub(crate) use memory::EngineMemory;

use crate::error::WorldError;
use crate::mode::Mode;
use crate::model::{Compiled, Model};
use crate::plan::Stage;
use accurate::AccurateEngine;
use tumble_integrate::Settings;

/// What an engine is built from, besides the compiled model and its state.
pub(crate) struct EngineSpec {
    /// The contact mode and its settings.
    pub mode: Mode,
    /// The integrator's settings (accurate mode), with the divergence limit already set.
    pub settings: Settings,
    /// The colliders, when two of them can touch.
    pub collider_set: Option<collider_set::ColliderSet>,
    /// |g|, for accurate mode's resting speed and first contact step.
    pub gravity: f64,
    /// Threads for the contact solves (0: one per core).
    pub threads: usize,
}

/// The engine for this mode and scene: fast mode's time stepping, or accurate mode's integration with contact
/// stages when colliders can touch.
pub(crate) fn build(spec: EngineSpec, compiled: Compiled, t: f64, y: Vec<f64>) -> Result<Box<dyn Engine>, WorldError> {
    let EngineSpec { mode, settings, gravity, threads, .. } = spec;
    let collider_set = spec.collider_set;
    match mode {
        Mode::Fast(fast) => {
            let limit = settings.divergence_limit;
            Ok(Box::new(fast::FastEngine::new(compiled, collider_set, t, y, fast, threads, limit)))
        }
        Mode::Accurate(accurate) => {
            Ok(Box::new(AccurateEngine::new(compiled, collider_set, settings, accurate, gravity, threads, t, y)?))
        }
    }
}

/// The stages an engine would run for `model`: the model's terms, then the engine's own. `plan()` and `stages()`
/// both come from here.
pub(crate) fn planned(mode: &Mode, model: &Model, settings: &Settings, has_scene: bool) -> Vec<Stage> {
    let mut stages = model.stages();
    let dim = model.layout.dim();
    match mode {
        Mode::Fast(f) => stages.extend(fast::FastEngine::planned(f, dim, has_scene, model.has_joints())),
        Mode::Accurate(a) => {
            let joints = (model.has_joints(), model.can_break());
            stages.extend(AccurateEngine::planned(settings, has_scene.then_some(a), dim, joints))
        }
    }
    stages
}
