//! A kept contact step's own contacts, computed afresh at its end: a feature that was not among its start's (a hull's
//! vertex coming round, a corner of a face the reduction left out) may sink a bounded depth within the step.

use super::contact_stages::ContactStages;
use crate::engine::found_contact::FoundContact;
use std::collections::BTreeSet;

/// How many tolerances past the deepest contact of its start a kept step's own contacts may sink (a hull's vertex
/// coming round inside a step sank 48 tolerances; one tolerance rejected steps of ten dominoes that two do not, 16%
/// more steps for 0.1 mm less depth).
pub(super) const LATE_SINK: f64 = 2.0;

/// The deepest penetration of the collider pairs of `every` in state y, their contacts computed afresh (m).
pub(super) fn deepest(
    cx: &mut ContactStages<'_>,
    model: &crate::model::Model,
    statics: &[nalgebra::Isometry3<f64>],
    every: &[FoundContact],
    y: &[f64],
) -> f64 {
    let pairs: BTreeSet<(usize, usize)> =
        every.iter().map(|f| (f.key.colliders.0 as usize, f.key.colliders.1 as usize)).collect();
    let pairs: Vec<(usize, usize)> = pairs.into_iter().collect();
    let poses = crate::model::actor_poses(model.layout, y, statics);
    let checks = cx.collider_set.checks;
    let found = cx.collider_set.pair_contacts(&pairs, &poses, |_, _| 0.0);
    cx.report.collision_checks += cx.collider_set.checks - checks;
    found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max)
}

/// The step to try again after a step of h sank a contact `sunk` deeper than the step started (m): short enough
/// that a sinking proportional to h stays within half the tolerance, and at most half of h.
pub(super) fn sunk_step(h: f64, sunk: f64, tolerance: f64) -> f64 {
    (h * 0.5 * tolerance / sunk).clamp(0.1 * h, 0.5 * h)
}

#[cfg(test)]
mod tests {
    use super::sunk_step;

    #[test]
    fn a_step_that_sank_late_is_taken_again_short_enough_and_at_most_half_as_long() {
        // sinking proportional to h: 4 tolerances in h = 1e-2 s -> a step that sinks half a tolerance, h / 8
        assert!((sunk_step(1e-2, 4e-4, 1e-4) - 1.25e-3).abs() < 1e-18);
        // sunk less than a tolerance (past the start's deepest by its allowance): still halved; far past: no less
        // than a tenth
        assert_eq!(sunk_step(1e-2, 0.5e-4, 1e-4), 0.5e-2);
        assert_eq!(sunk_step(1e-2, 1.0, 1e-4), 1e-3);
    }
}
