//! The sync times of the islands on their own clocks (`clocks.rs`): the groups meet at every multiple of `SYNC`,
//! and the touching phase looks for them at the first step past each sync time (it keeps when it last looked,
//! `TouchingPhase::synced`).

use super::touching_phase::TouchingPhase;

/// The groups meet at every multiple of this (s), whatever the frames and pauses (so that recording frames or pausing
/// changes nothing): frames inside a sync period are each group's own interpolation.
const SYNC: f64 = 1.0 / 60.0;

/// The first sync time after t.
pub(super) fn next_sync(t: f64) -> f64 {
    let next = ((t / SYNC).floor() + 1.0) * SYNC;
    if next > t {
        next
    } else {
        next + SYNC
    }
}

/// Whether the groups are due to be looked for at t: at the first step past each sync time (the phase keeps when it
/// last looked, so the answer is the same however the calls are cut); marks it looked for.
pub(super) fn sync_due(phase: &mut TouchingPhase, t: f64) -> bool {
    let due = !(phase.synced.is_finite() && (phase.synced / SYNC).floor() == (t / SYNC).floor());
    if due {
        phase.synced = t;
    }
    due
}
