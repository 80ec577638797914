//! What accurate mode's touching phase carries from step to step (part of the engine's memory), and its check
//! when a file gives it back.

use super::free_flight_memory::FreeFlight;
use super::sleep::Sleep;
use crate::engine::found_contact::ContactKey;
use crate::engine::last_contacts::LastContact;
use std::collections::BTreeMap;

/// What the touching phase carries from step to step (part of the engine's memory).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct TouchingPhase {
    /// Each contact's normal force of the last accepted step (the next step's first friction bound).
    pub lagged: BTreeMap<ContactKey, f64>,
    /// The step the error control proposes.
    pub h: f64,
    /// The stall window: its start time and the steps tried in it.
    pub window: (f64, usize),
    /// The integrator of the actors that touch nothing (`free_flight.rs`).
    pub free: Option<FreeFlight>,
    /// The contacts of the last accepted step, with the whole step's impulses.
    pub last: Vec<LastContact>,
    /// The last accepted step's h and its halves' difference d = y_half - y_whole (for the extrapolated state's
    /// error estimate).
    pub difference: Option<(f64, Vec<f64>)>,
    /// The islands asleep and the actors calm (`sleep.rs`).
    pub sleep: Sleep,
    /// Each contact's whole force of the last accepted step (N, normal and friction), where the next step's
    /// solves start from.
    pub warm: BTreeMap<ContactKey, nalgebra::Vector3<f64>>,
    /// Where the phase has got to, (t, y), between the calls it spans: the phase keeps its own state and the
    /// integrator's is set only when it ends (`advance.rs`). None until its first pause.
    /// (Absent from files written before the phase kept it: the integrator's state is the phase's.)
    #[serde(default)]
    pub at: Option<(f64, Vec<f64>)>,
    /// Each group's step size where the actors are advanced in groups on their own clocks (`clocks.rs`), by the
    /// group's first actor. (Absent from files written before: one clock.)
    #[serde(default)]
    pub clocks: BTreeMap<usize, f64>,
    /// When the groups were last looked for (`sync.rs`: once a sync period, at the first step past each sync
    /// time).
    #[serde(default = "never")]
    pub synced: f64,
}

fn never() -> f64 {
    f64::NEG_INFINITY
}

impl TouchingPhase {
    /// Whether it fits a scene of `actors` actors and `colliders` colliders and a state of length `dim`.
    pub fn fits(&self, actors: usize, colliders: usize, dim: usize) -> bool {
        self.h > 0.0
            && self.h.is_finite()
            && self.lagged.iter().all(|(k, f)| k.fits(colliders) && f.is_finite())
            && self.last.iter().all(|c| c.a < actors && c.b < actors)
            && self.free.as_ref().is_none_or(|f| f.held_components.iter().all(|&k| k < dim))
            && self.sleep.fits(actors)
            && self.warm.iter().all(|(k, f)| k.fits(colliders) && f.iter().all(|x| x.is_finite()))
            && self
                .difference
                .as_ref()
                .is_none_or(|(h, d)| *h > 0.0 && d.len() == dim && d.iter().all(|x| x.is_finite()))
            && self.at.as_ref().is_none_or(|(t, y)| t.is_finite() && y.len() == dim && y.iter().all(|x| x.is_finite()))
            && self.clocks.iter().all(|(&a, &h)| a < actors && h > 0.0 && h.is_finite())
    }
}
